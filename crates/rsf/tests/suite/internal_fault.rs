//! A fault inside the body through the existing velocity solvers (docs/faults-inside.md,
//! docs/math.md §15): after the mean–jump change of variables `u = T u'` the velocity
//! problem `min ½ v'ᵀ K' v' + Σ w_p φ(|j_T,p|)` with `K' = Tᵀ K T`, the normal jump tied
//! and Tresca friction on the jump blocks is what TNNMG and the direct solver already
//! solve: both give the same minimiser, part of the fault slipping, part stuck.
use rsf::direct::{DirectOptions, DirectSolver};
use rsf::faer::sparse::{SparseColMat, Triplet};
use rsf::fem::{
    rectangle, refine_red, vectorize, Assembler, Diagonal, DofTransform, FaultSides,
    LinearElasticity, SparseMatrix, TriangleMesh,
};
use rsf::friction::Tresca;
use rsf::method::FrictionBlocks;
use rsf::nonsmooth::{NoNonlinearity, NonsmoothSolver};
use rsf::tnnmg::{Tnnmg, TnnmgOptions};

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

// ---------------------------------------------------------------------------------------
// The internal fault inside the model (`ModelBuilder::internal_fault`).

use crate::common::{
    assert_first_order, fault_ode_last_slip, history_difference, implicit_slip_errors,
    internal_fault_displacements, partly_stuck_history, run_tresca_steps, slip_and_jump, within,
    QuasiDynamic,
};
use rsf::normal_stress::NormalStress;
use rsf::{Material, Model, ModelBuilder, Part, SolverKind, StepView};

/// `x` turned by `theta` (rad) about the origin.
fn turn(theta: f64, x: [f64; 2]) -> [f64; 2] {
    let (c, s) = (theta.cos(), theta.sin());
    [c * x[0] - s * x[1], s * x[0] + c * x[1]]
}

/// `[-1, 1]²` (9 × 9 coarse vertices, refined once: a two-level hierarchy) turned by
/// `theta`, with a fault from `(0, −0.5)` to `(0, 0.5)` (tips inside), the top and bottom
/// moving oppositely along the (turned) x axis — simple shear of the fault — the sides free,
/// no inertia.
fn sheared_block(theta: f64) -> rsf::Result<Model<2>> {
    let square = rectangle([-1.0, -1.0], [2.0, 2.0], 9, 9, Diagonal::Forward)?;
    let moved: Vec<[f64; 2]> = square.vertices().iter().map(|&x| turn(theta, x)).collect();
    let coarse = square.with_moved_vertices(moved)?;
    let back = move |x: &[f64; 2]| turn(-theta, *x);
    let v = 1e-4;
    ModelBuilder::refined(coarse, 1)?
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(
            Part::predicate("top", move |x| back(x)[1] > 1.0 - 1e-9),
            turn(theta, [v, 0.0]),
        )
        .dirichlet(
            Part::predicate("bottom", move |x| back(x)[1] < -1.0 + 1e-9),
            turn(theta, [-v, 0.0]),
        )
        .internal_fault("fault", turn(theta, [0.0, -0.5]), turn(theta, [0.0, 0.5]))
        .build()
}

/// Per step and frictional node (in order along the fault, by the fault's own
/// coordinate): the slip's length, and checks of what an observer sees at the split nodes.
struct Slips {
    along: Vec<usize>,
    rows: Vec<Vec<f64>>,
}

impl rsf::Observer<2> for Slips {
    fn observe(&mut self, s: &StepView<'_, 2, 2>) -> rsf::Result<rsf::Flow> {
        let (f, u, u0) = internal_fault_displacements(s)?;
        let mut row = Vec::new();
        for &k in &self.along {
            let (mi, pl) = f.pairs()[k];
            // The observer's slip is the Cartesian jump of the two sides' displacements.
            let (slip, jump) = slip_and_jump(s, (&u, &u0), (mi, pl));
            let scale = slip[0].hypot(slip[1]).max(1e-12);
            assert!((slip[0] - jump[0]).hypot(slip[1] - jump[1]) < 1e-9 * scale);
            assert_eq!(s.displacement(pl), [u[2 * pl], u[2 * pl + 1]]);
            // No opening: the jump is along the fault.
            let normal = f.faults()[0].normals()[k.min(f.faults()[0].normals().len() - 1)];
            let opening = (jump[0] * normal[0] + jump[1] * normal[1]).abs();
            assert!(opening < 1e-12 * scale, "opening {opening:e}");
            row.push(slip[0].hypot(slip[1]));
        }
        self.rows.push(row);
        Ok(rsf::Flow::Continue(()))
    }
}

