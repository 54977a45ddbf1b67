//! Two parallel strike-slip faults with SEAS BP5's physics (not a benchmark;
//! docs/fault-networks.md, "Two parallel faults in 3-D"): `rsf_scenes::Bp5Pair`, BP5's fault
//! repeated `--separation-km` apart across strike, each strand loaded at the plate rate, run
//! over many cycles with the boundary-element kernel (`--kernel okada`: both strands' cells
//! in one operator in Okada's half-space) or the finite-element volume (`--kernel fe`: both
//! planes in one graded box), with the catalogue of which strand each event ruptured.
//!
//! ```sh
//! cargo run --release --example bp5_pair -- --kernel okada --dx 2000 --out out/bp5_pair_okada
//! cargo run --release --example bp5_pair -- --kernel fe --dx 2000 --out out/bp5_pair_fe
//! ```
//!
//! Writes to `--out`: a station file per strand and point (`{west,east}_st{x₂}dp{x₃}.csv`:
//! step, time, the two slip components, slip rate, shear traction, state), `catalogue.csv`,
//! `summary.json` and `catalogue.png`, as `stepover` does. Runs: `--checkpoint-every N`,
//! `--resume FILE`, `--allow-change`, `--max-steps N`, `--overwrite`. The settings are one
//! struct, `rsf_scenes::Bp5PairRun` (docs/design.md, "One run configuration"): the flags,
//! the keys of `--config FILE.toml`, the checkpoint's fingerprint and `summary.json`'s
//! `settings`.

use std::path::PathBuf;
use std::time::Instant;

use crate::config::ConfigArgs;
use crate::estimates::{csv_row_bytes, operator_bytes, FIGURE_BYTES};
use crate::fields::FaultSize;
use crate::guard::{number, written, AnyError, Plan, Prepared};
use crate::network::{run_network, NetworkEnd, NetworkRun};
use crate::{cpu_seconds, machine};
use clap::Parser;
use rsf::fault_ode::InteriorOrdering;
use rsf::halfspace_operator::ElementOptions;
use rsf_scenes::{Bp5Kernel, Bp5Pair, Bp5PairRun, RunConfig};

/// `--epsilon`'s range ([`bp5_pair_ranges::EPSILON`](rsf_scenes::bp5_pair_ranges::EPSILON)).
#[cfg(test)]
pub(crate) const EPSILON: (f64, f64) = rsf_scenes::bp5_pair_ranges::EPSILON;

/// Two parallel strike-slip faults with SEAS BP5's physics.
#[derive(Parser)]
#[command(version)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/bp5_pair")]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out`.
    #[arg(long)]
    overwrite: bool,
    /// The run's settings (`rsf_scenes::Bp5PairRun`: these flags, or `--config`'s keys).
    #[command(flatten)]
    pub(crate) settings: Bp5PairRun,
    #[command(flatten)]
    config: ConfigArgs,
    /// Threads of each evaluation (the same bits for every value). Default: every core.
    #[arg(long, default_value_t = rsf::Parallelism::available_cores())]
    threads: usize,
    #[command(flatten)]
    pub(crate) job: crate::seas_args::JobArgs,
}

/// The run's peak (bytes) of `--kernel fe` with nested dissection, the anchor of its
/// estimate: measured 3.3 GB at 2 km (the ℋ-matrix of `S` included; AMD EPYC,
/// docs/fault-networks.md) with a margin of 1.25, at 192 825 vertices of the graded mesh
/// before the strands split it (`Bp5Pair::fe_mesh_vertices`; 245 907 after), growing like
/// `vertices^1.5` (BP5's graded box with nested dissection; `crate::seas_bp5`): at 4 km,
/// 171 071 vertices, that gives 3.45 GB against the measured 2.7 GB. The estimate before it
/// (the tensor grid's closed form, twice) gave 19.3 GB at 2 km and refused the defaults.
const PAIR_ND_PEAK_AT_2_KM: f64 = 1.25 * 3.3e9;
/// See [`PAIR_ND_PEAK_AT_2_KM`].
const PAIR_VERTICES_AT_2_KM: f64 = 192_825.0;
/// AMD's fill over nested dissection's on the pair's box: 37 GB against 2.7 GB at 4 km
/// (measured; the `--ordering` flag's documentation), rounded up.
const PAIR_AMD_OVER_ND: f64 = 14.0;

