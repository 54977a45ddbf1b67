"""The Xdmf index of `--hdf5` (crates/rsf-hdf5's binaries) and of `rsf.slider_3d(hdf5=…)`
read back by maintained Xdmf readers, against h5py's reading of the HDF5 file: meshio's
`TimeSeriesReader` reads the mesh (points and cells; meshio 5.3 does not read the
HyperSlab items through which each frame names its slab of a field), VTK's `vtkXdmfReader`
(the `vtk` wheel; ParaView's reader of the same files is vtkXdmf3Reader) every frame's
time, mesh and point fields. The binaries are found beside the repository
(crates/rsf-hdf5/target/release, which CI builds before pytest); outside CI a missing one
skips with the reason, under CI (the variable CI set) it fails."""

import os
import pathlib
import subprocess

import numpy as np
import pytest

from conftest import REPO

h5py = pytest.importorskip("h5py")
meshio = pytest.importorskip("meshio")

RELEASE = REPO / "crates" / "rsf-hdf5" / "target" / "release"

# The body's fields (rsf::observe::POINT_FIELDS) and the fault's (rsf_hdf5::FAULT_FIELDS).
VOLUME = ["displacement", "velocity", "slip_rate", "state_alpha", "slip",
          "shear_traction", "normal_traction", "fault"]
FAULT = ["slip", "slip_rate", "state_alpha", "shear_traction", "normal_traction", "fault"]


def binary(name):
    """crates/rsf-hdf5's release binary `name`; skipped (failed under CI) if missing."""
    path = RELEASE / name
    if not (path.exists() and os.access(path, os.X_OK)):
        why = (f"no {path}: build it with `cargo build --release --manifest-path "
               f"crates/rsf-hdf5/Cargo.toml` (needs libhdf5-dev)")
        if os.environ.get("CI"):
            pytest.fail(why)
        pytest.skip(why)
    return path


def run(name, *args):
    """Runs crates/rsf-hdf5's `name` with `args`; asserts success."""
    done = subprocess.run([str(binary(name)), *map(str, args)], capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr


def vtk_frames(xmf):
    """Every frame of `xmf` as VTK's Xdmf reader reads it: (time, points, cells, point
    data by name)."""
    pytest.importorskip("vtk")
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline
    from vtkmodules.vtkIOXdmf2 import vtkXdmfReader

    reader = vtkXdmfReader()
    reader.SetFileName(str(xmf))
    reader.UpdateInformation()
    info = reader.GetOutputInformation(0)
    times = info.Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS()) or []
    frames = []
    for t in times:
        reader.UpdateTimeStep(t)
        grid = reader.GetOutputDataObject(0)
        data = grid.GetPointData()
        fields = {data.GetArrayName(i): vtk_to_numpy(data.GetArray(i))
                  for i in range(data.GetNumberOfArrays())}
        points = vtk_to_numpy(grid.GetPoints().GetData())
        frames.append((t, points, grid.GetNumberOfCells(), fields))
    return frames


def check_index(h5, names, cell_type, corners):
    """The index beside `h5`, read by meshio (the mesh) and VTK (every frame), equals the
    file read by h5py: the points, the cells (of meshio's `cell_type`), the time axis and
    each field `names` at every frame, bit for bit (NaN off the fault included)."""
    xmf = h5.with_suffix(".xmf")
    with h5py.File(h5, "r") as f:
        points, cells = f["mesh/points"][:], f["mesh/cells"][:]
        times = f["time"][:]
        assert cells.shape[1] == corners
        with meshio.xdmf.TimeSeriesReader(str(xmf)) as reader:
            assert reader.num_steps == len(times) > 0
            p, blocks = reader.read_points_cells()
            np.testing.assert_array_equal(p, points)
            assert [b.type for b in blocks] == [cell_type]
            np.testing.assert_array_equal(blocks[0].data, cells)
        frames = vtk_frames(xmf)
        assert [t for t, *_ in frames] == list(times)
        for i, (_, p, n_cells, fields) in enumerate(frames):
            np.testing.assert_array_equal(p, points)
            assert n_cells == len(cells)
            assert sorted(fields) == sorted(names)
            for name in names:
                want = f["fields/" + name][i]
                assert fields[name].shape == want.shape, name
                assert fields[name].tobytes() == want.tobytes(), (name, i)
        # Something happened on the fault.
        assert np.nanmax(f["fields/slip_rate"][:]) > 0


# Each binary on a tiny run: its flags, the fields it writes, meshio's cell type and the
# vertices per cell.
RUNS = {
    "slider_3d": (["--level", "0", "--steps", "20", "--hdf5", "5"], VOLUME, "tetra", 4),
    "pipping_slider": (["--level", "1", "--steps", "40", "--hdf5", "10"], VOLUME,
                       "triangle", 3),
    # The fault's segments.
    "seas_bp1": (["--dz", "400", "--end-years", "2", "--hdf5", "5"], FAULT, "line", 2),
    "seas_bp3": (["--dx", "4000", "--end-years", "1", "--hdf5", "10"], FAULT, "line", 2),
    # Antiplane with pore pressure on the BEM kernel: the fault's segments.
    "seas_bp6": (["--variant", "a", "--dz", "400", "--end-years", "0.2", "--hdf5", "2"],
                 FAULT, "line", 2),
    # A fault alone on Okada's kernel: a poly-vertex per element's centre.
    "seas_bp5": (["--dx", "4000", "--end-years", "1", "--hdf5", "50"], FAULT, "vertex", 1),
    # The square fault alone in a whole space (BP7, BP8): a poly-vertex per cell's centre.
    "seas_bp7": (["--dx", "80", "--end-years", "3e-8", "--hdf5", "2"], FAULT, "vertex", 1),
    "seas_bp8": (["--dx", "80", "--end-days", "2", "--hdf5", "2"], FAULT, "vertex", 1),
}


@pytest.mark.parametrize("name", sorted(RUNS))
def test_binary(tmp_path, name):
    flags, fields, cell_type, corners = RUNS[name]
    run(name, *flags, "--threads", "1", "--out", tmp_path)
    check_index(tmp_path / "fields.h5", fields, cell_type, corners)


def test_python_slider_3d_hdf5(tmp_path):
    rsf = pytest.importorskip("rsf")
    if not rsf.HAS_HDF5:
        pytest.skip("the rsf package was built without the feature hdf5")
    path = tmp_path / "fields.h5"
    sim = rsf.slider_3d(hdf5=path, hdf5_every=2, level=0, steps=100,
                        loading_velocity_m_per_s=2e-2)
    sim.advance(steps=6)
    del sim
    check_index(path, VOLUME, "tetra", 4)
