//! SEAS BP5-QD (a vertical strike-slip fault in a half-space, two slip components, 3-D;
//! docs/seas-bp5.md), integrated by the fault ODE with either kernel: `--kernel okada`
//! (the default) a fault alone with Okada's half-space operator, loaded by back slip;
//! `--kernel fe` the finite-element volume model (`SeasBp5::fe_model`: the fault plane
//! inside a graded box, creeping outside the rate-and-state region, the far faces moving
//! with their side) condensed onto the fault.
//!
//! ```sh
//! cargo run --release --example seas_bp5 -- --out out/bp5            # Δx = 2 km, 1800 years
//! cargo run --release --example seas_bp5 -- --dx 1000 --out out/bp5_1km --threads 2
//! cargo run --release --example seas_bp5 -- --kernel fe --dx 2500 --out out/bp5_fe
//! ```
//!
//! The scene is `rsf_scenes::SeasBp5`: the rate-and-state region (100 km × 40 km) in
//! square cells of size `--dx`, each the centre of a constant-slip element of
//! `rsf::halfspace_operator::HalfSpaceOperator::fault_alone` (dense up to 4 096
//! unknowns, an ℋ-matrix of accuracy `--epsilon` beyond). The rest of the fault plane
//! creeps at V_p: back slip (`rsf::fault_alone::FaultAlone`) represents it exactly.
//!
//! Writes the benchmark's files to `--out` (`rsf_seas::SeasBp5Output`: the ten
//! on-fault stations `fltst_strk±XXdp±YY`, the nine off-fault stations
//! `blkst_strk±XXfn±YYdp±ZZ`, `global.dat`, the slip and stress profiles, `rupture.dat`,
//! the event catalogue `events.csv`), `summary.json` and the figure `overview.png`
//! (slip₂ along dip at x₂ = 0; the maximum slip rate against time), and prints the
//! ruptures and their recurrence intervals.
//!
//! Runs: `--checkpoint-every N` (a checkpoint `checkpoint.bin` every N steps, the files
//! and their resume log `bp5_resume.json` written at the same steps), `--resume FILE`
//! (continues the files in `--out` from a checkpoint of this run: the same bytes as an
//! uninterrupted run), `--max-steps N` (stop after step N in total, with a checkpoint),
//! `--overwrite` (a folder of another run is refused, and left untouched, otherwise).
//!
//! On MPI ranks: the `rsf-mpi` crate's `seas_bp5` runs [`main_on_ranks`] (every evaluation
//! shared by the ranks, the files written by rank 0; docs/scaling.md, "The fault ODE on MPI
//! ranks").

use std::cell::RefCell;
use std::path::PathBuf;
use std::process::ExitCode;
use std::rc::Rc;
use std::time::Instant;

use crate::estimates::{operator_bytes, seas_output_bytes};
use crate::guard::{flag, in_range, AnyError, Folder, Limits, Plan, Prepared, Processes, Program};
use crate::memory::StageMemory;
use crate::{cpu_seconds, machine};
use clap::Parser;
use rsf::checkpoint::Fingerprint;
use rsf::direct::{CheckpointPolicy, Progress};
use rsf::fault_ode::{FaultKernel, SchurOnlySetup, SetupProgress};
use rsf::observe::{Observer, TimeUnit};
use rsf::run_folder::{read_checkpoint, step_cap_error, until, RunFolder};
use rsf::Stepping;
use rsf_scenes::{FaultZone, SeasBp5, SeasBp5Grid, SeasBp5Mesh};
use rsf_seas::{
    utc_date_today, SeasBp5Output, SeasLayout, SeasSampling, SeasSetup, SEAS_BP5_RESUME_LOG,
    SECONDS_PER_YEAR,
};
use std::ops::ControlFlow;

