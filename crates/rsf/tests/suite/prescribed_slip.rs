//! A fault whose slip is given (issue 70, item 6; docs/faults-inside.md "A prescribed
//! slip"): a kinematic source on a fault inside the body (`ModelBuilder::internal_slip_at`)
//! and held displacements (`dirichlet_displacement`) are the data of the static problem
//! the builder solves as the initial equilibrium; a fault whose every pair is prescribed
//! builds a model without frictional nodes, which a simulation refuses by name; the static
//! problem is solved again by `StaticSolver`, watched (progress, a time limit) if asked.
use crate::common::{parameter_name, plane_x0};
use std::sync::{Arc, Mutex};

use rsf::direct::{DirectOptions, DirectSolver};
use rsf::fem::cuboid;
use rsf::model::{CreepRate, PrescribedSlip, StaticMethod, StaticOptions, StaticSolver};
use rsf::nonsmooth::{NoNonlinearity, NonsmoothSolver, SolveWatch, Stopping};
use rsf::{Error, Material, Model, ModelBuilder, Part};

const SLIP: [f64; 3] = [0.0, 0.6e-3, 0.8e-3];

/// The 2 m cube of `n³` boxes refined `levels` times with the buried square fault
/// `|y|, |z| ≤ 0.5` in the plane `x = 0` (the plus side is `x > 0`), its bottom clamped.
fn builder(n: usize, levels: usize) -> ModelBuilder<3> {
    crate::common::cube_with_buried_fault(n, levels)
}

/// [`builder`]`(n, levels)` with the slip [`SLIP`] prescribed at every pair.
fn fully_prescribed(n: usize, levels: usize) -> Model<3> {
    builder(n, levels)
        .internal_slip_at(|_| Some(PrescribedSlip::Cartesian(SLIP)))
        .build()
        .unwrap()
}

/// The largest `|u⁺ − u⁻ − s|` over the pairs where `s(x)` is given.
fn jump_error(model: &Model<3>, u: &[f64], s: impl Fn(&[f64; 3]) -> Option<[f64; 3]>) -> f64 {
    let f = model.internal_fault.as_ref().unwrap();
    let mut e = 0.0f64;
    for &(mi, pl) in f.pairs() {
        if let Some(s) = s(&model.vertices[mi]) {
            for c in 0..3 {
                e = e.max((u[3 * pl + c] - u[3 * mi + c] - s[c]).abs());
            }
        }
    }
    e
}

#[test]
fn a_fully_prescribed_fault_builds_and_a_simulation_refuses_it_by_name() {
    let model = fully_prescribed(4, 1);
    let pairs = model.internal_fault.as_ref().unwrap().pairs().len();
    assert_eq!(
        pairs,
        3 * 3,
        "the inner 3 × 3 nodes of the 5 × 5 fault grid"
    );
    assert!(model.frictional_boundary.is_empty());
    // The static problem is solved: every pair's jump is the slip (it is a fixed dof).
    let u = model.to_cartesian(&model.initial_displacement).unwrap();
    assert!(jump_error(&model, &u, |_| Some(SLIP)) < 1e-15);
    assert!(u.iter().any(|&x| x.abs() > 1e-4));
    let e = rsf::SimulationBuilder::new(model)
        .friction(rsf::friction::Tresca::new(10.0, 1e9).unwrap())
        .state_law(rsf::simulation::NoState)
        .initial_state(0.0)
        .integrator(rsf::time::Quasistatic::new())
        .time_step(0.5)
        .build()
        .err()
        .expect("a simulation needs a frictional node");
    assert!(matches!(e, Error::NoFrictionalNode { .. }), "{e}");
    assert!(e.to_string().contains("frictional node"), "{e}");
}

