"""Fault networks from Python (issue 83): ``rsf.Model(faults=...)`` builds several named faults
inside the body through the library's builder; every frictional node knows its fault
(``fault_names``, ``fault_index``, ``fault_nodes``); parameters may be given per fault; the
Green's functions of a two-fault model are blocks per fault pair; a stepover runs with its
outputs naming the faults.

The stepover here is point-symmetric: a 4 m square sheared by its top and bottom (the same
velocity, opposite signs), the west strand the east one rotated by 180° about the origin
(the east one given from its north end so that the rotation maps the slip direction too), on
a mesh the rotation maps onto itself (a grid of forward diagonals centred at the origin).
The rotation maps the problem onto itself, so every operator block and every trajectory of
the west strand equals the east strand's at the rotated nodes — to round-off, since the two
are summed in different orders. A block read with the wrong fault's rows or columns, or a
per-fault parameter put on the wrong nodes, breaks these equalities.
"""

import numpy as np
import pytest

import rsf

#: The square and its grid: h = 0.25 m, the strands on the grid lines x = ∓0.25 m.
SQUARE = dict(origin=(-2.0, -2.0), size=(4.0, 4.0), nx=17, ny=17)
MATERIAL = dict(youngs_modulus=3e10, poisson_ratio=0.25, density=2700.0)
V = 1e-9  # m/s, the top's and (opposite) the bottom's velocity


def sheared():
    return [
        (("top", lambda x: x[1] > 2.0 - 1e-9), (V, 0.0)),
        (("bottom", lambda x: x[1] < -2.0 + 1e-9), (-V, 0.0)),
    ]


def stepover(gap=0.5, **kw):
    """West strand x = -gap/2, y in [-1.5, 0.5]; east strand its rotation by 180°."""
    west = [(-gap / 2, -1.5), (-gap / 2, 0.5)]
    east = [(gap / 2, 1.5), (gap / 2, -0.5)]
    mesh = rsf.Mesh.rectangle(**SQUARE)
    return rsf.Model(
        mesh, **MATERIAL, dirichlet=sheared(), faults=[("west", west), ("east", east)], **kw
    )


def rotated(x_from, x_to):
    """The permutation p with x_to[p[i]] = -x_from[i] (the 180° rotation), asserted exact
    to round-off of the coordinates."""
    d = np.linalg.norm(x_to[None, :, :] + x_from[:, None, :], axis=2)
    p = d.argmin(axis=1)
    assert d[np.arange(len(p)), p].max() < 1e-12
    assert sorted(p) == list(range(len(p)))
    return p


def test_two_named_faults_and_their_nodes():
    model = stepover()
    assert model.fault_names == ["west", "east"]
    x = model.fault_coordinates
    index = model.fault_index
    # 2 m strands of 8 edges: 9 vertices, the 2 tips shared, 7 split pairs each.
    assert x.shape == (14, 2) and index.shape == (14,) and index.dtype == np.int64
    assert np.bincount(index).tolist() == [7, 7]
    for f, (name, xf) in enumerate((("west", -0.25), ("east", 0.25))):
        k = model.fault_nodes(name)
        assert sorted(k) == list(np.flatnonzero(index == f))
        np.testing.assert_array_equal(x[k, 0], xf)
        # In order along the strand, strictly between its tips.
        y = x[k, 1]
        assert np.all(np.diff(y) > 0) or np.all(np.diff(y) < 0)
    lo, hi = x[model.fault_nodes("west"), 1].min(), x[model.fault_nodes("west"), 1].max()
    assert (lo, hi) == (-1.25, 0.25)
    with pytest.raises(rsf.InvalidParameterError, match="`north` is none of"):
        model.fault_nodes("north")


def test_faults_beside_a_frictional_boundary_come_first():
    mesh = rsf.Mesh.rectangle(**SQUARE)
    model = rsf.Model(
        mesh,
        **MATERIAL,
        dirichlet=[(("top", lambda x: x[1] > 2.0 - 1e-9), (V, 0.0))],
        frictional_boundary=("base", lambda x: x[1] < -2.0 + 1e-9),
        faults=[("strand", [(0.0, -1.0), (0.0, 1.0)])],
    )
    assert model.fault_names == ["strand", "base"]
    # 7 split pairs on the strand, the base's 17 nodes.
    assert np.bincount(model.fault_index).tolist() == [7, 17]
    np.testing.assert_array_equal(model.fault_coordinates[model.fault_nodes("base"), 1], -2.0)


