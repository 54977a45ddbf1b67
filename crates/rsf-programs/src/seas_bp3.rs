//! A coarse SEAS BP3-QD (a thrust or normal fault dipping under a free surface, plane
//! strain, quasi-dynamic; docs/seas-bp3.md): the fault inside the body
//! (`ModelBuilder::internal_fault`), its normal stress changing with slip
//! (`NormalStress::FromSlip`), loaded by creep below W_f (`internal_creep`) and by each
//! side's rigid motion on the far boundaries, integrated by the fault ODE.
//!
//! ```sh
//! cargo run --release --example seas_bp3 -- --dip 60 --out out/bp3_60 --end-years 300
//! cargo run --release --example seas_bp3 -- --dip 30 --dx 250 --out out/bp3_30
//! ```
//!
//! The scene is `rsf_scenes::SeasBp3` (the mesh: a graded structured mesh sheared along
//! the dip, `SeasBp3::mesh`; the parameters: BP1's table, which BP3 shares, with the depth
//! replaced by the down-dip distance x_d).
//!
//! Writes the benchmark's files to `--out` (`SeasBp3::seas_setup`: the twelve on-fault
//! stations `fltst_dpXXX` with six columns — slip, log10 V, shear and normal stress,
//! log10 θ — the eight surface stations `srfst_fn…` with displacement and velocity, the
//! profiles `slip.dat`, `shear_stress.dat` and `normal_stress.dat`, the event catalogue
//! `events.csv`), the figure `overview.png` (slip profiles, maximum slip rate against
//! time), and prints the events.
//!
//! Runs: `--checkpoint-every N` (a checkpoint `checkpoint.bin` every N steps, the files
//! and their resume log `seas_resume.csv` written at the same steps), `--resume FILE`
//! (continues the files in `--out` from a checkpoint of this run: the same bytes as an
//! uninterrupted run), `--max-steps N` (stop after step N in total, with a checkpoint),
//! `--overwrite` (a folder of another run is refused, and left untouched, otherwise).

use std::path::PathBuf;
use std::time::Instant;

use crate::config::ConfigArgs;
use crate::estimates::{operator_bytes, seas_output_bytes, SEAS_BYTES_PER_NODE};
use crate::fields::FaultSize;
use crate::guard::{number, AnyError, Plan, Prepared};
use crate::seas_args::run_observed;
use crate::{cpu_seconds, machine};
use clap::Parser;
use rsf::observe::{Progress, TimeUnit};
use rsf::Stepping;
use rsf_ranks::Processes;
use rsf_scenes::SEAS_BP3_SURFACE_STATIONS;
use rsf_scenes::{
    KernelChoice, RunConfig, SeasBp1, SeasBp3, SeasBp3Run, SEAS_BP3_STATION_DISTANCES,
};
use rsf_seas::{SeasSampling, SeasSetup, SECONDS_PER_YEAR};

/// A coarse SEAS BP3-QD.
#[derive(Parser)]
#[command(version)]
pub struct Args {
    /// The run's settings (`rsf_scenes::SeasBp3Run`: these flags, or `--config`'s keys;
    /// Python's `rsf.seas_bp3` keywords).
    #[command(flatten)]
    pub(crate) settings: SeasBp3Run,
    #[command(flatten)]
    config: ConfigArgs,
    /// Output folder.
    #[arg(long, default_value = "out/seas_bp3")]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out` (without it, a folder holding any
    /// rsf program's run is refused and left untouched).
    #[arg(long)]
    overwrite: bool,
    /// Threads of each evaluation (the operator products and the per-node friction
    /// solves; the same bits for every value). Default: every core of the machine.
    #[arg(long, default_value_t = rsf::Parallelism::available_cores())]
    threads: usize,
    #[command(flatten)]
    header: crate::SeasHeaderArgs,
    /// `--checkpoint-every N` (a checkpoint `checkpoint.bin` every N steps, the files'
    /// resume log `seas_resume.csv` at the same steps), `--resume FILE` (continues the
    /// files in `--out`: the checkpoint and every file's rows are checked before anything
    /// is cut), `--allow-change`, `--max-steps N`; `--hdf5 N`; the limits.
    #[command(flatten)]
    pub(crate) job: crate::seas_args::JobArgs,
}

