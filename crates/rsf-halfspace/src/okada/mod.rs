//! Okada (1992) DC3D: displacement and displacement gradient anywhere in an elastic
//! half-space due to uniform slip (and opening) on a finite rectangle.
//!
//! Source: Y. Okada, "Internal deformation due to shear and tensile faults in a
//! half-space", Bull. Seism. Soc. Am. 82(2), 1018–1040 (1992), §3 (finite rectangular
//! source): the solution as the Chinnery sum over the rectangle's corners of
//! `f^A(ξ, η, z) − f̂^A(ξ, η, −z) + f^B(ξ, η, z) + z f^C(ξ, η, z)` (real source, image
//! source, surface corrections), with the vertical-fault (`cos δ = 0`) limits of the
//! part-B integrals and the treatment of the singular cases on the rectangle's edges and
//! their extensions. Our implementation follows the same organisation as Okada's FORTRAN
//! routine DC3D, and `tests/suite/okada_fixture.rs` compares it with that routine's output.
//!
//! # Conventions (docs/halfspace.md §1)
//! - Okada's frame: `x` along strike, `z` up, the half-space is `z ≤ 0`, `y` completes a
//!   right-handed frame. The rectangle's reference point is `(0, 0, −depth)`; a point
//!   `(ξ, η)` of the rectangle (`ξ ∈ [al1, al2]` along strike, `η ∈ [aw1, aw2]` up dip)
//!   is at `(ξ, η cos δ, −depth + η sin δ)`.
//! - Dislocation `[U1, U2, U3]` = motion of the hanging wall relative to the footwall:
//!   `U1` along strike (`+x`, left-lateral), `U2` up dip (reverse), `U3` opening. The
//!   hanging wall is the side the normal `n = (0, −sin δ, cos δ)` points to.
//! - Output: `u[i]` and `grad[i][j] = ∂u_i/∂x_j` in the same frame. Same length unit
//!   throughout (SI: m); displacements in the unit of the dislocation; derivatives
//!   dimensionless.
//! - To use another frame (e.g. SEAS BP5: `x₁` across the fault, `x₂` along strike,
//!   `x₃` down), map points with `x = x₂`, `y = x₁`, `z = −x₃` and the gradient by the
//!   same (orthogonal) map; docs/halfspace.md §1 has the details.
//!
//! # Singular cases
//! Lengths closer than `ε = 10⁻⁶ ×` the rectangle's smaller side to 0 are snapped to 0
//! (DC3D does the same with an absolute `10⁻⁶`). A point on an edge of the rectangle is
//! [`Error::OnEdge`] (DC3D returns zeros and `IRET = 1`); on the negative extension of an
//! edge (`R + ξ = 0` or `R + η = 0`) the logarithms are rewritten as in DC3D and the
//! result is finite, and near it `R + ξ` is computed without cancellation (DC3D loses
//! digits there); `|cos δ| < 10⁻⁶` is taken as a vertical fault; points on the surface
//! `z = 0` are regular.

mod geometry;
mod parts;

use crate::error::{check_finite, Error};
use crate::space::Space;
use geometry::{Corner, DipConsts};
use parts::{part_a, part_b, part_c, Part};

/// Relative snapping tolerance (times the rectangle's smaller side).
const EPS_REL: f64 = 1e-6;

/// A rectangle in Okada's frame (see the [module docs](self)): reference point
/// `(0, 0, −depth)`, dip `δ` in degrees, along-strike range `[al1, al2]` and up-dip range
/// `[aw1, aw2]` (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rectangle {
    depth: f64,
    dip_deg: f64,
    strike: [f64; 2],
    dip: [f64; 2],
}

impl Rectangle {
    /// The rectangle of DC3D's arguments `DEPTH, DIP, AL1, AL2, AW1, AW2`.
    ///
    /// # Errors
    /// [`Error::Parameter`] unless all are finite and `al1 < al2`, `aw1 < aw2` (with
    /// finite differences);
    /// [`Error::SourceAboveSurface`] if part of the rectangle is above `z = 0` (by more
    /// than the snapping tolerance).
    pub fn new(depth: f64, dip_deg: f64, strike: [f64; 2], dip: [f64; 2]) -> Result<Self, Error> {
        check_finite([
            ("depth", depth),
            ("dip", dip_deg),
            ("al1", strike[0]),
            ("al2", strike[1]),
            ("aw1", dip[0]),
            ("aw2", dip[1]),
        ])?;
        if !(strike[1] - strike[0] > 0.0 && (strike[1] - strike[0]).is_finite()) {
            return Err(Error::Parameter {
                name: "al2 - al1",
                value: strike[1] - strike[0],
                expected: "> 0 (and finite)",
            });
        }
        if !(dip[1] - dip[0] > 0.0 && (dip[1] - dip[0]).is_finite()) {
            return Err(Error::Parameter {
                name: "aw2 - aw1",
                value: dip[1] - dip[0],
                expected: "> 0 (and finite)",
            });
        }
        let rect = Self {
            depth,
            dip_deg,
            strike,
            dip,
        };
        let sd = DipConsts::new(0.5, dip_deg).sd;
        let z_top = -depth + (dip[0] * sd).max(dip[1] * sd);
        if !(z_top <= EPS_REL * rect.scale()) {
            return Err(Error::SourceAboveSurface { z_top });
        }
        Ok(rect)
    }

