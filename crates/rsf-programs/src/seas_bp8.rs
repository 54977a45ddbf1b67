//! SEAS BP8-QD-GS / BP8-QD-PW (fluid injection into a velocity-strengthening square of a
//! planar fault in a whole space; docs/seas-bp8.md): the pore pressure diffusing in the
//! fault plane from a Gaussian source (GS) or a Peaceman well (PW) lowers the effective
//! normal stress and drives one aseismic slip transient.
//!
//! ```sh
//! cargo run --release --example seas_bp8 -- --source gs --out out/bp8gs   # 10 m, 30 days
//! cargo run --release --example seas_bp8 -- --source pw --dx 20 --out out/bp8pw
//! ```
//!
//! The fault ODE (`--integrator`, Dormand–Prince 5(4) while accuracy sets the step) on the
//! `(800 m/Δx)²` square cells of the frictional square, the whole space's boundary-element
//! operator applied by FFTs (`rsf::halfspace_operator::WholeSpaceGrid`: exact up to
//! round-off, the locked exterior contributing nothing); the pressure the diffusion on the
//! square's nodes, exact in time (`rsf::pore_pressure::SurfaceDiffusion`), read at the
//! cells' centres. Where the pressure would reach the normal stress (PW, the cells next to
//! the well) `--overpressure floor` (the default) holds the effective normal stress above
//! `--sigma-min` MPa (`rsf::pore_pressure::EffectiveStressFloor`); `--overpressure refuse`
//! stops the run there with the cell and the time.
//!
//! Writes the benchmark's 20 files to `--out` (`rsf_seas::SeasBp5Output::bp8`: nine
//! stations `fltst_strk±XXXdp±YYY`, `global.dat`, ten profiles on the description's 81
//! positions), `summary.json`. Runs: `--checkpoint-every N`, `--resume FILE`,
//! `--max-steps N`, `--overwrite`, as every SEAS program.

use std::path::PathBuf;
use std::time::Instant;

use crate::config::ConfigArgs;
use crate::fields::FaultSize;
use crate::guard::{number, written, AnyError, Plan, Prepared};
use crate::square_fault::{elimination, print_volume, run_square_fault, volume_memory, SquareRun};
use crate::{cpu_seconds, machine};
use clap::Parser;
use rsf::observe::TimeUnit;
use rsf_scenes::{Bp8Source, RunConfig, SeasBp8, SeasBp8Run, BP8_SECONDS_PER_DAY};
use rsf_seas::{SeasBp5Output, SEAS_BP8_RESUME_LOG};

/// SEAS BP8-QD-GS / BP8-QD-PW.
#[derive(Parser)]
#[command(version)]
pub(crate) struct Args {
    /// The run's settings (`rsf_scenes::SeasBp8Run`: these flags, or `--config`'s keys).
    #[command(flatten)]
    pub(crate) settings: SeasBp8Run,
    #[command(flatten)]
    config: ConfigArgs,
    /// Output folder.
    #[arg(long, default_value = "out/seas_bp8")]
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
    let mut names = SeasBp5Output::bp8_file_names();
    names.extend(["checkpoint.bin", SEAS_BP8_RESUME_LOG, "summary.json"].map(String::from));
    names
}

crate::seas_args::configured_program!(Args, "seas_bp8", job);

