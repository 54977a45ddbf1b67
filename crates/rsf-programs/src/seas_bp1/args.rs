//! The flags of `seas_bp1` and its plan (judged from the flags alone, before any work).

use std::path::PathBuf;

use crate::cli::for_flag;
use crate::estimates::seas_output_bytes;
use crate::guard::{
    flag, flag_range, in_range, number, written, AnyError, Folder, Limits, Plan, Program,
};
use clap::Parser;
use rsf::run_folder::{output_plan, OutputEstimate, OutputPlan};
use rsf_scenes::{SeasBp1, SeasBp1Grid, SEAS_BP1_STATION_DEPTHS};

flag_range!(
    END_YEARS,
    END_YEARS_HELP = "Simulated time (years)",
    [1e-9, 1e5]
);
flag_range!(
    RATIO,
    RATIO_HELP = "Growth ratio of the mesh spacing away from the fault",
    [1, 2]
);
flag_range!(
    STATE_CHANGE_CAP,
    STATE_CHANGE_CAP_HELP = "Largest state change per step ξ (τ ≲ ξ D_c / V in slip); 0 for none",
    [0, 1e3]
);
flag_range!(
    FIXED_POINT_TOLERANCE,
    FIXED_POINT_TOLERANCE_HELP = "Tolerance of the fixed point iteration of each step (energy norm of the velocity correction; the paper's 1e-10 by default)",
    [1e-300, 1e3]
);
flag_range!(
    DYNAMIC_FIXED_POINT_TOLERANCE,
    DYNAMIC_FIXED_POINT_TOLERANCE_HELP = "Fixed point tolerance of the dynamic phases (energy norm of K + M, absolute): during an event ‖v‖ is about 1e6 in this norm, so 1e-6 is 1e-12 relative; the paper's 1e-10 lies below the round-off of the corrections (they stagnate near 1e-9)",
    [1e-300, 1e3]
);
flag_range!(
    EVENT_QUIET_TIME,
    EVENT_QUIET_TIME_HELP = "An event ends when the largest slip rate has stayed below 1e-3 m/s for this long (s); default 0 (the benchmark's definition), 60 with `--inertia` and reflecting far boundaries (`--absorbing none`: waves reflected by the domain's boundaries lift the slip rate over the threshold for fractions of a second after a rupture)",
    [0, 1e9]
);
flag_range!(
    SWITCH_TO_DYNAMIC,
    SWITCH_TO_DYNAMIC_HELP = "Switch to the dynamic method when the largest slip rate reaches this (m/s); default 1e-2 (docs/seas-bp1-fd.md: with absorbing boundaries 1e-3 / 1e-4 left the afterslip below a rupture to the dynamic step for hours). Needs `--inertia`",
    [1e-12, 1e2]
);
flag_range!(
    SWITCH_TO_QUASI_DYNAMIC,
    SWITCH_TO_QUASI_DYNAMIC_HELP = "Switch back to the quasi-dynamic method when it falls below this (m/s); default 1e-3 (docs/seas-bp1-fd.md). Needs `--inertia`",
    [1e-12, 1e2]
);