/// The prescribed slip gives the displacement the old route gave: the slip as a creep rate
/// (m/s, read as m over 1 s), one pair left to friction because the builder wanted a
/// frictional node, its jump set by hand, the static problem solved by the direct solver
/// with no nonlinearity on the Dirichlet factors (what `okada_anchor` did before). Two
/// different routes to one linear problem: the same displacement to round-off.
#[test]
fn the_prescribed_slip_gives_the_displacement_of_the_creep_rate_route() {
    let new = fully_prescribed(4, 1);
    let probe = [0.0, -0.25, -0.25];
    let at_probe = move |x: &[f64; 3]| (0..3).all(|c| (x[c] - probe[c]).abs() < 1e-9);
    let old = builder(4, 1)
        .internal_creep_at(move |x| (!at_probe(x)).then_some(CreepRate::Cartesian(SLIP)))
        .build()
        .unwrap();
    assert_eq!(old.frictional_boundary.len(), 1);
    let f = old.internal_fault.as_ref().unwrap();
    let mut v = vec![0.0; old.num_dofs()];
    for (&d, &w) in old.dirichlet.dofs.iter().zip(&old.dirichlet.factors) {
        v[d] = w;
    }
    let mut fixed = old.fixed.clone();
    for (k, &(mi, _)) in f.pairs().iter().enumerate() {
        if at_probe(&old.vertices[mi]) {
            let r = f.transform.frames[k];
            for a in 0..2 {
                fixed[3 * mi + a] = true;
                v[3 * mi + a] = (0..3).map(|b| r[b][a] * SLIP[b]).sum();
            }
        }
    }
    let zero = vec![0.0; v.len()];
    DirectSolver::<3>::new(old.stiffness.as_ref(), &fixed, DirectOptions::default())
        .unwrap()
        .solve(&zero, &NoNonlinearity, &mut v)
        .unwrap();
    let (u_old, u_new) = (
        old.to_cartesian(&v).unwrap(),
        new.to_cartesian(&new.initial_displacement).unwrap(),
    );
    let scale = u_new.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let diff = u_old
        .iter()
        .zip(&u_new)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    eprintln!("|u_new − u_old|∞ = {diff:e} of |u|∞ = {scale:e}");
    assert!(scale > 1e-4 && diff <= 1e-10 * scale, "{diff:e}");
}

/// P1 elements reproduce an affine field exactly: held on the whole boundary of the cube
/// and with a slip of 0 at every pair of the fault (an affine field has no jump; a free
/// pair would slip under the field's shear traction), the static solution is the field at
/// every vertex to round-off — the held values reach the equilibrium through
/// `dirichlet_displacement`, and the pairs' data through the mean–jump unknowns.
#[test]
fn an_affine_field_held_on_the_boundary_is_the_static_solution() {
    let field = |x: &[f64; 3]| {
        [
            1e-3 + 2e-4 * x[0] - 1e-4 * x[1] + 3e-4 * x[2],
            -2e-3 + 1e-4 * x[0] + 5e-4 * x[2],
            4e-4 * x[0] - 2e-4 * x[1] + 1e-4 * x[2],
        ]
    };
    let boundary = |x: &[f64; 3]| x.iter().any(|c| (c.abs() - 1.0).abs() < 1e-9);
    let model = ModelBuilder::refined(cuboid([-1.0; 3], [2.0; 3], [5; 3]).unwrap(), 1)
        .unwrap()
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet_displacement(Part::predicate("all", boundary), field)
        .internal_fault_polygon("fault", &plane_x0(0.5, (-0.5, 0.5)))
        .internal_slip_at(|_| Some(PrescribedSlip::InFrame([0.0, 0.0])))
        .build()
        .unwrap();
    assert!(model.frictional_boundary.is_empty());
    let u = model.to_cartesian(&model.initial_displacement).unwrap();
    let e = model.vertices.iter().enumerate().fold(0.0f64, |m, (p, x)| {
        let exact = field(x);
        (0..3).fold(m, |m, c| m.max((u[3 * p + c] - exact[c]).abs()))
    });
    eprintln!("affine field: |u − u_exact|∞ = {e:e}");
    // Round-off of a solve with K's condition (~1e3 here) on a field of 2e-3 m.
    assert!(e < 1e-13, "{e:e}");
}

