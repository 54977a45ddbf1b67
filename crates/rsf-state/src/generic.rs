//! The generic backward Euler update for a law given only by `∂ψ/∂α`.

use crate::{check_update_inputs, finite, Error, Result, StateLaw};

/// Largest `|β|` the bracket search explores.
const SEARCH_LIMIT: f64 = 1e300;
/// Iteration cap (bisection from a width of `1e300` to one ulp needs < 2100 halvings).
const MAX_ITERATIONS: usize = 2500;

/// Backward Euler step for any [`StateLaw`]: the root `β` of the strictly increasing
/// `F(β) = β − α_prev + τ ∂ψ/∂α(β, V)` (paper (3.5); docs/math.md §2).
///
/// **Bracketing.** With `g = ∂ψ/∂α(·, V)` nondecreasing and `g₀ = g(α_prev)`, the root
/// lies between `α_prev` and `α_prev − τ g₀` (one evaluation, no search). If `τ g₀`
/// overflows, a doubling search from `α_prev` finds a sign change (up to `|β| ≤ 1e300`).
///
/// **Iteration.** Newton steps on `F` (derivative `1 + τ ∂²ψ/∂α²` from
/// [`StateLaw::d2psi_dalpha2`] or a forward difference), replaced by bisection whenever
/// a step leaves the bracket or does not halve the previous step. It stops when the step
/// or the bracket is below `4ε·max(1, |β|)`, i.e. at machine precision, which is below the
/// paper's absolute `1e-12` for `|β| < 1000`; for larger `|β|` the absolute tolerance
/// `1e-12` is not representable and the relative one is used. Discontinuous `∂ψ/∂α` (a
/// subdifferential with a jump) converge by bisection onto the jump.
///
/// # Errors
/// [`Error::InvalidInput`] for inadmissible inputs, [`Error::NanDerivative`] if
/// `dpsi_dalpha` returns NaN, [`Error::NoBracket`] if no sign change exists in
/// `|β| ≤ 1e300` (non-monotone law), [`Error::NotConverged`] after 2500 iterations,
/// [`Error::NonFinite`] for a non-finite result. Never panics.
pub fn generic_update<S: StateLaw>(law: &S, alpha_prev: f64, v: f64, tau: f64) -> Result<f64> {
    check_update_inputs(alpha_prev, v, tau)?;
    if tau == 0.0 {
        return Ok(alpha_prev);
    }
    let g = |beta: f64| -> Result<f64> {
        let d = law.dpsi_dalpha(beta, v);
        if d.is_nan() {
            Err(Error::NanDerivative { alpha: beta, v })
        } else {
            Ok(d)
        }
    };
    // F(β) = (β − α_prev) + τ g(β); ±∞ are fine (they only carry the sign).
    let f = |beta: f64| -> Result<f64> { Ok((beta - alpha_prev) + tau * g(beta)?) };

    let g0 = g(alpha_prev)?;
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
    let (mut lo, mut hi) = if dir > 0.0 {
        (alpha_prev, far)
    } else {
        (far, alpha_prev)
    };

    let derivative = |beta: f64, f_beta: f64| -> Result<f64> {
        if let Some(d2) = law.d2psi_dalpha2(beta, v) {
            return Ok(1.0 + tau * d2.max(0.0));
        }
        let h = 1e-7 * beta.abs().max(1.0);
        let fh = f(beta + h)?;
        Ok(((fh - f_beta) / h).max(1.0))
    };

    // Start from the end with the smaller residual (often exact already).
    let f_lo = f(lo)?;
    let f_hi = f(hi)?;
    let (mut x, mut fx) = if f_lo.abs() <= f_hi.abs() {
        (lo, f_lo)
    } else {
        (hi, f_hi)
    };
    let mut dx_old = hi - lo;
    for _ in 0..MAX_ITERATIONS {
        if fx == 0.0 {
            return finite(x);
        }
        if fx < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let df = derivative(x, fx)?;
        let newton = x - fx / df;
        if (newton - x).abs() <= 2.0 * f64::EPSILON * x.abs().max(1.0) {
            // Converged: the Newton correction is at rounding level.
            return finite(newton);
        }
        let accept = newton.is_finite()
            && newton > lo
            && newton < hi
            && (2.0 * fx).abs() <= (dx_old * df).abs();
        let x_new = if accept { newton } else { 0.5 * (lo + hi) };
        dx_old = (x_new - x).abs();
        x = x_new;
        fx = f(x)?;
        let tol = 4.0 * f64::EPSILON * x.abs().max(1.0);
        if dx_old <= tol || hi - lo <= tol {
            return finite(x);
        }
    }
    Err(Error::NotConverged {
        iterations: MAX_ITERATIONS,
        width: hi - lo,
    })
}
