# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""Mesh a forest: one independent task per tree, on Dask distributed (docs/forests.md).

``mesh_all(inputs, out_dir, client=None, **mesh_options)`` meshes every skeleton or cylinder
file (.json .ply .obj .txt .csv .swc) exactly as ``ramiform mesh INPUT -o OUTPUT [options]``
does, one task per tree, and records each tree in ``out_dir/manifest.jsonl``. A rerun skips the
trees already done with the same input bytes and options, and retries the failed ones.

Command line: ``python3 -m ramiform.forest IN_DIR OUT_DIR [--scheduler ADDRESS] [--workers N]
[--threads T] [mesh options ...]``; exit 0 when every tree succeeded, 2 when some failed,
1 on a usage error.
"""

import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

#: File name endings read as trees.
TREE_SUFFIXES = (".json", ".ply", ".obj", ".txt", ".csv", ".swc")

MANIFEST = "manifest.jsonl"


def _find_cli():
    """The ``ramiform`` executable: each tree runs in its own process of it when it is found
    (faster than the in-process ``ramiform.mesh_file``: the executable runs with its malloc
    settings, docs/benchmarks.md "Forests on Dask")."""
    found = os.environ.get("RAMIFORM_BINARY") or shutil.which("ramiform")
    if found:
        return found
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.abspath(os.path.join(here, "..", ".."))
    for build in ("build", "build-me", "build-forest"):
        candidate = os.path.join(root, build, "ramiform")
        if os.access(candidate, os.X_OK):
            return candidate
    return None


def _program(cli):
    """The executable to run: ``cli`` when given, none for ``cli=False`` (in-process
    ``ramiform.mesh_file``), else the one _find_cli finds."""
    if cli is False:
        return None
    return cli or _find_cli()


def _mesh_file():
    """``ramiform.mesh_file`` when the compiled module provides it, else None."""
    try:
        from ramiform import mesh_file  # noqa: PLC0415
    except ImportError:
        return None
    return mesh_file


def option_words(options):
    """The ``ramiform mesh`` words for keyword options: key k is --k with '_' as '-'; True is
    the flag, False its --no- form, a list comma-separated values, None the default."""
    words = []
    for key in sorted(options):
        value = options[key]
        flag = "--" + key.replace("_", "-")
        if value is None:
            continue
        if value is True:
            words.append(flag)
        elif value is False:
            words.append("--no-" + key.replace("_", "-"))
        elif isinstance(value, (list, tuple)):
            words += [flag, ",".join(str(v) for v in value)]
        else:
            words += [flag, str(value)]
    return words


def options_hash(options, suffix):
    """Hash of the options that shape the output (``threads`` never does)."""
    shaped = {k: v for k, v in options.items() if k not in ("threads", "cli")}
    # The command words: levels=2 from Python and "--levels 2" from the command line agree.
    text = json.dumps({"options": option_words(shaped), "suffix": suffix})
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def file_hash(path):
    """SHA-256 of a file's bytes (hex)."""
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _run_cli(cli, input_path, output_path, options):
    with tempfile.TemporaryDirectory(prefix="ramiform-forest-") as tmp:
        stats_path = os.path.join(tmp, "stats.json")
        words = [cli, "mesh", input_path, "-o", output_path, "--stats", stats_path]
        proc = subprocess.run(words + option_words(options), capture_output=True, text=True,
                              check=False)
        if proc.returncode != 0:
            message = proc.stderr.strip() or proc.stdout.strip()
            raise ValueError(message.replace("ramiform: error: ", "")
                             or f"ramiform mesh exited {proc.returncode}")
        with open(stats_path, encoding="utf-8") as f:
            stats = json.load(f)
    stats.pop("seconds", None)
    return stats


_CHECKS = ("watertight", "manifold", "oriented", "components", "skeleton_components",
           "deviation_p99", "tolerance_reached")


def mesh_tree(input_path, output_path, options, cli=None):
    """Mesh one tree; a pure function of the input's bytes and ``options`` (the Dask task).

    Writes ``output_path`` atomically: the mesh goes to a temporary name in the same folder
    (same ending, so the same format) and is renamed when complete, so a killed run never
    leaves a half file under the final name. Returns one manifest record (dict); a bad input
    gives a record with ``error`` set, never an exception, and removes an older mesh left
    under ``output_path`` (it belonged to other input bytes or options).
    """
    options = dict(options)
    options.setdefault("threads", 1)
    suffix = os.path.splitext(output_path)[1]
    folder = os.path.dirname(os.path.abspath(output_path))
    base = os.path.basename(output_path)
    partial = os.path.join(folder, f".{base}.partial-{os.getpid()}{suffix}")
    record = {"input": os.path.abspath(input_path), "output": os.path.abspath(output_path),
              "triangles": None, "seconds": None, "checks": None, "error": None,
              "input_sha256": None, "options_hash": options_hash(options, suffix)}
    start = time.perf_counter()
    try:
        record["input_sha256"] = file_hash(input_path)
        program = _program(cli)
        mesh_file = None if program else _mesh_file()
        if mesh_file is not None:
            stats = mesh_file(input_path, partial, **options)
            stats = dict(stats)
        else:
            if program is None:
                raise RuntimeError("neither ramiform.mesh_file nor a ramiform executable found")
            stats = _run_cli(program, input_path, partial, options)
        os.replace(partial, output_path)
        record["triangles"] = stats.get("triangles")
        record["checks"] = {k: stats[k] for k in _CHECKS if k in stats}
    except (ValueError, OSError, RuntimeError) as e:
        record["error"] = str(e) or type(e).__name__
        # An older mesh under the final name belongs to other input bytes or options.
        if os.path.exists(output_path):
            os.remove(output_path)
    finally:
        if os.path.exists(partial):
            os.remove(partial)
    record["seconds"] = round(time.perf_counter() - start, 4)
    return record


