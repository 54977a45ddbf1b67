//! The program `slider_3d` (the example `slider_3d`; on MPI ranks the `rsf-mpi` crate's
//! binary `slider_3d`, [`main_on_ranks`]): the paper's slider extruded to three dimensions
//! (issue 12; docs/math.md §10): a
//! 5 m × 1 m × W block of tetrahedra, sheared at its top face with the ramped velocity
//! `(V_D g(t), 0, 0)`, sliding on its rate-and-state frictional bottom face (bilateral
//! contact, slip in the x–z plane). The lateral faces z = 0, W are traction-free, or held
//! at `u_z = 0` with `--plane-strain` (then the run reproduces the 2-D main job).
//!
//! ```sh
//! cargo run --release --example slider_3d                          # j = 2, W = 1 m, free faces
//! cargo run --release --example slider_3d -- --level 3 --plane-strain --solver tnnmg
//! cargo run --release --example slider_3d -- --scene my_3d_scene.toml --steps 2e3
//! ```
//!
//! Every field of `rsf_scenes::Slider3dScene` (those of `rsf_scenes::SliderScene` plus
//! `width_m` and `lateral`) is a flag of its name (`--mu0 0.5`, `--width-m 2`, `--lateral
//! plane-strain`), its default the 3-D scene's; `--scene` reads a TOML file with those
//! fields as keys, and the flags given override it.
//!
//! Writes to `out/slider_3d/` (or `--out DIR`): `timeseries.csv` (a `rsf::observe::PointSeries` at
//! x0 = (2.5, 0, W/2): the 2-D main job's columns, then the y and z components),
//! `frames/frame_NNNNNN.vtu` + `frames/frames.pvd` (tetrahedra, displacement and velocity;
//! on Γ_F slip, slip rate, state, shear and normal traction; every `--frame-every` steps,
//! default 100, for ParaView), `fault_snapshot.csv` (x, z, slip rate on Γ_F at the step of
//! the largest slip rate, or at `--snapshot-time`) and its figure `fault_slip_rate.png`. A
//! run whose series and frames are estimated above `--max-output-gb` (default 10) is
//! refused before any file is written. On more than one MPI rank ([`main_on_ranks`]) the
//! frames are parallel pieces: `frames/frame_NNNNNN_rRRRR.vtu` by rank RRRR and
//! `frames/frame_NNNNNN.pvtu`, listed in `frames.pvd`.
//!
//! Resumable (docs/reliability.md): `--checkpoint-every N` writes `checkpoint.bin` every N
//! steps, `--resume out/slider_3d/checkpoint.bin` continues the run in its folder (the
//! checkpoint, the scene's fingerprint and the time series are checked before any file is
//! cut; `timeseries.csv` and the frames end byte-identical to an uninterrupted run's; the
//! fault snapshot is of the resumed part only), `--max-steps N` stops after step N with a
//! checkpoint, `--allow-change FIELD` accepts a deliberate change, `--overwrite` replaces
//! the files of an earlier run (another program's folder is refused without it).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::cli::{PaperSlider3d, SliderArgs};
use crate::fields::FieldsRun;
use crate::guard::{AnyError, Limits, Plan, Prepared, Program};
use crate::session::{Session, SessionFlags};
use crate::{log_heat_map, FieldMap, FolderArgs, FrameArgs, HeatMapAxes};
use clap::Parser;
use rsf::fem::SimplexMesh;
use rsf::model::ProblemScales;
use rsf::observe::{PointSeries, Progress};
use rsf::run_folder::check_output_size;
use rsf::run_folder::RunFolder;
use rsf::{Flow, Model, Observer, StepView};
use rsf_ranks::Processes;
use rsf_scenes::steps_bound;
use rsf_scenes::{LateralBoundary, Slider3dScene};

/// VTU frames every this many steps unless `--frame-every` says otherwise.
const DEFAULT_FRAME_EVERY: usize = 100;
/// Bytes of a 3-D time series row (13 columns; 160 bytes measured at level 1; rounded up).
const SERIES_ROW_BYTES_3D: f64 = 250.0;
/// The files a run writes into its folder.
const OUTPUTS: [&str; 7] = [
    "timeseries.csv",
    "checkpoint.bin",
    "fault_snapshot.csv",
    "fault_slip_rate.png",
    "frames/frames.pvd",
    crate::fields::FIELDS_FILE,
    crate::fields::FIELDS_INDEX,
];

