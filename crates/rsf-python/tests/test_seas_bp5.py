"""BP5 from Python (issue 86 item 3): with either kernel — Okada's half-space and the
finite-element volume — the run writes the benchmark's files byte for byte as the Rust
program `seas_bp5` with the same settings; it resumes its own folder to the
uninterrupted run's bytes; the friction of the description is settable; bad settings
and settings the kernel would ignore are refused by their keyword."""

import pytest

import rsf

from conftest import benchmark_files, run_program

# Coarse and short: 10 km cells (10 × 4 on the rate-and-state region), the first years.
OKADA = dict(dx=10_000.0, end_years=5.0, threads=1, date="2026-01-01")
# The finite-element volume at its coarsest: 20 km cells in a ±100 km box graded by 2,
# the default ordering on both sides (nested dissection: the package and the program are
# built with METIS by default), and AMD's given as a keyword.
FE = dict(
    OKADA,
    kernel="fe",
    dx=20_000.0,
    domain_km=100.0,
    ratio=2.0,
    end_years=1.0,
)
STOP = 20


@pytest.mark.parametrize(
    "flags",
    [OKADA, FE, dict(FE, ordering="amd"), dict(FE, condensation="factor")],
    ids=["okada", "fe", "fe-amd", "fe-factor"],
)
def test_python_bp5_writes_the_rust_programs_files(tmp_path, flags):
    run_program("seas_bp5", tmp_path / "rust", **flags)
    rsf.seas_bp5(out=tmp_path / "python", **flags).run()
    rust = benchmark_files(tmp_path / "rust")
    # Ten fault stations, nine body stations, global.dat, profiles, rupture.dat,
    # events.csv.
    assert len(rust) > 20
    assert benchmark_files(tmp_path / "python") == rust


def test_interrupted_and_resumed_bp5_gives_the_uninterrupted_files(tmp_path):
    whole = tmp_path / "whole"
    sim = rsf.seas_bp5(out=whole, **OKADA)
    sim.run()
    assert sim.step > 2 * STOP
    part = tmp_path / "part"
    sim = rsf.seas_bp5(out=part, **OKADA)
    sim.advance(steps=STOP)
    sim.checkpoint(part / "checkpoint.bin")
    assert benchmark_files(part) != benchmark_files(whole)
    rsf.seas_bp5(out=part, resume=part / "checkpoint.bin", **OKADA).run()
    assert benchmark_files(part) == benchmark_files(whole)


def test_the_friction_is_settable_and_in_the_fingerprint(tmp_path):
    """`b0` (the description's b) changes the run: its checkpoint is refused by a run of
    the description's b, naming the field, unless `allow_change` names it."""
    out = tmp_path / "weaker"
    sim = rsf.seas_bp5(out=out, b0=0.025, **OKADA)
    sim.advance(steps=3)
    sim.checkpoint(out / "checkpoint.bin")
    with pytest.raises(rsf.CheckpointError, match="b0"):
        rsf.seas_bp5(resume=out / "checkpoint.bin", **OKADA)
    rsf.seas_bp5(resume=out / "checkpoint.bin", allow_change=["b0"], **OKADA)


@pytest.mark.parametrize(
    "keyword, value",
    [
        ("dx", 3000.0),  # does not divide 100 km and 40 km
        ("end_years", -1.0),
        ("tolerance", 0.0),
        ("epsilon", 0.5),
        ("kernel", "spectral"),
        ("integrator", "euler"),
        ("b0", -0.03),  # a scene parameter
        # Settings of the finite-element kernel, which Okada's would ignore.
        ("domain_km", 100.0),
        ("ratio", 1.5),
        ("mesh", "tensor"),
        ("condensation", "factor"),
        ("ordering", "amd"),
        ("fault_zone_width_km", 4.0),
    ],
)
def test_a_bad_setting_is_refused_by_its_keyword(keyword, value):
    with pytest.raises(rsf.InvalidParameterError, match=keyword):
        rsf.seas_bp5(**dict(OKADA, **{keyword: value}))


@pytest.mark.parametrize(
    "keyword, value",
    [
        ("domain_km", 50.0),
        ("ratio", 3.0),
        ("mesh", "octree"),
        ("condensation", "lu"),
        ("ordering", "rcm"),
        ("fault_zone_rigidity", 0.5),  # without its width
    ],
)
def test_a_bad_volume_setting_is_refused_by_its_keyword(keyword, value):
    with pytest.raises(rsf.InvalidParameterError, match=keyword):
        rsf.seas_bp5(**dict(FE, **{keyword: value}))