def test_a_3d_pair_of_polygons():
    cube = rsf.Mesh.cuboid((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), (9, 9, 9))
    square = lambda x: [(x, 0.25, 0.25), (x, 0.75, 0.25), (x, 0.75, 0.75), (x, 0.25, 0.75)]
    model = rsf.Model(
        cube,
        **MATERIAL,
        dirichlet=[(("left", lambda x: x[0] < 1e-9), (0.0, -V, 0.0)),
                   (("right", lambda x: x[0] > 1.0 - 1e-9), (0.0, V, 0.0))],
        faults=[("a", square(0.25)), ("b", square(0.75))],
    )
    assert model.fault_names == ["a", "b"]
    # 5 × 5 vertices per square, its rim shared: 3 × 3 split pairs each.
    assert np.bincount(model.fault_index).tolist() == [9, 9]
    for name, x0 in (("a", 0.25), ("b", 0.75)):
        np.testing.assert_array_equal(model.fault_coordinates[model.fault_nodes(name), 0], x0)


def test_refined_strands_and_a_3d_polygon_the_mesh_does_not_resolve():
    # Refined once: 16 edges per strand, 15 split pairs each.
    model = stepover(refine=1)
    assert np.bincount(model.fault_index).tolist() == [15, 15]
    # A plane between the grid's planes x = 0.25 and 0.375 (h = 0.125): the second fault
    # is named, the first is fine alone.
    cube = rsf.Mesh.cuboid((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), (9, 9, 9))
    square = lambda x: [(x, 0.25, 0.25), (x, 0.75, 0.25), (x, 0.75, 0.75), (x, 0.25, 0.75)]
    with pytest.raises(rsf.ModelError, match=r"`faults`: fault `b`: "):
        rsf.Model(cube, **MATERIAL,
                  dirichlet=[(("left", lambda x: x[0] < 1e-9), (0.0, -V, 0.0))],
                  faults=[("a", square(0.25)), ("b", square(0.3))])


@pytest.mark.parametrize(
    "faults, error, match",
    [
        # The Python side's checks: names, shapes, values.
        ([("a", [(0.0, -1.0), (0.0, 1.0)]), ("a", [(0.5, -1.0), (0.5, 1.0)])],
         rsf.InvalidParameterError, r"`faults`: fault `a`: the name is given twice"),
        ([("", [(0.0, -1.0), (0.0, 1.0)])], rsf.InvalidParameterError, r"`faults`: entry 0"),
        ([("a", [(0.0, -1.0)])], rsf.InvalidParameterError, r"`faults`: fault `a`: 1 points"),
        ([("a", [(0.0, -1.0, 0.0), (0.0, 1.0, 0.0)])], rsf.InvalidParameterError,
         r"fault `a`: a point of 3 coordinates"),
        ([("a", [(0.0, -1.0), (np.nan, 1.0)])], rsf.InvalidParameterError,
         r"fault `a`: the point .* is not finite"),
        ("a", rsf.InvalidParameterError, r"`faults`: .*\(name, points\)"),
        # The builder's, attributed to the fault that cannot be cut alone.
        ([("ok", [(0.0, -1.0), (0.0, 1.0)]), ("off", [(0.1, -1.0), (0.1, 1.0)])],
         rsf.ModelError, r"`faults`: fault `off`: the mesh has no edges along"),
        ([("ok", [(0.0, -1.0), (0.0, 1.0)]), ("out", [(5.0, -1.0), (5.0, 1.0)])],
         rsf.ModelError, r"`faults`: fault `out`: "),
        # Each fine alone, but two faults ending at one vertex: the library names both.
        ([("north", [(0.0, 0.0), (0.0, 1.0)]), ("east", [(0.0, 0.0), (1.0, 0.0)])],
         rsf.ModelError, r"`faults`: the faults \[\"north\", \"east\"\] meet at vertex"),
    ],
)
def test_refusals_name_the_keyword_and_the_fault(faults, error, match):
    mesh = rsf.Mesh.rectangle(**SQUARE)
    with pytest.raises(error, match=match):
        rsf.Model(mesh, **MATERIAL, dirichlet=sheared(), faults=faults)


FRICTION = dict(mu0=0.6, a=0.015, b=0.01, v0=1e-6, l=1e-4, sigma_n=5e6)


def ode(model, **kw):
    """The fault ODE of a model (its Green's functions are the condensed operator's)."""
    args = dict(
        friction=rsf.Friction.regularised(**FRICTION),
        alpha0=np.log(1e-4 / 1e-9),
        tau=1.0,
        method="fault-ode",
        radiation_damping=5e6,
    )
    args.update(kw)
    return rsf.simulate(model, **args)


