//! SEAS BP6-QD-A/S/C (fluid injection into a fault in an antiplane whole space;
//! docs/seas-bp6.md): the pore pressure of the description's closed form (or its
//! diffusion solved along the fault) lowers the effective normal stress and drives one
//! aseismic slip transient.
//!
//! ```sh
//! cargo run --release --example seas_bp6 -- --variant a --out out/bp6a          # 10 m, 2 years, BEM
//! cargo run --release --example seas_bp6 -- --variant s --out out/bp6s
//! cargo run --release --example seas_bp6 -- --variant c --out out/bp6c          # implicit, BEM
//! cargo run --release --example seas_bp6 -- --variant c --elastic fe --dz 50 --out out/bp6c_fe
//! cargo run --release --example seas_bp6 -- --variant a --elastic fe --dz 50 --out out/bp6a_fe
//! ```
//!
//! A and S run as a fault ODE (Dormand–Prince 5(4)) with the whole space's
//! boundary-element kernel on `2 l_f/Δz` cells (`--elastic bem`, the default; its product
//! through FFTs, `--bem-product fft`, or stored as `--kernel` says) or the finite-element
//! half space condensed onto the fault (`--elastic fe`, `--domain-km`, `--ratio`). C
//! (constant friction) runs with the implicit scheme (backward Euler, the direct solver:
//! the nonsmooth problem with the bound `f (σ̄₀ − p(t))` solved exactly at every step) on
//! the fault alone with the boundary-element kernel as its dense stiffness (`--elastic
//! bem`, the default: the description's 10 m in 2 min of CPU and 3 GB) or on the
//! finite-element model (`--elastic fe`: 50 m in 36 s and 1.9 GB, finer cells beyond
//! this machine's memory); a fault ODE cannot take it (its steps would be limited to
//! milliseconds by the damping alone, docs/seas-bp6.md).
//!
//! Writes the benchmark's files to `--out` (`rsf_seas::SeasBp6Output`: nine stations,
//! `global.dat`, four profiles). Runs: `--checkpoint-every N`, `--resume FILE`,
//! `--max-steps N`, `--overwrite`, as every SEAS program.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use crate::config::ConfigArgs;
use crate::fields::FaultSize;
use crate::fields::{Fault2d, FaultFields2d};
use crate::guard::{number, written, AnyError, Plan, Prepared};
use crate::seas_args::run_observed;
use crate::{cpu_seconds, machine};
use clap::Parser;
use rsf::checkpoint::Fingerprint;
use rsf::pore_pressure::PorePressure;
use rsf::whole_space::WholeSpaceKernel;
use rsf::Stepping;
use rsf_scenes::{
    Bp6BemProduct, Bp6Elastic, Bp6Variant, KernelChoice, RunConfig, SeasBp6, SeasBp6Run,
    BP6_C_FIRST_STEP, BP6_SECONDS_PER_YEAR,
};
use rsf_seas::{SeasBp6Output, SeasSetup, SEAS_BP6_RESUME_LOG};

/// SEAS BP6-QD-A/S/C.
#[derive(Parser)]
#[command(version)]
pub(crate) struct Args {
    /// The run's settings (`rsf_scenes::SeasBp6Run`: these flags, or `--config`'s keys;
    /// Python's `rsf.seas_bp6` keywords).
    #[command(flatten)]
    pub(crate) settings: SeasBp6Run,
    #[command(flatten)]
    config: ConfigArgs,
    /// Output folder.
    #[arg(long, default_value = "out/seas_bp6")]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out`.
    #[arg(long)]
    overwrite: bool,
    /// Threads of each evaluation (the same bits for every value).
    #[arg(long, default_value_t = 1)]
    threads: usize,
    #[command(flatten)]
    header: crate::SeasHeaderArgs,
    #[command(flatten)]
    pub(crate) job: crate::seas_args::JobArgs,
}

/// The files a run writes into `--out`.
fn outputs() -> Vec<String> {
    let mut names = SeasBp6Output::file_names();
    names.extend(["checkpoint.bin", SEAS_BP6_RESUME_LOG, "summary.json"].map(String::from));
    names
}

