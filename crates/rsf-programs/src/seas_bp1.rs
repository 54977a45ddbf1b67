//! The SCEC SEAS benchmark BP1-QD (Erickson et al. 2020; docs/seas-bp1.md): a vertical
//! strike-slip fault in an antiplane half-space, regularised rate-and-state friction with
//! the aging law, radiation damping, 3000 years of earthquake cycles — through the
//! library's scalar (antiplane) model, antisymmetric fault and adaptive steps.
//!
//! ```text
//! cargo run --release --example seas_bp1 -- --out out/seas_bp1
//! cargo run --release --example seas_bp1 -- --out out/bp1_coarse --dz 200 --end-years 600
//! ```
//! Flags: `--out DIR` (required; refuses a folder with files of another run unless
//! `--overwrite`), `--end-years Y` (default 3000), `--dz M` (element size on the fault,
//! default 25), `--domain-km L` (default 400), `--ratio R` (mesh growth away from the
//! fault, default 1.05), `--tolerance E` (adaptive steps, default 1e-3), `--state-change-cap`
//! (ξ, default 0.5; 0 for none), `--fixed-point-tolerance` (default 1e-10), `--inertia`
//! (Newmark, fully dynamic, no radiation damping: BP1-FD; its defaults the converged
//! set-up of docs/seas-bp1-fd.md: `--absorbing all --switch-to-dynamic 1e-2
//! --switch-to-quasi-dynamic 1e-3`), `--absorbing none|dynamic|all` (absorbing far
//! boundaries with `--inertia`, default `all`; docs/seas-bp1-fd.md),
//! `--dynamic-integrator newmark|backward-euler`,
//! `--every-step` (a station row
//! at every step instead of the benchmark's thinning), `--setup-per-time-step` (one solver
//! set-up per step size, for comparison), `--scheme runge-kutta|implicit` (default
//! `runge-kutta`: the quasi-dynamic equations condensed onto the fault and integrated by
//! the Dormand–Prince 5(4) pair; `implicit`: the paper's scheme), `--rk-tolerance`
//! (default 1e-6), `--checkpoint-every N` (a checkpoint `checkpoint.bin` every N steps,
//! with the benchmark files' resume log `seas_resume.csv`), `--resume FILE` (continues the
//! files in `--out` from a checkpoint of this run: fingerprint, checkpoint and every file's
//! rows are checked before anything is cut, and the continued files are byte-identical to
//! an uninterrupted run's, with either scheme and with `--inertia`; docs/reliability.md),
//! `--allow-change FIELD,…` (a deliberate change on resume, e.g. `end_years`), `--max-steps
//! N` (stop after step N in total, across resumes, with a checkpoint and the resume log to
//! continue from with a larger N), `--kernel hierarchical|dense` (how the Runge–Kutta run
//! stores the operator condensed onto the fault: as an ℋ-matrix, the default, or dense;
//! part of the fingerprint, so a checkpoint of the other kernel is refused on `--resume`),
//! `--kernel-epsilon E` (the ℋ-matrix's accuracy; default the `--rk-tolerance`,
//! `FaultKernel::matching`), `--threads N` (threads of each evaluation: the product with
//! the operator and the per-node friction solves; default every core of the machine; the
//! same bits for every N).
//!
//! Writes the benchmark's files (`fltst_dp000` … `fltst_dp350`, `devol.dat`), `events.csv`,
//! `summary.json` and `overview.png` (maximum slip rate against time, slip profiles).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use crate::cli::for_flag;
use crate::estimates::seas_output_bytes;
use crate::guard::{
    flag, in_range, number, AnyError, Folder, Limits, Plan, Prepared, Processes, Program,
};
use crate::{cpu_seconds, machine};
use clap::Parser;
use rsf::fault_ode::FaultOdeOptions;
use rsf::method::{FixedPointOptions, SolverOptions};
use rsf::observe::{FileMode, Progress, TimeUnit};
use rsf::run_folder::read_checkpoint;
use rsf::run_folder::{step_cap_error, until, RunFolder};
use rsf::{MethodKind, Observer};
use rsf_scenes::{SeasBp1, SeasBp1Far, SeasBp1Grid, SEAS_BP1_STATION_DEPTHS};
use rsf_seas::{SeasOutput, SeasSampling, SeasSetup, SECONDS_PER_YEAR};

