//! What a pressure diffusing over a fault surface is made of: the fault plane's frame, the
//! fault zone's hydraulic properties, the injection's source and the grid
//! (docs/pore-pressure.md).

use super::Injection;
use crate::error::{invalid, Result};

/// Tolerance of the frame's unit length and orthogonality.
const FRAME_TOLERANCE: f64 = 1e-9;

/// A plane of a 3-D model carrying a fault, with coordinates of its own: the point
/// `origin` (m, the model's coordinates) and two orthonormal in-plane axes `axis_u`,
/// `axis_v`. A point `x` of the model has the fault coordinates
/// `(u, v) = ((x − origin)·axis_u, (x − origin)·axis_v)` (m): its projection onto the
/// plane. SEAS BP8's fault `x₁ = 0` with `(u, v) = (x₂, x₃)` is
/// `origin = [0, 0, 0]`, `axis_u = [0, 1, 0]`, `axis_v = [0, 0, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FaultPlane {
    /// A point of the plane, where `(u, v) = (0, 0)` (m).
    pub origin: [f64; 3],
    /// The unit vector of the `u` axis.
    pub axis_u: [f64; 3],
    /// The unit vector of the `v` axis, orthogonal to `axis_u`.
    pub axis_v: [f64; 3],
}

impl FaultPlane {
    /// Checks a finite origin and finite orthonormal axes (to 1e-9).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `plane.origin`,
    /// `plane.axis_u` or `plane.axis_v`.
    pub fn validate(&self) -> Result<()> {
        if self.origin.iter().any(|c| !c.is_finite()) {
            return Err(invalid(
                "plane.origin",
                format!("{:?} m must be finite", self.origin),
            ));
        }
        for (name, a) in [("plane.axis_u", self.axis_u), ("plane.axis_v", self.axis_v)] {
            if !((dot(&a, &a).sqrt() - 1.0).abs() <= FRAME_TOLERANCE) {
                return Err(invalid(name, format!("{a:?} must be a unit vector")));
            }
        }
        if !(dot(&self.axis_u, &self.axis_v).abs() <= FRAME_TOLERANCE) {
            return Err(invalid(
                "plane.axis_v",
                format!("{:?} must be orthogonal to plane.axis_u", self.axis_v),
            ));
        }
        Ok(())
    }

    /// The fault coordinates `(u, v)` (m) of the model's point `x` (m).
    pub fn coordinates(&self, x: &[f64; 3]) -> [f64; 2] {
        let d = [
            x[0] - self.origin[0],
            x[1] - self.origin[1],
            x[2] - self.origin[2],
        ];
        [dot(&d, &self.axis_u), dot(&d, &self.axis_v)]
    }

    /// The model's vector of the in-plane vector with components `(w_u, w_v)`.
    pub fn vector(&self, w: [f64; 2]) -> [f64; 3] {
        [0, 1, 2].map(|i| w[0] * self.axis_u[i] + w[1] * self.axis_v[i])
    }

    /// The model's vector at `x` (m) of the in-plane vector field `field(u, v)`: the
    /// [`vector`](Self::vector) of `field` at the [`coordinates`](Self::coordinates) of `x`.
    pub fn vector_at(&self, x: &[f64; 3], field: impl FnOnce([f64; 2]) -> [f64; 2]) -> [f64; 3] {
        self.vector(field(self.coordinates(x)))
    }
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The fault zone through which the fluid flows (SEAS BP8 description eqs. 14–17), each
/// uniform, positive and finite.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FaultZone {
    /// The zone's thickness `L_fwid` (m).
    pub thickness: f64,
    /// Its permeability `k` (m²).
    pub permeability: f64,
    /// Its porosity `φ` (1).
    pub porosity: f64,
    /// The pore and fluid compressibility `β` (1/Pa): the sum of the two, as the
    /// description's.
    pub compressibility: f64,
    /// The fluid's viscosity `η_f` (Pa·s).
    pub viscosity: f64,
}

impl FaultZone {
    /// Checks every property positive and finite.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
    /// `zone.thickness`, `zone.permeability`, `zone.porosity`, `zone.compressibility` or
    /// `zone.viscosity`.
    pub fn validate(&self) -> Result<()> {
        for (name, v, unit) in [
            ("zone.thickness", self.thickness, "m"),
            ("zone.permeability", self.permeability, "m^2"),
            ("zone.porosity", self.porosity, ""),
            ("zone.compressibility", self.compressibility, "1/Pa"),
            ("zone.viscosity", self.viscosity, "Pa s"),
        ] {
            positive(name, v, unit)?;
        }
        Ok(())
    }

    /// The storage per unit area of the fault `φβL_fwid` (m/Pa): the volume a unit
    /// pressure change stores.
    pub fn storage(&self) -> f64 {
        self.porosity * self.compressibility * self.thickness
    }

    /// The mobility `k/η_f` (m²/(Pa·s)): the Darcy velocity per pressure gradient.
    pub fn mobility(&self) -> f64 {
        self.permeability / self.viscosity
    }

    /// The hydraulic diffusivity `α = k/(φβη_f)` (m²/s).
    pub fn diffusivity(&self) -> f64 {
        self.permeability / (self.porosity * self.compressibility * self.viscosity)
    }
}

/// `v > 0` and finite, or the error naming `name`.
pub(super) fn positive(name: &str, v: f64, unit: &str) -> Result<()> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(invalid(
            name,
            format!("{v} {unit} must be positive and finite"),
        ))
    }
}