#[derive(Parser, Debug)]
#[command(about = "SCEC SEAS benchmark BP1-QD (antiplane, 3000 years)")]
pub struct Args {
    /// Output folder.
    #[arg(long)]
    pub(super) out: PathBuf,
    /// Replace the files of an earlier run in the output folder.
    #[arg(long)]
    pub(super) overwrite: bool,
    #[arg(long, default_value_t = 3000.0, help = END_YEARS_HELP)]
    pub(super) end_years: f64,
    /// Element size on the fault (m).
    #[arg(long, default_value_t = 25.0)]
    pub(super) dz: f64,
    /// Side of the square domain (km).
    #[arg(long, default_value_t = 400.0)]
    pub(super) domain_km: f64,
    #[arg(long, default_value_t = 1.05, help = RATIO_HELP)]
    pub(super) ratio: f64,
    /// Relative tolerance of the adaptive steps (`--scheme implicit`, or the dynamic phases
    /// with `--inertia`), in (2.220446049250313e-16, 1) (open: from f64::EPSILON, which
    /// can never be met, to 1, which accepts any step).
    #[arg(long, default_value_t = 1e-3)]
    pub(super) tolerance: f64,
    /// Fully dynamic (BP1-FD): with the default scheme, Newmark with inertia and no
    /// radiation damping at fixed steps `--dynamic-tau` while the largest slip rate is
    /// above the switching thresholds, the quasi-dynamic Runge–Kutta run in between; with
    /// `--scheme implicit`, adaptive Newmark throughout.
    #[arg(long)]
    pub(super) inertia: bool,
    /// Far boundaries of the fully dynamic runs (docs/seas-bp1-fd.md): `none` (the far
    /// side moves with the plate, the bottom is free: both reflect), `dynamic`
    /// (absorbing — Lysmer–Kuhlemeyer dashpots against the motion relative to the far
    /// field at V_p/2 on the far side and the bottom — in the dynamic phases of the
    /// switching run, the quasi-dynamic phases as `none`), `all` (the absorbing model
    /// throughout: the implicit scheme, or both phases of the switching run, whose fault
    /// ODE sees the absorbing parts traction-free). Needs `--inertia`; default `all` (the
    /// converged set-up of docs/seas-bp1-fd.md), `none` without `--inertia`.
    #[arg(long, value_enum)]
    pub(super) absorbing: Option<Absorbing>,
    /// The integrator with inertia (`--inertia`): `newmark` (trapezoidal, energy
    /// conserving, the default) or `backward-euler` (first order, damps high frequencies;
    /// docs/seas-bp1-fd.md).
    #[arg(long, value_enum, default_value_t = DynamicIntegrator::Newmark)]
    pub(super) dynamic_integrator: DynamicIntegrator,
    /// Time step of the dynamic phases (s); default a quarter of the time a shear wave
    /// takes to cross an element on the fault, Δz/(4 c_s) (docs/seas-bp1.md: Δz/(2 c_s)
    /// gets the first event but not the recurrence).
    #[arg(long)]
    pub(super) dynamic_tau: Option<f64>,
    #[arg(long, help = SWITCH_TO_DYNAMIC_HELP)]
    pub(super) switch_to_dynamic: Option<f64>,
    #[arg(long, help = EVENT_QUIET_TIME_HELP)]
    pub(super) event_quiet_time: Option<f64>,
    #[arg(long, help = SWITCH_TO_QUASI_DYNAMIC_HELP)]
    pub(super) switch_to_quasi_dynamic: Option<f64>,
    #[arg(long, default_value_t = 1e-6, help = DYNAMIC_FIXED_POINT_TOLERANCE_HELP)]
    pub(super) dynamic_fixed_point_tolerance: f64,
    /// A station row at every accepted step (default: thinned as the benchmark suggests).
    #[arg(long)]
    pub(super) every_step: bool,
    #[arg(long, default_value_t = 0.5, help = STATE_CHANGE_CAP_HELP)]
    pub(super) state_change_cap: f64,
    #[arg(long, default_value_t = 1e-10, help = FIXED_POINT_TOLERANCE_HELP)]
    pub(super) fixed_point_tolerance: f64,
    /// Set up the solver for every step size (default: once, the quasistatic problem
    /// scaled by 1/τ).
    #[arg(long)]
    pub(super) setup_per_time_step: bool,
    /// Time integration: `runge-kutta` (quasi-dynamic equations condensed onto the fault,
    /// `--integrator`'s, the default) or `implicit` (the paper's scheme: backward Euler
    /// with the fixed point of velocity and state, the only one with `--inertia`).
    #[arg(long, value_enum, default_value_t = Scheme::RungeKutta)]
    pub(super) scheme: Scheme,
    /// Tolerance of the Runge–Kutta steps (local error per step relative to D_c in slip,
    /// absolute in ln θ), in (2.220446049250313e-16, 1) (open: from f64::EPSILON to 1).
    #[arg(long, default_value_t = 1e-6)]
    pub(super) rk_tolerance: f64,
    #[command(flatten)]
    pub(super) kernel: crate::KernelArgs,
    #[command(flatten)]
    pub(super) integrator: crate::IntegratorArgs,
    /// Threads of each evaluation of the Runge–Kutta run: the product with the condensed
    /// operator and the per-node friction solves (rayon; the same bits for every value).
    /// Default: every core of the machine.
    #[arg(long, default_value_t = rsf::Parallelism::available_cores())]
    pub(super) threads: usize,
    #[command(flatten)]
    pub(super) header: crate::SeasHeaderArgs,
    #[command(flatten)]
    pub(super) run: crate::ResumeArgs,
    /// `--hdf5 N`: the fault's fields (crates/rsf-hdf5's `seas_bp1`).
    #[command(flatten)]
    pub(crate) fields: crate::fields::FieldArgs,
    /// `--max-memory-gb` (nodes and fault operators estimated before anything is
    /// allocated), `--max-output-gb` (the station files: with `--every-step` and without
    /// `--max-steps`, the run stops at the step count whose rows fit, with a checkpoint).
    #[command(flatten)]
    pub(super) limits: Limits,
}

