//! The backward Euler update of a law given only by `∂ψ/∂α` (the algorithm behind
//! [`generic_update`](crate::generic_update)).

use crate::error::{check_update_inputs, finite, Error, Result};
use rsf_numeric::{safeguarded_newton, Bracket, IncreasingFunction, RootOutcome, Start, Stopping};

/// Largest `|β|` the bracket search explores.
const SEARCH_LIMIT: f64 = 1e300;
/// Iteration cap (bisection from a width of `1e300` to one ulp needs < 2100 halvings).
const MAX_ITERATIONS: usize = 2500;

/// A law at a fixed slip rate, as the update sees it: `∂ψ/∂α(·, V)` and, if known,
/// `∂²ψ/∂α²(·, V)`.
pub(crate) struct LawAtRate<G, H> {
    /// `β ↦ ∂ψ/∂α(β, V)` (1/s).
    pub(crate) dpsi: G,
    /// `β ↦ ∂²ψ/∂α²(β, V)` (1/s), `None` where unknown.
    pub(crate) d2psi: H,
    /// The slip rate `V` (m/s), for error reports.
    pub(crate) v: f64,
}

/// `F(β) = (β − α_prev) + τ ∂ψ/∂α(β, V)`, increasing; its slope from `∂²ψ/∂α²` or a
/// forward difference.
struct Residual<'a, G, H> {
    law: &'a LawAtRate<G, H>,
    alpha_prev: f64,
    tau: f64,
}

impl<G: Fn(f64) -> f64, H: Fn(f64) -> Option<f64>> IncreasingFunction for Residual<'_, G, H> {
    type Error = Error;
    fn value(&mut self, beta: f64) -> Result<f64> {
        // ±∞ are fine (they only carry the sign).
        Ok((beta - self.alpha_prev) + self.tau * dpsi(self.law, beta)?)
    }
    fn slope(&mut self, beta: f64, f_beta: f64) -> Result<f64> {
        if let Some(d2) = (self.law.d2psi)(beta) {
            return Ok(1.0 + self.tau * d2.max(0.0));
        }
        let h = 1e-7 * beta.abs().max(1.0);
        let fh = self.value(beta + h)?;
        Ok(((fh - f_beta) / h).max(1.0))
    }
}

fn dpsi<G: Fn(f64) -> f64, H>(law: &LawAtRate<G, H>, beta: f64) -> Result<f64> {
    let d = (law.dpsi)(beta);
    if d.is_nan() {
        Err(Error::NanDerivative {
            alpha: beta,
            v: law.v,
        })
    } else {
        Ok(d)
    }
}

/// The backward Euler step of [`generic_update`](crate::generic_update) (documented there):
/// bracket, then [`safeguarded_newton`] to `4ε·max(1, |β|)`.
///
/// # Errors
/// As [`generic_update`](crate::generic_update).
pub(crate) fn backward_euler<G: Fn(f64) -> f64, H: Fn(f64) -> Option<f64>>(
    law: &LawAtRate<G, H>,
    alpha_prev: f64,
    tau: f64,
) -> Result<f64> {
    let v = law.v;
    check_update_inputs(alpha_prev, v, tau)?;
    if tau == 0.0 {
        return Ok(alpha_prev);
    }
    let mut residual = Residual {
        law,
        alpha_prev,
        tau,
    };
    let mut f = |beta: f64| residual.value(beta);

    let g0 = dpsi(law, alpha_prev)?;
    if g0 == 0.0 {
        return Ok(alpha_prev);
    }
    let no_bracket = Error::NoBracket { alpha_prev, v, tau };
    let dir = if g0 > 0.0 { -1.0 } else { 1.0 };
    // Candidate far end from monotonicity.
    let mut far = alpha_prev - tau * g0;
    let mut f_far = if far.is_finite() { f(far)? } else { f64::NAN };
    if !(far.is_finite() && f_far * dir >= 0.0) {
        // Doubling search from α_prev in direction `dir`.
        let mut step = 1.0_f64.max(1e-3 * alpha_prev.abs());
        loop {
            far = alpha_prev + dir * step;
            if far.is_nan() || far.abs() > SEARCH_LIMIT {
                return Err(no_bracket);
            }
            f_far = f(far)?;
            if f_far * dir >= 0.0 {
                break;
            }
            step *= 2.0;
        }
    }
    if f_far == 0.0 {
        return finite(far);
    }
    let (lo, hi) = if dir > 0.0 {
        (alpha_prev, far)
    } else {
        (far, alpha_prev)
    };

    // Start from the end with the smaller residual (often exact already).
    let f_lo = f(lo)?;
    let f_hi = f(hi)?;
    let (x, fx) = if f_lo.abs() <= f_hi.abs() {
        (lo, f_lo)
    } else {
        (hi, f_hi)
    };
    let bracket = Bracket { lo, hi };
    let stopping = Stopping {
        tolerance: 4.0,
        max_iterations: MAX_ITERATIONS,
    };
    match safeguarded_newton(&mut residual, bracket, Start { x, value: fx }, stopping)? {
        RootOutcome::Converged(beta) => finite(beta),
        RootOutcome::IterationLimit { width, .. } => Err(Error::NotConverged {
            iterations: MAX_ITERATIONS,
            width,
        }),
    }
}