/// SEAS BP5-QD with the boundary-element (Okada) half-space operator.
#[derive(Parser)]
#[command(version)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/seas_bp5")]
    out: PathBuf,
    /// The elastic operator: `okada` (a fault alone in a half-space, boundary elements)
    /// or `fe` (the finite-element volume model condensed onto the fault).
    #[arg(long, value_enum, default_value_t = Kernel::Okada)]
    kernel: Kernel,
    /// Cell size on the fault (m); must divide 100 km and 40 km (`fe`: 50 km and 40 km).
    #[arg(long, default_value_t = 2000.0)]
    dx: f64,
    /// `fe`: distance from the fault to the box's far faces, and its depth (km) [default:
    /// 400].
    #[arg(long)]
    domain_km: Option<f64>,
    /// `fe`: growth of the spacing away from the rate-and-state region [default: 1.3].
    #[arg(long)]
    ratio: Option<f64>,
    /// `fe`: the volume's mesh, `graded` (an octree of Kuhn cubes refined towards the fault's
    /// rate-and-state region and the stations, growing in every direction) or `tensor`
    /// (a tensor grid graded axis by axis) [default: graded].
    #[arg(long, value_enum)]
    mesh: Option<MeshArg>,
    /// `fe`: a compliant fault zone of this total width (km) around the rate-and-state
    /// region (`|x₁| ≤ width/2`; a whole number of `2 dx`), not part of the benchmark
    /// (docs/seas-bp5.md, "A compliant fault zone"); needs `--fault-zone-rigidity`.
    #[arg(long)]
    fault_zone_width_km: Option<f64>,
    /// `fe`: the fault zone's shear modulus over the host's, in (0, 1].
    #[arg(long)]
    fault_zone_rigidity: Option<f64>,
    /// `fe`: how the volume is condensed onto the fault: `schur-only` (the Schur complement
    /// alone, no factor kept; its elimination checkpointed in `--out`) or `factor` (the
    /// volume's whole factor held through the run) [default: schur-only].
    #[arg(long, value_enum)]
    condensation: Option<Condensation>,
    /// `fe`: print each set-up stage's own peak memory (the process's peak is reset before
    /// every stage, so `/usr/bin/time -v` then reports the last stage's) instead of the
    /// peak so far.
    #[arg(long)]
    stage_peaks: bool,
    /// `fe`: fill-reducing ordering of the volume's factor, `amd` or `nested-dissection`
    /// (METIS: build with `--features metis`). Part of the fingerprint: the operator
    /// changes by round-off [default: amd].
    #[arg(long)]
    ordering: Option<rsf::fault_ode::InteriorOrdering>,
    /// End time (years).
    #[arg(long, default_value_t = 1800.0)]
    end_years: f64,
    /// Tolerance of the fault ODE (local error per step: tolerance · L in slip,
    /// tolerance in ln θ).
    #[arg(long, default_value_t = 1e-6)]
    tolerance: f64,
    /// Relative accuracy ε of the ℋ-matrix (used above 4 096 unknowns, Δx < 2 km).
    #[arg(long, default_value_t = 1e-6)]
    epsilon: f64,
    /// Threads of each evaluation (the same bits for every value). Default: every core
    /// of the machine.
    #[arg(long, default_value_t = rsf::Parallelism::available_cores())]
    threads: usize,
    #[command(flatten)]
    header: crate::SeasHeaderArgs,
    #[command(flatten)]
    run: crate::ResumeArgs,
    /// Replace the files of an earlier run in `--out`.
    #[arg(long)]
    overwrite: bool,
    #[command(flatten)]
    limits: Limits,
}

/// The files a run writes into `--out`.
fn outputs() -> Vec<String> {
    let mut outputs = SeasBp5Output::file_names();
    outputs.extend(
        [
            "events.csv",
            SETUP_FILE,
            "summary.json",
            "overview.png",
            "checkpoint.bin",
            SEAS_BP5_RESUME_LOG,
        ]
        .map(String::from),
    );
    outputs
}

impl Args {
    /// `--domain-km` (km) and `--ratio` of the finite-element kernel, or their defaults.
    fn box_size(&self) -> (f64, f64) {
        (self.domain_km.unwrap_or(400.0), self.ratio.unwrap_or(1.3))
    }

    /// `--ordering`, or its default.
    fn ordering(&self) -> rsf::fault_ode::InteriorOrdering {
        self.ordering.unwrap_or_default()
    }

    /// The scene: BP5, with the fault zone of `--fault-zone-width-km` and
    /// `--fault-zone-rigidity` if given (both or neither).
    ///
    /// # Errors
    /// One of the two flags without the other; the zone's values (the scene's checks).
    fn scene(&self) -> Result<SeasBp5, AnyError> {
        let fault_zone = match (self.fault_zone_width_km, self.fault_zone_rigidity) {
            (None, None) => None,
            (Some(width), Some(rigidity_ratio)) => Some(FaultZone {
                half_width: 0.5 * width * 1e3,
                rigidity_ratio,
            }),
            _ => {
                return Err(
                    "--fault-zone-width-km and --fault-zone-rigidity go together: the \
                            zone's width and its shear modulus over the host's"
                        .into(),
                )
            }
        };
        let bp5 = SeasBp5 {
            fault_zone,
            ..SeasBp5::default()
        };
        flag(
            "--fault-zone-width-km, --fault-zone-rigidity",
            bp5.validate(),
        )?;
        Ok(bp5)
    }