    /// Depth of the reference point (m).
    pub fn depth(&self) -> f64 {
        self.depth
    }

    /// Dip (degrees).
    pub fn dip_deg(&self) -> f64 {
        self.dip_deg
    }

    /// `[al1, al2]` (m).
    pub fn strike_range(&self) -> [f64; 2] {
        self.strike
    }

    /// `[aw1, aw2]` (m).
    pub fn dip_range(&self) -> [f64; 2] {
        self.dip
    }

    /// Area (m²).
    pub fn area(&self) -> f64 {
        (self.strike[1] - self.strike[0]) * (self.dip[1] - self.dip[0])
    }

    /// The smaller side (m), the length scale of the snapping tolerance.
    fn scale(&self) -> f64 {
        (self.strike[1] - self.strike[0]).min(self.dip[1] - self.dip[0])
    }

    /// The point `(ξ, η)` of the rectangle's plane in Okada's frame:
    /// `(ξ, η cos δ, −depth + η sin δ)` (with DC3D's `cos δ` snapping).
    pub fn point(&self, xi: f64, eta: f64) -> [f64; 3] {
        let k = DipConsts::new(0.5, self.dip_deg);
        [xi, eta * k.cd, -self.depth + eta * k.sd]
    }

    /// The centre of the rectangle.
    pub fn centre(&self) -> [f64; 3] {
        self.point(
            0.5 * (self.strike[0] + self.strike[1]),
            0.5 * (self.dip[0] + self.dip[1]),
        )
    }

    /// Unit vectors `[strike, up-dip, normal]`: `(1, 0, 0)`, `(0, cos δ, sin δ)` and
    /// `n = (0, −sin δ, cos δ)`, which points into the hanging wall.
    pub fn frame(&self) -> [[f64; 3]; 3] {
        let k = DipConsts::new(0.5, self.dip_deg);
        [[1.0, 0.0, 0.0], [0.0, k.cd, k.sd], [0.0, -k.sd, k.cd]]
    }
}

/// Displacement and displacement gradient at a point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Deformation {
    /// `[u_x, u_y, u_z]`, in the unit of the dislocation.
    pub u: [f64; 3],
    /// `grad[i][j] = ∂u_i/∂x_j` (dimensionless).
    pub grad: [[f64; 3]; 3],
}

impl Deformation {
    /// `self + s · other`.
    pub fn add_scaled(&self, s: f64, other: &Deformation) -> Deformation {
        let mut out = *self;
        for i in 0..3 {
            out.u[i] += s * other.u[i];
            for j in 0..3 {
                out.grad[i][j] += s * other.grad[i][j];
            }
        }
        out
    }

    fn from_dc3d_order(v: &[f64; 12]) -> Self {
        let mut d = Deformation {
            u: [v[0], v[1], v[2]],
            ..Deformation::default()
        };
        for j in 0..3 {
            for i in 0..3 {
                d.grad[i][j] = v[3 + 3 * j + i];
            }
        }
        d
    }

    fn is_finite(&self) -> bool {
        self.u
            .iter()
            .chain(self.grad.iter().flatten())
            .all(|v| v.is_finite())
    }
}

/// DC3D for one medium and one rectangle: the constants of the dip and medium computed
/// once, evaluated at many points.
#[derive(Debug, Clone, Copy)]
pub struct Okada {
    rect: Rectangle,
    consts: DipConsts,
    eps: f64,
}

impl Okada {
    /// DC3D for the medium constant `α = (λ + μ)/(λ + 2μ) = 1/(2(1 − ν))` and `rect`.
    ///
    /// # Errors
    /// [`Error::Parameter`] unless `0 < α < 1`.
    pub fn new(alpha: f64, rect: Rectangle) -> Result<Self, Error> {
        if !(alpha > 0.0 && alpha < 1.0) {
            return Err(Error::Parameter {
                name: "alpha",
                value: alpha,
                expected: "in (0, 1)",
            });
        }
        Ok(Self {
            rect,
            consts: DipConsts::new(alpha, rect.dip_deg),
            eps: EPS_REL * rect.scale(),
        })
    }

    /// The rectangle.
    pub fn rectangle(&self) -> &Rectangle {
        &self.rect
    }

