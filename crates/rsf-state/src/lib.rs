//! State laws of rate-and-state friction and their backward Euler update.
//!
//! Pipping, Sander & Kornhuber write the state evolution as a subdifferential inclusion
//! (2.4) `−α̇ ∈ ∂_α ψ(α, V)` with `ψ(·, V)` convex. Backward Euler (3.5) turns one time
//! step into a proximal problem, solved pointwise at every frictional node:
//!
//! ```text
//! α_n = argmin_β ½ |β − α_{n−1}|² + τ ψ(β, V)   ⇔   β − α_{n−1} + τ ∂_α ψ(β, V) ∋ 0.
//! ```
//!
//! * [`StateLaw`] — the trait. A user law implements only
//!   [`dpsi_dalpha`](StateLaw::dpsi_dalpha); the default [`update`](StateLaw::update)
//!   ([`generic_update`]) solves the implicit equation by safeguarded Newton/bisection.
//! * Built-in laws with closed-form updates: [`Aging`] (Dieterich, (2.15), (5.5), via the
//!   Wright omega function, overflow-safe), [`Slip`] (Ruina, (2.16)) and
//!   [`Discontinuous`] ((2.10), (2.17); here `α = θ`, not `ln θ`, see [`StateVariable`]).
//! * Beyond the paper: [`StateLaw::constant_rate_update`], the exact solution of the state
//!   equation over a step at constant slip rate, where a law has one in closed form (all
//!   three built-in laws; in stick it integrates healing exactly, which backward Euler in
//!   `α = ln θ` does not).
//!
//! # Units (SI)
//! Slip rate `V` in m/s, time step `τ` in s, `L` in m. For the aging and slip laws
//! `α = ln θ` with `θ` in s; for the discontinuous law `α = θ` in the paper's normalisation
//! `ψ_dc = |αV − 1|`, i.e. `α` in s/m.
//!
//! # Example: a user law through the trait
//! The "aging law without healing" `θ̇ = −θV/L` (i.e. `α̇ = −V/L`, `ψ = (V/L) α`) needs only
//! `∂ψ/∂α`; the generic update then integrates it:
//! ```
//! use rsf_state::{Aging, StateLaw};
//!
//! #[derive(Clone)]
//! struct NoHealing { l: f64 }
//! impl StateLaw for NoHealing {
//!     fn dpsi_dalpha(&self, _alpha: f64, v: f64) -> f64 { v / self.l }
//! }
//!
//! let law = NoHealing { l: 1e-5 };
//! let alpha = law.update(2.0, 1e-6, 1.0)?;      // α − τV/L exactly
//! assert!((alpha - (2.0 - 0.1)).abs() < 1e-12);
//! // The closed-form aging law and the generic solver agree:
//! let aging = Aging::new(1e-5)?;
//! let closed = aging.update(-10.0, 2e-4, 1e-3)?;
//! let generic = rsf_state::generic_update(&aging, -10.0, 2e-4, 1e-3)?;
//! assert!((closed - generic).abs() < 1e-10);
//! # Ok::<(), rsf_state::Error>(())
//! ```
#![warn(missing_docs)]

mod generic;
mod laws;
mod omega;
mod probe;

pub use generic::generic_update;
pub use laws::{Aging, Discontinuous, Slip};
pub use omega::{wright_omega, wright_omega_ln};
pub use probe::{
    probe_monotonicity, PROBE_ALPHA_MAX, PROBE_ALPHA_MIN, PROBE_ALPHA_POINTS, PROBE_SLIP_RATES,
};

/// Errors of this crate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A law parameter is outside its admissible range (e.g. `L ≤ 0`).
    #[error("invalid state-law parameter {name} = {value}: {requirement}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Rejected value.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// An argument of [`StateLaw::update`] is inadmissible (non-finite `α`, `V < 0`, `τ < 0`).
    #[error("invalid input {name} = {value}: {requirement}")]
    InvalidInput {
        /// Argument name.
        name: &'static str,
        /// Rejected value.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// `∂ψ/∂α` returned NaN.
    #[error("dpsi_dalpha({alpha}, {v}) is NaN")]
    NanDerivative {
        /// State at which the derivative was evaluated.
        alpha: f64,
        /// Slip rate (m/s).
        v: f64,
    },
    /// No sign change of `β − α_prev + τ ∂ψ/∂α(β, V)` was found in `|β| ≤ 1e300`
    /// (the law is not monotone, or its root is out of range).
    #[error("no bracket for the state update (alpha_prev = {alpha_prev}, v = {v}, tau = {tau})")]
    NoBracket {
        /// Previous state.
        alpha_prev: f64,
        /// Slip rate (m/s).
        v: f64,
        /// Time step (s).
        tau: f64,
    },
    /// The safeguarded iteration did not converge (not expected for monotone laws).
    #[error("state update not converged after {iterations} iterations (bracket width {width})")]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// Remaining bracket width.
        width: f64,
    },
    /// `∂ψ/∂α(·, V)` decreases between two neighbouring states of the probe grid
    /// ([`probe_monotonicity`]): `ψ(·, V)` is not convex and the backward Euler update may
    /// have several roots, of which the generic update would return one.
    #[error(
        "dpsi_dalpha is not nondecreasing in alpha: dpsi_dalpha({alpha_lo}, {v}) = {dpsi_lo:e} > \
         dpsi_dalpha({alpha_hi}, {v}) = {dpsi_hi:e} (the state update could have several roots)"
    )]
    NotMonotone {
        /// Slip rate (m/s).
        v: f64,
        /// The smaller state.
        alpha_lo: f64,
        /// The larger state.
        alpha_hi: f64,
        /// `∂ψ/∂α(alpha_lo, v)` (1/s).
        dpsi_lo: f64,
        /// `∂ψ/∂α(alpha_hi, v)` (1/s), smaller than `dpsi_lo`.
        dpsi_hi: f64,
    },
    /// The update produced a non-finite state (e.g. a closed form overflowed).
    #[error("state update gave a non-finite value {value}")]
    NonFinite {
        /// The offending value.
        value: f64,
    },
}

