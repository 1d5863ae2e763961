# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""Every ```python block of docs/python.md runs, each in a fresh directory, as a reader would
paste it (the examples assert what they claim)."""

import os
import re
import runpy

import pytest

DOCS = os.environ.get("RAMIFORM_DOCS") or os.path.join(os.path.dirname(__file__), "..", "..", "docs")
PAGE = os.path.join(DOCS, "python.md")


def _blocks():
    with open(PAGE, encoding="utf-8") as f:
        return re.findall(r"^```python\n(.*?)^```", f.read(), flags=re.S | re.M)


def test_the_page_has_the_examples():
    blocks = _blocks()
    assert len(blocks) >= 3
    # the first example is the ten-line one the page promises
    code = [line for line in blocks[0].splitlines() if line.strip()]
    assert len(code) <= 12, code


@pytest.mark.parametrize("index", range(len(_blocks())))
def test_example_runs(index, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    path = tmp_path / f"example_{index}.py"
    path.write_text(_blocks()[index], encoding="utf-8")
    runpy.run_path(str(path), run_name="__main__")
    if "savefig" in _blocks()[index]:
        assert (tmp_path / "python_tree.png").stat().st_size > 10000
