//! The run of a slider example on a model of its own (`inclined_block`, `curved_fault`): a
//! time series at x0, a progress bar and, with `--frame-every`, VTU frames; then the run
//! read back from the series and its one-paragraph summary.

use std::path::Path;

use rsf::observe::{FileMode, PointSeries};
use rsf::{Observer, Until};
use rsf_scenes::{SceneSimulation, SliderScene};

use crate::{stats, FrameArgs, SliderRun, SliderStats};

/// Runs `sim` (built from `scene`) to the scene's end time, writing `out/timeseries.csv` (a
/// [`PointSeries`] at vertex `x0`) and the frames `frames` asks for, and returns the run
/// read back from the series with its statistics.
///
/// # Errors
/// A refused or unwritable file (new files only: an earlier run's are refused), and the
/// run's errors.
pub fn run_with_series(
    scene: &SliderScene,
    sim: &mut SceneSimulation<2>,
    x0: usize,
    out: &Path,
    frames: &FrameArgs,
    label: &str,
) -> Result<(SliderRun, SliderStats), Box<dyn std::error::Error>> {
    let series_csv = out.join("timeseries.csv");
    let mut frame_files = frames.observer(0, out, FileMode::Create)?;
    let mut series = PointSeries::new(&series_csv, sim.model(), x0, FileMode::Create)?;
    let mut progress = scene.progress(0.0, label);
    let mut observers: Vec<&mut dyn Observer<2>> = vec![&mut series, &mut progress];
    if let Some(f) = frame_files.as_mut() {
        observers.push(f);
    }
    let summary = sim.run_until(Until::Time(scene.end_time_s), &mut observers)?;
    drop(observers);
    let mut run = SliderRun::from_series(&PointSeries::<2>::read(&series_csv)?);
    (run.dofs, run.frictional_nodes) = (
        sim.model().num_dofs(),
        sim.model().frictional_boundary.len(),
    );
    run.seconds = summary.seconds;
    let st = stats(&run, scene.end_time_s);
    Ok((run, st))
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
