#!/usr/bin/python3
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""MPU reconstruction (`ramiform reconstruct`, docs/reconstruction.md) side by side with screened
Poisson reconstruction (Open3D's create_from_point_cloud_poisson, Debian's python3-open3d,
installed by `scripts/install-deps.sh --bench`) on the same oriented points, in one run.

For each model of ../shared/data/models (kitten.xyz and oni.pwn as they are; bunny.ply and
cow.off as the 30,000 area-weighted points with face normals that ramiform draws, written by
`reconstruct --save-points` and handed to Open3D unchanged):
  - seconds: ramiform's whole command (reading, normals, MPU fit, marching cubes, writing; best
    of three) and its MPU fit alone; Open3D's Poisson call alone (best of three), at octree
    depth 8 and 9;
  - triangles, pieces (connected components), closed (every edge in two triangles);
  - accuracy: the distance from every input point to the mesh (Open3D's RaycastingScene, the
    same measure for both), median / p99 / max relative to the points' bounding-box diagonal.
Usage: bench/compare_reconstruct.py [BUILD_DIR] [OUT.md]      (prints a markdown table)
(Debian's /usr/bin/python3, the interpreter python3-open3d installs into.)
"""
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
import open3d as o3d

build = sys.argv[1] if len(sys.argv) > 1 else "build"
out = open(sys.argv[2], "w") if len(sys.argv) > 2 else sys.stdout
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
data = os.path.join(root, "..", "shared", "data", "models")
binary = os.path.join(build, "ramiform")
if not os.path.isdir(data):
    sys.exit("compare_reconstruct: ../shared/data/models is absent; nothing to compare")


def read_points(path):
    v = np.loadtxt(path)
    return v[:, :3], v[:, 3:6]


def accuracy(mesh, points, diagonal):
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(mesh))
    d = scene.compute_distance(o3d.core.Tensor(points, dtype=o3d.core.Dtype.Float32)).numpy()
    d = d / diagonal
    return np.median(d), np.quantile(d, 0.99), d.max()


def pieces(mesh):
    clusters, _, _ = mesh.cluster_connected_triangles()
    return len(set(np.asarray(clusters).tolist()))


rows = []
with tempfile.TemporaryDirectory() as work:
    for model in ["kitten.xyz", "oni.pwn", "bunny.ply", "cow.off"]:
        src = os.path.join(data, model)
        pts_path = os.path.join(work, "points.xyz")
        mesh_path = os.path.join(work, "mpu.ply")
        stats_path = os.path.join(work, "s.json")
        best = None
        for _ in range(3):
            subprocess.run([binary, "reconstruct", src, "-o", mesh_path, "--threads", "2",
                            "--stats", stats_path, "--save-points", pts_path],
                           check=True, capture_output=True)
            s = json.load(open(stats_path))
            if best is None or s["seconds"]["total"] < best["seconds"]["total"]:
                best = s
        points, normals = read_points(pts_path)
        diagonal = float(np.linalg.norm(points.max(0) - points.min(0)))
        mesh = o3d.io.read_triangle_mesh(mesh_path)
        acc = accuracy(mesh, points, diagonal)
        rows.append((model, "ramiform MPU", best["seconds"]["total"], best["seconds"]["mpu"],
                     len(mesh.triangles), pieces(mesh), mesh.is_watertight(), acc))
        pc = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
        pc.normals = o3d.utility.Vector3dVector(normals)
        for depth in (8, 9):
            t_best = None
            for _ in range(3):
                t0 = time.perf_counter()
                pm, _ = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(pc, depth=depth)
                t = time.perf_counter() - t0
                t_best = t if t_best is None else min(t_best, t)
            acc = accuracy(pm, points, diagonal)
            rows.append((model, f"Open3D Poisson depth {depth}", t_best, t_best,
                         len(pm.triangles), pieces(pm), pm.is_watertight(), acc))

print("| model | method | total s | fit s | triangles | pieces | closed | "
      "distance to points median / p99 / max (of the diagonal) |", file=out)
print("|---|---|---|---|---|---|---|---|", file=out)
for m, meth, total, fit, tris, pcs, closed, (p50, p99, mx) in rows:
    print(f"| {m} | {meth} | {total:.3f} | {fit:.3f} | {tris} | {pcs} | "
          f"{'yes' if closed else 'no'} | {p50:.2e} / {p99:.2e} / {mx:.2e} |", file=out)
