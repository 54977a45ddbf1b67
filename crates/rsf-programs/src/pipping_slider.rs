//! The run driver of the `pipping_slider` example (the paper's model problem, Pipping,
//! Sander & Kornhuber §6.1, Table 6.1), as a library function so that tests run it exactly
//! as the example does (`tests/resume_end_to_end.rs`). See the example's documentation
//! for the flags and the files it writes.

use std::path::PathBuf;

use crate::cli::describe_method;
use crate::cli::{for_flag, window};
use crate::estimates::{slider_fault_nodes, slider_memory, slider_what, RECORDED_STEP_BYTES};
use crate::fields::FieldsRun;
use crate::guard::{AnyError, Limits, Plan, Prepared, Program};
use crate::run_folder::FolderArgs;
use crate::session::{Session, SessionFlags};
use crate::{
    line_plot, space_time_map, stats, write_summary, FieldMap, FrameArgs, Labels, Series,
    SliderArgs, SliderRun,
};
use clap::Parser;
use rsf::observe::{Every, FrictionalProfile, Interval, PointSeries};
use rsf::run_folder::check_window;
use rsf::run_folder::RunFolder;
use rsf::Observer;
use rsf_scenes::plan_output;
use rsf_scenes::{SliderScene, SLIDER_CENTRE};

/// The paper's slider (§6.1, Table 6.1): time series at x0, fault profile, summary, figures.
#[derive(Parser, Debug, Clone)]
#[command(name = "pipping_slider", version)]
pub struct Cli {
    /// The scene's fields as flags, `--scene FILE.toml`, `--adaptive TOL`.
    #[command(flatten)]
    pub slider: SliderArgs,
    /// Profile window T0,T1 (s) [default: 0.6725T,0.6775T].
    #[arg(long, value_parser = window, value_name = "T0,T1")]
    pub window: Option<(f64, f64)>,
    /// Output folder.
    #[arg(long, default_value = "out/pipping_slider")]
    pub out: PathBuf,
    /// Write `checkpoint.bin` every N steps (0: never).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub checkpoint_every: usize,
    /// Continue from this checkpoint, appending to the files in the output folder (the
    /// checkpoint, the folder's rows and the scene are checked to belong together first).
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    #[command(flatten)]
    pub folder: FolderArgs,
    #[command(flatten)]
    pub frames: FrameArgs,
    /// Threads of every parallel part of a step (`rsf::method::SolverOptions::parallelism`):
    /// a count, `0` or `pool` for rayon's pool, `seq` for one; default every core of the
    /// machine. The output does not depend on it. (The node order of TNNMG's smoothers is
    /// the scene's `--tnnmg-smoother`: `lexicographic`, the default and the paper's
    /// figures, sequential; `multicolour` or `red-black-chunks` on these threads, the same
    /// bits for every thread count, other round-off than lexicographic.)
    #[arg(long, default_value_t = rsf::Parallelism::default(), value_name = "N")]
    pub threads: rsf::Parallelism,
    #[command(flatten)]
    pub limits: Limits,
}

impl Cli {
    /// The scene of the flags and the scene file, validated.
    fn scene(&self) -> Result<SliderScene, AnyError> {
        self.slider.scene()
    }

    /// The profile window (s) of the flags or the scene's default.
    fn window(&self, t_end: f64) -> (f64, f64) {
        self.window.unwrap_or((0.6725 * t_end, 0.6775 * t_end))
    }
}

impl Program for Cli {
    crate::name_and_limits!("pipping_slider");

    fn plan(&self) -> Result<Plan, AnyError> {
        let scene = self.scene()?;
        let (w0, w1) = self.window(scene.end_time_s);
        for_flag(
            "--window",
            "window",
            check_window("window", (w0, w1), scene.end_time_s),
        )?;
        // The output bound of the run (the library's plan, with the slider's frictional
        // nodes in closed form): refused here before any work.
        let output = for_flag(
            "--max-steps",
            "max_steps",
            for_flag(
                "--steps",
                "steps",
                plan_output(
                    &scene,
                    (w0, w1),
                    slider_fault_nodes(scene.level) as usize,
                    600,
                    rsf_scenes::OutputLimits {
                        max_steps: self.folder.max_steps,
                        max_gb: self.limits.max_output_gb,
                    },
                ),
            ),
        )?;
        // The series is read back into memory at the end (a row per step, at most the
        // step cap or the step bound).
        let rows = crate::estimates::slider_steps(&scene)
            .min(output.step_cap.map_or(f64::INFINITY, |c| c as f64))
            .min(self.folder.max_steps.map_or(f64::INFINITY, |c| c as f64));
        let memory = slider_memory(&scene) + rows * RECORDED_STEP_BYTES;
        self.frames.fields.check(Self::NAME)?;
        let fields = self.frames.fields.bytes_bound(
            rows,
            crate::estimates::slider_nodes(scene.level).min(1e18) as usize,
            // Two triangles per square of the 5·2ʲ × 2ʲ grid.
            (
                (10.0 * 4f64.powi(scene.level.min(500) as i32)).min(1e18) as usize,
                3,
            ),
        );
        let what = slider_what(&scene);
        Ok(Plan::new()
            .threads("--threads", self.threads.threads())
            .memory(memory, "--level, --steps (or --scene)", what.clone())
            .output(
                output.bytes + fields,
                "--steps, --window, --hdf5 (or --scene)",
                what,
            )
            .folder(
                self.folder
                    .out_folder(&self.out, &OUTPUTS, self.resume.as_deref())
                    .fingerprint(self.fingerprint(&scene)),
            ))
    }
}

