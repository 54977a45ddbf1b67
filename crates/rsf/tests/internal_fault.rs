//! A fault inside the body through the existing velocity solvers (docs/faults-inside.md,
//! docs/math.md §15): after the mean–jump change of variables `u = T u'` the velocity
//! problem `min ½ v'ᵀ K' v' + Σ w_p φ(|j_T,p|)` with `K' = Tᵀ K T`, the normal jump tied
//! and Tresca friction on the jump blocks is what TNNMG and the direct solver already
//! solve: both give the same minimiser, part of the fault slipping, part stuck.
use rsf::faer::sparse::{SparseColMat, Triplet};
use rsf::fem::{
    rectangle, refine_red, vectorize, Assembler, Diagonal, FaultSides, LinearElasticity,
    SparseMatrix, TriangleMesh,
};
use rsf::friction::Tresca;
use rsf::method::FrictionBlocks;
use rsf::tnnmg::{
    DirectOptions, DirectSolver, NoNonlinearity, NonsmoothSolver, Tnnmg, TnnmgOptions,
};

struct Problem {
    mesh: TriangleMesh,
    sides: FaultSides,
    t: SparseMatrix,
    k: SparseMatrix,
    p: SparseMatrix,
    fixed: Vec<bool>,
    v0: Vec<f64>,
    nodes: Vec<usize>,
    weights: Vec<f64>,
}

/// `[-1, 1]²` refined once from 9 × 9 vertices; a vertical fault from `(0, −0.5)` to
/// `(0, 0.5)` (tips inside) split on the fine mesh; the outer boundary moves with
/// `v = (γ̇ (y + 1)²/2, 0)`, a shear growing with y (so that part of the fault can stick).
/// The coarse space (the unsplit coarse mesh) is continuous across
/// the fault: its prolongation gives a plus copy its original's row.
fn problem() -> Problem {
    let coarse = rectangle([-1.0, -1.0], [2.0, 2.0], 9, 9, Diagonal::Forward).unwrap();
    let (fine, p) = refine_red(&coarse);
    let nv0 = fine.num_vertices();
    let (mesh, sides) = fine
        .split_along_segment("f", [0.0, -0.5], [0.0, 0.5])
        .unwrap();
    let nv = mesh.num_vertices();
    let mut original: Vec<usize> = (0..nv).collect();
    for (mi, pl) in sides.pairs() {
        original[pl] = mi;
    }
    // The coarse space on the split mesh: a plus copy takes its original's row of P.
    let copy: Vec<Triplet<usize, usize, f64>> = (0..2 * nv)
        .map(|i| Triplet::new(i, 2 * original[i / 2] + i % 2, 1.0))
        .collect();
    let copy = SparseColMat::try_new_from_triplets(2 * nv, 2 * nv0, &copy).unwrap();
    let p_split = &copy * &vectorize::<2>(&p);
    assert!(nv0 < nv);
    let tr = sides.mean_jump_transform::<2>(&mesh).unwrap();
    let k = Assembler::new(&mesh)
        .unwrap()
        .stiffness(&mesh, &LinearElasticity::plane_strain(1.0, 0.25).unwrap())
        .unwrap();
    let mut fixed = vec![false; 2 * nv];
    let mut v0 = vec![0.0; 2 * nv];
    for f in 0..mesh.num_boundary_facets() {
        if mesh.boundary_facet_tag(f).is_some() {
            continue;
        }
        for &q in mesh.boundary_facet(f) {
            fixed[2 * q] = true;
            fixed[2 * q + 1] = true;
            let y = mesh.vertices()[q][1];
            v0[2 * q] = 0.5e-3 * (y + 1.0) * (y + 1.0);
        }
    }
    // The jump blocks (at the minus copies) in increasing order, tangential slip first,
    // normal tied; weights: half of each adjacent fault edge (the minus face's lumping).
    let mut pairs: Vec<(usize, f64)> = Vec::new();
    let len: Vec<f64> = sides
        .minus_facets()
        .iter()
        .map(|&f| mesh.boundary_facet_measure(f))
        .collect();
    for (i, &(mi, pl)) in sides.nodes().iter().enumerate() {
        if mi == pl {
            continue;
        }
        fixed[2 * mi + 1] = true;
        let w = 0.5
            * (len.get(i.wrapping_sub(1)).copied().unwrap_or(0.0)
                + len.get(i).copied().unwrap_or(0.0));
        pairs.push((mi, w));
    }
    pairs.sort_by_key(|x| x.0);
    Problem {
        mesh,
        sides,
        k: tr.congruence(&k).unwrap(),
        p: tr.prolongation(&p_split).unwrap(),
        t: tr.t,
        fixed,
        v0,
        nodes: pairs.iter().map(|x| x.0).collect(),
        weights: pairs.iter().map(|x| x.1).collect(),
    }
}

