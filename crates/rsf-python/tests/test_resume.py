"""BP1 from Python resumes by the programs' folder rule (docs/reliability.md, "Round 5";
issues 86 and 87): a checkpoint continues only the files of its own run — proven by the
folder's manifest (its run id) or, where the manifest is missing, by the files themselves
— `overwrite=True` with `resume` gives another run's folder to the checkpoint's run whole
or refuses, and a simulation that writes files is never resumed behind their back."""

import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest

import rsf

from conftest import program

# Coarse and short: 2 s of stepping per run on this machine.
FLAGS = dict(dz=1000.0, domain_km=60.0, end_years=150.0, threads=1, date="2026-01-01")
# Another trajectory from the first steps, the same fingerprint fields but one.
OTHER = dict(FLAGS, rk_tolerance=1e-7)
# Where the interrupted runs stop (a checkpoint there).
STOP = 800


def files(folder):
    """The files of a run's folder by name, but those that name a run or its time
    (`rsf-run.txt`: the run id; `checkpoint.bin`: wall times)."""
    return {
        p.name: p.read_bytes()
        for p in sorted(pathlib.Path(folder).iterdir())
        if p.is_file() and p.name not in ("rsf-run.txt", "checkpoint.bin")
    }


def interrupted(out, **flags):
    """A run into `out` stopped after `STOP` steps with its checkpoint `out/checkpoint.bin`
    (the default path of a run with `out`)."""
    sim = rsf.seas_bp1(out=out, **dict(FLAGS, **flags))
    sim.advance(steps=STOP, checkpoint_every=STOP)
    assert sim.step == STOP
    return pathlib.Path(out) / "checkpoint.bin"


def in_new_process(**kwargs):
    """`rsf.seas_bp1(**kwargs).run()` in a new Python process: its result."""
    code = "import rsf, sys; rsf.seas_bp1(**eval(sys.argv[1])).run()"
    args = {k: str(v) if isinstance(v, pathlib.Path) else v for k, v in kwargs.items()}
    return subprocess.run(
        [sys.executable, "-c", code, repr(args)], capture_output=True, text=True
    )


@pytest.fixture(scope="module")
def whole(tmp_path_factory):
    """The uninterrupted run's folder."""
    out = tmp_path_factory.mktemp("whole")
    rsf.seas_bp1(out=out, **FLAGS).run()
    return out


def test_interrupted_and_resumed_in_a_new_process_gives_the_uninterrupted_files(
    tmp_path, whole
):
    checkpoint = interrupted(tmp_path)
    assert files(tmp_path) != files(whole)
    done = in_new_process(out=tmp_path, resume=checkpoint, **FLAGS)
    assert done.returncode == 0, done.stderr
    assert files(tmp_path) == files(whole)
    assert len([n for n in files(whole) if n.startswith("fltst_")]) == 12


def test_a_checkpoint_elsewhere_carries_the_run_and_resumes_its_folder(tmp_path, whole):
    """A checkpoint outside `out` carries the folder's run id: it resumes the folder."""
    out, elsewhere = tmp_path / "run", tmp_path / "elsewhere.bin"
    sim = rsf.seas_bp1(out=out, **FLAGS)
    sim.advance(steps=STOP, checkpoint=elsewhere, checkpoint_every=STOP)
    run_line = [
        ln for ln in (out / "rsf-run.txt").read_text().splitlines() if ln.startswith("run=")
    ]
    assert run_line and run_line[0][4:].encode() in elsewhere.read_bytes()
    rsf.seas_bp1(out=out, resume=elsewhere, **FLAGS).run()
    assert files(out) == files(whole)


def test_a_folder_without_manifest_refuses_another_runs_checkpoint(tmp_path):
    """The issue's first splice: B (another trajectory) finished, its `rsf-run.txt`
    deleted, takes A's checkpoint: refused by B's own files, B unchanged, no run id."""
    a, b = tmp_path / "a", tmp_path / "b"
    checkpoint = interrupted(a)
    rsf.seas_bp1(out=b, **OTHER).run()
    (b / "rsf-run.txt").unlink()
    before = files(b)
    with pytest.raises(rsf.CheckpointError, match="splice"):
        rsf.seas_bp1(out=b, resume=checkpoint, **FLAGS)
    assert files(b) == before
    manifest = b / "rsf-run.txt"
    assert not manifest.exists() or "run=" not in manifest.read_text()


