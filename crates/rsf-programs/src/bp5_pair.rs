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
//! `--resume FILE`, `--allow-change`, `--max-steps N`, `--overwrite`.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use crate::estimates::{csv_row_bytes, operator_bytes, FIGURE_BYTES};
use crate::guard::{
    flag_range, in_range, number, written, AnyError, Folder, Limits, Plan, Prepared, Program,
};
use crate::{cpu_seconds, machine};
use clap::Parser;
use rsf::checkpoint::Fingerprint;
use rsf::halfspace_operator::ElementOptions;
use rsf_scenes::{Bp5Pair, SeasBp5, SeasBp5Grid};

/// The elastic operator of a two-strand run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PairKernel {
    /// Both strands alone in Okada's half-space (boundary elements).
    Okada,
    /// Both strands inside a finite-element box, condensed onto them.
    Fe,
}

impl std::fmt::Display for PairKernel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            PairKernel::Okada => "okada",
            PairKernel::Fe => "fe",
        })
    }
}

flag_range!(
    DX,
    DX_HELP = "Cell size on the strands (m); must divide l_f = 100 km and W_f = 40 km (`fe`: and half the separation)",
    [250, 20e3]
);
flag_range!(
    SEPARATION_KM,
    SEPARATION_KM_HELP = "Distance between the strands across strike (km); `fe`: half of it a whole number of `--dx`",
    [1e-3, 1e3]
);
flag_range!(
    DOMAIN_KM,
    DOMAIN_KM_HELP = "`fe`: distance from the strands to the box's far faces, and its depth (km); the graded box's root cubes (edge dx·2^k ≤ 64 km) within the mesh's cell limit too (about 3000 km at --dx 2000: a larger box is refused naming --domain-km)",
    [75, 1e4]
);
flag_range!(
    RATIO,
    RATIO_HELP = "`fe`: growth of the spacing away from the strands' rate-and-state regions",
    [1, 2]
);
flag_range!(END_YEARS, END_YEARS_HELP = "End time (years)", [1e-9, 1e5]);
flag_range!(
    pub(crate) EPSILON,
    EPSILON_HELP = "Relative accuracy ε of the ℋ-matrices (above 4 096 unknowns)",
    [1e-14, 1e-2]
);

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
    /// The elastic operator: `okada` or `fe`.
    #[arg(long, value_enum, default_value_t = PairKernel::Okada)]
    kernel: PairKernel,
    #[arg(long, default_value_t = 2000.0, allow_negative_numbers = true, help = DX_HELP)]
    dx: f64,
    #[arg(long, default_value_t = 8.0, allow_negative_numbers = true, help = SEPARATION_KM_HELP)]
    separation_km: f64,
    #[arg(long, default_value_t = 400.0, allow_negative_numbers = true, help = DOMAIN_KM_HELP)]
    domain_km: f64,
    #[arg(long, default_value_t = 1.3, allow_negative_numbers = true, help = RATIO_HELP)]
    ratio: f64,
    /// `fe`: fill-reducing ordering of the volume's elimination, `nested-dissection`
    /// (METIS; the default where it is built, as in the examples: with two planes through
    /// the box AMD's fill is ten times larger — 37 GB against 2.7 GB at 4 km) or `amd`.
    #[arg(long, default_value = DEFAULT_ORDERING)]
    ordering: rsf::fault_ode::InteriorOrdering,
    #[arg(long, default_value_t = 1800.0, allow_negative_numbers = true, help = END_YEARS_HELP)]
    end_years: f64,
    /// Tolerance of the fault ODE (local error per step: tolerance · L in slip, tolerance in
    /// ln θ), in (2.220446049250313e-16, 1) (open: from f64::EPSILON to 1).
    #[arg(long, default_value_t = 1e-6, allow_negative_numbers = true)]
    tolerance: f64,
    #[command(flatten)]
    integrator: crate::IntegratorArgs,
    #[arg(long, default_value_t = 1e-6, allow_negative_numbers = true, help = EPSILON_HELP)]
    epsilon: f64,
    /// Threads of each evaluation (the same bits for every value). Default: every core.
    #[arg(long, default_value_t = rsf::Parallelism::available_cores())]
    threads: usize,
    /// `--checkpoint-every N`, `--resume FILE`, `--allow-change`, `--max-steps N`.
    #[command(flatten)]
    run: crate::ResumeArgs,
    #[command(flatten)]
    limits: Limits,
}