/// The scene of the settings (its parameters BP1's table).
fn scene(run: &SeasBp3Run) -> SeasBp3 {
    run.scene(SeasBp1::default())
}

/// The files a run writes into `--out`.
fn outputs() -> Vec<String> {
    let mut names = SeasBp3::file_names();
    names.extend(["overview.png", "checkpoint.bin"].map(String::from));
    names
}

crate::seas_args::configured_program!(Args, "seas_bp3", job);

impl Args {
    /// The plan of the checked settings (issue 87: `--dip 1e-300` ended in "cell 0 is
    /// degenerate"; measured: 1e-5° degenerates, 1e-3° still meshes at the default --dx;
    /// the settings' check refuses below 1°, a margin for every --dx, BP3's dips, 30° and
    /// 60°, well inside).
    fn planned(&self) -> Result<Plan, AnyError> {
        let run = &self.settings;
        let (bp3, grid) = (scene(run), run.grid());
        let w_f = bp3.params.w_f;
        self.header.check()?;
        // The graded mesh in closed form (rsf_fem::geometric_grading_len, as SeasBp3::mesh
        // grades it), before anything is allocated.
        let (s, _) = run.dip.to_radians().sin_cos();
        let side = rsf::fem::geometric_grading_len(grid.dx, 2.0 * grid.dx, grid.ratio, grid.domain);
        let nz = rsf::fem::geometric_grading_len(grid.dx * s, w_f * s, grid.ratio, grid.domain * s);
        let nodes = (2.0 * side - 1.0) * nz + nz;
        let hierarchical = run.kernel == KernelChoice::Hierarchical;
        let memory = nodes * SEAS_BYTES_PER_NODE + 2.0 * operator_bytes(nz, hierarchical);
        let profile = grid.domain / 500.0 + 1.0;
        let stations = (SEAS_BP3_STATION_DISTANCES.len() + SEAS_BP3_SURFACE_STATIONS.len()) as f64;
        let plan = Plan::new()
            .memory(
                memory,
                "--dx, --domain-km, --ratio",
                format!(
                    "BP3 on dx = {} m, domain = {} km, ratio = {}: about {nodes:.3e} nodes, \
                     {nz:.3e} on the fault",
                    number(run.dx),
                    number(run.domain_km),
                    number(run.ratio)
                ),
            )
            .output(
                seas_output_bytes(run.end_years, stations, 8, 3.0 * profile),
                "--end-years, --domain-km",
                format!(
                    "{} years of {stations} stations and 3 profiles of {profile:.3e} values",
                    run.end_years
                ),
            );
        // The fault's fields (--hdf5): its nodes and the segments between them.
        let fault = FaultSize::of(nz + 1.0, (nz, 2.0));
        self.flags().plan(plan, outputs(), run.fingerprint(), fault)
    }
}

crate::seas_args::ranked_entry_points! {
    Args, run, job;
    /// The program `seas_bp3` (`cargo run --release --example seas_bp3 -- --out DIR …`).
    main,
    /// The program `seas_bp3` with `writers` of the fault's fields (`--hdf5 N`,
    /// [`FieldWriters::fault_2d`](crate::fields::FieldWriters::fault_2d); the binary
    /// `seas_bp3` of crates/rsf-hdf5).
    main_with_fields,
    /// The program on the processes of a job (MPI ranks, the `rsf-mpi` crate's `seas_bp3`):
    /// every evaluation of the fault ODE shared by the ranks
    /// ([`rsf::FaultOde::share_evaluations`]; the dense or the ℋ-kernel, the normal stress
    /// evaluated whole on every rank), the files written by rank 0 — byte-identical to one
    /// process's (docs/scaling.md, "The fault ODE on MPI ranks").
    ///
    /// With `writers` (the `rsf-mpi` crate built with its feature `hdf5`), `--hdf5 N`
    /// writes the fault's fields from rank 0, as [`main_with_fields`] does in one process.
    main_on_ranks,
}