/// Errors name what was set: a slip without a fault inside the body, a slip that opens the
/// fault, a slip where both sides are held by Dirichlet parts, held displacements in a
/// model of some columns.
#[test]
fn a_slip_or_a_held_displacement_the_model_cannot_take_is_refused_by_name() {
    let block = || {
        ModelBuilder::new(cuboid([-1.0; 3], [2.0; 3], [5; 3]).unwrap())
            .material(Material::new(1e10, 0.25, 2700.0))
            .without_mass()
            .dirichlet(Part::predicate("bottom", |x| x[2] < -1.0 + 1e-9), [0.0; 3])
    };
    let e = block()
        .internal_slip_at(|_| Some(PrescribedSlip::InFrame([1.0, 0.0])))
        .build()
        .unwrap_err();
    assert_eq!(parameter_name(e), "internal_slip");
    let e = builder(4, 0)
        .internal_slip_at(|_| Some(PrescribedSlip::Cartesian([1e-3, 0.0, 0.0])))
        .build()
        .unwrap_err();
    assert!(e.to_string().contains("normal part"), "{e}");
    assert_eq!(parameter_name(e), "internal_slip");
    let e = builder(4, 0)
        .internal_slip_at(|_| Some(PrescribedSlip::InFrame([f64::NAN, 0.0])))
        .build()
        .unwrap_err();
    assert_eq!(parameter_name(e), "internal_slip");
    // A fault through the whole cube: the pairs on the clamped bottom are held.
    let through = ModelBuilder::new(cuboid([-1.0; 3], [2.0; 3], [5; 3]).unwrap())
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(Part::predicate("bottom", |x| x[2] < -1.0 + 1e-9), [0.0; 3])
        .internal_fault_polygon("fault", &plane_x0(1.0, (-1.0, 1.0)))
        .internal_slip_at(|_| Some(PrescribedSlip::rake(1e-3, 90.0)))
        .build()
        .unwrap_err();
    assert!(through.to_string().contains("both sides held"), "{through}");
    let nv = 125;
    let e = block()
        .dirichlet_displacement(Part::predicate("top", |x| x[2] > 1.0 - 1e-9), |_| {
            [1e-3, 0.0, 0.0]
        })
        .frictional_boundary(Part::predicate("side", |x| x[0] < -1.0 + 1e-9))
        .build_columns(&vec![true; nv], |_| Ok(vec![0.0; 3 * nv]))
        .unwrap_err();
    assert_eq!(parameter_name(e), "dirichlet_displacement");
    let e = block()
        .dirichlet_displacement(Part::predicate("top", |x| x[2] > 1.0 - 1e-9), |_| {
            [f64::INFINITY, 0.0, 0.0]
        })
        .frictional_boundary(Part::predicate("side", |x| x[0] < -1.0 + 1e-9))
        .build()
        .unwrap_err();
    assert_eq!(parameter_name(e), "dirichlet");
}

