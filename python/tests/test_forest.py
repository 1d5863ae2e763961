# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""ramiform.forest: a generated forest of 50 trees plus one broken file, meshed on a Dask
LocalCluster of two worker processes, compared byte for byte with `ramiform mesh` and with a
serial in-process run; the manifest, reruns that skip and redo (docs/forests.md)."""

import filecmp
import json
import os
import shutil
import subprocess
import sys
import time

import pytest

from ramiform import forest

BINARY = os.environ.get("RAMIFORM_BINARY") or shutil.which("ramiform")
OPTIONS = {"levels": 1}  # the paper's uniform method: fast, and enough to compare bytes
# Under AddressSanitizer (make sanitize sets RAMIFORM_TEST_SANITIZED) every mesh costs ~20x:
# a forest of 30 still holds every kind of input (.json, .ply, TreeQSM, SWC, the broken file).
SANITIZED = bool(os.environ.get("RAMIFORM_TEST_SANITIZED"))
TREES = 30 if SANITIZED else 50
BIG_SEGMENTS = "40" if SANITIZED else "150"

pytestmark = pytest.mark.skipif(BINARY is None, reason="needs the ramiform executable")


def _work_dir(tmp_path_factory):
    root = os.environ.get("RAMIFORM_TEST_TMP")
    if root:
        path = os.path.join(root, "forest")
        shutil.rmtree(path, ignore_errors=True)
        os.makedirs(path)
        return path
    return str(tmp_path_factory.mktemp("forest"))


def _write_treeqsm(path, seed):
    """A TreeQSM cylinder model (radius length start axis parent): a trunk and two branches."""
    lean = 0.1 * (seed % 7)
    rows = [(0.3, 3.0, 0, 0, 0, 0, 0, 1, 0),
            (0.15, 2.0, 0, 0, 3, 0.6, lean, 0.8, 1),
            (0.12, 1.5 + 0.05 * seed, 0, 0, 3, -0.6, 0, 0.8, 1)]
    with open(path, "w", encoding="utf-8") as f:
        for row in rows:
            f.write("\t".join(str(v) for v in row) + "\n")


def _write_swc(path, seed):
    """A small SWC neuron (micrometres): a one-point soma and three dendrites."""
    lines = ["# generated for test_forest", "1 1 0 0 0 5 -1"]
    for k in range(3):
        lines.append(f"{2 + 2 * k} 3 {4 + k} {seed % 5 - 2} {k - 1} 1.5 1")
        lines.append(f"{3 + 2 * k} 3 {12 + 2 * k} {seed % 3} {3 * k - 3} 0.8 {2 + 2 * k}")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")


@pytest.fixture(scope="module")
def plot(tmp_path_factory):
    """IN_DIR with TREES small trees (seeds 1..TREES: skeletons of 3-12 segments from `ramiform
    generate` as .json, every fifth as .ply; seeds 3, 13, ... TreeQSM cylinder models .txt;
    seeds 8, 28 SWC neurons) and one broken .json."""
    work = _work_dir(tmp_path_factory)
    in_dir = os.path.join(work, "in")
    os.makedirs(in_dir)
    for seed in range(1, TREES + 1):
        stem = os.path.join(in_dir, f"tree{seed:03d}")
        if seed % 10 == 3:
            _write_treeqsm(stem + ".txt", seed)
            continue
        if seed in (8, 28):
            _write_swc(stem + ".swc", seed)
            continue
        path = stem + (".ply" if seed % 5 == 0 else ".json")
        subprocess.run([BINARY, "generate", path, "--segments", str(3 + seed % 10),
                        "--seed", str(seed)], check=True, capture_output=True)
    with open(os.path.join(in_dir, "broken.json"), "w", encoding="utf-8") as f:
        f.write('{"nodes": [[0, 0, 0, 0.1], [0, 0, 1,\n')
    return work, in_dir


@pytest.fixture(scope="module")
def cluster_run(plot):
    distributed = pytest.importorskip("distributed")
    work, in_dir = plot
    out_dir = os.path.join(work, "cluster")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            first = forest.mesh_all(in_dir, out_dir, client=client, **OPTIONS)
            yield {"client": client, "out_dir": out_dir, "first": first, "in_dir": in_dir,
                   "work": work}


def _manifest(out_dir):
    with open(os.path.join(out_dir, "manifest.jsonl"), encoding="utf-8") as f:
        return [json.loads(line) for line in f if line.strip()]


def _bytes(path):
    with open(path, "rb") as f:
        return f.read()


def test_one_mesh_per_good_tree_and_a_manifest_line_per_input(cluster_run):
    out_dir, results = cluster_run["out_dir"], cluster_run["first"]
    assert len(results) == TREES + 1
    meshes = sorted(n for n in os.listdir(out_dir) if n.endswith(".ply"))
    assert len(meshes) == TREES
    assert "broken.ply" not in meshes
    assert not [n for n in os.listdir(out_dir) if "partial" in n]
    lines = _manifest(out_dir)
    assert len(lines) == TREES + 1
    assert len({r["input"] for r in lines}) == TREES + 1
    broken = [r for r in lines if r["error"]]
    assert len(broken) == 1
    assert broken[0]["input"].endswith("broken.json")
    assert "broken.json:" in broken[0]["error"]  # the library's message: file and line
    assert broken[0]["triangles"] is None
    for r in lines:
        if r["error"]:
            continue
        assert r["checks"]["watertight"] is True
        assert r["checks"]["components"] == 1
        assert r["triangles"] > 0
        assert os.path.exists(r["output"])
        # the triangle count of the file itself (binary PLY header)
        header = _bytes(r["output"])[:2000].split(b"end_header")[0].decode("ascii")
        faces = [ln for ln in header.splitlines() if ln.startswith("element face")]
        assert int(faces[0].split()[2]) == r["triangles"]


def test_meshes_identical_to_the_cli(cluster_run):
    out_dir, in_dir, work = cluster_run["out_dir"], cluster_run["in_dir"], cluster_run["work"]
    cli_dir = os.path.join(work, "cli")
    os.makedirs(cli_dir, exist_ok=True)
    names = ["tree001.json", "tree005.ply", "tree013.txt", "tree017.json", "tree028.swc",
             "tree030.ply", "tree042.json", "tree050.ply"]
    names = [n for n in names if int(n[4:7]) <= TREES]
    for name in names:
        stem = os.path.splitext(name)[0]
        out = os.path.join(cli_dir, stem + ".ply")
        subprocess.run([BINARY, "mesh", os.path.join(in_dir, name), "-o", out,
                        *forest.option_words(OPTIONS)], check=True, capture_output=True)
        assert _bytes(out) == _bytes(os.path.join(out_dir, stem + ".ply")), name


def test_cluster_identical_to_a_serial_run(cluster_run):
    out_dir, in_dir, work = cluster_run["out_dir"], cluster_run["in_dir"], cluster_run["work"]
    serial_dir = os.path.join(work, "serial")
    # serial, in this process, through the command-line executable, two threads per tree
    results = forest.mesh_all(in_dir, serial_dir, cli=BINARY, threads=2, **OPTIONS)
    assert sum(1 for r in results if r["error"]) == 1
    names = sorted(n for n in os.listdir(out_dir) if n.endswith(".ply"))
    assert names == sorted(n for n in os.listdir(serial_dir) if n.endswith(".ply"))
    for name in names:
        assert _bytes(os.path.join(out_dir, name)) == _bytes(os.path.join(serial_dir, name)), name
    by_input = {r["input"]: r for r in _manifest(out_dir)}
    for r in results:
        assert r["triangles"] == by_input[r["input"]]["triangles"]
        assert r["options_hash"] == by_input[r["input"]]["options_hash"]  # threads excluded


def test_rerun_skips_finished_trees_and_retries_the_failed_one(cluster_run):
    out_dir, in_dir, client = cluster_run["out_dir"], cluster_run["in_dir"], cluster_run["client"]
    before = len(_manifest(out_dir))
    results = forest.mesh_all(in_dir, out_dir, client=client, **OPTIONS)
    assert sum(1 for r in results if r.get("skipped")) == TREES
    retried = [r for r in results if not r.get("skipped")]
    assert len(retried) == 1 and retried[0]["input"].endswith("broken.json")
    assert len(_manifest(out_dir)) == before + 1

    # a deleted output is redone, and only it
    victim = os.path.join(out_dir, "tree023.ply")
    kept = _bytes(victim)
    os.remove(victim)
    results = forest.mesh_all(in_dir, out_dir, client=client, **OPTIONS)
    redone = [r for r in results if not r.get("skipped") and not r["error"]]
    assert [os.path.basename(r["output"]) for r in redone] == ["tree023.ply"]
    assert sum(1 for r in results if r.get("skipped")) == TREES - 1
    assert _bytes(victim) == kept

    # a changed input is redone
    changed = os.path.join(in_dir, "tree002.json")
    subprocess.run([BINARY, "generate", changed, "--segments", "4", "--seed", "99"],
                   check=True, capture_output=True)
    results = forest.mesh_all(in_dir, out_dir, client=client, **OPTIONS)
    redone = [r for r in results if not r.get("skipped") and not r["error"]]
    assert [os.path.basename(r["output"]) for r in redone] == ["tree002.ply"]


def test_other_options_remesh(plot, tmp_path):
    _, in_dir = plot
    paths = [os.path.join(in_dir, "tree001.json"), os.path.join(in_dir, "tree004.json")]
    out_dir = str(tmp_path / "opts")
    first = forest.mesh_all(paths, out_dir, cli=BINARY, levels=1)
    again = forest.mesh_all(paths, out_dir, cli=BINARY, levels=2)
    assert not any(r.get("skipped") for r in again)
    assert all(b["triangles"] > a["triangles"] for a, b in zip(first, again))


def test_command_line_module(plot, tmp_path):
    _, in_dir = plot
    good = tmp_path / "good"
    good.mkdir()
    for name in ("tree004.json", "tree010.ply", "tree011.json"):
        shutil.copy(os.path.join(in_dir, name), good / name)
    env = dict(os.environ, RAMIFORM_BINARY=BINARY)
    run = subprocess.run([sys.executable, "-m", "ramiform.forest", str(good),
                          str(tmp_path / "out"), "--levels", "1"],
                         capture_output=True, text=True, env=env, check=False)
    assert run.returncode == 0, run.stderr
    assert "3 trees: 3 meshed, 0 skipped, 0 failed" in run.stdout
    for stem in ("tree004", "tree010", "tree011"):
        cli_out = tmp_path / f"{stem}.cli.ply"
        src = next(good.glob(stem + ".*"))
        subprocess.run([BINARY, "mesh", str(src), "-o", str(cli_out), "--levels", "1"],
                       check=True, capture_output=True)
        assert _bytes(cli_out) == _bytes(tmp_path / "out" / f"{stem}.ply")
    # the same options from Python and from the command line: everything skipped
    results = forest.mesh_all(str(good), str(tmp_path / "out"), levels=1, cli=BINARY)
    assert all(r.get("skipped") for r in results)

    shutil.copy(os.path.join(in_dir, "broken.json"), good / "broken.json")
    run = subprocess.run([sys.executable, "-m", "ramiform.forest", str(good),
                          str(tmp_path / "out"), "--levels", "1"],
                         capture_output=True, text=True, env=env, check=False)
    assert run.returncode == 2
    assert "4 trees: 0 meshed, 3 skipped, 1 failed" in run.stdout
    assert "broken.json:" in run.stderr


def test_a_tree_turned_bad_loses_its_old_mesh(plot, tmp_path):
    _, in_dir = plot
    tree = tmp_path / "in" / "elm.json"
    tree.parent.mkdir()
    shutil.copy(os.path.join(in_dir, "tree007.json"), tree)
    out_dir = str(tmp_path / "out")
    first = forest.mesh_all(str(tree.parent), out_dir, cli=BINARY, **OPTIONS)
    assert first[0]["error"] is None and os.path.exists(first[0]["output"])
    tree.write_text("{ not json\n")
    again = forest.mesh_all(str(tree.parent), out_dir, cli=BINARY, **OPTIONS)
    assert "elm.json:1" in again[0]["error"]
    assert not os.path.exists(again[0]["output"])
    assert [r["error"] is None for r in _manifest(out_dir)] == [True, False]


def test_a_killed_run_leaves_only_whole_meshes(tmp_path):
    in_dir = tmp_path / "in"
    in_dir.mkdir()
    for seed in range(1, 9):
        subprocess.run([BINARY, "generate", str(in_dir / f"big{seed}.json"), "--segments",
                        BIG_SEGMENTS, "--seed", str(seed)], check=True, capture_output=True)
    out_dir = tmp_path / "out"
    env = dict(os.environ, RAMIFORM_BINARY=BINARY)
    run = subprocess.Popen([sys.executable, "-m", "ramiform.forest", str(in_dir), str(out_dir)],
                           env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    manifest = out_dir / "manifest.jsonl"
    try:
        # kill it (SIGKILL: no cleanup) once some trees are done and the next is being meshed
        for _ in range(600):
            if manifest.exists() and manifest.read_text().count("\n") >= 2:
                break
            if run.poll() is not None:
                break
            time.sleep(0.05)
    finally:
        run.kill()
        run.wait()
    finished = {os.path.basename(r["output"]) for r in _manifest(str(out_dir))}
    assert finished
    whole = sorted(n for n in os.listdir(out_dir) if n.endswith(".ply") and not n.startswith("."))
    assert set(whole) >= finished
    for name in whole:  # every mesh under its final name is the complete one
        cli_out = tmp_path / ("cli_" + name)
        subprocess.run([BINARY, "mesh", str(in_dir / name.replace(".ply", ".json")), "-o",
                        str(cli_out), "--threads", "1"], check=True, capture_output=True)
        assert _bytes(cli_out) == _bytes(out_dir / name), name
    results = forest.mesh_all(str(in_dir), str(out_dir))
    assert sum(1 for r in results if r.get("skipped")) == len(finished)
    assert all(r["error"] is None for r in results)
    assert len([n for n in os.listdir(out_dir) if n.endswith(".ply")
                and not n.startswith(".")]) == 8


def test_bad_options_are_refused_before_any_tree(plot, tmp_path):
    _, in_dir = plot
    paths = [os.path.join(in_dir, "tree001.json")]
    for cli in (None, BINARY):
        with pytest.raises(ValueError, match="levels"):
            forest.mesh_all(paths, str(tmp_path / "a"), cli=cli, levels=99)
        with pytest.raises((TypeError, ValueError), match="bogus"):
            forest.mesh_all(paths, str(tmp_path / "b"), cli=cli, bogus=1)
    assert not (tmp_path / "a" / "manifest.jsonl").exists()
    env = dict(os.environ, RAMIFORM_BINARY=BINARY)
    run = subprocess.run([sys.executable, "-m", "ramiform.forest", in_dir, str(tmp_path / "c"),
                          "--levels", "99"], capture_output=True, text=True, env=env, check=False)
    assert run.returncode == 1
    assert "levels" in run.stderr


def test_forest_imports_without_the_compiled_module(tmp_path):
    """A package without ramiform._ramiform (the sanitizer build, a CLI-only install): forest
    imports and finds the executable; the module's names raise ImportError saying why."""
    package = tmp_path / "ramiform"
    package.mkdir()
    for name in ("__init__.py", "forest.py"):
        shutil.copy(os.path.join(os.path.dirname(forest.__file__), name), package / name)
    code = ("from ramiform import forest\n"
            "import ramiform\n"
            "print(ramiform.__file__)\n"
            "try:\n    ramiform.polygonize_tets\nexcept ImportError as e:\n    print('ok', e)\n")
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    # run in tmp_path: `python -c` puts the working directory first on sys.path
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=env, cwd=tmp_path, check=False)
    assert proc.returncode == 0, proc.stderr
    where, message = proc.stdout.split("\n", 1)
    assert where == str(package / "__init__.py")
    assert message.startswith("ok ramiform.polygonize_tets: the compiled module"), message


def test_in_process_mesh_file_writes_the_cli_bytes(plot, tmp_path):
    """cli=False: the compiled module's mesh_file in this process, byte for byte the CLI's."""
    pytest.importorskip("ramiform._ramiform")
    _, in_dir = plot
    for name in ("tree001.json", "tree008.swc", "tree013.txt", "broken.json"):
        a = forest.mesh_tree(os.path.join(in_dir, name), str(tmp_path / ("a_" + name + ".ply")),
                             OPTIONS, cli=False)
        b = forest.mesh_tree(os.path.join(in_dir, name), str(tmp_path / ("b_" + name + ".ply")),
                             OPTIONS, cli=BINARY)
        assert a["triangles"] == b["triangles"] and a["checks"] == b["checks"]
        assert (a["error"] is None) == (b["error"] is None) == (name != "broken.json")
        if a["error"] is None:
            assert filecmp.cmp(a["output"], b["output"], shallow=False)