/// Bytes of the station rows of one step with `--every-step` (12 files of 7 numbers).
const EVERY_STEP_BYTES: f64 = 12.0 * 7.0 * 25.0;

impl Args {
    /// The grid of the flags.
    pub(super) fn grid(&self) -> SeasBp1Grid {
        SeasBp1Grid {
            dz: self.dz,
            domain: self.domain_km * 1e3,
            ratio: self.ratio,
        }
    }

    /// The output plan of `--every-step` (a station row at every step of an adaptive run
    /// whose step count is unknown before it runs): the one output policy,
    /// [`output_plan`] — `--max-steps` if it fits, else the steps whose rows fit in
    /// `--max-output-gb`. `None` without `--every-step` (the benchmark's thinned rows,
    /// bounded by `--end-years`).
    ///
    /// # Errors
    /// A `--max-steps` whose rows do not fit in `--max-output-gb`.
    pub(super) fn every_step_plan(&self) -> Result<Option<OutputPlan>, AnyError> {
        if !self.every_step {
            return Ok(None);
        }
        let estimate = OutputEstimate {
            bytes: self
                .run
                .max_steps
                .map_or(f64::INFINITY, |m| m as f64 * EVERY_STEP_BYTES),
            fixed_bytes: 0.0,
            bytes_per_step: EVERY_STEP_BYTES,
            adaptive: true,
        };
        Ok(Some(output_plan(
            estimate,
            self.run.max_steps,
            self.limits.max_output_gb,
        )?))
    }

    /// The step cap of the run: `--max-steps`, or with `--every-step` the steps whose
    /// station rows fit in `--max-output-gb` ([`every_step_plan`](Self::every_step_plan)).
    pub(super) fn step_cap(&self) -> Option<u64> {
        match self.every_step_plan() {
            Ok(Some(plan)) => plan.step_cap,
            _ => self.run.max_steps,
        }
    }

