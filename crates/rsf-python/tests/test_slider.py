"""The paper's slider from Python: shapes and units of the records, named errors,
per-node parameters as functions and arrays, checkpoints and resume."""

import numpy as np
import pytest

import rsf

STEPS = 60
SCENE = dict(level=2, steps=STEPS, end_time_s=0.9, solver="direct")


def test_records_have_the_documented_shapes_and_units():
    sim = rsf.slider(fault_every=20, **SCENE)
    summary = sim.run()
    assert summary["steps"] == STEPS and sim.step == STEPS
    s = sim.series()
    for key in ("t", "tau", "step", "max_slip_rate", "fixed_point_iterations"):
        assert s[key].shape == (STEPS,), key
    # Fixed steps tau = T / N (s), the time after step n is n tau.
    tau = SCENE["end_time_s"] / STEPS
    np.testing.assert_allclose(s["tau"], tau, rtol=1e-12)
    np.testing.assert_allclose(s["t"], tau * np.arange(1, STEPS + 1), rtol=1e-9)
    assert np.all(s["step"] == np.arange(1, STEPS + 1))
    f = sim.fault()
    x = sim.fault_coordinates
    n = x.shape[0]
    assert x.shape == (n, 2) and n > 4
    # The fault is the block's base y = 0, 0 <= x <= 5 m.
    assert np.all(x[:, 1] == 0.0) and x[:, 0].min() == 0.0 and x[:, 0].max() == 5.0
    assert f["t"].shape == (STEPS // 20,)
    assert f["slip_rate"].shape == (STEPS // 20, n)
    assert f["alpha"].shape == (STEPS // 20, n)
    assert f["slip"].shape == (STEPS // 20, n, 2)
    assert f["shear_traction"].shape == (STEPS // 20, n)
    # The records at the recorded steps agree with the series (m/s).
    at = np.searchsorted(s["t"], f["t"])
    np.testing.assert_array_equal(f["slip_rate"].max(axis=1), s["max_slip_rate"][at])
    # Slip is tangential (bilateral contact): its normal component vanishes.
    assert np.all(f["slip"][:, :, 1] == 0.0)
    fields = sim.fields()
    v = fields["points"].shape[0]
    assert fields["displacement"].shape == (v, 2) and fields["velocity"].shape == (v, 2)
    assert fields["cells"].shape[1] == 3 and fields["cells"].max() == v - 1


def test_an_invalid_parameter_raises_the_named_exception_naming_it():
    with pytest.raises(rsf.InvalidParameterError, match="level"):
        rsf.slider(level=11)
    with pytest.raises(rsf.InvalidParameterError, match="levl"):
        rsf.slider(levl=2)
    with pytest.raises(rsf.InvalidParameterError, match="steps"):
        rsf.slider(steps="many")
    with pytest.raises(rsf.InvalidParameterError, match=r"`b`.*shape"):
        rsf.slider(level=1, b=[0.01, 0.02])
    with pytest.raises(rsf.InvalidParameterError, match="`state_law`.*healing"):
        rsf.slider(state_law="healing")
    assert issubclass(rsf.InvalidParameterError, rsf.RsfError)


def b_profile(x):
    """Velocity weakening in the middle of the fault only."""
    return 0.005 + 0.012 * np.exp(-((x[:, 0] - 2.5) ** 2))


def test_a_function_of_the_coordinates_and_the_equivalent_array_give_the_same_bits():
    by_function = rsf.slider(b=b_profile, **SCENE)
    x = by_function.fault_coordinates
    by_array = rsf.slider(b=b_profile(x), **SCENE)
    uniform = rsf.slider(**SCENE)
    for sim in (by_function, by_array, uniform):
        sim.run()
    a, b = by_function.series(), by_array.series()
    assert a["max_slip_rate"].tobytes() == b["max_slip_rate"].tobytes()
    fa, fb = by_function.fields(), by_array.fields()
    assert fa["velocity"].tobytes() == fb["velocity"].tobytes()
    # ... and the profile matters (the check could fail).
    assert uniform.series()["max_slip_rate"].tobytes() != a["max_slip_rate"].tobytes()


def test_resume_after_a_stop_gives_the_uninterrupted_runs_arrays(tmp_path):
    whole = rsf.slider(fault_every=10, **SCENE)
    whole.run()
    first = rsf.slider(fault_every=10, **SCENE)
    first.advance(steps=STEPS // 2)
    path = tmp_path / "half.ckpt"
    first.checkpoint(path)
    rest = rsf.slider(fault_every=10, **SCENE)
    rest.resume(path)
    assert rest.step == STEPS // 2
    rest.run()
    w, a, b = whole.series(), first.series(), rest.series()
    for key in w:
        joined = np.concatenate([a[key], b[key]])
        assert joined.tobytes() == w[key].tobytes(), key
    wf, af, bf = whole.fault(), first.fault(), rest.fault()
    joined = np.concatenate([af["slip_rate"], bf["slip_rate"]])
    assert joined.tobytes() == wf["slip_rate"].tobytes()
    assert rest.fields()["displacement"].tobytes() == whole.fields()["displacement"].tobytes()


def test_a_checkpoint_of_another_scene_is_refused(tmp_path):
    sim = rsf.slider(**SCENE)
    sim.advance(steps=2)
    path = tmp_path / "c.ckpt"
    sim.checkpoint(path)
    other = rsf.slider(**dict(SCENE, b=0.02))
    with pytest.raises(rsf.CheckpointError, match="b"):
        other.resume(path)


def test_pandas_and_xarray_views():
    pd = pytest.importorskip("pandas")
    xr = pytest.importorskip("xarray")
    sim = rsf.slider(fault_every=10, **SCENE)
    sim.advance(steps=20)
    frame = sim.to_pandas()
    assert isinstance(frame, pd.DataFrame) and len(frame) == 20
    ds = sim.to_xarray()
    assert isinstance(ds, xr.Dataset)
    assert ds["slip_rate"].dims == ("t", "node") and ds.sizes["t"] == 2
