# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""The Python module against independent computations and against the CLI: NumPy views, field
values and gradients, the polygonizers' meshes (watertight, nodes inside, deviation), checks,
growth, scripts, readers and writers, bad input as exceptions, thread counts, the GIL, and files
byte-identical with `ramiform mesh` (docs/python.md)."""

import filecmp
import math
import os
import shutil
import subprocess
import threading
import time
import warnings

import numpy as np
import pytest

import ramiform as rf

BINARY = os.environ.get("RAMIFORM_BINARY") or shutil.which("ramiform")
needs_cli = pytest.mark.skipif(BINARY is None, reason="needs the ramiform executable")


@pytest.fixture
def work(tmp_path):
    return tmp_path


def fork():
    """A Y: a trunk and two branches, radii tapering from 0.3 to 0.15."""
    positions = np.array([[0, 0, 0], [0, 0, 2], [1, 0, 3.5], [-1, 0.2, 3.3]], dtype=float)
    radii = np.array([0.3, 0.25, 0.15, 0.15])
    edges = np.array([[0, 1], [1, 2], [1, 3]])
    return rf.Skeleton(positions, radii, edges)


def write_swc(path):
    lines = ["# a soma and three dendrites, micrometres", "1 1 0 0 0 6 -1"]
    for k in range(3):
        a = 2 * math.pi * k / 3
        c, s = math.cos(a), math.sin(a)
        lines.append(f"{2 + 2 * k} {3 if k else 2} {7 * c:.2f} {7 * s:.2f} 0 1.2 1")
        lines.append(f"{3 + 2 * k} {3 if k else 2} {20 * c:.2f} {20 * s:.2f} 2 0.6 {2 + 2 * k}")
    path.write_text("\n".join(lines) + "\n")
    return path


# --- Skeleton ---------------------------------------------------------------------------------

def test_skeleton_views_share_memory_and_are_read_only():
    s = fork()
    assert len(s) == 4 and s.node_count == 4 and s.edge_count == 3 and s.components() == 1
    np.testing.assert_array_equal(s.positions[2], [1, 0, 3.5])
    np.testing.assert_array_equal(s.radii, [0.3, 0.25, 0.15, 0.15])
    assert s.edges.dtype == np.uint32 and s.edges.shape == (3, 2)
    assert s.types is None
    # views, not copies: two reads see the same buffer, owned by the skeleton
    assert np.shares_memory(s.positions, s.positions)
    assert np.may_share_memory(s.positions, s.radii)  # both are strided views of the nodes
    assert s.positions.strides == (32, 8) and s.radii.strides == (32,)
    for a in (s.positions, s.radii, s.edges):
        with pytest.raises(ValueError):
            a[0] = 0


def test_skeleton_bad_input_names_the_element():
    p = np.zeros((2, 3))
    with pytest.raises(ValueError, match=r"positions must have shape \(N, 3\), got \(2, 2\)"):
        rf.Skeleton(np.zeros((2, 2)), [1, 1], [[0, 1]])
    with pytest.raises(ValueError, match="radii has 3 values for 2 positions"):
        rf.Skeleton(p, [1, 1, 1], [[0, 1]])
    with pytest.raises(ValueError, match=r"edges\[0\] refers to node 5 of 2"):
        rf.Skeleton(p + [[0, 0, 0], [0, 0, 1]], [1, 1], [[0, 5]])
    with pytest.raises(ValueError, match="radius"):
        rf.Skeleton(p + [[0, 0, 0], [0, 0, 1]], [1, -1], [[0, 1]])
    with pytest.raises(ValueError):
        rf.Skeleton(np.array([[0, 0, np.nan], [0, 0, 1]]), [1, 1], [[0, 1]])
    with pytest.raises(TypeError):
        rf.Skeleton("not an array", [1], [])


def test_read_and_write_skeleton_round_trip(work):
    s = fork()
    rf.write_skeleton(str(work / "y.json"), s)
    t = rf.read_skeleton(str(work / "y.json"))
    np.testing.assert_array_equal(t.positions, s.positions)
    np.testing.assert_array_equal(t.radii, s.radii)
    np.testing.assert_array_equal(t.edges, s.edges)


def test_read_skeleton_reads_every_format(work):
    s = fork()
    rf.write_skeleton(str(work / "y.ply"), s)
    np.testing.assert_array_equal(rf.read_skeleton(str(work / "y.ply")).positions, s.positions)
    (work / "y.obj").write_text("v 0 0 0\nv 0 0 2\nv 1 0 3\nl 1 2\nl 2 3\n")
    obj = rf.read_skeleton(str(work / "y.obj"), obj_radius=0.1)
    assert obj.edge_count == 2 and np.all(obj.radii == 0.1)
    with pytest.raises(ValueError, match="radius"):
        rf.read_skeleton(str(work / "y.obj"))  # an OBJ carries no radius
    # TreeQSM cylinders: radius length start(3) axis(3) parent; a trunk and one branch
    (work / "qsm.txt").write_text("0.3 3 0 0 0 0 0 1 0\n0.1 1 0 0 3 0.6 0 0.8 1\n")
    qsm = rf.read_skeleton(str(work / "qsm.txt"))
    assert qsm.components() == 1 and qsm.positions[:, 2].max() == pytest.approx(3.8)
    assert qsm.radii.max() == pytest.approx(0.3)


def test_read_swc_keeps_types_and_bad_files_name_the_line(work):
    s = rf.read_skeleton(str(write_swc(work / "cell.swc")))
    assert s.types is not None and s.types.dtype == np.int32
    assert set(s.types.tolist()) == {1, 2, 3}
    # soma regions: the soma is a sphere and each neurite starts on its surface (its own part)
    assert s.components() == 4 and len(s) == 10
    raw = rf.read_skeleton(str(work / "cell.swc"), soma_regions=False)
    assert raw.components() == 1 and len(raw) == 7 and raw.edge_count == 6
    assert raw.types.tolist() == [1, 2, 2, 3, 3, 3, 3]
    bad = work / "bad.swc"
    bad.write_text("1 1 0 0 0 5 -1\n2 3 5 0 0 1 7\n")
    with pytest.raises(ValueError, match=r"bad\.swc:2"):
        rf.read_skeleton(str(bad))
    with pytest.raises(ValueError, match="nothing.json"):
        rf.read_skeleton(str(work / "nothing.json"))


def test_branching_tree_matches_the_cli(work):
    t = rf.branching_tree(segments=40, seed=3, tip_radius=0.01)
    assert t.edge_count == 40 and t.components() == 1
    assert t.radii.min() == pytest.approx(0.01)
    if BINARY:
        subprocess.run([BINARY, "generate", str(work / "g.json"), "--segments", "40", "--seed",
                        "3", "--tip-radius", "0.01"], check=True, capture_output=True)
        g = rf.read_skeleton(str(work / "g.json"))
        np.testing.assert_array_equal(g.positions, t.positions)
        np.testing.assert_array_equal(g.radii, t.radii)
    with pytest.raises(ValueError):
        rf.branching_tree(segments=0)


# --- Field --------------------------------------------------------------------------------------

def test_convolution_field_of_a_long_segment_is_a_cylinder_of_its_radius():
    # lambda_i makes an infinitely long segment's surface a cylinder of radius exactly r: at the
    # middle of a segment 200 radii long, f at distance r from the axis is iso to within 1e-4
    s = rf.Skeleton([[0, 0, -100], [0, 0, 100]], [1, 1], [[0, 1]])
    f = rf.skeleton_field(s)
    angles = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    ring = np.stack([np.cos(angles), np.sin(angles), np.zeros(8)], axis=1)
    values = f.evaluate(ring)
    assert values.shape == (8,)
    np.testing.assert_allclose(values, f.iso, rtol=1e-4)
    assert f.evaluate([[0, 0, 0]])[0] > f.iso > f.evaluate([[0, 3, 0]])[0]


def test_gradients_agree_with_central_differences():
    f = rf.skeleton_field(fork())
    rng = np.random.default_rng(1)
    p = rng.uniform([-1, -1, 0], [1, 1, 3.5], size=(50, 3))
    v, g = f.evaluate(p, gradients=True)
    assert g.shape == (50, 3)
    h = 1e-6
    for axis in range(3):
        e = np.zeros(3)
        e[axis] = h
        fd = (f.evaluate(p + e) - f.evaluate(p - e)) / (2 * h)
        np.testing.assert_allclose(g[:, axis], fd, rtol=1e-4, atol=1e-6 * np.abs(g).max())
    np.testing.assert_array_equal(v, f.evaluate(p))


def test_field_values_do_not_depend_on_threads():
    f = rf.skeleton_field(rf.branching_tree(segments=200, seed=2))
    lo, hi = f.bounds
    p = np.random.default_rng(5).uniform(lo, hi, size=(20000, 3))
    np.testing.assert_array_equal(f.evaluate(p, threads=1), f.evaluate(p, threads=2))


def test_field_options_and_bad_points():
    s = fork()
    d = rf.skeleton_field(s, surface="distance", kernel="wyvill")
    assert d.iso == pytest.approx(0.5)
    assert "distance" in repr(d)
    with pytest.raises(ValueError, match="cauchy"):
        rf.skeleton_field(s, kernel="wyvill")  # a convolution surface needs the Cauchy kernel
    with pytest.raises(ValueError, match="surface must be"):
        rf.skeleton_field(s, surface="sdf")
    with pytest.raises(ValueError, match="fit-radii needs a convolution surface"):
        rf.skeleton_field(s, surface="distance", fit_radii=True)
    f = rf.skeleton_field(s)
    with pytest.raises(ValueError, match=r"points\[1\] is not finite"):
        f.evaluate([[0, 0, 0], [0, np.inf, 0]])
    with pytest.raises(ValueError, match="shape"):
        f.evaluate([1, 2, 3])
    with pytest.raises(ValueError, match="threads"):
        f.evaluate([[0, 0, 0]], threads=-1)


def test_fit_radii_splits_the_skeleton_and_reports_the_fit():
    s = fork()
    f = rf.skeleton_field(s, fit_radii=True)
    assert f.skeleton.edge_count > s.edge_count
    assert f.fit["converged"] is True and f.fit["edges"] == f.skeleton.edge_count
    assert rf.skeleton_field(s).fit is None


# --- Polygonizers and checks -----------------------------------------------------------------

def test_tets_mesh_is_watertight_holds_the_nodes_and_meets_its_tolerance():
    s = fork()
    f = rf.skeleton_field(s, fit_radii=True)
    m = rf.polygonize_tets(f, tolerance=0.05)
    assert m.triangles.dtype == np.uint32 and m.vertices.dtype == np.float64
    assert m.triangles.max() < m.vertex_count
    c = rf.check(m, skeleton=s, field=f)
    assert c["watertight"] and c["oriented"] and c["manifold"]
    assert c["components"] == 1 and c["euler"] == 2
    assert c["skeleton_nodes_inside"] == 1.0
    assert m.stats["tolerance_reached"] and m.stats["deviation_p99"] <= 0.05
    assert c["deviation_p99"] <= 0.06  # another sample of points
    # the field's exact outward normals: unit length, and along the gradient's opposite
    assert np.allclose(np.linalg.norm(m.normals, axis=1), 1.0)
    _, g = f.evaluate(m.vertices, gradients=True)
    cos = -(g * m.normals).sum(axis=1) / np.linalg.norm(g, axis=1)
    assert cos.min() > 0.999
    # vertices lie near the surface: |f - iso| / |grad f| (first order) against the smallest
    # radius, 0.15 (the improvement pass moves some vertices off the surface, within tolerance)
    v, g = f.evaluate(m.vertices, gradients=True)
    assert np.quantile(np.abs(v - f.iso) / np.linalg.norm(g, axis=1), 0.99) < 0.05 * 0.15
    assert c["vertex_deviation_p99"] <= 0.06


def test_tets_without_tolerance_is_the_uniform_mesher():
    f = rf.skeleton_field(fork())
    m1 = rf.polygonize_tets(f, tolerance=None, levels=1)
    m2 = rf.polygonize_tets(f, tolerance=None, levels=2)
    assert "tolerance" not in m1.stats and m1.stats["levels"] == 1
    assert m2.triangle_count > 2 * m1.triangle_count
    assert rf.check(m1)["watertight"] and rf.check(m2)["watertight"]
    with pytest.raises(ValueError):
        rf.polygonize_tets(f, levels=99)
    with pytest.raises(ValueError):
        rf.polygonize_tets(f, tolerance=5.0)


def test_an_explicit_skeleton_is_the_one_followed():
    f = rf.skeleton_field(fork())
    given = rf.polygonize_tets(f, fork(), tolerance=None, levels=1)
    own = rf.polygonize_tets(f, tolerance=None, levels=1)
    np.testing.assert_array_equal(given.vertices, own.vertices)
    with pytest.raises(TypeError):
        rf.polygonize_tets(f, "fork.json")


def test_marching_cubes_of_a_sphere():
    # one node without edges: a point primitive whose surface is a sphere of the node's radius
    s = rf.Skeleton([[1, 2, 3]], [0.5], np.zeros((0, 2), dtype=int))
    f = rf.skeleton_field(s, surface="distance")
    m = rf.marching_cubes(f, cell=0.05)
    r = np.linalg.norm(m.vertices - [1, 2, 3], axis=1)
    np.testing.assert_allclose(r, 0.5, atol=0.05 * 0.05)
    c = rf.check(m)
    assert c["watertight"] and c["components"] == 1 and c["euler"] == 2
    coarse = rf.marching_cubes(f, resolution=8)
    assert coarse.triangle_count < m.triangle_count
    with pytest.raises(ValueError, match="cell"):
        rf.marching_cubes(f, cell=-1.0)


def test_threads_give_identical_meshes():
    t = rf.branching_tree(segments=60, seed=4, tip_radius=0.03)
    f = rf.skeleton_field(t)
    a = rf.polygonize_tets(f, tolerance=0.1, threads=1)
    b = rf.polygonize_tets(f, tolerance=0.1, threads=2)
    np.testing.assert_array_equal(a.vertices, b.vertices)
    np.testing.assert_array_equal(a.triangles, b.triangles)
    np.testing.assert_array_equal(a.normals, b.normals)


def test_long_calls_release_the_gil():
    f = rf.skeleton_field(rf.branching_tree(segments=300, seed=1, tip_radius=0.02))
    done = []
    worker = threading.Thread(target=lambda: done.append(rf.polygonize_tets(f, tolerance=0.02)))
    ticks = 0
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.0005)
    worker.join()
    assert done and done[0].triangle_count > 0
    # with the GIL held through the C++ call the loop could only run before and after it
    assert ticks >= 20, ticks


def test_ctrl_c_cancels_a_long_call_and_writes_nothing(work):
    import signal
    tree = rf.branching_tree(segments=3000, seed=1, tip_radius=0.005)
    out = work / "never.ply"
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        # about a minute of work when not interrupted
        rf.mesh_skeleton(tree, str(out), fit_radii=True, tolerance=0.01)
    timer.join()
    # the mesh is written at the end of the call: no file means the work was cut short
    assert not out.exists() and not [p for p in os.listdir(work) if p.startswith("never")]


def test_mesh_from_arrays_and_checks_of_broken_meshes():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    t = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    c = rf.check(rf.Mesh(v, t))
    assert c["watertight"] and c["oriented"] and c["euler"] == 2
    flipped = t.copy()
    flipped[3] = [1, 3, 2]
    c = rf.check(rf.Mesh(v, flipped))
    assert c["watertight"] and not c["oriented"] and c["misoriented_edges"] == 3
    c = rf.check(rf.Mesh(v, t[:3]))
    assert not c["watertight"] and c["boundary_edges"] == 3
    with pytest.raises(ValueError, match=r"triangles\[1\] refers to vertex 9 of 4"):
        rf.Mesh(v, [[0, 1, 2], [0, 1, 9]])
    with pytest.raises(ValueError, match="normals has 1 rows for 4 vertices"):
        rf.Mesh(v, t, normals=[[0, 0, 1]])
    inside = rf.check(rf.Mesh(v, t), skeleton=rf.Skeleton([[0.1, 0.1, 0.1], [2, 2, 2]], [1, 1],
                                                          [[0, 1]]))
    assert inside["skeleton_nodes_inside_count"] == 1 and inside["skeleton_nodes_inside"] == 0.5


def test_write_and_read_mesh(work):
    f = rf.skeleton_field(fork())
    m = rf.polygonize_tets(f, tolerance=None, levels=1)
    for ext in ("ply", "obj", "off"):
        rf.write_mesh(str(work / f"m.{ext}"), m)
        back = rf.read_mesh(str(work / f"m.{ext}"))
        assert back.triangle_count == m.triangle_count
        np.testing.assert_allclose(back.vertices, m.vertices, rtol=1e-12, atol=1e-12)
    rf.write_mesh(str(work / "up.ply"), m, up="y")
    up = rf.read_mesh(str(work / "up.ply"))
    np.testing.assert_allclose(up.vertices[:, 1], m.vertices[:, 2])  # (x, z, -y)
    with pytest.raises(ValueError, match="unknown format|extension"):
        rf.write_mesh(str(work / "m.xyz"), m)
    with pytest.raises(ValueError, match="up must be"):
        rf.write_mesh(str(work / "m.ply"), m, up="x")
    (work / "broken.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")
    with pytest.raises(ValueError, match="broken.off"):
        rf.read_mesh(str(work / "broken.off"))


# --- Byte-identical with the CLI -------------------------------------------------------------

@needs_cli
def test_files_are_byte_identical_with_the_cli(work):
    tree = work / "tree.json"
    subprocess.run([BINARY, "generate", str(tree), "--segments", "80", "--seed", "7",
                    "--tip-radius", "0.03"], check=True, capture_output=True)
    subprocess.run([BINARY, "mesh", str(tree), "-o", str(work / "cli.ply"), "--fit-radii",
                    "--tolerance", "0.05", "--threads", "2"], check=True, capture_output=True)
    s = rf.read_skeleton(str(tree))
    # step by step: field, polygonizer, writer
    f = rf.skeleton_field(s, fit_radii=True, threads=1)
    m = rf.polygonize_tets(f, tolerance=0.05, threads=1)
    rf.write_mesh(str(work / "py.ply"), m)
    assert filecmp.cmp(work / "cli.ply", work / "py.ply", shallow=False)
    # in one call, .glb with bark UVs, and the uniform mesher
    subprocess.run([BINARY, "mesh", str(tree), "-o", str(work / "cli.glb"), "--levels", "1"],
                   check=True, capture_output=True)
    one = rf.mesh_skeleton(s, str(work / "py.glb"), levels=1)
    assert filecmp.cmp(work / "cli.glb", work / "py.glb", shallow=False)
    assert one.uvs is not None and one.stats["watertight"]


@needs_cli
def test_swc_labels_are_byte_identical_with_the_cli(work):
    cell = write_swc(work / "cell.swc")
    subprocess.run([BINARY, "mesh", str(cell), "-o", str(work / "cli.ply"), "--levels", "1"],
                   check=True, capture_output=True)
    s = rf.read_skeleton(str(cell))
    m = rf.polygonize_tets(rf.skeleton_field(s), tolerance=None, levels=1)
    assert m.labels is not None and set(m.labels.tolist()) <= {1, 2, 3}
    assert (m.labels == 1).any() and (m.labels == 2).any() and (m.labels == 3).any()
    rf.write_mesh(str(work / "py.ply"), m)
    assert filecmp.cmp(work / "cli.ply", work / "py.ply", shallow=False)
    np.testing.assert_array_equal(rf.read_mesh(str(work / "cli.ply")).labels, m.labels)


@needs_cli
def test_mesh_file_is_the_cli_in_process(work):
    tree = work / "tree.json"
    rf.write_skeleton(str(tree), rf.branching_tree(segments=50, seed=9, tip_radius=0.03))
    subprocess.run([BINARY, "mesh", str(tree), "-o", str(work / "cli.glb"), "--levels", "1",
                    "--no-cleanup"], check=True, capture_output=True)
    stats = rf.mesh_file(tree, work / "py.glb", levels=1, cleanup=False, threads=2)
    assert filecmp.cmp(work / "cli.glb", work / "py.glb", shallow=False)
    assert stats["watertight"] and "seconds" not in stats and stats["levels"] == 1
    with pytest.raises(TypeError, match=r"mesh_file\(\).*--frobnicate"):
        rf.mesh_file(tree, work / "x.ply", frobnicate=1)
    with pytest.raises(ValueError, match=r"mesh_file\(\): --levels: Value 99 not in range"):
        rf.mesh_file(tree, work / "x.ply", levels=99)
    with pytest.raises(ValueError, match=r"mesh_file\(\): --cell: applies to --method mc"):
        rf.mesh_file(tree, work / "x.ply", cell=0.1)
    with pytest.warns(RuntimeWarning, match="triangle budget"):
        rf.mesh_file(tree, work / "x.ply", levels=0, tolerance=0.001, max_triangles=2000)
    (work / "broken.json").write_text('{"nodes": [')
    with pytest.raises(ValueError, match="broken.json"):
        rf.mesh_file(work / "broken.json", work / "b.ply")
    assert not (work / "b.ply").exists()


def test_mesh_skeleton_without_output_writes_nothing(work):
    before = set(os.listdir(work))
    m = rf.mesh_skeleton(fork(), levels=1)
    assert set(os.listdir(work)) == before
    assert m.stats["watertight"] and m.stats["skeleton_components"] == 1
    with pytest.raises(ValueError, match="does not exist"):
        rf.mesh_skeleton(fork(), str(work / "no" / "dir.ply"), levels=1)
    with pytest.raises(ValueError, match="method"):
        rf.mesh_skeleton(fork(), method="dual")


# --- Growth, scripts, points ---------------------------------------------------------------

def test_grow_reaches_a_crown_with_pipe_model_radii():
    rng = np.random.default_rng(3)
    crown = rng.normal([0, 0, 12], [3, 3, 2], size=(800, 3))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a dozen points are never reached
        t = rf.grow(crown, step=0.5, influence=6, kill=1.0, tip_radius=0.05, pipe_exponent=2.0)
    assert t.components() == 1 and t.edge_count > 50
    np.testing.assert_array_equal(t.positions[0], [0, 0, 0])
    # pipe model with n = 2: a node's r^2 is the sum of its children's r^2, tips 0.05
    assert t.radii.min() == pytest.approx(0.05)
    assert t.radii[0] == pytest.approx(t.radii.max())
    assert t.positions[:, 2].max() > 10
    with pytest.raises(ValueError, match=r"points\[0\] is not finite"):
        rf.grow(np.array([[np.nan, 0, 0]]))
    with pytest.raises(ValueError, match="no branch grew"):
        rf.grow(np.array([[0, 0, 0.5]]), kill=2)
    with pytest.warns(RuntimeWarning, match="attraction points reached"):
        rf.grow(np.array([[0, 0, 5], [0, 0, 500]]), influence=10, kill=2)


def test_run_script_commits_only_on_success(work):
    text = "line s 0 0 0 0 0 2 radius=0.3\nsave_mesh s s.ply resolution=32\n"
    r = rf.run_script(text, out=str(work))
    assert [os.path.basename(p) for p in r["outputs"]] == ["s.ply"]
    assert rf.check(rf.read_mesh(str(work / "s.ply")))["watertight"]
    bad = "line t 0 0 0 0 0 2 radius=0.3\nsave_mesh t t.ply resolution=32\nfrobnicate t\n"
    with pytest.raises(ValueError, match=r"<script>:3"):
        rf.run_script(bad, out=str(work))
    assert not (work / "t.ply").exists()
    r = rf.run_script("param r 0.2\nsphere b $r\neval b 0 0 0\n", out=str(work), params={"r": "0.4"})
    assert r["outputs"] == [] and len(r["reports"]) == 1


def test_read_points(work):
    (work / "p.xyz").write_text("0 0 0 0 0 1\n1 2 3 1 0 0\n")
    p, n = rf.read_points(str(work / "p.xyz"))
    np.testing.assert_array_equal(p, [[0, 0, 0], [1, 2, 3]])
    np.testing.assert_array_equal(n, [[0, 0, 1], [1, 0, 0]])
    (work / "q.xyz").write_text("0 0 0\n1 2 zz\n")
    with pytest.raises(ValueError, match=r"q\.xyz:2"):
        rf.read_points(str(work / "q.xyz"))