    /// `--condensation` or its default.
    fn condensation(&self) -> Condensation {
        self.condensation.unwrap_or(Condensation::SchurOnly)
    }

    /// The finite-element grid of the flags: the fault zone's slab meshed at `--dx`.
    fn grid(&self, bp5: &SeasBp5) -> SeasBp5Grid {
        let (domain_km, ratio) = self.box_size();
        SeasBp5Grid {
            dx: self.dx,
            domain: domain_km * 1e3,
            ratio,
            mesh: self.mesh.unwrap_or(MeshArg::Graded).mesh(),
            near_fault: bp5.fault_zone.map_or(0.0, |z| z.half_width),
        }
    }
}

impl Program for Args {
    const NAME: &'static str = "seas_bp5";

    fn limits(&self) -> Limits {
        self.limits
    }

    fn plan(&self) -> Result<Plan, AnyError> {
        in_range("--end-years", self.end_years, (1e-9, 1e5), "years")?;
        let bp5 = self.scene()?;
        let cells = flag("--dx", bp5.cells(self.dx))?.len() as f64;
        flag("--tolerance", bp5.fault_ode_options(self.tolerance))?;
        in_range(
            "--epsilon",
            self.epsilon,
            (f64::MIN_POSITIVE, 1e-2),
            "a relative accuracy",
        )?;
        flag("--epsilon", bp5.half_space(self.epsilon))?;
        self.header.check()?;
        let m = 2.0 * cells;
        let (domain_km, ratio) = self.box_size();
        if self.kernel == Kernel::Okada {
            for (flag, given) in [
                ("--domain-km", self.domain_km.is_some()),
                ("--ratio", self.ratio.is_some()),
                ("--ordering", self.ordering.is_some()),
                ("--mesh", self.mesh.is_some()),
                ("--condensation", self.condensation.is_some()),
                ("--stage-peaks", self.stage_peaks),
                ("--fault-zone-width-km", self.fault_zone_width_km.is_some()),
                ("--fault-zone-rigidity", self.fault_zone_rigidity.is_some()),
            ] {
                if given {
                    return Err(format!(
                        "{flag}: a setting of the finite-element kernel: it needs --kernel fe \
                         (the Okada kernel has no volume), without it it would be ignored"
                    )
                    .into());
                }
            }
        }
        if self.ordering() == rsf::fault_ode::InteriorOrdering::NestedDissection
            && !rsf_metis::is_available()
        {
            return Err(crate::guard::refuse(
                "--ordering",
                "nested-dissection",
                "needs METIS, which this build lacks: build with `--features metis`",
            ));
        }
        let memory = match self.kernel {
            // The fault alone: the operator (dense up to 4 096 unknowns, an ℋ-matrix
            // beyond), the table of distinct source–receiver pairs it is built from (48
            // bytes each, if tabulated) and the body stations' columns.
            Kernel::Okada => {
                let (ns, nd) = (bp5.l_f / self.dx, bp5.w_f / self.dx);
                let pairs = (2.0 * ns - 1.0) * nd * nd;
                let table = if pairs <= rsf::halfspace::TABLE_MAX_PAIRS as f64 {
                    48.0 * pairs
                } else {
                    0.0
                };
                // The ℋ-matrix of the half-space and its set-up: three times the generic
                // budget of `operator_bytes` (measured: 163 MB peak at m = 8 000, Δx = 1 km;
                // docs/reliability.md, "Memory estimates").
                let operator = if m > 4096.0 {
                    3.0 * operator_bytes(m, true)
                } else {
                    operator_bytes(m, false)
                };
                operator + table + 9.0 * 3.0 * 8.0 * m
            }
            Kernel::Fe => {
                in_range(
                    "--domain-km",
                    domain_km,
                    (75.0, 1e4),
                    "km: 1.5 l_f/2 and more",
                )?;
                in_range("--ratio", ratio, (1.0, 2.0), "the growth of the spacing")?;
                let (h, far) = (self.dx, domain_km * 1e3);
                match self.mesh.unwrap_or(MeshArg::Graded) {
                    MeshArg::Tensor | MeshArg::TensorMirrored => {
                        // The tensor grid in closed form, its model and factor
                        // (crate::estimates::fe_3d_memory: the constants fitted to measured
                        // peaks, issue 74), and the condensed operator.
                        let vertices =
                            crate::estimates::fe_3d_box_vertices(h, bp5.l_f, bp5.w_f, ratio, far);
                        crate::estimates::fe_3d_memory(vertices) + operator_bytes(m, m > 4096.0)
                    }
                    MeshArg::Graded => {
                        // The set-up's peak as measured on the graded mesh (docs/seas-bp5.md,
                        // "The volume at the description's resolution"): the Schur-only
                        // elimination's grows like vertices^1.6, the whole factor's like
                        // vertices^1.9.
                        let nested = self.ordering
                            == Some(rsf::fault_ode::InteriorOrdering::NestedDissection);
                        let condensation = self.condensation();
                        let peak = |vertices: f64| {
                            let peak = match condensation {
                                Condensation::SchurOnly if nested => {
                                    SCHUR_ONLY_ND_PEAK_AT_500_M
                                        * (vertices / GRADED_VERTICES_AT_500_M).powf(1.5)
                                }
                                Condensation::SchurOnly => {
                                    SCHUR_ONLY_PEAK_AT_1_KM
                                        * (vertices / GRADED_VERTICES_AT_1_KM).powf(1.6)
                                }
                                Condensation::Factor => {
                                    GRADED_PEAK_AT_4_KM
                                        * (vertices / GRADED_VERTICES_AT_4_KM).powf(1.9)
                                }
                            };
                            peak + operator_bytes(m, m > 4096.0)
                        };
                        // Below 1 km the mesh itself takes seconds (8 s at 500 m): a run
                        // whose estimate from the fewest vertices its mesh can have is
                        // already above the limit is refused on that bound, unmeshed.
                        let limit = self.limits.max_memory_gb * 1e9;
                        match graded_vertices_at_least(self.dx, domain_km, ratio) {
                            Some(fewest) if peak(fewest) > limit => peak(fewest),
                            _ => {
                                // The graded mesh itself (about a second at 1 km).
                                let vertices = flag("--dx", bp5.fe_model_builder(&self.grid(&bp5)))?
                                    .mesh()
                                    .num_vertices()
                                    as f64;
                                peak(vertices)
                            }
                        }
                    }
                }
            }
        };
        // Ten fault stations, nine body stations and global.dat; the four profiles (slip
        // and stress along dip and along strike: a row holds a column or a row of the
        // grid); rupture.dat (one row per cell, once).
        let (along_strike, along_dip) = (bp5.l_f / self.dx, bp5.w_f / self.dx);
        let output = seas_output_bytes(self.end_years, 20.0, 13, 2.0 * (along_strike + along_dip))
            + cells * rsf::run_folder::SERIES_ROW_BYTES;
        let names = outputs();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        Ok(Plan::new()
            .pool(self.threads)
            .memory(
                memory,
                "--dx, --kernel, --domain-km, --ratio",
                format!("BP5 on dx = {:e} m: {cells} cells", self.dx),
            )
            .output(
                output,
                "--end-years, --dx",
                format!("{} years of the benchmark's files", self.end_years),
            )
            .folder(
                Folder::new("--out", &self.out, &names)
                    .overwrite(self.overwrite)
                    .resume_from(self.run.resume.as_deref())
                    .allow_change(&self.run.allow_change),
            ))
    }
}

