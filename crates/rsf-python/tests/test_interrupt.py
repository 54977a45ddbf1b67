"""Ctrl-C: a SIGINT sent to a process running a simulation stops it at a step boundary
with a checkpoint, from which another process continues on the uninterrupted run's
trajectory."""

import signal
import subprocess
import sys
import time

import pytest

import rsf

# tau = 3 ms: the run is far longer than the 1.5 s before the signal and has no failing step
# in its first 135 s of model time (at tau = 15 ms, end_time_s=1500, the relaxed fixed point
# does not converge at step 8376, t = 125.6 s, which a child on a fast or idle machine
# reached within 1.5 s: the test then failed with that ConvergenceError).
SCENE = dict(level=3, steps=100000, end_time_s=300.0, solver="direct")

CHILD = """
import sys
import rsf
sim = rsf.slider(**{scene!r})
print("started", flush=True)
try:
    sim.run(checkpoint=sys.argv[1])
except KeyboardInterrupt as e:
    print("interrupted", sim.step, e, flush=True)
    sys.exit(0)
sys.exit(3)
"""


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_ctrl_c_leaves_a_checkpoint_that_resumes(tmp_path):
    path = tmp_path / "interrupted.ckpt"
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD.format(scene=SCENE), str(path)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert child.stdout.readline().strip() == "started"
    time.sleep(1.5)
    child.send_signal(signal.SIGINT)
    out, err = child.communicate(timeout=60)
    assert child.returncode == 0, (out, err)
    words = out.split()
    assert words[0] == "interrupted", out
    step = int(words[1])
    assert 0 < step < SCENE["steps"]
    assert "checkpoint written" in out and path.exists()
    # The checkpoint resumes, and the resumed run is the uninterrupted one.
    resumed = rsf.slider(**SCENE)
    resumed.resume(path)
    assert resumed.step == step
    resumed.advance(steps=5)
    whole = rsf.slider(**SCENE)
    whole.advance(steps=step + 5)
    assert resumed.time == whole.time
    assert resumed.fields()["velocity"].tobytes() == whole.fields()["velocity"].tobytes()