    /// The deformation at `point` (Okada's frame, `z ≤ 0`) due to the dislocation
    /// `[U1, U2, U3]` (strike, dip, tensile).
    ///
    /// # Errors
    /// As [`Okada::unit_responses`], and [`Error::Parameter`] for a non-finite
    /// dislocation.
    pub fn deformation(
        &self,
        point: [f64; 3],
        dislocation: [f64; 3],
    ) -> Result<Deformation, Error> {
        check_finite([
            ("disl1", dislocation[0]),
            ("disl2", dislocation[1]),
            ("disl3", dislocation[2]),
        ])?;
        let unit = self.unit_responses(point)?;
        let mut out = Deformation::default();
        for (c, resp) in unit.iter().enumerate() {
            if dislocation[c] != 0.0 {
                out = out.add_scaled(dislocation[c], resp);
            }
        }
        if out.is_finite() {
            Ok(out)
        } else {
            Err(Error::NonFinite {
                what: "deformation",
            })
        }
    }

    /// The deformations at `point` due to unit strike-slip, unit dip-slip and unit
    /// opening, in that order.
    ///
    /// # Errors
    /// [`Error::Parameter`] for a non-finite point; [`Error::AboveSurface`] for `z > 0`;
    /// [`Error::OnEdge`] on an edge of the rectangle; [`Error::NonFinite`] if the result
    /// overflows.
    pub fn unit_responses(&self, point: [f64; 3]) -> Result<[Deformation; 3], Error> {
        self.unit_responses_in(point, Space::HalfSpace)
    }

    /// As [`unit_responses`](Self::unit_responses) in a half-space, or in a whole space:
    /// then the real source's part A alone (Okada 1992, §3: the full-space term of his
    /// solution, without the image and the surface terms B and C), at any `z` — the
    /// rectangle and the point moved together vertically give the same result, so the
    /// rectangle's `depth` only places it.
    ///
    /// # Errors
    /// As [`unit_responses`](Self::unit_responses) ([`Error::AboveSurface`] only in a
    /// half-space).
    pub fn unit_responses_in(
        &self,
        point: [f64; 3],
        space: Space,
    ) -> Result<[Deformation; 3], Error> {
        let [x, y, z] = point;
        check_finite([("x", x), ("y", y), ("z", z)])?;
        if z > 0.0 && space == Space::HalfSpace {
            return Err(Error::AboveSurface { z });
        }
        let images: &[bool] = match space {
            Space::HalfSpace => &[false, true],
            Space::WholeSpace => &[false],
        };
        let k = &self.consts;
        let eps = self.eps;
        let snap = |v: f64| if v.abs() < eps { 0.0 } else { v };
        let [al1, al2] = self.rect.strike;
        let xi = [snap(x - al1), snap(x - al2)];
        let mut total: Part = [[0.0; 12]; 3];

        for &image in images {
            let d = if image {
                self.rect.depth - z
            } else {
                self.rect.depth + z
            };
            let p = y * k.cd + d * k.sd;
            let q = snap(y * k.sd - d * k.cd);
            let et = [snap(p - self.rect.dip[0]), snap(p - self.rect.dip[1])];
            if q == 0.0
                && ((xi[0] * xi[1] <= 0.0 && et[0] * et[1] == 0.0)
                    || (et[0] * et[1] <= 0.0 && xi[0] * xi[1] == 0.0))
            {
                return Err(Error::OnEdge { point });
            }
            let flags = NegativeExtension::new(xi, et, q);
            for (ke, &eta) in et.iter().enumerate() {
                for (jx, &xij) in xi.iter().enumerate() {
                    let corner = Corner::new(
                        xij,
                        eta,
                        q,
                        k,
                        flags.r_plus_xi[ke],
                        flags.r_plus_eta[jx],
                        eps,
                    )
                    .ok_or(Error::OnEdge { point })?;
                    let sign = if jx == ke { 1.0 } else { -1.0 };
                    let du = if image {
                        image_terms(&corner, k, z)
                    } else {
                        real_terms(&corner, k)
                    };
                    for (t, d) in total.iter_mut().zip(du.iter()) {
                        for (a, b) in t.iter_mut().zip(d.iter()) {
                            *a += sign * b;
                        }
                    }
                }
            }
        }
        let out = total.map(|v| Deformation::from_dc3d_order(&v));
        if out.iter().all(Deformation::is_finite) {
            Ok(out)
        } else {
            Err(Error::NonFinite {
                what: "deformation",
            })
        }
    }
}

