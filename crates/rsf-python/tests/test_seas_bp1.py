"""BP1 from Python writes the benchmark's files byte for byte as the Rust program
`seas_bp1` with the same flags."""

import subprocess

import numpy as np
import pytest

import rsf

from conftest import program

FLAGS = dict(dz=200.0, domain_km=100.0, end_years=300.0, threads=1, date="2026-01-01")


def test_python_bp1_writes_the_rust_programs_files(tmp_path):
    rust, py = tmp_path / "rust", tmp_path / "python"
    args = [str(program("seas_bp1")), "--out", str(rust)]
    for k, v in FLAGS.items():
        args += ["--" + k.replace("_", "-"), str(v)]
    subprocess.run(args, check=True, capture_output=True)
    sim = rsf.seas_bp1(out=py, **FLAGS)
    sim.run()
    names = sorted(p.name for p in rust.iterdir() if p.name.startswith("fltst_"))
    assert len(names) == 12
    for name in names + ["devol.dat", "events.csv"]:
        assert (py / name).read_bytes() == (rust / name).read_bytes(), name
    # The records in memory: the series reaches the end time (s), events are found.
    s = sim.series()
    assert s["t"][-1] == pytest.approx(300.0 * 365.25 * 24 * 3600, rel=1e-12)
    ev = sim.events()
    assert len(ev["onset"]) >= 2 and np.all(np.diff(ev["onset"]) > 0)
    assert np.all(ev["peak_slip_rate"] > 1e-3)


def test_overwrite_replaces_the_runs_files(tmp_path):
    """A second run into a folder with `overwrite` writes its files anew (the same flags:
    the same bytes); without it the folder is refused."""
    short = dict(FLAGS, end_years=1.0)

    def files():
        return {
            p.name: p.read_bytes()
            for p in tmp_path.iterdir()
            if p.name.startswith("fltst_") or p.name in ("devol.dat", "events.csv")
        }

    rsf.seas_bp1(out=tmp_path, **short).run()
    first = files()
    assert len(first) == 14
    rsf.seas_bp1(out=tmp_path, overwrite=True, **short).run()
    assert files() == first


def test_the_folder_of_another_run_is_refused(tmp_path):
    rsf.seas_bp1(out=tmp_path, **dict(FLAGS, end_years=1.0)).run()
    with pytest.raises(rsf.RsfIOError):
        rsf.seas_bp1(out=tmp_path, **FLAGS)


@pytest.mark.parametrize("epsilon", [0.5, 1e-300])
def test_kernel_epsilon_outside_the_librarys_range_is_refused_by_its_keyword(epsilon):
    # The library's range [1e-14, 1e-2] (rsf::fault_ode::MIN_KERNEL_EPSILON and
    # MAX_KERNEL_EPSILON), named as the keyword: 0.5 passed a range of (2.2e-16, 1) here
    # and was refused later as `kernel.epsilon`; 1e-300 took every block to full rank.
    with pytest.raises(rsf.InvalidParameterError, match="kernel_epsilon"):
        rsf.seas_bp1(dz=1000.0, domain_km=60.0, kernel_epsilon=epsilon, threads=1)
