# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""Scans from Python (docs/reconstruction.md, docs/particles.md): MPU fields through oriented or
bare points, normal orientation, reconstruction of a file, and surface particles."""

import math
import os

import numpy as np
import pytest

import ramiform as rf

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "data")


def sphere(n, r=1.0):
    """n points on the sphere of radius r (Fibonacci lattice) and their outward normals."""
    i = np.arange(n)
    z = 1 - (2 * i + 1) / n
    q = np.sqrt(1 - z * z)
    g = math.pi * (3 - math.sqrt(5)) * i
    u = np.stack([q * np.cos(g), q * np.sin(g), z], axis=1)
    return r * u, u


def test_mpu_field_is_the_signed_distance_near_a_sphere():
    points, normals = sphere(2000)
    f = rf.mpu_field(points, normals)
    rng = np.random.default_rng(1)
    d = rng.normal(size=(500, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    radii = rng.uniform(0.9, 1.1, size=500)
    values = f.evaluate(d * radii[:, None])
    # inside is f > iso, and near the points f - iso is the distance to the sphere within 10 %
    np.testing.assert_allclose(values - f.iso, 1 - radii, rtol=0.1, atol=1e-3)


def test_orient_normals_turns_flipped_normals_back_and_estimates_missing_ones():
    points, normals = sphere(1500)
    bad = normals.copy()
    bad[::4] *= -1
    fixed, report = rf.orient_normals(points, bad)
    assert report["flipped"] == len(bad[::4])
    np.testing.assert_allclose(fixed, normals, atol=1e-12)
    estimated, report = rf.orient_normals(points)
    assert report["estimated"] == 1500
    assert np.all(np.sum(estimated * normals, axis=1) > 0.99)


def test_reconstruct_a_file_gives_a_closed_mesh_with_stats(tmp_path):
    out = tmp_path / "pebble.ply"
    mesh = rf.reconstruct(os.path.join(EXAMPLES, "pebble.xyz"), out=str(out))
    assert out.exists()
    s = mesh.stats
    assert s["mesh"]["watertight"] and s["mesh"]["components"] == 1
    assert s["points"] == 600 and s["normals"]["flipped"] == 0
    # the vertices lie on the ellipsoid the points were taken from
    v = mesh.vertices
    level = (v[:, 0] / 1.2) ** 2 + (v[:, 1] / 0.8) ** 2 + (v[:, 2] / 0.6) ** 2
    assert np.max(np.abs(level - 1)) < 0.05
    points, normals = rf.read_surface_points(os.path.join(EXAMPLES, "pebble.xyz"))
    assert points.shape == (600, 3) and normals.shape == (600, 3)


def test_reconstruct_takes_the_commands_options():
    path = os.path.join(EXAMPLES, "pebble.xyz")
    coarse = rf.reconstruct(path, resolution=16, sharp=False, neighbours=8, min_points=12)
    fine = rf.reconstruct(path, resolution=48, support=0.9, max_depth=6, speck_cells=0)
    assert coarse.stats["mesh"]["watertight"] and fine.stats["mesh"]["watertight"]
    # 16 and 48 cells along the longest side of the surface's bounds (the ellipsoid's 2.4 and a
    # margin that depends on the fit): the cell sizes the stats report
    coarse_cell, fine_cell = coarse.stats["mesh"]["cell_size"], fine.stats["mesh"]["cell_size"]
    assert 2.4 / 16 < coarse_cell < 1.3 * 2.4 / 16
    assert 2.4 / 48 < fine_cell < 1.3 * 2.4 / 48
    assert len(fine.triangles) > 4 * len(coarse.triangles)
    with pytest.raises(Exception):
        rf.reconstruct(path, min_points=2)


def test_particles_lie_on_the_surface_evenly():
    points, normals = sphere(3000)
    f = rf.mpu_field(points, normals)
    p = rf.particles(f, count=1500, threads=2)
    pos, nor, delta = p["positions"], p["normals"], p["delta"]
    assert abs(len(pos) - 1500) < 300
    values, gradients = f.evaluate(pos, gradients=True)
    assert np.all(np.abs(values - f.iso) / np.linalg.norm(gradients, axis=1) <= 1e-4 * delta)
    assert np.all(np.sum(nor * pos / np.linalg.norm(pos, axis=1)[:, None], axis=1) > 0.99)
    assert p["stats"]["spacing_cv"] < 0.3
    again = rf.particles(f, count=1500, threads=1)
    np.testing.assert_array_equal(again["positions"], pos)


def test_bad_points_are_refused_with_the_library_message():
    points, normals = sphere(100)
    normals[7] = 0
    with pytest.raises(ValueError, match="point 7"):
        rf.mpu_field(points, normals)
    with pytest.raises(ValueError, match="shape"):
        rf.mpu_field(points[:, :2])


def test_tree_from_points_stem_and_bad_input():
    rng = np.random.default_rng(5)
    h = rng.uniform(0, 2, 3000)
    phi = rng.uniform(0, 2 * np.pi, 3000)
    stem = np.c_[0.1 * np.cos(phi), 0.1 * np.sin(phi), h]
    tree = rf.tree_from_points(stem)
    assert tree.components() == 1
    # the root at the base, on the axis; the top near z = 2; the radius from the points
    assert abs(tree.positions[0][2]) < 0.05 and np.linalg.norm(tree.positions[0][:2]) < 0.02
    assert abs(tree.positions[:, 2].max() - 2.0) < 0.2
    assert np.all(np.abs(tree.radii - 0.1) < 0.02)
    # y up: the same skeleton, rotated
    turned = rf.tree_from_points(stem[:, [0, 2, 1]] * [1, 1, -1], up="y")
    assert np.allclose(turned.positions, tree.positions[:, [0, 2, 1]] * [1, 1, -1], atol=1e-9)
    with pytest.raises(ValueError, match="at least 10 points"):
        rf.tree_from_points(stem[:5])
    with pytest.raises(ValueError, match="up"):
        rf.tree_from_points(stem, up="x")
    bad = stem.copy()
    bad[7, 1] = np.nan
    with pytest.raises(ValueError, match=r"points\[7\] is not finite"):
        rf.tree_from_points(bad)
