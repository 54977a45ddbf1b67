//! Adaptive time steps with error control (docs/math.md §9).
//!
//! The coupled scheme is first order: Newmark (or backward Euler) for the velocity, and the
//! backward Euler update of the state, whose local truncation error `−τ²/2 · α̈` dominates.
//! [`StepControl`] (the options) turns a per-step error estimate (computed by the caller)
//! into accept/reject decisions and the next time step, acting on a [`ControllerState`]
//! (the evolving part, which a checkpoint saves):
//!
//! - accept when the scaled error `err ≤ 1`; next `τ = τ · clamp(s · err^{−1/2}, f_min,
//!   f_max)` (exponent `−1/(p + 1)` for order `p = 1`, safety `s`);
//! - reject otherwise (or when the step itself failed, e.g. a fixed point that did not
//!   converge) and retry with the smaller `τ`; below `τ_min` the step is an error;
//! - a **physical cap**: the state may change by at most `ξ` per step,
//!   `τ_next ≤ ξ τ / max_p |α_n − α_{n−1}|`. For the aging and slip laws in slip
//!   (`Vθ/L ≫ 1`) `|Δα| ≈ τV/L`, so this is Lapusta et al.'s `τ ≤ ξ L / V_max`, without
//!   needing `L` from the state law;
//! - time steps are restricted to the **ladder** `τ_ref · 2^k` (k integer, `τ_ref` the
//!   initial step): a proposal is rounded down to it. Everything that depends on τ (the
//!   matrix `A = c_M M + c_K K`, its factorisation or multigrid set-up) is then built once
//!   per rung and reused whenever the step returns to it; a handful of rungs cover a whole
//!   seismic cycle.

use crate::{invalid, Error, Result};

/// The admissible relative tolerances, the open interval `(f64::EPSILON, 1)`: a relative
/// tolerance `≥ 1` accepts any step (the error control is off), one `≤ ε` can never be met
/// in double precision (the step shrinks until `tau_min`, or until time stops advancing).
pub const TOLERANCE_RANGE: (f64, f64) = (f64::EPSILON, 1.0);

/// The smallest admissible `tau_min` (s): `f64::MIN_POSITIVE`, the smallest normal double.
/// Below it `1/τ` (the mass coefficient `2/τ` of Newmark) overflows. A run driver should
/// also ask for `tau_min ≥ ε · T` (T the end time), below which a step at `t ≈ T` does not
/// advance time; the controller does not know `T`.
pub const TAU_MIN_FLOOR: f64 = f64::MIN_POSITIVE;

/// Options of the step controller. Units: `tau_*` in s; tolerances as described.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StepControl {
    /// Relative tolerance: on the displacement `u − u₀` (per dof, maximum norm) and, as an
    /// absolute tolerance, on the state `α = ln θ` (an error `δα` is a relative error
    /// `δθ/θ`).
    pub tolerance: f64,
    /// Absolute tolerance on the displacement (m), for dofs whose displacement since the
    /// start is small.
    pub displacement_atol: f64,
    /// Absolute tolerance on the state θ (s): the state test at a frictional node is
    /// `|δθ| ≤ state_atol + tolerance · θ`, i.e. `|δα| ≤ tolerance + state_atol / θ` with
    /// `θ = e^α` the larger of the step's two states. `0` (the default of
    /// [`new`](Self::new)): purely relative in θ. A state far below `state_atol / tolerance`
    /// occurs in healing (`θ̇ ≈ 1`: an absolute error in θ is carried, not amplified, while
    /// θ grows) and in fast slip (`θ̇ = 1 − Vθ/L` contracts at the rate `V/L`); its relative
    /// error need not be resolved there (docs/math.md §9).
    pub state_atol: f64,
    /// Safety factor `s` of the step proposal (0, 1].
    pub safety: f64,
    /// Smallest factor by which a step may shrink (0, 1).
    pub min_factor: f64,
    /// Largest factor by which a step may grow (> 1).
    pub max_factor: f64,
    /// Smallest time step (s): a step that fails or is rejected at `tau_min` is an error.
    pub tau_min: f64,
    /// Largest time step (s).
    pub tau_max: f64,
    /// `ξ` of the physical cap (state change per step at most `ξ`), or `None`.
    pub state_change_cap: Option<f64>,
    /// Slip test with this slip-rate floor `V_f` (m/s), or `None`: at every frictional
    /// node the relative error of the step's slip, `(Δ ln(V + V_f))² / 12` (the trapezoidal
    /// slip `(τ/2)(V_{n−1} + V_n)` of a slip rate exponential in time), must be at most
    /// `tolerance`. Local like the state test; `V_f` keeps it finite in stick.
    pub slip_rate_floor: Option<f64>,
    /// Local extrapolation of the state: after an accepted step, `α_n` is corrected by the
    /// state error estimate, `α_n += (τ/2)(α̇_{n−1} − α̇_n) / (1 + τ ∂²ψ/∂α²(α_n, V_n))`, i.e.
    /// towards the trapezoidal rule, damped where the state equation is stiff
    /// (docs/math.md §9). The error estimate then bounds the error of the uncorrected
    /// update, as usual for local extrapolation.
    pub state_extrapolation: bool,
}