    /// Refuses the flags the chosen scheme would ignore: the fully dynamic run's without
    /// `--inertia`, the implicit scheme's with the default fault ODE (issue 87: a flag
    /// that does nothing is refused naming the flag that would use it).
    ///
    /// # Errors
    /// The first such flag, named with the flag it needs.
    fn refuse_ignored_flags(&self) -> Result<(), AnyError> {
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
                // Issue 87's probe: `--dynamic-fixed-point-tolerance 1e-300` ran without
                // --inertia, the value never used.
                (
                    "--dynamic-fixed-point-tolerance",
                    self.dynamic_fixed_point_tolerance != 1e-6,
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
        // The settings of the implicit scheme are ignored by the default one (the fault
        // ODE's Runge–Kutta run without --inertia): refused when given (issue 87:
        // `--tolerance 1e-8` gave byte-identical files while summary.json recorded it).
        if self.scheme == Scheme::RungeKutta && !self.inertia {
            for (flag, given) in [
                ("--tolerance", self.tolerance != 1e-3),
                ("--state-change-cap", self.state_change_cap != 0.5),
                (
                    "--fixed-point-tolerance",
                    self.fixed_point_tolerance != 1e-10,
                ),
                ("--setup-per-time-step", self.setup_per_time_step),
            ] {
                if given {
                    return Err(format!(
                        "{flag}: a setting of the implicit scheme (`--scheme implicit`, or the \
                         dynamic phases with --inertia); the default scheme, the fault ODE's \
                         Runge–Kutta run, would ignore it — its tolerance is --rk-tolerance"
                    )
                    .into());
                }
            }
        }
        Ok(())
    }
}

impl Program for Args {
    const NAME: &'static str = "seas_bp1";

    fn limits(&self) -> Limits {
        self.limits
    }

    fn plan(&self) -> Result<Plan, AnyError> {
        let bp1 = SeasBp1::default();
        in_range("--end-years", self.end_years, END_YEARS, "years")?;
        in_range(
            "--state-change-cap",
            self.state_change_cap,
            STATE_CHANGE_CAP,
            "0: no cap",
        )?;
        in_range(
            "--fixed-point-tolerance",
            self.fixed_point_tolerance,
            FIXED_POINT_TOLERANCE,
            "an absolute tolerance",
        )?;
        in_range(
            "--dynamic-fixed-point-tolerance",
            self.dynamic_fixed_point_tolerance,
            DYNAMIC_FIXED_POINT_TOLERANCE,
            "an absolute tolerance",
        )?;
        in_range("--ratio", self.ratio, RATIO, "the growth of the spacing")?;
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
        self.refuse_ignored_flags()?;
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
            (
                "--switch-to-dynamic",
                self.switch_to_dynamic,
                SWITCH_TO_DYNAMIC,
            ),
            (
                "--switch-to-quasi-dynamic",
                self.switch_to_quasi_dynamic,
                SWITCH_TO_QUASI_DYNAMIC,
            ),
        ];
        for (flag, v, range) in thresholds {
            if let Some(v) = v {
                in_range(flag, v, range, "m/s: a slip rate")?;
            }
        }
        if let Some(q) = self.event_quiet_time {
            in_range("--event-quiet-time", q, EVENT_QUIET_TIME, "s")?;
        }
        let stations = SEAS_BP1_STATION_DEPTHS.len() as f64;
        let output = match self.every_step_plan()? {
            Some(plan) => plan.bytes,
            None => seas_output_bytes(self.end_years, stations, 7, size.fault_nodes),
        };
        let mut outputs = SeasBp1::file_names();
        self.fields.check("seas_bp1")?;
        outputs.extend(["summary.json", "overview.png", "checkpoint.bin"].map(String::from));
        outputs.extend(crate::fields::FIELD_OUTPUTS.map(String::from));
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
                format!("{} years of the benchmark's files", written(self.end_years)),
            )
            .folder(
                self.run
                    .folder(Folder::new("--out", &self.out, &outputs).overwrite(self.overwrite))
                    .fingerprint(self.fingerprint()?),
            ))
    }
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq)]
pub(super) enum DynamicIntegrator {
    Newmark,
    BackwardEuler,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq)]
pub(super) enum Absorbing {
    None,
    Dynamic,
    All,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq)]
pub(super) enum Scheme {
    RungeKutta,
    Implicit,
}

/// The run: the paper's implicit simulation, the Runge–Kutta run on the fault, or the
/// latter with fully dynamic events.
pub(super) type Bp1Run =
    rsf::Run<2, rsf::friction::AsinhLaw, rsf::state::Aging, rsf::Integrator, 1>;
