"""HDF5 fields of the 3-D slider read back with h5py: the file's fault fields equal the
records the run keeps in memory, its last frame the state, and the Xdmf index parses and
references the file's datasets. BP1's series in `seas.h5` equal its text files read by
numpy."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest

import rsf

SCENE = dict(level=0, steps=100, loading_velocity_m_per_s=2e-2)


@pytest.mark.skipif(rsf.HAS_HDF5, reason="this build has HDF5 output")
def test_without_the_feature_hdf5_is_a_named_error(tmp_path):
    with pytest.raises(rsf.InvalidParameterError, match="hdf5"):
        rsf.slider_3d(hdf5=tmp_path / "f.h5", **SCENE)


@pytest.mark.skipif(not rsf.HAS_HDF5, reason="built without the feature hdf5")
def test_hdf5_fields_read_back_with_h5py_equal_the_run(tmp_path):
    h5py = pytest.importorskip("h5py")
    path = tmp_path / "fields.h5"
    sim = rsf.slider_3d(hdf5=path, hdf5_every=2, fault_every=2, **SCENE)
    sim.advance(steps=6)
    rec = sim.fault()
    with h5py.File(path, "r") as f:
        assert list(f["step"][:]) == [2, 4, 6]
        np.testing.assert_array_equal(f["time"][:], rec["t"])
        nodes = f["mesh/fault_nodes"][:]
        np.testing.assert_array_equal(f["mesh/points"][:][nodes], rec["x"])
        n = f["mesh/points"].shape[0]
        assert f["fields/displacement"].shape == (3, n, 3)
        assert f["fields/slip_rate"].shape == (3, n)
        # On the fault: the records' values, bit for bit; off the fault NaN.
        assert f["fields/slip_rate"][:, nodes].tobytes() == rec["slip_rate"].tobytes()
        assert f["fields/state_alpha"][:, nodes].tobytes() == rec["alpha"].tobytes()
        assert f["fields/slip"][:, nodes, :].tobytes() == rec["slip"].tobytes()
        assert f["fields/shear_traction"][:, nodes].tobytes() == rec["shear_traction"].tobytes()
        off = np.setdiff1d(np.arange(n), nodes)
        assert np.all(np.isnan(f["fields/slip_rate"][:, off]))
        # The last frame is the state now.
        state = sim.fields()
        assert f["fields/velocity"][-1].tobytes() == state["velocity"].tobytes()
        assert np.any(rec["slip_rate"] > 0)
        # The Xdmf index: XML whose every HDF reference is a dataset of the declared size.
        root = ET.parse(path.with_suffix(".xmf")).getroot()
        grids = root.findall(".//Grid[@GridType='Uniform']")
        assert [float(g.find("Time").get("Value")) for g in grids] == list(f["time"][:])
        refs = [d for d in root.iter("DataItem") if d.get("Format") == "HDF"]
        # Per frame: the cells, the points and the 8 point fields (rsf::observe::POINT_FIELDS).
        assert len(refs) == 3 * 10
        for d in refs:
            name, dataset = d.text.strip().split(":")
            assert name == path.name
            dims = tuple(int(x) for x in d.get("Dimensions").split())
            assert f[dataset].shape == dims, dataset


# 300 years: at dz = 400 m the first event starts at about 214 years.
BP1 = dict(dz=400.0, domain_km=100.0, end_years=300.0, threads=1, date="2026-01-01")


@pytest.mark.skipif(not rsf.HAS_HDF5, reason="built without the feature hdf5")
def test_a_simulation_writing_hdf5_is_not_resumed_behind_its_file(tmp_path):
    """`Simulation.resume` on a simulation whose HDF5 file was written from its own start
    raises naming `resume` (issue 86: the file would be continued from another step)."""
    sim = rsf.slider_3d(**SCENE)
    sim.advance(steps=3)
    sim.checkpoint(tmp_path / "c.bin")
    writing = rsf.slider_3d(hdf5=tmp_path / "f.h5", **SCENE)
    with pytest.raises(rsf.InvalidParameterError, match="resume"):
        writing.resume(tmp_path / "c.bin")


@pytest.mark.skipif(not rsf.HAS_HDF5, reason="built without the feature hdf5")
def test_an_hdf5_run_resumed_from_its_checkpoint_writes_the_uninterrupted_file(tmp_path):
    """`rsf.slider_3d(hdf5=…, resume=…)` continues the fields file at the checkpoint's step
    once the file shows it holds the checkpoint's run (issue 87): a run stopped after its
    checkpoint (two frames past it) and resumed in a new simulation ends with the
    uninterrupted run's datasets, bit for bit; the file of another run (another loading
    velocity) is refused, unchanged, and `allow_change` without `resume` is refused."""
    h5py = pytest.importorskip("h5py")
    whole, part, other = (tmp_path / n for n in ("whole.h5", "part.h5", "other.h5"))
    rsf.slider_3d(hdf5=whole, hdf5_every=2, **SCENE).advance(steps=8)
    first = rsf.slider_3d(hdf5=part, hdf5_every=2, **SCENE)
    first.advance(steps=4)
    first.checkpoint(tmp_path / "c.bin")
    first.advance(steps=2)
    del first
    faster = dict(SCENE, loading_velocity_m_per_s=3e-2)
    rsf.slider_3d(hdf5=other, hdf5_every=2, **faster).advance(steps=6)
    before = other.read_bytes()
    with pytest.raises(rsf.CheckpointError, match="another run"):
        rsf.slider_3d(hdf5=other, hdf5_every=2, resume=tmp_path / "c.bin", **SCENE)
    assert other.read_bytes() == before
    with pytest.raises(rsf.InvalidParameterError, match="allow_change"):
        rsf.slider_3d(allow_change=["end_time_s"], **SCENE)
    resumed = rsf.slider_3d(hdf5=part, hdf5_every=2, resume=tmp_path / "c.bin", **SCENE)
    resumed.advance(steps=4)
    with h5py.File(whole, "r") as a, h5py.File(part, "r") as b:
        assert list(b["step"][:]) == [2, 4, 6, 8]
        names = ["step", "time"] + [f"fields/{n}" for n in a["fields"]]
        for name in names:
            assert a[name][:].tobytes() == b[name][:].tobytes(), name


@pytest.mark.skipif(not rsf.HAS_HDF5, reason="built without the feature hdf5")
def test_read_fields_names_the_dimensions_and_gives_cf_units(tmp_path):
    """`rsf.read_fields` gives the file as an xarray Dataset on named dimensions (xarray's
    own engines see `phony_dim_N`), its values the file's bit for bit, CF `units` on every
    field and coordinate, the fault's nodes marked."""
    h5py = pytest.importorskip("h5py")
    pytest.importorskip("xarray")
    path = tmp_path / "fields.h5"
    sim = rsf.slider_3d(hdf5=path, hdf5_every=2, fault_every=2, **SCENE)
    sim.advance(steps=6)
    ds = rsf.read_fields(path)
    with h5py.File(path, "r") as f:
        n = f["mesh/points"].shape[0]
        assert dict(ds.sizes) == {
            "time": 3, "vertex": n, "component": 3,
            "cell": f["mesh/cells"].shape[0], "corner": 4,
        }
        assert ds["displacement"].dims == ("time", "vertex", "component")
        assert ds["slip_rate"].dims == ("time", "vertex")
        for name in f["fields"]:
            assert ds[name].values.tobytes() == f[f"fields/{name}"][:].tobytes(), name
        assert ds["time"].values.tobytes() == f["time"][:].tobytes()
        assert list(ds["step"].values) == [2, 4, 6]
        assert ds["on_fault"].values.sum() == f["mesh/fault_nodes"].shape[0]
    units = {name: ds[name].attrs["units"] for name in ds.data_vars if name != "cells"}
    assert units == {
        "displacement": "m", "velocity": "m/s", "slip_rate": "m/s", "state_alpha": "1",
        "slip": "m", "shear_traction": "Pa", "normal_traction": "Pa", "fault": "1",
    }
    assert ds["time"].attrs["units"] == "s" and ds["x"].attrs["units"] == "m"
    assert "fingerprint" in ds.attrs
    # On the fault: the records' slip rates.
    rec = sim.fault()
    on = ds["slip_rate"].isel(vertex=np.flatnonzero(ds["on_fault"].values))
    assert np.isnan(ds["slip_rate"].where(~ds["on_fault"]).values).all()
    assert np.sort(on.values, axis=1).tobytes() == np.sort(rec["slip_rate"], axis=1).tobytes()


