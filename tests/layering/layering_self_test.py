#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""The layering check catches what it must: on a copy of the project's table and headers, a
backward public include, a backward internal include, a relative include out of its folder and
an unknown stage folder each fail with the file and line named; the untouched copy passes.

usage: layering_self_test.py ROOT
"""

import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
CHECK = os.path.join(HERE, "check_layering.py")


def run(root):
    r = subprocess.run([sys.executable, CHECK, root], capture_output=True, text=True)
    return r.returncode, r.stdout + r.stderr


def expect(condition, message):
    if not condition:
        print("FAILED:", message)
        sys.exit(1)


def main(argv):
    source = os.path.abspath(argv[1])
    with tempfile.TemporaryDirectory() as tmp:
        os.makedirs(os.path.join(tmp, "docs"))
        shutil.copy(os.path.join(source, "docs", "architecture.md"), os.path.join(tmp, "docs"))
        shutil.copytree(os.path.join(source, "src"), os.path.join(tmp, "src"))
        shutil.copytree(os.path.join(source, "include"), os.path.join(tmp, "include"))

        rc, out = run(tmp)
        expect(rc == 0, f"the project's own tree must pass, got {rc}:\n{out}")

        # field/ reaching up into io/ (public header), as curves.cpp once did.
        victim = os.path.join(tmp, "src", "field", "kernels.cpp")
        with open(victim, encoding="utf-8") as f:
            text = f.read()
        with open(victim, "w", encoding="utf-8") as f:
            f.write('#include "ramiform/io/mesh_io.h"\n' + text)
        rc, out = run(tmp)
        expect(rc == 1, f"a backward public include must fail, got {rc}:\n{out}")
        expect("src/field/kernels.cpp:1: includes ramiform/io/mesh_io.h" in out and
               "'field' may not include 'io'" in out, f"message must name file, line, rule:\n{out}")

        # An internal header of a higher stage, in a public header of a lower one.
        with open(victim, "w", encoding="utf-8") as f:
            f.write(text)
        header = os.path.join(tmp, "include", "ramiform", "core", "types.h")
        with open(header, encoding="utf-8") as f:
            lines = f.read().split("\n")
        lines.insert(4, '#include "polygonize/delaunay.h"')
        with open(header, "w", encoding="utf-8") as f:
            f.write("\n".join(lines))
        rc, out = run(tmp)
        expect(rc == 1 and "include/ramiform/core/types.h:5: includes polygonize/delaunay.h" in out
               and "'core' may not include 'polygonize'" in out,
               f"a backward internal include must fail:\n{out}")

        # A relative path out of the folder (it would get past the stage include path too).
        with open(victim, "w", encoding="utf-8") as f:
            f.write('#include "../io/text_scan.h"\n' + text)
        rc, out = run(tmp)
        expect(rc == 1 and "src/field/kernels.cpp:1: includes ../io/text_scan.h: a relative path"
               in out, f"a relative include out of the folder must fail:\n{out}")
        with open(victim, "w", encoding="utf-8") as f:
            f.write(text)

        # A folder that is no stage of the table.
        os.remove(header)
        shutil.copy(os.path.join(source, "include", "ramiform", "core", "types.h"), header)
        os.makedirs(os.path.join(tmp, "src", "gizmo"))
        rc, out = run(tmp)
        expect(rc == 1 and "src/gizmo: folder is not a stage" in out, f"unknown stage:\n{out}")
    print("layering self-test: 5 passed, 0 failed")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
