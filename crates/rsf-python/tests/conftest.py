"""Shared paths and helpers of the package's tests: the repository, the Rust programs."""

import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]


@pytest.fixture
def repo():
    """The repository's root."""
    return REPO


def program(name):
    """The example `name` built by the README's test command (or a release build), or the
    program the environment variable `RSF_<NAME>` names."""
    given = os.environ.get("RSF_" + name.upper())
    if given:
        candidates = [pathlib.Path(given)]
    else:
        candidates = []
        for profile in ("release", "debug"):
            examples = REPO / "target" / profile / "examples"
            candidates.append(examples / name)
            # cargo test leaves the example under its hashed name.
            candidates += [p for p in examples.glob(name + "-*") if p.suffix == ""]
    found = [c for c in candidates if c.exists() and os.access(c, os.X_OK)]
    if not found:
        pytest.fail(
            f"no {name} program: run `cargo test --workspace --all-features` (which builds "
            f"the examples) or set RSF_{name.upper()} to the program"
        )
    return max(found, key=lambda p: p.stat().st_mtime)