fn energy(k: &SparseMatrix, x: &[f64]) -> f64 {
    let mut y = vec![0.0; x.len()];
    rsf::fem::spmv_add(k.as_ref(), 1.0, x, &mut y);
    x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>()
}

#[test]
fn tnnmg_and_the_direct_solver_agree_on_a_velocity_step_with_an_internal_fault() {
    let pb = problem();
    let n = pb.fixed.len();
    let b = vec![0.0; n];
    // Tresca threshold: 0.8 of the largest shear traction per unit length of the stuck fault.
    let mut stuck_fixed = pb.fixed.clone();
    for &p in &pb.nodes {
        stuck_fixed[2 * p] = true;
    }
    let mut stuck = pb.v0.clone();
    DirectSolver::<2>::new(pb.k.as_ref(), &stuck_fixed, DirectOptions::default())
        .unwrap()
        .solve(&b, &NoNonlinearity, &mut stuck)
        .unwrap();
    let mut r = vec![0.0; n];
    rsf::fem::spmv_add(pb.k.as_ref(), 1.0, &stuck, &mut r);
    let tau_max = pb
        .nodes
        .iter()
        .zip(&pb.weights)
        .map(|(&p, &w)| r[2 * p].abs() / w)
        .fold(0.0f64, f64::max);
    assert!(tau_max > 0.0);
    let law = Tresca::new(0.8 * tau_max, 1.0).unwrap();
    let nf = pb.nodes.len();
    let friction = FrictionBlocks::new(
        pb.nodes.clone(),
        pb.weights.clone(),
        vec![law; nf],
        &vec![0.0; nf],
    );

    let mut v_direct = pb.v0.clone();
    DirectSolver::<2>::new(pb.k.as_ref(), &pb.fixed, DirectOptions::default())
        .unwrap()
        .solve(&b, &friction, &mut v_direct)
        .unwrap();
    let mut v_tnnmg = pb.v0.clone();
    let report = Tnnmg::<2>::new(
        pb.k.as_ref(),
        &pb.fixed,
        std::slice::from_ref(&pb.p),
        None,
        TnnmgOptions::default(),
    )
    .unwrap()
    .solve(&b, &friction, &mut v_tnnmg)
    .unwrap();
    let d: Vec<f64> = v_tnnmg.iter().zip(&v_direct).map(|(a, b)| a - b).collect();
    let rel = (energy(&pb.k, &d) / energy(&pb.k, &v_direct)).sqrt();
    eprintln!(
        "TNNMG vs direct: relative energy-norm difference {rel:e} after {} iterations",
        report.iterations
    );
    assert!(rel < 1e-8, "{rel:e}");
    // Part of the fault slips, part sticks; the slip is the jump of the Cartesian field.
    let slipping = pb
        .nodes
        .iter()
        .filter(|&&p| v_direct[2 * p].abs() > 1e-12)
        .count();
    eprintln!("{slipping} of {nf} fault pairs slip");
    assert!(slipping > 0 && slipping < nf, "{slipping} of {nf} slip");
    assert_eq!(pb.mesh.num_vertices(), pb.fixed.len() / 2);
    let mut v = vec![0.0; n];
    rsf::fem::spmv_add(pb.t.as_ref(), 1.0, &v_direct, &mut v);
    let jumps = pb.sides.jump(&v, 2).unwrap();
    for ((&(mi, pl), j), n) in pb.sides.nodes().iter().zip(&jumps).zip(
        pb.sides
            .normals()
            .iter()
            .chain(std::iter::once(pb.sides.normals().last().unwrap())),
    ) {
        if mi == pl {
            continue;
        }
        // No opening; the tangential jump is the slip the solver saw.
        let opening = n[0] * j[0] + n[1] * j[1];
        assert!(opening.abs() < 1e-15);
        let slip = (j[0] * j[0] + j[1] * j[1]).sqrt();
        assert!((slip - v_direct[2 * mi].abs()).abs() < 1e-14);
    }
}