/// The 3-D slider: time series at x0, VTU frames, a fault-plane slip-rate snapshot.
#[derive(Parser)]
#[command(version)]
pub struct Cli {
    /// The scene's fields as flags (`rsf_scenes::Slider3dScene`: those of the 2-D scene,
    /// `--width-m` (also `--width`) and `--lateral`, with the 3-D scene's defaults),
    /// `--scene FILE.toml`, `--adaptive TOL`.
    #[command(flatten)]
    pub(crate) slider: SliderArgs<PaperSlider3d>,
    /// `u_z = 0` on both lateral faces (plane strain): `--lateral plane-strain`.
    #[arg(long)]
    plane_strain: bool,
    /// VTU frames (this example's default: every 100 steps).
    #[command(flatten)]
    pub(crate) frames: FrameArgs,
    /// Time of the fault snapshot (s) [default: the step of the largest slip rate].
    #[arg(long, value_name = "T")]
    snapshot_time: Option<f64>,
    /// Output folder.
    #[arg(long, default_value = "out/slider_3d")]
    out: PathBuf,
    /// `--overwrite`, `--allow-change`, `--max-output-gb` (time series rows and VTU
    /// frames), `--max-steps`.
    #[command(flatten)]
    folder: FolderArgs,
    /// Write `checkpoint.bin` every N steps (0: never).
    #[arg(long, default_value_t = 0, value_name = "N")]
    checkpoint_every: usize,
    /// Continue from this checkpoint, appending to the files in the output folder (the
    /// checkpoint, the folder's time series and the scene are checked to belong together
    /// first).
    #[arg(long, value_name = "FILE")]
    resume: Option<PathBuf>,
    /// Threads of every parallel part of a step (`rsf::method::SolverOptions::parallelism`: the
    /// direct solver's sweeps and its dense Newton factorisations of at least
    /// `rsf::direct::DENSE_PARALLEL_MIN` unknowns, the right-hand side rows; docs/scaling.md):
    /// a count, `0` or `pool` for rayon's pool, `seq` for one; default every core of the
    /// machine. The output does not depend on it. (`--dense-threads` is an old name of
    /// this flag.)
    #[arg(long, default_value_t = rsf::Parallelism::default(), alias = "dense-threads", value_name = "N")]
    threads: rsf::Parallelism,
    /// Memory (GiB) the `auto` solver choice may give the direct solver (its estimate must
    /// fit, else TNNMG; docs/scaling.md), in (0, inf). Default:
    /// `rsf::method::DEFAULT_MEMORY_BUDGET_BYTES`.
    #[arg(long)]
    memory_budget_gib: Option<f64>,
    /// `--max-memory-gb` (nodes estimated before anything is allocated; 35 kB per node,
    /// measured at level 4), `--max-output-gb` (time series rows and VTU frames).
    #[command(flatten)]
    limits: Limits,
    /// Solve every fixed point iteration's velocity problem to the solver's tolerance (the
    /// paper's rule) instead of the scene's (3-D default: `by-solver`, inexact solves for
    /// TNNMG; docs/scaling.md): `--fixed-point-inner-solves exact`.
    #[arg(long)]
    exact_inner_solves: bool,
}

impl Program for Cli {
    crate::name_and_limits!("slider_3d");

