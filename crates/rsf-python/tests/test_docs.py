"""Every ```python block of docs/python.md runs (from the repository's root, figures
with matplotlib's Agg back end)."""

import os
import re

import pytest

from conftest import REPO

BLOCKS = re.findall(r"```python\n(.*?)```", (REPO / "docs" / "python.md").read_text(), re.S)


def test_the_page_has_its_eight_examples():
    # BP1 end to end, BP6 (fluid injection), BP3 and BP5, BP1 interrupted and resumed into
    # its folder, a 2-D problem from a Gmsh file, a fault network of your own, the
    # dislocation kernels, the Green's functions.
    assert len(BLOCKS) == 8


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_docs_python_block_runs(index, tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    monkeypatch.chdir(REPO)
    code = BLOCKS[index].replace('"out/', f'"{tmp_path}/out/')
    os.makedirs(tmp_path / "out", exist_ok=True)
    exec(compile(code, f"docs/python.md block {index}", "exec"), {})
