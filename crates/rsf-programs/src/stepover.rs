//! A stepover between two strike-slip strands in map view (plane strain, quasi-dynamic;
//! docs/fault-networks.md): the fault network `rsf_scenes::Stepover` — two parallel
//! strands with SEAS BP1's friction along strike from their tips, loaded by creep beyond
//! their far ends and by the box's plate motion — integrated by the fault ODE over many
//! cycles, with the catalogue of which strand each event ruptured.
//!
//! ```sh
//! cargo run --release --example stepover -- --gap-km 1 --overlap-km 2 --out out/stepover
//! cargo run --release --example stepover -- --gap-km 4 --dx 50 --end-years 1500 --out out/stepover_4km
//! ```
//!
//! Writes to `--out`: a station file per strand and distance from its tip
//! (`{south,north}_sNN.Nkm.csv`: step, time, slip, slip rate, shear traction, state;
//! rsf::observe::FaultStations), the catalogue `catalogue.csv` (every event: onset, end,
//! the strand and place where it nucleated, the strands it ruptured, per strand its peak
//! slip rate, moment and rupture time; rsf::observe::FaultCatalogue), `summary.json` (the
//! scene, the run, the events, how many jumped the step), and the figure `catalogue.png`
//! (each event's strands against time).
//!
//! Runs: `--checkpoint-every N`, `--resume FILE`, `--allow-change`, `--max-steps N` as the
//! SEAS programs (the files and the catalogue continue byte for byte), `--overwrite`.

use std::path::PathBuf;
use std::time::Instant;

use crate::config::ConfigArgs;
use crate::estimates::{csv_row_bytes, operator_bytes, FIGURE_BYTES, SEAS_BYTES_PER_NODE};
use crate::fields::FaultSize;
use crate::guard::{number, written, AnyError, Plan, Prepared};
use crate::network::{run_network, NetworkEnd, NetworkRun};
use crate::{cpu_seconds, machine};
use clap::Parser;
use rsf_scenes::{KernelChoice, RunConfig, Stepover, StepoverRun};

/// A stepover between two strike-slip strands (map view, plane strain).
#[derive(Parser)]
#[command(version)]
pub struct Args {
    /// The run's settings (`rsf_scenes::StepoverRun`: these flags, or `--config`'s keys).
    #[command(flatten)]
    pub(crate) settings: StepoverRun,
    #[command(flatten)]
    config: ConfigArgs,
    /// Output folder.
    #[arg(long, default_value = "out/stepover")]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out` (without it, a folder holding any
    /// rsf program's run is refused and left untouched).
    #[arg(long)]
    overwrite: bool,
    /// Threads of each evaluation (the same bits for every value). Default: every core.
    #[arg(long, default_value_t = rsf::Parallelism::available_cores())]
    threads: usize,
    #[command(flatten)]
    pub(crate) job: crate::seas_args::JobArgs,
}

/// The files a run writes into `--out`.
fn outputs(stepover: &Stepover) -> Vec<String> {
    crate::network::network_outputs(&stepover.stations())
}

/// Bytes per station row (step, time, slip, slip rate, traction, state).
fn station_row_bytes() -> f64 {
    csv_row_bytes(6)
}

crate::seas_args::configured_program!(Args, "stepover", job);

impl Args {
    /// The plan of the checked settings.
    fn planned(&self) -> Result<Plan, AnyError> {
        let run = &self.settings;
        let (stepover, grid) = (run.scene(), run.grid());
        // The graded mesh in closed form (as Stepover::mesh grades it).
        let [x_half, _] = stepover.box_half(&grid);
        let reach = x_half - grid.domain;
        let len = rsf::fem::geometric_grading_len;
        let nx = 2.0 * len(grid.dx, reach, grid.ratio, x_half) - 1.0;
        let g = 0.5 * stepover.gap;
        let ny = 2.0 * len(grid.dx, 2.0 * grid.dx, grid.ratio, grid.domain)
            + 2.0 * len(grid.dx, (2.0 * grid.dx).min(g), grid.ratio, g)
            - 3.0;
        let nodes = nx * ny;
        // Both strands' slip nodes across the box.
        let fault_nodes = 2.0 * (x_half + x_half) / grid.dx;
        let hierarchical = run.kernel == KernelChoice::Hierarchical;
        let memory = nodes * SEAS_BYTES_PER_NODE + 2.0 * operator_bytes(fault_nodes, hierarchical);
        // Rows: every step, a few hundred steps per year with events (the BP1 programs'
        // rate is an upper bound for the stations written at every step).
        let stations = stepover.stations().len() as f64;
        let rows = run.end_years * 400.0 + 1e4;
        let plan = Plan::new()
            .memory(
                memory,
                "--dx, --domain-km, --ratio, --strand-km",
                format!(
                    "the stepover on dx = {} m: about {nodes:.3e} nodes, {fault_nodes:.3e} on \
                     the strands",
                    number(run.dx)
                ),
            )
            .output(
                stations * rows * station_row_bytes() + FIGURE_BYTES + 1e7,
                "--end-years",
                format!(
                    "{} years of {stations} station files",
                    written(run.end_years)
                ),
            );
        // The faults' fields (--hdf5): both strands' nodes across the box, the segments between them.
        let fault = FaultSize::of(fault_nodes, (fault_nodes, 2.0));
        self.flags()
            .plan(plan, outputs(&stepover), run.fingerprint(), fault)
    }
}

crate::seas_args::entry_points!(Args, run, "stepover", "FieldWriters::fault_2d");

fn run(args: Args, folder: Prepared) -> Result<(), AnyError> {
    let run = args.settings;
    let (stepover, grid) = (run.scene(), run.grid());
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let model = stepover.model(&grid)?;
    println!(
        "stepover: gap {} km, overlap {} km, strands {} km, Δx = {} m, {} nodes, {} frictional \
         nodes ({} on the south strand); on {}",
        run.gap_km,
        run.overlap_km,
        run.strand_km,
        run.dx,
        model.vertices.len(),
        model.frictional_boundary.len(),
        model.frictional_boundary.along_fault(0).len(),
        machine()
    );
    let mut options = stepover.params.fault_ode_options(run.tolerance)?;
    options.kernel = run.fault_kernel()?;
    options.integrator = run.integrator;
    options.parallelism = rsf::Parallelism::rayon(args.threads);
    let mut ode = stepover.fault_ode(model, options)?;
    println!("S: {}", ode.kernel_report());
    println!(
        "set-up: wall {:.1} s, CPU {:.1} s",
        clock.elapsed().as_secs_f64(),
        cpu_seconds() - cpu0
    );
    let rigidity = stepover.params.shear_modulus();
    let network = NetworkRun::of(args.flags(), &folder, run.end_years, rigidity);
    let stations = stepover.stations();
    let outcome = run_network(&mut ode, &stations, run.fingerprint(), network, |w, t| {
        w.fault_2d(t)
    })?;
    crate::network::finish(
        NetworkEnd::of(&args.out, &outcome, &ode, run.integrator, (clock, cpu0)),
        serde_json::json!({ "program": "stepover", "scene": stepover, "grid": grid }),
        serde_json::json!({ "settings": run.summary() }),
    )
}
