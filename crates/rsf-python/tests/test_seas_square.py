"""BP7 and BP8 from Python (issue 86 items 1 and 3): the keyword arguments are the
programs' run configurations (the same names, defaults and ranges as the flags and the
keys of a `--config` file); a run writes the benchmark's files byte for byte as the Rust
program with the same settings — given as flags or as a TOML file — resumes its own
folder to the uninterrupted run's bytes, and refuses a bad setting by its keyword."""

import pathlib
import subprocess

import pytest

import rsf

from conftest import program

# Coarse and short: 100 cells of 80 m. BP7 for 0.4 s (the bump's rise, T = 1 s, not
# reached: the first rows and the slip's start), BP8 for half a day of injection.
BP7 = dict(dx=80.0, end_years=0.4 / 31_557_600.0, date="2026-01-01")
BP8 = dict(dx=80.0, end_days=0.5, date="2026-01-01")


def files(folder):
    """The benchmark's files of a run's folder by name (not the run's manifest, its
    checkpoint, its summary or the resume log, which name the run and its stops)."""
    skip = {"checkpoint.bin", "summary.json", "rsf-run.txt"}
    return {
        p.name: p.read_bytes()
        for p in sorted(pathlib.Path(folder).iterdir())
        if p.is_file() and p.name not in skip and p.suffix != ".json"
    }


def run_program(name, out, flags=(), config=None):
    args = [str(program(name)), "--out", str(out), *flags]
    if config is not None:
        args += ["--config", str(config)]
    subprocess.run(args, check=True, capture_output=True)


def as_flags(settings):
    out = []
    for k, v in settings.items():
        out += ["--" + k.replace("_", "-"), str(v)]
    return out


def as_toml(settings):
    """The settings as a `--config` file's lines (the date is a flag: it is the files'
    header, not a setting)."""
    lines = []
    for k, v in settings.items():
        if k == "date":
            continue
        lines.append(f"{k} = {v!r}" if isinstance(v, float) else f'{k} = "{v}"')
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize(
    "name, settings",
    [
        ("seas_bp7", BP7),
        ("seas_bp7", dict(BP7, law="slip", d_rs=0.53)),
        ("seas_bp8", BP8),
        ("seas_bp8", dict(BP8, source="pw", sigma_min=2.0)),
    ],
    ids=["bp7-aging", "bp7-slip", "bp8-gs", "bp8-pw"],
)
def test_python_writes_the_rust_programs_files(tmp_path, name, settings):
    getattr(rsf, name)(out=tmp_path / "python", **settings).run()
    python = files(tmp_path / "python")
    assert any(n.startswith("fltst_") for n in python) and "global.dat" in python
    run_program(name, tmp_path / "flags", as_flags(settings))
    assert files(tmp_path / "flags") == python
    # The same settings as the program's TOML file.
    config = tmp_path / "run.toml"
    config.write_text(as_toml(settings))
    run_program(name, tmp_path / "file", ["--date", settings["date"]], config)
    assert files(tmp_path / "file") == python


def test_interrupted_and_resumed_bp8_gives_the_uninterrupted_files(tmp_path):
    # Through the shut-in at 100 hours.
    settings = dict(BP8, end_days=5.0)
    whole = rsf.seas_bp8(out=tmp_path / "whole", **settings)
    whole.run()
    steps = whole.step
    assert steps > 20
    part = tmp_path / "part"
    sim = rsf.seas_bp8(out=part, **settings)
    sim.advance(steps=steps // 2, checkpoint_every=steps // 2)
    assert files(part) != files(tmp_path / "whole")
    rsf.seas_bp8(out=part, resume=part / "checkpoint.bin", **settings).run()
    assert files(part) == files(tmp_path / "whole")


@pytest.mark.parametrize(
    "name, settings, keyword",
    [
        ("seas_bp7", dict(dx=30.0), "dx"),  # 800 m is no whole number of 30 m cells
        ("seas_bp7", dict(dx=float("nan")), "dx"),
        ("seas_bp7", dict(law="agin"), "law"),
        ("seas_bp7", dict(d_c=1.0), "d_c"),  # no such setting: BP7 calls it d_rs
        ("seas_bp7", dict(end_years="ten"), "end_years"),
        ("seas_bp8", dict(sigma_min=2.0, overpressure="refuse"), "sigma_min"),
        ("seas_bp8", dict(tolerance=1.0), "tolerance"),
        ("seas_bp8", dict(source="well"), "source"),
    ],
)
def test_a_bad_setting_is_refused_by_its_keyword(tmp_path, name, settings, keyword):
    with pytest.raises(rsf.InvalidParameterError, match=keyword):
        getattr(rsf, name)(out=tmp_path, **settings)
    # Refused before the folder was made.
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(
    "name, settings, station",
    [
        ("seas_bp7", BP7, "fltst_strk-100dp-100"),
        ("seas_bp8", BP8, "fltst_strk+000dp+000"),
    ],
    ids=["bp7", "bp8"],
)
def test_the_finite_element_kernel_from_python_is_the_programs(
    tmp_path, name, settings, station
):
    """`kernel="fe"` (a finite-element box, 1.6 km) from Python runs the program's
    volume: the same files byte for byte (both order the volume by nested dissection
    where METIS is built, AMD where not)."""
    fe = dict(settings, kernel="fe", domain_km=1.6)
    getattr(rsf, name)(out=tmp_path / "python", **fe).run()
    python = files(tmp_path / "python")
    assert station in python
    run_program(name, tmp_path / "program", as_flags(fe))
    assert files(tmp_path / "program") == python
    # Without the finite elements the box's settings are refused by name.
    with pytest.raises(rsf.InvalidParameterError, match="domain_km"):
        getattr(rsf, name)(**dict(settings, domain_km=1.6))