/// The set-up's and run's peak (bytes) of `--kernel fe` on a graded mesh of `vertices`
/// vertices with `ordering` (the fault operator's storage is the caller's).
fn pair_fe_peak(vertices: f64, ordering: rsf::fault_ode::InteriorOrdering) -> f64 {
    let nd = PAIR_ND_PEAK_AT_2_KM * (vertices / PAIR_VERTICES_AT_2_KM).powf(1.5);
    match ordering {
        rsf::fault_ode::InteriorOrdering::NestedDissection => nd,
        _ => PAIR_AMD_OVER_ND * nd,
    }
}

/// The elimination's checkpoint (`--kernel fe`).
const SETUP_FILE: &str = "setup.bin";

/// The files a run writes into `--out`.
fn outputs(pair: &Bp5Pair) -> Vec<String> {
    let mut names = crate::network::network_outputs(&pair.stations());
    names.push(SETUP_FILE.into());
    names
}

impl Args {
    /// The settings as the run uses them: the ordering the build's fastest where unset
    /// (nested dissection where METIS is built, `InteriorOrdering::fastest_built`).
    fn resolved(&self) -> Bp5PairRun {
        self.settings.resolved(InteriorOrdering::fastest_built())
    }
}

crate::seas_args::configured_program!(Args, "bp5_pair", job);

impl Args {
    /// The plan of the checked settings.
    fn planned(&self) -> Result<Plan, AnyError> {
        let run = self.resolved();
        let (pair, grid) = (run.scene(), run.grid());
        let cells = 2.0 * (pair.bp5.l_f / run.dx) * (pair.bp5.w_f / run.dx);
        let unknowns = 2.0 * cells;
        let hierarchical = unknowns > 4096.0;
        // setup.bin, the elimination kept in --out (0 without it).
        let mut setup_file = 0.0;
        let memory = match run.kernel {
            Bp5Kernel::Okada => operator_bytes(unknowns, hierarchical) + cells * 2e3,
            Bp5Kernel::Fe => {
                let ordering = run.ordering.unwrap_or(InteriorOrdering::Amd);
                let peak = |vertices: f64| {
                    pair_fe_peak(vertices, ordering) + operator_bytes(unknowns, hierarchical)
                };
                // Refused unmeshed where a lower bound of the pair's vertices (BP5's
                // one-plane mesh's, by arithmetic; an oversize octree refused naming
                // --domain-km) is already too large; else the pair's graded mesh counted.
                let fewest = crate::seas_bp5::graded_mesh_fewest_vertices(&grid, run.domain_km)?;
                let limit = self.job.limits.max_memory_gb * 1e9;
                let vertices = if peak(fewest) > limit {
                    fewest
                } else {
                    crate::cli::for_fields(
                        &crate::cli::FE_GRID_FLAGS,
                        pair.fe_mesh_vertices(&grid),
                    )? as f64
                };
                // Each strand's nodes (its rate-and-state region's grid, edges included),
                // two slip unknowns each; no watched vertex.
                let nodes = (pair.bp5.l_f / run.dx + 1.0) * (pair.bp5.w_f / run.dx + 1.0);
                setup_file = crate::estimates::setup_file_bytes(4.0 * nodes, vertices);
                peak(vertices)
            }
        };
        let stations = pair.stations().len() as f64;
        let rows = run.end_years * 100.0 + 1e4;
        let plan = Plan::new()
            .memory(
                memory,
                "--dx, --kernel, --domain-km, --ratio",
                format!(
                    "two strands of {cells:.3e} cells at dx = {} m ({})",
                    number(run.dx),
                    kernel_name(run.kernel)
                ),
            )
            .output(
                stations * rows * csv_row_bytes(7) + FIGURE_BYTES + 1e7,
                "--end-years",
                format!(
                    "{} years of {stations} station files",
                    written(run.end_years)
                ),
            )
            .output(
                setup_file,
                "--dx, --domain-km, --ratio",
                format!("the elimination kept in {SETUP_FILE}"),
            );
        // The faults' fields (--hdf5): both strands' grids with their rims, their quadrilaterals.
        let rims = 2.0 * (pair.bp5.l_f / run.dx + pair.bp5.w_f / run.dx + 1.0);
        let fault = FaultSize::of(cells + rims, (cells, 4.0));
        self.flags()
            .plan(plan, outputs(&pair), run.fingerprint(), fault)
    }
}

