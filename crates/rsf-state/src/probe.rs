//! The monotonicity probe of a user law's `∂ψ/∂α` (docs/math.md §2: the backward Euler
//! update has exactly one root only if `ψ(·, V)` is convex).

use crate::error::{Error, Result};

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

/// The check of [`probe_monotonicity`](crate::probe_monotonicity) for `dpsi(α, V) = ∂ψ/∂α(α, V)`.
pub(crate) fn first_decrease(dpsi: impl Fn(f64, f64) -> f64) -> Result<()> {
    let h = (PROBE_ALPHA_MAX - PROBE_ALPHA_MIN) / (PROBE_ALPHA_POINTS - 1) as f64;
    for &v in &PROBE_SLIP_RATES {
        let mut prev: Option<(f64, f64)> = None;
        for i in 0..PROBE_ALPHA_POINTS {
            let alpha = PROBE_ALPHA_MIN + h * i as f64;
            let d = dpsi(alpha, v);
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
