"""Array-likes where the package takes arrays (issue 86, "Python at par"): nested lists,
`float32` points and integer or whole-float cells of any width give the same mesh and the
same kernels' values as `float64`/`int64` arrays, bit for bit; what is not an array of
numbers of the stated shape is refused naming the keyword."""

import numpy as np
import pytest

import rsf

POINTS = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]
CELLS = [[0, 1, 2], [1, 3, 2]]


def plate(mesh):
    """A unit square on `mesh` pressed by gravity, dragged at its top, frictional at its
    base."""
    return rsf.Model(
        mesh,
        youngs_modulus=1e9,
        poisson_ratio=0.25,
        density=2.5e3,
        gravity=(0.0, -9.81),
        dirichlet=[(("top", lambda x: x[1] > 1.0 - 1e-9), (1e-4, 0.0))],
        frictional_boundary=("bottom", lambda x: x[1] < 1e-9),
    )


def model_bits(mesh):
    """The model built on `mesh`: its size and its fault's coordinates."""
    model = plate(mesh)
    return model.num_nodes, model.fault_coordinates.tobytes()


def test_lists_and_other_dtypes_give_the_same_mesh():
    reference = rsf.Mesh(np.array(POINTS), np.array(CELLS, dtype=np.int64))
    for points, cells in [
        (POINTS, CELLS),
        (tuple(map(tuple, POINTS)), tuple(map(tuple, CELLS))),
        (np.array(POINTS, dtype=np.float32), np.array(CELLS, dtype=np.int32)),
        (np.array(POINTS, dtype=np.int64), np.array(CELLS, dtype=np.uint16)),
        (np.array(POINTS), np.array(CELLS, dtype=np.float64)),
    ]:
        mesh = rsf.Mesh(points, cells)
        assert mesh.dim == 2
        assert mesh.points.tobytes() == reference.points.tobytes()
        assert model_bits(mesh) == model_bits(reference)


@pytest.mark.parametrize(
    "points, cells, name",
    [
        (POINTS, [[0, 1, 2.5], [1, 3, 2]], "cells"),
        (POINTS, [[0, 1, -2], [1, 3, 2]], "cells"),
        (POINTS, [[0, 1, np.nan], [1, 3, 2]], "cells"),
        (POINTS, [[True, False, True]], "cells"),
        (POINTS, [[0, 1], [1, 3]], "cells"),
        (POINTS, [["a", "b", "c"]], "cells"),
        (np.array(POINTS) + 1j, CELLS, "points"),
        ([["x", "y"]], CELLS, "points"),
        ([[0.0, 0.0, 0.0, 0.0]], [[0, 0, 0, 0, 0]], "points"),
        ([0.0, 1.0], CELLS, "points"),
    ],
)
def test_what_is_not_an_array_of_numbers_is_refused_by_its_keyword(points, cells, name):
    with pytest.raises(rsf.InvalidParameterError, match=f"`{name}`"):
        rsf.Mesh(points, cells)


def test_the_kernels_take_array_likes():
    at = [[100.0, 200.0, -300.0], [-50.0, 20.0, -10.0]]
    vertices = [[0.0, 0.0, -1000.0], [1000.0, 0.0, -1000.0], [0.0, 1000.0, -1500.0]]
    args = dict(slip=[1.0, 0.0, 0.0], mu=3e10, nu=0.25)
    u, s = rsf.triangle_deformation(at, vertices, **args)
    u_ref, s_ref = rsf.triangle_deformation(
        np.array(at), np.array(vertices, dtype=np.float32).astype(np.float64), **args
    )
    assert u.tobytes() == u_ref.tobytes() and s.tobytes() == s_ref.tobytes()
    with pytest.raises(rsf.InvalidParameterError, match="`vertices`"):
        rsf.triangle_deformation(at, vertices[:2] + [[0.0, 1.0]], **args)


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: rsf.slider(fault_every=-1), "fault_every"),
        (lambda: rsf.slider_3d(hdf5_every=-1, level=0), "hdf5_every"),
        (lambda: rsf.seas_bp1(threads=-1), "threads"),
        (lambda: rsf.seas_bp6(threads=-2), "threads"),
        (lambda: rsf.seas_bp6(diffusion_cells=-800, pressure="diffusion"), "diffusion_cells"),
        (lambda: rsf.Mesh.rectangle((0.0, 0.0), (1.0, 1.0), -1, 3), "nx"),
        (lambda: rsf.Mesh.cuboid((0.0,) * 3, (1.0,) * 3, (2, -2, 2)), "n"),
        (lambda: rsf.slider(level=0).advance(steps=-1), "steps"),
        (lambda: rsf.slider(level=0).run(checkpoint_every=-5), "checkpoint_every"),
        (lambda: rsf.slider(level=0).advance(steps=2**70), "steps"),
    ],
)
def test_negative_or_oversized_counts_are_refused_by_their_keyword(call, name):
    """Whole-number keywords (steps, threads, intervals, cell counts) refuse a negative or
    oversized int as `InvalidParameterError` naming the keyword (issue 86: a bare
    `OverflowError: can't convert negative int to unsigned`, naming nothing)."""
    with pytest.raises(rsf.InvalidParameterError, match=f"`{name}`"):
        call()


def test_a_count_that_is_not_an_int_is_a_type_error_naming_it():
    with pytest.raises(TypeError, match="fault_every"):
        rsf.slider(fault_every=1.5)


def test_the_discontinuous_law_with_a_rate_and_state_law_is_refused_by_state_law():
    """The discontinuous state law evolves θ itself, which the rate-and-state laws read as
    ln θ: refused naming `state_law` (issue 86: documented, then refused by the library
    naming a frictional node), from the sliders and from a problem of one's own; with
    Tresca friction, which does not read the state, it runs."""
    for call in (
        lambda: rsf.slider(level=0, state_law="discontinuous"),
        lambda: rsf.slider_3d(level=0, state_law="discontinuous"),
    ):
        with pytest.raises(rsf.InvalidParameterError, match="`state_law`.*ln θ"):
            call()
    model = plate(rsf.Mesh(POINTS, CELLS))
    args = dict(alpha0=-10.0, tau=1e-3, end_time=5e-3, state_law="discontinuous")
    laws = dict(mu0=0.6, a=0.01, b=0.015, v0=1e-6, l=1e-5, sigma_n=5e4)
    for friction in (rsf.Friction.dieterich_ruina(**laws), rsf.Friction.regularised(**laws)):
        with pytest.raises(rsf.InvalidParameterError, match="`state_law`"):
            rsf.simulate(model, friction=friction, **args)
    sim = rsf.simulate(model, friction=rsf.Friction.tresca(mu=0.6, sigma_n=5e4), **args)
    assert sim.run()["steps"] == 5