def check_options(options, suffix=".ply", cli=None):
    """Raise ValueError (a bad value) or TypeError (an unknown option) when ``ramiform mesh``
    refuses ``options``, before any tree is submitted: a bad option is the caller's error,
    not a failure of every tree. Probes the command with a path that cannot exist (the
    options are parsed before any file is opened)."""
    missing = os.path.join(tempfile.gettempdir(),
                           f"ramiform-forest-absent-{os.getpid()}-{time.time_ns()}")
    probe_in, probe_out = os.path.join(missing, "probe.json"), os.path.join(missing, "p" + suffix)
    program = _program(cli)
    mesh_file = None if program else _mesh_file()
    if mesh_file is not None:
        try:
            mesh_file(probe_in, probe_out, **options)
        except ValueError as e:
            if str(e).startswith("mesh_file():"):
                raise
        return
    if program is None:
        raise RuntimeError("neither ramiform.mesh_file nor a ramiform executable found")
    proc = subprocess.run([program, "mesh", probe_in, "-o", probe_out] + option_words(options),
                          capture_output=True, text=True, check=False)
    if proc.returncode == 1:
        raise ValueError(proc.stderr.strip().splitlines()[0] if proc.stderr.strip()
                         else "ramiform mesh refused the options")


def list_inputs(inputs):
    """The tree files of a directory (sorted, by ending) or a list of paths."""
    if isinstance(inputs, (str, os.PathLike)) and os.path.isdir(inputs):
        names = sorted(n for n in os.listdir(inputs)
                       if n.lower().endswith(TREE_SUFFIXES) and not n.startswith("."))
        return [os.path.join(inputs, n) for n in names]
    if isinstance(inputs, (str, os.PathLike)):
        return [os.fspath(inputs)]
    return [os.fspath(p) for p in inputs]


def read_manifest(out_dir):
    """The last record of each input in ``out_dir/manifest.jsonl`` (dict by input path)."""
    latest = {}
    path = os.path.join(out_dir, MANIFEST)
    if not os.path.exists(path):
        return latest
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if not line:
                continue
            try:
                record = json.loads(line)
            except json.JSONDecodeError:
                continue  # a line cut by a killed run
            latest[record["input"]] = record
    return latest


def _output_for(input_path, out_dir, suffix, taken):
    stem = os.path.splitext(os.path.basename(input_path))[0]
    name = stem + suffix
    if name in taken:  # tree.json and tree.ply in one folder
        name = os.path.basename(input_path).replace(".", "_") + suffix
    taken.add(name)
    return os.path.join(out_dir, name)


