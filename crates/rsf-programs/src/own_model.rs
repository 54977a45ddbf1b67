//! The run of a slider example on a model of its own (`inclined_block`, `curved_fault`): a
//! time series at x0, a progress bar and, with `--frame-every`, VTU frames; then the run
//! read back from the series and its one-paragraph summary.

use std::path::{Path, PathBuf};

use rsf::observe::{FileMode, PointSeries};
use rsf::run_folder::{check_output_size, RunFolder, SERIES_ROW_BYTES};
use rsf::{Observer, Until};
use rsf_scenes::{steps_bound, SceneSimulation, SliderScene};

use crate::guard::{Folder, Limits, Plan};
use crate::{stats, FrameArgs, SliderRun, SliderStats};

/// The output flags of a slider example on a model of its own: the folder, whether an
/// earlier run's files there may be replaced, the output bound, the frames.
#[derive(Debug, Clone, clap::Args)]
pub struct OwnRunArgs {
    /// Output folder [default: the example's].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Replace the files of an earlier run in the output folder (without it, a folder
    /// holding any rsf program's run is refused and left untouched).
    #[arg(long)]
    pub overwrite: bool,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub frames: FrameArgs,
    /// `--max-memory-gb`, `--max-output-gb` (a series row per step, the frames).
    #[command(flatten)]
    pub limits: Limits,
}

/// A slider example's run on its own model: the program (its name in the run folder's
/// manifest), a label for the progress bar, the folder and the figure it writes there.
#[derive(Debug, Clone, Copy)]
pub struct OwnRun<'a> {
    /// The program's name (e.g. `inclined_block`).
    pub program: &'a str,
    /// The progress bar's label.
    pub label: &'a str,
    /// The output folder.
    pub out: &'a Path,
    /// The figure's file name in the folder.
    pub figure: &'a str,
    /// The output flags.
    pub args: &'a OwnRunArgs,
}

impl OwnRun<'_> {
    /// The files the run writes into its folder.
    fn outputs(&self) -> [&str; 3] {
        ["timeseries.csv", self.figure, "frames/frames.pvd"]
    }

    /// The run folder: the program and the files it writes.
    fn folder(&self) -> RunFolder {
        RunFolder::new(self.out, self.program, &self.outputs())
    }

    /// The plan of the run of `scene` (on a model of about the paper's slider's size at
    /// its level), from the flags alone: the memory, the output (a series row per step,
    /// the frames) and the folder ([`Plan`], which the guard checks and prepares before
    /// anything is computed: another run's files are refused unless `--overwrite`, the
    /// folder is locked and probed writable, no output path may be a folder).
    ///
    /// # Errors
    /// `--hdf5 N`: these examples have no build with a writer of fields
    /// ([`NoFieldWriter`](crate::fields::NoFieldWriter)).
    pub fn plan(&self, scene: &SliderScene) -> Result<Plan, crate::guard::AnyError> {
        self.args.frames.fields.check(self.program)?;
        let steps = steps_bound(scene, (0.0, scene.end_time_s));
        let k = 2f64.powi(scene.level.min(1000) as i32);
        let nodes = crate::estimates::slider_nodes(scene.level);
        let frames = self.args.frames.bytes_bound(
            0,
            steps,
            nodes.min(1e18) as usize,
            (10.0 * k * k).min(1e18) as usize,
        );
        let what = crate::estimates::slider_what(scene);
        Ok(Plan::new()
            .memory(
                crate::estimates::slider_memory(scene),
                "--level (or --scene)",
                what.clone(),
            )
            .output(
                steps * SERIES_ROW_BYTES + frames,
                "--steps, --end-time, --frame-every (or --scene)",
                what,
            )
            .folder(Folder::new("--out", self.out, &self.outputs()).overwrite(self.args.overwrite)))
    }
}

/// Runs `sim` (built from `scene`) to the scene's end time, writing `out/timeseries.csv` (a
/// [`PointSeries`] at vertex `x0`) and the frames the flags ask for, and returns the run
/// read back from the series with its statistics, into the folder the guard prepared
/// from [`OwnRun::plan`] (`mode`: its answer). Before the first step the output is bounded (a series
/// row per step of the scene's step bound, the frames: `--max-output-gb`).
///
/// # Errors
/// A refused folder or output bound, an unwritable file, and the run's errors.
pub fn run_with_series(
    scene: &SliderScene,
    sim: &mut SceneSimulation<2>,
    x0: usize,
    run: OwnRun<'_>,
    mode: FileMode,
) -> Result<(SliderRun, SliderStats), Box<dyn std::error::Error>> {
    let folder = run.folder();
    let steps = steps_bound(scene, (0.0, scene.end_time_s));
    let model = sim.model();
    let frames_bytes =
        run.args
            .frames
            .bytes_bound(0, steps, model.num_nodes(), model.cells.len() / 3);
    check_output_size(
        steps * SERIES_ROW_BYTES + frames_bytes,
        run.args.limits.max_output_gb,
        "steps",
    )?;
    let series_csv = folder.path("timeseries.csv");
    let mut frame_files = run.args.frames.observer(0, run.out, mode)?;
    let mut series = PointSeries::new(&series_csv, sim.model(), x0, mode)?;
    let mut progress = scene.progress(0.0, run.label);
    let mut observers: Vec<&mut dyn Observer<2>> = vec![&mut series, &mut progress];
    if let Some(f) = frame_files.as_mut() {
        observers.push(f);
    }
    let summary = sim.run_until(Until::Time(scene.end_time_s), &mut observers)?;
    drop(observers);
    let mut result = SliderRun::from_series(&PointSeries::<2>::read(&series_csv)?);
    (result.dofs, result.frictional_nodes) = (
        sim.model().num_dofs(),
        sim.model().frictional_boundary.len(),
    );
    result.seconds = summary.seconds;
    let st = stats(&result, scene.end_time_s);
    Ok((result, st))
}

/// Prints the size of a run (`frames` of its frictional nodes with nodal frames), its
/// steps and its events.
pub fn print_run(run: &SliderRun, st: &SliderStats, frames: usize) {
    println!(
        "{} dofs, {} frictional nodes ({frames} with nodal frames), {} steps in {:.2} s",
        run.dofs,
        run.frictional_nodes,
        run.fpi.len(),
        run.seconds
    );
    println!(
        "fixed point iterations: mean {:.2}, max {}; first slip event (max V > 1e-3 m/s): {}; \
         slip events: {}; peak slip rate {:.3e} m/s",
        st.fpi_mean,
        st.fpi_max,
        st.first_slip_event_s
            .map_or("none".into(), |t| format!("{t:.3} s")),
        st.slip_events,
        st.peak_slip_rate_mps
    );
}
