"""The notebook docs/notebooks/first_session.ipynb runs: its code cells in order, in one
namespace, from the repository's root (figures with matplotlib's Agg back end) — as a
reader's kernel would run them, without a kernel (no Jupyter needed in CI)."""

import json

import pytest

from conftest import REPO

NOTEBOOK = REPO / "docs" / "notebooks" / "first_session.ipynb"


def test_the_notebook_runs_top_to_bottom(monkeypatch):
    pytest.importorskip("matplotlib")
    pytest.importorskip("pandas")
    pytest.importorskip("xarray")
    monkeypatch.chdir(REPO)
    cells = json.loads(NOTEBOOK.read_text())["cells"]
    code = [c for c in cells if c["cell_type"] == "code"]
    assert len(code) >= 5
    namespace: dict = {}
    for i, cell in enumerate(code):
        exec(compile("".join(cell["source"]), f"{NOTEBOOK.name} cell {i}", "exec"), namespace)
    # What the cells computed: a run, its records and a figure.
    assert namespace["summary"]["steps"] > 0
    assert namespace["fault"].sizes["t"] > 1
    assert namespace["fig"].axes[0].get_ylabel() == "slip rate (m/s)"