crate::seas_args::configured_program!(Args, "seas_bp6", job);

impl Args {
    /// The plan of the checked settings.
    fn planned(&self) -> Result<Plan, AnyError> {
        self.header.check()?;
        let run = &self.settings;
        let (variant, elastic) = (run.variant, run.elastic);
        let bp6 = SeasBp6::default();
        let cells = run.cells(&bp6);
        let hierarchical = run.kernel == KernelChoice::Hierarchical;
        let (nodes, memory) = match elastic {
            // C: the dense stiffness as a sparse matrix (16 bytes an entry), its energy
            // norm, the direct solver's copies and dense matrices: measured 180 to 190
            // bytes per entry of S (max RSS at 800, 2000 and 4000 cells), bounded by 256.
            Bp6Elastic::Bem if variant == Bp6Variant::C => (cells, 256.0 * cells * cells + 1e8),
            Bp6Elastic::Bem => (
                cells,
                match run.bem_product() {
                    Bp6BemProduct::Fft => 64.0 * cells,
                    Bp6BemProduct::Stored => crate::estimates::operator_bytes(cells, hierarchical),
                } + 1e8,
            ),
            Bp6Elastic::Fe => {
                let g = run.grid();
                let nx = rsf::fem::geometric_grading_len(g.dz, 0.0, g.ratio, g.domain);
                let nz = 2.0 * rsf::fem::geometric_grading_len(g.dz, bp6.l_f, g.ratio, g.domain);
                let n = nx * nz;
                if variant == Bp6Variant::C {
                    // C: the implicit scheme's direct solver on the volume, whose fault
                    // block is dense: fitted to the measured peaks (max RSS of 2-year runs,
                    // `--domain-km` 400: 229, 624 and 1 941 MB at Δz = 200, 100, 50 m, for
                    // 36 860, 67 140 and 128 400 nodes and 200, 400, 800 cells) as
                    // 3 636 B a node + 2 375 B per (cell)², with a margin of 1.25.
                    (n, 1.25 * (3636.0 * n + 2375.0 * cells * cells))
                } else {
                    (
                        n,
                        n * crate::estimates::SEAS_BYTES_PER_NODE
                            + 3.0 * crate::estimates::operator_bytes(cells, hierarchical),
                    )
                }
            }
        };
        // Station rows (9 files of 7 columns, global.dat): at most one per step, the
        // steps bounded by one per 10 minutes for this estimate (2 years of BP6-S at 10 m
        // take about 10⁴); 4 profiles of 202 columns.
        let seconds = run.end_years * BP6_SECONDS_PER_YEAR;
        let rows = seconds / run.station_interval.max(600.0);
        let output = rows * (10.0 * 110.0) + seconds / run.profile_interval * 4.0 * 202.0 * 15.0;
        let plan = Plan::new()
            .memory(
                memory,
                "--dz, --elastic, --domain-km, --ratio",
                format!("BP6 on Δz = {} m: about {nodes:.3e} nodes", number(run.dz)),
            )
            .output(
                output,
                "--end-years",
                format!("{} years of stations and profiles", written(run.end_years)),
            );
        // The fault's fields (--hdf5): its nodes and the segments between them.
        let fault = FaultSize::of(cells + 1.0, (cells, 2.0));
        self.flags().plan(plan, outputs(), run.fingerprint(), fault)
    }
}

crate::seas_args::entry_points!(Args, run, "seas_bp6", "Fault2d");

