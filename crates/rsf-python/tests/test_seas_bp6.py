"""BP6 from Python (issue 86 item 3): the run writes the benchmark's files byte for byte
as the Rust program `seas_bp6` with the same settings, resumes its own folder to the
uninterrupted run's bytes, refuses bad settings by their keyword, and its pore pressure
is the description's at its check values and the files' column."""

import numpy as np
import pytest

import rsf

from conftest import benchmark_files
from conftest import run_program as conftest_run_program

# Coarse and short: 100 cells of 400 m, half a year (the injection, the slip transient
# to 8e-7 m/s and its decay: about 360 steps, a row at every step); 0.2 s per run here.
FLAGS = dict(variant="a", dz=400.0, end_years=0.5, date="2026-01-01")
# Where the interrupted run stops (in the transient).
STOP = 150

DAY = 86_400.0


files = benchmark_files


def run_program(out, **flags):
    conftest_run_program("seas_bp6", out, **flags)


@pytest.fixture(scope="module")
def whole(tmp_path_factory):
    """The uninterrupted Python run's folder."""
    out = tmp_path_factory.mktemp("whole")
    sim = rsf.seas_bp6(out=out, **FLAGS)
    sim.run()
    assert sim.step > 2 * STOP
    return out


@pytest.mark.parametrize(
    "settings",
    [
        {},
        dict(variant="s"),
        dict(variant="c"),  # the implicit scheme, the kernel as a dense stiffness
        dict(elastic="fe", domain_km=60.0),  # the finite-element half space
    ],
    ids=["a", "s", "c", "a-fe"],
)
def test_python_bp6_writes_the_rust_programs_files(tmp_path, settings):
    flags = dict(FLAGS, **settings)
    run_program(tmp_path / "rust", **flags)
    rsf.seas_bp6(out=tmp_path / "python", **flags).run()
    rust = files(tmp_path / "rust")
    # Nine stations, global.dat, four profiles.
    assert len(rust) == 14
    assert files(tmp_path / "python") == rust


def test_interrupted_and_resumed_bp6_gives_the_uninterrupted_files(tmp_path, whole):
    sim = rsf.seas_bp6(out=tmp_path, **FLAGS)
    sim.advance(steps=STOP, checkpoint_every=STOP)
    assert sim.step == STOP
    assert files(tmp_path) != files(whole)
    rsf.seas_bp6(out=tmp_path, resume=tmp_path / "checkpoint.bin", **FLAGS).run()
    assert files(tmp_path) == files(whole)


def test_the_folder_of_another_run_is_refused(tmp_path, whole):
    rsf.seas_bp6(out=tmp_path, **FLAGS).advance(steps=3)
    with pytest.raises(rsf.RsfIOError):
        rsf.seas_bp6(out=tmp_path, **FLAGS)


@pytest.mark.parametrize(
    "keyword, value",
    [
        ("dz", 300.0),  # does not divide 40 km
        ("end_years", -1.0),
        ("tolerance", 0.5),
        ("variant", "x"),
        ("elastic", "spectral"),
        ("profile_interval", 10.0),
        ("diffusion_cells", 100),  # with the closed form, which would ignore it
        ("kernel", "dense"),  # with the FFT product, which would ignore it
    ],
)
def test_a_bad_setting_is_refused_by_its_keyword(keyword, value):
    with pytest.raises(rsf.InvalidParameterError, match=keyword):
        rsf.seas_bp6(**dict(FLAGS, **{keyword: value}))


def test_bem_product_with_the_finite_elements_is_refused():
    with pytest.raises(rsf.InvalidParameterError, match="bem_product"):
        rsf.seas_bp6(elastic="fe", bem_product="fft", dz=400.0)