/// A lower bound of the graded mesh's vertices at `dx` (m) below 1 km, for a box of at
/// least the default half-width (400 km) graded by at most the default ratio (1.3), the
/// sizes of the counts measured (`None` otherwise: a smaller box or a faster grading has
/// fewer vertices): the count at 1 km grown like `dx^-1.6`. Measured from 1 km to 500 m the
/// count grows like `dx^-1.62` (86 710 to 266 764 vertices) and faster below, where the
/// fine cells around the fault plane, a surface, take the larger share (`dx^-2` in the
/// limit); a fault zone only adds vertices.
fn graded_vertices_at_least(dx: f64, domain_km: f64, ratio: f64) -> Option<f64> {
    (dx < 1000.0 && domain_km >= 400.0 && ratio <= 1.3)
        .then(|| GRADED_VERTICES_AT_1_KM * (1000.0 / dx).powf(1.6))
}

/// The set-up's peak (bytes) of `--kernel fe` on the graded mesh at 4 km and its vertices
/// (measured: docs/three-d.md, "BP5 on the graded mesh"), the anchor of its estimate.
const GRADED_PEAK_AT_4_KM: f64 = 287e6;
/// See [`GRADED_PEAK_AT_4_KM`].
const GRADED_VERTICES_AT_4_KM: f64 = 7701.0;