/// 20 quasistatic steps of 0.5 s with Tresca friction, weakest at the fault's centre
/// (μ = 0.3 + 0.6·|y′|, y′ along the fault, σ̄_n = 5 MPa): the slip of every pair at
/// every step.
fn slip_history(theta: f64, solver: SolverKind) -> Vec<Vec<f64>> {
    let model = sheared_block(theta).unwrap();
    let f = model.internal_fault.as_ref().unwrap();
    let mut slips = Slips {
        along: (0..f.pairs().len()).collect(),
        rows: Vec::new(),
    };
    let mu = |x: &[f64; 2]| 0.3 + 0.6 * turn(-theta, *x)[1].abs();
    run_tresca_steps(model.clone(), mu, solver, 20, &mut slips);
    slips.rows
}

/// The model's outputs at the split nodes are the two sides' Cartesian values, the
/// observers' slip is the jump, the fault never opens; TNNMG on the two-level hierarchy
/// (coarse space continuous across the fault) and the direct solver give the same slip
/// history; and the same problem turned by 0.3 and 1.2 rad slips the same.
#[test]
fn a_model_with_an_internal_fault_slips_the_same_with_both_solvers_and_turned() {
    let direct = slip_history(0.0, SolverKind::Direct);
    let largest = partly_stuck_history(&direct);
    let differs = |a: &[Vec<f64>], b: &[Vec<f64>]| history_difference(a, b) / largest;
    let tnnmg = slip_history(0.0, SolverKind::Tnnmg);
    let d = differs(&direct, &tnnmg);
    eprintln!("TNNMG against direct: {d:e} of the largest slip");
    assert!(d < 1e-6, "{d:e}");
    for theta in [0.3, 1.2] {
        let turned = slip_history(theta, SolverKind::Direct);
        let d = differs(&direct, &turned);
        eprintln!("turned by {theta}: {d:e} of the largest slip");
        assert!(d < 1e-8, "{theta}: {d:e}");
    }
}

/// What `internal_fault` refuses, by name.
#[test]
fn an_internal_fault_refuses_what_does_not_fit() {
    let named = |r: rsf::Result<Model<2>>, what: &str| match r {
        Err(rsf::Error::InvalidParameter { name, .. }) => assert_eq!(name, what),
        other => panic!(
            "expected InvalidParameter {what}, got {:?}",
            other.map(|_| ())
        ),
    };
    let block = || {
        ModelBuilder::new(rectangle([-1.0, -1.0], [2.0, 2.0], 9, 9, Diagonal::Forward).unwrap())
            .material(Material::new(1e10, 0.25, 2700.0))
            .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
    };
    // (A frictional boundary beside the fault is no longer refused: issue 83 made it a
    // model of its own, tested in fault_network.rs.)
    // A fault reaching a Dirichlet part that fixes one component: its end node is split
    // and only part of it prescribed.
    named(
        block()
            .dirichlet_components(
                Part::predicate("left", |x| x[0] < -1.0 + 1e-9),
                &[0],
                [0.0, 0.0],
            )
            .internal_fault("f", [-1.0, 0.0], [0.0, 0.0])
            .build(),
        "dirichlet",
    );
    // A fault reaching a Dirichlet part that fixes both sides of its end (the top moves
    // as one): that pair's motion is prescribed (no slip) and it is not a frictional node.
    let m = block()
        .internal_fault("f", [0.0, 0.0], [0.0, 1.0])
        .build()
        .unwrap();
    let f = m.internal_fault.as_ref().unwrap();
    assert_eq!(m.frictional_boundary.len(), f.pairs().len() - 1);
    // A segment the mesh does not resolve: the splitting's error.
    assert!(matches!(
        block().internal_fault("f", [0.1, -0.5], [0.1, 0.5]).build(),
        Err(rsf::Error::Fem(_))
    ));
}

/// The quasi-dynamic problem on the sheared block's internal fault (velocity
/// strengthening, a = 0.015 > b = 0.01, f₀ = 0.1 so that the loading reaches the friction
/// after about 1.3 s, the regularised law, aging law, radiation damping μ/(2c_s)) as a
/// builder, the state steady at 1e-4 m/s: `normal_stress`'s with the laws' σ̄_n.
fn quasi_dynamic() -> QuasiDynamic<2> {
    crate::normal_stress::quasi_dynamic(sheared_block(0.0).unwrap(), NormalStress::Fixed)
}

/// The two engines on an internal fault: the fault ODE (the volume condensed onto the
/// jump, Runge–Kutta at tolerance 1e-9) and the implicit scheme (backward Euler, fixed
/// steps) agree, the implicit scheme converging to the fault ODE at first order in τ.
#[test]
fn the_fault_ode_and_the_implicit_scheme_agree_on_an_internal_fault() {
    let t_end = 3.0;
    let until = within(t_end);
    let (reference, _) = fault_ode_last_slip(quasi_dynamic(), until);
    let errors = implicit_slip_errors(quasi_dynamic, t_end, &[25, 50, 100, 200], &reference);
    assert_first_order(&errors);
}