def test_a_folder_of_another_run_is_refused_naming_the_python_keywords(tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    checkpoint = interrupted(a)
    rsf.seas_bp1(out=b, **OTHER).run()
    before = files(b)
    with pytest.raises(rsf.CheckpointError) as refused:
        rsf.seas_bp1(out=b, resume=checkpoint, **FLAGS)
    message = str(refused.value)
    assert "`overwrite=True`" in message and "--" not in message, message
    assert files(b) == before


def test_overwrite_gives_another_runs_folder_to_the_checkpoints_run_whole(tmp_path):
    """The issue's second splice: `resume` + `overwrite=True` into another finished run's
    folder ends byte-identical to the checkpoint's run resumed in its own folder."""
    a, b, own = tmp_path / "a", tmp_path / "b", tmp_path / "own"
    checkpoint = interrupted(a)
    shutil.copytree(a, own)
    rsf.seas_bp1(out=b, **OTHER).run()
    done = in_new_process(out=b, resume=checkpoint, overwrite=True, **FLAGS)
    assert done.returncode == 0, done.stderr
    rsf.seas_bp1(out=own, resume=own / "checkpoint.bin", **FLAGS).run()
    assert files(b) == files(own)


def test_overwrite_then_resume_never_loses_years(tmp_path, whole):
    """Issue 86's 494 years: a simulation built with `overwrite=True` (its files written
    anew from t = 0) is not resumed behind its files' back — `Simulation.resume` raises
    naming `resume=`; `resume=` with `overwrite=True` into the checkpoint's own folder is
    refused (nothing to replace); the folder resumed without it is the whole run."""
    elsewhere = tmp_path / "a.bin"
    out = tmp_path / "run"
    sim = rsf.seas_bp1(out=out, **FLAGS)
    sim.advance(steps=STOP, checkpoint=elsewhere, checkpoint_every=STOP)
    fresh = rsf.seas_bp1(out=tmp_path / "fresh", overwrite=True, **FLAGS)
    with pytest.raises(rsf.InvalidParameterError, match="resume="):
        fresh.resume(elsewhere)
    with pytest.raises(rsf.CheckpointError, match="`overwrite=True`"):
        rsf.seas_bp1(out=out, resume=elsewhere, overwrite=True, **FLAGS)
    rsf.seas_bp1(out=out, resume=elsewhere, **FLAGS).run()
    assert files(out) == files(whole)


def test_a_checkpoint_of_the_program_resumes_from_python_and_back(tmp_path, whole):
    """The same fingerprint both ways: the program's checkpoint continued from Python and
    Python's by the program give the uninterrupted run's files."""
    flags = []
    for k, v in FLAGS.items():
        flags += ["--" + k.replace("_", "-"), str(v)]
    rust = tmp_path / "rust"
    stopped = subprocess.run(
        [str(program("seas_bp1")), "--out", str(rust), "--max-steps", str(STOP)] + flags,
        capture_output=True,
        text=True,
    )
    assert stopped.returncode != 0 and "step cap" in stopped.stderr, stopped.stderr
    rsf.seas_bp1(out=rust, resume=rust / "checkpoint.bin", **FLAGS).run()
    assert files(rust).items() >= files(whole).items()
    py = tmp_path / "python"
    checkpoint = interrupted(py)
    done = subprocess.run(
        [str(program("seas_bp1")), "--out", str(py), "--resume", str(checkpoint)] + flags,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    assert files(py).items() >= files(whole).items()


PREDICATE_RUN = """
import sys
import numpy as np
import rsf

mesh = rsf.Mesh.read_gmsh(sys.argv[1])
model = rsf.Model(mesh, refine=1, youngs_modulus=5e7, poisson_ratio=0.3, density=5e3,
                  gravity=(0.0, -9.81), dirichlet=[("top", (2e-4, 0.0))],
                  frictional_boundary=("base", lambda x: bool(x[1] < 1e-9)), ramp=3.75)
friction = rsf.Friction.dieterich_ruina(mu0=0.6, a=0.010, b=0.015, v0=1e-6, l=1e-5,
                                        sigma_n=49050.0)
sim = rsf.simulate(model, friction=friction, state_law="aging", alpha0=-10.0,
                   tau=1.5e-3, end_time=0.3)
if sys.argv[2] == "stop":
    sim.advance(steps=100)
    sim.checkpoint(sys.argv[3])
else:
    if sys.argv[2] == "resume":
        sim.resume(sys.argv[3])
    sim.run()
    np.save(sys.argv[4], np.array([sim.fields()["displacement"], sim.fields()["velocity"]]))
"""


def test_a_predicate_models_checkpoint_resumes_in_a_new_process(tmp_path, repo):
    """Issue 86 item 2: a frictional part given as a Python predicate is fingerprinted by
    the nodes it selects, not by the function's address: its checkpoint resumes in a new
    process, to the uninterrupted run's state bit for bit."""
    mesh = repo / "crates/rsf-fem/tests/fixtures/plate.msh"
    checkpoint = tmp_path / "predicate.bin"

    def go(*args):
        done = subprocess.run(
            [sys.executable, "-c", PREDICATE_RUN, str(mesh)] + [str(a) for a in args],
            capture_output=True,
            text=True,
        )
        assert done.returncode == 0, done.stderr
        return done

    go("stop", checkpoint)
    go("resume", checkpoint, tmp_path / "resumed.npy")
    go("whole", checkpoint, tmp_path / "whole.npy")
    resumed, whole = np.load(tmp_path / "resumed.npy"), np.load(tmp_path / "whole.npy")
    assert resumed.tobytes() == whole.tobytes()
