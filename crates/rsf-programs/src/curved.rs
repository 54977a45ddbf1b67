//! The figure of the curved-fault example (the arc block itself is in `rsf_scenes`).

use std::path::Path;

use crate::{line_plot, Labels, PlotResult, Series, SliderRun};

/// The figure `path` of a run's largest slip rate on the fault against time (log scale).
///
/// # Errors
/// Drawing or writing the PNG.
pub fn max_slip_rate_figure(path: &Path, title: &str, run: &SliderRun) -> PlotResult {
    let rate: Vec<(f64, f64)> = run
        .max_slip_rate
        .iter()
        .map(|&(t, v)| (t, v.max(1e-40)))
        .collect();
    line_plot(
        path,
        &Labels {
            title,
            x: "t (s)",
            y: "max slip rate (m/s)",
        },
        &Series::alone(&rate),
        true,
        false,
    )
}
