//! Built-in state laws with closed-form backward Euler updates.

use crate::error::{check_update_inputs, finite, Error, Result};
use crate::law::StateLaw;
use rsf_numeric::{wright_omega_ln, StateVariable};

fn check_l(l: f64) -> Result<()> {
    if l.is_finite() && l > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name: "l",
            value: l,
            requirement: "finite and > 0",
        })
    }
}

/// `ln(V/L)` without overflow (V > 0).
fn ln_v_over_l(v: f64, l: f64) -> f64 {
    let q = v / l;
    if q.is_finite() && q >= f64::MIN_POSITIVE {
        q.ln()
    } else {
        v.ln() - l.ln()
    }
}

/// Dieterich's aging law (2.15) in `α = ln θ`: `α̇ = e^{−α} − V/L`,
/// `ψ_d(α, V) = (V/L) α + e^{−α}`.
///
/// Closed-form update (5.5): `α_n − τ e^{−α_n} = r`, `r = α_prev − τV/L`, so
/// `α_n = r + ω(ln τ − r)` with the Wright omega function `ω`; evaluated as
/// `ln τ − ln ω(ln τ − r)` when `ln τ − r > 0` (no cancellation, `τ e^{−r}` never formed),
/// overflow-safe for any `τV/L` (even when it overflows `f64`: then `α_n = ln(L/V)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aging {
    l: f64,
}

impl Aging {
    /// `L > 0` finite (m).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] otherwise.
    pub fn new(l: f64) -> Result<Self> {
        check_l(l)?;
        Ok(Self { l })
    }
    /// Characteristic slip distance `L` (m).
    pub fn l(&self) -> f64 {
        self.l
    }
}

impl StateLaw for Aging {
    /// Monotone by construction (docs/math.md §2): no probe.
    fn check_monotone(&self) -> Result<()> {
        Ok(())
    }
    fn dpsi_dalpha(&self, alpha: f64, v: f64) -> f64 {
        v / self.l - (-alpha).exp()
    }
    fn d2psi_dalpha2(&self, alpha: f64, _v: f64) -> Option<f64> {
        Some((-alpha).exp())
    }
    fn psi(&self, alpha: f64, v: f64) -> Option<f64> {
        Some(v / self.l * alpha + (-alpha).exp())
    }
    /// `ln(L/V)` for `V > 0`.
    fn steady_state(&self, v: f64) -> Option<f64> {
        (v > 0.0).then(|| -ln_v_over_l(v, self.l))
    }
    fn update(&self, alpha_prev: f64, v: f64, tau: f64) -> Result<f64> {
        check_update_inputs(alpha_prev, v, tau)?;
        if tau == 0.0 {
            return Ok(alpha_prev);
        }
        let k = tau * (v / self.l);
        if !k.is_finite() {
            // τV/L overflows: α_n = ln(L/V) + O(ln k / k).
            return finite(-ln_v_over_l(v, self.l));
        }
        let r = alpha_prev - k;
        let lt = tau.ln();
        let x = lt - r;
        let y = wright_omega_ln(x);
        let alpha = if x > 0.0 { lt - y } else { r + y.exp() };
        finite(alpha)
    }
    /// `θ̇ = 1 − Vθ/L` at constant `V` is linear in `θ = e^α`:
    /// `θ_n = θ_prev e^{−k} + τ φ₁(k)` with `k = τV/L`, `φ₁(k) = (1 − e^{−k})/k` (`φ₁(0) = 1`),
    /// evaluated in log space as `α_n = ln(e^{α_prev − k} + e^{ln τ + ln φ₁(k)})`: exact healing
    /// `ln(θ_prev + τ)` at `V = 0`, `α_n → ln(L/V)` for large `k`, no overflow for any
    /// `τV/L` (if it overflows `f64`, `α_n = ln(L/V)`).
    fn constant_rate_update(&self, alpha_prev: f64, v: f64, tau: f64) -> Option<Result<f64>> {
        Some(check_update_inputs(alpha_prev, v, tau).and_then(|()| {
            if tau == 0.0 {
                return Ok(alpha_prev);
            }
            let k = tau * (v / self.l);
            if !k.is_finite() {
                return finite(-ln_v_over_l(v, self.l));
            }
            let ln_phi1 = if k > 0.0 {
                (-(-k).exp_m1() / k).ln()
            } else {
                0.0
            };
            finite(log_add_exp(alpha_prev - k, tau.ln() + ln_phi1))
        }))
    }
}

/// `ln(e^a + e^b)` without overflow.
fn log_add_exp(a: f64, b: f64) -> f64 {
    let (hi, lo) = if a >= b { (a, b) } else { (b, a) };
    hi + (lo - hi).exp().ln_1p()
}

/// Ruina's slip law (2.16) in `α = ln θ`: `α̇ = −(V/L)(α + ln(V/L))`,
/// `ψ_r(α, V) = (V/L)(α²/2 + ln(V/L) α)`.
///
/// Closed-form update: `α_n (1 + τV/L) = α_prev − (τV/L) ln(V/L)`; at `V = 0` the state
/// is frozen (`α_n = α_prev`); if `τV/L` overflows, `α_n = ln(L/V)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slip {
    l: f64,
}

impl Slip {
    /// `L > 0` finite (m).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] otherwise.
    pub fn new(l: f64) -> Result<Self> {
        check_l(l)?;
        Ok(Self { l })
    }
    /// Characteristic slip distance `L` (m).
    pub fn l(&self) -> f64 {
        self.l
    }
}

