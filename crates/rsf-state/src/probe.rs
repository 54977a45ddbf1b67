//! The monotonicity probe of a user law's `∂ψ/∂α` (docs/math.md §2: the backward Euler
//! update has exactly one root only if `ψ(·, V)` is convex).

use crate::{Error, Result, StateLaw};

/// Smallest state of the probe grid.
pub const PROBE_ALPHA_MIN: f64 = -40.0;
/// Largest state of the probe grid.
pub const PROBE_ALPHA_MAX: f64 = 40.0;
/// Number of states of the probe grid (spacing 0.5).
pub const PROBE_ALPHA_POINTS: usize = 161;
/// Slip rates of the probe grid (m/s): 0 and every power of ten from 1e-15 to 1e3.
pub const PROBE_SLIP_RATES: [f64; 20] = [
    0.0, 1e-15, 1e-14, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2,
    1e-1, 1.0, 1e1, 1e2, 1e3,
];
/// Relative allowance for round-off: a decrease smaller than this times the larger
/// magnitude of two neighbouring values is not reported.
const ROUND_OFF: f64 = 1e-12;

/// Checks on a grid that `∂ψ/∂α(·, V)` is nondecreasing, i.e. that `ψ(·, V)` is convex
/// and the backward Euler update `β − α_prev + τ ∂ψ/∂α(β, V) = 0` has a single root.
///
/// **Grid.** `α` at the [`PROBE_ALPHA_POINTS`] = 161 equally spaced points of
/// [[`PROBE_ALPHA_MIN`], [`PROBE_ALPHA_MAX`]] = [−40, 40] (spacing 0.5; for `α = ln θ` this
/// is θ from 4e-18 s to 2e17 s), for each slip rate of [`PROBE_SLIP_RATES`] (0 and
/// 1e-15 … 1e3 m/s): 3220 evaluations. Neighbouring values may decrease by round-off
/// (1e-12 of their magnitude). A probe can only find violations on its grid: a law that
/// is non-monotone on a finer scale than 0.5 or outside the grid passes (the generic
/// update then still fails with [`Error::NoBracket`] when it cannot bracket a root, but
/// may return one of several roots).
///
/// # Errors
/// [`Error::NotMonotone`] with the first decreasing pair found; [`Error::NanDerivative`]
/// if the law returns NaN on the grid. Never panics.
pub fn probe_monotonicity<S: StateLaw>(law: &S) -> Result<()> {
    let h = (PROBE_ALPHA_MAX - PROBE_ALPHA_MIN) / (PROBE_ALPHA_POINTS - 1) as f64;
    for &v in &PROBE_SLIP_RATES {
        let mut prev: Option<(f64, f64)> = None;
        for i in 0..PROBE_ALPHA_POINTS {
            let alpha = PROBE_ALPHA_MIN + h * i as f64;
            let d = law.dpsi_dalpha(alpha, v);
            if d.is_nan() {
                return Err(Error::NanDerivative { alpha, v });
            }
            if let Some((alpha_lo, d_lo)) = prev {
                let scale = d_lo.abs().max(d.abs());
                // Infinite values only carry the sign: +∞ then a finite value decreases.
                let decreases = if scale.is_finite() {
                    d < d_lo - ROUND_OFF * scale
                } else {
                    d < d_lo
                };
                if decreases {
                    return Err(Error::NotMonotone {
                        v,
                        alpha_lo,
                        alpha_hi: alpha,
                        dpsi_lo: d_lo,
                        dpsi_hi: d,
                    });
                }
            }
            prev = Some((alpha, d));
        }
    }
    Ok(())
}