/// The scene and the volume's grid of the flags.
fn scene(args: &Args) -> (Bp5Pair, SeasBp5Grid) {
    let pair = Bp5Pair {
        bp5: SeasBp5::default(),
        separation: args.separation_km * 1e3,
    };
    let grid = SeasBp5Grid {
        dx: args.dx,
        domain: args.domain_km * 1e3,
        ratio: args.ratio,
        ..SeasBp5Grid::default()
    };
    (pair, grid)
}

/// The default ordering: METIS's nested dissection where it is built.
const DEFAULT_ORDERING: &str = if cfg!(feature = "metis") {
    "nested-dissection"
} else {
    "amd"
};

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
    let mut names: Vec<String> = pair
        .stations()
        .iter()
        .map(|s| format!("{}_{}.csv", s.fault, s.label))
        .collect();
    names.extend(crate::network::NETWORK_FILES.map(String::from));
    names.push(SETUP_FILE.into());
    names
}

impl Args {
    /// What a checkpoint continues: the two strands, the grid and what changes the
    /// trajectory (the plan's too: a checkpoint is checked against it before the folder
    /// changes).
    ///
    /// # Errors
    /// None today; a `Result` as the other programs' (the plan's `?`).
    fn fingerprint(&self) -> Result<Fingerprint, AnyError> {
        let (pair, _) = scene(self);
        Ok(self.integrator.fingerprint(
            crate::cli::with_box_and_end(
                Fingerprint::of_serialized(&pair).with("kernel", self.kernel),
                (self.dx, self.domain_km, self.ratio),
                self.end_years,
                self.tolerance,
            )
            .with("epsilon", self.epsilon)
            .with("ordering", self.ordering),
        ))
    }
}

impl Program for Args {
    const NAME: &'static str = "bp5_pair";

    fn limits(&self) -> Limits {
        self.limits
    }

    fn plan(&self) -> Result<Plan, AnyError> {
        in_range("--end-years", self.end_years, END_YEARS, "years")?;
        in_range("--dx", self.dx, DX, "m")?;
        in_range("--separation-km", self.separation_km, SEPARATION_KM, "km")?;
        in_range("--domain-km", self.domain_km, DOMAIN_KM, "km")?;
        in_range("--ratio", self.ratio, RATIO, "the growth of the spacing")?;
        in_range("--epsilon", self.epsilon, EPSILON, "a relative accuracy")?;
        let (pair, grid) = scene(self);
        pair.bp5
            .cells(self.dx)
            .map_err(|e| format!("--dx {}: {e}", written(self.dx)))?;
        pair.validate()
            .map_err(|e| format!("--separation-km {}: {e}", written(self.separation_km)))?;
        crate::cli::for_flag(
            "--tolerance",
            "tolerance",
            pair.bp5.fault_ode_options(self.tolerance),
        )?;
        let cells = 2.0 * (pair.bp5.l_f / self.dx) * (pair.bp5.w_f / self.dx);
        let unknowns = 2.0 * cells;
        let hierarchical = unknowns > 4096.0;
        // setup.bin, the elimination kept in --out (0 without it).
        let mut setup_file = 0.0;
        let memory = match self.kernel {
            PairKernel::Okada => operator_bytes(unknowns, hierarchical) + cells * 2e3,
            PairKernel::Fe => {
                let half = 0.5 * self.separation_km * 1e3 / self.dx;
                if (half - half.round()).abs() > 1e-9 * half.max(1.0) || half < 1.0 {
                    return Err(format!(
                        "--separation-km {}: half of it must be a whole number (≥ 1) of --dx",
                        written(self.separation_km)
                    )
                    .into());
                }
                let peak = |vertices: f64| {
                    pair_fe_peak(vertices, self.ordering) + operator_bytes(unknowns, hierarchical)
                };
                // Refused unmeshed where a lower bound of the pair's vertices (BP5's
                // one-plane mesh's, by arithmetic; an oversize octree refused naming
                // --domain-km) is already too large; else the pair's graded mesh counted.
                let fewest = crate::seas_bp5::graded_mesh_fewest_vertices(&grid, self.domain_km)?;
                let limit = self.limits.max_memory_gb * 1e9;
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
                let nodes = (pair.bp5.l_f / self.dx + 1.0) * (pair.bp5.w_f / self.dx + 1.0);
                setup_file = crate::estimates::setup_file_bytes(4.0 * nodes, vertices);
                peak(vertices)
            }
        };
        let stations = pair.stations().len() as f64;
        let rows = self.end_years * 100.0 + 1e4;
        let names = outputs(&pair);
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        Ok(Plan::new()
            .pool(self.threads)
            .memory(
                memory,
                "--dx, --kernel, --domain-km, --ratio",
                format!(
                    "two strands of {cells:.3e} cells at dx = {} m ({})",
                    number(self.dx),
                    self.kernel
                ),
            )
            .output(
                stations * rows * csv_row_bytes(7) + FIGURE_BYTES + 1e7,
                "--end-years",
                format!(
                    "{} years of {stations} station files",
                    written(self.end_years)
                ),
            )
            .output(
                setup_file,
                "--dx, --domain-km, --ratio",
                format!("the elimination kept in {SETUP_FILE}"),
            )
            .folder(
                self.run
                    .folder(Folder::new("--out", &self.out, &names).overwrite(self.overwrite))
                    .fingerprint(self.fingerprint()?),
            ))
    }
}