def test_greens_blocks_per_fault_pair():
    g = ode(stepover()).greens_functions()
    assert g.fault_names == ["west", "east"] and g.dim == 14
    S = g.matrix()
    w, e = g.unknowns_of("west"), g.unknowns_of("east")
    assert len(w) == len(e) == 7 and sorted(np.r_[w, e]) == list(range(14))
    blocks = {(r, s): g.block(r, s) for r in ("west", "east") for s in ("west", "east")}
    # Each block is the dense matrix's slice, bit for bit.
    for (r, s), b in blocks.items():
        np.testing.assert_array_equal(b, S[np.ix_(g.unknowns_of(r), g.unknowns_of(s))])
    scale = np.abs(S).max()
    # Reciprocity across the faults: S_we = S_ewᵀ (the dense kernel: to round-off).
    np.testing.assert_allclose(blocks["west", "east"], blocks["east", "west"].T,
                               rtol=0, atol=1e-12 * scale)
    # The rotation maps west onto east: S_ee = P S_ww Pᵀ and S_ew = P S_we Pᵀ.
    p = rotated(g.positions[w, :2], g.positions[e, :2])
    ww, ee = blocks["west", "west"], blocks["east", "east"]
    np.testing.assert_allclose(ee[np.ix_(p, p)], ww, rtol=0, atol=1e-10 * scale)
    np.testing.assert_allclose(blocks["east", "west"][np.ix_(p, p)],
                               blocks["west", "east"], rtol=0, atol=1e-10 * scale)
    # The diagonal blocks are positive definite; the strands interact (the cross block is
    # not zero) but less than each strand with itself.
    for b in (ww, ee):
        assert np.linalg.eigvalsh(0.5 * (b + b.T)).min() > 0
    cross = np.linalg.norm(blocks["west", "east"])
    assert 0 < cross < 0.1 * np.linalg.norm(ww)


def test_the_cross_block_decays_with_the_gap():
    gaps = [0.5, 1.0, 1.5, 2.0]
    cross = []
    for gap in gaps:
        g = ode(stepover(gap)).greens_functions()
        own = np.linalg.norm(g.block("west", "west"))
        cross.append(np.linalg.norm(g.block("west", "east")) / own)
    # Strictly decreasing as the strands move apart.
    assert all(b < a for a, b in zip(cross, cross[1:])), cross


def test_per_fault_parameters_are_the_arrays_they_stand_for():
    """A dict of per-fault values runs the same trajectory, bit for bit, as the array it
    stands for (built here from fault_index and fault_nodes)."""
    model = stepover()
    x = model.fault_coordinates
    west = model.fault_index == model.fault_names.index("west")
    b_west = lambda x: 0.02 + 0.001 * x[:, 1]
    as_dict = dict(FRICTION, b={"west": b_west, "east": 0.005})
    b = np.where(west, b_west(x), 0.005)
    as_array = dict(FRICTION, b=b)
    runs = []
    for params in (as_dict, as_array):
        sim = ode(model, friction=rsf.Friction.regularised(**params), fault_every=1)
        sim.advance(steps=20)
        runs.append(sim.fault())
    np.testing.assert_array_equal(runs[0]["slip_rate"], runs[1]["slip_rate"])
    np.testing.assert_array_equal(runs[0]["alpha"], runs[1]["alpha"])
    with pytest.raises(rsf.InvalidParameterError, match=r"`b`: no value for the fault `east`"):
        ode(model, friction=rsf.Friction.regularised(**dict(FRICTION, b={"west": 0.01})))
    with pytest.raises(rsf.InvalidParameterError, match=r"`b`: `north` is none of"):
        ode(model, friction=rsf.Friction.regularised(
            **dict(FRICTION, b={"west": 0.01, "east": 0.01, "north": 0.01})))
    with pytest.raises(rsf.InvalidParameterError, match=r"one value per fault node: shape \(7,\)"):
        ode(model, friction=rsf.Friction.regularised(
            **dict(FRICTION, b={"west": np.zeros(14), "east": 0.01})))


