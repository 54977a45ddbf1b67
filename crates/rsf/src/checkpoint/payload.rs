//! What a checkpoint file holds, as one serde value (format `RSFCKPT5`, encoded by postcard).

use std::borrow::Cow;

use serde::{Deserialize, Serialize};

/// The content of a checkpoint: every field of [`Checkpoint`](super::Checkpoint) as plain
/// numbers, strings and `f64` vectors (exact: postcard writes an `f64` as its 8 bytes).
/// Borrowed when written, owned when read.
#[derive(Debug, Serialize, Deserialize)]
pub(super) struct Payload<'a> {
    /// Space dimension `D`.
    pub dim: u64,
    /// Steps done.
    pub step: u64,
    /// The step and time from which the run counts its time (s).
    pub time_origin: (u64, f64),
    /// Simulated time (s).
    pub time: f64,
    /// The current step size τ (s).
    pub tau: f64,
    /// Wall time of the run so far (s).
    pub wall_time_s: f64,
    /// The fingerprint's `(field, value)` pairs in order.
    pub fingerprint: Cow<'a, [(String, String)]>,
    /// Displacement, velocity and acceleration (length `n` each).
    pub u: Cow<'a, [f64]>,
    /// Velocity (length `n`).
    pub v: Cow<'a, [f64]>,
    /// Acceleration (length `n`).
    pub a: Cow<'a, [f64]>,
    /// The state `α = ln θ` of the frictional nodes.
    pub alpha: Cow<'a, [f64]>,
    /// The adaptive step controller's values (empty without one).
    pub controller: Vec<f64>,
    /// The method's tag and values (`MethodState::to_values`).
    pub method: (u64, Vec<f64>),
}
