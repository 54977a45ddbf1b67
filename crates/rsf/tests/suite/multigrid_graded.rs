//! Multigrid on graded meshes (issue 70, item 6; docs/tnnmg.md "Multigrid on graded
//! meshes"): a bisection mesh graded from a fault in every direction as a multigrid
//! hierarchy (`BisectionMesh::hierarchy`, levels by the size clamped at `root/2^ℓ`,
//! `ModelBuilder::from_hierarchy`) — the static problem of a prescribed slip solved by
//! TNNMG without nonlinearity in a number of iterations that does not grow with the levels
//! or the grading; on a tensor grid of anisotropic boxes (the same refinement, cells 20
//! times longer along the fault than across it) the same solver stalls.
use crate::common::plane_x0;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use rsf::fem::{cuboid_from_coordinates, BisectionMesh, MeshHierarchy};
use rsf::model::PrescribedSlip;
use rsf::nonsmooth::{NoNonlinearity, NonsmoothSolver, SolveWatch, Stopping};
use rsf::tnnmg::{Tnnmg, TnnmgOptions};
use rsf::{Material, Model, ModelBuilder, Part};

/// The relative energy-norm correction at which the solves stop.
const TOLERANCE: f64 = 1e-8;

/// The distance between the boxes `[lo, hi]` and `[a, b]` (0 where they meet).
fn box_distance((lo, hi): ([f64; 3], [f64; 3]), (a, b): ([f64; 3], [f64; 3])) -> f64 {
    (0..3)
        .map(|i| (a[i] - hi[i]).max(lo[i] - b[i]).max(0.0))
        .fold(0.0f64, f64::hypot)
}

/// The model on `hierarchy` of the box `[-half, half]³` with every face clamped and the
/// square `|y|, |z| ≤ patch` of the plane `x = 0` slipping 1 m along `y` at every pair.
fn model(hierarchy: MeshHierarchy<3>, half: [f64; 3], patch: f64) -> Model<3> {
    let tol = 1e-9 * half[0];
    ModelBuilder::from_hierarchy(hierarchy)
        .material(Material::new(7.5e10, 0.25, 2700.0))
        .without_mass()
        .without_initial_equilibrium()
        .dirichlet(
            Part::predicate("faces", move |x| (0..3).any(|i| x[i].abs() > half[i] - tol)),
            [0.0; 3],
        )
        .fault_tangent([0.0, 1.0, 0.0])
        .internal_fault_polygon("fault", &plane_x0(patch, (-patch, patch)))
        .internal_slip_at(|_| Some(PrescribedSlip::InFrame([1.0, 0.0])))
        .build()
        .unwrap()
}

/// The bisection hierarchy of the box `[-4 root, 4 root]³` (root 8 m), graded from the
/// patch `|y|, |z| ≤ 8` of `x = 0`: cells `h = root/2^levels` there, `h + g d` at the
/// distance `d`.
fn graded(levels: usize, g: f64) -> (MeshHierarchy<3>, [f64; 3], f64) {
    let root = 8.0;
    let half = 4.0 * root;
    let patch = root;
    let h = root / 2f64.powi(levels as i32);
    let region = ([0.0, -patch, -patch], [0.0, patch, patch]);
    let b = BisectionMesh::kuhn_box([-half; 3], [half; 3], root).unwrap();
    let hierarchy = b
        .hierarchy(
            |lo, hi| h + g * box_distance((lo, hi), region),
            levels,
            20_000_000,
        )
        .unwrap();
    (hierarchy, [half; 3], patch)
}

/// The tensor grid of boxes `1 × a × a` (m; `a` the aspect), 16 × 8 × 8 of them on the
/// coarsest level, refined `levels` times (red refinement), the patch half the box.
fn tensor(levels: usize, aspect: f64) -> (MeshHierarchy<3>, [f64; 3], f64) {
    let lines = |n: usize, d: f64| -> Vec<f64> {
        (0..=n).map(|i| (i as f64 - n as f64 / 2.0) * d).collect()
    };
    let (xs, ys) = (lines(16, 1.0), lines(8, aspect));
    let coarse = cuboid_from_coordinates(&xs, &ys, &ys).unwrap();
    let half = [8.0, 4.0 * aspect, 4.0 * aspect];
    (
        MeshHierarchy::refine_uniformly(coarse, levels),
        half,
        2.0 * aspect,
    )
}

/// What one multigrid solve took.
struct Solve {
    dofs: usize,
    iterations: usize,
    cycles: usize,
    /// The mean reduction of the correction per iteration (geometric, after the first).
    rate: f64,
    seconds: f64,
    converged: bool,
}

