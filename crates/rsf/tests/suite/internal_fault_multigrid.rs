//! Multigrid on a fault inside the body: `ModelBuilder::internal_fault` splits every level
//! of the hierarchy that resolves the fault, so the coarse spaces can slip
//! (docs/faults-inside.md). Measured here on a Tresca velocity problem with part of the
//! fault slipping: TNNMG's iteration count stays bounded as the mesh is refined, and it is
//! below that of the same solver whose coarse spaces are continuous across the fault (the
//! first version: only the finest mesh split, a plus copy taking its original's row).
use rsf::direct::{DirectOptions, DirectSolver};
use rsf::faer::sparse::{SparseColMat, Triplet};
use rsf::fem::{rectangle, vectorize, Diagonal, DofTransform, MeshHierarchy, SparseMatrix};
use rsf::friction::Tresca;
use rsf::method::FrictionBlocks;
use rsf::model::{MaterialRegions, Medium};
use rsf::nonsmooth::{NoNonlinearity, NonsmoothSolver};
use rsf::tnnmg::{Tnnmg, TnnmgOptions};
use rsf::{Material, Model, ModelBuilder, Part};

const FROM: [f64; 2] = [0.0, -0.5];
const TO: [f64; 2] = [0.0, 0.5];

/// `[-1, 1]²` from 5 × 5 vertices refined `levels` times, the fault from (0, −0.5) to
/// (0, 0.5) (resolved on every level), the whole outer boundary Dirichlet.
fn coarse() -> rsf::fem::TriangleMesh {
    rectangle([-1.0, -1.0], [2.0, 2.0], 5, 5, Diagonal::Forward).unwrap()
}

fn model(levels: usize, fault: &[[f64; 2]]) -> Model<2> {
    model_with(levels, fault, 1.0)
}

/// The body of [`model`] with the side x > 0 (the fault's minus side) `ratio` times
/// stiffer.
fn medium(ratio: f64) -> MaterialRegions<2> {
    let rock = Material::new(1e10, 0.25, 2700.0);
    let stiff = Material {
        youngs_modulus: ratio * rock.youngs_modulus,
        ..rock
    };
    MaterialRegions::new(rock).region("stiff", |x| x[0] > 0.0, stiff)
}

fn model_with(levels: usize, fault: &[[f64; 2]], ratio: f64) -> Model<2> {
    ModelBuilder::refined(coarse(), levels)
        .unwrap()
        .material(medium(ratio))
        .without_mass()
        .dirichlet(
            Part::predicate("outer", |x| x[0].abs().max(x[1].abs()) > 1.0 - 1e-9),
            [0.0, 0.0],
        )
        .internal_fault_polyline("fault", fault)
        .build()
        .unwrap()
}

/// The coarse spaces continuous across the fault: the unsplit hierarchy's prolongations,
/// the finest one `T⁻¹ C P` (`C` gives a plus copy its original's row).
fn continuous_prolongations(model: &Model<2>, levels: usize) -> Vec<SparseMatrix> {
    let h = MeshHierarchy::try_refine_uniformly(coarse(), levels).unwrap();
    let f = model.internal_fault.as_ref().unwrap();
    let (nv0, nv) = (h.finest().num_vertices(), model.vertices.len());
    let mut original: Vec<usize> = (0..nv).collect();
    for &(mi, pl) in f.pairs() {
        original[pl] = mi;
    }
    for j in f.network.junctions() {
        for &(copy, _) in j.sectors() {
            original[copy] = j.vertex();
        }
    }
    let copy: Vec<Triplet<usize, usize, f64>> = (0..2 * nv)
        .map(|i| Triplet::new(i, 2 * original[i / 2] + i % 2, 1.0))
        .collect();
    let copy = SparseColMat::try_new_from_triplets(2 * nv, 2 * nv0, &copy).unwrap();
    let mut out: Vec<SparseMatrix> = (1..=levels)
        .map(|j| vectorize::<2>(h.prolongation(j)))
        .collect();
    let last = out.last_mut().unwrap();
    *last = f.transform.prolongation(&(&copy * &*last)).unwrap();
    out
}

/// The Tresca velocity problem on `model`'s unknowns: the outer boundary moving with
/// v = (γ̇ (y + 1)²/2, 0) (a shear growing with y), the threshold 0.8 of the largest
/// shear traction of the stuck fault. Returns the initial iterate (boundary values) and
/// the friction blocks.
fn tresca_problem(model: &Model<2>) -> (Vec<f64>, FrictionBlocks<Tresca>) {
    tresca_problem_at(model, 0.8)
}