@pytest.mark.skipif(rsf.HAS_HDF5, reason="this build has HDF5 output")
def test_without_the_feature_seas_series_are_a_named_error(tmp_path):
    with pytest.raises(rsf.InvalidParameterError, match="hdf5"):
        rsf.seas_bp1(out=tmp_path, hdf5=True, **BP1)


@pytest.mark.skipif(not rsf.HAS_HDF5, reason="built without the feature hdf5")
def test_bp1_series_in_hdf5_equal_its_text_files(tmp_path):
    h5py = pytest.importorskip("h5py")
    with pytest.raises(rsf.InvalidParameterError, match="out"):
        rsf.seas_bp1(hdf5=True, **BP1)
    sim = rsf.seas_bp1(out=tmp_path, hdf5=True, **BP1)
    sim.run()
    stations = sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("fltst_"))
    assert len(stations) == 12
    with h5py.File(tmp_path / "seas.h5", "r") as f:
        assert sorted(f.keys()) == sorted(stations + ["devol.dat", "events"])
        for name in stations:
            # numpy's own reader of the text file: the same numbers, bit for bit.
            path = tmp_path / name
            text = np.loadtxt(path, skiprows=_header_lines(path) + 1, ndmin=2)
            g = f[name]
            columns = ["t", "slip", "slip_rate", "shear_stress", "state"]
            for j, c in enumerate(columns):
                assert g[c][:].tobytes() == text[:, j].tobytes(), (name, c)
            assert g.attrs["location"].startswith("on fault")
        path = tmp_path / "devol.dat"
        devol = np.loadtxt(path, skiprows=_header_lines(path) + 2)
        assert f["devol.dat/z"][:].tobytes() == devol[0, 2:].tobytes()
        assert f["devol.dat/slip"][:].tobytes() == devol[1:, 2:].tobytes()
        assert f["devol.dat/slip"].shape == (devol.shape[0] - 1, devol.shape[1] - 2)
        # The catalogue: numpy's reader of events.csv, column by column.
        path = tmp_path / "events.csv"
        names = path.read_text().splitlines()[0].split(",")
        events = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
        assert sorted(f["events"].keys()) == sorted(names)
        for j, name in enumerate(names):
            assert f["events"][name][:].tobytes() == events[:, j].tobytes(), name
        onsets = f["events/t_start_s"][:]
        assert len(onsets) >= 2 and np.all(np.diff(onsets) > 0)


def _header_lines(path):
    """The number of `#` lines at the top of a SEAS file."""
    with open(path) as f:
        return sum(1 for line in f if line.startswith("#"))
