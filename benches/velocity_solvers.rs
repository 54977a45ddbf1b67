//! Time per solve of the velocity problem (R_τ) on the paper's slider, levels j = 2..7
//! (issue 4): TNNMG, the direct solver, nonlinear Gauss–Seidel (j ≤ 3) and a plain linear
//! multigrid solve of the same A (TNNMG with no nonlinearity), all to the paper's
//! tolerance (1e-10 absolute in the energy norm K + M) from the same warm start.
//!
//! The problem is the one of `crates/rsf/tests/velocity_solvers.rs`: Newmark, τ = 1.5e-3 s,
//! Dieterich–Ruina at steady state α = ln(L/V) for V = 1e-6 m/s, right-hand side from the
//! equilibrium displacement plus a shear prestress whose traction on Γ_F equals the
//! steady-state friction at V, the previous velocity sliding at V, the top at 2e-4 m/s.
//!
//! Before timing, each configuration prints its iteration count and set-up time
//! (`setup` lines on stderr), which `docs/tnnmg.md` tabulates next to criterion's times.
//!
//! `cargo bench --bench velocity_solvers` (all) or `... -- tnnmg/6` (a filter).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use rsf::fem::SparseMatrix;
use rsf::friction::DieterichRuina;
use rsf::time::{Kinematics, Newmark, VelocityIntegrator};
use rsf::tnnmg::{
    BlockNonlinearity, DirectOptions, DirectSolver, NoNonlinearity, NonlinearGaussSeidel,
    NonsmoothSolver, Stopping, Tnnmg, TnnmgOptions,
};
use rsf::{FrictionBlocks, Model, SliderScene};

const V_TOP: f64 = 2e-4;
const V_SLIDE: f64 = 1e-6;

struct Problem {
    model: Model<2>,
    a: SparseMatrix,
    b: Vec<f64>,
    v0: Vec<f64>,
    friction: FrictionBlocks<DieterichRuina>,
}

fn problem(level: usize) -> Problem {
    let scene = SliderScene {
        level,
        steps: 10_000,
        ..SliderScene::default()
    };
    let tau = scene.tau();
    let model = scene.build_model().expect("slider model");
    let a = rsf::fem::combine(
        2.0 / tau,
        model.mass.as_ref().expect("mass"),
        tau / 2.0,
        &model.stiffness,
    )
    .expect("A");
    let n = model.fixed.len();
    let mut top = vec![false; n];
    for &i in &model.dirichlet.dofs {
        top[i] = true;
    }
    let params = scene.rate_state_params();
    let g = scene.youngs_modulus_pa / (2.0 * (1.0 + scene.poisson_ratio));
    let gamma = params.steady_state_friction(V_SLIDE) * scene.sigma_n_pa / g;
    let mut u = model.initial_displacement.clone();
    let mut v_prev = vec![0.0; n];
    for (p, x) in model.vertices.iter().enumerate() {
        u[2 * p] += gamma * x[1];
        v_prev[2 * p] = if top[2 * p] { V_TOP } else { V_SLIDE };
    }
    let kin = Kinematics {
        u,
        v: v_prev.clone(),
        a: vec![0.0; n],
    };
    let mut b = vec![0.0; n];
    Newmark
        .right_hand_side(
            tau,
            model.mass.as_ref(),
            &model.stiffness,
            &model.load,
            &kin,
            &mut b,
        )
        .expect("rhs");
    let mut v0 = v_prev;
    for (i, &f) in model.fixed.iter().enumerate() {
        if f {
            v0[i] = if top[i] && i % 2 == 0 { V_TOP } else { 0.0 };
        }
    }
    let nf = model.frictional.nodes.len();
    let law = DieterichRuina::new(params).expect("law");
    let friction = FrictionBlocks::new(
        model.frictional.nodes.clone(),
        model.frictional.weights.clone(),
        vec![law; nf],
        &vec![(scene.l_m / V_SLIDE).ln(); nf],
    );
    Problem {
        model,
        a,
        b,
        v0,
        friction,
    }
}

fn paper_stopping() -> Stopping {
    Stopping {
        absolute: 1e-10,
        relative: 0.0,
        max_iterations: 1000,
    }
}

/// Prints the iteration count and set-up time, then benchmarks one solve from `v0`.
fn bench_solver<S: NonsmoothSolver<2>, N: BlockNonlinearity<2>>(
    c: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    level: usize,
    p: &Problem,
    setup: impl FnOnce() -> S,
    nl: &N,
) {
    let n = p.v0.len();
    let t = Instant::now();
    let mut solver = setup();
    let mut v = p.v0.clone();
    // The first solve includes the direct solver's condensation (cached afterwards).
    let report = solver.solve(&p.b, nl, &mut v).expect("solve");
    eprintln!(
        "setup {name} j={level} n={n} iterations={} first_solve_incl_setup={:.4}s",
        report.iterations,
        t.elapsed().as_secs_f64()
    );
    c.bench_with_input(BenchmarkId::new(name, level), &level, |bch, _| {
        bch.iter(|| {
            v.copy_from_slice(&p.v0);
            black_box(solver.solve(&p.b, nl, &mut v).expect("solve"))
        })
    });
}

fn velocity_solvers(c: &mut Criterion) {
    let mut group = c.benchmark_group("velocity_solvers");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    for level in 2..=7 {
        let p = problem(level);
        let tn_opts = TnnmgOptions {
            stopping: paper_stopping(),
            ..TnnmgOptions::default()
        };
        let tnnmg = || {
            Tnnmg::<2>::new(
                p.a.as_ref(),
                &p.model.fixed,
                &p.model.prolongations,
                Some(p.model.energy_norm.as_ref()),
                tn_opts.clone(),
            )
            .expect("tnnmg")
        };
        bench_solver(&mut group, "tnnmg", level, &p, tnnmg, &p.friction);
        bench_solver(&mut group, "linear_mg", level, &p, tnnmg, &NoNonlinearity);
        bench_solver(
            &mut group,
            "direct",
            level,
            &p,
            || {
                DirectSolver::<2>::new(p.a.as_ref(), &p.model.fixed, DirectOptions::default())
                    .expect("direct")
            },
            &p.friction,
        );
        if level <= 3 {
            bench_solver(
                &mut group,
                "gauss_seidel",
                level,
                &p,
                || {
                    NonlinearGaussSeidel::<2>::new(
                        p.a.as_ref(),
                        &p.model.fixed,
                        Some(p.model.energy_norm.as_ref()),
                        Stopping {
                            max_iterations: 1_000_000,
                            ..paper_stopping()
                        },
                        false,
                    )
                    .expect("gauss-seidel")
                },
                &p.friction,
            );
        }
    }
    group.finish();
}

criterion_group!(benches, velocity_solvers);
criterion_main!(benches);
