//! Work–precision study of the paper's slider scene (issue 6, first half): error against
//! wall time for the time step, the mesh, the solver tolerances, and TNNMG against the
//! direct solver at every point. Interpretation: `docs/work-precision.md`.
//!
//! ```text
//! cargo build --release --example work_precision
//! target/release/examples/work_precision                      # all studies, ≲ 15 min
//! target/release/examples/work_precision --study time         # one study: time|mesh|tol|energy
//! target/release/examples/work_precision --study time --big    # adds N = 1e6 (reference 2e6)
//! target/release/examples/work_precision --study adaptive     # adaptive τ against uniform N
//! target/release/examples/work_precision --study integrators --runs DIR  # the fault ODE's
//!     # integrators from seas_bp1/seas_bp5 run folders DIR/PROBLEM_INTEGRATOR_TOL
//! target/release/examples/work_precision --study mesh --big    # adds j = 6 (reference)
//! perf record -o /tmp/perf.data target/release/examples/work_precision --study profile \
//!     --level 3 --steps 10000 [--solver direct]                # one run to 0.6 T, phases
//! ```
//!
//! Flags: `--out DIR` (CSV, default `docs/work-precision`), `--figures DIR` (PNG, default
//! `docs/figures`), `--level j` (time and tolerance studies, default 2), `--ref-n N`
//! (time-step reference, default 2e5), `--mesh-steps N` (τ = T/N of the mesh study, default
//! 2000), `--energy-steps N` (steps per period of the frictionless study, default 400),
//! `--integrator newmark|backward-euler` and `--solver tnnmg|direct` (restrict the time-step
//! study; both by default; `--solver` also picks the solver of `--study profile`);
//! adaptive study: `--tolerances`, `--uniform` (comma-separated lists) or, by default, the
//! preferred numbers `--per-decade 6|12|24` (default 24) from 2.4e-2 to 1e-5 and from
//! N = 1e3 to 1e5.
//!
//! Quantities (the first slip event is at ≈ 10.1 s = 0.67 T at j = 2):
//! - (a) the displacement increment `Δu = u_x(x0, t_a) − u_x(x0, 0)` at `t_a = 0.6 T = 9 s`,
//!   relative to the reference's (`u_x(x0, 0)`, the gravity equilibrium, is 0 in the
//!   continuum by symmetry; its O(h) discrete value would swamp a mesh comparison);
//! - (b) the time `t_s` of the first slip event (max slip rate on Γ_F first above 1e-3 m/s,
//!   crossing interpolated linearly in log slip rate between steps), relative to the
//!   reference's `t_s`;
//! - (c) the slip-rate history at x0 over the loading phase: the RMS over the steps in
//!   `[T/4, 0.6 T]` of `ln |v_x(x0)| − ln |v_x^ref(x0)|` (reference interpolated linearly
//!   in time, in ln V), i.e. a mean relative error of the slip rate;
//! - (e) frictionless shear mode (mesh study only): Γ_F clamped, roller sides, top fixed,
//!   no gravity, initial velocity `A ω sin(π y) e_x`: exact solution
//!   `u = A sin(π y) sin(ω t) e_x`, `ω = π √(μ/ρ)`; error of `(u_h, v_h)` against the
//!   nodal interpolant of the exact solution after 1.25 periods, in the discrete energy norm
//!   `(eᵀ K e + ėᵀ M ė)^{1/2}`, relative to the exact energy norm.

// The studies live in `examples/work_precision/`; this file stays the program, one of
// the `examples/*.rs` that `tests/careless_inputs.rs` lists.
#[path = "work_precision/common.rs"]
mod common;
#[path = "work_precision/errors.rs"]
mod errors;
#[path = "work_precision/integrators.rs"]
mod integrators;
#[path = "work_precision/mesh.rs"]
mod mesh;
#[path = "work_precision/plot.rs"]
mod plot;
#[path = "work_precision/time.rs"]
mod time;
#[path = "work_precision/tolerance.rs"]
mod tolerance;
#[path = "work_precision/trace.rs"]
mod trace;

use std::path::PathBuf;

use clap::{Parser, ValueEnum};
use rsf::{Integrator, SolverKind};
use rsf_programs::cli::step_count;
use rsf_programs::estimates::{slider_memory, FIGURE_BYTES, RECORDED_STEP_BYTES};
use rsf_programs::guard::{in_range, AnyError, Folder, Limits, Plan, Prepared, Program};
use rsf_programs::machine;
use rsf_scenes::SliderScene;

use common::{base, elapsed, log, window, Ctx, Res};
use mesh::{energy_study, mesh_study};
use time::{adaptive_study, time_study};
use tolerance::tol_study;
use trace::trace;

/// Which study to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Study {
    /// Time, tolerance and mesh studies.
    All,
    /// Error against τ.
    Time,
    /// Error against the refinement level.
    Mesh,
    /// Error against the solver tolerance.
    Tol,
    /// Energy-norm error of an elastic oscillation.
    Energy,
    /// Adaptive time steps against uniform N (Newmark, direct solver), same reference.
    Adaptive,
    /// One run for `perf record`.
    Profile,
    /// The fault ODE's integrators (issue 84): reads the `seas_bp1`/`seas_bp5` run folders
    /// under `--runs` (named `PROBLEM_INTEGRATOR_TOLERANCE`), writes `integrators.csv` and
    /// its figure.
    Integrators,
}

