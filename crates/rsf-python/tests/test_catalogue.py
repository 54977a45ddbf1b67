"""A fault network's catalogue from Python: `read_catalogue` gives the `stepover`
program's catalogue.csv as arrays that agree with the events the program put in its
summary.json (written from the same events by serde, independently of the CSV)."""

import json
import subprocess

import numpy as np
import pytest

import rsf

from conftest import program


def test_the_stepover_catalogue_reads_as_its_summarys_events(tmp_path):
    out = tmp_path / "stepover"
    args = [str(program("stepover")), "--out", str(out), "--dx", "500", "--gap-km", "1",
            "--end-years", "300", "--threads", "1"]
    subprocess.run(args, check=True, capture_output=True)
    cat = rsf.read_catalogue(out / "catalogue.csv")
    summary = json.loads((out / "summary.json").read_text())
    events = summary["events"]
    assert cat["faults"] == summary["faults"] == ["south", "north"]
    n = len(events)
    assert n >= 2 and cat["onset"].shape == (n,)
    assert np.array_equal(cat["onset"], [e["onset_s"] for e in events])
    assert np.array_equal(cat["ruptured"], [e["ruptured"] for e in events])
    assert np.array_equal(cat["peak_slip_rate"], [e["peak_slip_rate"] for e in events])
    assert np.array_equal(cat["moment"], [e["moment"] for e in events])
    rupture = np.array([[np.nan if t is None else t for t in e["rupture_s"]] for e in events])
    assert np.array_equal(cat["rupture"], rupture, equal_nan=True)
    names = [summary["faults"][e["nucleation_fault"]] for e in events]
    assert list(cat["nucleation_fault"]) == names
    assert np.array_equal(cat["nucleation_x"], [e["nucleation_x"] for e in events])
    # What the columns mean: a fault ruptured iff it has a rupture time, which lies in
    # its event; ended events last end - onset.
    assert np.array_equal(cat["ruptured"], ~np.isnan(cat["rupture"]))
    done = ~np.isnan(cat["end"])
    assert np.allclose(cat["duration"][done], (cat["end"] - cat["onset"])[done], rtol=1e-12)
    r = cat["ruptured"]
    assert np.all(cat["rupture"][r] >= np.repeat(cat["onset"], 2).reshape(n, 2)[r])
    assert summary["stats"]["ruptured_every_fault"] == int(np.sum(r.all(axis=1)))


def test_a_file_that_is_not_a_catalogue_is_refused_by_name(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("step,t_s,slip\n1,0,0\n")
    with pytest.raises(ValueError, match="bad.csv"):
        rsf.read_catalogue(bad)