impl Cli {
    /// What a checkpoint continues: the scene and, besides it, what changes the files —
    /// the profile window and the frame spacing (a resume with another window would mix
    /// two windows in the profile). The plan's too: a checkpoint is checked against it
    /// before the folder changes.
    fn fingerprint(&self, scene: &SliderScene) -> rsf::checkpoint::Fingerprint {
        let (w0, w1) = self.window(scene.end_time_s);
        self.frames.fields.fingerprint(
            scene
                .fingerprint()
                .with("window", format!("{w0:e},{w1:e}"))
                .with("frame_every", self.frames.frame_every.unwrap_or(0)),
        )
    }
}

/// The files a run writes into its folder.
const OUTPUTS: [&str; 11] = [
    crate::fields::FIELDS_FILE,
    crate::fields::FIELDS_INDEX,
    "timeseries.csv",
    "frictional_profile.csv",
    "slip_rate_map.csv",
    "checkpoint.bin",
    "summary.json",
    "displacement_x0.png",
    "slip_rate_x0.png",
    "slip_rate_map.png",
    "frames/frames.pvd",
];

/// The program `pipping_slider` with `writers` of its fields (`--hdf5 N`: the fields of
/// the body, [`FieldWriters::volume_2d`](crate::fields::FieldWriters::volume_2d); the binary
/// `pipping_slider` of crates/rsf-hdf5).
pub fn main_with_fields(
    writers: std::sync::Arc<dyn crate::fields::FieldWriters>,
) -> std::process::ExitCode {
    crate::guard::main_supplied(
        |cli: &mut Cli| cli.frames.fields.supply(writers),
        run_prepared,
    )
}

/// Runs the example with the flags `cli` (what `main` does).
///
/// # Errors
/// Every error of the run, typed: invalid flags or scene, a refused folder or checkpoint,
/// a run stopped at `--max-steps`, solver and I/O errors.
pub fn run(cli: Cli) -> Result<(), AnyError> {
    let prepared = crate::guard::prepare(&cli)?;
    run_prepared(cli, prepared)
}

