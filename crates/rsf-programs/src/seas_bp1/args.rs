//! The flags of `seas_bp1` and its plan (judged from the flags alone, before any work).

use std::path::PathBuf;

use crate::config::ConfigArgs;
use crate::estimates::seas_output_bytes;
use crate::fields::FaultSize;
use crate::guard::{number, written, AnyError, Plan};
use clap::Parser;
use rsf::run_folder::{output_plan, OutputEstimate, OutputPlan};
use rsf_scenes::{GridEstimate, RunConfig, SeasBp1, SeasBp1Run, SEAS_BP1_STATION_DEPTHS};

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
    /// The resume flags, `--hdf5 N`, `--max-memory-gb` (nodes and fault operators
    /// estimated before anything is allocated), `--max-output-gb` (the station files: with
    /// `--every-step` and without `--max-steps`, the run stops at the step count whose rows
    /// fit, with a checkpoint).
    #[command(flatten)]
    pub(crate) job: crate::seas_args::JobArgs,
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
            .job
            .fields
            .adaptive_bytes(self.fault_size()?)
            .unwrap_or((0.0, 0.0));
        let per_step = EVERY_STEP_BYTES + fields;
        let estimate = OutputEstimate {
            bytes: self
                .job
                .run
                .max_steps
                .map_or(f64::INFINITY, |m| fixed + m as f64 * per_step),
            fixed_bytes: fixed,
            bytes_per_step: per_step,
            adaptive: true,
        };
        Ok(Some(output_plan(
            estimate,
            self.job.run.max_steps,
            self.job.limits.max_output_gb,
        )?))
    }

    /// The model's size, before anything is allocated.
    ///
    /// # Errors
    /// A grid that does not fit BP1, named as the user wrote it.
    fn size(&self) -> Result<GridEstimate, AnyError> {
        let run = &self.settings;
        let size = run.scene().estimate(&run.grid());
        size.map_err(|e| self.config.named(e))
    }

    /// The fault's fields' size (`--hdf5`): its nodes and the segments between them.
    fn fault_size(&self) -> Result<FaultSize, AnyError> {
        let nodes = self.size()?.fault_nodes;
        Ok(FaultSize::of(nodes, (nodes - 1.0, 2.0)))
    }

    /// The step cap of the run: `--max-steps`, or with `--every-step` the steps whose
    /// station rows fit in `--max-output-gb` ([`every_step_plan`](Self::every_step_plan)).
    pub(super) fn step_cap(&self) -> Option<u64> {
        match self.every_step_plan() {
            Ok(Some(plan)) => plan.step_cap,
            _ => self.job.run.max_steps,
        }
    }
}

/// The files a run writes into `--out`.
fn outputs() -> Vec<String> {
    let mut outputs = SeasBp1::file_names();
    outputs.extend(["summary.json", "overview.png", "checkpoint.bin"].map(String::from));
    outputs
}

crate::seas_args::configured_program!(Args, "seas_bp1", job);

impl Args {
    /// The plan of the checked settings.
    fn planned(&self) -> Result<Plan, AnyError> {
        let run = &self.settings;
        let size = self.size()?;
        self.header.check()?;
        let stations = SEAS_BP1_STATION_DEPTHS.len() as f64;
        let output = match self.every_step_plan()? {
            Some(plan) => plan.bytes,
            None => seas_output_bytes(run.end_years, stations, 7, size.fault_nodes),
        };
        let plan = Plan::new()
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
        let (flags, fingerprint) = (self.flags(), run.fingerprint());
        if run.every_step {
            Ok(flags.folder(plan, outputs(), fingerprint))
        } else {
            flags.plan(plan, outputs(), fingerprint, self.fault_size()?)
        }
    }
}

/// The run: the paper's implicit simulation, the Runge–Kutta run on the fault, or the
/// latter with fully dynamic events.
pub(super) type Bp1Run =
    rsf::Run<2, rsf::friction::AsinhLaw, rsf::state::Aging, rsf::Integrator, 1>;