/// The static problem solved again by `StaticSolver`: the direct solver gives the build's
/// `u₀` bit for bit (the same factorisation and solve), multigrid on the hierarchy gives it
/// to its tolerance (relative 1e-10 in the energy norm, measured in `K`'s norm), and a
/// watch reports the solve's progress without changing its iterates.
#[test]
fn the_static_solver_solves_the_builds_problem_again_directly_and_by_multigrid() {
    let model = builder(2, 2)
        .internal_slip_at(|x| Some(PrescribedSlip::rake(1e-3 * (1.0 - x[1] * x[1]), 30.0)))
        .build()
        .unwrap();
    let u0 = &model.initial_displacement;
    let held = |u: &mut Vec<f64>| {
        for (i, (&f, &v)) in model.fixed.iter().zip(u0).enumerate() {
            u[i] = if f { v } else { 0.0 };
        }
    };
    let mut u = vec![0.0; model.num_dofs()];
    held(&mut u);
    let mut direct =
        StaticSolver::new(&model, StaticOptions::method(StaticMethod::Direct)).unwrap();
    assert!(direct.solve(&mut u).unwrap().is_none());
    assert!(u.iter().zip(u0).all(|(a, b)| a.to_bits() == b.to_bits()));

    let stopping = Stopping {
        absolute: 0.0,
        relative: 1e-10,
        max_iterations: 200,
    };
    let solve_mg = |watch: Option<SolveWatch>| {
        let mut options = StaticOptions::method(StaticMethod::Multigrid).with_stopping(stopping);
        options.watch = watch;
        let mut mg = StaticSolver::new(&model, options).unwrap();
        let mut u = vec![0.0; model.num_dofs()];
        held(&mut u);
        let report = mg.solve(&mut u).unwrap().expect("multigrid reports");
        (u, report)
    };
    let (u_mg, report) = solve_mg(None);
    let seen = Arc::new(Mutex::new(Vec::new()));
    let s = seen.clone();
    let (u_watched, _) = solve_mg(Some(
        SolveWatch::new().progress(0.0, move |p| s.lock().unwrap().push(p.iteration)),
    ));
    assert!(u_mg
        .iter()
        .zip(&u_watched)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
    let seen = seen.lock().unwrap().clone();
    eprintln!(
        "multigrid: {} iterations, reports at {seen:?}",
        report.iterations
    );
    assert_eq!(seen, (1..=report.iterations).collect::<Vec<_>>());
    let k_norm = |x: &[f64]| {
        let mut y = vec![0.0; x.len()];
        rsf::fem::spmv_add(model.stiffness.as_ref(), 1.0, x, &mut y);
        x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>().sqrt()
    };
    let diff: Vec<f64> = u_mg.iter().zip(u0).map(|(a, b)| a - b).collect();
    let rel = k_norm(&diff) / k_norm(u0);
    eprintln!("‖u_mg − u_direct‖_K / ‖u_direct‖_K = {rel:e}");
    assert!(rel < 1e-8, "{rel:e}");
}

/// A solve stopped by its watch's time limit is a typed error with the iterations done and
/// the last correction (here after the first iteration: a limit of 0 s), and the
/// iteration cap is one too; neither returns an unconverged displacement.
#[test]
fn multigrid_stops_at_its_time_limit_and_its_iteration_cap_with_a_typed_error() {
    let model = fully_prescribed(2, 2);
    let mut u = model.initial_displacement.clone();
    for (x, &f) in u.iter_mut().zip(&model.fixed) {
        if !f {
            *x = 0.0;
        }
    }
    let options = StaticOptions::method(StaticMethod::Multigrid)
        .with_watch(SolveWatch::new().time_limit(0.0));
    let e = StaticSolver::new(&model, options)
        .unwrap()
        .solve(&mut u.clone())
        .unwrap_err();
    eprintln!("{e}");
    match e {
        Error::Solver(rsf::tnnmg::Error::TimeLimit {
            iterations,
            correction,
            ..
        }) => assert!(iterations == 1 && correction > 0.0),
        e => panic!("{e}"),
    }
    let options = StaticOptions::method(StaticMethod::Multigrid).with_stopping(Stopping {
        absolute: 0.0,
        relative: 1e-14,
        max_iterations: 2,
    });
    let e = StaticSolver::new(&model, options)
        .unwrap()
        .solve(&mut u)
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::Solver(rsf::tnnmg::Error::NotConverged { iterations: 2, .. })
        ),
        "{e}"
    );
    // The builder's equilibrium takes the same options.
    let e = builder(2, 2)
        .internal_slip_at(|_| Some(PrescribedSlip::Cartesian(SLIP)))
        .equilibrium_solver(
            StaticOptions::method(StaticMethod::Multigrid)
                .with_watch(SolveWatch::new().time_limit(0.0)),
        )
        .build()
        .unwrap_err();
    assert!(
        matches!(e, Error::Solver(rsf::tnnmg::Error::TimeLimit { .. })),
        "{e}"
    );
}
