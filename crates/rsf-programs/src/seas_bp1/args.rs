//! The flags of `seas_bp1` and its plan (judged from the flags alone, before any work).

use std::path::PathBuf;

use crate::config::ConfigArgs;
use crate::estimates::seas_output_bytes;
use crate::fields::FaultSize;
use crate::guard::{number, written, AnyError, Folder, Limits, Plan, Program};
use clap::Parser;
use rsf::run_folder::{output_plan, OutputEstimate, OutputPlan};
use rsf_scenes::{RunConfig, SeasBp1, SeasBp1Run, SEAS_BP1_STATION_DEPTHS};

#[derive(Parser, Debug)]
#[command(about = "SCEC SEAS benchmark BP1-QD (antiplane, 3000 years)")]
pub struct Args {
    /// Output folder.
    #[arg(long)]
    pub(super) out: PathBuf,
    /// Replace the files of an earlier run in the output folder.
    #[arg(long)]
    pub(super) overwrite: bool,
    /// The run's settings (`rsf_scenes::SeasBp1Run`: these flags, or `--config`'s keys).
    #[command(flatten)]
    pub(crate) settings: SeasBp1Run,
    #[command(flatten)]
    pub(super) config: ConfigArgs,
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
    /// The output plan of `--every-step` (a station row at every step of an adaptive run
    /// whose step count is unknown before it runs): the one output policy,
    /// [`output_plan`] — `--max-steps` if it fits, else the steps whose rows fit in
    /// `--max-output-gb`. `None` without `--every-step` (the benchmark's thinned rows,
    /// bounded by `--end-years`).
    ///
    /// # Errors
    /// A `--max-steps` whose rows do not fit in `--max-output-gb`.
    pub(super) fn every_step_plan(&self) -> Result<Option<OutputPlan>, AnyError> {
        if !self.settings.every_step {
            return Ok(None);
        }
        // With --hdf5 its frames too: one cap for both (FieldArgs::adaptive_bytes).
        let (fixed, fields) = self
            .fields
            .adaptive_bytes(self.fault_size()?)
            .unwrap_or((0.0, 0.0));
        let per_step = EVERY_STEP_BYTES + fields;
        let estimate = OutputEstimate {
            bytes: self
                .run
                .max_steps
                .map_or(f64::INFINITY, |m| fixed + m as f64 * per_step),
            fixed_bytes: fixed,
            bytes_per_step: per_step,
            adaptive: true,
        };
        Ok(Some(output_plan(
            estimate,
            self.run.max_steps,
            self.limits.max_output_gb,
        )?))
    }

    /// The fault's fields' size (`--hdf5`): its nodes and the segments between them.
    fn fault_size(&self) -> Result<FaultSize, AnyError> {
        let run = &self.settings;
        let size = run
            .scene()
            .estimate(&run.grid())
            .map_err(|e| self.config.named(e))?;
        Ok(FaultSize::of(
            size.fault_nodes,
            (size.fault_nodes - 1.0, 2.0),
        ))
    }

    /// The step cap of the run: `--max-steps`, or with `--every-step` the steps whose
    /// station rows fit in `--max-output-gb` ([`every_step_plan`](Self::every_step_plan)).
    pub(super) fn step_cap(&self) -> Option<u64> {
        match self.every_step_plan() {
            Ok(Some(plan)) => plan.step_cap,
            _ => self.run.max_steps,
        }
    }
}

impl Program for Args {
    const NAME: &'static str = "seas_bp1";

    fn limits(&self) -> Limits {
        self.limits
    }

    fn configure(mut self, matches: &clap::ArgMatches) -> Result<Self, AnyError> {
        self.settings = self.config.merged(self.settings, matches)?;
        Ok(self)
    }

    fn plan(&self) -> Result<Plan, AnyError> {
        self.config.validate(&self.settings)?;
        let run = &self.settings;
        // The model's size, before anything is allocated (the grid checked above).
        let size = run
            .scene()
            .estimate(&run.grid())
            .map_err(|e| self.config.named(e))?;
        self.header.check()?;
        let stations = SEAS_BP1_STATION_DEPTHS.len() as f64;
        let output = match self.every_step_plan()? {
            Some(plan) => plan.bytes,
            None => seas_output_bytes(run.end_years, stations, 7, size.fault_nodes),
        };
        let mut outputs = SeasBp1::file_names();
        self.fields.check("seas_bp1")?;
        outputs.extend(["summary.json", "overview.png", "checkpoint.bin"].map(String::from));
        outputs.extend(crate::fields::FIELD_OUTPUTS.map(String::from));
        let outputs: Vec<&str> = outputs.iter().map(String::as_str).collect();
        let plan = Plan::new()
            .pool(self.threads)
            .memory(
                size.bytes,
                "--dz, --domain-km, --ratio",
                format!(
                    "BP1 on dz = {} m, domain = {} km, ratio = {}: about {:.3e} nodes \
                     ({:.3e} on the fault)",
                    number(run.dz),
                    number(run.domain_km),
                    number(run.ratio),
                    size.nodes,
                    size.fault_nodes
                ),
            )
            .output(
                output,
                "--end-years, --every-step, --max-steps, --hdf5",
                format!("{} years of the benchmark's files", written(run.end_years)),
            );
        // The fault's fields (--hdf5), in the station rows' cap with --every-step.
        let plan = if run.every_step {
            plan
        } else {
            self.fields.adaptive_output(
                plan,
                self.fault_size()?,
                self.run.max_steps,
                self.limits,
            )?
        };
        Ok(plan.folder(
            self.run
                .folder(Folder::new("--out", &self.out, &outputs).overwrite(self.overwrite))
                .fingerprint(run.fingerprint()),
        ))
    }
}

/// The run: the paper's implicit simulation, the Runge–Kutta run on the fault, or the
/// latter with fully dynamic events.
pub(super) type Bp1Run =
    rsf::Run<2, rsf::friction::AsinhLaw, rsf::state::Aging, rsf::Integrator, 1>;
