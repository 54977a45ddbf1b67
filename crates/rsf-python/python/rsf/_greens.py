"""The Green's functions of a run's faults: the fault operator S applied matrix-free
(a ``scipy.sparse.linalg.LinearOperator``), its dense matrix behind a size limit, and
``.npz`` files (docs/fault-networks.md, "Green's functions")."""

import numpy as np

#: The ``format`` entry of the files :meth:`GreensFunctions.to_npz` writes.
GREENS_FORMAT = "rsf-greens-1"

#: The per-unknown arrays and the scalars a description holds (the HDF5 file's names).
_ARRAYS = ("fault", "node", "component", "positions", "directions", "weights")
_SCALARS = (
    "dimension",
    "origin",
    "kernel",
    "epsilon",
    "leaf_size",
    "relative_error",
    "error_samples",
    "max_rank",
    "low_rank_blocks",
    "tolerance",
    "unit_S",
    "rsf_version",
)


class GreensFunctions:
    """The fault operator S of a run (``Simulation.greens_functions()``) or of a file
    (:meth:`from_npz`, :meth:`from_hdf5`).

    ``S`` maps slip (m) on the ``dim`` slip unknowns to forces (N in 3-D, N/m per unit
    thickness in 2-D; ``unit_S``): unit slip on unknown ``j`` changes the traction on
    unknown ``i`` by ``-S[i, j] / weights[i]`` (Pa). Per unknown: ``fault`` (an index
    into ``fault_names``), ``node``, ``component``, ``positions`` (m, shape
    ``(dim, 3)``), ``directions`` (unit slip vectors, ``(dim, 3)``), ``weights`` (m² in
    3-D, m in 2-D). ``origin`` (``finite_element``, ``okada_grid``,
    ``boundary_elements``, ``whole_space``, ``other``), ``kernel`` (``dense`` or
    ``hierarchical`` with ``epsilon``), ``relative_error`` (the measured
    ``‖S − S_H‖_F/‖S‖_F``) and ``tolerance`` (the relative accuracy to which S is known:
    round-off for the dense kernel) say how it was made. S is symmetric positive
    semi-definite to ``tolerance``.
    """

    def __init__(self, description, *, simulation=None, matrix=None):
        self._sim = simulation
        self._matrix = None if matrix is None else np.asarray(matrix, dtype=np.float64)
        self.fault_names = [str(n) for n in description["fault_names"]]
        for k in _ARRAYS:
            setattr(self, k, np.asarray(description[k]))
        for k in _SCALARS:
            v = description[k]
            setattr(self, k, v.item() if isinstance(v, np.ndarray) else v)
        m = len(self.weights)
        if self._matrix is not None and self._matrix.shape != (m, m):
            raise ValueError(f"S of shape {self._matrix.shape} for {m} unknowns")

    @classmethod
    def _of_simulation(cls, simulation, description):
        return cls(description, simulation=simulation)

    @property
    def dim(self):
        """Number of slip unknowns (rows and columns of S)."""
        return len(self.weights)

    def __repr__(self):
        return (
            f"GreensFunctions(dim={self.dim}, faults={self.fault_names}, "
            f"origin={self.origin!r}, kernel={self.kernel!r}, "
            f"relative_error={self.relative_error:.3e})"
        )

    def unknowns_of(self, name):
        """The unknowns (indices) of the fault ``name``, in order (empty for another name)."""
        if name not in self.fault_names:
            return np.zeros(0, dtype=np.int64)
        return np.flatnonzero(self.fault == self.fault_names.index(name))

    def apply(self, x):
        """``S x`` for the slip ``x`` (m, shape ``(dim,)`` or ``(dim, 1)``): one product with
        the run's operator (matrix-free), or with the file's matrix."""
        x = np.ascontiguousarray(np.ravel(x), dtype=np.float64)
        if x.shape != (self.dim,):
            raise ValueError(f"x of {x.size} entries for {self.dim} unknowns")
        if self._sim is not None:
            return np.asarray(self._sim._greens_apply(x))
        return self._matrix @ x

    def as_linear_operator(self):
        """S as a ``scipy.sparse.linalg.LinearOperator`` of shape ``(dim, dim)``: each
        ``matvec`` is :meth:`apply` (no dense matrix is built); symmetric, so ``rmatvec``
        is the same product."""
        from scipy.sparse.linalg import LinearOperator

        return LinearOperator(
            (self.dim, self.dim), matvec=self.apply, rmatvec=self.apply, dtype=np.float64
        )

    def matrix(self, max_unknowns=4096):
        """The dense S, shape ``(dim, dim)``, built column by column ``S e_j``: ``dim``
        products with the operator and ``8 dim²`` bytes; refused (``InvalidParameterError``)
        for ``dim > max_unknowns`` before any product. A file's matrix as read."""
        if self._matrix is not None:
            return self._matrix
        return np.asarray(self._sim._greens_dense(int(max_unknowns)))

    def block(self, receiver, source, max_unknowns=4096):
        """The block of S from the slip of fault ``source`` to the forces on fault
        ``receiver``, shape ``(len(unknowns_of(receiver)), len(unknowns_of(source)))``:
        one product per source unknown (matrix-free; a file's matrix sliced), the
        entries of :meth:`matrix` bit for bit (the library's ``GreensFunctions::block``).
        Refused (``ValueError``) for a name the faults do not have; like :meth:`matrix`
        (``InvalidParameterError``) for more source unknowns than ``max_unknowns``."""
        rows, cols = self.unknowns_of(receiver), self.unknowns_of(source)
        for which, name, u in (("receiver", receiver, rows), ("source", source, cols)):
            if u.size == 0:
                raise ValueError(f"{which}: {name!r} is none of the faults {self.fault_names}")
        if self._matrix is not None:
            return self._matrix[np.ix_(rows, cols)]
        return np.asarray(self._sim._greens_block(receiver, source, int(max_unknowns)))

    def to_npz(self, path, max_unknowns=4096):
        """Writes the description and the dense S (:meth:`matrix`) into the ``.npz`` file
        ``path``: the arrays and scalars by their names (as the HDF5 file of
        ``rsf_hdf5::write_greens``), ``S``, ``fault_names`` and ``format``."""
        arrays = {k: getattr(self, k) for k in _ARRAYS}
        scalars = {k: np.asarray(getattr(self, k)) for k in _SCALARS}
        np.savez(
            path,
            S=self.matrix(max_unknowns),
            fault_names=np.asarray(self.fault_names, dtype=str),
            format=np.asarray(GREENS_FORMAT),
            **arrays,
            **scalars,
        )

    def to_hdf5(self, path, max_unknowns=4096):
        """Writes the description and the dense S (refused above ``max_unknowns``) into the
        HDF5 file ``path`` by the library's writer (``rsf_hdf5::write_greens``: ``S``, the
        per-unknown datasets with their ``unit``, the accuracy and origin as attributes;
        a package built with the feature ``hdf5``). Only Green's functions of a run: a
        file's are copied by :meth:`to_npz`."""
        if self._sim is None:
            raise ValueError(
                "to_hdf5 writes the Green's functions of a run (Simulation.greens_functions()); "
                "these were read from a file: use to_npz"
            )
        self._sim._greens_to_hdf5(path, int(max_unknowns))

    @classmethod
    def from_hdf5(cls, path):
        """The Green's functions an HDF5 file of :meth:`to_hdf5` (or of the Rust
        ``rsf_hdf5::write_greens``) holds, read by the library's reader (applied with its
        matrix)."""
        from ._rsf import _read_greens_hdf5

        description, matrix = _read_greens_hdf5(path)
        return cls(description, matrix=matrix)

    @classmethod
    def from_npz(cls, path):
        """The Green's functions a :meth:`to_npz` file holds (applied with its matrix)."""
        with np.load(path, allow_pickle=False) as f:
            if str(f["format"]) != GREENS_FORMAT:
                raise ValueError(f"{path}: format {f['format']}, not {GREENS_FORMAT}")
            description = {k: f[k] for k in _ARRAYS + _SCALARS}
            description["fault_names"] = list(f["fault_names"])
            return cls(description, matrix=f["S"])
