# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""Line drawings from Python (docs/drawing.md): the silhouette of an MPU sphere lies on its
contour circle, the files are written, bad options raise."""

import json
import math

import numpy as np
import pytest

import ramiform as rf


def sphere(n):
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    r = np.sqrt(1 - z * z)
    a = math.pi * (3 - math.sqrt(5)) * i
    p = np.stack([r * np.cos(a), r * np.sin(a), z], axis=1)
    return p, p.copy()


def test_sphere_silhouette_is_the_contour_circle(tmp_path):
    points, normals = sphere(3000)
    f = rf.mpu_field(points, normals)
    svg, js = tmp_path / "s.svg", tmp_path / "s.json"
    d = rf.draw(f, camera="eye=0,0,5;target=0,0,0", count=3000, out=str(svg),
                polylines=str(js), threads=2)
    sil = [l for l in d["lines"] if l["kind"] == "silhouette"]
    assert len(sil) == 1 and sil[0]["closed"]
    p = sil[0]["points"]
    # The contour of a unit sphere seen from distance 5 is the circle z = 1/5, radius sqrt(24)/5.
    assert np.max(np.abs(p[:, 2] - 0.2)) < 0.01
    assert np.max(np.abs(np.linalg.norm(p[:, :2], axis=1) - math.sqrt(24) / 5)) < 0.01
    assert sil[0]["visible"].all()
    assert d["camera"]["eye"] == [0, 0, 5]
    assert d["stats"]["lines_silhouette"] == 1
    assert "<g id=\"silhouette\"" in svg.read_text()
    assert len(json.loads(js.read_text())["lines"]) == len(d["lines"])


def test_saved_particles_are_reused_and_regenerated_locally(tmp_path):
    f = rf.mpu_field(*sphere(2000))
    state = tmp_path / "p.ply"
    p = rf.particles(f, count=1500, iterations=10, state=str(state))
    n = len(p["positions"])
    # A drawing from the saved state uses exactly those particles, and twice gives the same lines.
    a = rf.draw(f, particle_state=str(state), camera="eye=0,0,5;target=0,0,0",
                lines=["silhouette"], threads=1)
    b = rf.draw(f, particle_state=str(state), camera="eye=0,0,5;target=0,0,0",
                lines=["silhouette"], threads=2)
    assert a["stats"]["particles"] == n
    assert len(a["lines"]) == len(b["lines"]) > 0
    for la, lb in zip(a["lines"], b["lines"]):
        assert np.array_equal(la["points"], lb["points"])
    # Regeneration after an "edit" confined to a box: particles away from it keep their exact
    # positions, in order, first in the result.
    lo, hi = np.array([0.6, -0.5, -0.5]), np.array([1.5, 0.5, 0.5])
    r = rf.particles(f, previous=str(state), edit_min=lo.tolist(), edit_max=hi.tolist(),
                     iterations=10)
    kept = r["stats"]["kept"]
    delta = p["delta"][:, None]
    far = np.any((p["positions"] < lo - delta) | (p["positions"] > hi + delta), axis=1)
    assert 0 < kept < n and kept >= np.count_nonzero(far)
    old = {tuple(x) for x in p["positions"]}
    assert all(tuple(x) in old for x in r["positions"][:kept])
    assert len(r["positions"]) > kept
    with pytest.raises(ValueError, match="edit_min"):
        rf.particles(f, previous=str(state))
    with pytest.raises(Exception, match="no_such"):
        rf.draw(f, particle_state=str(tmp_path / "no_such.ply"))


def test_bad_options_raise():
    points, normals = sphere(500)
    f = rf.mpu_field(points, normals)
    with pytest.raises(ValueError, match="unknown line kind 'contour'"):
        rf.draw(f, lines=["contour"], count=300)
    with pytest.raises(ValueError, match="'eye'"):
        rf.draw(f, camera="eye=1,2", count=300)
    with pytest.raises(ValueError, match="k_c"):
        rf.draw(f, k_c=2.0, count=300)
    with pytest.raises(ValueError, match="straddle must be auto, movement or search"):
        rf.draw(f, straddle="both", count=300)


def test_shipped_drawings_parse_as_svg_with_their_groups():
    import glob
    import os
    import xml.etree.ElementTree as ET

    folder = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "drawings")
    files = sorted(glob.glob(os.path.join(folder, "*.svg")))
    assert len(files) >= 10
    ns = "{http://www.w3.org/2000/svg}"
    for f in files:
        root = ET.parse(f).getroot()
        assert root.tag == ns + "svg", f
        assert len(root.get("viewBox").split()) == 4, f
        groups = {g.get("id"): g for g in root.iter(ns + "g")}
        assert {"silhouette", "suggestive", "feature"} <= set(groups), f
        assert len(groups["silhouette"].findall(ns + "path")) > 0, f
        for p in root.iter(ns + "path"):
            d = p.get("d")
            assert d.startswith("M") and "nan" not in d.lower(), f