    fn plan(&self) -> Result<Plan, AnyError> {
        let scene = scene(self)?;
        let s = &scene.slider;
        if let Some(t) = self.snapshot_time {
            // A NaN or a time outside the run would give an empty (all-zero) snapshot.
            if !(t.is_finite() && (0.0..=s.end_time_s).contains(&t)) {
                return Err(crate::guard::refuse(
                    "--snapshot-time",
                    crate::guard::written(t),
                    &format!(
                        "must be a finite time inside [0, T] = [0, {:e}] s",
                        s.end_time_s
                    ),
                ));
            }
        }
        if let Some(gib) = self.memory_budget_gib {
            crate::memory_budget_bytes("--memory-budget-gib", gib)?;
        }
        // The model's size, and the output bound: a series row per step, a frame of every
        // vertex and cell (six tetrahedra per hexahedron) every --frame-every steps (frames
        // in pieces on ranks repeat their border points: `run` checks their exact sizes).
        let (nodes, bytes) = scene.estimated_bytes();
        let bytes = bytes + crate::estimates::slider_3d_direct_bytes(&scene, nodes);
        let k = 2f64.powi(s.level.min(1000) as i32);
        let cells = 6.0 * 5.0 * k * k * scene.width_m.round().max(1.0) * k;
        let steps = steps_bound(s, (0.0, s.end_time_s))
            .min(self.folder.max_steps.map_or(f64::INFINITY, |m| m as f64));
        let frames = self.frames.bytes_bound(
            DEFAULT_FRAME_EVERY,
            steps,
            nodes.min(1e18) as usize,
            cells.min(1e18) as usize,
        );
        self.frames.fields.check(Self::NAME)?;
        let fields = self.frames.fields.bytes_bound(
            steps,
            nodes.min(1e18) as usize,
            (cells.min(1e18) as usize, 4),
        );
        let what = format!(
            "the 3-D slider at level {} and width {} m: about {nodes:.3e} nodes, {steps:.3e} steps",
            s.level, scene.width_m
        );
        Ok(Plan::new()
            .pool(self.threads.threads())
            .memory(bytes, "--level, --width (or --scene)", what.clone())
            .output(
                steps * SERIES_ROW_BYTES_3D + frames + fields,
                "--steps, --frame-every, --hdf5, --max-steps",
                what,
            )
            .folder(
                self.folder
                    .out_folder(&self.out, &OUTPUTS, self.resume.as_deref()),
            ))
    }
}

/// The program `slider_3d` in one process (the example `slider_3d`).
pub fn main() -> ExitCode {
    // With threads, the whole run on the pool (no hand-over per parallel region).
    crate::guard::main(|cli, prepared| run(cli, prepared, None))
}

/// The program `slider_3d` in one process with `writers` of its fields (`--hdf5 N`: the
/// fields of the body, [`FieldWriters::volume_3d`](crate::fields::FieldWriters::volume_3d);
/// the binary `slider_3d` of crates/rsf-hdf5).
pub fn main_with_fields(writers: std::sync::Arc<dyn crate::fields::FieldWriters>) -> ExitCode {
    crate::guard::main_supplied(
        |cli: &mut Cli| cli.frames.fields.supply(writers),
        |cli, prepared| run(cli, prepared, None),
    )
}

/// The program on the processes of a job (MPI ranks, the `rsf-mpi` crate's `slider_3d`;
/// docs/scaling.md, "Phase 5" and "Phase 7"): the finest mesh is partitioned
/// ([`partition`]) before anything is assembled, each rank assembles only its own nodes'
/// columns of `K`, `M` and the energy norm
/// ([`ModelBuilder::build_columns`](rsf::ModelBuilder::build_columns)) and the ranks
/// solve the initial equilibrium together
/// ([`equilibrium_on_ranks`](rsf::model::equilibrium_on_ranks), at every size: its bits
/// are not the one-process model's Cholesky or multigrid solution's); every rank then runs
/// the same simulation, and every velocity problem is solved by TNNMG on the ranks
/// ([`TnnmgOnRanks`](rsf::method::TnnmgOnRanks)); rank 0 writes every file but the
/// frames. On more than one rank the
/// frames are written in parallel pieces ([`rsf::observe::VtuFrames::pieces`]): every rank
/// writes `frames/frame_NNNNNN_rRRRR.vtu` (RRRR its rank), the tetrahedra whose
/// lowest-numbered vertex it owns by [`partition`] with the points they use and their
/// mesh numbers (`global_node`), and rank 0 writes `frames/frame_NNNNNN.pvtu` and lists it
/// in `frames.pvd`; on one rank the frames are one file each, as in one process. The
/// other files are byte-identical at every rank count, and the pieces hold the one-rank
/// frames' values bit for bit (the one-process reference is one rank: the solver on ranks
/// has its own smoother order, so its files differ from the example's by round-off of the
/// solver tolerance). The solver is TNNMG (`--solver auto` becomes `tnnmg`; another
/// solver is refused). A checkpoint holds the whole replicated state, so a run resumes on
/// any rank count; the frames after the checkpoint are then in the new count's pieces
/// (each `.pvtu` names its own), and `frames.pvd` may list `.vtu` and `.pvtu` frames.
/// With `writers` (the `rsf-mpi` crate built with its feature `hdf5`), `--hdf5 N` has rank
/// 0 write the body's fields (`fields.h5` and its Xdmf index), one process's bytes; without,
/// `--hdf5 N` is refused before any work.
pub fn main_on_ranks(processes: &dyn Processes, writers: crate::fields::Writers) -> ExitCode {
    let supply = |cli: &mut Cli| cli.frames.fields.supply_if(writers);
    crate::guard::main_on_ranks_supplied(processes, supply, |cli, prepared, processes| {
        run(cli, prepared, Some(processes))
    })
}

