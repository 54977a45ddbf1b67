//! Time per solve of the velocity problem (R_τ) on the paper's slider, levels j = 2..8
//! (issues 4 and 9): TNNMG (default options and the classical one-cycle iteration), linear
//! multigrid solves of the same A (TNNMG's machinery with no nonlinearity, with both option
//! sets), the direct solver (j ≤ 6: its condensation grows too costly beyond) and nonlinear
//! Gauss–Seidel (j ≤ 3), all to the paper's tolerance (1e-10 absolute in the energy norm
//! K + M) from the same warm start.
//!
//! The problem is the one of `crates/rsf/tests/suite/velocity_solvers.rs`: Newmark, τ = 1.5e-3 s,
//! Dieterich–Ruina at steady state α = ln(L/V) for V = 1e-6 m/s, right-hand side from the
//! equilibrium displacement plus a shear prestress whose traction on Γ_F equals the
//! steady-state friction at V, the previous velocity sliding at V, the top at 2e-4 m/s.
//!
//! Before timing, each configuration prints its iteration count, multigrid cycles and
//! set-up time (`setup` lines on stderr), which `docs/tnnmg.md` tabulates next to
//! criterion's times.
//!
//! Times are the CPU time of the benchmarking thread (Linux: `/proc/thread-self/schedstat`,
//! elsewhere wall time), so that the numbers stay meaningful on a machine shared with other
//! jobs: waiting for a core is not counted (cache and memory-bandwidth interference still
//! is). The solvers are single threaded.
//!
//! `cargo bench --bench velocity_solvers` (all) or `... -- tnnmg/6` (a filter); levels can
//! be restricted with `RSF_BENCH_LEVELS=4,8`; `RSF_BENCH_SHAPES=1` adds TNNMG variants
//! (smoothing steps, V/W-cycles, linear correction, cycle budget and reduction).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::measurement::{Measurement, ValueFormatter};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use rsf::direct::{DirectOptions, DirectSolver};
use rsf::fem::SparseMatrix;
use rsf::friction::DieterichRuina;
use rsf::method::FrictionBlocks;
use rsf::nonsmooth::{BlockNonlinearity, NoNonlinearity, NonsmoothSolver, StepSolver, Stopping};
use rsf::tnnmg::{NonlinearGaussSeidel, Tnnmg, TnnmgOptions};
use rsf::Model;
use rsf_scenes::SliderScene;

// The problem's construction, shared with the tests.
#[path = "../crates/rsf/tests/suite/common/velocity.rs"]
mod velocity;
use velocity::{
    newmark_rhs, slider_velocity_problem, steady_shear_strain, tnnmg_on, uniform_friction,
    with_dirichlet_values,
};

/// CPU time of the calling thread, in seconds.
#[derive(Debug, Clone, Copy)]
struct ThreadTime;

impl ThreadTime {
    fn now() -> f64 {
        // First field: time spent on the CPU, in ns (Linux ≥ 2.6.24).
        std::fs::read_to_string("/proc/thread-self/schedstat")
            .ok()
            .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
            .map(|ns| ns * 1e-9)
            .unwrap_or_else(|| {
                static START: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
                START.get_or_init(Instant::now).elapsed().as_secs_f64()
            })
    }
}

impl Measurement for ThreadTime {
    type Intermediate = f64;
    type Value = f64;
    fn start(&self) -> f64 {
        Self::now()
    }
    fn end(&self, start: f64) -> f64 {
        (Self::now() - start) * 1e9
    }
    fn add(&self, a: &f64, b: &f64) -> f64 {
        a + b
    }
    fn zero(&self) -> f64 {
        0.0
    }
    fn to_f64(&self, value: &f64) -> f64 {
        *value
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        &NanosFormatter
    }
}

/// Formats nanoseconds like criterion's wall-time formatter.
struct NanosFormatter;

impl ValueFormatter for NanosFormatter {
    fn scale_values(&self, typical: f64, values: &mut [f64]) -> &'static str {
        let (factor, unit) = if typical < 1e3 {
            (1.0, "ns")
        } else if typical < 1e6 {
            (1e-3, "µs")
        } else if typical < 1e9 {
            (1e-6, "ms")
        } else {
            (1e-9, "s")
        };
        values.iter_mut().for_each(|v| *v *= factor);
        unit
    }
    fn scale_throughputs(
        &self,
        _: f64,
        throughput: &Throughput,
        values: &mut [f64],
    ) -> &'static str {
        let per = match *throughput {
            Throughput::Elements(n) | Throughput::Bytes(n) | Throughput::BytesDecimal(n) => n,
            _ => 1,
        } as f64;
        values.iter_mut().for_each(|v| *v = per * 1e9 / *v);
        "/s"
    }
    fn scale_for_machines(&self, _: &mut [f64]) -> &'static str {
        "ns"
    }
}

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
    let (scene, model, a) = slider_velocity_problem(level);
    let tau = scene.tau();
    let n = model.fixed.len();
    let mut top = vec![false; n];
    for &i in &model.dirichlet.dofs {
        top[i] = true;
    }
    let gamma = steady_shear_strain(&scene, V_SLIDE);
    let mut u = model.initial_displacement.clone();
    let mut v_prev = vec![0.0; n];
    for (p, x) in model.vertices.iter().enumerate() {
        u[2 * p] += gamma * x[1];
        v_prev[2 * p] = if top[2 * p] { V_TOP } else { V_SLIDE };
    }
    let b = newmark_rhs(&model, tau, u, v_prev.clone());
    let v0 = with_dirichlet_values(&model, &top, V_TOP, v_prev);
    let law = DieterichRuina::new(scene.rate_state_params()).expect("law");
    let friction = uniform_friction(&model, law, (scene.l_m / V_SLIDE).ln());
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

