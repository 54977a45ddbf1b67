//! The closed-form pressure of fluid injected into an unbounded fault surface (SEAS BP8
//! description, eqs. 21 and 25; docs/pore-pressure.md).

use super::exp_integral::{exp_integral_e1, exp_integral_e1_difference};
use super::surface::{FaultPlane, FaultZone, SurfaceInjection, SurfaceSource};
use super::PorePressure;
use crate::error::{invalid, Result};

/// The pressure of a [`SurfaceInjection`] into an unbounded planar fault zone, from
/// `p = p₀` at `t = 0` (SEAS BP8 description, Kim, Dunham, Romanet & Erickson, 2026-08-12:
/// eq. 21 for the Gaussian source, eq. 25 for a point source), with
/// `C = Q₀/(4π α φβL_fwid)` and `r` the distance from the source in the plane (m):
///
/// ```text
/// Gaussian of width w:  p − p₀ = C [E₁(r²/(2w² + 4αt)) − E₁(r²/(2w²))]   (C ln(1 + 2αt/w²) at r = 0),
/// point source (well):  p − p₀ = C E₁(r²/(4αt))                        (+∞ at r = 0),
/// ```
///
/// for `0 < t ≤ t_off`; after the shut-in the difference of the forms at `t` and
/// `t − t_off` (superposition). `E₁` is the exponential integral. A well's radius and
/// storage do not enter (eq. 25 is the point source's). On a fault of half-width `l` with
/// no-flux edges it holds while `t ≪ l²/(4α)` (BP8: 222 h). The Darcy velocity
/// `−(k/η_f) ∂p/∂r` points away from the source:
/// `(k/η_f)(2C/r)[e^{−r²/(2w²)} − e^{−r²/(2w² + 4αt)}]` (Gaussian) and
/// `(Q₀/(2πL_fwid r)) e^{−r²/(4αt)}` (point source), 0 at the source itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceInjectionPressure {
    zone: FaultZone,
    injection: SurfaceInjection,
    plane: FaultPlane,
    initial: f64,
}

impl SurfaceInjectionPressure {
    /// The field of `injection` into the fault zone `zone` on `plane`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) as
    /// [`FaultZone::validate`], [`SurfaceInjection::validate`] and
    /// [`FaultPlane::validate`].
    pub fn new(zone: FaultZone, injection: SurfaceInjection, plane: FaultPlane) -> Result<Self> {
        zone.validate()?;
        injection.validate()?;
        plane.validate()?;
        Ok(Self {
            zone,
            injection,
            plane,
            initial: 0.0,
        })
    }

    /// The same field from a uniform pressure `p₀` (Pa) at `t = 0`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
    /// `initial_pressure` if `p₀` is not finite.
    pub fn with_initial_pressure(self, p0: f64) -> Result<Self> {
        if !p0.is_finite() {
            return Err(invalid(
                "initial_pressure",
                format!("{p0} Pa must be finite"),
            ));
        }
        Ok(Self {
            initial: p0,
            ..self
        })
    }

    /// The plane.
    pub fn plane(&self) -> &FaultPlane {
        &self.plane
    }

    /// `C = Q₀/(4π α φβL_fwid)` (Pa).
    pub fn scale(&self) -> f64 {
        self.injection.injection.rate
            / (4.0 * std::f64::consts::PI * self.zone.diffusivity() * self.zone.storage())
    }

    /// `p(u, v, t)` (Pa) at the plane's coordinates `uv` (m).
    pub fn at(&self, uv: [f64; 2], t: f64) -> f64 {
        let r2 = self.distance_squared(uv);
        let off = self.injection.injection.shut_in;
        let mut p = self.on(r2, t);
        if t > off {
            p -= self.on(r2, t - off);
        }
        self.initial + self.scale() * p
    }

    /// The Darcy velocity `(q_u, q_v)` (m/s) at `uv` (m).
    pub fn darcy_at(&self, uv: [f64; 2], t: f64) -> [f64; 2] {
        let d = [
            uv[0] - self.injection.position[0],
            uv[1] - self.injection.position[1],
        ];
        let r2 = d[0] * d[0] + d[1] * d[1];
        if r2 == 0.0 {
            return [0.0, 0.0];
        }
        let off = self.injection.injection.shut_in;
        let mut g = self.radial_gradient(r2, t);
        if t > off {
            g -= self.radial_gradient(r2, t - off);
        }
        // −(k/η_f) ∂p/∂r along d/r: −(k/η_f) C g d / r², g = r ∂(p/C)/∂r.
        let q = -self.zone.mobility() * self.scale() * g / r2;
        [q * d[0], q * d[1]]
    }

    fn distance_squared(&self, uv: [f64; 2]) -> f64 {
        let d = [
            uv[0] - self.injection.position[0],
            uv[1] - self.injection.position[1],
        ];
        d[0] * d[0] + d[1] * d[1]
    }

    /// `(4αt, 2w²)` of the injection switched on at 0, at `t > 0` (m²): `w = 0` for the
    /// point source, the Gaussian of width 0.
    fn spreads(&self, t: f64) -> Option<(f64, f64)> {
        let w2 = match self.injection.source {
            SurfaceSource::Gaussian { width } => 2.0 * width * width,
            SurfaceSource::Well(_) => 0.0,
        };
        (t > 0.0).then(|| (4.0 * self.zone.diffusivity() * t, w2))
    }

    /// `(p − p₀)/C` of the injection switched on at 0 and never off, at `r²` and `t`:
    /// `E₁(r²/(2w² + 4αt)) − E₁(r²/(2w²))`.
    fn on(&self, r2: f64, t: f64) -> f64 {
        let Some((spread, w2)) = self.spreads(t) else {
            return 0.0;
        };
        match (r2 == 0.0, w2 == 0.0) {
            (true, true) => f64::INFINITY,
            (true, false) => (spread / w2).ln_1p(),
            (false, true) => exp_integral_e1(r2 / spread),
            (false, false) => exp_integral_e1_difference(r2 / (w2 + spread), r2 / w2),
        }
    }

    /// `r ∂/∂r` of [`on`](Self::on) (1), for `r > 0`: `r d/dr E₁(r²/s) = −2 e^{−r²/s}`.
    fn radial_gradient(&self, r2: f64, t: f64) -> f64 {
        let Some((spread, w2)) = self.spreads(t) else {
            return 0.0;
        };
        // e^{−r²/0} = 0 for the point source.
        -2.0 * (-r2 / (w2 + spread)).exp() + 2.0 * (-r2 / w2).exp()
    }
}

impl PorePressure<3> for SurfaceInjectionPressure {
    fn pressure(&self, x: &[f64; 3], t: f64) -> f64 {
        self.at(self.plane.coordinates(x), t)
    }
    fn darcy_velocity_vector(&self, x: &[f64; 3], t: f64) -> Option<[f64; 3]> {
        Some(self.plane.vector_at(x, |uv| self.darcy_at(uv, t)))
    }
    fn breakpoints(&self) -> Vec<f64> {
        vec![self.injection.injection.shut_in]
    }
}