impl StepControl {
    /// Tolerance `tolerance` (relative), `displacement_atol = tolerance · length` with
    /// `length` a displacement scale of the problem (e.g. the characteristic slip distance
    /// `L`), safety 0.9, factors [0.2, 2], `ξ = 0.5`, τ in `[tau_min, tau_max]`, local
    /// extrapolation of the state, no slip test, a state test relative in θ
    /// (`state_atol = 0`). (The slider scene adds the slip test with `V_f = 1e-9` m/s and
    /// `state_atol = tolerance · L/V_load`, both measured in `docs/work-precision.md`; the
    /// slip test is a relative test on the slip rate of every fault node, which suits a
    /// fault with rate-and-state friction but not, e.g., a frictionless one.)
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for non-positive or non-finite values, a tolerance
    /// outside [`TOLERANCE_RANGE`], `tau_min` below [`TAU_MIN_FLOOR`] or
    /// `tau_min > tau_max`.
    pub fn new(tolerance: f64, length: f64, tau_min: f64, tau_max: f64) -> Result<Self> {
        let c = Self {
            tolerance,
            displacement_atol: tolerance * length,
            state_atol: 0.0,
            safety: 0.9,
            min_factor: 0.2,
            max_factor: 2.0,
            tau_min,
            tau_max,
            state_change_cap: Some(0.5),
            slip_rate_floor: None,
            state_extrapolation: true,
        };
        c.validate()?;
        Ok(c)
    }

    /// Checks the options: `tolerance` in [`TOLERANCE_RANGE`] (open), the absolute
    /// tolerances finite and `≥ 0`, `safety` in (0, 1], `min_factor` in (0, 1),
    /// `max_factor` finite and > 1, `tau_min` finite and `≥` [`TAU_MIN_FLOOR`], `tau_max`
    /// finite and `≥ tau_min`, the cap and the slip-rate floor (if set) finite and > 0.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first invalid one and its range.
    pub fn validate(&self) -> Result<()> {
        let pos = |x: f64| x.is_finite() && x > 0.0;
        let (lo, hi) = TOLERANCE_RANGE;
        if !(self.tolerance > lo && self.tolerance < hi) {
            return invalid(
                "tolerance",
                self.tolerance,
                "in (f64::EPSILON = 2.220446049250313e-16, 1): a relative tolerance >= 1 \
                 accepts any step, one <= the machine epsilon can never be met",
            );
        }
        if !(self.displacement_atol.is_finite() && self.displacement_atol >= 0.0) {
            return invalid(
                "displacement_atol",
                self.displacement_atol,
                "finite and >= 0 (m)",
            );
        }
        if !(self.state_atol.is_finite() && self.state_atol >= 0.0) {
            return invalid("state_atol", self.state_atol, "finite and >= 0 (s)");
        }
        if !(self.safety > 0.0 && self.safety <= 1.0) {
            return invalid("safety", self.safety, "in (0, 1]");
        }
        if !(self.min_factor > 0.0 && self.min_factor < 1.0) {
            return invalid("min_factor", self.min_factor, "in (0, 1)");
        }
        if !(self.max_factor > 1.0 && self.max_factor.is_finite()) {
            return invalid("max_factor", self.max_factor, "finite and > 1");
        }
        if !(self.tau_min.is_finite() && self.tau_min >= TAU_MIN_FLOOR) {
            return invalid(
                "tau_min",
                self.tau_min,
                "finite and >= f64::MIN_POSITIVE = 2.2250738585072014e-308 (s): a normal \
                 double, below it 1/tau overflows",
            );
        }
        if !(pos(self.tau_max) && self.tau_max >= self.tau_min) {
            return invalid("tau_max", self.tau_max, "finite and >= tau_min (s)");
        }
        if let Some(xi) = self.state_change_cap {
            if !pos(xi) {
                return invalid("state_change_cap", xi, "finite and > 0");
            }
        }
        if let Some(v) = self.slip_rate_floor {
            if !pos(v) {
                return invalid("slip_rate_floor", v, "finite and > 0 (m/s)");
            }
        }
        Ok(())
    }
}