#[derive(Parser, Debug)]
#[command(about = "SCEC SEAS benchmark BP1-QD (antiplane, 3000 years)")]
pub struct Args {
    /// Output folder.
    #[arg(long)]
    out: PathBuf,
    /// Replace the files of an earlier run in the output folder.
    #[arg(long)]
    overwrite: bool,
    /// Simulated time (years).
    #[arg(long, default_value_t = 3000.0)]
    end_years: f64,
    /// Element size on the fault (m).
    #[arg(long, default_value_t = 25.0)]
    dz: f64,
    /// Side of the square domain (km).
    #[arg(long, default_value_t = 400.0)]
    domain_km: f64,
    /// Growth ratio of the mesh spacing away from the fault.
    #[arg(long, default_value_t = 1.05)]
    ratio: f64,
    /// Relative tolerance of the adaptive steps.
    #[arg(long, default_value_t = 1e-3)]
    tolerance: f64,
    /// Fully dynamic (BP1-FD): with the default scheme, Newmark with inertia and no
    /// radiation damping at fixed steps `--dynamic-tau` while the largest slip rate is
    /// above the switching thresholds, the quasi-dynamic Runge–Kutta run in between; with
    /// `--scheme implicit`, adaptive Newmark throughout.
    #[arg(long)]
    inertia: bool,
    /// Far boundaries of the fully dynamic runs (docs/seas-bp1-fd.md): `none` (the far
    /// side moves with the plate, the bottom is free: both reflect), `dynamic`
    /// (absorbing — Lysmer–Kuhlemeyer dashpots against the motion relative to the far
    /// field at V_p/2 on the far side and the bottom — in the dynamic phases of the
    /// switching run, the quasi-dynamic phases as `none`), `all` (the absorbing model
    /// throughout: the implicit scheme, or both phases of the switching run, whose fault
    /// ODE sees the absorbing parts traction-free). Needs `--inertia`; default `all` (the
    /// converged set-up of docs/seas-bp1-fd.md), `none` without `--inertia`.
    #[arg(long, value_enum)]
    absorbing: Option<Absorbing>,
    /// The integrator with inertia (`--inertia`): `newmark` (trapezoidal, energy
    /// conserving, the default) or `backward-euler` (first order, damps high frequencies;
    /// docs/seas-bp1-fd.md).
    #[arg(long, value_enum, default_value_t = DynamicIntegrator::Newmark)]
    dynamic_integrator: DynamicIntegrator,
    /// Time step of the dynamic phases (s); default a quarter of the time a shear wave
    /// takes to cross an element on the fault, Δz/(4 c_s) (docs/seas-bp1.md: Δz/(2 c_s)
    /// gets the first event but not the recurrence).
    #[arg(long)]
    dynamic_tau: Option<f64>,
    /// Switch to the dynamic method when the largest slip rate reaches this (m/s);
    /// default 1e-2 (docs/seas-bp1-fd.md: with absorbing boundaries 1e-3 / 1e-4 left the
    /// afterslip below a rupture to the dynamic step for hours). Without `--inertia`
    /// unused (1e-3, as in checkpoints before issue 59).
    #[arg(long)]
    switch_to_dynamic: Option<f64>,
    /// An event ends when the largest slip rate has stayed below 1e-3 m/s for this long
    /// (s); default 0 (the benchmark's definition), 60 with `--inertia` and reflecting far
    /// boundaries (`--absorbing none`: waves reflected by the domain's boundaries lift
    /// the slip rate over the threshold for fractions of a second after a rupture).
    #[arg(long)]
    event_quiet_time: Option<f64>,
    /// Switch back to the quasi-dynamic method when it falls below this (m/s); default
    /// 1e-3 (docs/seas-bp1-fd.md). Without `--inertia` unused (1e-4).
    #[arg(long)]
    switch_to_quasi_dynamic: Option<f64>,
    /// Fixed point tolerance of the dynamic phases (energy norm of K + M, absolute): during
    /// an event ‖v‖ is about 1e6 in this norm, so 1e-6 is 1e-12 relative; the paper's 1e-10
    /// lies below the round-off of the corrections (they stagnate near 1e-9).
    #[arg(long, default_value_t = 1e-6)]
    dynamic_fixed_point_tolerance: f64,
    /// A station row at every accepted step (default: thinned as the benchmark suggests).
    #[arg(long)]
    every_step: bool,
    /// Largest state change per step ξ (τ ≲ ξ D_c / V in slip); 0 for none.
    #[arg(long, default_value_t = 0.5)]
    state_change_cap: f64,
    /// Tolerance of the fixed point iteration of each step (energy norm of the velocity
    /// correction; the paper's 1e-10 by default).
    #[arg(long, default_value_t = 1e-10)]
    fixed_point_tolerance: f64,
    /// Set up the solver for every step size (default: once, the quasistatic problem
    /// scaled by 1/τ).
    #[arg(long)]
    setup_per_time_step: bool,
    /// Time integration: `runge-kutta` (quasi-dynamic equations condensed onto the fault,
    /// Dormand–Prince 5(4), the default) or `implicit` (the paper's scheme: backward Euler
    /// with the fixed point of velocity and state, the only one with `--inertia`).
    #[arg(long, value_enum, default_value_t = Scheme::RungeKutta)]
    scheme: Scheme,
    /// Tolerance of the Runge–Kutta steps (local error per step relative to D_c in slip,
    /// absolute in ln θ).
    #[arg(long, default_value_t = 1e-6)]
    rk_tolerance: f64,
    #[command(flatten)]
    kernel: crate::KernelArgs,
    /// Threads of each evaluation of the Runge–Kutta run: the product with the condensed
    /// operator and the per-node friction solves (rayon; the same bits for every value).
    /// Default: every core of the machine.
    #[arg(long, default_value_t = rsf::Parallelism::available_cores())]
    threads: usize,
    #[command(flatten)]
    header: crate::SeasHeaderArgs,
    #[command(flatten)]
    run: crate::ResumeArgs,
    /// `--max-memory-gb` (nodes and fault operators estimated before anything is
    /// allocated), `--max-output-gb` (the station files: with `--every-step` and without
    /// `--max-steps`, the run stops at the step count whose rows fit, with a checkpoint).
    #[command(flatten)]
    limits: Limits,
}

