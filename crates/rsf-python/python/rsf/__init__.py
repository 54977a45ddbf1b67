"""rsf from Python: rate-and-state friction, earthquake cycles (docs/python.md).

The scenes of the library with their parameters as keyword arguments
(:func:`slider`, :func:`slider_3d`, :func:`seas_bp1`, :func:`seas_bp3`, :func:`seas_bp5`,
:func:`seas_bp6`, :func:`seas_bp7`, :func:`seas_bp8`), a problem of your own
(:class:`Mesh`, :class:`Model`, :class:`Friction`, :func:`simulate`), runs
(:meth:`Simulation.advance`, :meth:`Simulation.run`; the GIL is released while
stepping, Ctrl-C stops at a step boundary) with checkpoints, and the records as
numpy arrays (:meth:`Simulation.series`, :meth:`Simulation.fault`,
:meth:`Simulation.events`, :meth:`Simulation.fields`), as pandas/xarray objects
where those packages are installed. Units are SI throughout.

The dislocation kernels at points (:func:`rectangle_deformation`, Okada's
rectangle; :func:`triangle_deformation`, Nikkhoo & Walter's triangle; each in a
half-space or the whole space) give displacement and stress as numpy arrays.

A fault network's event catalogue, ``catalogue.csv`` of the programs ``stepover``
and ``bp5_pair`` (docs/fault-networks.md), reads as numpy arrays with
:func:`read_catalogue`; an HDF5 fields file (``slider_3d(hdf5=...)``) as an xarray
Dataset with named dimensions and CF units with :func:`read_fields`.

The fault operator of a run condensed onto the fault (its Green's functions:
slip on every fault unknown to the force on every one) is
:meth:`Simulation.greens_functions`, a :class:`GreensFunctions` applied
matrix-free as a ``scipy.sparse.linalg.LinearOperator``, written to ``.npz``.

Every error of the library is an exception of a class derived from
:class:`RsfError` carrying the library's message: :class:`InvalidParameterError`
(naming the parameter), :class:`ModelError`, :class:`ConvergenceError`,
:class:`CheckpointError`, :class:`RsfIOError`.

Custom state laws stay Rust traits (``rsf::state::StateLaw``): a Python callback
per node per stage of every step would cost more than the step itself.
"""

from ._catalogue import read_catalogue  # noqa: F401
from ._fields import read_fields  # noqa: F401
from ._greens import GreensFunctions  # noqa: F401
from ._rsf import (  # noqa: F401
    HAS_HDF5,
    CheckpointError,
    ConvergenceError,
    Friction,
    InvalidParameterError,
    Mesh,
    Model,
    ModelError,
    RsfError,
    RsfIOError,
    Simulation,
    rectangle_deformation,
    seas_bp1,
    seas_bp3,
    seas_bp5,
    seas_bp6,
    seas_bp6_pore_pressure,
    seas_bp7,
    seas_bp8,
    simulate,
    slider,
    slider_3d,
    triangle_deformation,
)

__all__ = [
    "HAS_HDF5",
    "CheckpointError",
    "ConvergenceError",
    "Friction",
    "GreensFunctions",
    "InvalidParameterError",
    "Mesh",
    "Model",
    "ModelError",
    "RsfError",
    "RsfIOError",
    "Simulation",
    "read_catalogue",
    "read_fields",
    "rectangle_deformation",
    "seas_bp1",
    "seas_bp3",
    "seas_bp5",
    "seas_bp6",
    "seas_bp6_pore_pressure",
    "seas_bp7",
    "seas_bp8",
    "simulate",
    "slider",
    "slider_3d",
    "triangle_deformation",
]