# The description's check values of p (MPa, docs/seas-bp6.md: eq. 26 with Table 1's
# parameters, written to three decimals) at z (rows, km) and t (columns, days).
CHECK_MPA = np.array(
    [
        [4.635, 6.555, 2.715, 1.853, 1.258],
        [2.165, 3.899, 2.580, 1.810, 1.244],
        [0.836, 2.116, 2.215, 1.688, 1.205],
        [0.013, 0.181, 0.780, 1.037, 0.963],
        [0.000, 0.000, 0.025, 0.185, 0.433],
    ]
)
CHECK_Z_KM = np.array([0.0, 0.5, 1.0, 2.5, 5.0])
CHECK_T_DAYS = np.array([50.0, 100.0, 200.0, 365.0, 730.0])


def test_the_pore_pressure_is_the_descriptions_at_its_check_values():
    for side in (-1.0, 1.0):
        f = rsf.seas_bp6_pore_pressure(side * CHECK_Z_KM * 1e3, CHECK_T_DAYS * DAY)
        assert f["p"].shape == (5, 5)
        # To the check values' rounding.
        assert np.max(np.abs(f["p"].T / 1e6 - CHECK_MPA)) <= 5e-4
        # The Darcy velocity flows away from the injection.
        q = f["darcy_velocity"][:, 1:]
        assert np.all(side * q[:, :3] > 0)
    # The diffusion solved along the fault converges to it away from the source (its
    # cusp at z = 0 is cut off by h/2 of the gradient: docs/seas-bp6.md).
    away = []
    for cells in (400, 800):
        f = rsf.seas_bp6_pore_pressure(
            CHECK_Z_KM[1:] * 1e3, CHECK_T_DAYS * DAY, pressure="diffusion",
            diffusion_cells=cells,
        )
        away.append(np.max(np.abs(f["p"].T / 1e6 - CHECK_MPA[1:])))
    assert away[1] < away[0] < 0.05


def numeric_rows(text):
    """The rows of numbers of a SEAS file (not its header or field-list lines)."""
    rows = []
    for line in text.splitlines():
        try:
            rows.append([float(x) for x in line.split()])
        except ValueError:
            continue
    return [r for r in rows if r]


def test_the_files_pore_pressure_is_the_functions(whole):
    """The station files' pore pressure column (MPa) is the function's at the station
    and the rows' times (to the files' printed digits)."""
    for name, z_km in [("fltst_strk+05", 0.5), ("fltst_strk-15", -1.5)]:
        rows = np.array(numeric_rows((whole / name).read_text()))
        t, p_mpa = rows[:, 0], rows[:, 4]
        f = rsf.seas_bp6_pore_pressure([z_km * 1e3], t)
        assert np.max(p_mpa) > 0.1
        np.testing.assert_allclose(p_mpa, f["p"][:, 0] / 1e6, rtol=1e-6, atol=1e-12)


def test_pore_pressure_arguments_are_checked():
    with pytest.raises(rsf.InvalidParameterError, match="t"):
        rsf.seas_bp6_pore_pressure([0.0], [-1.0])
    with pytest.raises(rsf.InvalidParameterError, match="diffusion_cells"):
        rsf.seas_bp6_pore_pressure([0.0], [1.0], pressure="diffusion", diffusion_cells=1)
    # Lists of ints are array-likes.
    f = rsf.seas_bp6_pore_pressure([0, 1000], [0, 86400])
    assert f["p"].shape == (2, 2) and np.all(f["p"][0] == 0.0)


def test_a_checkpoint_between_the_files_marks_is_refused(tmp_path):
    """BP6's files keep a mark where each call stops: a checkpoint written before the
    call's end has none, and its resume is refused naming the resume log (the files
    unchanged) rather than continuing them at another step."""
    sim = rsf.seas_bp6(out=tmp_path, **FLAGS)
    sim.advance(steps=STOP + 5, checkpoint_every=STOP)
    before = files(tmp_path)
    with pytest.raises(rsf.RsfError, match="bp6_resume.json"):
        rsf.seas_bp6(out=tmp_path, resume=tmp_path / "checkpoint.bin", **FLAGS)
    assert files(tmp_path) == before