/// TNNMG option variants compared with `RSF_BENCH_SHAPES=1` (the choice of the default's
/// smoothing steps, cycle type, cycle budget and inexact-Newton reduction, docs/tnnmg.md).
fn shape_variants() -> Vec<(String, TnnmgOptions)> {
    use rsf::tnnmg::LinearCorrection::{Cycles, PreconditionedCg};
    [
        (PreconditionedCg, (1, 1), 1, 4, 0.05),
        (PreconditionedCg, (2, 2), 1, 2, 0.1),
        (PreconditionedCg, (3, 3), 1, 3, 0.02),
        (PreconditionedCg, (3, 3), 1, 2, 0.1),
        (Cycles, (3, 3), 1, 3, 0.02),
        (PreconditionedCg, (1, 1), 2, 3, 0.02),
        (PreconditionedCg, (2, 2), 2, 3, 0.02),
    ]
    .into_iter()
    .map(|(method, (pre, post), gamma, v_cycles, reduction)| {
        let kind = if method == Cycles { "cycles" } else { "cg" };
        let shape = if gamma == 1 { "V" } else { "W" };
        (
            format!("tnnmg_{kind}_{shape}{pre}{post}_max{v_cycles}_red{reduction}"),
            TnnmgOptions {
                linear_correction: method,
                smoothing: (pre, post),
                cycle_index: gamma,
                v_cycles,
                linear_reduction: Some(reduction),
                ..TnnmgOptions::default()
            },
        )
    })
    .collect()
}

/// For solvers without multigrid cycles.
fn no_cycles<S>(_: &S) -> Option<usize> {
    None
}

/// Prints the iteration count (and `cycles(solver)`) and set-up time, then benchmarks one
/// solve from `v0`.
#[expect(
    clippy::too_many_arguments,
    reason = "a bench helper: the group, the problem and the solver's set-up and probes"
)]
fn bench_solver<S: NonsmoothSolver<2>, N: BlockNonlinearity<2>>(
    c: &mut criterion::BenchmarkGroup<'_, ThreadTime>,
    name: &str,
    level: usize,
    p: &Problem,
    setup: impl FnOnce() -> S,
    cycles: impl Fn(&S) -> Option<usize>,
    nl: &N,
) {
    let n = p.v0.len();
    let t = Instant::now();
    let mut solver = setup();
    let setup_s = t.elapsed().as_secs_f64();
    let mut v = p.v0.clone();
    // The first solve includes the direct solver's condensation (cached afterwards).
    let report = solver.solve(&p.b, nl, &mut v).expect("solve");
    eprintln!(
        "setup {name} j={level} n={n} iterations={} cycles={:?} setup={setup_s:.4}s \
         first_solve_incl_setup={:.4}s",
        report.iterations,
        cycles(&solver),
        t.elapsed().as_secs_f64()
    );
    c.bench_with_input(BenchmarkId::new(name, level), &level, |bch, _| {
        bch.iter(|| {
            v.copy_from_slice(&p.v0);
            black_box(solver.solve(&p.b, nl, &mut v).expect("solve"))
        })
    });
}

/// The levels of `RSF_BENCH_LEVELS` (comma-separated), or `default`.
fn bench_levels(default: std::ops::RangeInclusive<usize>) -> Vec<usize> {
    std::env::var("RSF_BENCH_LEVELS")
        .map(|s| {
            s.split(',')
                .map(|l| l.trim().parse().expect("level"))
                .collect()
        })
        .unwrap_or_else(|_| default.collect())
}