/// [`tresca_problem`] with the threshold `fraction` of the largest shear traction of the
/// stuck fault.
fn tresca_problem_at(model: &Model<2>, fraction: f64) -> (Vec<f64>, FrictionBlocks<Tresca>) {
    let (k, fixed) = (&model.stiffness, &model.fixed);
    let n = fixed.len();
    let mut v0 = vec![0.0; n];
    for (q, x) in model.vertices.iter().enumerate() {
        if fixed[2 * q] && x[0].abs().max(x[1].abs()) > 1.0 - 1e-9 {
            v0[2 * q] = 0.5e-3 * (x[1] + 1.0) * (x[1] + 1.0);
        }
    }
    let nodes = model.frictional_boundary.nodes.clone();
    let weights = model.frictional_boundary.weights.clone();
    let mut stuck_fixed = fixed.clone();
    for &p in &nodes {
        stuck_fixed[2 * p] = true;
    }
    let mut stuck = v0.clone();
    DirectSolver::<2>::new(k.as_ref(), &stuck_fixed, DirectOptions::default())
        .unwrap()
        .solve(&vec![0.0; n], &NoNonlinearity, &mut stuck)
        .unwrap();
    let mut r = vec![0.0; n];
    rsf::fem::spmv_add(k.as_ref(), 1.0, &stuck, &mut r);
    let tau_max = nodes
        .iter()
        .zip(&weights)
        .map(|(&p, &w)| r[2 * p].abs() / w)
        .fold(0.0f64, f64::max);
    let law = Tresca::new(fraction * tau_max, 1.0).unwrap();
    let nf = nodes.len();
    (
        v0,
        FrictionBlocks::new(nodes, weights, vec![law; nf], &vec![0.0; nf]),
    )
}

/// The direct solver's minimiser and TNNMG's iterate from `v0` on `k` with
/// `prolongations` with its iterations, or `None` if TNNMG does not converge (in its
/// default 200 iterations).
fn direct_and_maybe_tnnmg(
    k: &SparseMatrix,
    fixed: &[bool],
    prolongations: &[SparseMatrix],
    v0: &[f64],
    friction: &FrictionBlocks<Tresca>,
) -> (Vec<f64>, Option<(usize, Vec<f64>)>) {
    let b = vec![0.0; v0.len()];
    let mut direct = v0.to_vec();
    DirectSolver::<2>::new(k.as_ref(), fixed, DirectOptions::default())
        .unwrap()
        .solve(&b, friction, &mut direct)
        .unwrap();
    let mut v = v0.to_vec();
    let report = Tnnmg::<2>::new(
        k.as_ref(),
        fixed,
        prolongations,
        None,
        TnnmgOptions::default(),
    )
    .unwrap()
    .solve(&b, friction, &mut v);
    (direct, report.ok().map(|r| (r.iterations, v)))
}

/// The direct solver's minimiser, TNNMG's iterations and the relative energy-norm
/// difference of its result from the direct one (TNNMG must converge).
fn direct_and_tnnmg(
    k: &SparseMatrix,
    fixed: &[bool],
    prolongations: &[SparseMatrix],
    v0: &[f64],
    friction: &FrictionBlocks<Tresca>,
) -> (Vec<f64>, usize, f64) {
    let (direct, tnnmg) = direct_and_maybe_tnnmg(k, fixed, prolongations, v0, friction);
    let (iterations, v) = tnnmg.expect("TNNMG converges");
    let energy = |x: &[f64]| {
        let mut y = vec![0.0; x.len()];
        rsf::fem::spmv_add(k.as_ref(), 1.0, x, &mut y);
        x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>()
    };
    let d: Vec<f64> = v.iter().zip(&direct).map(|(a, b)| a - b).collect();
    let error = (energy(&d) / energy(&direct)).sqrt();
    (direct, iterations, error)
}

/// TNNMG's iterations with the model's (split) coarse spaces and with continuous ones,
/// and the relative energy-norm difference of both from the direct solver's minimiser;
/// the fraction of the fault's pairs that slip.
fn iterations(levels: usize, fault: &[[f64; 2]]) -> (usize, usize, f64, f64, f64) {
    iterations_on(model(levels, fault), levels, 0.8)
}

/// [`iterations`] on `model` (refined `levels` times from [`coarse`]), the Tresca threshold
/// `fraction` of the stuck fault's largest shear traction.
fn iterations_on(model: Model<2>, levels: usize, fraction: f64) -> (usize, usize, f64, f64, f64) {
    let (v0, friction) = tresca_problem_at(&model, fraction);
    let (k, fixed) = (&model.stiffness, &model.fixed);
    let (direct, split, split_error) =
        direct_and_tnnmg(k, fixed, &model.prolongations, &v0, &friction);
    let continuous = continuous_prolongations(&model, levels);
    let (_, continuous, continuous_error) = direct_and_tnnmg(k, fixed, &continuous, &v0, &friction);
    let nodes = &model.frictional_boundary.nodes;
    let slipping = nodes
        .iter()
        .filter(|&&p| direct[2 * p].abs() > 1e-12)
        .count();
    (
        split,
        continuous,
        split_error,
        continuous_error,
        slipping as f64 / nodes.len() as f64,
    )
}

