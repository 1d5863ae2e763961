#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""Checks that no #include crosses the pipeline backwards.

The stages and what each may include are read from the table between <!-- stages:begin -->
and <!-- stages:end --> in docs/architecture.md (the same table CMake reads). Every file
under src/<stage>/ and include/ramiform/<stage>/ may include headers of its own stage and of
the stages in its row: public ones as "ramiform/<stage>/x.h" or <ramiform/<stage>/x.h>,
internal ones as "<stage>/x.h". Includes of headers in the same folder ("x.h") and of other
libraries are not checked; a path with ".." is refused (it would hide the stage it reaches). Prints one line per violation, "file:line: ..."; exits 1 when there
is any, 2 when the table cannot be read, else 0.

usage: check_layering.py [ROOT]   (ROOT: the project's root, default: two folders up)
"""

import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]')
ROW = re.compile(r"^\|\s*([a-z_]+)\s*\|([a-z_, ]*)\|\s*$")
SOURCE_SUFFIXES = (".h", ".hpp", ".cpp", ".cc", ".inc", ".in")


def read_table(path):
    """Returns (stages in order, {stage: set of stages it may include})."""
    order, allowed, inside = [], {}, False
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if "<!-- stages:begin -->" in line:
                inside = True
            elif "<!-- stages:end -->" in line:
                inside = False
            elif inside:
                m = ROW.match(line.strip())
                if not m or m.group(1) == "stage":
                    continue
                stage = m.group(1)
                lower = {s for s in re.split(r"[,\s]+", m.group(2)) if s}
                unknown = sorted(lower - set(order))
                if unknown:
                    raise ValueError(f"{path}:{number}: stage '{stage}' may include "
                                     f"{', '.join(unknown)}, not listed above it")
                order.append(stage)
                allowed[stage] = lower | {stage}
    if not order:
        raise ValueError(f"{path}: no stage table between <!-- stages:begin --> and "
                         "<!-- stages:end -->")
    return order, allowed


def target_stage(header, stages):
    """The stage a quoted include names, or None for same-folder and third-party headers."""
    parts = header.split("/")
    if len(parts) >= 3 and parts[0] == "ramiform" and parts[1] in stages:
        return parts[1]
    if len(parts) >= 2 and parts[0] in stages:
        return parts[0]
    return None


def check(root):
    order, allowed = read_table(os.path.join(root, "docs", "architecture.md"))
    stages = set(order)
    problems, files = [], 0
    for base in ("src", os.path.join("include", "ramiform")):
        base_dir = os.path.join(root, base)
        if not os.path.isdir(base_dir):
            continue
        for entry in sorted(os.listdir(base_dir)):
            folder = os.path.join(base_dir, entry)
            if not os.path.isdir(folder):
                continue
            if entry not in stages:
                problems.append(f"{os.path.join(base, entry)}: folder is not a stage of the table "
                                "in docs/architecture.md")
                continue
            for dirpath, _, names in os.walk(folder):
                for name in sorted(names):
                    if not name.endswith(SOURCE_SUFFIXES):
                        continue
                    path = os.path.join(dirpath, name)
                    files += 1
                    rel = os.path.relpath(path, root)
                    with open(path, encoding="utf-8", errors="replace") as f:
                        for number, line in enumerate(f, 1):
                            m = INCLUDE.match(line)
                            if not m:
                                continue
                            if ".." in m.group(1).split("/"):
                                problems.append(f"{rel}:{number}: includes {m.group(1)}: a "
                                                "relative path out of the folder hides which "
                                                "stage it reaches; name the stage "
                                                "(\"ramiform/<stage>/...\" or \"<stage>/...\")")
                                continue
                            to = target_stage(m.group(1), stages)
                            if to is not None and to not in allowed[entry]:
                                may = ", ".join(s for s in order if s in allowed[entry])
                                problems.append(f"{rel}:{number}: includes {m.group(1)}: stage "
                                                f"'{entry}' may not include '{to}' (it may "
                                                f"include: {may})")
    return problems, files


def main(argv):
    root = argv[1] if len(argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
    try:
        problems, files = check(os.path.abspath(root))
    except (OSError, ValueError) as e:
        print(f"layering: {e}", file=sys.stderr)
        return 2
    for p in problems:
        print(p)
    if problems:
        print(f"layering: {len(problems)} include(s) cross the pipeline backwards "
              "(docs/architecture.md)")
        return 1
    print(f"layering: {files} files checked, every include follows docs/architecture.md")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
