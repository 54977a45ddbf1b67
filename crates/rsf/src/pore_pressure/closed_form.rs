//! The closed-form pressure of fluid injected at a point of an infinite fault, flowing
//! along it only (docs/seas-bp6.md, "Pore pressure"; Lambert & Dunham, SEAS BP6
//! description, eqs. 20, 25–27).

use super::PorePressure;
use crate::error::{invalid, Result};

/// An injection history: a volume rate `rate` (m/s: volume per time per unit area of the
/// plane the fault's flow crosses, BP6's `q₀`) from `t = 0` until the shut-in `shut_in`
/// (s; `f64::INFINITY` for none), nothing after.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Injection {
    /// `q₀` (m/s), finite and ≥ 0.
    pub rate: f64,
    /// `t_off` (s), > 0 (may be infinite).
    pub shut_in: f64,
}

impl Injection {
    /// Checks `rate ≥ 0` finite and `shut_in > 0`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `injection.rate`
    /// or `injection.shut_in`.
    pub fn validate(&self) -> Result<()> {
        if !(self.rate >= 0.0 && self.rate.is_finite()) {
            return Err(invalid(
                "injection.rate",
                format!("{} m/s must be finite and >= 0", self.rate),
            ));
        }
        if !(self.shut_in > 0.0) {
            return Err(invalid(
                "injection.shut_in",
                format!("{} s must be > 0", self.shut_in),
            ));
        }
        Ok(())
    }

    /// The rate at time `t` (m/s): `rate` on `[0, shut_in)`, 0 elsewhere.
    pub fn rate_at(&self, t: f64) -> f64 {
        if (0.0..self.shut_in).contains(&t) {
            self.rate
        } else {
            0.0
        }
    }
}

/// The pressure of an [`Injection`] at a point `source` of an infinite planar fault,
/// diffusing along the fault's direction `direction` only, from `p = 0` at `t = 0`
/// (BP6 description eqs. 26–27):
///
/// ```text
/// p(s, t) = q₀/(βφ √α) [G(s, t) H(t) − G(s, t − t_off) H(t − t_off)],
/// G(s, t) = √t [exp(−s²/(4αt))/√π − (|s|/√(4αt)) erfc(|s|/√(4αt))],
/// ```
///
/// `s = (x − source)·direction` (m) the distance along the fault, `βφ` the storage (1/Pa:
/// pore and fluid compressibility times porosity), `α = k/(φβη_f)` the hydraulic
/// diffusivity (m²/s). On a fault of finite length `2l` with no-flux ends it holds while
/// `t ≪ l²/(4α)` (the diffusion length `√(4αt)` well inside the fault; for BP6, 5 km after
/// 2 years against `l = 20 km`). The Darcy velocity is
/// `q = sgn(s)(q₀/2)[erfc(|s|/√(4αt)) − erfc(|s|/√(4α(t − t_off)))]` (m/s), 0 at the
/// source itself, where it jumps by `q₀`. `erfc` is musl's (the `libm` crate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InjectionPressure<const D: usize> {
    injection: Injection,
    storage: f64,
    diffusivity: f64,
    source: [f64; D],
    direction: [f64; D],
}

impl<const D: usize> InjectionPressure<D> {
    /// The field of `injection` at `source` (m) along the unit vector `direction`, with
    /// storage `βφ` (1/Pa) and diffusivity `α` (m²/s).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `injection.*`,
    /// `storage`, `diffusivity` (positive and finite), `source` (finite) or `direction`
    /// (finite, unit length to 1e-9).
    pub fn new(
        injection: Injection,
        storage: f64,
        diffusivity: f64,
        source: [f64; D],
        direction: [f64; D],
    ) -> Result<Self> {
        injection.validate()?;
        for (name, v) in [("storage", storage), ("diffusivity", diffusivity)] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(invalid(name, format!("{v} must be positive and finite")));
            }
        }
        if source.iter().any(|c| !c.is_finite()) {
            return Err(invalid("source", format!("{source:?} must be finite")));
        }
        let norm: f64 = direction.iter().map(|c| c * c).sum::<f64>().sqrt();
        if !((norm - 1.0).abs() <= 1e-9) {
            return Err(invalid(
                "direction",
                format!("{direction:?} must be a unit vector"),
            ));
        }
        Ok(Self {
            injection,
            storage,
            diffusivity,
            source,
            direction,
        })
    }

    /// The injection.
    pub fn injection(&self) -> Injection {
        self.injection
    }

    /// The distance along the fault from the source (m).
    pub fn along(&self, x: &[f64; D]) -> f64 {
        (0..D)
            .map(|i| (x[i] - self.source[i]) * self.direction[i])
            .sum()
    }

    /// `p(s, t)` (Pa) at distance `s` (m) along the fault.
    pub fn at(&self, s: f64, t: f64) -> f64 {
        let a = self.diffusivity;
        let scale = self.injection.rate / (self.storage * a.sqrt());
        let mut g = green(s, t, a);
        if t > self.injection.shut_in {
            g -= green(s, t - self.injection.shut_in, a);
        }
        scale * g
    }

    /// The Darcy velocity `q(s, t)` (m/s) at distance `s` (m) along the fault.
    pub fn darcy_at(&self, s: f64, t: f64) -> f64 {
        if s == 0.0 || !(t > 0.0) {
            return 0.0;
        }
        let a = self.diffusivity;
        let erfc = |t: f64| libm::erfc(s.abs() / (4.0 * a * t).sqrt());
        let mut q = erfc(t);
        if t > self.injection.shut_in {
            q -= erfc(t - self.injection.shut_in);
        }
        s.signum() * 0.5 * self.injection.rate * q
    }
}

/// `G(s, t)` of the closed form (0 for `t ≤ 0`).
fn green(s: f64, t: f64, a: f64) -> f64 {
    if !(t > 0.0) {
        return 0.0;
    }
    let x = s.abs() / (4.0 * a * t).sqrt();
    t.sqrt() * ((-x * x).exp() / std::f64::consts::PI.sqrt() - x * libm::erfc(x))
}

impl<const D: usize> PorePressure<D> for InjectionPressure<D> {
    fn pressure(&self, x: &[f64; D], t: f64) -> f64 {
        self.at(self.along(x), t)
    }
    fn darcy_velocity(&self, x: &[f64; D], t: f64) -> Option<f64> {
        Some(self.darcy_at(self.along(x), t))
    }
    fn darcy_velocity_vector(&self, x: &[f64; D], t: f64) -> Option<[f64; D]> {
        let q = self.darcy_at(self.along(x), t);
        Some(self.direction.map(|d| q * d))
    }
    fn breakpoints(&self) -> Vec<f64> {
        vec![self.injection.shut_in]
    }
}
