//! Multigrid on a fault inside the body: `ModelBuilder::internal_fault` splits every level
//! of the hierarchy that resolves the fault, so the coarse spaces can slip
//! (docs/faults-inside.md). Measured here on a Tresca velocity problem with part of the
//! fault slipping: TNNMG's iteration count stays bounded as the mesh is refined, and it is
//! below that of the same solver whose coarse spaces are continuous across the fault (the
//! first version: only the finest mesh split, a plus copy taking its original's row).
use rsf::faer::sparse::{SparseColMat, Triplet};
use rsf::fem::{rectangle, vectorize, Diagonal, MeshHierarchy, SparseMatrix};
use rsf::friction::Tresca;
use rsf::method::FrictionBlocks;
use rsf::tnnmg::{
    DirectOptions, DirectSolver, NoNonlinearity, NonsmoothSolver, Tnnmg, TnnmgOptions,
};
use rsf::{Material, Model, ModelBuilder, Part};

const FROM: [f64; 2] = [0.0, -0.5];
const TO: [f64; 2] = [0.0, 0.5];

/// `[-1, 1]²` from 5 × 5 vertices refined `levels` times, the fault from (0, −0.5) to
/// (0, 0.5) (resolved on every level), the whole outer boundary Dirichlet.
fn coarse() -> rsf::fem::TriangleMesh {
    rectangle([-1.0, -1.0], [2.0, 2.0], 5, 5, Diagonal::Forward).unwrap()
}

fn model(levels: usize) -> Model<2> {
    ModelBuilder::refined(coarse(), levels)
        .unwrap()
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(
            Part::predicate("outer", |x| x[0].abs().max(x[1].abs()) > 1.0 - 1e-9),
            [0.0, 0.0],
        )
        .internal_fault("fault", FROM, TO)
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

/// TNNMG's iterations with the model's (split) coarse spaces and with continuous ones,
/// and the relative energy-norm difference of both from the direct solver's minimiser;
/// the fraction of the fault's pairs that slip.
fn iterations(levels: usize) -> (usize, usize, f64, f64, f64) {
    let model = model(levels);
    let k = &model.stiffness;
    let fixed = &model.fixed;
    let n = fixed.len();
    // The outer boundary moves with v = (γ̇ (y + 1)²/2, 0): a shear growing with y.
    let mut v0 = vec![0.0; n];
    for (q, x) in model.vertices.iter().enumerate() {
        if fixed[2 * q] && x[0].abs().max(x[1].abs()) > 1.0 - 1e-9 {
            v0[2 * q] = 0.5e-3 * (x[1] + 1.0) * (x[1] + 1.0);
        }
    }
    let b = vec![0.0; n];
    let nodes = model.frictional_boundary.nodes.clone();
    let weights = model.frictional_boundary.weights.clone();
    // Tresca threshold: 0.8 of the largest shear traction of the stuck fault.
    let mut stuck_fixed = fixed.clone();
    for &p in &nodes {
        stuck_fixed[2 * p] = true;
    }
    let mut stuck = v0.clone();
    DirectSolver::<2>::new(k.as_ref(), &stuck_fixed, DirectOptions::default())
        .unwrap()
        .solve(&b, &NoNonlinearity, &mut stuck)
        .unwrap();
    let mut r = vec![0.0; n];
    rsf::fem::spmv_add(k.as_ref(), 1.0, &stuck, &mut r);
    let tau_max = nodes
        .iter()
        .zip(&weights)
        .map(|(&p, &w)| r[2 * p].abs() / w)
        .fold(0.0f64, f64::max);
    let law = Tresca::new(0.8 * tau_max, 1.0).unwrap();
    let nf = nodes.len();
    let friction = FrictionBlocks::new(nodes.clone(), weights, vec![law; nf], &vec![0.0; nf]);
    let mut direct = v0.clone();
    DirectSolver::<2>::new(k.as_ref(), fixed, DirectOptions::default())
        .unwrap()
        .solve(&b, &friction, &mut direct)
        .unwrap();
    let energy = |x: &[f64]| {
        let mut y = vec![0.0; n];
        rsf::fem::spmv_add(k.as_ref(), 1.0, x, &mut y);
        x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>()
    };
    let solve = |prolongations: &[SparseMatrix]| {
        let mut v = v0.clone();
        let report = Tnnmg::<2>::new(
            k.as_ref(),
            fixed,
            prolongations,
            None,
            TnnmgOptions::default(),
        )
        .unwrap()
        .solve(&b, &friction, &mut v)
        .unwrap();
        let d: Vec<f64> = v.iter().zip(&direct).map(|(a, b)| a - b).collect();
        (report.iterations, (energy(&d) / energy(&direct)).sqrt())
    };
    let (split, split_error) = solve(&model.prolongations);
    let (continuous, continuous_error) = solve(&continuous_prolongations(&model, levels));
    let slipping = nodes
        .iter()
        .filter(|&&p| direct[2 * p].abs() > 1e-12)
        .count();
    (
        split,
        continuous,
        split_error,
        continuous_error,
        slipping as f64 / nf as f64,
    )
}

#[test]
fn tnnmg_on_split_coarse_levels_converges_in_a_bounded_number_of_iterations() {
    let mut split = Vec::new();
    for levels in 1..=4 {
        let (s, c, es, ec, slipping) = iterations(levels);
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