/// `∫₀^{end} e^{−μ(end + after − s)} ds` (s): a mode of rate `μ` (1/s) under a unit rate
/// on `[0, end)`, `after` seconds past its end.
pub(super) fn response(mu: f64, end: f64, after: f64) -> f64 {
    if mu == 0.0 {
        end
    } else {
        -(-mu * end).exp_m1() / mu * (-mu * after).exp()
    }
}

/// A Peaceman well (SEAS BP8 description §2.1.2, eqs. 22–23): the injection enters a well
/// of pressure `p_w` and storage `S_well`, from which the volume rate
/// `WI (p_w − p_e)` flows into the fault at the well's node, whose pressure is `p_e`;
/// `WI = 2πkL_fwid/(η_f ln(r_e/r_well))` the well index.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PeacemanWell {
    /// The well's radius `r_well` (m), positive and below the equivalent radius.
    pub radius: f64,
    /// The wellbore storage `S_well` (m³/Pa), finite and ≥ 0 (0: no storage, the
    /// injection enters the fault at once).
    pub storage: f64,
    /// Peaceman's equivalent radius `r_e` (m): the distance from the well where the
    /// unbounded steady radial pressure equals the well node's. `None`: Peaceman's
    /// `0.14 √(h_u² + h_v²)` for the five-point Laplacian of the grid (Peaceman 1983;
    /// `0.198 h` on squares). Only the numerical field uses it.
    pub equivalent_radius: Option<f64>,
}

/// How the injection is spread over the fault.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SurfaceSource {
    /// A Gaussian `exp(−r²/(2w²))/(2πw²)` of width `w` (m; BP8's `L_gauss`), `r` the
    /// distance from the source (description eq. 19).
    Gaussian {
        /// The width `w` (m).
        width: f64,
    },
    /// A Peaceman well at the source (description eqs. 22–23; the closed form takes it as
    /// a point source, eq. 25).
    Well(PeacemanWell),
}

/// What is injected where: a volume rate `injection.rate` (m³/s, the description's `Q₀`)
/// until `injection.shut_in` (s), through `source`, at the fault coordinates `position`
/// (m).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SurfaceInjection {
    /// The volume rate `Q₀` (m³/s) and the shut-in `t_off` (s).
    pub injection: Injection,
    /// The source's shape.
    pub source: SurfaceSource,
    /// The source's centre `(u, v)` in the plane's coordinates (m).
    pub position: [f64; 2],
}

impl SurfaceInjection {
    /// Checks the injection, a finite position, a positive finite Gaussian width, and a
    /// well's positive finite radius, finite non-negative storage and equivalent radius
    /// (when given) above the radius.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `injection.*`,
    /// `source.position`, `source.width`, `well.radius`, `well.storage` or
    /// `well.equivalent_radius`.
    pub fn validate(&self) -> Result<()> {
        self.injection.validate()?;
        if self.position.iter().any(|c| !c.is_finite()) {
            return Err(invalid(
                "source.position",
                format!("{:?} m must be finite", self.position),
            ));
        }
        match self.source {
            SurfaceSource::Gaussian { width } => positive("source.width", width, "m"),
            SurfaceSource::Well(w) => {
                positive("well.radius", w.radius, "m")?;
                if !(w.storage >= 0.0 && w.storage.is_finite()) {
                    return Err(invalid(
                        "well.storage",
                        format!("{} m^3/Pa must be finite and >= 0", w.storage),
                    ));
                }
                if let Some(r) = w.equivalent_radius {
                    if !(r > w.radius && r.is_finite()) {
                        return Err(invalid(
                            "well.equivalent_radius",
                            format!("{r} m must be finite and above well.radius"),
                        ));
                    }
                }
                Ok(())
            }
        }
    }
}

/// A uniform grid of `cells[0] × cells[1]` rectangles over `[lower[0], upper[0]] ×
/// [lower[1], upper[1]]` in a plane's coordinates `(u, v)` (m), its nodes
/// `(lower[0] + i h_u, lower[1] + j h_v)`, `i = 0…cells[0]`, `j = 0…cells[1]`. BP8's
/// `Ω_f` at 10 m: `lower = [−400, −400]`, `upper = [400, 400]`, `cells = [80, 80]`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SurfaceGrid {
    /// The lower corner `(u₀, v₀)` (m).
    pub lower: [f64; 2],
    /// The upper corner `(u₁, v₁)` (m).
    pub upper: [f64; 2],
    /// The cells along `u` and along `v`.
    pub cells: [usize; 2],
}

impl SurfaceGrid {
    /// The cell sizes `(h_u, h_v)` (m).
    pub fn spacing(&self) -> [f64; 2] {
        [0, 1].map(|a| (self.upper[a] - self.lower[a]) / self.cells[a] as f64)
    }

    /// The nodes along `u` and along `v`: `cells + 1`.
    pub fn nodes(&self) -> [usize; 2] {
        self.cells.map(|c| c + 1)
    }

    /// The position `(u, v)` (m) of node `(i, j)`.
    pub fn node(&self, i: usize, j: usize) -> [f64; 2] {
        let h = self.spacing();
        [
            self.lower[0] + i as f64 * h[0],
            self.lower[1] + j as f64 * h[1],
        ]
    }
}
