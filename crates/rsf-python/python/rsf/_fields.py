"""The HDF5 fields file of a run (``rsf.slider_3d(hdf5=...)``, the crate rsf-hdf5's
``Hdf5Fields``) as an xarray Dataset with named dimensions, coordinates and CF ``units``
(h5py and xarray imported on demand). xarray's own HDF5 engines see the file's datasets
on anonymous ``phony_dim_N`` dimensions; this reader names them."""

from __future__ import annotations

from os import PathLike
from typing import Any, Union

_COMPONENTS = ["x", "y", "z"]


def read_fields(path: Union[str, "PathLike[str]"]) -> Any:
    """The fields file ``path`` as an ``xarray.Dataset``.

    Dimensions: ``time`` (the frames), ``vertex`` (the mesh's vertices), ``component``
    (``x``, ``y``, ``z`` of the vector fields), ``cell`` and ``corner`` (the mesh's
    simplices). Coordinates: ``time`` (s), ``step`` (per frame), the vertices' ``x``,
    ``y``, ``z`` (m) and ``on_fault`` (whether the vertex is a frictional node). Data: every
    field of the file (``displacement``, ``velocity``, ``slip`` in m, m/s, m; ``slip_rate``,
    ``state_alpha``, ``shear_traction``, ``normal_traction``, ``fault`` on the fault, NaN
    elsewhere) with its ``units`` (CF: ``1`` for a dimensionless value) and the mesh's
    ``cells`` (vertex indices). The file's attributes ``fingerprint`` (the run's, JSON) and
    each field's others (``fault_names`` of ``fault``) are kept as attributes.

    Raises ``ImportError`` without h5py or xarray, ``OSError``/``KeyError`` for a file
    that is not such a file.
    """
    import h5py
    import numpy as np
    import xarray as xr

    with h5py.File(path, "r") as f:
        points = f["mesh/points"][:]
        fault_nodes = f["mesh/fault_nodes"][:]
        on_fault = np.zeros(points.shape[0], dtype=bool)
        on_fault[fault_nodes] = True
        coords: dict[str, Any] = {
            "time": ("time", f["time"][:], {"units": "s", "standard_name": "time"}),
            "step": ("time", f["step"][:]),
            "vertex": np.arange(points.shape[0]),
            "component": _COMPONENTS,
            "on_fault": ("vertex", on_fault),
        }
        for i, name in enumerate(_COMPONENTS):
            coords[name] = ("vertex", points[:, i], {"units": "m"})
        data: dict[str, Any] = {
            "cells": (("cell", "corner"), f["mesh/cells"][:].astype(np.int64)),
        }
        for name, d in f["fields"].items():
            dims = ("time", "vertex", "component")[: d.ndim]
            attrs = {k: _text(v) for k, v in d.attrs.items() if k != "unit"}
            attrs["units"] = _text(d.attrs.get("unit", "1")) or "1"
            data[name] = (dims, d[:], attrs)
        attrs = {k: _text(v) for k, v in f.attrs.items()}
    return xr.Dataset(data, coords=coords, attrs=attrs)


def _text(value: Any) -> Any:
    """An attribute as text where h5py gives bytes."""
    return value.decode() if isinstance(value, bytes) else value
