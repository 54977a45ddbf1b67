//! SEAS BP7-QD-A / BP7-QD-S (nucleation on a velocity-weakening disc of a square fault in
//! a whole space; docs/seas-bp7.md): the fault outside the square creeps at the plate
//! rate, a prescribed shear-stress bump `Δτ₀ G₁(r) G₂(t)` centred at `(−50, −50)` m
//! kicks it at `t = 0`, and the disc ruptures in earthquakes over 10 years.
//!
//! ```sh
//! cargo run --release --example seas_bp7 -- --law aging --out out/bp7a   # 10 m, 10 years
//! cargo run --release --example seas_bp7 -- --law slip --dx 20 --out out/bp7s
//! ```
//!
//! The fault ODE (`--integrator`, Dormand–Prince 5(4) while accuracy sets the step) on the
//! `(800 m/Δx)²` square cells, the whole space's boundary-element operator applied by
//! FFTs (`rsf::halfspace_operator::WholeSpaceGrid`), loaded by back slip at V_p and by
//! the bump (`rsf::fault_ode::LoadChange`, steps ending at its rise time T = 1 s).
//! `--d-rs` (mm) sets D_RS: 0.50 by default, 0.53 in two of the five implementations the
//! restatement read (docs/seas-bp7.md).
//!
//! Writes the benchmark's files to `--out` (`rsf_seas::SeasBp5Output::bp7`: thirteen
//! stations `fltst_strk±XXXdp±YYY`, six `blkst_…`, `global.dat`, slip and shear-stress
//! profiles, `rupture.dat`, `events.csv`), `summary.json`. Runs: `--checkpoint-every N`,
//! `--resume FILE`, `--max-steps N`, `--overwrite`, as every SEAS program.

use std::path::PathBuf;
use std::time::Instant;

use crate::config::ConfigArgs;
use crate::fields::FaultSize;
use crate::guard::{number, written, AnyError, Plan, Prepared};
use crate::square_fault::{elimination, print_volume, run_square_fault, volume_memory, SquareRun};
use crate::{cpu_seconds, machine};
use clap::Parser;
use rsf::observe::TimeUnit;
use rsf_scenes::{RunConfig, SeasBp7Run};
use rsf_seas::{SeasBp5Output, SEAS_BP7_RESUME_LOG, SECONDS_PER_YEAR};

/// SEAS BP7-QD-A / BP7-QD-S.
#[derive(Parser)]
#[command(version)]
pub(crate) struct Args {
    /// The run's settings (`rsf_scenes::SeasBp7Run`: these flags, or `--config`'s keys).
    #[command(flatten)]
    pub(crate) settings: SeasBp7Run,
    #[command(flatten)]
    config: ConfigArgs,
    /// Output folder.
    #[arg(long, default_value = "out/seas_bp7")]
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
    let mut names = SeasBp5Output::bp7_file_names();
    names.extend(["checkpoint.bin", SEAS_BP7_RESUME_LOG, "summary.json"].map(String::from));
    names
}

crate::seas_args::configured_program!(Args, "seas_bp7", job);

impl Args {
    /// The plan of the checked settings.
    fn planned(&self) -> Result<Plan, AnyError> {
        let run = &self.settings;
        let cells = run.cells().map_err(|e| self.config.named(e))? as f64;
        self.header.check()?;
        // Station rows (19 files of 8 columns and global.dat, 130 B a row each) at most
        // one per accepted step, the steps bounded by 10 000 a year for this estimate
        // (measured at 20 m: 1 318 a year with the aging law, 3 459 with the slip law;
        // docs/seas-bp7.md; fewer with `--station-interval`); profile rows (4 files of
        // 83 columns) one per second of events, 2 000 a year.
        let years = run.end_years;
        let rows = years * 1e4;
        let output = rows * 20.0 * 130.0 + years * 2000.0 * 4.0 * 83.0 * 15.0;
        // The fault ODE's vectors and the FFT operator's circulant, 2 kB per cell as BP8
        // (docs/seas-bp8.md), the six off-fault stations' displacement columns (3 × 2
        // values a cell each) 300 B per cell; the rows, kept in memory until the files
        // are written; 100 MB for the rest.
        let memory = match run.volume_grid().map_err(|e| self.config.named(e))? {
            None => 2300.0 * cells + output + 1e8,
            // The square's grid with its rim: (√cells + 1)² frictional nodes.
            Some(grid) => {
                let stations = rsf_seas::bp7_body_station_points();
                let pairs = (cells.sqrt() + 1.0).powi(2);
                let l_f = run.scene().l_f;
                volume_memory(
                    &grid,
                    (l_f, &stations),
                    pairs,
                    self.job.limits.max_memory_gb * 1e9,
                )? + output
            }
        };
        let plan = Plan::new()
            .memory(
                memory,
                "--dx",
                format!("BP7 on Δx = {} m: {cells} cells", number(run.dx)),
            )
            .output(
                output,
                "--end-years",
                format!("{} years of stations and profiles", written(run.end_years)),
            );
        // The fault's fields (--hdf5): the square's grid with its rim, its quadrilaterals.
        let fault = FaultSize::of((cells.sqrt() + 1.0).powi(2), (cells, 4.0));
        self.flags().plan(plan, outputs(), run.fingerprint(), fault)
    }
}

crate::seas_args::entry_points!(Args, run, "seas_bp7", "FieldWriters::fault_3d");

fn run(args: Args, folder: Prepared) -> Result<(), AnyError> {
    let run = args.settings;
    let law = run.law;
    let bp7 = run.scene();
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let setup = run.seas_setup(args.header.modeler.clone(), args.header.date_or_today());
    let fingerprint = run.fingerprint();
    let kernel = match run.volume_grid()? {
        None => "whole space (FFT boundary elements)",
        Some(_) => "finite elements",
    };
    println!(
        "BP7-QD-{}, Δx = {} m, D_RS = {} mm, {kernel}; on {}",
        law.name(),
        run.dx,
        run.d_rs,
        machine()
    );
    let mut options = bp7.fault_ode_options(run.tolerance)?;
    options.parallelism = rsf::Parallelism::rayon(args.threads);
    options.integrator = run.integrator;
    let (mut ode, body) = run.fault_ode(options, elimination(&args.job.limits))?;
    if let Some(grid) = run.volume_grid()? {
        print_volume(&ode, &grid);
    }
    // The folder's lock is held until the run ends.
    let settings = SquareRun {
        flags: args.flags(),
        folder: &folder,
        integrator: run.integrator,
        fingerprint,
        end: run.end_seconds(),
        unit: (
            TimeUnit {
                seconds: SECONDS_PER_YEAR,
                symbol: "yr",
            },
            "BP7",
        ),
        started: (clock, cpu0),
    };
    let output = |model: &rsf::Model<3, 3>| Ok(run.output(&args.out, model, body, setup)?);
    let keys = serde_json::json!({
        "problem": format!("BP7-QD-{}", law.name()),
        "settings": run.summary(),
    });
    run_square_fault(settings, &mut ode, output, keys)?;
    Ok(())
}