fn run(args: Args, folder: Prepared, processes: Option<&dyn Processes>) -> Result<(), AnyError> {
    // Rank 0 (or the one process) writes the files and tells.
    let root = processes.is_none_or(|p| p.rank() == 0);
    let settings = args.settings;
    let (bp3, grid) = (scene(&settings), settings.grid());
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let model = bp3.model(&grid)?;
    let fb = &model.frictional_boundary;
    if root {
        println!(
            "BP3-QD, dip {}° ({}), Δx = {} m, box ±{} km, {} nodes, {} frictional nodes; on {}",
            settings.dip,
            if bp3.normal_faulting {
                "normal"
            } else {
                "thrust"
            },
            settings.dx,
            settings.domain_km,
            model.vertices.len(),
            fb.len(),
            machine()
        );
    }
    let options = settings.fault_ode_options(&bp3, args.threads)?;
    let mut ode = bp3.fault_ode(model, options)?;
    if let Some(p) = processes {
        ode.share_evaluations(p.group())?;
    }
    if root {
        println!("S: {}", ode.kernel_report());
        if let Some(r) = ode.normal_kernel_report() {
            println!("S_N: {r}");
        }
        if let Some(p) = processes {
            println!("{} MPI ranks share every evaluation", p.size());
        }
        println!(
            "set-up: wall {:.1} s, CPU {:.1} s",
            clock.elapsed().as_secs_f64(),
            cpu_seconds() - cpu0
        );
    }
    let setup = SeasSetup {
        modeler: args.header.modeler.clone(),
        date: args.header.date_or_today(),
        ..bp3.seas_setup(settings.dx, SeasSampling::default())
    };
    // The checkpoint is checked and restored before any file is touched, then the files'
    // rows up to its step.
    let flags = args.flags();
    let end = settings.end_years * SECONDS_PER_YEAR;
    let step_cap = folder.step_cap(args.job.run.max_steps);
    let session = flags.session(step_cap, settings.fingerprint(), end, &mut ode)?;
    if !root {
        // The same steps as rank 0, no files (no observer here ends a run).
        session.follow(&mut ode, &mut [])?;
        return Ok(());
    }
    let mut fields = flags.fields_observer(&session, folder.mode(), |w, t| w.fault_2d(t))?;
    let mut output = rsf_seas::SeasOutput::for_session(
        &session,
        &args.out,
        ode.model(),
        ode.problem().friction_laws(),
        setup,
        folder.mode(),
    )?;
    // The fault ODE computes the surface stations' vertices (not the whole field) after
    // every step; their initial row needs them now.
    ode.watch_vertices(&output.surface_vertices())?;
    if session.resumed().is_none() {
        output.write_initial_state(ode.model(), ode.state())?;
    }
    let year = TimeUnit::year(SECONDS_PER_YEAR);
    let progress = Progress::time_in(ode.state().time, end, year, "BP3");
    let files = vec![&mut output as &mut dyn rsf::Observer<2>];
    let summary = run_observed(session, &mut ode, files, &mut fields, progress)?;
    let wall = clock.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - cpu0;
    for e in output.events() {
        println!(
            "event at {:.3} yr: peak slip rate {:.3e} m/s, hypocentre x_d = {:.2} km",
            e.t_start / SECONDS_PER_YEAR,
            e.peak_slip_rate,
            e.hypocentre_depth / 1e3
        );
    }
    println!(
        "{} steps ({} attempts rejected, {} of them for σ̄_n ≤ 0 at a stage), {} evaluations; \
         wall {wall:.1} s, CPU {cpu:.1} s; wrote {}",
        summary.steps,
        summary.rejected_attempts,
        summary.rejected_normal_stress,
        ode.evaluations(),
        args.out.display()
    );
    println!(
        "integrator: {}",
        crate::IntegratorArgs {
            integrator: settings.integrator
        }
        .summary(Some(ode.integrator_stats()))
    );
    crate::seas_overview(
        &args.out,
        "slip.dat",
        "down-dip distance (km)",
        output.events().len(),
    )?;
    println!("wrote {}", args.out.join("overview.png").display());
    Ok(())
}