/// The kernel as its flag's value (`okada`, `fe`).
fn kernel_name(kernel: Bp5Kernel) -> &'static str {
    match kernel {
        Bp5Kernel::Okada => "okada",
        Bp5Kernel::Fe => "fe",
    }
}

crate::seas_args::entry_points!(Args, run, "bp5_pair", "FieldWriters::fault_3d");

fn run(args: Args, folder: Prepared) -> Result<(), AnyError> {
    let run = args.resolved();
    let (pair, grid) = (run.scene(), run.grid());
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let options = run.fault_ode_options(args.threads)?;
    let mut ode = match run.kernel {
        Bp5Kernel::Okada => {
            let element_options = ElementOptions {
                epsilon: run.epsilon,
                ..ElementOptions::default()
            };
            pair.bem_fault_ode(run.dx, options, &element_options)?
        }
        Bp5Kernel::Fe => {
            let model = pair.fe_model(&grid)?;
            println!(
                "the box: {} vertices, {} frictional nodes",
                model.vertices.len(),
                model.frictional_boundary.len()
            );
            // The Schur complement alone (no factor kept), its elimination checkpointed in
            // the run folder (as seas_bp5's).
            let path = args.out.join(SETUP_FILE);
            if args.job.run.resume.is_none() {
                match std::fs::remove_file(&path) {
                    Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(e.into()),
                    _ => {}
                }
            }
            let setup = rsf::fault_ode::SchurOnlySetup {
                watch_vertices: Vec::new(),
                checkpoint: Some(rsf::direct::CheckpointPolicy::new(&path)),
                max_bytes: Some(
                    (args.job.limits.max_memory_gb * 1e9).min(usize::MAX as f64) as usize
                ),
                progress: None,
            };
            pair.fe_fault_ode_schur_only(model, options, setup)
                .map_err(|e| {
                    crate::run_folder::kept_setup_hint(e, &path, &args.job.run.allow_change)
                })?
        }
    };
    let fb = &ode.model().frictional_boundary;
    println!(
        "two BP5 strands {} km apart, {} kernel, Δx = {} m, {} + {} frictional nodes; on {}",
        run.separation_km,
        kernel_name(run.kernel),
        run.dx,
        fb.along_fault(0).len(),
        fb.along_fault(1).len(),
        machine()
    );
    println!("S: {}", ode.kernel_report());
    let setup = (clock.elapsed().as_secs_f64(), cpu_seconds() - cpu0);
    println!("set-up: wall {:.1} s, CPU {:.1} s", setup.0, setup.1);
    let network = NetworkRun::of(
        args.flags(),
        &folder,
        run.end_years,
        pair.bp5.shear_modulus(),
    );
    let stations = pair.stations();
    let outcome = run_network(&mut ode, &stations, run.fingerprint(), network, |w, t| {
        w.fault_3d(t)
    })?;
    crate::network::finish(
        NetworkEnd::of(&args.out, &outcome, &ode, run.integrator, (clock, cpu0)),
        serde_json::json!({
            "program": "bp5_pair",
            "scene": pair,
            "grid": grid,
        }),
        serde_json::json!({
            "settings": run.summary(),
            "setup_wall_seconds": setup.0,
            "setup_cpu_seconds": setup.1,
            "kernel_report": ode.kernel_report().to_string(),
        }),
    )
}

#[cfg(test)]
mod tests {
    /// The plans of the largest boxes (`--domain-km` 1e4, the range's end, and the largest
    /// the octree's root cubes admit) at every `--dx` whose half separation (4 km) it
    /// divides: each returns, refused naming the flag or admitted within `--max-memory-gb`;
    /// the time of each is printed, not asserted (as `seas_bp5`'s).
    #[test]
    fn the_plans_of_the_largest_boxes_return_with_their_estimates() {
        let dx = [250.0, 500.0, 1000.0, 2000.0, 4000.0];
        crate::seas_bp5::plans_of_the_largest_boxes::<super::Args>(&dx);
    }
}