/// Which corners lie on the negative extension of an edge, where `R + ξ` (or `R + η`)
/// vanishes: `r_plus_xi[k]` for the corners with `η = et[k]`, `r_plus_eta[j]` for those
/// with `ξ = xi[j]` (both ends of the edge are then on the extension). DC3D flags
/// `R + ξ < ε`, which also catches points up to `√(2|ξ|ε)` off the line, where it drops
/// `ln(η² + q²)` and the `2/(η² + q²)` part of `X11` from both corners (they cancel in the
/// sum) but where the plain `R + ξ` it keeps elsewhere has lost most of its digits. We
/// compute `R + ξ` without cancellation (`geometry::sum_with_r`) and flag only the points
/// on the line itself (`η = q = 0` after snapping), where `R + ξ = 0` exactly.
struct NegativeExtension {
    r_plus_xi: [bool; 2],
    r_plus_eta: [bool; 2],
}

impl NegativeExtension {
    fn new(xi: [f64; 2], et: [f64; 2], q: f64) -> Self {
        Self {
            r_plus_xi: [
                xi[0] < 0.0 && et[0] == 0.0 && q == 0.0,
                xi[0] < 0.0 && et[1] == 0.0 && q == 0.0,
            ],
            r_plus_eta: [
                et[0] < 0.0 && xi[0] == 0.0 && q == 0.0,
                et[0] < 0.0 && xi[1] == 0.0 && q == 0.0,
            ],
        }
    }
}

/// The real source's term at one corner, `−f^A(ξ, η, z)` rotated from the fault's
/// `(ξ, η, q)`-aligned components to `(x, y, z)` (the `z` derivatives change sign with
/// the real source's depth `d = depth + z`).
fn real_terms(c: &Corner, k: &DipConsts) -> Part {
    let a = part_a(c, k);
    let (sd, cd) = (k.sd, k.cd);
    a.map(|v| {
        let mut du = [0.0; 12];
        for b in 0..4 {
            let i = 3 * b;
            let s = if b == 3 { -1.0 } else { 1.0 };
            du[i] = -s * v[i];
            du[i + 1] = s * (-v[i + 1] * cd + v[i + 2] * sd);
            du[i + 2] = s * (-v[i + 1] * sd - v[i + 2] * cd);
        }
        du
    })
}

/// The image source's terms at one corner, `f̂^A + f^B + z f^C`, rotated to `(x, y, z)`,
/// with the `z` derivative of `z f^C`'s factor `z`.
fn image_terms(c: &Corner, k: &DipConsts, z: f64) -> Part {
    let a = part_a(c, k);
    let b = part_b(c, k);
    let cc = part_c(c, k, z);
    let (sd, cd) = (k.sd, k.cd);
    let mut out = [[0.0; 12]; 3];
    for comp in 0..3 {
        let (va, vb, vc) = (&a[comp], &b[comp], &cc[comp]);
        let du = &mut out[comp];
        for blk in 0..4 {
            let i = 3 * blk;
            let ab = |m: usize| va[m] + vb[m];
            du[i] = ab(i) + z * vc[i];
            du[i + 1] = (ab(i + 1) + z * vc[i + 1]) * cd - (ab(i + 2) + z * vc[i + 2]) * sd;
            du[i + 2] = (ab(i + 1) - z * vc[i + 1]) * sd + (ab(i + 2) - z * vc[i + 2]) * cd;
        }
        du[9] += vc[0];
        du[10] += vc[1] * cd - vc[2] * sd;
        du[11] -= vc[1] * sd + vc[2] * cd;
    }
    out
}

/// DC3D in one call: medium constant `alpha = (λ + μ)/(λ + 2μ)`, point `[x, y, z]`, the
/// rectangle of DC3D's `depth`, `dip`, `[al1, al2]`, `[aw1, aw2]`
/// ([`Rectangle::new`]) and the dislocation `[U1, U2, U3]` (see the [module docs](self)
/// for the conventions).
///
/// # Errors
/// Those of [`Okada::new`] and [`Okada::deformation`].
///
/// # Example
/// ```
/// use rsf_halfspace::okada::{dc3d, Rectangle};
/// // 1 m of left-lateral strike slip on a vertical fault 2 km long, from the surface
/// // to 1 km depth; displacement 500 m off the fault's middle on the surface.
/// let fault = Rectangle::new(0.0, 90.0, [-1e3, 1e3], [-1e3, 0.0]).unwrap();
/// let d = dc3d(2.0 / 3.0, [0.0, 500.0, 0.0], fault, [1.0, 0.0, 0.0]).unwrap();
/// // The footwall side (y > 0) moves towards −x.
/// assert!(d.u[0] < 0.0 && d.u[0] > -0.5);
/// ```
pub fn dc3d(
    alpha: f64,
    point: [f64; 3],
    rect: Rectangle,
    dislocation: [f64; 3],
) -> Result<Deformation, Error> {
    Okada::new(alpha, rect)?.deformation(point, dislocation)
}
