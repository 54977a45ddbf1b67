"""Shared paths and helpers of the package's tests: the repository, the Rust programs."""

import os
import pathlib
import subprocess

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


def run_program(name, out, check=True, **flags):
    """Runs the program `name` into `out` with `flags` (Python's keyword names: `--` and
    dashes for underscores); its completed process (text). `check`: a failure raises."""
    args = [str(program(name)), "--out", str(out)]
    for k, v in flags.items():
        args += ["--" + k.replace("_", "-"), str(v)]
    return subprocess.run(args, check=check, capture_output=True, text=True)


def benchmark_files(folder):
    """The benchmark's files of a run's folder by name — the stations (`fltst_`, `srfst_`,
    `blkst_`), the `.dat` series and profiles, `events.csv` — not the run's manifest, its
    checkpoint or resume log (which name the run and its stops), nor a program's own
    summary and figure."""
    return {
        p.name: p.read_bytes()
        for p in sorted(pathlib.Path(folder).iterdir())
        if p.is_file()
        and (
            p.name.startswith(("fltst_", "srfst_", "blkst_"))
            or p.suffix == ".dat"
            or p.name == "events.csv"
        )
    }