/// Bytes of the station rows of one step with `--every-step` (12 files of 7 numbers).
const EVERY_STEP_BYTES: f64 = 12.0 * 7.0 * 25.0;

impl Args {
    /// The grid of the flags.
    fn grid(&self) -> SeasBp1Grid {
        SeasBp1Grid {
            dz: self.dz,
            domain: self.domain_km * 1e3,
            ratio: self.ratio,
        }
    }

    /// The step cap of the run: `--max-steps`, or with `--every-step` the steps whose
    /// station rows fit in `--max-output-gb`.
    fn step_cap(&self) -> Option<u64> {
        self.run.max_steps.or_else(|| {
            (self.every_step && self.limits.max_output_gb.is_finite()).then(|| {
                ((self.limits.max_output_gb * 1e9 / EVERY_STEP_BYTES).floor() as u64).max(1)
            })
        })
    }
}

impl Program for Args {
    const NAME: &'static str = "seas_bp1";

    fn limits(&self) -> Limits {
        self.limits
    }

    fn plan(&self) -> Result<Plan, AnyError> {
        let bp1 = SeasBp1::default();
        in_range("--end-years", self.end_years, (1e-9, 1e5), "years")?;
        in_range(
            "--state-change-cap",
            self.state_change_cap,
            (0.0, 1e3),
            "0: no cap",
        )?;
        for (flag, tol) in [
            ("--fixed-point-tolerance", self.fixed_point_tolerance),
            (
                "--dynamic-fixed-point-tolerance",
                self.dynamic_fixed_point_tolerance,
            ),
        ] {
            in_range(flag, tol, (1e-300, 1e3), "an absolute tolerance")?;
        }
        // The model's size, before anything is allocated.
        let size = for_flag(
            "--ratio",
            "ratio",
            for_flag(
                "--domain-km",
                "domain",
                for_flag("--dz", "dz", bp1.estimate(&self.grid())),
            ),
        )?;
        // The methods' settings.
        flag("--tolerance", bp1.step_control(self.tolerance))?;
        for_flag(
            "--rk-tolerance",
            "tolerance",
            bp1.fault_ode_options(self.rk_tolerance),
        )?;
        self.kernel.kernel(self.rk_tolerance)?;
        self.header.check()?;
        // The fully dynamic flags need --inertia; their values are physical.
        if !self.inertia {
            for (flag, given) in [
                (
                    "--absorbing",
                    self.absorbing.is_some_and(|a| a != Absorbing::None),
                ),
                ("--dynamic-tau", self.dynamic_tau.is_some()),
                ("--switch-to-dynamic", self.switch_to_dynamic.is_some()),
                (
                    "--switch-to-quasi-dynamic",
                    self.switch_to_quasi_dynamic.is_some(),
                ),
                (
                    "--dynamic-integrator",
                    self.dynamic_integrator != DynamicIntegrator::Newmark,
                ),
            ] {
                if given {
                    return Err(format!(
                        "{flag}: a setting of the fully dynamic run: it needs --inertia \
                         (BP1-FD), without it it would be ignored"
                    )
                    .into());
                }
            }
        }
        if self.absorbing == Some(Absorbing::Dynamic) && self.scheme == Scheme::Implicit {
            return Err("--absorbing dynamic: the implicit scheme has one model (use all)".into());
        }
        let crossing = self.dz / (bp1.shear_modulus() / bp1.rho).sqrt();
        if let Some(tau) = self.dynamic_tau {
            // Below a thousandth of the crossing time a step resolves nothing more, and a
            // dynamic phase of a minute would take hundreds of millions of steps (issue 74:
            // `--dynamic-tau 1e-9` ran without bound).
            in_range(
                "--dynamic-tau",
                tau,
                (1e-3 * crossing, crossing),
                &format!(
                    "s: at most the {crossing:.3e} s a shear wave takes to cross an element \
                     of the fault (Δz/c_s), a longer step does not resolve the rupture; at \
                     least a thousandth of it, a shorter one resolves nothing more and an \
                     event would take without bound"
                ),
            )?;
        }
        let thresholds = [
            ("--switch-to-dynamic", self.switch_to_dynamic),
            ("--switch-to-quasi-dynamic", self.switch_to_quasi_dynamic),
        ];
        for (flag, v) in thresholds {
            if let Some(v) = v {
                in_range(flag, v, (1e-12, 1e2), "m/s: a slip rate")?;
            }
        }
        if let Some(q) = self.event_quiet_time {
            in_range("--event-quiet-time", q, (0.0, 1e9), "s")?;
        }
        let stations = SEAS_BP1_STATION_DEPTHS.len() as f64;
        let output = match (self.every_step, self.step_cap()) {
            (true, Some(cap)) => cap as f64 * EVERY_STEP_BYTES,
            _ => seas_output_bytes(self.end_years, stations, 7, size.fault_nodes),
        };
        let mut outputs: Vec<String> = SEAS_BP1_STATION_DEPTHS
            .iter()
            .map(|&d| SeasBp1::station_name(d))
            .collect();
        outputs.extend(
            [
                "devol.dat",
                "events.csv",
                "summary.json",
                "overview.png",
                "checkpoint.bin",
                rsf_seas::SEAS_RESUME_LOG,
            ]
            .map(String::from),
        );
        let outputs: Vec<&str> = outputs.iter().map(String::as_str).collect();
        Ok(Plan::new()
            .pool(self.threads)
            .memory(
                size.bytes,
                "--dz, --domain-km, --ratio",
                format!(
                    "BP1 on dz = {} m, domain = {} km, ratio = {}: about {:.3e} nodes \
                     ({:.3e} on the fault)",
                    number(self.dz),
                    number(self.domain_km),
                    number(self.ratio),
                    size.nodes,
                    size.fault_nodes
                ),
            )
            .output(
                output,
                "--end-years, --every-step, --max-steps",
                format!("{} years of the benchmark's files", self.end_years),
            )
            .folder(
                Folder::new("--out", &self.out, &outputs)
                    .overwrite(self.overwrite)
                    .resume_from(self.run.resume.as_deref())
                    .allow_change(&self.run.allow_change),
            ))
    }
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq)]
enum DynamicIntegrator {
    Newmark,
    BackwardEuler,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq)]