/// The whole run's peak (bytes) of `--kernel fe` with the Schur-only elimination on the
/// graded mesh (octree) at 1 km, 86 710 vertices: measured 7.3 GB (the elimination's
/// stage, AMD EPYC; docs/seas-bp5.md), with a margin of 1.25 — the anchor of its estimate,
/// which at 2 km (33 142 vertices) gives 1.96 GB against the measured 1.55 GB.
const SCHUR_ONLY_PEAK_AT_1_KM: f64 = 1.25 * 7.30e9;
/// See [`SCHUR_ONLY_PEAK_AT_1_KM`].
const GRADED_VERTICES_AT_1_KM: f64 = 86_710.0;

/// As [`SCHUR_ONLY_PEAK_AT_1_KM`] with `--ordering nested-dissection`: measured 11.49 GB at
/// 500 m, 266 764 vertices (AMD EPYC), with a margin of 1.25; the exponent 1.5 keeps the
/// estimate (2.7 GB at 1 km, 0.6 GB at 2 km) above the elimination's plan plus the model
/// there (about 2.0 and 0.4 GB; docs/three-d.md, "On BP5's graded box").
const SCHUR_ONLY_ND_PEAK_AT_500_M: f64 = 1.25 * 11.49e9;
/// See [`SCHUR_ONLY_ND_PEAK_AT_500_M`].
const GRADED_VERTICES_AT_500_M: f64 = 266_764.0;

/// The file of the Schur-only elimination's checkpoints in `--out` (its finished state
/// kept: a `--resume` of the run reads it instead of eliminating again).
const SETUP_FILE: &str = "setup.bin";

/// Removes `path` if it is there.
fn remove_if_present(path: &std::path::Path) -> Result<(), AnyError> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(format!("{}: {e}", path.display()).into())
        }
        _ => Ok(()),
    }
}

/// A line on standard error at every tenth of the elimination's work (flops), with the
/// fronts done and the wall time.
fn elimination_progress() -> SetupProgress {
    let mut next = 0.1;
    Box::new(move |p: &Progress| {
        let done = if p.flops > 0.0 {
            p.flops_done / p.flops
        } else {
            1.0
        };
        if done >= next {
            eprintln!(
                "set-up: {:.0} % of the elimination ({} of {} fronts, {:.0} s)",
                100.0 * done,
                p.fronts_done,
                p.fronts,
                p.seconds
            );
            while next <= done {
                next += 0.1;
            }
        }
        ControlFlow::Continue(())
    })
}

/// How the finite-element kernel condenses the volume onto the fault.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq)]
enum Condensation {
    /// The Schur complement alone, by an elimination that keeps no factor column
    /// (checkpointed in `--out`).
    SchurOnly,
    /// The volume's whole sparse Cholesky factor, kept for the run.
    Factor,
}

/// The finite-element kernel's mesh (`SeasBp5Mesh`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq)]
enum MeshArg {
    /// An octree of Kuhn cubes refined towards the fault and the stations, graded in every direction.
    Graded,
    /// A tensor grid graded axis by axis.
    Tensor,
    /// The tensor grid with alternate boxes mirrored (the graded mesh's pattern of diagonals).
    TensorMirrored,
}

impl MeshArg {
    fn mesh(self) -> SeasBp5Mesh {
        match self {
            MeshArg::Graded => SeasBp5Mesh::Graded,
            MeshArg::Tensor => SeasBp5Mesh::Tensor,
            MeshArg::TensorMirrored => SeasBp5Mesh::TensorMirrored,
        }
    }
}

/// The elastic operator of the run.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq)]
enum Kernel {
    /// Okada's half-space, a fault alone, back slip.
    Okada,
    /// The finite-element volume model.
    Fe,
}

/// The program `seas_bp5` (`cargo run --release --example seas_bp5 -- --out DIR …`).
pub fn main() -> ExitCode {
    crate::guard::main(|args, folder| run(args, folder, None))
}