/// The evolving state of adaptive time steps: the ladder `τ_ref · 2^k` and the rung `k` of
/// the current step, counters and the last error. It belongs to a simulation's state (what
/// a checkpoint saves); the options ([`StepControl`]) belong to its method, and the
/// controller's decisions are [`StepControl::start`], [`StepControl::accept`] and
/// [`StepControl::reject`] acting on this state.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ControllerState {
    /// Reference step `τ_ref` of the ladder (s).
    tau_ref: f64,
    /// Current rung: `τ = τ_ref · 2^k`.
    k: i32,
    /// Accepted and rejected steps so far.
    accepted: u64,
    rejected: u64,
    last_error: f64,
}

/// Number of `f64` values of [`ControllerState::to_values`].
pub const CONTROLLER_STATE_LEN: usize = 5;

impl ControllerState {
    /// The current time step (s).
    pub fn tau(&self) -> f64 {
        rung(self.tau_ref, self.k)
    }

    /// Steps accepted through [`StepControl::accept`] so far. A caller that shortens a
    /// step to end on a breakpoint and does not report it (as `rsf`'s simulation does, to
    /// keep the rung) has taken more steps than this.
    pub fn accepted(&self) -> u64 {
        self.accepted
    }

    /// Rejected step attempts so far.
    pub fn rejected(&self) -> u64 {
        self.rejected
    }

    /// The scaled error of the last attempt.
    pub fn last_error(&self) -> f64 {
        self.last_error
    }

    /// The state as numbers (for checkpoints): `τ_ref`, `k`, accepted, rejected, last
    /// error.
    pub fn to_values(&self) -> [f64; CONTROLLER_STATE_LEN] {
        [
            self.tau_ref,
            f64::from(self.k),
            self.accepted as f64,
            self.rejected as f64,
            self.last_error,
        ]
    }

    /// The state written by [`to_values`](Self::to_values).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for the wrong number of values or invalid values.
    pub fn from_values(values: &[f64]) -> Result<Self> {
        let invalid = |value: f64| Error::InvalidParameter {
            name: "controller state",
            value,
            requirement: "5 values written by ControllerState::to_values (finite but the \
                          last error, which is >= 0 or +inf after a failed attempt)",
        };
        if values.len() != CONTROLLER_STATE_LEN {
            return Err(invalid(values.len() as f64));
        }
        // The last error is +∞ after a failed attempt (`reject(f64::INFINITY)`); the other
        // values are finite.
        if let Some(&bad) = values[..CONTROLLER_STATE_LEN - 1]
            .iter()
            .find(|x| !x.is_finite())
        {
            return Err(invalid(bad));
        }
        if !(values[4] >= 0.0) {
            return Err(invalid(values[4]));
        }
        if !(values[0] > 0.0) || values[1].fract() != 0.0 || values[2] < 0.0 || values[3] < 0.0 {
            return Err(invalid(values[0]));
        }
        Ok(Self {
            tau_ref: values[0],
            k: values[1] as i32,
            accepted: values[2] as u64,
            rejected: values[3] as u64,
            last_error: values[4],
        })
    }
}

