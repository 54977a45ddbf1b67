"""Type stubs of the native module ``rsf._rsf`` (docs/python.md).

Checked against the built module by ``python -m mypy.stubtest rsf._rsf`` and used by
mypy on the documentation's examples (``crates/rsf-python/tests/test_stubs.py``).
Units are SI throughout; array shapes are given in each docstring.
"""

from collections.abc import Callable, Mapping, Sequence
from os import PathLike
from typing import Any, Literal, Union, final

import numpy as np
import numpy.typing as npt

_Path = Union[str, "PathLike[str]"]
_Array = npt.NDArray[np.float64]
_ArrayLike = npt.ArrayLike
# A per-node parameter: one number, one value per fault node, or a function of the fault
# nodes' coordinates (shape `(n, dim)`, m) called once; or per fault, a dict from every
# fault's name (`Model.fault_names`) to such a value for that fault's nodes.
_PerValue = Union[float, _ArrayLike, Callable[[_Array], _ArrayLike]]
_PerNode = Union[_PerValue, Mapping[str, _PerValue]]
# A part of the boundary: a Gmsh physical group's name, or `(name, predicate)`, the
# predicate a function of a facet's midpoint (shape `(dim,)`, m) returning a bool.
_Part = Union[str, tuple[str, Callable[[_Array], bool]]]
# A state law's name ("discontinuous" only with `Friction.tresca`); `simulate` also takes
# a dict from every fault's name to one.
_StateLaw = Literal["aging", "slip", "discontinuous"]

__all__ = [
    "RsfError",
    "InvalidParameterError",
    "ModelError",
    "ConvergenceError",
    "CheckpointError",
    "RsfIOError",
    "Simulation",
    "Mesh",
    "Model",
    "Friction",
    "slider",
    "slider_3d",
    "seas_bp1",
    "seas_bp3",
    "seas_bp5",
    "seas_bp6",
    "seas_bp6_pore_pressure",
    "seas_bp7",
    "seas_bp8",
    "simulate",
    "rectangle_deformation",
    "triangle_deformation",
    "_read_greens_hdf5",
    "HAS_HDF5",
]

HAS_HDF5: bool

class RsfError(Exception):
    """Every error of the library (its message is the library's)."""

class InvalidParameterError(RsfError):
    """An invalid parameter, named in the message."""

class ModelError(RsfError):
    """A model that cannot be built or run (mesh, boundary conditions, …)."""

class ConvergenceError(RsfError):
    """A solver that did not converge (iterations and residual in the message)."""

class CheckpointError(RsfError):
    """A checkpoint that cannot be read, is corrupt or belongs to another run."""

class RsfIOError(RsfError):
    """A file that cannot be read or written, named in the message."""

@final
class Mesh:
    """A simplicial mesh (m): triangles in 2-D, tetrahedra in 3-D."""

    def __new__(cls, points: _ArrayLike, cells: _ArrayLike) -> Mesh: ...
    @staticmethod
    def rectangle(
        origin: Sequence[float],
        size: Sequence[float],
        nx: int,
        ny: int,
        diagonal: Literal["forward", "backward"] = "forward",
    ) -> Mesh: ...
    @staticmethod
    def cuboid(origin: Sequence[float], size: Sequence[float], n: Sequence[int]) -> Mesh: ...
    @staticmethod
    def read_gmsh(path: _Path, dim: int = 2) -> Mesh: ...
    @property
    def dim(self) -> int:
        """The space dimension, 2 or 3."""
    @property
    def points(self) -> _Array:
        """Vertex coordinates (m), shape `(n, dim)`."""

@final
class Model:
    """A model of a mesh: material (Young's modulus in Pa, Poisson's ratio, density in
    kg/m³), gravity (m/s²), boundary conditions and the frictional part."""

    def __new__(
        cls,
        mesh: Mesh,
        *,
        youngs_modulus: float,
        poisson_ratio: float,
        density: float,
        refine: int = 0,
        gravity: Sequence[float] | None = None,
        dirichlet: Sequence[tuple[_Part, Sequence[float]]] = ...,
        frictional_boundary: _Part | None = None,
        ramp: float | None = None,
        faults: Sequence[tuple[str, _ArrayLike | str]] | None = None,
    ) -> Model: ...
    @property
    def fault_coordinates(self) -> _Array:
        """Coordinates of the frictional nodes (m), shape `(n_fault, dim)`."""
    @property
    def fault_names(self) -> list[str]:
        """The faults' names: `faults`' in order, then the frictional boundary's part."""
    @property
    def fault_index(self) -> npt.NDArray[np.int64]:
        """The fault of every frictional node (an index into `fault_names`), `(n_fault,)`."""
    def fault_nodes(self, name: str) -> npt.NDArray[np.int64]:
        """The frictional nodes of fault `name` (positions in `fault_coordinates`), along it."""
    @property
    def num_nodes(self) -> int:
        """Mesh vertices (after refinement and splitting)."""

