#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""Server-side latency of `ramiform studio` (docs/studio_api.md, docs/benchmarks.md).

Starts `ramiform studio --port 0` on its first script (the demo crown made for editing,
examples/studio.rf) and measures, over HTTP on loopback:
  1. editing the `points` param (the tree regrows and is meshed again) until the run is done:
     POST /api/run, polling GET /api/run/ID every 10 ms; as the page does while a slider is
     dragged (draft runs) and on its release (full runs); wall time and the tree's save_mesh
     line, and for full runs when the new mesh could be shown (its `early` entry listed and
     its view fetched, before the bark UVs and files are made);
  2. line mode on the grown tree with 10,000 particles: the first camera (which spreads the
     particles and finds the feature lines) and then CAMERAS cameras orbiting the tree (only
     the view-dependent lines), each twice as the page asks for it (the quick drawing, hidden
     lines by surfels, then the exact one by rays), timed by the client, by
     X-Ramiform-Seconds and by the server process's CPU time (Linux: /proc/PID/stat, user +
     system, both threads: unlike wall time it barely moves when other work shares the
     cores); and the
     same for the Stanford bunny fitted by `mpu` when ../shared/data/models/bunny.ply exists
     (--bunny PATH).

With --big, also full runs of the same script growing in steps half as long (about 4,900
segments at 6,000 points): issue 22's "tree of a few thousand segments".

usage: bench/studio_latency.py [--binary build/ramiform] [--edits 5] [--cameras 12]
                               [--threads 0] [--big]