@pytest.mark.parametrize("method", ["fault-ode", "implicit"])
def test_a_stepover_runs_symmetric_with_named_outputs(method):
    """A few steps of the symmetric stepover, velocity weakening on both strands: every
    record names its nodes' faults, and the east strand's slip rate and state are the west
    one's at the rotated nodes (to the solvers' accuracy)."""
    model = stepover()
    kw = dict(fault_every=5)
    if method == "implicit":
        # Steps of a day (the fault ODE's adaptive steps reach about a week in 40).
        kw.update(method="implicit", integrator="quasistatic", solver="direct", tau=86400.0)
    sim = ode(model, **kw)
    sim.advance(steps=40)
    f = sim.fault()
    assert f["fault_names"] == ["west", "east"]
    np.testing.assert_array_equal(f["fault"], model.fault_index)
    w = np.flatnonzero(f["fault"] == 0)
    e = np.flatnonzero(f["fault"] == 1)
    p = rotated(f["x"][w], f["x"][e])
    v = f["slip_rate"]
    assert v.shape == (8, 14) and np.all(np.isfinite(v))
    # Loaded by the plates, the strands have sped up from rest towards the plates' rate.
    assert 1e-11 < v[-1].max() < 2 * V and np.all(v[-1] > v[0])
    # The mirror images agree to round-off amplified by the run in the fault ODE (measured
    # 2e-13 of the largest slip rate, 1e-14 in α), to the fixed point's tolerance in the
    # implicit scheme, whose iterations stop at different residuals on the two strands
    # (measured 1.6e-10, 7e-11 in α).
    tol = 1e-11 if method == "fault-ode" else 1e-8
    atol = tol * np.abs(v).max()
    np.testing.assert_allclose(v[:, e[p]], v[:, w], rtol=0, atol=atol)
    np.testing.assert_allclose(f["alpha"][:, e[p]], f["alpha"][:, w], rtol=0, atol=tol)
    # A record read with the wrong fault's nodes differs at the level of the variation
    # along a strand.
    assert np.abs(v[:, e] - v[:, w]).max() > 1e3 * atol
    ds = sim.to_xarray()
    assert sorted(set(ds["fault"].values)) == ["east", "west"]


def test_fault_ode_refuses_the_implicit_settings():
    model = stepover()
    with pytest.raises(rsf.InvalidParameterError, match="`solver`"):
        ode(model, solver="direct")
    with pytest.raises(rsf.InvalidParameterError, match="`method`"):
        ode(model, method="explicit")
    with pytest.raises(rsf.InvalidParameterError, match="integrator"):
        ode(model, integrator="newmark")


def test_the_catalogue_names_the_fault_that_ruptured():
    """The west strand velocity weakening, the east one strengthening: every event of the
    catalogue nucleates on and ruptures the west strand alone. Its onsets and peaks are
    those of the single-series detector (`events()`, the same thresholds on the same
    largest slip rate), and each fault's moment is μ Σ w |Δδ| recomputed from the slips
    recorded at every step (the weights from the Green's functions' description)."""
    model = stepover()
    friction = rsf.Friction.regularised(
        mu0=0.6, a=0.01, b={"west": 0.015, "east": 0.005}, v0=1e-6, l=1e-5, sigma_n=5e7
    )
    sim = ode(model, friction=friction, alpha0=np.log(1e-5 / 1e-9), fault_every=1)
    sim.advance(until=1e7)
    c, ev = sim.catalogue(), sim.events()
    n = len(c["onset"])
    assert n >= 2 and c["faults"] == ["west", "east"]
    np.testing.assert_array_equal(c["onset"], ev["onset"])
    np.testing.assert_array_equal(c["peak_slip_rate"].max(axis=1), ev["peak_slip_rate"])
    assert list(c["nucleation_fault"]) == ["west"] * n
    np.testing.assert_array_equal(c["nucleation_x"][:, 0], -0.25)
    np.testing.assert_array_equal(c["ruptured"], np.tile([True, False], (n, 1)))
    assert np.all(c["peak_slip_rate"][:, 0] > 1e-3) and np.all(c["peak_slip_rate"][:, 1] < 1e-3)
    assert np.all(np.isnan(c["rupture"][:, 1])) and np.all(c["rupture"][:, 0] >= c["onset"])
    # The moments from the records: δ at the step before the onset and at the end.
    f = sim.fault()
    g = sim.greens_functions()
    weights = np.empty(len(f["x"]))
    for i, x in enumerate(f["x"]):
        weights[i] = g.weights[np.flatnonzero(np.all(g.positions[:, :2] == x, axis=1))[0]]
    mu = MATERIAL["youngs_modulus"] / (2 * (1 + MATERIAL["poisson_ratio"]))
    step = {t: i for i, t in enumerate(f["t"])}
    for e in range(n - 1):
        before = ev["onset_step"][e] - 2  # records are of steps 1, 2, …
        after = step[c["end"][e]]
        jump = np.linalg.norm(f["slip"][after] - f["slip"][before], axis=1)
        for j in range(2):
            on = f["fault"] == j
            expected = mu * np.sum(weights[on] * jump[on])
            assert c["moment"][e, j] == pytest.approx(expected, rel=1e-12)
    assert np.all(c["moment"][:-1, 0] > 1e3 * c["moment"][:-1, 1])