/// Work–precision studies of the slider (docs/work-precision.md).
#[derive(Parser)]
#[command(version)]
struct Cli {
    /// The study.
    #[arg(long, value_enum, default_value = "all")]
    study: Study,
    /// Steps of the profile run (`1e4` accepted).
    #[arg(long, value_parser = step_count, default_value = "10000")]
    steps: usize,
    /// Only this solver (default: both).
    #[arg(long, value_enum)]
    solver: Option<SolverKind>,
    /// Only this integrator in the time study (default: Newmark and backward Euler).
    #[arg(long, value_enum)]
    integrator: Option<Integrator>,
    /// Include the large cases.
    #[arg(long)]
    big: bool,
    /// The folder of the run folders of `--study integrators`.
    #[arg(long, default_value = "out/integrators")]
    runs: PathBuf,
    /// Output folder of the tables.
    #[arg(long, default_value = "docs/work-precision")]
    out: PathBuf,
    /// Output folder of the figures.
    #[arg(long, default_value = "docs/figures")]
    figures: PathBuf,
    /// Refinement level of the time and tolerance studies.
    #[arg(long, default_value_t = 2)]
    level: usize,
    /// Steps of the reference run.
    #[arg(long, value_parser = step_count, default_value = "200000")]
    ref_n: usize,
    /// Steps of the mesh study.
    #[arg(long, value_parser = step_count, default_value = "2000")]
    mesh_steps: usize,
    /// Steps of the energy study.
    #[arg(long, value_parser = step_count, default_value = "400")]
    energy_steps: usize,
    /// Tolerances of the adaptive study (default: the E-series of `--per-decade` from
    /// 2.4e-2 down to 1e-5).
    #[arg(long, value_delimiter = ',')]
    tolerances: Option<Vec<f64>>,
    /// Uniform step counts of the adaptive study (default: the E-series of `--per-decade`
    /// from 1e3 to 1e5).
    #[arg(long, value_delimiter = ',', value_parser = step_count)]
    uniform: Option<Vec<usize>>,
    /// Values per decade of the adaptive study's default grids: the preferred numbers
    /// E6, E12 or E24 (IEC 60063). The cheapest setting that reaches an error level is
    /// only found to within one grid step, and the cost of uniform steps is not monotone
    /// in N (the fixed point iterations per step vary), so the grids must be fine.
    #[arg(long, default_value = "24", value_parser = clap::builder::PossibleValuesParser::new(["6", "12", "24"]))]
    per_decade: String,
    /// State update of the time and adaptive studies' runs (the reference keeps backward
    /// Euler).
    #[arg(long, value_enum, default_value = "backward-euler")]
    state_integrator: rsf::method::StateIntegrator,
    /// Replace the files of an earlier run in `--out` and `--figures` (without it, a
    /// folder holding any rsf program's run is refused and left untouched).
    #[arg(long)]
    overwrite: bool,
    #[command(flatten)]
    limits: Limits,
}

impl Program for Cli {
    rsf_programs::name_and_limits!("work_precision");

    fn plan(&self) -> Result<Plan, AnyError> {
        if let Some(u) = &self.uniform {
            rsf_programs::guard::distinct("--uniform", u)?;
        }
        if let Some(t) = &self.tolerances {
            rsf_programs::guard::distinct("--tolerances", t)?;
            for &tol in t {
                in_range(
                    "--tolerances",
                    tol,
                    (f64::EPSILON * 2.0, 0.5),
                    "relative tolerances",
                )?;
            }
        }
        let study = self.study;
        let has = |s: &[Study]| s.contains(&study);
        // The tables (in `--out`) and figures (in `--figures`) of the studies this run
        // makes: each study's `--study` values, its name, whether it draws a figure
        // (`work_precision_{name}.png`).
        let studies: [(&[Study], &str, bool); 6] = [
            (&[Study::All, Study::Time], "time_step", true),
            (&[Study::All, Study::Tol], "tolerance", true),
            (&[Study::Adaptive], "adaptive", true),
            (&[Study::All, Study::Mesh], "mesh", true),
            (&[Study::Energy], "energy", false),
            (&[Study::Integrators], "integrators", true),
        ];
        let mut csv = Vec::new();
        let mut png = Vec::new();
        for (values, name, figure) in studies {
            if has(values) {
                csv.push(format!("{name}.csv"));
                if figure {
                    png.push(format!("work_precision_{name}.png"));
                }
            }
        }
        let csv: Vec<&str> = csv.iter().map(String::as_str).collect();
        let png: Vec<&str> = png.iter().map(String::as_str).collect();
        // The finest level any run takes (the mesh study's reference: j = 5, or 6 with
        // --big) and the longest run's every step in memory (the reference at --ref-n,
        // the profile run at --steps).
        let mesh = has(&[Study::All, Study::Mesh, Study::Energy]);
        let level = self
            .level
            .max(if mesh { 5 + usize::from(self.big) } else { 0 });
        let steps = self
            .ref_n
            .max(self.steps)
            .max(self.mesh_steps)
            .max(self.energy_steps) as f64
            * if self.big { 10.0 } else { 1.0 };
        let scene = SliderScene {
            level,
            ..SliderScene::default()
        };
        let memory = slider_memory(&scene) + steps * RECORDED_STEP_BYTES;
        Ok(Plan::new()
            .memory(
                memory,
                "--level, --ref-n, --steps, --mesh-steps, --energy-steps",
                format!("runs up to level {level} and {steps:.3e} steps"),
            )
            .output(
                (csv.len() as f64) * 1e6 + png.len() as f64 * FIGURE_BYTES,
                "--study",
                "the studies' tables and figures",
            )
            .folder(Folder::new("--out", &self.out, &csv).overwrite(self.overwrite))
            .folder(Folder::new("--figures", &self.figures, &png).overwrite(self.overwrite)))
    }
}