/// The owner of every vertex of `mesh` (the model's finest mesh) among `ranks` ranks,
/// the same on every rank: METIS's k-way partition of the mesh's vertex graph (the node
/// graph of the model's matrices, [`SimplexMesh::vertex_graph`];
/// `rsf_metis::part_graph_kway`, deterministic) where the build has METIS (the `rsf-mpi`
/// crate's does), else slabs of equal width across the longest side of the mesh's
/// bounding box (vertex `p` to rank `⌊ranks · (x_p − min)/(max − min)⌋` on that axis).
/// Coarse nodes have the owner of the fine node with their number (nested hierarchies).
/// Made before the model: each rank then assembles its own nodes' columns.
///
/// # Errors
/// METIS's errors other than its absence.
pub fn partition(mesh: &SimplexMesh<3>, ranks: usize) -> Result<Vec<usize>, AnyError> {
    let (xadj, adjncy) = mesh.vertex_graph();
    match rsf_metis::part_graph_kway(&xadj, &adjncy, ranks) {
        Ok(owner) => return Ok(owner),
        Err(rsf_metis::Error::FeatureDisabled(_)) => {}
        Err(e) => return Err(e.into()),
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for x in mesh.vertices() {
        for c in 0..3 {
            lo[c] = lo[c].min(x[c]);
            hi[c] = hi[c].max(x[c]);
        }
    }
    let axis = (0..3)
        .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
        .unwrap_or(0);
    let width = (hi[axis] - lo[axis]).max(f64::MIN_POSITIVE);
    Ok(mesh
        .vertices()
        .iter()
        .map(|x| (((x[axis] - lo[axis]) / width * ranks as f64) as usize).min(ranks - 1))
        .collect())
}

/// The conditioning scales of the whole model of which every rank of `processes` holds
/// the columns `model` ([`ProblemScales::combined`] of every rank's, one all-gather: the
/// same on every rank). Collective.
fn whole_scales(model: &Model<3>, processes: &dyn Processes) -> ProblemScales {
    let s = ProblemScales::of_model(model);
    let (m_lo, m_hi) = s.mass.unwrap_or((f64::NAN, f64::NAN));
    let own = [
        s.stiffness.0,
        s.stiffness.1,
        m_lo,
        m_hi,
        s.load,
        s.displacement,
    ];
    let size = processes.size();
    let mut all = vec![0.0; own.len() * size];
    processes
        .group()
        .all_gather(&own, &vec![own.len(); size], &mut all);
    let parts: Vec<ProblemScales> = all
        .chunks_exact(own.len())
        .map(|x| ProblemScales {
            stiffness: (x[0], x[1]),
            mass: s.mass.map(|_| (x[2], x[3])),
            load: x[4],
            displacement: x[5],
            displacement_estimate: 0.0,
        })
        .collect();
    ProblemScales::combined(&parts)
}

/// The scene of the flags and `--scene` with the shortcuts (`--plane-strain`,
/// `--exact-inner-solves`) applied, validated.
fn scene(cli: &Cli) -> Result<Slider3dScene, Box<dyn std::error::Error>> {
    let mut scene = cli.slider.scene()?;
    if cli.plane_strain {
        scene.lateral = LateralBoundary::PlaneStrain;
    }
    if cli.exact_inner_solves {
        scene.slider.fixed_point_inner_solves = rsf::method::InnerSolves::Exact;
    }
    Ok(scene)
}

/// Slip rates `√(v_x² + v_z²)` on Γ_F (the fault normal is y) at one step.
struct FaultSnapshot {
    /// Take the first step at or after this time; `None`: the step of the largest slip rate.
    at: Option<f64>,
    time: f64,
    peak: f64,
    slip_rates: Vec<f64>,
}

impl FaultSnapshot {
    fn new(at: Option<f64>, frictional_nodes: usize) -> Self {
        Self {
            at,
            time: f64::NAN,
            peak: f64::NEG_INFINITY,
            slip_rates: vec![0.0; frictional_nodes],
        }
    }

    /// Writes `fault_snapshot.csv` and `fault_slip_rate.png` into `out`.
    fn write(
        &self,
        model: &Model<3>,
        width: f64,
        out: &Path,
    ) -> Result<(), Box<dyn std::error::Error>> {
        let nodes = &model.frictional_boundary.nodes;
        let mut csv =
            std::io::BufWriter::new(std::fs::File::create(out.join("fault_snapshot.csv"))?);
        writeln!(csv, "x_m,z_m,slip_rate_mps")?;
        for (&p, v) in nodes.iter().zip(&self.slip_rates) {
            let x = model.vertices[p];
            writeln!(csv, "{},{},{v:e}", x[0], x[2])?;
        }
        csv.flush()?;
        // Γ_F's nodes lie on a tensor grid of the (x, z) plane.
        let grid = |c: usize| {
            let mut v: Vec<f64> = nodes.iter().map(|&p| model.vertices[p][c]).collect();
            v.sort_by(f64::total_cmp);
            v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
            v
        };
        let (xs, zs) = (grid(0), grid(2));
        let index = |axis: &[f64], v: f64| axis.partition_point(|&a| a < v - 1e-9);
        let mut values = vec![vec![0.0; xs.len()]; zs.len()];
        for (&p, &v) in nodes.iter().zip(&self.slip_rates) {
            let x = model.vertices[p];
            values[index(&zs, x[2])][index(&xs, x[0])] = v;
        }
        let axes = HeatMapAxes {
            title: &format!("Slip rate on the fault plane y = 0, t = {:.4} s", self.time),
            x_label: "x (m)",
            y_label: "z (m)",
            log10_range: (-12.0, -2.0),
        };
        let height = (200.0 + 800.0 * (width / 5.0).min(1.0)) as u32;
        log_heat_map(
            &out.join("fault_slip_rate.png"),
            (1000, height),
            &axes,
            &FieldMap {
                xs: &xs,
                ys: &zs,
                values: &values,
            },
        )
    }
}

impl Observer<3> for FaultSnapshot {
    fn observe(&mut self, s: &StepView<'_, 3>) -> rsf::Result<Flow> {
        let take = match self.at {
            Some(t) => self.time.is_nan() && s.report.time >= t,
            None => s.report.max_slip_rate > self.peak,
        };
        if take {
            self.time = s.report.time;
            self.peak = s.report.max_slip_rate;
            let v = &s.state.kinematics.v;
            for (r, &p) in self
                .slip_rates
                .iter_mut()
                .zip(&s.model.frictional_boundary.nodes)
            {
                *r = v[3 * p].hypot(v[3 * p + 2]);
            }
        }
        Ok(Flow::Continue(()))
    }
}

/// The model on the processes of a job: the node owners (a partition of the finest mesh),
/// which also share out the frames' cells; each rank assembles its own nodes' columns of
/// the matrices and the ranks solve the initial equilibrium together (docs/scaling.md
/// "Phase 7"). Returns the model and the ranks' TNNMG settings.
fn model_on_ranks(
    scene: &Slider3dScene,
    p: &dyn Processes,
) -> Result<(Model<3>, rsf::method::TnnmgOnRanks), AnyError> {
    let builder = scene.model_builder()?;
    let owner = partition(builder.mesh(), p.size())?;
    let keep: Vec<bool> = owner.iter().map(|&r| r == p.rank()).collect();
    let ranks = rsf::method::TnnmgOnRanks::new(owner, p.transports());
    let model = builder.build_columns(&keep, |system| {
        rsf::model::equilibrium_on_ranks::<3>(
            system.stiffness,
            system.fixed,
            system.load,
            system.prolongations,
            (&ranks.owner, (ranks.transport)()),
        )
    })?;
    // The conditioning of the whole model: each rank's scales are of its columns.
    scene.slider.check_scales(&whole_scales(&model, p))?;
    Ok((model, ranks))
}

/// The output bound, before any file: a series row per step, a frame of every vertex
/// and cell every --frame-every steps. In pieces (on ranks, `frame_owner`): every piece's
/// points and cells (the border points in more than one piece), the `.pvtu` (about 1.1 kB
/// and 40 bytes per piece) counted as 8 more points (1.6 kB) per piece.
fn check_output_bound(
    cli: &Cli,
    s: &rsf_scenes::SliderScene,
    model: &Model<3>,
    frame_owner: Option<&[usize]>,
    owner_ranks: usize,
) -> Result<(), AnyError> {
    let steps = steps_bound(s, (0.0, s.end_time_s));
    let (frame_points, frame_cells) = match frame_owner {
        Some(owner) => {
            let sizes = rsf::observe::VtuFrames::piece_sizes(&model.cells, 4, owner, owner_ranks);
            sizes
                .iter()
                .fold((8 * sizes.len(), 0), |(p, c), s| (p + s.0, c + s.1))
        }
        None => (model.num_nodes(), model.cells.len() / 4),
    };
    let frames_bytes =
        cli.frames
            .bytes_bound(DEFAULT_FRAME_EVERY, steps, frame_points, frame_cells)
            + cli
                .frames
                .fields
                .bytes_bound(steps, model.num_nodes(), (model.cells.len() / 4, 4));
    check_output_size(
        steps.min(cli.folder.max_steps.map_or(f64::INFINITY, |m| m as f64)) * SERIES_ROW_BYTES_3D
            + frames_bytes,
        cli.limits.max_output_gb,
        "steps",
    )?;
    Ok(())
}

/// The solver of a run on MPI ranks: TNNMG, which the ranks share (`auto` chooses it).
///
/// # Errors
/// Another solver asked for by `--solver`.
fn solver_on_ranks(solver: rsf::SolverKind) -> Result<rsf::SolverKind, AnyError> {
    match solver {
        rsf::SolverKind::Auto | rsf::SolverKind::Tnnmg => Ok(rsf::SolverKind::Tnnmg),
        other => Err(format!(
            "on MPI ranks the velocity problems are solved by TNNMG on the ranks: \
             --solver {other} is not shared (use --solver tnnmg or auto)"
        )
        .into()),
    }
}

/// The run's last lines: steps and time, the mean iterations per step, the first slip
/// event and the snapshot (from the series file `series_csv`).
///
/// # Errors
/// Reading the series.
fn report(
    series_csv: &std::path::Path,
    summary: &rsf::RunSummary,
    snapshot: &FaultSnapshot,
) -> Result<(), AnyError> {
    let rows = PointSeries::<3>::read(series_csv)?;
    let steps = rows.len().max(1) as f64;
    let fpi = rows.iter().map(|r| r.fixed_point_iterations).sum::<usize>() as f64 / steps;
    let its = rows.iter().map(|r| r.solver_iterations).sum::<usize>() as f64 / steps;
    let first_event = rows.iter().find(|r| r.max_slip_rate > 1e-3).map(|r| r.time);
    println!(
        "{} steps in {:.2} s ({:.3} s per step) on {}",
        summary.steps,
        summary.seconds,
        summary.seconds / summary.steps.max(1) as f64,
        crate::machine()
    );
    println!(
        "per step: fixed point iterations {fpi:.2}, solver iterations {its:.2}; first slip event (max V > 1e-3 m/s): {}; snapshot at t = {:.4} s (max V {:.3e} m/s)",
        first_event.map_or("none".into(), |t| format!("{t:.4} s")),
        snapshot.time,
        snapshot.peak
    );
    Ok(())
}

fn run(cli: Cli, prepared: Prepared, processes: Option<&dyn Processes>) -> Result<(), AnyError> {
    let mut scene = scene(&cli)?;
    let root = processes.is_none_or(|p| p.rank() == 0);
    if processes.is_some() {
        scene.slider.solver = solver_on_ranks(scene.slider.solver)?;
    }
    let s = &scene.slider;
    let out = cli.out.clone();
    let folder = RunFolder::new(&out, "slider_3d", &OUTPUTS);
    let println = |line: String| {
        if root {
            println!("{line}");
        }
    };
    println(format!(
        "slider_3d: level {}, W = {} m, {:?} lateral faces, N = {} (τ = {:.3e} s), {} law, {}, {} solver → {}",
        s.level,
        scene.width_m,
        scene.lateral,
        s.steps,
        s.tau(),
        s.state_law,
        s.integrator,
        s.solver,
        out.display()
    ));
    let setup = std::time::Instant::now();
    let mut options = scene.slider.solver_options();
    options.parallelism = cli.threads;
    if let Some(gib) = cli.memory_budget_gib {
        options.memory_budget_bytes = crate::memory_budget_bytes("--memory-budget-gib", gib)?;
    }
    // On ranks: each rank assembles its own nodes' columns ([`model_on_ranks`]).
    let owner_ranks = processes.map_or(1, |p| p.size());
    let (model, frame_owner) = match processes {
        None => (cli.slider.named(scene.build_model())?, None),
        Some(p) => {
            let (model, ranks) = model_on_ranks(&scene, p)?;
            let frame_owner = (p.size() > 1).then(|| ranks.owner.to_vec());
            options.ranks = Some(ranks);
            if root {
                eprintln!("{} MPI ranks share every velocity solve", p.size());
            }
            (model, frame_owner)
        }
    };
    let mut sim = scene
        .simulation_builder_with_model(model)?
        .solver_options(options)
        .build()?;
    let model = sim.model();
    let x0 = model.nearest_node(&scene.centre())?;
    let series_csv = out.join("timeseries.csv");
    check_output_bound(&cli, s, model, frame_owner.as_deref(), owner_ranks)?;
    let frame_every = cli.frames.frame_every.unwrap_or(DEFAULT_FRAME_EVERY);
    // What changes the files besides the scene: the frame spacing.
    let fingerprint = cli
        .frames
        .fields
        .fingerprint(scene.fingerprint().with("frame_every", frame_every));
    // Everything is checked before any file is touched: folder (the guard), checkpoint
    // (every rank restores the whole state), then rank 0 the rows it continues.
    let session = Session::start(
        SessionFlags {
            resume: cli.resume.as_deref(),
            allow_change: &cli.folder.allow_change,
            checkpoint_every: cli.checkpoint_every,
            step_cap: cli.folder.max_steps,
        },
        folder.path("checkpoint.bin"),
        fingerprint,
        s.end_time_s,
        &mut sim,
    )?;
    if let (Some(c), true) = (session.resumed(), root) {
        PointSeries::<3>::check_resume(&series_csv, c.state.step)?;
        PointSeries::<3>::check_checkpoint_row(&series_csv, c, x0)?;
    }
    let mode = session.mode(prepared.mode());
    // The fields file (`--hdf5 N`, rank 0) first: it proves it holds the checkpoint's run
    // before anything is cut.
    let mut fields = match root {
        true => cli.frames.fields.observer(
            ("slider_3d", &out),
            FieldsRun::of(&session, prepared.mode(), &cli.folder.allow_change),
            |w, target| w.volume_3d(target),
        )?,
        false => None,
    };
    // Frames next: a missing index on resume is refused before the series is continued.
    // On more than one rank every rank writes its piece of each frame (the cells whose
    // lowest-numbered vertex it owns), rank 0 the `.pvtu` and the index; on one rank the
    // one-process files.
    let mut frames = match (processes, frame_owner) {
        (Some(p), Some(owner)) => {
            cli.frames
                .pieces(DEFAULT_FRAME_EVERY, &out, mode, owner, p.group())?
        }
        _ => cli.frames.observer(DEFAULT_FRAME_EVERY, &out, mode)?,
    };
    if !root {
        // The same steps as rank 0, its frame pieces the only files (no observer here ends
        // a run; rank 0 reports a step cap).
        let mut observers: Vec<&mut dyn Observer<3>> = Vec::new();
        if let Some(f) = frames.as_mut() {
            observers.push(f);
        }
        session.follow(&mut sim, &mut observers)?;
        return Ok(());
    }
    let model = sim.model();
    let mut series = PointSeries::new(&series_csv, model, x0, mode)?;
    let mut snapshot = FaultSnapshot::new(cli.snapshot_time, model.frictional_boundary.nodes.len());
    println(format!(
        "{} dofs, {} frictional nodes, {} solver; set-up {:.2} s",
        model.num_dofs(),
        model.frictional_boundary.nodes.len(),
        sim.method().solver_name(),
        setup.elapsed().as_secs_f64()
    ));
    let mut observers: Vec<&mut dyn Observer<3>> = vec![&mut series, &mut snapshot];
    if let Some(f) = frames.as_mut() {
        observers.push(f);
    }
    if let Some(f) = fields.as_mut() {
        observers.push(f.as_mut());
    }
    let progress = Progress::steps(s.steps, "slider 3-D");
    let summary = session.run(&mut sim, &mut observers, Some(progress))?;
    drop(observers);
    snapshot.write(sim.model(), scene.width_m, &out)?;

    report(&series_csv, &summary, &snapshot)
}