@final
class Friction:
    """A friction law of the frictional nodes (parameters may be per node)."""

    @staticmethod
    def dieterich_ruina(
        mu0: _PerNode, a: _PerNode, b: _PerNode, v0: _PerNode, l: _PerNode, sigma_n: _PerNode
    ) -> Friction: ...
    @staticmethod
    def regularised(
        mu0: _PerNode, a: _PerNode, b: _PerNode, v0: _PerNode, l: _PerNode, sigma_n: _PerNode
    ) -> Friction: ...
    @staticmethod
    def tresca(mu: _PerNode, sigma_n: _PerNode) -> Friction: ...

@final
class Simulation:
    """A run: stepped with the GIL released, stopped by Ctrl-C at a step boundary,
    checkpointed and resumed, its records as numpy arrays."""

    @property
    def step(self) -> int:
        """Steps taken so far (across resumes)."""
    @property
    def time(self) -> float:
        """Time of the state (s)."""
    @property
    def tau(self) -> float:
        """The next step's length τ (s)."""
    @property
    def fault_coordinates(self) -> _Array:
        """Coordinates of the fault nodes (m), shape `(n_fault, dim)`."""
    def advance(
        self,
        until: float | None = None,
        *,
        steps: int | None = None,
        progress: bool = False,
        checkpoint: _Path | None = None,
        checkpoint_every: int = 0,
    ) -> dict[str, Any]: ...
    def run(
        self,
        *,
        progress: bool = False,
        checkpoint: _Path | None = None,
        checkpoint_every: int = 0,
    ) -> dict[str, Any]: ...
    def checkpoint(self, path: _Path) -> None: ...
    def resume(self, path: _Path) -> None: ...
    def greens_functions(self) -> Any: ...
    def _greens_apply(self, x: _ArrayLike) -> _Array: ...
    def _greens_dense(self, max_unknowns: int) -> _Array: ...
    def _greens_block(self, receiver: str, source: str, max_unknowns: int) -> _Array: ...
    def _greens_to_hdf5(self, path: _Path, max_unknowns: int) -> None: ...
    def series(self) -> dict[str, npt.NDArray[Any]]: ...
    def fault(self) -> dict[str, Any]: ...
    def events(self) -> dict[str, npt.NDArray[Any]]: ...
    def catalogue(self) -> dict[str, Any]: ...
    def fields(self) -> dict[str, npt.NDArray[Any]]: ...
    def to_pandas(self) -> Any: ...
    def to_xarray(self) -> Any: ...