/// The preferred numbers of the E6, E12 or E24 series (IEC 60063) in `[lo, hi]`,
/// increasing (`per_decade` is 6, 12 or 24).
fn preferred_numbers(lo: f64, hi: f64, per_decade: usize) -> Vec<f64> {
    const E24: [f64; 24] = [
        1.0, 1.1, 1.2, 1.3, 1.5, 1.6, 1.8, 2.0, 2.2, 2.4, 2.7, 3.0, 3.3, 3.6, 3.9, 4.3, 4.7, 5.1,
        5.6, 6.2, 6.8, 7.5, 8.2, 9.1,
    ];
    let stride = 24 / per_decade;
    let mut out = Vec::new();
    for decade in (lo.log10().floor() as i32)..=(hi.log10().ceil() as i32) {
        for m in E24.iter().step_by(stride) {
            // Two significant digits: round away the binary noise of m · 10^decade.
            let x = format!("{m}e{decade}").parse::<f64>().expect("a number");
            if x >= lo * (1.0 - 1e-12) && x <= hi * (1.0 + 1e-12) {
                out.push(x);
            }
        }
    }
    out
}

fn main() -> std::process::ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, _folders: Prepared) -> Res<()> {
    let c = Ctx {
        out: cli.out,
        figures: cli.figures,
        level: cli.level,
        big: cli.big,
        ref_n: cli.ref_n,
        mesh_steps: cli.mesh_steps,
        energy_steps: cli.energy_steps,
        integrators: match cli.integrator {
            Some(i) => vec![i],
            None => vec![Integrator::Newmark, Integrator::BackwardEuler],
        },
        solvers: match cli.solver {
            Some(s) => vec![s],
            None => vec![SolverKind::Tnnmg, SolverKind::Direct],
        },
        tolerances: cli.tolerances.unwrap_or_else(|| {
            let per_decade = cli.per_decade.parse().expect("checked by clap");
            let mut t = preferred_numbers(1e-5, 2.4e-2, per_decade);
            t.reverse();
            t
        }),
        uniform: cli.uniform.unwrap_or_else(|| {
            let per_decade = cli.per_decade.parse().expect("checked by clap");
            preferred_numbers(1e3, 1e5, per_decade)
                .into_iter()
                .map(|n| n.round() as usize)
                .collect()
        }),
        state_integrator: cli.state_integrator,
    };
    let study = cli.study;
    elapsed();
    log(&format!("machine: {}", machine()));
    if study == Study::Profile {
        // One run for `perf record`: phases setup / step / record by Instant.
        let mut s = base(c.level, cli.steps);
        if let Some(solver) = cli.solver {
            s.solver = solver;
        }
        let (tmin, tmax) = window(&s);
        let tr = trace(&s, tmin, tmax, false)?;
        log(&format!(
            "profile j = {} N = {} {}: setup {:.3} s, stepping {:.3} s, recording {:.4} s, \
             {} steps, {:.2} FPI/step, {:.2} solver its/FPI, cpu {:.2} s",
            s.level,
            s.steps,
            s.solver.name(),
            tr.setup_s,
            tr.step_s,
            tr.record_s,
            tr.steps(),
            tr.fpi as f64 / tr.steps() as f64,
            tr.solver_its as f64 / tr.fpi.max(1) as f64,
            tr.cpu_s
        ));
    }
    if matches!(study, Study::All | Study::Time) {
        time_study(&c)?;
    }
    if matches!(study, Study::All | Study::Tol) {
        tol_study(&c)?;
    }
    if study == Study::Adaptive {
        adaptive_study(&c)?;
    }
    if study == Study::Integrators {
        integrators::integrator_study(&cli.runs, &c.out, &c.figures)?;
    }
    if matches!(study, Study::All | Study::Mesh) {
        mesh_study(&c)?;
    } else if study == Study::Energy {
        let lines = energy_study(&c)?;
        for (l, p) in lines {
            log(&format!("{l}: {p:?}"));
        }
    }
    log("done");
    Ok(())
}
