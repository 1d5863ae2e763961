# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""The curve and surface skeletons from Python (docs/skeletal.md): the same fields as the scene
language builds, bad values refused with the library's message."""

import numpy as np
import pytest

import ramiform as rf

CUBIC = np.array([[0, 0, 0], [0, 0, 4], [4, 0, 4], [4, 0, 0]], float)


def test_bezier_field_surface_lies_at_the_radius():
    f = rf.bezier_field(CUBIC, radius=0.3)
    # the curve's apex is (2, 0, 3); the surface is 0.3 above it (Wyvill: f = iso there)
    top = f.evaluate(np.array([[2, 0, 3.3]]))[0]
    assert abs(top - f.iso) < 1e-9
    assert f.evaluate(np.array([[2, 0, 3.0]]))[0] > f.iso


def test_scene_language_and_python_agree():
    points = np.random.default_rng(3).uniform(-1, 5, size=(50, 3))
    f = rf.bezier_field(CUBIC, radius=0.5, def_="squared-cosine:0.3", tie="last")
    script = ("bezier b 0,0,0 0,0,4 4,0,4 4,0,0 radius=0.5 def=squared-cosine:0.3 tie=last\n" +
              "".join(f"eval b {p[0]!r} {p[1]!r} {p[2]!r}\n" for p in points))
    reports = rf.run_script(script, out=".")["reports"]  # the eval lines only
    # 'f(x,y,z) = V (inside|outside, iso 0.5)', V with 6 significant digits
    printed = [float(r.split(" = ")[1].split(" ")[0]) for r in reports]
    np.testing.assert_allclose(printed, f.evaluate(points), rtol=1e-5, atol=1e-12)


def test_surfaces_and_segment_fields():
    shell = rf.superquadric_field(radii=[1, 1, 0.25], e1=0.4, e2=0.4, radius=0.3, depth=4)
    assert shell.evaluate(np.array([[0, 0, 0.0]]))[0] > shell.iso
    assert shell.evaluate(np.array([[0, 0, 1.0]]))[0] < shell.iso
    patch = rf.patch_field(np.array([[i, j, 0] for i in range(4) for j in range(4)], float),
                           radius=0.2, max_error=0.01)
    assert patch.evaluate(np.array([[1.5, 1.5, 0.1]]))[0] > patch.iso
    seg = rf.segment_field([0, 0, 0], [3, 0, 0], radius=0.5, def_="flat:8")
    assert seg.evaluate(np.array([[1.5, 0, 0.45]]))[0] > seg.iso
    assert seg.evaluate(np.array([[3.05, 0, 0]]))[0] == 0.0  # flat end: nothing beyond it


@pytest.mark.parametrize("call", [
    lambda: rf.bezier_field(CUBIC, def_="squared-cosine:2"),
    lambda: rf.bezier_field(CUBIC, tie="middle"),
    lambda: rf.bezier_field(CUBIC[:1]),
    lambda: rf.bezier_field(CUBIC, radii=[1, 2]),
    lambda: rf.patch_field(CUBIC),
    lambda: rf.superquadric_field(e1=0),
    lambda: rf.superquadric_field(depth=11),
    lambda: rf.segment_field([0, 0, 0], [0, 0, 0]),
])
def test_bad_values_raise_value_error(call):
    with pytest.raises(ValueError):
        call()


def test_skeleton_distances_match_the_cli_rule(tmp_path):
    path = tmp_path / "u.json"
    path.write_text('{"nodes": [{"position": [-1, 0, 1], "radius": 0.1},'
                    ' {"position": [1, 0, 1], "radius": 0.1}],'
                    ' "edges": [{"nodes": [0, 1], "controls": [[-1, 0, -1], [1, 0, -1]]}]}')
    s = rf.read_skeleton(str(path), keep_curves=True)
    far = np.array([[0, 0, 100.0]])  # equally near both ends of the U
    first = rf.skeleton_distances(s, far)
    last = rf.skeleton_distances(s, far, tie="last")
    assert first["distance"][0] == last["distance"][0]
    assert first["t"][0] == 0.0 and last["t"][0] == 1.0