"""
import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--binary", default=os.environ.get("RAMIFORM_BINARY", "build/ramiform"))
    ap.add_argument("--edits", type=int, default=5)
    ap.add_argument("--cameras", type=int, default=12)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--count", type=int, default=10000)
    ap.add_argument("--big", action="store_true",
                    help="also edit a tree of a few thousand segments (full runs)")
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--bunny", default=os.path.join(here, "..", "..", "shared", "data", "models",
                                                      "bunny.ply"))
    args = ap.parse_args()

    out = tempfile.mkdtemp(prefix="studio-bench-")
    proc = subprocess.Popen([args.binary, "studio", "--port", "0", "--out", out,
                             "--threads", str(args.threads)],
                            stdout=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline().strip()
        url = line.split(": ", 1)[1]
        base, token = url.split("/?token=")
        headers = {"X-Ramiform-Token": token, "Content-Type": "application/json"}

        def call(method, path, body=None):
            data = None if body is None else json.dumps(body).encode()
            req = urllib.request.Request(base + path, data=data, method=method, headers=headers)
            with urllib.request.urlopen(req, timeout=600) as r:
                return r.read(), dict(r.headers)

        script = json.loads(call("GET", "/api/info")[0])["script"]

        def run(params, draft=False, text=None):
            t0 = time.perf_counter()
            body = {"script": text or script, "params": params, "draft": draft}
            rid = json.loads(call("POST", "/api/run", body)[0])["run"]
            early = None
            while True:
                st = json.loads(call("GET", "/api/run/" + rid)[0])
                tree = [e for e in st.get("early", []) if e["shape"] == "tree"]
                if early is None and tree:
                    call("GET", tree[0]["view"])  # the page fetches it to show it
                    early = time.perf_counter() - t0
                if st["state"] != "running":
                    break
                time.sleep(0.01)
            wall = time.perf_counter() - t0
            run.early = early
            if st["state"] != "done":
                sys.exit(f"run {rid} {st['state']}: {st['error']}")
            mesh = [e for e in st["log"] if e["command"] == "save_mesh"]
            return rid, wall, st["seconds"], st["log"], mesh[-1]["seconds"] if mesh else float("nan")

        rid, wall, _, log, _ = run({})
        print(f"first run of the studio crown: {wall:.2f} s wall")
        for e in log:
            print(f"  line {e['line']:3d} {e['command']:16s} {e['seconds']:.3f} s")
        for draft in (True, False):
            walls, tree_mesh, earlies = [], [], []
            for k in range(args.edits):
                points = 2500 + 100 * (k + 1)  # a moved `points` slider: the tree regrows
                rid, wall, _, log, mesh_s = run({"points": str(points)}, draft)
                walls.append(wall)
                tree_mesh.append(mesh_s)
                if run.early is not None:
                    earlies.append(run.early)
            print(f"param edit (points), {'draft' if draft else 'full'} runs -> run done, "
                  f"{args.edits} edits: wall median {statistics.median(walls):.3f} s, max "
                  f"{max(walls):.3f} s; the tree's save_mesh line median "
                  f"{statistics.median(tree_mesh):.3f} s")
            if earlies:
                print(f"  the new tree mesh fetched from the run's early meshes (before its bark "
                      f"UVs and files): median {statistics.median(earlies):.3f} s, max "
                      f"{max(earlies):.3f} s")

        # Cameras in the page's +Y-up frame (model z is page y, model y is page -z).
        def camera(angle, target, r):
            return {"eye": [target[0] + r * math.sin(angle), target[1] + 1.5,
                            target[2] + r * math.cos(angle)],
                    "target": target, "up": [0, 1, 0], "fov": 40, "width": 800, "height": 600}

        ticks = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100

        def cpu_seconds():
            try:
                with open(f"/proc/{proc.pid}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
                return (int(fields[11]) + int(fields[12])) / ticks  # utime + stime
            except OSError:
                return float("nan")

        def lines(angle, shape, target, r, visibility="rays"):
            t0 = time.perf_counter()
            body, hdr = call("POST", "/api/lines", {"run": rid, "shape": shape,
                                                    "camera": camera(angle, target, r),
                                                    "lines": ["silhouette", "suggestive", "feature"],
                                                    "count": args.count,
                                                    "visibility": visibility})
            return time.perf_counter() - t0, float(hdr.get("X-Ramiform-Seconds", "nan")), len(body)

        def orbit(shape, target, r):
            first, server_first, _ = lines(0.0, shape, target, r)
            print(f"lines of {shape}, first camera ({args.count} particles spread, feature "
                  f"lines): {first:.3f} s wall, {server_first:.3f} s server")
            # As the page asks: per camera the quick drawing (surfels), then the exact one (rays).
            for visibility in ("surfels", "rays"):
                cpu0 = cpu_seconds()
                times = [lines(2 * math.pi * (k + 1) / (args.cameras + 1), shape, target, r,
                               visibility) for k in range(args.cameras)]
                cpu = (cpu_seconds() - cpu0) / args.cameras
                wall = [t[0] for t in times]
                server = [t[1] for t in times]
                print(f"lines of {shape}, {args.cameras} more cameras, hidden lines by "
                      f"{visibility}: wall median {statistics.median(wall):.3f} s (max "
                      f"{max(wall):.3f}), server median {statistics.median(server):.3f} s -> "
                      f"{1 / statistics.median(wall):.1f} frames/s; server CPU {cpu:.3f} s "
                      f"per camera (mean)")

        orbit("tree", [0, 4.5, 0], 14.0)
        if os.path.exists(args.bunny):
            # The bunny of ../shared/data/models spans x ±5, y 0..9.7, z ±3.8 (model axes).
            rid = run({}, text=f"mpu bunny {os.path.abspath(args.bunny)}\n")[0]
            orbit("bunny", [0, 0, -4.8], 24.0)
        else:
            print(f"lines of the bunny: skipped ({args.bunny} not found)")
        if args.big:
            # A tree of a few thousand segments: the same script growing in shorter steps.
            big = script.replace("step=0.22 influence=1.4 kill=0.45",
                                 "step=0.11 influence=0.9 kill=0.25")
            if big == script:
                sys.exit("--big: the studio script's grow line has changed; update this bench")
            run({"points": "6000"}, text=big)  # grows the first big tree
            walls, earlies = [], []
            for k in range(args.edits):
                rid, wall, _, log, _ = run({"points": str(5900 - 100 * k)}, text=big)
                walls.append(wall)
                if run.early is not None:
                    earlies.append(run.early)
            grown = [e for e in log if e["command"] == "grow"]
            nodes = re.search(r"(\d+) nodes", grown[-1]["message"]).group(1)
            print(f"param edit (points) of the few-thousand-segment tree ({nodes} nodes), "
                  f"full runs: the new tree mesh from the early meshes median "
                  f"{statistics.median(earlies):.3f} s (max {max(earlies):.3f}); run done median "
                  f"{statistics.median(walls):.3f} s")
    finally:
        proc.terminate()
        proc.wait(timeout=30)


if __name__ == "__main__":
    main()
