# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""Every ```python block of docs/python.md and docs/neurons.md runs, each in a fresh directory
(holding a small neuron.swc for the neuron page), as a reader would paste it (the examples
assert what they claim)."""

import math
import os
import re
import runpy

import pytest

DOCS = os.environ.get("RAMIFORM_DOCS") or os.path.join(os.path.dirname(__file__), "..", "..", "docs")
PAGE = os.path.join(DOCS, "python.md")
NEURONS = os.path.join(DOCS, "neurons.md")
SWC = "1 1 0 0 0 6 -1\n2 3 7 0 0 1.2 1\n3 3 20 0 2 0.6 2\n4 2 -7 0 0 1 1\n5 2 -25 1 0 0.5 4\n"


def _blocks(page=PAGE):
    with open(page, encoding="utf-8") as f:
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


def test_neuron_example_runs(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "neuron.swc").write_text(SWC, encoding="utf-8")
    (block,) = _blocks(NEURONS)
    script = tmp_path / "example.py"
    script.write_text(block, encoding="utf-8")
    runpy.run_path(str(script), run_name="__main__")
    assert (tmp_path / "neuron.ply").exists()
    # the soma's membrane: a sphere of radius 6 (the neurites cover a little of it)
    soma = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("1 "))
    area = float(soma.split()[1])
    assert 0.9 * 4 * math.pi * 36 < area < 1.01 * 4 * math.pi * 36