impl Args {
    /// The plan of the checked settings.
    fn planned(&self) -> Result<Plan, AnyError> {
        let run = &self.settings;
        let cells = run.cells().map_err(|e| self.config.named(e))? as f64;
        self.header.check()?;
        // The fault ODE's vectors, the FFT operator's circulant (4 times the cells, a
        // 2 × 2 block of complex entries each) and the pressure's nodes: 2 kB per cell
        // (measured: 27 MB of max RSS for GS at 10 m, 6 400 cells); PW's modal system of
        // the well, dense in its D directions (one per distinct eigenvalue of the cosine
        // modes: D = 3 283 at 5 m, docs/pore-pressure.md; estimated here as
        // (n/2 + 1)(n/2 + 2)/2 for n cells a side, 3 321 at 5 m), its
        // eigendecomposition's copies counted four times (PW at 5 m: 419 MB of max RSS,
        // this estimate 504 MB); 100 MB for the rest.
        let n = cells.sqrt();
        let modes = (0.5 * n + 1.0) * (0.5 * n + 2.0) / 2.0;
        let well = if run.source == Bp8Source::Well {
            4.0 * 8.0 * modes * modes
        } else {
            0.0
        };
        let memory = match run.volume_grid().map_err(|e| self.config.named(e))? {
            None => 2000.0 * cells + well + 1e8,
            // The square's inner grid: (√cells − 1)² frictional nodes.
            Some(grid) => {
                let pairs = (n - 1.0).powi(2);
                let l_f = SeasBp8::default().l_f;
                volume_memory(
                    &grid,
                    (l_f, &[]),
                    pairs,
                    self.job.limits.max_memory_gb * 1e9,
                )? + well
            }
        };
        // Station rows (9 files of 11 columns and global.dat) at most one per step, the
        // steps bounded by one per minute for this estimate (30 days at 10 m take a few
        // thousand); 10 profiles of 83 columns.
        let seconds = run.end_seconds();
        let rows = seconds / run.station_interval.max(60.0);
        let output = rows * (10.0 * 170.0) + seconds / run.profile_interval * 10.0 * 83.0 * 15.0;
        let plan = Plan::new()
            .memory(
                memory,
                "--dx",
                format!("BP8 on Δx = {} m: {cells} cells", number(run.dx)),
            )
            .output(
                output,
                "--end-days",
                format!("{} days of stations and profiles", written(run.end_days)),
            );
        // The fault's fields (--hdf5): the square's grid with its rim, its quadrilaterals.
        let fault = FaultSize::of((cells.sqrt() + 1.0).powi(2), (cells, 4.0));
        self.flags().plan(plan, outputs(), run.fingerprint(), fault)
    }
}

crate::seas_args::entry_points!(Args, run, "seas_bp8", "FieldWriters::fault_3d");

fn run(args: Args, folder: Prepared) -> Result<(), AnyError> {
    let run = args.settings;
    let source = run.source;
    let policy = run.overpressure();
    let bp8 = SeasBp8::default();
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let field = bp8.pressure(source, run.dx)?;
    let friction_pressure = bp8.friction_pressure(field.clone(), policy)?;
    let setup = run.seas_setup(args.header.modeler.clone(), args.header.date_or_today());
    let fingerprint = run.fingerprint();
    let mut options = bp8.fault_ode_options(run.tolerance)?;
    options.parallelism = rsf::Parallelism::rayon(args.threads);
    options.integrator = run.integrator;
    let kernel = match run.volume_grid()? {
        None => "whole space (FFT boundary elements)",
        Some(_) => "finite elements",
    };
    println!(
        "BP8-QD-{}, Δx = {} m, {kernel}, {policy:?}; on {}",
        source.name(),
        run.dx,
        machine()
    );
    let mut ode = run.fault_ode(options, friction_pressure, elimination(&args.job.limits))?;
    let volume = run.volume_grid()?;
    if let Some(grid) = volume {
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
                seconds: BP8_SECONDS_PER_DAY,
                symbol: "d",
            },
            "BP8",
        ),
        started: (clock, cpu0),
    };
    let output = |model: &rsf::Model<3, 3>| Ok(run.output(&args.out, model, field, setup)?);
    let keys = serde_json::json!({
        "problem": format!("BP8-QD-{}", source.name()),
        "settings": run.summary(),
        "overpressure": format!("{policy:?}"),
        "fe_box_half_width_m": volume.map(|g| g.root_and_far().1),
    });
    run_square_fault(settings, &mut ode, output, keys)?;
    Ok(())
}