def test_a_scene_has_no_network_catalogue():
    with pytest.raises(rsf.InvalidParameterError, match="`catalogue`"):
        rsf.seas_bp1(dz=1000.0, domain_km=100.0, threads=1, end_years=1.0).catalogue()


@pytest.mark.parametrize("method", ["fault-ode", "implicit"])
def test_a_network_run_resumes_bit_for_bit(method, tmp_path):
    """A checkpoint of the stepover resumes into a new simulation of the same model (its
    fingerprint holds the faults) and continues bit for bit; a model with another fault
    geometry is refused."""
    kw = dict(fault_every=1)
    if method == "implicit":
        kw.update(method="implicit", integrator="quasistatic", solver="direct", tau=86400.0)
    first = ode(stepover(), **kw)
    first.advance(steps=15)
    first.checkpoint(tmp_path / "c.bin")
    first.advance(steps=15)
    second = ode(stepover(), **kw)
    second.resume(tmp_path / "c.bin")
    second.advance(steps=15)
    a, b = first.fault(), second.fault()
    np.testing.assert_array_equal(a["slip_rate"][-15:], b["slip_rate"])
    np.testing.assert_array_equal(a["alpha"][-15:], b["alpha"])
    other = ode(stepover(gap=1.0), **kw)
    with pytest.raises(rsf.CheckpointError, match="model"):
        other.resume(tmp_path / "c.bin")


@pytest.mark.skipif(not rsf.HAS_HDF5, reason="built without the feature hdf5")
def test_greens_functions_of_two_faults_round_trip_through_hdf5(tmp_path):
    """A two-fault run's Green's functions written to HDF5 by the library's writer and read
    back by its reader: the matrix and the description bit for bit, the blocks per pair by
    name the run's; h5py sees S and the fault names; the npz file of the same run equal."""
    h5py = pytest.importorskip("h5py")
    g = ode(stepover()).greens_functions()
    path = tmp_path / "greens.h5"
    g.to_hdf5(path)
    back = rsf.GreensFunctions.from_hdf5(path)
    assert back.matrix().tobytes() == g.matrix().tobytes()
    assert back.fault_names == g.fault_names == ["west", "east"]
    for k in ("fault", "node", "component", "positions", "directions", "weights"):
        assert getattr(back, k).tobytes() == getattr(g, k).tobytes(), k
    for k in ("origin", "kernel", "relative_error", "tolerance", "unit_S", "dimension"):
        assert getattr(back, k) == getattr(g, k), k
    for pair in [("west", "east"), ("east", "west"), ("east", "east")]:
        assert back.block(*pair).tobytes() == g.block(*pair).tobytes(), pair
    with h5py.File(path, "r") as f:
        assert f["S"][:].tobytes() == g.matrix().tobytes()
        assert [n.decode() for n in f["fault_names"][:]] == ["west", "east"]
    g.to_npz(tmp_path / "greens.npz")
    npz = rsf.GreensFunctions.from_npz(tmp_path / "greens.npz")
    assert npz.matrix().tobytes() == back.matrix().tobytes()
    with pytest.raises(ValueError, match="to_npz"):
        back.to_hdf5(tmp_path / "again.h5")


