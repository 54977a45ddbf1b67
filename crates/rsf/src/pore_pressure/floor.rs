//! A floor under the effective normal stress: where a pore pressure would reach the
//! normal stress, the fault would open, which a model without opening cannot represent
//! (docs/seas-bp8.md, "Where p reaches σ̄₀").

use super::PorePressure;
use crate::error::{invalid, Result};

/// The pressure field `field` on a fault of uniform normal stress `σ̄₀` (Pa), with the
/// effective normal stress it leaves held above a floor `σ_min`: the friction laws see
///
/// ```text
/// σ̄ = φ(σ̄₀ − p),   φ(x) = x for x ≥ 2σ_min,   φ(x) = σ_min + max(x, 0)²/(4σ_min) below,
/// ```
///
/// — `φ` is `C¹`, increasing on `x > 0`, never below `σ_min`, and the identity above
/// `2σ_min`, where the pressure given is the field's own, bit for bit. The field passed
/// to the run is `p̃ = σ̄₀ − φ(σ̄₀ − p)` (the pressure the floor leaves), so that
/// `σ̄₀ − p̃ = φ(σ̄₀ − p)`; its Darcy velocity and breakpoints are the field's.
///
/// Why (SEAS BP8-PW, docs/seas-bp8.md): the well's pressure passes the normal stress near
/// the well, where a fault zone would open (a hydraulic fracture) and its pressure could
/// not rise further; the benchmark's model has no opening. Without a floor a run stops
/// there with [`Error::NormalStressNotPositive`](crate::Error::NormalStressNotPositive);
/// with it, the cells near the well keep a strength of `f σ_min` and slip freely, and the
/// pressure the files report stays the diffusion's (read it from `field`, not from this
/// wrapper). [`engaged`](Self::engaged) says where the floor acts.
#[derive(Debug, Clone)]
pub struct EffectiveStressFloor<P> {
    field: P,
    sigma_n: f64,
    sigma_min: f64,
}

impl<P> EffectiveStressFloor<P> {
    /// `field` on a fault of normal stress `sigma_n` (Pa) held at `sigma_min` (Pa) or more.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `sigma_n` (not
    /// positive and finite) or `sigma_min` (not in `(0, σ̄₀/2]`: the floor would act where
    /// no pressure is).
    pub fn new(field: P, sigma_n: f64, sigma_min: f64) -> Result<Self> {
        if !(sigma_n > 0.0 && sigma_n.is_finite()) {
            return Err(invalid(
                "sigma_n",
                format!("{sigma_n} Pa must be positive and finite"),
            ));
        }
        if !(sigma_min > 0.0 && sigma_min <= 0.5 * sigma_n) {
            return Err(invalid(
                "sigma_min",
                format!(
                    "{sigma_min} Pa must be in (0, σ̄₀/2] = (0, {}] Pa",
                    0.5 * sigma_n
                ),
            ));
        }
        Ok(Self {
            field,
            sigma_n,
            sigma_min,
        })
    }

    /// The field without the floor.
    pub fn field(&self) -> &P {
        &self.field
    }

    /// `σ_min` (Pa).
    pub fn sigma_min(&self) -> f64 {
        self.sigma_min
    }

    /// `φ(x)` (Pa) of an effective normal stress `x` (Pa).
    pub fn floor(&self, x: f64) -> f64 {
        let m = self.sigma_min;
        if x >= 2.0 * m {
            x
        } else {
            let y = x.max(0.0);
            m + y * y / (4.0 * m)
        }
    }

    /// Whether the floor changes the effective normal stress of a pressure `p` (Pa):
    /// `σ̄₀ − p < 2σ_min`.
    pub fn engaged(&self, p: f64) -> bool {
        !(self.sigma_n - p >= 2.0 * self.sigma_min)
    }

    /// The pressure left by the floor for the field's pressure `p` (Pa).
    fn held(&self, p: f64) -> f64 {
        if self.engaged(p) {
            self.sigma_n - self.floor(self.sigma_n - p)
        } else {
            p
        }
    }
}

impl<const D: usize, P: PorePressure<D>> PorePressure<D> for EffectiveStressFloor<P> {
    fn pressure(&self, x: &[f64; D], t: f64) -> f64 {
        self.held(self.field.pressure(x, t))
    }

    fn pressures(&self, t: f64, points: &[[f64; D]], out: &mut [f64]) {
        self.field.pressures(t, points, out);
        for p in out.iter_mut() {
            *p = self.held(*p);
        }
    }

    fn darcy_velocity(&self, x: &[f64; D], t: f64) -> Option<f64> {
        self.field.darcy_velocity(x, t)
    }

    fn darcy_velocity_vector(&self, x: &[f64; D], t: f64) -> Option<[f64; D]> {
        self.field.darcy_velocity_vector(x, t)
    }

    fn breakpoints(&self) -> Vec<f64> {
        self.field.breakpoints()
    }
}

#[cfg(test)]
mod tests {
    use super::EffectiveStressFloor;
    use crate::pore_pressure::{PorePressure, PressureFn};

    #[test]
    fn the_floor_is_c1_and_the_identity_above_twice_the_floor() {
        let f =
            EffectiveStressFloor::new(PressureFn(|x: &[f64; 1], _t: f64| x[0]), 25e6, 1e6).unwrap();
        let m = 1e6;
        // Identity above 2 σ_min: the field's bits.
        for p in [0.0, 1.234e6, 22.9e6, 23e6] {
            assert_eq!(f.pressure(&[p], 0.0).to_bits(), p.to_bits());
            assert!(!f.engaged(p));
        }
        // Value and slope continuous at 2 σ_min and at 0; never below σ_min; increasing.
        let h = 1e-3;
        let phi = |x: f64| f.floor(x);
        for x0 in [2.0 * m, 0.0] {
            assert!((phi(x0 + h) - phi(x0 - h)).abs() < 3.0 * h);
            let left = (phi(x0) - phi(x0 - h)) / h;
            let right = (phi(x0 + h) - phi(x0)) / h;
            assert!((left - right).abs() < 1e-6, "{left} {right}");
        }
        let mut last = phi(-5e6);
        assert_eq!(last, m);
        for k in 1..=400 {
            let x = -5e6 + k as f64 * 2e4;
            let y = phi(x);
            assert!(y >= m && y >= last);
            last = y;
        }
        // The effective stress left by a pressure of 40 MPa on 25 MPa is σ_min.
        assert_eq!(25e6 - f.pressure(&[40e6], 0.0), m);
        assert!(f.engaged(24e6));
        // Refusals.
        assert!(
            EffectiveStressFloor::new(PressureFn(|_: &[f64; 1], _: f64| 0.0), 25e6, 0.0).is_err()
        );
        assert!(
            EffectiveStressFloor::new(PressureFn(|_: &[f64; 1], _: f64| 0.0), 25e6, 13e6).is_err()
        );
        assert!(
            EffectiveStressFloor::new(PressureFn(|_: &[f64; 1], _: f64| 0.0), -1.0, 1.0).is_err()
        );
    }
}