def mesh_all(inputs, out_dir, client=None, suffix=".ply", **mesh_options):
    """Mesh every tree of ``inputs`` into ``out_dir``; one Dask task per tree.

    inputs: a directory (its .json .ply .obj .txt .csv .swc files) or a list of paths.
    out_dir: created if missing; tree ``a/oak.csv`` becomes ``out_dir/oak<suffix>``.
    client: a ``distributed.Client`` (local or remote scheduler); None runs the trees serially
    in this process. mesh_options: the ``ramiform mesh`` options as keywords (levels=2,
    tolerance=0.02, fit_radii=True, ...); ``threads`` defaults to 1 per task, and results
    never depend on it. Each tree runs in a process of the ``ramiform`` executable when one is
    found (``cli=PATH`` names it); ``cli=False`` meshes in the worker's own process with the
    compiled module's ``mesh_file`` instead (the same bytes, about a quarter slower).

    Returns one record per input, in input order (the manifest's lines for this run, and the
    earlier records of skipped trees with ``"skipped": True``). A tree whose previous record
    has no error, the same input bytes, the same options hash and whose output still exists
    is skipped; every other tree is (re)meshed and its record appended to the manifest.

    Options that ``ramiform mesh`` refuses raise ValueError (TypeError for an unknown one)
    before any tree runs; a bad tree file never raises.
    """
    os.makedirs(out_dir, exist_ok=True)
    cli = mesh_options.pop("cli", None)
    options = dict(mesh_options)
    options.setdefault("threads", 1)
    check_options(options, suffix, cli)
    paths = list_inputs(inputs)
    previous = read_manifest(out_dir)
    digest = options_hash(options, suffix)
    taken = set()
    jobs, results = [], [None] * len(paths)
    for i, path in enumerate(paths):
        output = _output_for(path, out_dir, suffix, taken)
        old = previous.get(os.path.abspath(path))
        if (old and old.get("error") is None and old.get("options_hash") == digest
                and os.path.exists(output) and old.get("output") == os.path.abspath(output)
                and old.get("input_sha256") == file_hash(path)):
            results[i] = dict(old, skipped=True)
        else:
            jobs.append((i, path, output))
    manifest = open(os.path.join(out_dir, MANIFEST), "a", encoding="utf-8")
    with manifest:
        def record(i, rec):
            results[i] = rec
            manifest.write(json.dumps(rec, sort_keys=True) + "\n")
            manifest.flush()

        if client is None:
            for i, path, output in jobs:
                record(i, mesh_tree(path, output, options, cli))
        else:
            from distributed import as_completed  # noqa: PLC0415
            # A window of tasks in flight, refilled as trees finish: a city's million trees
            # never sit in the scheduler at once (each pending task costs it memory).
            window = max(8, 4 * _cluster_threads(client))
            pending = iter(jobs)
            futures = {}

            def submit(ac=None):
                job = next(pending, None)
                if job is None:
                    return False
                i, path, output = job
                future = client.submit(mesh_tree, path, output, options, cli, pure=False,
                                       key=f"ramiform-tree-{i}-{digest}-{time.time_ns()}")
                futures[future] = i
                if ac is not None:
                    ac.add(future)
                return True

            for _ in range(window):
                if not submit():
                    break
            running = as_completed(list(futures))
            for future in running:
                record(futures.pop(future), future.result())
                submit(running)
    return results


def _cluster_threads(client):
    """Worker threads of the cluster behind ``client`` (at least 1)."""
    try:
        return max(1, sum(client.nthreads().values()))
    except Exception:  # noqa: BLE001 (a scheduler that cannot say: use the minimum window)
        return 1


def _mesh_options(words):
    """``--levels 2 --fit-radii --no-cleanup`` -> {"levels": "2", "fit_radii": True, ...}."""
    options, i = {}, 0
    while i < len(words):
        word = words[i]
        if not word.startswith("--") or len(word) < 3:
            raise ValueError(f"unexpected argument {word!r} (mesh options are --name [value])")
        key = word[2:].replace("-", "_")
        if "=" in key:
            key, value = key.split("=", 1)
            options[key] = value
            i += 1
            continue
        values = []
        while i + 1 < len(words) and not (words[i + 1].startswith("--")):
            values.append(words[i + 1])
            i += 1
        if key.startswith("no_") and not values:
            options[key[3:]] = False
        elif not values:
            options[key] = True
        else:
            options[key] = values[0] if len(values) == 1 else values
        i += 1
    return options


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="python3 -m ramiform.forest",
        description="Mesh every tree file of IN_DIR into OUT_DIR, one Dask task per tree; "
                    "other options are passed to `ramiform mesh`. Exit 0: all trees meshed; "
                    "2: some failed (see OUT_DIR/manifest.jsonl); 1: usage.")
    parser.add_argument("in_dir")
    parser.add_argument("out_dir")
    parser.add_argument("--scheduler", help="address of a running scheduler, tcp://host:8786")
    parser.add_argument("--workers", type=int, default=0,
                        help="local worker processes (default 0: serial, in this process)")
    parser.add_argument("--threads", type=int, default=1, help="threads per tree (default 1)")
    parser.add_argument("--suffix", default=".ply", help="output ending (.ply .obj .off .glb)")
    args, rest = parser.parse_known_args(argv)
    try:
        options = _mesh_options(rest)
    except ValueError as e:
        parser.print_usage(sys.stderr)
        print(f"forest: error: {e}", file=sys.stderr)
        return 1
    if not os.path.isdir(args.in_dir):
        print(f"forest: error: {args.in_dir}: not a directory", file=sys.stderr)
        return 1
    client = cluster = None
    start = time.perf_counter()
    if args.scheduler or args.workers > 0:
        from distributed import Client, LocalCluster  # noqa: PLC0415
        if args.scheduler:
            client = Client(args.scheduler)
        else:
            cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
            client = Client(cluster)
    try:
        results = mesh_all(args.in_dir, args.out_dir, client=client, suffix=args.suffix,
                           threads=args.threads, **options)
    except (ValueError, TypeError) as e:
        print(f"forest: error: {e}", file=sys.stderr)
        return 1
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
    failed = [r for r in results if r.get("error")]
    skipped = sum(1 for r in results if r.get("skipped"))
    for r in failed:
        print(f"forest: {r['input']}: {r['error']}", file=sys.stderr)
    seconds = time.perf_counter() - start
    print(f"forest: {len(results)} trees: {len(results) - len(failed) - skipped} meshed, "
          f"{skipped} skipped, {len(failed)} failed in {seconds:.1f} s; "
          f"manifest {os.path.join(args.out_dir, MANIFEST)}")
    return 2 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