enum Absorbing {
    None,
    Dynamic,
    All,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq)]
enum Scheme {
    RungeKutta,
    Implicit,
}

/// The run: the paper's implicit simulation, the Runge–Kutta run on the fault, or the
/// latter with fully dynamic events.
type Bp1Run = rsf::Run<2, rsf::friction::AsinhLaw, rsf::state::Aging, rsf::Integrator, 1>;

/// The program `seas_bp1` (`cargo run --release --example seas_bp1 -- --out DIR …`).
pub fn main() -> ExitCode {
    // With threads, the whole run on the pool (no hand-over per parallel region).
    crate::guard::main(|args, prepared| run(args, prepared, None))
}

/// The program on the processes of a job (MPI ranks, the `rsf-mpi` crate's `seas_bp1`):
/// the Runge–Kutta run of BP1-QD with every evaluation shared by the ranks
/// ([`rsf::FaultOde::share_evaluations`]; the dense or the ℋ-kernel), the files written by
/// rank 0 — byte-identical to one process's (docs/scaling.md, "Past one machine").
pub fn main_on_ranks(processes: &dyn Processes) -> ExitCode {
    crate::guard::main_on_ranks(processes, |args, prepared, processes| {
        run(args, prepared, Some(processes))
    })
}

fn run(args: Args, prepared: Prepared, processes: Option<&dyn Processes>) -> Result<(), AnyError> {
    // Rank 0 (or the one process) writes the files and tells.
    let root = processes.is_none_or(|p| p.rank() == 0);
    let bp1 = SeasBp1::default();
    let grid = args.grid();
    // The methods' settings (checked by the plan before any file was touched).
    let mut control = bp1.step_control(args.tolerance)?;
    control.state_change_cap = (args.state_change_cap > 0.0).then_some(args.state_change_cap);
    let rk_options = for_flag(
        "rk_tolerance",
        "tolerance",
        bp1.fault_ode_options(args.rk_tolerance),
    )?;
    // The folder was refused before anything was computed if it holds another run (of
    // this or of any other rsf program, unless --overwrite) or cannot be written.
    let stations: Vec<(String, f64)> = SEAS_BP1_STATION_DEPTHS
        .iter()
        .map(|&d| (SeasBp1::station_name(d), d))
        .collect();
    let folder = RunFolder::new(&args.out, "seas_bp1", &[]);
    let fresh = prepared.mode();
    let step_cap = args.step_cap();
    if let (Some(cap), None) = (step_cap, args.run.max_steps) {
        eprintln!(
            "--every-step: at most {cap} steps (station rows within --max-output-gb {})",
            args.limits.max_output_gb
        );
    }
    let t_setup = Instant::now();
    // BP1-FD's defaults: the converged set-up of docs/seas-bp1-fd.md. Without inertia the
    // switching thresholds are unused; their old defaults keep BP1-QD's fingerprints.
    let absorbing = args.absorbing.unwrap_or(if args.inertia {
        Absorbing::All
    } else {
        Absorbing::None
    });
    let (switch_to_dynamic, switch_to_quasi_dynamic) = match args.inertia {
        true => (1e-2, 1e-3),
        false => (1e-3, 1e-4),
    };
    let switch_to_dynamic = args.switch_to_dynamic.unwrap_or(switch_to_dynamic);
    let switch_to_quasi_dynamic = args
        .switch_to_quasi_dynamic
        .unwrap_or(switch_to_quasi_dynamic);
    let far = |absorbing| {
        if absorbing {
            SeasBp1Far::Absorbing
        } else {
            SeasBp1Far::Dirichlet
        }
    };
    let model = bp1.model_with_far(&grid, args.inertia, far(absorbing == Absorbing::All))?;
    let (nodes, fault_nodes) = (model.num_nodes(), model.frictional_boundary.len());
    let scheme = args.scheme;
    let method = match (scheme, args.inertia) {
        (Scheme::Implicit, _) => MethodKind::Implicit,
        (Scheme::RungeKutta, false) => MethodKind::FaultOde,
        (Scheme::RungeKutta, true) => MethodKind::Switching,
    };
    // The implicit scheme on `model`, with or without inertia, from τ₀ (s).
    let implicit = |model, inertia, tau0, fixed_point_tolerance| {
        let builder = bp1.simulation_builder(model, inertia, tau0, control)?;
        let builder = match (inertia, args.dynamic_integrator) {
            (true, DynamicIntegrator::BackwardEuler) => {
                builder.integrator(rsf::Integrator::BackwardEuler)
            }
            _ => builder,
        };
        builder
            .fixed_point(FixedPointOptions {
                tolerance: fixed_point_tolerance,
                ..FixedPointOptions::default()
            })
            .solver_options(SolverOptions {
                setup_per_time_step: args.setup_per_time_step,
                ..SolverOptions::default()
            })
            .build()
    };
    let kernel = args.kernel.kernel(args.rk_tolerance)?;
    let fault_ode_options = FaultOdeOptions {
        kernel,
        parallelism: rsf::Parallelism::rayon(args.threads),
        ..rk_options
    };
    fault_ode_options.validate()?;
    let fault_ode = |model| bp1.fault_ode(model, fault_ode_options);
    let mut sim: Bp1Run = match method {
        MethodKind::Implicit => {
            implicit(model, args.inertia, 1e-2, args.fixed_point_tolerance)?.into()
        }
        MethodKind::FaultOde => fault_ode(model)?.into(),
        MethodKind::Switching => {
            let c_s = (bp1.shear_modulus() / bp1.rho).sqrt();
            let dynamic_tau = args.dynamic_tau.unwrap_or(0.25 * args.dz / c_s);
            let dynamic_model = match absorbing {
                Absorbing::Dynamic => bp1.model_with_far(&grid, true, far(true))?,
                _ => model.clone(),
            };
            let dynamic = implicit(dynamic_model, true, 1.0, args.dynamic_fixed_point_tolerance)?;
            rsf::SwitchingRun::new(
                fault_ode(model)?,
                dynamic,
                rsf::switching::SwitchingOptions {
                    to_dynamic: switch_to_dynamic,
                    to_quasi_dynamic: switch_to_quasi_dynamic,
                    dynamic_tau,
                    restart_dt: dynamic_tau,
                },
            )?
            .into()
        }
    };
    if let Some(p) = processes {
        match &mut sim {
            rsf::Run::FaultOde(ode) => ode.share_evaluations(p.group())?,
            _ => {
                return Err("MPI ranks share the Runge–Kutta run of BP1-QD (--scheme \
                            runge-kutta without --inertia)"
                    .into())
            }
        }
    }
    let setup_s = t_setup.elapsed().as_secs_f64();
    let kernel_report = match &sim {
        rsf::Run::Implicit(_) => None,
        rsf::Run::FaultOde(s) => Some(s.kernel_report().clone()),
        rsf::Run::Switching(s) => Some(s.quasi_dynamic().kernel_report().clone()),
    };
    if let (Some(r), true) = (&kernel_report, root) {
        eprintln!("{r}");
    }
    if let Some(p) = processes.filter(|_| root) {
        eprintln!("{} MPI ranks share every evaluation", p.size());
    }
    if root {
        eprintln!(
        "BP1{} ({scheme:?}): dz = {} m, domain {} km, {nodes} nodes, {fault_nodes} on the fault; set-up {setup_s:.1} s",
        if args.inertia { "-FD" } else { "-QD" },
        args.dz,
        args.domain_km
    );
    }
    let sampling = SeasSampling {
        every_step: args.every_step,
        event_quiet_time: args.event_quiet_time.unwrap_or(
            if args.inertia && absorbing == Absorbing::None {
                60.0
            } else {
                0.0
            },
        ),
        ..SeasSampling::default()
    };
    // What a checkpoint continues: the scene, grid, physics and sampling, and the options
    // of the method that change the trajectory.
    let fingerprint = bp1
        .fingerprint(&grid, args.inertia, &sampling)
        .with("method", method)
        .with("end_years", args.end_years)
        .with("tolerance", args.tolerance)
        .with("state_change_cap", args.state_change_cap)
        .with("fixed_point_tolerance", args.fixed_point_tolerance)
        .with("setup_per_time_step", args.setup_per_time_step)
        .with("rk_tolerance", args.rk_tolerance)
        .with("kernel", kernel)
        .with("dynamic_tau", format!("{:?}", args.dynamic_tau))
        .with("switch_to_dynamic", switch_to_dynamic)
        .with("switch_to_quasi_dynamic", switch_to_quasi_dynamic)
        .with(
            "dynamic_fixed_point_tolerance",
            args.dynamic_fixed_point_tolerance,
        );
    // Only when set: checkpoints of runs without absorbing parts keep their fingerprint.
    let fingerprint = match absorbing {
        Absorbing::None => fingerprint,
        a => fingerprint.with("absorbing", format!("{a:?}")),
    };
    let fingerprint = match args.dynamic_integrator {
        DynamicIntegrator::Newmark => fingerprint,
        i => fingerprint.with("dynamic_integrator", format!("{i:?}")),
    };
    let setup = SeasSetup {
        modeler: args.header.modeler.clone(),
        date: args
            .header
            .date
            .clone()
            .unwrap_or_else(rsf_seas::utc_date_today),
        stations,
        ..bp1.seas_setup(args.dz, args.inertia, sampling)
    };
    // On resume everything is checked before any file is touched: the checkpoint (its
    // checksum and fingerprint), then every file's rows up to the checkpoint's step.
    let resumed = match &args.run.resume {
        None => None,
        Some(path) => {
            let c = read_checkpoint(path, &fingerprint, &args.run.allow_change)?;
            if root {
                SeasOutput::<rsf::friction::AsinhLaw>::check_resume(
                    &args.out,
                    rsf::Stepping::model(&sim),
                    &setup,
                    c.state.step,
                )?;
            }
            rsf::Stepping::restore(&mut sim, &c)?;
            Some(c)
        }
    };
    let mode = match &resumed {
        Some(c) => FileMode::Resume { step: c.state.step },
        None => fresh,
    };
    let t_end = args.end_years * SECONDS_PER_YEAR;
    let end = until(t_end, step_cap);
    if !root {
        // The same steps as rank 0, no files (no observer here ends a run).
        sim.run_until(end, &mut [])?;
        return Ok(());
    }
    let mut output = SeasOutput::new(
        &args.out,
        rsf::Stepping::model(&sim),
        sim.problem().friction_laws(),
        setup,
        mode,
    )?;
    // A run that can stop before its end (checkpoints, a step cap) logs what its
    // benchmark files hold at each checkpoint.
    if args.run.checkpoint_every > 0 || step_cap.is_some() {
        output = output.with_resume_log(mode)?;
    }
    if resumed.is_none() {
        // The benchmark's first row: the initial state at t = 0.
        output.write_initial_state(rsf::Stepping::model(&sim), rsf::Stepping::state(&sim))?;
    }
    // Every `--checkpoint-every` steps, and where the step cap stops the run.
    let mut checkpointer = args.run.checkpointer(
        folder.path("checkpoint.bin"),
        fingerprint,
        resumed.as_ref().map_or(0.0, |c| c.wall_time_s),
    )?;
    let t0 = rsf::Stepping::state(&sim).time;
    let mut progress = Progress::time_in(t0, t_end, TimeUnit::year(SECONDS_PER_YEAR), "BP1");
    let (wall, cpu) = (Instant::now(), cpu_seconds());
    let run = {
        // The files first, the checkpoint after them: a checkpoint never runs ahead.
        let mut observers: Vec<&mut dyn Observer<2, 1>> =
            vec![&mut output, &mut progress, &mut checkpointer];
        sim.run_until(end, &mut observers)
    };
    let (wall, cpu) = (wall.elapsed().as_secs_f64(), cpu_seconds() - cpu);
    let summary = match run {
        Ok(s) => s,
        Err(e) => {
            eprintln!("run failed after {} steps: {}", e.summary.steps, e.error);
            return Err(e.error.into());
        }
    };
    if let Some(e) = step_cap_error(
        &summary,
        end,
        rsf::Stepping::state(&sim),
        &folder.path("checkpoint.bin"),
    ) {
        return Err(e.into());
    }
    let events = output.events();
    let done: Vec<_> = events.iter().filter(|e| e.t_end.is_finite()).collect();
    let intervals: Vec<f64> = done
        .windows(2)
        .map(|w| (w[1].t_start - w[0].t_start) / SECONDS_PER_YEAR)
        .collect();
    let later: Vec<f64> = intervals.iter().skip(3).copied().collect();
    let mean_recurrence = if later.is_empty() {
        f64::NAN
    } else {
        later.iter().sum::<f64>() / later.len() as f64
    };
    let accepted_by_controller = match &sim {
        rsf::Run::Implicit(s) => s.state().controller.as_ref().map(|c| c.accepted()),
        rsf::Run::FaultOde(_) | rsf::Run::Switching(_) => None,
    };
    let evaluations = match &sim {
        rsf::Run::Implicit(_) => None,
        rsf::Run::FaultOde(s) => Some(s.evaluations()),
        rsf::Run::Switching(s) => Some(s.quasi_dynamic().evaluations()),
    };
    let switching = match &sim {
        rsf::Run::Switching(s) => {
            let st = s.stats();
            Some(serde_json::json!({
                "dynamic_phases": st.dynamic_phases,
                "dynamic_steps": st.dynamic_steps,
                "quasi_dynamic_steps": st.quasi_dynamic_steps,
                "dynamic_time_s": st.dynamic_time,
                "dynamic_tau_s": s.dynamic().tau(),
                "switch_to_dynamic_mps": switch_to_dynamic,
                "switch_to_quasi_dynamic_mps": switch_to_quasi_dynamic,
            }))
        }
        _ => None,
    };
    let exchanges = match &sim {
        rsf::Run::FaultOde(s) => s.exchanges(),
        _ => None,
    };
    let (tau_min, tau_max, _) = output.time_steps();
    let json = serde_json::json!({
        "problem": if args.inertia { "BP1-FD" } else { "BP1-QD" },
        "dz_m": args.dz,
        "absorbing": format!("{:?}", absorbing),
        "dynamic_integrator": format!("{:?}", args.dynamic_integrator),
        "event_start_years": events.iter().map(|e| e.t_start / SECONDS_PER_YEAR).collect::<Vec<_>>(),
        "domain_km": args.domain_km,
        "ratio": args.ratio,
        "tolerance": args.tolerance,
        "setup_per_time_step": args.setup_per_time_step,
        "fixed_point_tolerance": args.fixed_point_tolerance,
        "state_change_cap": args.state_change_cap,
        "nodes": nodes,
        "fault_nodes": fault_nodes,
        "end_years": args.end_years,
        // Steps of the whole run (across resumes); the counts and times below are this
        // invocation's.
        "accepted_steps": rsf::Stepping::state(&sim).step,
        "steps_this_invocation": summary.steps,
        "rejected_attempts": summary.rejected_attempts,
        "accepted_by_controller": accepted_by_controller,
        "scheme": format!("{scheme:?}"),
        "rk_tolerance": (scheme == Scheme::RungeKutta).then_some(args.rk_tolerance),
        "rate_evaluations": evaluations,
        "kernel": kernel_report.as_ref().map(|r| serde_json::json!({
            "kernel": r.kernel.to_string(),
            "dim": r.dim,
            "relative_error_frobenius": r.relative_error,
            "stored_entries": r.stored_entries,
            "compression_ratio": r.compression_ratio(),
            "dense_blocks": r.dense_blocks,
            "low_rank_blocks": r.low_rank_blocks,
            "max_rank": r.max_rank,
            "setup_s": r.setup_seconds,
        })),
        "threads": args.threads,
        // On MPI ranks: the processes and what they exchanged (counted by the code).
        "ranks": exchanges.map(|e| serde_json::json!({
            "ranks": e.ranks,
            "all_gathers": e.all_gathers,
            "values_per_all_gather": e.values as f64 / e.all_gathers.max(1) as f64,
            "bytes_received_per_rank": 8 * e.values,
        })),
        "switching": switching,
        "tau_min_s": tau_min,
        "tau_max_s": tau_max,
        "fixed_point_iterations_mean": summary.fpi_mean,
        "setup_s": setup_s,
        "wall_time_s": wall,
        "cpu_time_s": cpu,
        "machine": machine(),
        "events": events.len(),
        "first_event_years": events.first().map(|e| e.t_start / SECONDS_PER_YEAR),
        "recurrence_intervals_years": intervals,
        "mean_recurrence_from_4th_interval_years": mean_recurrence,
        "peak_slip_rate_mps": done.iter().map(|e| e.peak_slip_rate).fold(0.0, f64::max),
        "hypocentre_depths_m": done.iter().map(|e| e.hypocentre_depth).collect::<Vec<_>>(),
        "surface_slip_m": done.iter().map(|e| e.surface_slip).collect::<Vec<_>>(),
        "durations_s": done.iter().map(|e| e.t_end - e.t_start).collect::<Vec<_>>(),
    });
    let path = args.out.join("summary.json");
    rsf::checkpoint::write_atomically(&path, serde_json::to_string_pretty(&json)?.as_bytes())?;
    eprintln!(
        "{} steps ({} rejected), {} events, mean recurrence (4th interval on) {mean_recurrence:.1} yr, \
         wall {wall:.1} s, cpu {cpu:.1} s",
        summary.steps,
        summary.rejected_attempts,
        events.len()
    );
    crate::seas_overview(&args.out, "devol.dat", "depth (km)", done.len())?;
    Ok(())
}