#[test]
fn tnnmg_on_split_coarse_levels_converges_in_a_bounded_number_of_iterations() {
    let mut split = Vec::new();
    for levels in 1..=4 {
        let (s, c, es, ec, slipping) = iterations(levels, &[FROM, TO]);
        eprintln!(
            "levels {levels}: TNNMG iterations {s} (split coarse spaces) vs {c} (continuous); \
             differences from the direct solver {es:.1e}, {ec:.1e}; {:.0}% of the pairs slip",
            100.0 * slipping
        );
        assert!(slipping > 0.0 && slipping < 1.0, "part of the fault slips");
        assert!(es < 1e-8 && ec < 1e-8, "{es:e} {ec:e}");
        assert!(
            s <= c,
            "split coarse spaces take {s} iterations, continuous {c}"
        );
        split.push(s);
    }
    // Mesh independence: the finest needs at most a few iterations more than the coarsest.
    assert!(split[3] <= split[0] + 3, "{split:?}");
}

/// A kinked fault (from (−0.5, −0.5) up the diagonal to (0, 0), then up to (0, 0.5)):
/// the coarse copies on each side follow the cells at the kink; TNNMG on the split
/// hierarchy converges to the direct solver's minimiser, in no more iterations than with
/// continuous coarse spaces.
#[test]
fn tnnmg_on_a_kinked_internal_fault_agrees_with_the_direct_solver() {
    for levels in [2, 3] {
        let (s, c, es, ec, slipping) = iterations(levels, &[[-0.5, -0.5], [0.0, 0.0], TO]);
        eprintln!(
            "kinked, levels {levels}: TNNMG iterations {s} (split) vs {c} (continuous); \
             differences from the direct solver {es:.1e}, {ec:.1e}; {:.0}% of the pairs slip",
            100.0 * slipping
        );
        assert!(slipping > 0.0 && slipping < 1.0, "part of the fault slips");
        assert!(es < 1e-8 && ec < 1e-8, "{es:e} {ec:e}");
        assert!(s <= c, "split {s}, continuous {c}");
    }
}

/// A side 10⁴ times stiffer than the other: with the jump shared by stiffness (the model's
/// transform, the stiff side's share ≈ 10⁻⁴) TNNMG needs about the iterations of the
/// homogeneous body; with the plain mean (`T` with shares ½, the same problem) the
/// node-block smoother drags the stiff side with every slip update and needs more.
#[test]
fn tnnmg_on_a_fault_between_contrasting_sides_shares_the_jump_by_stiffness() {
    let levels = 3;
    let fault = [FROM, TO];
    let homogeneous = iterations(levels, &fault).0;
    let model = model_with(levels, &fault, 1e4);
    let f = model.internal_fault.as_ref().unwrap();
    let shares = &f.transform.minus_share;
    let largest = shares.iter().fold(0.0f64, |m, &b| m.max(b));
    assert!(
        largest < 1e-3,
        "the stiff minus side takes {largest:e} of the jump"
    );
    let (v0, friction) = tresca_problem(&model);
    let (direct, shared, error) = direct_and_tnnmg(
        &model.stiffness,
        &model.fixed,
        &model.prolongations,
        &v0,
        &friction,
    );
    // The same problem in the mean's coordinates: K_mean = T_meanᵀ K T_mean on the split
    // mesh, its finest prolongation T_mean⁻¹ (T P').
    let split = MeshHierarchy::try_refine_uniformly(coarse(), levels)
        .unwrap()
        .finest()
        .split_along_polyline("fault", &fault)
        .unwrap()
        .0;
    let cartesian = medium(1e4).assemble(&split, false).unwrap().stiffness;
    let mean = f
        .transform
        .reshared::<2>(&f.faults()[0], &vec![0.5; shares.len()])
        .unwrap();
    let k_mean = mean.congruence(&cartesian).unwrap();
    let mut prolongations = model.prolongations.clone();
    let last = prolongations.last_mut().unwrap();
    *last = mean.prolongation(&(&f.transform.t * &*last)).unwrap();
    // Initial iterate and boundary values: Cartesian outside the pairs, the jump (0 at
    // the start) at the minus nodes, so the same vector in both coordinates except the
    // pairs' means, which start at 0 in both.
    let (direct_mean, mean_tnnmg) =
        direct_and_maybe_tnnmg(&k_mean, &model.fixed, &prolongations, &v0, &friction);
    let mean_iterations = mean_tnnmg.map(|(iterations, _)| iterations);
    let slip_difference = model
        .frictional_boundary
        .nodes
        .iter()
        .map(|&p| (direct[2 * p] - direct_mean[2 * p]).abs())
        .fold(0.0f64, f64::max);
    let slip_scale = model
        .frictional_boundary
        .nodes
        .iter()
        .map(|&p| direct[2 * p].abs())
        .fold(0.0f64, f64::max);
    eprintln!(
        "contrast 1e4, levels {levels}: TNNMG iterations {shared} (shared by stiffness) vs \
         {mean_iterations:?} (mean; None: not converged in 200), homogeneous {homogeneous}; \
         difference from the direct solver {error:.1e}; the direct solver's slip in the two \
         coordinates differs by {slip_difference:.1e} of {slip_scale:.1e}"
    );
    assert!(error < 1e-8, "{error:e}");
    assert!(slip_difference < 1e-9 * slip_scale);
    assert!(
        shared <= homogeneous + 2,
        "{shared} vs homogeneous {homogeneous}"
    );
    assert!(
        mean_iterations.is_none_or(|m| shared < m),
        "{shared} vs mean {mean_iterations:?}"
    );
}