impl StepControl {
    /// The controller's state at the start of a run with initial step `tau0` (s), which
    /// becomes the reference of the ladder after clamping to `[tau_min, tau_max]`.
    ///
    /// # Errors
    /// Invalid options or a `tau0` that is not finite and positive.
    pub fn start(&self, tau0: f64) -> Result<ControllerState> {
        self.validate()?;
        crate::check_time_step(tau0)?;
        Ok(ControllerState {
            tau_ref: tau0.clamp(self.tau_min, self.tau_max),
            k: 0,
            accepted: 0,
            rejected: 0,
            last_error: 0.0,
        })
    }

    /// The rung of the ladder of `c` at or below `tau` within the bounds.
    fn rung_below(&self, c: &ControllerState, tau: f64) -> i32 {
        let tau = tau.clamp(self.tau_min, self.tau_max);
        let mut k = (tau / c.tau_ref).log2().floor() as i32;
        // Guard the rounding of log2 and the bounds.
        while rung(c.tau_ref, k) > tau * (1.0 + 1e-12) {
            k -= 1;
        }
        while rung(c.tau_ref, k + 1) <= tau * (1.0 + 1e-12) {
            k += 1;
        }
        while rung(c.tau_ref, k) < self.tau_min * (1.0 - 1e-12) {
            k += 1;
        }
        k
    }

    /// The step of error `err` (scaled, accept when `≤ 1`) and largest state change
    /// `max |Δα|` was accepted: moves `c` to the next step size.
    pub fn accept(&self, c: &mut ControllerState, err: f64, state_change: f64) {
        c.accepted += 1;
        c.last_error = err;
        let tau = c.tau();
        let factor = if err > 0.0 {
            (self.safety * err.powf(-0.5)).clamp(self.min_factor, self.max_factor)
        } else {
            self.max_factor
        };
        let mut next = tau * factor;
        if let Some(xi) = self.state_change_cap {
            if state_change > 0.0 {
                next = next.min(xi * tau / state_change);
            }
        }
        // Never below the rung under the current step unless the estimate asks for it.
        c.k = self.rung_below(c, next);
    }

    /// The attempt with scaled error `err` was rejected (`err = ∞` for a failed attempt):
    /// moves `c` to a smaller step.
    ///
    /// The step shrinks by a factor `clamp(s · err^{−1/2}, min(f_min, ½), ½)` (¼ for a
    /// failed attempt, `err` not finite), rounded down to the ladder, and always by at
    /// least one rung.
    ///
    /// # Errors
    /// [`Error::StepTooSmall`] when no rung below the current step is at least `tau_min`
    /// (the step is then unchanged; the attempt still counts as rejected).
    pub fn reject(&self, c: &mut ControllerState, err: f64) -> Result<()> {
        c.rejected += 1;
        c.last_error = err;
        let tau = c.tau();
        let factor = if err.is_finite() && err > 0.0 {
            // A rejection shrinks by at least ½ even when f_min > ½ (`clamp` needs
            // lo ≤ hi).
            (self.safety * err.powf(-0.5)).clamp(self.min_factor.min(0.5), 0.5)
        } else {
            0.25
        };
        let k = self.rung_below(c, tau * factor).min(c.k - 1);
        if rung(c.tau_ref, k) < self.tau_min * (1.0 - 1e-12) {
            return Err(Error::StepTooSmall {
                tau,
                tau_min: self.tau_min,
            });
        }
        c.k = k;
        Ok(())
    }
}