/// The program `bp5_pair` (`cargo run --release --example bp5_pair -- --out DIR …`).
pub fn main() -> ExitCode {
    crate::guard::main(run)
}

fn run(args: Args, folder: Prepared) -> Result<(), AnyError> {
    let (pair, grid) = scene(&args);
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let mut options = pair.bp5.fault_ode_options(args.tolerance)?;
    options.integrator = args.integrator.integrator;
    options.parallelism = rsf::Parallelism::rayon(args.threads);
    options.kernel = rsf::fault_ode::FaultKernel::matching(args.epsilon);
    let mut ode = match args.kernel {
        PairKernel::Okada => {
            let element_options = ElementOptions {
                epsilon: args.epsilon,
                ..ElementOptions::default()
            };
            pair.bem_fault_ode(args.dx, options, &element_options)?
        }
        PairKernel::Fe => {
            let model = pair.fe_model(&grid)?;
            println!(
                "the box: {} vertices, {} frictional nodes",
                model.vertices.len(),
                model.frictional_boundary.len()
            );
            options.ordering = args.ordering;
            // The Schur complement alone (no factor kept), its elimination checkpointed in
            // the run folder (as seas_bp5's).
            let path = args.out.join(SETUP_FILE);
            if args.run.resume.is_none() {
                match std::fs::remove_file(&path) {
                    Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(e.into()),
                    _ => {}
                }
            }
            let setup = rsf::fault_ode::SchurOnlySetup {
                watch_vertices: Vec::new(),
                checkpoint: Some(rsf::direct::CheckpointPolicy::new(&path)),
                max_bytes: Some((args.limits.max_memory_gb * 1e9).min(usize::MAX as f64) as usize),
                progress: None,
            };
            pair.fe_fault_ode_schur_only(model, options, setup)
                .map_err(|e| crate::run_folder::kept_setup_hint(e, &path, &args.run.allow_change))?
        }
    };
    let fb = &ode.model().frictional_boundary;
    println!(
        "two BP5 strands {} km apart, {} kernel, Δx = {} m, {} + {} frictional nodes; on {}",
        args.separation_km,
        args.kernel,
        args.dx,
        fb.along_fault(0).len(),
        fb.along_fault(1).len(),
        machine()
    );
    println!("S: {}", ode.kernel_report());
    let setup = (clock.elapsed().as_secs_f64(), cpu_seconds() - cpu0);
    println!("set-up: wall {:.1} s, CPU {:.1} s", setup.0, setup.1);
    let fingerprint = args.fingerprint()?;
    let outcome = crate::network::run_network(
        &mut ode,
        &pair.stations(),
        fingerprint,
        crate::network::NetworkRun {
            out: &args.out,
            fresh: folder.mode(),
            end_years: args.end_years,
            resume: &args.run,
            label: "bp5_pair",
            rigidity: pair.bp5.shear_modulus(),
        },
    )?;
    crate::network::finish(
        crate::network::NetworkEnd {
            out: &args.out,
            outcome: &outcome,
            evaluations: ode.evaluations(),
            integrator: args.integrator.summary(Some(ode.integrator_stats())),
            started: (clock, cpu0),
        },
        serde_json::json!({
            "program": "bp5_pair",
            "scene": pair,
            "kernel": args.kernel,
            "grid": grid,
        }),
        serde_json::json!({
            "end_years": args.end_years,
            "tolerance": args.tolerance,
            "epsilon": args.epsilon,
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