def test_each_fault_its_own_state_law():
    """`state_law` per fault: a dict giving every fault the same law runs the single law's
    trajectory bit for bit; with aging on one strand and slip on the other (strands 2 m
    apart, the cross block 0.4 % of the own block), each strand follows its own law's
    uniform run to within 1 % of the two laws' difference (measured 0.12 % and 0.09 % of 1.70
    in α after 30 days), and the point-symmetric stepover maps the mixed run onto the
    swapped one (west ↔ east; measured 3.3e-10 in α)."""
    model = stepover(gap=2.0)

    def run(state_law):
        # The implicit scheme's fixed steps of a day: every run's records at the same times.
        sim = ode(model, state_law=state_law, fault_every=1, method="implicit",
                  integrator="quasistatic", solver="direct", tau=86400.0)
        sim.advance(steps=30)
        return sim.fault()

    aging, slip = run("aging"), run("slip")
    same = run({"west": "slip", "east": "slip"})
    np.testing.assert_array_equal(same["alpha"], slip["alpha"])
    np.testing.assert_array_equal(same["slip_rate"], slip["slip_rate"])
    mixed = run({"west": "aging", "east": "slip"})
    swapped = run({"west": "slip", "east": "aging"})
    w = np.flatnonzero(model.fault_index == 0)
    e = np.flatnonzero(model.fault_index == 1)
    np.testing.assert_array_equal(mixed["t"], aging["t"])
    a = lambda r, nodes: r["alpha"][:, nodes]
    laws_apart = np.abs(a(aging, w) - a(slip, w)).max()
    assert laws_apart > 0.1, laws_apart
    assert np.abs(a(mixed, w) - a(aging, w)).max() < 0.01 * laws_apart
    assert np.abs(a(mixed, e) - a(slip, e)).max() < 0.01 * laws_apart
    p = rotated(mixed["x"][w], mixed["x"][e])
    # To the fixed point's tolerance (the mirror-image strands of the uniform runs agree to
    # 7e-11 in α, test_a_stepover_runs_symmetric_with_named_outputs).
    np.testing.assert_allclose(a(swapped, e[p]), a(mixed, w), rtol=0, atol=1e-8)
    np.testing.assert_allclose(a(swapped, w), a(mixed, e[p]), rtol=0, atol=1e-8)
    with pytest.raises(rsf.InvalidParameterError, match=r"`state_law`: no law for the fault `east`"):
        ode(model, state_law={"west": "aging"})
    with pytest.raises(rsf.InvalidParameterError, match=r"`state_law`: `north` is none of"):
        ode(model, state_law={"west": "aging", "east": "slip", "north": "slip"})
    with pytest.raises(rsf.InvalidParameterError, match=r"state_law"):
        ode(model, state_law={"west": "aging", "east": "discontinuous"})


FIXTURES = __import__("pathlib").Path(__file__).resolve().parents[2] / "rsf-fem/tests/fixtures"


@pytest.mark.parametrize("case", ["2d", "3d"])
def test_faults_from_gmsh_physical_groups(case):
    """A fault named by a Gmsh physical group inside the body (a curve in 2-D, a surface in
    3-D; meshes gmsh wrote, crates/rsf-fem/tests/fixtures) builds the model the same fault
    given by its points builds (the geometry from the .geo files): the same nodes, in the
    same order, bit for bit."""
    if case == "2d":
        mesh = rsf.Mesh.read_gmsh(FIXTURES / "stepover.msh", dim=2)
        points = {"south": [(0.5, 0.8), (2.5, 0.8)], "north": [(1.5, 1.2), (3.5, 1.2)]}
        dirichlet = [("top", (1e-9, 0.0)), ("bottom", (-1e-9, 0.0))]
    else:
        mesh = rsf.Mesh.read_gmsh(FIXTURES / "two_faults.msh", dim=3)
        square = lambda x: [(x, 0.25, 0.25), (x, 0.75, 0.25), (x, 0.75, 0.75), (x, 0.25, 0.75)]
        points = {"west": square(0.6), "east": square(1.4)}
        ends = lambda x: x[0] < 1e-9 or x[0] > 2.0 - 1e-9
        dirichlet = [(("ends", ends), (0.0, 1e-9, 0.0))]
    by_group = rsf.Model(mesh, **MATERIAL, dirichlet=dirichlet,
                         faults=[(name, name) for name in points])
    by_points = rsf.Model(mesh, **MATERIAL, dirichlet=dirichlet, faults=list(points.items()))
    assert by_group.fault_names == list(points) == by_points.fault_names
    assert by_group.num_nodes == by_points.num_nodes
    # The same pairs (the polygon's and the group's faces are the same faces, possibly
    # listed in another order in 3-D): every fault's node set, and the node counts.
    for name in points:
        a = by_group.fault_coordinates[by_group.fault_nodes(name)]
        b = by_points.fault_coordinates[by_points.fault_nodes(name)]
        assert len(a) == len(b) > 0
        np.testing.assert_array_equal(np.unique(a, axis=0), np.unique(b, axis=0))
    with pytest.raises(rsf.InvalidParameterError, match=r"`faults`: fault `x`: .*`nowhere`"):
        rsf.Model(mesh, **MATERIAL, dirichlet=dirichlet, faults=[("x", "nowhere")])