/// `Result` with this crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

/// What the state variable `α` of a law is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum StateVariable {
    /// `α = ln θ`, `θ` in s (aging, slip laws; what the rate-state friction laws expect).
    LogTheta,
    /// `α = θ` itself (discontinuous law (2.17)).
    Theta,
}

/// A state law `−α̇ ∈ ∂_α ψ(α, V)` (2.4) with `ψ(·, V)` convex.
///
/// Only [`dpsi_dalpha`](StateLaw::dpsi_dalpha) is required; it must be nondecreasing in
/// `α` (this is the convexity of `ψ`) and may be discontinuous (return any element of the
/// subdifferential at a kink).
pub trait StateLaw: Clone + Send + Sync {
    /// `∂ψ/∂α(α, V)` in 1/s, nondecreasing in `α`; `V ≥ 0` in m/s.
    fn dpsi_dalpha(&self, alpha: f64, v: f64) -> f64;

    /// `∂²ψ/∂α²(α, V)` (1/s) if known; used by the Newton steps of [`generic_update`]
    /// (a finite difference is used otherwise).
    fn d2psi_dalpha2(&self, _alpha: f64, _v: f64) -> Option<f64> {
        None
    }

    /// `ψ(α, V)` (1/s) if known (informational; the update does not need it).
    fn psi(&self, _alpha: f64, _v: f64) -> Option<f64> {
        None
    }

    /// Whether `α` is `ln θ` or `θ`. Default [`StateVariable::LogTheta`].
    fn state_variable(&self) -> StateVariable {
        StateVariable::LogTheta
    }

    /// The steady state at constant `V` (where `∂ψ/∂α = 0`), if it exists.
    fn steady_state(&self, _v: f64) -> Option<f64> {
        None
    }

    /// Checks that [`dpsi_dalpha`](StateLaw::dpsi_dalpha) is nondecreasing in `α`, as the
    /// update needs. A simulation calls it once per frictional node at construction. The
    /// default probes a documented grid ([`probe_monotonicity`]); the built-in laws, monotone
    /// by construction, return `Ok(())` at once.
    ///
    /// # Errors
    /// [`Error::NotMonotone`] or [`Error::NanDerivative`] (see [`probe_monotonicity`]).
    fn check_monotone(&self) -> Result<()> {
        probe_monotonicity(self)
    }

    /// Backward Euler step (3.5): `α_n = prox_{τψ(·, V)}(α_prev)`, the solution `β` of
    /// `β − α_prev + τ ∂ψ/∂α(β, V) ∋ 0`.
    ///
    /// `alpha_prev` finite, `v ≥ 0` finite (m/s), `tau ≥ 0` finite (s). The default is
    /// [`generic_update`] (safeguarded Newton/bisection to machine precision `4ε·max(1, |β|)`,
    /// i.e. below the paper's absolute `1e-12` whenever `|β| < 1000`).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for inadmissible arguments; the errors of
    /// [`generic_update`]; [`Error::NonFinite`] if the result would not be finite.
    /// Never panics.
    fn update(&self, alpha_prev: f64, v: f64, tau: f64) -> Result<f64> {
        generic_update(self, alpha_prev, v, tau)
    }

    /// The exact solution at `t + τ` of `α̇ = −∂ψ/∂α(α, V)` from `alpha_prev` at `t`, the
    /// slip rate held at `v` over the step, if the law has one in closed form (the `rsf`
    /// crate's `StateIntegrator::ConstantSlipRate`; docs/friction-state.md). `None` (the
    /// default) if it does not; a law that has it returns `Some` for every input.
    ///
    /// Arguments as for [`update`](StateLaw::update). The built-in laws: [`Aging`]
    /// (`θ̇ = 1 − Vθ/L` is linear in `θ`), [`Slip`] (linear in `α`) and [`Discontinuous`]
    /// (its backward Euler step is already exact at constant `V`).
    ///
    /// # Errors
    /// As [`update`](StateLaw::update) (wrapped in `Some`). Never panics.
    fn constant_rate_update(&self, _alpha_prev: f64, _v: f64, _tau: f64) -> Option<Result<f64>> {
        None
    }
}

/// Checks the arguments of [`StateLaw::update`].
///
/// # Errors
/// [`Error::InvalidInput`] if `alpha_prev` is not finite, `v` is not finite and `≥ 0`, or
/// `tau` is not finite and `≥ 0`.
pub fn check_update_inputs(alpha_prev: f64, v: f64, tau: f64) -> Result<()> {
    if !alpha_prev.is_finite() {
        return Err(Error::InvalidInput {
            name: "alpha_prev",
            value: alpha_prev,
            requirement: "finite",
        });
    }
    if !(v.is_finite() && v >= 0.0) {
        return Err(Error::InvalidInput {
            name: "v",
            value: v,
            requirement: "finite and >= 0",
        });
    }
    if !(tau.is_finite() && tau >= 0.0) {
        return Err(Error::InvalidInput {
            name: "tau",
            value: tau,
            requirement: "finite and >= 0",
        });
    }
    Ok(())
}

pub(crate) fn finite(value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::NonFinite { value })
    }
}
