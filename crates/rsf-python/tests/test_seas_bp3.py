"""BP3 from Python (issue 86 item 3): the run writes the benchmark's files byte for byte
as the Rust program `seas_bp3` with the same settings, a checkpoint of the program
resumes here to the uninterrupted run's bytes (and the package's own), another run's
folder is refused, and bad settings are refused by their keyword."""

import pytest

import rsf

from conftest import benchmark_files, run_program

# Coarse and short: 2 km elements in a ±100 km box graded by 1.2 (the grid of
# rsf-scenes' BP3 tests), the first years of loading.
GRID = dict(dx=2000.0, domain_km=100.0, ratio=1.2, threads=1, date="2026-01-01")
FLAGS = dict(GRID, end_years=20.0)
# Where the interrupted runs stop.
STOP = 40


@pytest.fixture(scope="module")
def whole(tmp_path_factory):
    """The uninterrupted Python run's folder (the thrust)."""
    out = tmp_path_factory.mktemp("whole")
    sim = rsf.seas_bp3(out=out, **FLAGS)
    sim.run()
    assert sim.step > 2 * STOP
    return out


@pytest.mark.parametrize("dip", [60.0, 30.0], ids=["thrust", "normal"])
def test_python_bp3_writes_the_rust_programs_files(tmp_path, dip):
    flags = dict(FLAGS, dip=dip)
    run_program("seas_bp3", tmp_path / "rust", **flags)
    rsf.seas_bp3(out=tmp_path / "python", **flags).run()
    rust = benchmark_files(tmp_path / "rust")
    # Twelve fault stations, eight surface stations, three profiles, events.csv.
    assert len(rust) == 24
    assert benchmark_files(tmp_path / "python") == rust


def test_a_checkpoint_of_the_program_resumes_in_python(tmp_path, whole):
    # The program stops at its step cap with a checkpoint (and says so, failing).
    stopped = run_program("seas_bp3", tmp_path, check=False, max_steps=STOP, **FLAGS)
    assert "step cap" in stopped.stderr, stopped.stderr
    assert benchmark_files(tmp_path) != benchmark_files(whole)
    rsf.seas_bp3(out=tmp_path, resume=tmp_path / "checkpoint.bin", **FLAGS).run()
    assert benchmark_files(tmp_path) == benchmark_files(whole)


def test_interrupted_and_resumed_bp3_gives_the_uninterrupted_files(tmp_path, whole):
    sim = rsf.seas_bp3(out=tmp_path, **FLAGS)
    sim.advance(steps=STOP, checkpoint_every=STOP)
    assert sim.step == STOP
    rsf.seas_bp3(out=tmp_path, resume=tmp_path / "checkpoint.bin", **FLAGS).run()
    assert benchmark_files(tmp_path) == benchmark_files(whole)


def test_the_folder_of_another_run_is_refused(tmp_path):
    rsf.seas_bp3(out=tmp_path, **FLAGS).advance(steps=3)
    with pytest.raises(rsf.RsfIOError):
        rsf.seas_bp3(out=tmp_path, **dict(FLAGS, dip=30.0))


@pytest.mark.parametrize(
    "keyword, value",
    [
        ("dip", 0.5),  # a flat detachment
        ("dip", 90.0),
        ("dx", 2e4),  # above W_f/4
        ("domain_km", 50.0),  # the box must reach 1.5 W_f down the fault
        ("ratio", 3.0),
        ("end_years", -1.0),
        ("tolerance", 2.0),
        ("kernel", "spectral"),
        ("integrator", "euler"),
        ("sigma_n", -1.0),  # a scene parameter, BP1's table
    ],
)
def test_a_bad_setting_is_refused_by_its_keyword(keyword, value):
    with pytest.raises(rsf.InvalidParameterError, match=keyword):
        rsf.seas_bp3(**dict(FLAGS, **{keyword: value}))
