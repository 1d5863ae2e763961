#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""Server-side latency of `ramiform studio` (docs/studio_api.md, docs/benchmarks.md).

Starts `ramiform studio --port 0` on the demo crown (examples/demo.rf) and measures, over HTTP
on loopback:
  1. editing a `param` of the demo crown until the run is done: POST /api/run with a changed
     `tolerance` (or `points`), polling GET /api/run/ID every 10 ms; the wall time and the
     server's own `seconds`, and the seconds of the tree's save_mesh line;
  2. line mode on the grown tree with 10,000 particles: the first camera (which spreads the
     particles and finds the feature lines) and then CAMERAS cameras orbiting the tree (only
     the view-dependent lines), each timed by the client and by X-Ramiform-Seconds.

usage: bench/studio_latency.py [--binary build/ramiform] [--edits 5] [--cameras 12]
                               [--threads 0]
"""
import argparse
import json
import math
import os
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

        def run(params):
            t0 = time.perf_counter()
            rid = json.loads(call("POST", "/api/run", {"script": script, "params": params})[0])["run"]
            while True:
                st = json.loads(call("GET", "/api/run/" + rid)[0])
                if st["state"] != "running":
                    break
                time.sleep(0.01)
            wall = time.perf_counter() - t0
            if st["state"] != "done":
                sys.exit(f"run {rid} {st['state']}: {st['error']}")
            mesh = [e for e in st["log"] if e["command"] == "save_mesh"]
            return rid, wall, st["seconds"], st["log"], mesh[-1]["seconds"] if mesh else float("nan")

        rid, wall, _, log, _ = run({})
        print(f"first run of the demo crown: {wall:.2f} s wall")
        for e in log:
            print(f"  line {e['line']:3d} {e['command']:16s} {e['seconds']:.3f} s")
        walls, tree_mesh = [], []
        for k in range(args.edits):
            tol = 0.05 + 0.01 * (k + 1)  # a changed tolerance slider: the tree is re-meshed
            rid, wall, _, log, mesh_s = run({"tolerance": f"{tol:.2f}"})
            walls.append(wall)
            tree_mesh.append(mesh_s)
        print(f"param edit (tolerance) -> run done, {args.edits} edits: wall median "
              f"{statistics.median(walls):.3f} s, max {max(walls):.3f} s; the tree's save_mesh "
              f"line median {statistics.median(tree_mesh):.3f} s")

        def camera(angle):
            r = 14.0
            return {"eye": [r * math.sin(angle), 6.0, r * math.cos(angle)], "target": [0, 4.5, 0],
                    "up": [0, 1, 0], "fov": 40, "width": 800, "height": 600}

        def lines(angle):
            t0 = time.perf_counter()
            body, hdr = call("POST", "/api/lines", {"run": rid, "shape": "tree", "camera": camera(angle),
                                                    "lines": ["silhouette", "suggestive", "feature"],
                                                    "count": args.count})
            return time.perf_counter() - t0, float(hdr.get("X-Ramiform-Seconds", "nan")), len(body)

        first, server_first, _ = lines(0.0)
        print(f"lines, first camera ({args.count} particles spread, feature lines): {first:.3f} s "
              f"wall, {server_first:.3f} s server")
        times = [lines(2 * math.pi * (k + 1) / (args.cameras + 1)) for k in range(args.cameras)]
        wall = [t[0] for t in times]
        server = [t[1] for t in times]
        print(f"lines, {args.cameras} more cameras: wall median {statistics.median(wall):.3f} s "
              f"(max {max(wall):.3f}), server median {statistics.median(server):.3f} s -> "
              f"{1 / statistics.median(wall):.1f} frames/s")
    finally:
        proc.terminate()
        proc.wait(timeout=30)


if __name__ == "__main__":
    main()