fn run(args: Args, folder: Prepared) -> Result<(), AnyError> {
    let settings = args.settings;
    let (variant, elastic) = (settings.variant, settings.elastic);
    let tol = settings.tolerance();
    let bp6 = SeasBp6::default();
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let pressure = bp6.pressure(settings.pressure())?;
    let setup = SeasSetup {
        problem: format!("SEAS Benchmark BP6-QD-{}", variant.name()),
        modeler: args.header.modeler.clone(),
        date: args.header.date_or_today(),
        element_size: settings.dz,
        ..bp6.seas_setup(variant, settings.dz)
    };
    let fingerprint = settings.fingerprint();
    let common = Common {
        args: &args,
        folder,
        setup,
        fingerprint,
        pressure: pressure.clone(),
        clock,
        cpu0,
    };
    println!(
        "BP6-QD-{}, Δz = {} m, {:?} kernel, {:?} pore pressure; on {}",
        variant.name(),
        settings.dz,
        elastic,
        settings.pressure(),
        machine()
    );
    match (variant, elastic) {
        (Bp6Variant::C, Bp6Elastic::Bem) => {
            let model = bp6.bem_constant_friction_model(settings.dz, settings.bem_kernel()?)?;
            let fault = bp6.output_fault(&model, variant);
            println!(
                "{} cells, the kernel as a dense stiffness (set-up CPU {:.1} s)",
                fault.positions.len(),
                cpu_seconds() - cpu0
            );
            let mut sim =
                bp6.constant_friction(model, pressure, BP6_C_FIRST_STEP, bp6.step_control(tol)?)?;
            common.drive(&mut sim, fault, |s| (s.step_count_text(), None))
        }
        (Bp6Variant::C, Bp6Elastic::Fe) => {
            let model = bp6.fe_model(&settings.grid(), variant)?;
            let fault = bp6.output_fault(&model, variant);
            println!(
                "{} nodes, {} on the fault",
                model.vertices.len(),
                fault.positions.len()
            );
            let mut sim =
                bp6.constant_friction(model, pressure, BP6_C_FIRST_STEP, bp6.step_control(tol)?)?;
            common.drive(&mut sim, fault, |s| (s.step_count_text(), None))
        }
        (_, Bp6Elastic::Bem) => {
            let mut options = bp6.fault_ode_options(tol)?;
            options.parallelism = rsf::Parallelism::rayon(args.threads);
            options.integrator = settings.integrator;
            let kernel = settings.bem_kernel()?;
            let mut ode = bp6.bem_fault_ode(settings.dz, variant, kernel, options, pressure)?;
            match kernel {
                WholeSpaceKernel::Fft => println!(
                    "S: the FFT product of the Toeplitz kernel, m = {}",
                    ode.kernel_report().dim
                ),
                WholeSpaceKernel::Stored(_) => println!("S: {}", ode.kernel_report()),
            }
            let fault = bp6.output_fault(ode.model(), variant);
            common.drive(&mut ode, fault, |o| {
                (o.evaluations_text(), Some(o.integrator_stats()))
            })
        }
        (_, Bp6Elastic::Fe) => {
            let model = bp6.fe_model(&settings.grid(), variant)?;
            println!("{} nodes", model.vertices.len());
            let mut options = bp6.fault_ode_options(tol)?;
            options.parallelism = rsf::Parallelism::rayon(args.threads);
            options.integrator = settings.integrator;
            options.kernel = settings.fault_kernel()?;
            let mut ode = bp6.fe_fault_ode(model, variant, options, pressure)?;
            println!("S: {}", ode.kernel_report());
            let fault = bp6.output_fault(ode.model(), variant);
            common.drive(&mut ode, fault, |o| {
                (o.evaluations_text(), Some(o.integrator_stats()))
            })
        }
    }
}

/// What every run of the program shares.
struct Common<'a> {
    args: &'a Args,
    folder: Prepared,
    setup: SeasSetup,
    fingerprint: Fingerprint,
    pressure: Arc<dyn PorePressure<2>>,
    clock: Instant,
    cpu0: f64,
}

/// A line of what a method counted.
trait Counts {
    fn evaluations_text(&self) -> String {
        String::new()
    }
    fn step_count_text(&self) -> String {
        String::new()
    }
}

impl<L: rsf::friction::FrictionLaw, S: rsf::state::StateLaw, const C: usize> Counts
    for rsf::FaultOde<2, L, S, C>
{
    fn evaluations_text(&self) -> String {
        format!("{} evaluations", self.evaluations())
    }
}

impl<const C: usize> Counts for rsf_scenes::SeasBp6Implicit<C> {}