fn rung(tau_ref: f64, k: i32) -> f64 {
    tau_ref * 2f64.powi(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn control() -> StepControl {
        StepControl::new(1e-3, 1e-5, 1e-6, 1.0).unwrap()
    }

    #[test]
    fn steps_stay_on_the_ladder_and_within_bounds() {
        let o = control();
        let mut c = o.start(1e-3).unwrap();
        for err in [
            0.0, 1e-6, 0.01, 0.5, 0.9, 1e-9, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        ] {
            o.accept(&mut c, err, 0.0);
            let r = (c.tau() / 1e-3).log2();
            assert!((r - r.round()).abs() < 1e-9, "off the ladder: {}", c.tau());
            assert!(c.tau() <= 1.0 && c.tau() >= 1e-6);
        }
        assert!(
            c.tau() <= 1.0 && c.tau() > 0.4,
            "grows to tau_max: {}",
            c.tau()
        );
        while c.tau() > 2e-6 {
            o.reject(&mut c, f64::INFINITY).unwrap();
        }
        assert!(o.reject(&mut c, f64::INFINITY).is_err() || c.tau() >= 1e-6);
        let mut errs = 0;
        for _ in 0..40 {
            if o.reject(&mut c, 10.0).is_err() {
                errs += 1;
            }
            assert!(c.tau() >= 1e-6 * (1.0 - 1e-12));
        }
        assert!(errs > 0, "rejections at tau_min are errors");
    }

    #[test]
    fn growth_is_limited_and_the_state_cap_applies() {
        let o = control();
        let mut c = o.start(1e-3).unwrap();
        o.accept(&mut c, 0.0, 0.0);
        assert_eq!(c.tau(), 2e-3, "at most max_factor = 2 per step");
        // A state change of 2 per step with ξ = 0.5 caps the next step at τ/4.
        o.accept(&mut c, 1e-6, 2.0);
        assert_eq!(c.tau(), 5e-4);
        // An error estimate of 4 halves... (0.9 · 4^{-1/2} = 0.45 → rung below is τ/4).
        let t = c.tau();
        o.reject(&mut c, 4.0).unwrap();
        assert_eq!(c.tau(), t / 4.0);
    }

    #[test]
    fn state_round_trips_and_rejects_garbage() {
        let o = control();
        let mut c = o.start(1e-3).unwrap();
        o.accept(&mut c, 0.1, 0.0);
        o.reject(&mut c, 3.0).unwrap();
        let s = c.to_values();
        let d = ControllerState::from_values(&s).unwrap();
        assert_eq!(c, d);
        assert!(ControllerState::from_values(&[1.0]).is_err());
        assert!(ControllerState::from_values(&[1.0, f64::NAN, 0.0, 0.0, 0.0]).is_err());
        assert!(ControllerState::from_values(&[1.0, 0.5, 0.0, 0.0, 0.0]).is_err());
    }

    #[test]
    fn invalid_options_are_errors() {
        assert!(StepControl::new(0.0, 1.0, 1e-6, 1.0).is_err());
        assert!(StepControl::new(1e-3, 1.0, 1.0, 1e-6).is_err());
        assert!(StepControl::new(1e-3, f64::NAN, 1e-6, 1.0).is_err());
        // Tolerances outside (ε, 1), named with the range; the ends inside are accepted.
        for tol in [
            1.0,
            1e300,
            f64::MAX,
            f64::EPSILON,
            1e-300,
            5e-324,
            f64::INFINITY,
        ] {
            match StepControl::new(tol, 1.0, 1e-6, 1.0) {
                Err(Error::InvalidParameter {
                    name, requirement, ..
                }) => {
                    assert_eq!(name, "tolerance", "{tol:e}");
                    assert!(requirement.contains("(f64::EPSILON"), "{requirement}");
                }
                other => panic!("tolerance {tol:e}: {other:?}"),
            }
        }
        for tol in [1.0 - f64::EPSILON, 2.0 * f64::EPSILON] {
            assert!(StepControl::new(tol, 1.0, 1e-6, 1.0).is_ok(), "{tol:e}");
        }
        // tau_min must be a normal double (1/τ finite).
        for tau_min in [5e-324, 1e-310] {
            match StepControl::new(1e-3, 1.0, tau_min, 1.0) {
                Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, "tau_min"),
                other => panic!("tau_min {tau_min:e}: {other:?}"),
            }
        }
        assert!(StepControl::new(1e-3, 1.0, f64::MIN_POSITIVE, 1.0).is_ok());
        let mut c = control();
        c.safety = 1.5;
        assert!(c.validate().is_err());
        let mut c = control();
        c.slip_rate_floor = Some(0.0);
        assert!(c.validate().is_err());
        for bad in [-1e-3, f64::NAN, f64::INFINITY] {
            let mut c = control();
            c.state_atol = bad;
            assert!(c.validate().is_err(), "state_atol = {bad}");
        }
        let mut c = control();
        c.state_atol = 1e-4;
        assert!(c.validate().is_ok());
    }
}