fn velocity_solvers(c: &mut Criterion<ThreadTime>) {
    let mut group = c.benchmark_group("velocity_solvers");
    let levels = bench_levels(2..=8);
    for level in levels {
        let problem = problem(level);
        let p = &problem;
        let tnnmg = |opts: TnnmgOptions| {
            let opts = TnnmgOptions {
                stopping: paper_stopping(),
                ..opts
            };
            move || tnnmg_on(&p.a, &p.model, opts)
        };
        let cycles = |s: &Tnnmg<2>| Some(s.last_solve_cycles());
        for (name, opts) in [
            ("tnnmg", TnnmgOptions::default()),
            ("tnnmg_classical", TnnmgOptions::classical()),
        ] {
            bench_solver(
                &mut group,
                name,
                level,
                p,
                tnnmg(opts.clone()),
                cycles,
                &p.friction,
            );
            let linear = format!("linear_mg{}", name.strip_prefix("tnnmg").unwrap_or(""));
            bench_solver(
                &mut group,
                &linear,
                level,
                p,
                tnnmg(opts),
                cycles,
                &NoNonlinearity,
            );
        }
        if std::env::var_os("RSF_BENCH_SHAPES").is_some() {
            for (name, opts) in shape_variants() {
                bench_solver(
                    &mut group,
                    &name,
                    level,
                    p,
                    tnnmg(opts),
                    cycles,
                    &p.friction,
                );
            }
        }
        if level <= 6 {
            bench_solver(
                &mut group,
                "direct",
                level,
                p,
                || {
                    DirectSolver::<2>::new(p.a.as_ref(), &p.model.fixed, DirectOptions::default())
                        .expect("direct")
                },
                no_cycles,
                &p.friction,
            );
        }
        if level <= 3 {
            bench_solver(
                &mut group,
                "gauss_seidel",
                level,
                p,
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
                no_cycles,
                &p.friction,
            );
        }
    }
    group.finish();
}

/// The direct solver for `a` on the problem's fixed dofs, with the energy norm, condensed
/// onto Γ_F (set-up complete).
fn condensed_direct(p: &Problem, a: &SparseMatrix) -> DirectSolver<2> {
    let mut d = DirectSolver::<2>::new(a.as_ref(), &p.model.fixed, DirectOptions::default())
        .expect("direct")
        .with_energy_norm(p.model.energy_norm.as_ref())
        .expect("energy norm");
    d.prepare(&p.model.frictional_boundary.nodes)
        .expect("condensation");
    d
}

/// Set-up of the direct solver for a new time step (a new rung of the adaptive ladder,
/// issue 10): from scratch, and from the solver of another τ reusing its ordering and
/// symbolic factorisation (`DirectSolver::for_matrix`), for A at 2τ. Both include the
/// condensation onto Γ_F and the harmonic extension of the energy norm. Levels j ≤ 5
/// (`RSF_BENCH_LEVELS` applies). `cargo bench --bench velocity_solvers -- direct_setup`.
fn direct_setup(c: &mut Criterion<ThreadTime>) {
    let mut group = c.benchmark_group("direct_setup");
    let levels = bench_levels(2..=5);
    for level in levels.into_iter().filter(|&l| l <= 5) {
        let p = problem(level);
        let tau = SliderScene::default().end_time_s / 10_000.0;
        let a2 = rsf::fem::combine(
            1.0 / tau,
            p.model.mass.as_ref().expect("mass"),
            tau,
            &p.model.stiffness,
        )
        .expect("A at 2τ");
        let fresh = |a: &SparseMatrix| condensed_direct(&p, a);
        let base = fresh(&p.a);
        let n = p.model.num_dofs() as u64;
        group.throughput(Throughput::Elements(n));
        group.bench_function(BenchmarkId::new("fresh", level), |bch| {
            bch.iter(|| black_box(fresh(&a2)))
        });
        group.bench_function(BenchmarkId::new("reused_analysis", level), |bch| {
            bch.iter(|| black_box(base.for_matrix(a2.as_ref()).expect("for_matrix")))
        });
    }
    group.finish();
}

/// The per-step work of the direct solver outside the condensed problem: the forward
/// sweep of `begin_step` (the condensed right-hand side) and the backward sweep of
/// `finish_step` (the bulk velocity), one pair per iteration. Levels j ≤ 6
/// (`RSF_BENCH_LEVELS` applies). From j = 5 the sweeps use two threads, whose second this
/// measurement does not count: compare kernels with
/// `RAYON_NUM_THREADS=1 cargo bench --bench velocity_solvers -- direct_sweeps`.
fn direct_sweeps(c: &mut Criterion<ThreadTime>) {
    let mut group = c.benchmark_group("direct_sweeps");
    for level in bench_levels(3..=6).into_iter().filter(|&l| l <= 6) {
        let p = problem(level);
        let mut d = condensed_direct(&p, &p.a);
        let mut v = p.v0.clone();
        group.throughput(Throughput::Elements(d.factor_nnz() as u64));
        group.bench_function(BenchmarkId::new("forward_backward", level), |bch| {
            bch.iter(|| {
                d.begin_step(&p.b, &p.v0, &p.model.frictional_boundary.nodes)
                    .expect("begin");
                d.finish_step(&mut v).expect("finish");
                black_box(&v);
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .with_measurement(ThreadTime)
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    targets = velocity_solvers, direct_setup, direct_sweeps
}
criterion_main!(benches);