impl Common<'_> {
    fn drive<const C: usize, R: Stepping<2, C>>(
        self,
        run: &mut R,
        fault: rsf_seas::Bp6Fault,
        counts: impl Fn(&R) -> (String, Option<rsf::fault_ode::StepperStats>),
    ) -> Result<(), AnyError>
    where
        Fault2d<C>: FaultFields2d<C>,
    {
        let args = self.args;
        println!(
            "set-up: wall {:.1} s, CPU {:.1} s",
            self.clock.elapsed().as_secs_f64(),
            cpu_seconds() - self.cpu0
        );
        // The folder's lock (`self.folder`) is held until the run ends.
        let (flags, folder) = (args.flags(), &self.folder);
        let end = args.settings.end_years * BP6_SECONDS_PER_YEAR;
        let step_cap = folder.step_cap(args.job.run.max_steps);
        let session = flags.session(step_cap, self.fingerprint, end, run)?;
        let mut fields = flags.fields_observer(&session, folder.mode(), Fault2d::<C>::make)?;
        let mut output = SeasBp6Output::new(&args.out, fault, self.pressure.clone(), self.setup)?
            .with_intervals(
                args.settings.station_interval,
                args.settings.profile_interval,
            );
        if session.keeps_resume_log() {
            output = output.with_resume_log(args.job.run.checkpoint_every);
        }
        match session.resumed() {
            Some(c) => output.resume(c.state.step, c.state.time)?,
            None => output.write_initial_state(run.model(), run.state(), run.fault_tractions()),
        }
        let year = rsf::observe::TimeUnit::year(BP6_SECONDS_PER_YEAR);
        let progress = rsf::observe::Progress::time_in(run.state().time, end, year, "BP6");
        let mut peak = Peak::default();
        let files: Vec<&mut dyn rsf::Observer<2, C>> = vec![&mut output, &mut peak];
        let summary = run_observed(session, run, files, &mut fields, progress)?;
        let wall = self.clock.elapsed().as_secs_f64();
        let cpu = cpu_seconds() - self.cpu0;
        let (counts, integrator) = counts(run);
        println!(
            "{} steps ({} attempts rejected){}{counts}; wall {wall:.1} s, CPU {cpu:.1} s; \
             wrote {}",
            summary.steps,
            summary.rejected_attempts,
            if counts.is_empty() { "" } else { ", " },
            args.out.display()
        );
        let json = serde_json::json!({
            "steps": summary.steps,
            "rejected_attempts": summary.rejected_attempts,
            "wall_s": wall,
            "cpu_s": cpu,
            "machine": machine(),
            "integrator": integrator.map(|st| {
                crate::IntegratorArgs {
                    integrator: args.settings.integrator,
                }
                .summary(Some(st))
            }),
            // For the integrators' work–precision study (docs/work-precision.md): the run's
            // (this invocation's) largest fault-wide slip rate at an accepted step and its
            // time, the steps and the evaluations of this invocation.
            "peak_slip_rate_mps": peak.rate,
            "peak_time_years": peak.time / BP6_SECONDS_PER_YEAR,
            "accepted_steps": run.state().step,
            "rate_evaluations": integrator.map(|st| {
                st.explicit_evaluations + st.stabilized_evaluations + st.implicit_evaluations
            }),
            "cpu_time_s": cpu,
            "settings": args.settings.summary(),
        });
        std::fs::write(args.out.join("summary.json"), json.to_string())?;
        Ok(())
    }
}

/// The fault's largest slip rate at an accepted step and its time (s).
#[derive(Debug, Default)]
struct Peak {
    rate: f64,
    time: f64,
}

impl<const C: usize> rsf::Observer<2, C> for Peak {
    fn observe(&mut self, step: &rsf::StepView<'_, 2, C>) -> rsf::Result<rsf::Flow> {
        if step.report.max_slip_rate > self.rate {
            self.rate = step.report.max_slip_rate;
            self.time = step.state.time;
        }
        Ok(rsf::Flow::Continue(()))
    }
    fn reads_volume(&self) -> bool {
        false
    }
}
