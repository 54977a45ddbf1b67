//! The state of a simulation: everything that changes from step to step and that a
//! checkpoint saves (docs/design.md, "Problem, method, state").

use rsf_time::{ControllerState, Kinematics};

/// The state of a simulation after `step` steps: time, time step, `(u, v, a)`, the state
/// variable `α` on Γ_F and the step controller's state. This is what
/// [`Checkpoint`](crate::Checkpoint)s save and what observers see
/// ([`StepView::state`](crate::StepView)); a simulation holds exactly one.
///
/// Shapes: `kinematics.u`, `.v`, `.a` have one value per dof (node-major, `D` per node);
/// `alpha` one per frictional node, in `model.frictional_boundary.nodes` order.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SimulationState {
    /// Steps taken.
    pub step: usize,
    /// Time `t_n` after `step` steps (s).
    pub time: f64,
    /// Time step τ of the next step (s).
    pub tau: f64,
    /// Step index and time (s) where the current τ began: the next steps are at
    /// `t_n = origin time + (n − origin step) τ` (`(0, 0)` for a run at constant τ).
    pub time_origin: (usize, f64),
    /// Displacement `u` (m), velocity `v` (m/s) and acceleration `a` (m/s²).
    pub kinematics: Kinematics,
    /// State `α` per frictional node (`ln θ` with θ in s for the rate-and-state laws).
    pub alpha: Vec<f64>,
    /// State of the adaptive step control (`None` for a fixed τ).
    pub controller: Option<ControllerState>,
}

impl SimulationState {
    /// Time of step `n` of the current segment of constant τ: `t_s + (n − n_s) τ` (exactly
    /// `n τ` for a run at constant τ from the start).
    pub(crate) fn time_of(&self, n: usize) -> f64 {
        let (n0, t0) = self.time_origin;
        t0 + (n - n0) as f64 * self.tau
    }
}
