"""The Green's functions of a run's fault operator from Python (``Simulation.greens_functions``,
docs/fault-networks.md): the LinearOperator's matvec is the dense matrix's product;
reciprocity (xᵀ S y = yᵀ S x) to the kernel's accuracy, and the ℋ-matrix's S against the
dense one by the error its set-up measured; the .npz file reads back exactly; the dense
matrix is refused above its limit, and a run without an operator says so."""

import numpy as np
import pytest
from scipy.sparse.linalg import LinearOperator, cg

import rsf

#: BP1 on a coarse grid (the run is never stepped: only its operator is read).
BP1 = dict(domain_km=100.0, threads=1, end_years=10.0)


def bp1(dz, kernel="dense", **kw):
    return rsf.seas_bp1(dz=dz, kernel=kernel, **BP1, **kw).greens_functions()


def test_the_linear_operator_is_the_dense_matrix():
    g = bp1(1000.0)
    assert (g.origin, g.kernel, g.dimension, g.unit_S) == (
        "finite_element",
        "dense",
        2,
        "N/m^2",
    )
    m = g.dim
    assert m > 10 and g.positions.shape == (m, 3) and g.weights.shape == (m,)
    # An antiplane fault: every unknown slips out of the plane.
    np.testing.assert_array_equal(g.directions, np.tile([0.0, 0.0, 1.0], (m, 1)))
    assert list(g.unknowns_of(g.fault_names[0])) == list(range(m))
    op = g.as_linear_operator()
    assert isinstance(op, LinearOperator) and op.shape == (m, m)
    S = g.matrix()
    # A fault's block from its source columns alone: the matrix's entries, bit for bit.
    name = g.fault_names[0]
    np.testing.assert_array_equal(g.block(name, name), S)
    with pytest.raises(ValueError, match="north"):
        g.block(name, "north")
    with pytest.raises(rsf.InvalidParameterError, match="exceed the limit"):
        g.block(name, name, max_unknowns=m - 1)
    scale = np.abs(S).sum(axis=1).max()
    rng = np.random.default_rng(83)
    X = rng.standard_normal((m, 3))
    for x in X.T:
        np.testing.assert_allclose(op @ x, S @ x, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(op.matmat(X), S @ X, rtol=0, atol=1e-12 * scale)
    # Reciprocity to round-off (the dense kernel), positive definite.
    x, y = X[:, 0], X[:, 1]
    bound = 1e-12 * scale * np.linalg.norm(x) * np.linalg.norm(y)
    assert abs(x @ (op @ y) - y @ (op @ x)) <= bound
    eig = np.linalg.eigvalsh(0.5 * (S + S.T))
    assert eig.min() > 0
    # Matrix-free in an inversion's solve: CG on S + I·max(diag) through the operator
    # agrees with the dense solve.
    shift = S.diagonal().max()
    shifted = LinearOperator((m, m), matvec=lambda v: op @ v + shift * v, dtype=float)
    b = S @ X[:, 2]
    z, info = cg(shifted, b, rtol=1e-12, maxiter=10 * m)
    assert info == 0
    np.testing.assert_allclose(z, np.linalg.solve(S + shift * np.eye(m), b), rtol=1e-8)


def test_the_hierarchical_kernel_is_reciprocal_to_its_accuracy():
    dense = bp1(250.0)
    h = bp1(250.0, kernel="hierarchical", kernel_epsilon=1e-6)
    assert h.kernel == "hierarchical" and h.epsilon == 1e-6 and h.low_rank_blocks > 0
    S, Sd = h.matrix(), dense.matrix()
    error = np.linalg.norm(S - Sd) / np.linalg.norm(Sd)
    # The error of S_H against S is the one its set-up measured (over every entry).
    assert 0 < error <= h.tolerance
    assert error == pytest.approx(h.relative_error, rel=1e-6)
    rng = np.random.default_rng(7)
    x, y = rng.standard_normal((2, h.dim))
    op = h.as_linear_operator()
    bound = h.tolerance * np.linalg.norm(S) * np.linalg.norm(x) * np.linalg.norm(y)
    assert abs(x @ (op @ y) - y @ (op @ x)) <= bound


def test_npz_round_trip(tmp_path):
    g = bp1(1000.0)
    path = tmp_path / "greens.npz"
    g.to_npz(path)
    back = rsf.GreensFunctions.from_npz(path)
    np.testing.assert_array_equal(back.matrix(), g.matrix())
    for k in ("fault", "node", "component", "positions", "directions", "weights"):
        np.testing.assert_array_equal(getattr(back, k), getattr(g, k))
    assert back.fault_names == g.fault_names
    for k in ("origin", "kernel", "relative_error", "tolerance", "unit_S", "dimension"):
        assert getattr(back, k) == getattr(g, k), k
    x = np.linspace(-1.0, 1.0, g.dim)
    scale = np.abs(g.matrix()).sum(axis=1).max()
    got = back.as_linear_operator() @ x
    np.testing.assert_allclose(got, g.apply(x), rtol=0, atol=1e-12 * scale)


def test_the_dense_matrix_is_refused_above_its_limit_and_needs_an_operator():
    g = bp1(1000.0)
    with pytest.raises(rsf.InvalidParameterError, match="exceed the limit"):
        g.matrix(max_unknowns=g.dim - 1)
    with pytest.raises(ValueError):
        g.apply(np.zeros(g.dim + 1))
    with pytest.raises(rsf.InvalidParameterError, match="greens_functions"):
        rsf.slider().greens_functions()