/// The model reports where the builder stopped cutting the hierarchy: every level for a
/// fault on the coarsest mesh's edges; from level 1 up for one between the coarsest
/// vertices (level 0's spacing 0.5 has no vertex at y = ±0.25), which level 0 does not
/// resolve.
#[test]
fn the_coarsest_split_level_is_reported() {
    let coarsest = |fault: &[[f64; 2]]| {
        model(2, fault)
            .internal_fault
            .as_ref()
            .unwrap()
            .coarsest_split_level()
    };
    assert_eq!(coarsest(&[FROM, TO]), 0);
    assert_eq!(coarsest(&[[0.0, -0.25], [0.0, 0.25]]), 1);
    assert_eq!(coarsest(&[[0.0, -0.125], [0.0, 0.125]]), 2);
}

/// A network on [`coarse`]: a main fault from (−0.5, 0) to (0.5, 0), a second from its
/// middle up to (0, 0.5) (a branch) or through it from (0, −0.5) (a crossing).
fn network_model(levels: usize, crossing: bool) -> Model<2> {
    ModelBuilder::refined(coarse(), levels)
        .unwrap()
        .material(medium(1.0))
        .without_mass()
        .dirichlet(
            Part::predicate("outer", |x| x[0].abs().max(x[1].abs()) > 1.0 - 1e-9),
            [0.0, 0.0],
        )
        .internal_fault_polyline("main", &[[-0.5, 0.0], [0.5, 0.0]])
        .internal_fault_polyline("second", &[[0.0, if crossing { -0.5 } else { 0.0 }], TO])
        .build()
        .unwrap()
}

/// A branch and a crossing: every level is cut along the network (its junction three or
/// four copies on each), and TNNMG on that hierarchy converges to the direct solver's
/// minimiser in a bounded number of iterations as the mesh is refined, in no more than
/// with coarse spaces continuous across the faults.
#[test]
fn tnnmg_on_a_fault_network_cut_on_every_level_agrees_with_the_direct_solver() {
    for crossing in [false, true] {
        let mut split = Vec::new();
        for levels in 1..=3 {
            let model = network_model(levels, crossing);
            let f = model.internal_fault.as_ref().unwrap();
            assert_eq!(f.coarsest_split_level(), 0);
            assert_eq!(f.network.junctions().len(), 1);
            // At 0.8 of the stuck network's largest shear traction (the single fault's
            // threshold) every node of the network slips; at 0.95, 7–25 %.
            let (s, c, es, ec, slipping) = iterations_on(model, levels, 0.95);
            eprintln!(
                "network (crossing {crossing}), levels {levels}: TNNMG iterations {s} (split) \
                 vs {c} (continuous); differences from the direct solver {es:.1e}, {ec:.1e}; \
                 {:.0}% of the slip nodes slip",
                100.0 * slipping
            );
            assert!(
                slipping > 0.0 && slipping < 1.0,
                "part of the network slips"
            );
            assert!(es < 1e-8 && ec < 1e-8, "{es:e} {ec:e}");
            assert!(s <= c, "split {s}, continuous {c}");
            split.push(s);
        }
        assert!(split[2] <= split[0] + 3, "{split:?}");
    }
}
