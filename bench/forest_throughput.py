#!/usr/bin/python3
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""Trees per minute of ramiform.forest.mesh_all on this machine, 1 vs 2 Dask workers.

Generates a forest (default 40 trees of 300-1000 segments, seeds 1..N, `ramiform generate`),
then meshes it with a LocalCluster of 1 and of 2 worker processes (one thread each, default
mesh options), and checks the two runs wrote the same bytes.

  PYTHONPATH=build/python /usr/bin/python3 bench/forest_throughput.py \
      [--binary build/ramiform] [--trees 40] [--min-segments 300] [--max-segments 1000]
"""

import argparse
import os
import platform
import shutil
import subprocess
import tempfile
import time

import distributed

from ramiform import forest


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default=os.environ.get("RAMIFORM_BINARY")
                        or shutil.which("ramiform") or "build/ramiform")
    parser.add_argument("--trees", type=int, default=40)
    parser.add_argument("--min-segments", type=int, default=300)
    parser.add_argument("--max-segments", type=int, default=1000)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    args = parser.parse_args()
    os.environ["RAMIFORM_BINARY"] = os.path.abspath(args.binary)
    with tempfile.TemporaryDirectory(prefix="ramiform-forest-bench-") as work:
        in_dir = os.path.join(work, "in")
        os.makedirs(in_dir)
        span = args.max_segments - args.min_segments
        segments = 0
        for i in range(args.trees):
            n = args.min_segments + (span * i) // max(1, args.trees - 1)
            segments += n
            subprocess.run([args.binary, "generate", os.path.join(in_dir, f"t{i:04d}.json"),
                            "--segments", str(n), "--seed", str(i + 1)], check=True,
                           capture_output=True)
        print(f"forest: {args.trees} trees, {segments} segments "
              f"({args.min_segments}-{args.max_segments} each); {os.cpu_count()} cores, "
              f"{platform.processor() or platform.machine()}")
        outputs = {}
        for workers in args.workers:
            out_dir = os.path.join(work, f"out{workers}")
            with distributed.LocalCluster(n_workers=workers, threads_per_worker=1,
                                          processes=True, dashboard_address=None) as cluster, \
                    distributed.Client(cluster) as client:
                start = time.perf_counter()
                results = forest.mesh_all(in_dir, out_dir, client=client)
                seconds = time.perf_counter() - start
            failed = sum(1 for r in results if r["error"])
            triangles = sum(r["triangles"] or 0 for r in results)
            busy = sum(r["seconds"] for r in results)
            print(f"workers {workers}: {seconds:.1f} s wall, {60 * len(results) / seconds:.1f} "
                  f"trees/min, {triangles} triangles, {busy:.1f} s in tasks, {failed} failed")
            outputs[workers] = {n: open(os.path.join(out_dir, n), "rb").read()
                                for n in sorted(os.listdir(out_dir)) if n.endswith(".ply")}
        runs = list(outputs.values())
        same = all(r == runs[0] for r in runs[1:])
        print(f"outputs identical across worker counts: {same}")


if __name__ == "__main__":
    main()