/// The program on the processes of a job (MPI ranks, the `rsf-mpi` crate's `seas_bp5`):
/// every evaluation of the fault ODE shared by the ranks
/// ([`rsf::FaultOde::share_evaluations`]: the half-space operator's elements, or the
/// finite-element operator's rows), the files written by rank 0 — byte-identical to one
/// process's (docs/scaling.md, "The fault ODE on MPI ranks").
pub fn main_on_ranks(processes: &dyn Processes) -> ExitCode {
    crate::guard::main_on_ranks(processes, |args, folder, processes| {
        run(args, folder, Some(processes))
    })
}

fn run(args: Args, _prepared: Prepared, processes: Option<&dyn Processes>) -> Result<(), AnyError> {
    // Rank 0 (or the one process) writes the files and tells.
    let root = processes.is_none_or(|p| p.rank() == 0);
    let bp5 = args.scene()?;
    let (domain_km, ratio) = args.box_size();
    // Checked before any file is touched.
    let cells = bp5.cells(args.dx).map_err(|e| format!("--dx: {e}"))?.len();
    let grid = args.grid(&bp5);
    let mut options = bp5
        .fault_ode_options(args.tolerance)
        .map_err(|e| format!("--tolerance: {e}"))?;
    options.parallelism = rsf::Parallelism::rayon(args.threads);
    let half_space = bp5
        .half_space(args.epsilon)
        .map_err(|e| format!("--epsilon: {e}"))?;
    // A folder of another run (unless --overwrite), one that cannot be written: refused
    // by the guard before anything was computed.
    let folder = RunFolder::new(&args.out, "seas_bp5", &[]);
    // What a checkpoint continues: the scene, the grid and what changes the trajectory.
    let mut fingerprint = Fingerprint::of_serialized(&bp5)
        .with("kernel", format!("{:?}", args.kernel))
        .with("dx", args.dx)
        .with("domain_km", domain_km)
        .with("ratio", ratio)
        .with("ordering", args.ordering())
        .with("end_years", args.end_years)
        .with("tolerance", args.tolerance)
        .with("epsilon", args.epsilon);
    if args.kernel == Kernel::Fe {
        // The volume's mesh (a field since the graded mesh; an older finite-element
        // checkpoint, of the tensor grid, is then refused by its missing field).
        fingerprint = fingerprint
            .with("mesh", format!("{:?}", grid.mesh))
            .with("condensation", format!("{:?}", args.condensation()));
    }
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let setup = SeasSetup {
        problem: "SEAS Benchmark BP5-QD".into(),
        modeler: args.header.modeler.clone(),
        date: args.header.date.clone().unwrap_or_else(utc_date_today),
        element_size: args.dx,
        stations: Vec::new(),
        depth_axis: 2,
        depth_down: false,
        sigma_n: bp5.sigma_n,
        profile_spacing: args.dx,
        sampling: SeasSampling::default(),
        layout: SeasLayout::default(),
        surface_stations: Vec::new(),
    };
    let (mut ode, output) = match args.kernel {
        Kernel::Okada => {
            let model = bp5.model(args.dx)?;
            if root {
                println!(
                    "BP5-QD, Okada, Δx = {} m, {cells} cells ({} slip unknowns); on {}",
                    args.dx,
                    2 * cells,
                    machine()
                );
            }
            // On ranks, each builds and holds its rows of the operator.
            let (ode, columns) = bp5.fault_ode_on_ranks(
                model,
                options,
                &half_space,
                &SeasBp5::body_station_points(),
                processes.map(|p| p.group()),
            )?;
            let output = if root {
                Some(bp5.output(&args.out, args.dx, columns, setup)?)
            } else {
                None
            };
            (ode, output)
        }
        Kernel::Fe => {
            // The build's stages, each with its peak memory (docs/three-d.md, "The build's
            // memory").
            let stages = Rc::new(RefCell::new(StageMemory::start(args.stage_peaks)));
            let builder = bp5
                .fe_model_builder(&grid)
                .map_err(|e| format!("--kernel fe: {e}"))?;
            stages.borrow_mut().end("mesh");
            let mesh = builder.mesh();
            let mesh_line = format!(
                "{:?} mesh: {} vertices, {} tetrahedra, smallest dihedral angle {:.2}°, box ±{} km",
                grid.mesh,
                mesh.num_vertices(),
                mesh.num_cells(),
                mesh.min_dihedral_angle().to_degrees(),
                mesh.vertices().iter().map(|x| x[0]).fold(0.0, f64::max) / 1e3
            );
            let watch = Rc::clone(&stages);
            let model = builder
                .on_stage(move |stage| watch.borrow_mut().end(stage.name()))
                .build()
                .map_err(|e| format!("--kernel fe: {e}"))?;
            let m = 2 * model.frictional_boundary.len();
            if root {
                println!(
                    "BP5-QD, finite elements, Δx = {} m, ratio {ratio}, {} vertices (the fault's \
                     split), {m} slip unknowns; on {}",
                    args.dx,
                    model.vertices.len(),
                    machine()
                );
                println!("{mesh_line}");
            }
            if m > 4096 {
                options.kernel = FaultKernel::hierarchical(args.epsilon);
            }
            options.ordering = args.ordering();
            let output = if root {
                Some(bp5.volume_output(&args.out, &model, args.dx, setup)?)
            } else {
                None
            };
            let mut ode = match args.condensation() {
                Condensation::Factor => bp5.fe_fault_ode(model, options)?,
                Condensation::SchurOnly => {
                    // The stations' vertices on every rank (the elimination keeps them).
                    let watch_vertices = bp5.station_vertices(&model)?;
                    let path = folder.path(SETUP_FILE);
                    if args.run.resume.is_none() {
                        // Another run's elimination is not this one's to continue.
                        remove_if_present(&path)?;
                    }
                    let checkpoint = CheckpointPolicy {
                        // One process writes it; the others eliminate alike.
                        every_seconds: root.then_some(600.0),
                        ..CheckpointPolicy::new(path)
                    };
                    let setup = SchurOnlySetup {
                        watch_vertices,
                        checkpoint: root.then_some(checkpoint),
                        max_bytes: Some(
                            (args.limits.max_memory_gb * 1e9).min(usize::MAX as f64) as usize
                        ),
                        progress: root.then(|| elimination_progress()),
                    };
                    bp5.fe_fault_ode_schur_only(model, options, setup)?
                }
            };
            stages.borrow_mut().end("condensation and operator");
            if root {
                println!("the set-up's stages (memory of this process):");
                print!("{}", stages.borrow().table());
            }
            if let Some(output) = &output {
                ode.watch_vertices(&output.volume_vertices())?;
                match args.condensation() {
                    Condensation::Factor => {
                        println!("volume factor: {} entries", ode.factor_nnz())
                    }
                    Condensation::SchurOnly => {
                        println!("volume: Schur complement only (no factor kept)")
                    }
                }
            }
            (ode, output)
        }
    };
    if let Some(p) = processes {
        ode.share_evaluations(p.group())?;
    }
    let setup_s = clock.elapsed().as_secs_f64();
    let end = until(args.end_years * SECONDS_PER_YEAR, args.run.max_steps);
    let Some(mut output) = output else {
        // The other ranks: the same steps as rank 0 (from the same checkpoint), no files
        // (no observer here ends a run).
        if let Some(path) = &args.run.resume {
            ode.restore(&read_checkpoint(
                path,
                &fingerprint,
                &args.run.allow_change,
            )?)?;
        }
        ode.run_until(end, &mut [])?;
        return Ok(());
    };
    println!("S: {}", ode.kernel_report());
    if let Some(p) = processes {
        println!("{} MPI ranks share every evaluation", p.size());
    }
    println!(
        "set-up: wall {setup_s:.1} s, CPU {:.1} s",
        cpu_seconds() - cpu0
    );
    if args.run.checkpoint_every > 0 || args.run.max_steps.is_some() {
        output = output.with_resume_log(args.run.checkpoint_every);
    }
    let resumed = match &args.run.resume {
        Some(path) => {
            let c = read_checkpoint(path, &fingerprint, &args.run.allow_change)?;
            output.resume(c.state.step)?;
            ode.restore(&c)?;
            Some(c)
        }
        None => {
            output.write_initial_state(
                ode.model(),
                ode.state(),
                rsf::Stepping::fault_tractions(&ode),
            );
            None
        }
    };
    // Every `--checkpoint-every` steps, and where the step cap stops the run.
    let mut checkpointer = args.run.checkpointer(
        folder.path("checkpoint.bin"),
        fingerprint,
        resumed.as_ref().map_or(0.0, |c| c.wall_time_s),
    )?;
    let run = {
        // The files first, the checkpoint after them: a checkpoint never runs ahead.
        let mut progress = rsf::observe::Progress::time_in(
            ode.state().time,
            args.end_years * SECONDS_PER_YEAR,
            TimeUnit::year(SECONDS_PER_YEAR),
            "BP5",
        );
        let mut observers: Vec<&mut dyn Observer<3, 3>> =
            vec![&mut output, &mut progress, &mut checkpointer];
        ode.run_until(end, &mut observers)
    };
    let summary = match run {
        Ok(s) => s,
        Err(e) => {
            eprintln!("run failed after {} steps: {}", e.summary.steps, e.error);
            return Err(e.error.into());
        }
    };
    if let Some(e) = step_cap_error(&summary, end, ode.state(), &folder.path("checkpoint.bin")) {
        return Err(e.into());
    }
    let wall = clock.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - cpu0;
    // Events with a peak above 0.1 m/s: the ruptures (the catalogue also holds the
    // shallow afterslip that crosses 1 mm/s after some).
    let ruptures: Vec<_> = output
        .events()
        .iter()
        .filter(|e| e.peak_slip_rate >= 0.1)
        .collect();
    let mut previous: Option<f64> = None;
    let mut intervals = Vec::new();
    for e in &ruptures {
        let years = e.t_start / SECONDS_PER_YEAR;
        let interval = previous.map_or(String::new(), |p| {
            intervals.push(years - p);
            format!(", {:.3} yr after the previous", years - p)
        });
        println!(
            "rupture at {years:.4} yr ({:.1} s): peak slip rate {:.3e} m/s at x₂ = {:.1} km, \
             x₃ = {:.1} km, {:.1} s above 1 mm/s{interval}",
            e.t_start,
            e.peak_slip_rate,
            e.hypocentre[0] / 1e3,
            e.hypocentre[1] / 1e3,
            e.t_end.map_or(f64::NAN, |t| t - e.t_start),
        );
        previous = Some(years);
    }
    println!(
        "{} steps ({} attempts rejected), {} evaluations; wall {wall:.1} s, CPU {cpu:.1} s; \
         wrote {}",
        summary.steps,
        summary.rejected_attempts,
        ode.evaluations(),
        args.out.display()
    );
    let json = serde_json::json!({
        "problem": "BP5-QD",
        "kernel": format!("{:?}", args.kernel),
        "domain_km": (args.kernel == Kernel::Fe).then_some(domain_km),
        "ratio": (args.kernel == Kernel::Fe).then_some(ratio),
        "dx_m": args.dx,
        "cells": cells,
        "end_years": args.end_years,
        "tolerance": args.tolerance,
        "epsilon": args.epsilon,
        "operator": ode.kernel_report().to_string(),
        "volume_factor_entries": ode.factor_nnz(),
        "accepted_steps": ode.state().step,
        "steps_this_invocation": summary.steps,
        "rejected_attempts": summary.rejected_attempts,
        "rate_evaluations": ode.evaluations(),
        "threads": args.threads,
        "setup_s": setup_s,
        "wall_time_s": wall,
        "cpu_time_s": cpu,
        "machine": machine(),
        "rupture_start_years": ruptures.iter().map(|e| e.t_start / SECONDS_PER_YEAR).collect::<Vec<_>>(),
        "recurrence_intervals_years": intervals,
        "peak_slip_rates_mps": ruptures.iter().map(|e| e.peak_slip_rate).collect::<Vec<_>>(),
        "catalogue_events": output.events().len(),
    });
    rsf::checkpoint::write_atomically(
        &folder.path("summary.json"),
        serde_json::to_string_pretty(&json)?.as_bytes(),
    )?;
    // Slip₂ along dip at x₂ = 0 and the maximum slip rate against time.
    crate::seas_overview(&args.out, "slip_2_depth.dat", "depth (km)", ruptures.len())?;
    println!("wrote {}", args.out.join("overview.png").display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bound that refuses a run unmeshed stays below the vertices measured at 500 m
    /// (the one size below 1 km with a measured count), so no run the mesh would admit is
    /// refused on it there.
    #[test]
    fn the_unmeshed_bound_is_below_the_measured_count() {
        let at_500_m = graded_vertices_at_least(500.0, 400.0, 1.3).unwrap();
        assert!(at_500_m <= GRADED_VERTICES_AT_500_M, "{at_500_m}");
        assert!(at_500_m > 0.95 * GRADED_VERTICES_AT_500_M, "{at_500_m}");
        assert_eq!(graded_vertices_at_least(1000.0, 400.0, 1.3), None);
        // Boxes with fewer vertices than the measured ones have no bound.
        assert_eq!(graded_vertices_at_least(500.0, 100.0, 1.3), None);
        assert_eq!(graded_vertices_at_least(500.0, 400.0, 2.0), None);
    }
}