impl StateLaw for Slip {
    /// Monotone by construction (docs/math.md §2): no probe.
    fn check_monotone(&self) -> Result<()> {
        Ok(())
    }
    fn dpsi_dalpha(&self, alpha: f64, v: f64) -> f64 {
        if v > 0.0 {
            v / self.l * (alpha + ln_v_over_l(v, self.l))
        } else {
            0.0
        }
    }
    fn d2psi_dalpha2(&self, _alpha: f64, v: f64) -> Option<f64> {
        Some(v / self.l)
    }
    fn psi(&self, alpha: f64, v: f64) -> Option<f64> {
        Some(if v > 0.0 {
            v / self.l * (0.5 * alpha * alpha + ln_v_over_l(v, self.l) * alpha)
        } else {
            0.0
        })
    }
    /// `ln(L/V)` for `V > 0`.
    fn steady_state(&self, v: f64) -> Option<f64> {
        (v > 0.0).then(|| -ln_v_over_l(v, self.l))
    }
    fn update(&self, alpha_prev: f64, v: f64, tau: f64) -> Result<f64> {
        // α_n = α_prev/(1+k) + target·k/(1+k), written as a convex combination.
        self.relax(alpha_prev, v, tau, |a, target, k| {
            let lambda = 1.0 / (1.0 + k);
            a * lambda + target * (k * lambda)
        })
    }
    /// `α̇ = −(V/L)(α − ln(L/V))` at constant `V` is linear in `α`:
    /// `α_n = α_prev + (ln(L/V) − α_prev)(1 − e^{−k})`, `k = τV/L`; `V = 0` keeps `α`, an
    /// overflowing `k` gives `ln(L/V)`.
    fn constant_rate_update(&self, alpha_prev: f64, v: f64, tau: f64) -> Option<Result<f64>> {
        Some(self.relax(alpha_prev, v, tau, |a, target, k| {
            a + (target - a) * (-(-k).exp_m1())
        }))
    }
}

impl Slip {
    /// A step towards the steady state `ln(L/V)`: `combine(α_prev, ln(L/V), τV/L)` after the
    /// checks and the limits shared by both updates (`τ = 0` or `V = 0` keep `α`, an
    /// overflowing `τV/L` gives `ln(L/V)`).
    fn relax(
        &self,
        alpha_prev: f64,
        v: f64,
        tau: f64,
        combine: impl FnOnce(f64, f64, f64) -> f64,
    ) -> Result<f64> {
        check_update_inputs(alpha_prev, v, tau)?;
        if tau == 0.0 || v == 0.0 {
            return Ok(alpha_prev);
        }
        let k = tau * (v / self.l);
        let target = -ln_v_over_l(v, self.l);
        if !k.is_finite() {
            return finite(target);
        }
        finite(combine(alpha_prev, target, k))
    }
}

/// The discontinuous law (2.10), (2.17), with **`α = θ`** (not `ln θ`):
/// `ψ_dc(α, V) = |αV − 1|`, so `α̇ = +V` if `αV < 1` and `−V` if `αV > 1`.
///
/// Closed-form update: move `α_prev` by `τV` towards `1/V` without passing it; `V = 0`
/// keeps `α`. `α` is in s/m in the paper's normalisation (`θ/L` with `L` = 1 m).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Discontinuous;

impl StateLaw for Discontinuous {
    /// Monotone by construction (docs/math.md §2): no probe.
    fn check_monotone(&self) -> Result<()> {
        Ok(())
    }
    /// `V sign(αV − 1)`, with the subgradient 0 at the kink `αV = 1`.
    fn dpsi_dalpha(&self, alpha: f64, v: f64) -> f64 {
        let p = alpha * v;
        if p > 1.0 {
            v
        } else if p < 1.0 {
            -v
        } else {
            0.0
        }
    }
    fn d2psi_dalpha2(&self, _alpha: f64, _v: f64) -> Option<f64> {
        Some(0.0)
    }
    fn psi(&self, alpha: f64, v: f64) -> Option<f64> {
        Some((alpha * v - 1.0).abs())
    }
    fn state_variable(&self) -> StateVariable {
        StateVariable::Theta
    }
    /// `1/V` for `V > 0`.
    fn steady_state(&self, v: f64) -> Option<f64> {
        (v > 0.0).then(|| 1.0 / v)
    }
    fn update(&self, alpha_prev: f64, v: f64, tau: f64) -> Result<f64> {
        check_update_inputs(alpha_prev, v, tau)?;
        if tau == 0.0 || v == 0.0 {
            return Ok(alpha_prev);
        }
        let target = 1.0 / v; // +∞ for subnormal V: never reached, harmless
        let step = tau * v;
        let p = alpha_prev * v;
        let alpha = if p < 1.0 {
            (alpha_prev + step).min(target)
        } else if p > 1.0 {
            (alpha_prev - step).max(target)
        } else {
            alpha_prev
        };
        finite(alpha)
    }
    /// The backward Euler step: at constant `V`, `α` moves at speed `V` towards `1/V` and
    /// stays there, which the step reproduces exactly.
    fn constant_rate_update(&self, alpha_prev: f64, v: f64, tau: f64) -> Option<Result<f64>> {
        Some(self.update(alpha_prev, v, tau))
    }
}