/// The run of `cli` in its folder, which the guard has prepared (`prepared`: its file
/// mode and lock; [`crate::guard::prepare`]).
///
/// # Errors
/// As [`run`].
pub fn run_prepared(cli: Cli, prepared: Prepared) -> Result<(), AnyError> {
    let scene = cli.scene()?;
    let t_end = scene.end_time_s;
    let (w0, w1) = cli.window(t_end);
    let folder = RunFolder::new(&cli.out, "pipping_slider", &OUTPUTS);
    let out = folder.dir.clone();
    println!(
        "pipping_slider: {} → {}",
        describe_method(&scene),
        out.display()
    );

    let setup = std::time::Instant::now();
    let mut options = scene.solver_options();
    options.parallelism = cli.threads;
    let mut sim = cli
        .slider
        .named(scene.simulation_builder())?
        .solver_options(options)
        .build()?;
    let x0 = sim.model().nearest_node(&SLIDER_CENTRE)?;
    let (series_csv, profile_csv, map_csv) = (
        folder.path("timeseries.csv"),
        folder.path("frictional_profile.csv"),
        folder.path("slip_rate_map.csv"),
    );
    // The output bound: a series row per step, a profile row per node and step in the
    // window and per node of 600 map samples; the steps bounded by N (fixed), or by
    // T / tau_min_s and --max-steps (adaptive; without --max-steps, a cap that fits in
    // --max-output-gb).
    let plan = plan_output(
        &scene,
        (w0, w1),
        sim.model().frictional_boundary.len(),
        600,
        rsf_scenes::OutputLimits {
            max_steps: cli.folder.max_steps,
            max_gb: cli.limits.max_output_gb,
        },
    )?;
    if let Some(cap) = plan.step_cap {
        println!(
            "at most {cap} steps (output at most {:.3} GB)",
            plan.bytes / 1e9
        );
    }
    // Besides the scene, what changes the files: the profile window and the frame
    // spacing (a resume with another window would mix two windows in the profile).
    let fingerprint = cli.fingerprint(&scene);
    // Everything is checked before any file is touched: folder (the guard), checkpoint,
    // rows.
    let session = Session::start(
        SessionFlags {
            resume: cli.resume.as_deref(),
            allow_change: &cli.folder.allow_change,
            checkpoint_every: cli.checkpoint_every,
            step_cap: plan.step_cap,
        },
        folder.path("checkpoint.bin"),
        fingerprint,
        t_end,
        &mut sim,
    )?;
    if let Some(c) = session.resumed() {
        let step = c.state.step;
        PointSeries::<2>::check_resume(&series_csv, step)?;
        FrictionalProfile::<2>::check_resume(&profile_csv, step)?;
        FrictionalProfile::<2>::check_resume(&map_csv, step)?;
        PointSeries::<2>::check_checkpoint_row(&series_csv, c, x0)?;
    }
    let (resumed_at, wall_time_before) = (session.resumed_step(), session.wall_time_before());
    let mode = session.mode(prepared.mode());
    // 600 samples of the map: every N/600 steps, or every T/600 s for adaptive steps.
    let map_every = match sim.method().step_control() {
        Some(_) => Interval::Time(t_end / 600.0),
        None => Interval::Steps((scene.steps / 600).max(1)),
    };
    // Frames first: a missing index on resume is refused before the CSVs are continued.
    // The fields file (`--hdf5 N`) before them: it proves it holds the checkpoint's run
    // before anything is cut.
    let mut fields = cli.frames.fields.observer(
        ("pipping_slider", &out),
        FieldsRun::of(&session, prepared.mode(), &cli.folder.allow_change),
        |w, target| w.volume_2d(target),
    )?;
    let mut frames = cli.frames.observer(0, &out, mode)?;
    let mut series = PointSeries::new(&series_csv, sim.model(), x0, mode)?;
    let mut profile = FrictionalProfile::new(&profile_csv, (w0, w1), mode)?;
    let mut map = Every::new(
        map_every,
        FrictionalProfile::new(&map_csv, (0.0, t_end), mode)?,
    )?;
    let progress = scene.progress(sim.time(), "slider");
    let mut observers: Vec<&mut dyn Observer<2>> = vec![&mut series, &mut profile, &mut map];
    if let Some(f) = frames.as_mut() {
        observers.push(f);
    }
    if let Some(f) = fields.as_mut() {
        observers.push(f.as_mut());
    }
    let setup_seconds = setup.elapsed().as_secs_f64();
    let summary = session.run(&mut sim, &mut observers, Some(progress))?;
    drop(observers);

    // Everything below comes from the files: the whole run, also after a resume.
    let mut run = SliderRun::from_series(&PointSeries::<2>::read(&series_csv)?);
    run.set_map_from_profile(&FrictionalProfile::<2>::read(&map_csv)?);
    (run.dofs, run.frictional_nodes) = (
        sim.model().num_dofs(),
        sim.model().frictional_boundary.len(),
    );
    // Wall time of the whole run: this invocation's steps plus the resumed checkpoint's.
    (run.seconds, run.setup_seconds) = (wall_time_before + summary.seconds, setup_seconds);
    run.rejected_steps = sim.state().controller.map_or(0, |c| c.rejected());
    let st = stats(&run, t_end);
    write_summary(&out, &scene, &run, &st)?;

    figures(&out, &run)?;
    println!(
        "{} dofs, {} steps ({} rejected; {} in this run{}) in {:.2} s (set-up {:.2} s) on {}",
        run.dofs,
        run.fpi.len(),
        run.rejected_steps,
        summary.steps,
        resumed_at.map_or(String::new(), |n| format!(", resumed at step {n}")),
        run.seconds,
        run.setup_seconds,
        crate::machine()
    );
    println!(
        "fixed point iterations: mean {:.2}, max {}; solver iterations {}; relaxed steps {}",
        st.fpi_mean, st.fpi_max, st.solver_iterations, st.relaxed_steps
    );
    println!(
        "first slip event (time of the first step with max V > 1e-3 m/s): {}; slip events: {}; peak slip rate {:.3e} m/s; u_x0 over [0.9T, T]: {:.3e} … {:.3e} m",
        st.first_slip_event_s.map_or("none".into(), |t| format!("{t:.3} s")),
        st.slip_events,
        st.peak_slip_rate_mps,
        st.u_x0_range_last_tenth_m.0,
        st.u_x0_range_last_tenth_m.1
    );
    Ok(())
}

/// The figures of a run: the displacement and the slip rate at x0 against time, the slip
/// rate along the frictional boundary against time (PNG in `out`).
fn figures(out: &std::path::Path, run: &SliderRun) -> Result<(), AnyError> {
    line_plot(
        &out.join("displacement_x0.png"),
        &Labels {
            title: "Displacement u_x at x0 = (2.5, 0)",
            x: "t (s)",
            y: "u_x (m)",
        },
        &Series::alone(&run.u_x0),
        false,
        false,
    )?;
    let rate: Vec<(f64, f64)> = run
        .v_x0
        .iter()
        .map(|&(t, v)| (t, v.abs().max(1e-40)))
        .collect();
    line_plot(
        &out.join("slip_rate_x0.png"),
        &Labels {
            title: "Slip rate |v| at x0 = (2.5, 0)",
            x: "t (s)",
            y: "slip rate (m/s)",
        },
        &Series::alone(&rate),
        true,
        false,
    )?;
    space_time_map(
        &out.join("slip_rate_map.png"),
        "Slip rate along the frictional boundary",
        &FieldMap {
            xs: &run.map.1,
            ys: &run.map.0,
            values: &run.map.2,
        },
        (-12.0, -2.0),
    )?;
    Ok(())
}