/// The model's static problem by TNNMG without nonlinearity on its hierarchy, from the
/// held values (0 elsewhere), to [`TOLERANCE`], at most `cap` iterations; every
/// iteration's correction read by a `SolveWatch`.
fn solve(model: &Model<3>, options: TnnmgOptions, cap: usize) -> Solve {
    let options = TnnmgOptions {
        stopping: Stopping {
            absolute: 0.0,
            relative: TOLERANCE,
            max_iterations: cap,
        },
        ..options
    };
    let t = Instant::now();
    let corrections = Arc::new(Mutex::new(Vec::new()));
    let seen = corrections.clone();
    let mut mg = Tnnmg::<3>::new(
        model.stiffness.as_ref(),
        &model.fixed,
        &model.prolongations,
        None,
        options,
    )
    .unwrap()
    .with_watch(SolveWatch::new().progress(0.0, move |p| seen.lock().unwrap().push(p.correction)));
    let mut v = model.initial_displacement.clone();
    let zero = vec![0.0; v.len()];
    let converged = match mg.solve(&zero, &NoNonlinearity, &mut v) {
        Ok(_) => true,
        Err(rsf::tnnmg::Error::NotConverged { .. }) => false,
        Err(e) => panic!("{e}"),
    };
    let c = corrections.lock().unwrap().clone();
    let k = c.len();
    let rate = if k > 2 {
        (c[k - 1] / c[1]).powf(1.0 / (k - 2) as f64)
    } else {
        0.0
    };
    Solve {
        dofs: model.num_dofs(),
        iterations: k,
        cycles: mg.last_solve_cycles(),
        rate,
        seconds: t.elapsed().as_secs_f64(),
        converged,
    }
}

fn row(name: &str, levels: usize, s: &Solve) {
    eprintln!(
        "| {name} | {levels} | {} | {}{} | {} | {:.3} | {:.1} |",
        s.dofs,
        s.iterations,
        if s.converged { "" } else { " (cap)" },
        s.cycles,
        s.rate,
        s.seconds
    );
}

/// The test: on bisection hierarchies of 1, 2 and 3 levels graded at `g = 0.5`, TNNMG's
/// default iteration (a Gauss–Seidel sweep, conjugate gradients preconditioned by up to
/// four V(2,2)-cycles) reaches the tolerance in a number of iterations that does not grow
/// with the levels (at most two more than on one level: a rate independent of `h`), while
/// on the tensor grid of `1 × 20 × 20` boxes refined once the same solver needs at least
/// three times the iterations of the cubes' grid (aspect 1) of the same size, or does not
/// converge in 100.
#[test]
fn multigrid_on_a_graded_bisection_hierarchy_converges_at_a_rate_independent_of_the_levels() {
    eprintln!("| mesh | levels | dofs | iterations | V-cycles | rate | s |");
    eprintln!("|---|---|---|---|---|---|---|");
    let mut iterations = Vec::new();
    for levels in 1..=3 {
        let (h, half, patch) = graded(levels, 0.5);
        let s = solve(&model(h, half, patch), TnnmgOptions::default(), 200);
        row("bisection, g = 0.5", levels, &s);
        assert!(s.converged);
        iterations.push(s.iterations);
    }
    assert!(
        iterations[2] <= iterations[0] + 2,
        "iterations grow with the levels: {iterations:?}"
    );
    let on_tensor = |aspect: f64| {
        let (h, half, patch) = tensor(1, aspect);
        solve(&model(h, half, patch), TnnmgOptions::default(), 100)
    };
    let (cubes, long) = (on_tensor(1.0), on_tensor(20.0));
    row("tensor, aspect 1", 1, &cubes);
    row("tensor, aspect 20", 1, &long);
    assert!(cubes.converged);
    assert!(
        !long.converged || long.iterations >= 3 * cubes.iterations,
        "the anisotropic grid did not slow multigrid down: {} against {} iterations",
        long.iterations,
        cubes.iterations
    );
}

/// The table of docs/tnnmg.md "Multigrid on graded meshes": bisection hierarchies of 1 to
/// 5 levels at gradings 0.25, 0.5 and 1, the default iteration and the classical one (one
/// V(3,3)-cycle per iteration); the tensor grids of aspect 1, 5 and 20 refined 1 to 3
/// times. `cargo test -p rsf --test suite multigrid_graded::study -- --ignored --nocapture`
#[test]
#[ignore = "a measurement (minutes): the table of docs/tnnmg.md"]
fn study_of_multigrid_on_graded_meshes() {
    eprintln!("| mesh | levels | dofs | iterations | V-cycles | rate | s |");
    eprintln!("|---|---|---|---|---|---|---|");
    // The rows of one hierarchy `(h, half, patch)`: the default iteration's, and with
    // `classical` the classical one's too.
    let rows = |mesh: &str, levels, (h, half, patch), classical: bool| {
        let m = model(h, half, patch);
        row(mesh, levels, &solve(&m, TnnmgOptions::default(), 500));
        if classical {
            let name = format!("{mesh}, classical");
            row(&name, levels, &solve(&m, TnnmgOptions::classical(), 500));
        }
    };
    for g in [0.25, 0.5, 1.0] {
        for levels in 1..=5 {
            let mesh = format!("bisection, g = {g}");
            rows(&mesh, levels, graded(levels, g), true);
        }
    }
    for aspect in [1.0, 5.0, 20.0] {
        for levels in 1..=3 {
            let mesh = format!("tensor, aspect {aspect}");
            rows(&mesh, levels, tensor(levels, aspect), false);
        }
    }
}
