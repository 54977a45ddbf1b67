//! Bounds on the output of a slider scene's run, before it starts: the number of steps,
//! the step cap that keeps an adaptive run's files within a size, the output plan of the
//! main job (docs/reliability.md).

pub use rsf::run_folder::OutputPlan;
use rsf::run_folder::{output_plan, OutputEstimate, PROFILE_ROW_BYTES, SERIES_ROW_BYTES};
use rsf::{Error, Result};

use crate::{SliderScene, TimeStep};

/// An upper bound on the number of steps of a run of `scene` that end in `(t0, t1]` (s):
/// fixed steps `⌈N (t1 − t0) / T⌉ + 1`; adaptive steps `⌈(t1 − t0) / tau_min_s⌉ + 2` — every
/// step the controller chooses is at least `tau_min_s`, and only a step shortened to land
/// on the end of the loading ramp or on `T` is shorter (one each).
pub fn steps_bound(scene: &SliderScene, (t0, t1): (f64, f64)) -> f64 {
    let span = (t1 - t0).max(0.0);
    match scene.time_step {
        TimeStep::Fixed {} => (span / scene.tau()).ceil() + 1.0,
        TimeStep::Adaptive(a) => (span / (a.tau_min_s * (1.0 - 1e-12))).ceil() + 2.0,
    }
}

/// The step cap of a run of `scene` writing or holding `bytes_per_step` bytes per accepted
/// step (docs/reliability.md): `max_steps` if given (refused if even that does not fit in
/// `max_gb` gigabytes), none if [`steps_bound`] steps fit, else for adaptive steps the
/// count that fits.
///
/// # Errors
/// [`Error::InvalidParameter`] named `max_output_gb` (not positive and finite),
/// `max_steps` (0, or its output above `max_gb`) or `steps` (fixed steps above `max_gb`).
pub fn step_cap(
    scene: &SliderScene,
    bytes_per_step: f64,
    max_steps: Option<u64>,
    max_gb: f64,
) -> Result<Option<u64>> {
    if !(max_gb.is_finite() && max_gb > 0.0) {
        return Err(Error::InvalidParameter {
            name: "max_output_gb".into(),
            reason: format!("{max_gb} GB: must be positive and finite"),
        });
    }
    if max_steps == Some(0) {
        return Err(Error::InvalidParameter {
            name: "max_steps".into(),
            reason: "0 steps: must be at least 1".into(),
        });
    }
    let bound = steps_bound(scene, (0.0, scene.end_time_s));
    let estimate = OutputEstimate {
        bytes: max_steps.map_or(bound, |m| bound.min(m as f64)) * bytes_per_step,
        fixed_bytes: 0.0,
        bytes_per_step,
        adaptive: matches!(scene.time_step, TimeStep::Adaptive(_)),
    };
    Ok(output_plan(estimate, max_steps, max_gb)?.step_cap)
}

/// The limits a user puts on a run's output: at most `max_steps` steps in total (if
/// given) and `max_gb` gigabytes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputLimits {
    /// Stop after this many steps in total (across resumes), if given.
    pub max_steps: Option<u64>,
    /// Refuse a run whose output is estimated above this many gigabytes.
    pub max_gb: f64,
}

/// Plans the output of a slider run with `nodes` frictional nodes, the profile `window`,
/// a map of `map_samples` samples, within `limits` (at most `max_steps` steps, if given,
/// and `max_gb` gigabytes). The bound: [`steps_bound`] rows of the time series (at most `max_steps`),
/// [`steps_bound`] of the window plus the map's samples, each times `nodes` profile rows.
/// A run with a bound above `max_gb` is refused — except an adaptive run without
/// `max_steps`, whose honest bound (`T / tau_min_s` rows) is usually far above any disk:
/// it gets the step cap whose output fits in `max_gb` (the run stops there, resumable).
///
/// # Errors
/// [`Error::InvalidParameter`] named `steps` (fixed steps) or `max_steps` with the
/// estimate and how to override it.
pub fn plan_output(
    scene: &SliderScene,
    window: (f64, f64),
    nodes: usize,
    map_samples: usize,
    limits: OutputLimits,
) -> Result<OutputPlan> {
    let OutputLimits { max_steps, max_gb } = limits;
    let cap = |rows: f64| max_steps.map_or(rows, |m| rows.min(m as f64));
    let nodes = nodes as f64;
    let map_rows = (map_samples + 1) as f64 * nodes;
    let estimate = OutputEstimate {
        bytes: cap(steps_bound(scene, (0.0, scene.end_time_s))) * SERIES_ROW_BYTES
            + (cap(steps_bound(scene, window)) * nodes + map_rows) * PROFILE_ROW_BYTES,
        fixed_bytes: map_rows * PROFILE_ROW_BYTES,
        // Every step in the window (the worst case).
        bytes_per_step: SERIES_ROW_BYTES + nodes * PROFILE_ROW_BYTES,
        adaptive: matches!(scene.time_step, TimeStep::Adaptive(_)),
    };
    output_plan(estimate, max_steps, max_gb)
}