def slider(*, fault_every: int = 0, **kwargs: Any) -> Simulation: ...
def _read_greens_hdf5(path: _Path) -> tuple[dict[str, Any], _Array]: ...
def slider_3d(
    *,
    fault_every: int = 0,
    hdf5: _Path | None = None,
    hdf5_every: int = 1,
    resume: _Path | None = None,
    allow_change: Sequence[str] = ...,
    **kwargs: Any,
) -> Simulation: ...
def seas_bp1(
    *,
    dz: float = ...,
    domain_km: float = ...,
    ratio: float = ...,
    rk_tolerance: float = ...,
    kernel: Literal["hierarchical", "dense"] = "hierarchical",
    kernel_epsilon: float | None = None,
    integrator: Literal[
        "auto", "rkc", "rosenbrock", "dormand-prince", "bogacki-shampine"
    ] = ...,
    threads: int | None = None,
    end_years: float = ...,
    every_step: bool = False,
    out: _Path | None = None,
    overwrite: bool = False,
    resume: _Path | None = None,
    allow_change: Sequence[str] = ...,
    hdf5: bool = False,
    modeler: str = "rsf",
    date: str | None = None,
    fault_every: int = 0,
    **kwargs: Any,
) -> Simulation: ...
def seas_bp3(
    *,
    dip: float = ...,
    dx: float = ...,
    domain_km: float = ...,
    ratio: float = ...,
    tolerance: float = ...,
    kernel: Literal["hierarchical", "dense"] = "hierarchical",
    kernel_epsilon: float | None = None,
    integrator: Literal[
        "auto", "rkc", "rosenbrock", "dormand-prince", "bogacki-shampine"
    ] = "auto",
    threads: int | None = None,
    end_years: float = ...,
    out: _Path | None = None,
    overwrite: bool = False,
    resume: _Path | None = None,
    allow_change: Sequence[str] = ...,
    modeler: str = "rsf",
    date: str | None = None,
    fault_every: int = 0,
    **kwargs: Any,
) -> Simulation: ...
def seas_bp5(
    *,
    kernel: Literal["okada", "fe"] = "okada",
    dx: float = ...,
    domain_km: float | None = None,
    ratio: float | None = None,
    mesh: Literal["graded", "tensor"] | None = None,
    condensation: Literal["schur-only", "factor"] | None = None,
    ordering: Literal["amd", "nested-dissection"] | None = None,
    fault_zone_width_km: float | None = None,
    fault_zone_rigidity: float | None = None,
    end_years: float = ...,
    tolerance: float = ...,
    epsilon: float = ...,
    integrator: Literal[
        "auto", "rkc", "rosenbrock", "dormand-prince", "bogacki-shampine"
    ] = ...,
    threads: int | None = None,
    out: _Path | None = None,
    overwrite: bool = False,
    resume: _Path | None = None,
    allow_change: Sequence[str] = ...,
    modeler: str = "rsf",
    date: str | None = None,
    fault_every: int = 0,
    **kwargs: Any,
) -> Simulation: ...
def seas_bp6(
    *,
    variant: Literal["a", "s", "c"] = "a",
    dz: float = ...,
    elastic: Literal["bem", "fe"] = "bem",
    bem_product: Literal["fft", "stored"] | None = None,
    domain_km: float = ...,
    ratio: float = ...,
    tolerance: float | None = None,
    pressure: Literal["closed-form", "diffusion"] = "closed-form",
    diffusion_cells: int | None = None,
    kernel: Literal["hierarchical", "dense"] = "hierarchical",
    kernel_epsilon: float | None = None,
    integrator: Literal[
        "auto", "rkc", "rosenbrock", "dormand-prince", "bogacki-shampine"
    ] = "auto",
    threads: int = 1,
    end_years: float = ...,
    station_interval: float = ...,
    profile_interval: float = ...,
    out: _Path | None = None,
    overwrite: bool = False,
    resume: _Path | None = None,
    allow_change: Sequence[str] = ...,
    modeler: str = "rsf",
    date: str | None = None,
    fault_every: int = 0,
    **kwargs: Any,
) -> Simulation: ...
def seas_bp7(
    *,
    out: _Path | None = None,
    overwrite: bool = False,
    resume: _Path | None = None,
    allow_change: Sequence[str] = ...,
    threads: int = 1,
    modeler: str = "rsf",
    date: str | None = None,
    fault_every: int = 0,
    kernel: Literal["bem", "fe"] = ...,
    domain_km: float | None = ...,
    ratio: float | None = ...,
    law: Literal["aging", "slip"] = ...,
    end_years: float = ...,
    dx: float = ...,
    d_rs: float = ...,
    tolerance: float = ...,
    station_interval: float = ...,
    integrator: Literal[
        "auto", "rkc", "rosenbrock", "dormand-prince", "bogacki-shampine"
    ] = ...,
) -> Simulation: ...
def seas_bp8(
    *,
    out: _Path | None = None,
    overwrite: bool = False,
    resume: _Path | None = None,
    allow_change: Sequence[str] = ...,
    threads: int = 1,
    modeler: str = "rsf",
    date: str | None = None,
    fault_every: int = 0,
    kernel: Literal["bem", "fe"] = ...,
    domain_km: float | None = ...,
    ratio: float | None = ...,
    source: Literal["gs", "pw"] = ...,
    end_days: float = ...,
    dx: float = ...,
    tolerance: float = ...,
    overpressure: Literal["floor", "refuse"] = ...,
    sigma_min: float | None = ...,
    station_interval: float = ...,
    profile_interval: float = ...,
    integrator: Literal[
        "auto", "rkc", "rosenbrock", "dormand-prince", "bogacki-shampine"
    ] = ...,
) -> Simulation: ...
def seas_bp6_pore_pressure(
    z: _ArrayLike,
    t: _ArrayLike,
    *,
    pressure: Literal["closed-form", "diffusion"] = "closed-form",
    diffusion_cells: int | None = None,
    **kwargs: Any,
) -> dict[str, _Array]: ...
def simulate(
    model: Model,
    *,
    friction: Friction,
    alpha0: _PerNode,
    tau: float,
    state_law: _StateLaw | Mapping[str, _StateLaw] = ...,
    integrator: Literal["newmark", "backward-euler", "quasistatic"] | None = None,
    solver: Literal["auto", "tnnmg", "direct", "gauss-seidel"] | None = None,
    end_time: float | None = None,
    fault_every: int = 0,
    method: Literal["implicit", "fault-ode"] = "implicit",
    radiation_damping: _PerNode | None = None,
) -> Simulation: ...
def rectangle_deformation(
    points: _ArrayLike,
    centre: Sequence[float],
    strike: float,
    dip: float,
    length: float,
    width: float,
    slip: Sequence[float],
    mu: float,
    nu: float,
    space: Literal["half", "whole"] = "half",
) -> tuple[_Array, _Array]: ...
def triangle_deformation(
    points: _ArrayLike,
    vertices: _ArrayLike,
    slip: Sequence[float],
    mu: float,
    nu: float,
    space: Literal["half", "whole"] = "half",
) -> tuple[_Array, _Array]: ...
