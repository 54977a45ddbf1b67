//! The errors of this crate and the input checks of the state update.

/// Errors of this crate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A law parameter is outside its admissible range (e.g. `L ≤ 0`).
    #[error(
        "invalid state-law parameter {name} = {}: {requirement}",
        rsf_numeric::written(*value)
    )]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Rejected value.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// An argument of [`StateLaw::update`](crate::StateLaw::update) is inadmissible (non-finite `α`, `V < 0`, `τ < 0`).
    #[error("invalid input {name} = {}: {requirement}", rsf_numeric::written(*value))]
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
    /// ([`probe_monotonicity`](crate::probe_monotonicity)): `ψ(·, V)` is not convex and the backward Euler update may
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
    /// A name that is not one of a choice's names.
    #[error(transparent)]
    UnknownName(#[from] rsf_numeric::UnknownName),
}

/// `Result` with this crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

/// Checks the arguments of [`StateLaw::update`](crate::StateLaw::update).
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
