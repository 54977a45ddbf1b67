"""The type stubs of the native module (``rsf/_rsf.pyi``) agree with the built module
(mypy's ``stubtest``: every name, signature, default and class of the runtime module
against the stub), and mypy finds no error in the documentation's examples checked
against them (issue 86: stubs generated and checked by mypy in CI). A stub that drifts
from the module — a keyword added in Rust and not in the stub — fails here."""

import re
import subprocess
import sys

import pytest

from conftest import REPO

pytest.importorskip("mypy")


def run(args, cwd):
    return subprocess.run(
        [sys.executable, "-m", *args], cwd=cwd, capture_output=True, text=True
    )


def test_the_stubs_are_the_native_modules(tmp_path):
    r = run(["mypy.stubtest", "rsf._rsf"], tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr


def test_mypy_passes_on_the_docs_examples(tmp_path):
    text = (REPO / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert blocks
    for i, b in enumerate(blocks):
        (tmp_path / f"block{i}.py").write_text(b)
    # Third-party packages without stubs (matplotlib, scipy) are Any; rsf's names are
    # checked against the stubs.
    r = run(["mypy", "--ignore-missing-imports", *sorted(p.name for p in tmp_path.glob("block*.py"))], tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr


def test_mypy_finds_a_wrong_argument(tmp_path):
    # The check bites: a string where the stub says float.
    (tmp_path / "wrong.py").write_text('import rsf\nrsf.seas_bp1(dz="25")\n')
    r = run(["mypy", "--ignore-missing-imports", "wrong.py"], tmp_path)
    assert r.returncode != 0 and "dz" in r.stdout, r.stdout
