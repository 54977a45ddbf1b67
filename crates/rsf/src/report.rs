//! What one time step did ([`StepReport`]): the numbers every observer, summary and figure
//! uses, as the step produced them.

/// What one time step did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepReport {
    /// Step index n (1-based).
    pub step: usize,
    /// Time t_n (s).
    pub time: f64,
    /// The time step τ of this step (s).
    pub tau: f64,
    /// Fixed point iterations (velocity solves) of this step (0 for a method without a
    /// fixed point: the fault ODE).
    pub fixed_point_iterations: usize,
    /// Velocity-solver iterations summed over the fixed point iterations (0 for the fault
    /// ODE, which solves no velocity problem).
    pub solver_iterations: usize,
    /// Right-hand-side evaluations of an explicit method (the fault ODE: each one product
    /// with the condensed operator, rejected attempts included; 0 for the implicit
    /// scheme).
    pub evaluations: usize,
    /// Fixed point iterations that took a damped step (the paper's ω < 1, or the fallback
    /// of Anderson acceleration).
    pub relaxed_iterations: usize,
    /// Last fixed point correction `‖v^{ν+1} − v^ν‖` (energy norm).
    pub correction: f64,
    /// The quantity the fixed point test compared with the tolerance: the last correction,
    /// or the estimated error `θ/(1 − θ) · correction` (see
    /// [`FixedPointOptions::error_estimate`](crate::method::FixedPointOptions::error_estimate)).
    pub fixed_point_error: f64,
    /// Largest slip rate on Γ_F after the step (m/s).
    pub max_slip_rate: f64,
    /// Adaptive steps: attempts rejected before this step was accepted (for any reason).
    pub rejected_attempts: usize,
    /// Of `rejected_attempts`, those rejected because a trial state — a Runge–Kutta stage
    /// of the fault ODE or a fixed-point iterate of the implicit scheme — had a normal
    /// stress `σ̄_n ≤ 0` (or not finite) on a fault inside the body
    /// ([`NormalStress::FromSlip`](crate::normal_stress::NormalStress::FromSlip);
    /// docs/reliability.md, "Trial points outside the domain").
    pub rejected_normal_stress: usize,
    /// Adaptive steps: the scaled local error estimate of the accepted step (≤ 1).
    pub error_estimate: f64,
    /// Adaptive steps: the scaled local error estimate of the last attempt rejected before
    /// this step (∞ for an attempt without a finite estimate — a failed or refused attempt;
    /// 0 if none was rejected). A collapse of the step size names it
    /// ([`Error::StepSizeCollapse`](crate::Error::StepSizeCollapse)).
    pub rejected_error: f64,
    /// Wall time of the step (s; not part of any numerical output).
    pub seconds: f64,
}
