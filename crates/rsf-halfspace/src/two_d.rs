//! 2-D dislocations in a half-space, in closed form, in the cross-section `(y, z)` of
//! Okada's frame (`z ≤ 0` up, the fault infinitely long along `x`; docs/halfspace.md §4).
//!
//! - [`antiplane_segment`]: uniform strike slip on the vertical segment `y = 0`,
//!   depths `[d1, d2]` (a pair of screw dislocations with their images across the free
//!   surface; `d2 = ∞` is a single screw dislocation at depth `d1`, the fault slipping
//!   below it) — displacement `u_x` and stresses `σ_xy`, `σ_xz` anywhere.
//! - [`edge_surface_displacement`]: uniform dip slip on a dipping segment (a pair of
//!   edge dislocations, plane strain), the displacement of the free surface (Freund &
//!   Barnett 1976, BSSA 66(3), 667–675, in the form of Segall 2010, *Earthquake and
//!   Volcano Deformation*, §3.3; independent of ν).
//! - [`edge_segment_stress`]: the same source's stress anywhere in the half-space
//!   (Segall 2010, eqs. 3.77–3.79 as corrected in the book's errata).
//!
//! Slip follows Okada's convention: the motion of the hanging wall relative to the
//! footwall, where the hanging wall is the side of `n = (0, −sin δ, cos δ)` (for a
//! vertical fault `y < 0`).

use crate::error::Error;
use crate::stress::Medium;
use std::f64::consts::PI;

/// The antiplane field at a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AntiplaneField {
    /// `u_x` (m, in the unit of the slip).
    pub u: f64,
    /// `σ_xy = μ ∂u_x/∂y` (Pa).
    pub sigma_xy: f64,
    /// `σ_xz = μ ∂u_x/∂z` (Pa).
    pub sigma_xz: f64,
}

/// `(sin δ, cos δ)` with `cos δ = 0`, `sin δ = 1` when `|cos δ| < 10⁻⁶`, as in DC3D, so that
/// a vertical segment's ends are exactly at `y = 0`.
fn sin_cos_snapped(dip_deg: f64) -> (f64, f64) {
    let (sd, cd) = dip_deg.to_radians().sin_cos();
    if cd.abs() < 1e-6 {
        (1.0, 0.0)
    } else {
        (sd, cd)
    }
}

/// `a/(y² + a²)`, 0 for infinite `a`.
fn ratio(a: f64, y: f64) -> f64 {
    if a.is_infinite() {
        0.0
    } else {
        a / (y * y + a * a)
    }
}

/// `y/(y² + a²)`, 0 for infinite `a`.
fn slope(a: f64, y: f64) -> f64 {
    if a.is_infinite() {
        0.0
    } else {
        y / (y * y + a * a)
    }
}

/// Uniform strike slip `slip` (`u_x` of the side `y < 0` minus that of `y > 0`) on the
/// vertical segment `y = 0`, `−d2 ≤ z ≤ −d1` (`depths = [d1, d2]`), in a half-space of
/// shear modulus `mu`; the field at `point = [y, z]`:
///
/// ```text
/// u_x  = s/(2π) [atan((z + d1)/y) − atan((z + d2)/y) + atan((d1 − z)/y) − atan((d2 − z)/y)]
/// σ_xy = μ ∂u_x/∂y,  σ_xz = μ ∂u_x/∂z
/// ```
///
/// (the segment and its mirror image `z → −z`, which makes `σ_xz = 0` on `z = 0`). On
/// `y = 0` the displacement is the mean of the two sides (0). The shear traction on the
/// fault plane in Okada's sense (`(σ n)·e_s`, `n = (0, −1, 0)`) is `−σ_xy`.
///
/// # Errors
/// [`Error::Parameter`] unless `mu > 0`, `slip`, `y`, `z` and `d1` are finite and
/// `0 ≤ d1 < d2` (`d2` may be `+∞`); [`Error::AboveSurface`] for `z > 0`;
/// [`Error::AtDislocation`] at an end of the segment.
pub fn antiplane_segment(
    mu: f64,
    slip: f64,
    [d1, d2]: [f64; 2],
    [y, z]: [f64; 2],
) -> Result<AntiplaneField, Error> {
    if !(mu.is_finite() && mu > 0.0) {
        return Err(Error::Parameter {
            name: "mu",
            value: mu,
            expected: "finite and > 0",
        });
    }
    for (name, value) in [("slip", slip), ("d1", d1), ("y", y), ("z", z)] {
        if !value.is_finite() {
            return Err(Error::Parameter {
                name,
                value,
                expected: "finite",
            });
        }
    }
    if !(d1 >= 0.0 && d2 > d1) {
        return Err(Error::Parameter {
            name: "d2",
            value: d2,
            expected: "d2 > d1 >= 0",
        });
    }
    if z > 0.0 {
        return Err(Error::AboveSurface { z });
    }
    if y == 0.0 && (z == -d1 || z == -d2) {
        return Err(Error::AtDislocation { x: y, z });
    }
    // Offsets of the point from the segment's ends and from their images.
    let (a1, a2, b1, b2) = (z + d1, z + d2, d1 - z, d2 - z);
    let c = slip / (2.0 * PI);
    let u = if y == 0.0 {
        0.0
    } else {
        c * ((a1 / y).atan() - (a2 / y).atan() + (b1 / y).atan() - (b2 / y).atan())
    };
    let sigma_xy = mu * c * (-ratio(a1, y) + ratio(a2, y) - ratio(b1, y) + ratio(b2, y));
    let sigma_xz = mu * c * (slope(a1, y) - slope(a2, y) - slope(b1, y) + slope(b2, y));
    let field = AntiplaneField {
        u,
        sigma_xy,
        sigma_xz,
    };
    if field.u.is_finite() && field.sigma_xy.is_finite() && field.sigma_xz.is_finite() {
        Ok(field)
    } else {
        Err(Error::NonFinite {
            what: "antiplane field",
        })
    }
}

/// The surface displacement `(u_y, u_z)` at `(y, 0)` of uniform dip slip `slip`
/// (reverse positive: the hanging wall moves up dip) on the segment of Okada's
/// cross-section `(η cos δ, −depth + η sin δ)`, `η ∈ [aw1, aw2]`, dip `dip_deg` — the 2-D
/// (plane-strain, infinitely long) limit of [`okada::dc3d`](crate::okada::dc3d) with
/// `U2 = slip` at the surface. With `s_v = s sin δ`, `s_h = s cos δ` and, for each end
/// `k` of the segment at `(y_k, −d_k)`, `ζ_k = −(y − y_k)/d_k`:
///
/// ```text
/// u_z = (1/π) Σ_k ±[s_v atan ζ_k + (s_h + s_v ζ_k)/(1 + ζ_k²)]
/// u_y = (1/π) Σ_k ±[s_h atan ζ_k + (s_v − s_h ζ_k)/(1 + ζ_k²)]
/// ```
///
/// `+` at the up-dip end, `−` at the down-dip end. A surface-breaking segment
/// (`d_k = 0` at the up-dip end) is allowed except at the trace itself.
///
/// # Errors
/// [`Error::Parameter`] for non-finite input, `aw1 ≥ aw2` or a dip outside `(0°, 180°)`;
/// [`Error::SourceAboveSurface`] if the segment reaches above `z = 0`;
/// [`Error::AtDislocation`] at a surface-breaking segment's trace.
pub fn edge_surface_displacement(
    slip: f64,
    depth: f64,
    dip_deg: f64,
    aw: [f64; 2],
    y: f64,
) -> Result<[f64; 2], Error> {
    check_finite(&[("slip", slip), ("y", y)])?;
    DipSegment { depth, dip_deg, aw }.check()?;
    let (sd, cd) = sin_cos_snapped(dip_deg);
    let (sv, sh) = (slip * sd, slip * cd);
    // Depth of the up-dip end (η = aw2) and of the down-dip end.
    let (d_top, d_bot) = (depth - aw[1] * sd, depth - aw[0] * sd);
    if d_top < 0.0 {
        return Err(Error::SourceAboveSurface { z_top: -d_top });
    }
    let end = |yk: f64, dk: f64| -> Result<[f64; 2], Error> {
        if dk == 0.0 {
            if y == yk {
                return Err(Error::AtDislocation { x: y, z: 0.0 });
            }
            // ζ → ±∞: only the arctangents remain.
            let a = if y < yk { 0.5 * PI } else { -0.5 * PI };
            return Ok([sh * a, sv * a]);
        }
        let zeta = -(y - yk) / dk;
        let a = zeta.atan();
        let w = 1.0 / (1.0 + zeta * zeta);
        Ok([sh * a + (sv - sh * zeta) * w, sv * a + (sh + sv * zeta) * w])
    };
    let top = end(aw[1] * cd, d_top)?;
    let bot = end(aw[0] * cd, d_bot)?;
    let u = [(top[0] - bot[0]) / PI, (top[1] - bot[1]) / PI];
    if u.iter().all(|v| v.is_finite()) {
        Ok(u)
    } else {
        Err(Error::NonFinite {
            what: "surface displacement",
        })
    }
}

/// A segment of a plane-strain (infinitely long) dipping fault in Okada's cross-section:
/// the points `(η cos δ, −depth + η sin δ)`, `η ∈ [aw1, aw2]` (m), `δ = dip_deg`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DipSegment {
    /// Depth of the reference point `η = 0` (m, positive down).
    pub depth: f64,
    /// Dip δ (degrees, in `(0, 180)`).
    pub dip_deg: f64,
    /// `[aw1, aw2]`: the segment's extent along dip from the reference point (m).
    pub aw: [f64; 2],
}

impl DipSegment {
    /// Finite numbers, a dip in `(0°, 180°)` and `aw1 < aw2`.
    fn check(&self) -> Result<(), Error> {
        let Self { depth, dip_deg, aw } = *self;
        check_finite(&[
            ("depth", depth),
            ("dip", dip_deg),
            ("aw1", aw[0]),
            ("aw2", aw[1]),
        ])?;
        if !(dip_deg > 0.0 && dip_deg < 180.0) {
            return Err(Error::Parameter {
                name: "dip",
                value: dip_deg,
                expected: "in (0, 180) degrees",
            });
        }
        if !(aw[1] > aw[0]) {
            return Err(Error::Parameter {
                name: "aw2 - aw1",
                value: aw[1] - aw[0],
                expected: "> 0",
            });
        }
        Ok(())
    }
}

/// [`Error::Parameter`] naming the first value that is not finite.
fn check_finite(values: &[(&'static str, f64)]) -> Result<(), Error> {
    match values.iter().find(|(_, v)| !v.is_finite()) {
        Some(&(name, value)) => Err(Error::Parameter {
            name,
            value,
            expected: "finite",
        }),
        None => Ok(()),
    }
}

/// Plane-strain stress (Pa, tension positive) in Okada's cross-section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneStrainStress {
    /// `σ_yy`.
    pub yy: f64,
    /// `σ_zz`.
    pub zz: f64,
    /// `σ_yz`.
    pub yz: f64,
    /// `σ_xx = ν (σ_yy + σ_zz)` (plane strain along the fault's strike `x`).
    pub xx: f64,
}

/// The stress `[σ11, σ22, σ12]` of one edge dislocation at depth `xi2` below the origin
/// of Segall's frame (`x1` horizontal, `x2` down), Burgers vector `(s1, s2)`, in a
/// half-space `x2 ≥ 0` (Segall 2010, eqs. 3.77–3.79 with the errata): the dislocation,
/// its image at `x2 = −xi2` and the surface correction. `c = μ/(2π(1 − ν))`.
fn segall_edge_stress(c: f64, s1: f64, s2: f64, xi2: f64, x1: f64, x2: f64) -> [f64; 3] {
    let (a, b) = (x2 - xi2, x2 + xi2);
    let x12 = x1 * x1;
    let r1 = x12 + a * a;
    let r2 = x12 + b * b;
    let (r1_2, r2_2, r2_3) = (r1 * r1, r2 * r2, r2 * r2 * r2);
    let (a2, b2, b3) = (a * a, b * b, b * b * b);
    let m = 6.0 * x2 * b * x12;
    let s11 = s2
        * (x1 * (a2 - x12) / r1_2 - x1 * (b2 - x12) / r2_2
            + 4.0 * xi2 * x1 / r2_3 * ((2.0 * xi2 - x2) * b2 + (3.0 * x2 + 2.0 * xi2) * x12))
        + s1 * (a * (a2 + 3.0 * x12) / r1_2 - b * (b2 + 3.0 * x12) / r2_2
            + 2.0 * xi2 / r2_3 * (m - a * b3 - x12 * x12));
    let s22 = -s2
        * (x1 * (3.0 * a2 + x12) / r1_2
            - x1 * (3.0 * b2 + x12) / r2_2
            - 4.0 * xi2 * x2 * x1 / r2_3 * (3.0 * b2 - x12))
        + s1 * (a * (a2 - x12) / r1_2
            - b * (b2 - x12) / r2_2
            - 2.0 * xi2 / r2_3 * (m - (3.0 * x2 + xi2) * b3 + x12 * x12));
    let s12 = s2
        * (a * (a2 - x12) / r1_2 - b * (b2 - x12) / r2_2
            + 2.0 * xi2 / r2_3 * (m - x12 * x12 + (xi2 - x2) * b3))
        + s1 * (x1 * (a2 - x12) / r1_2 - x1 * (b2 - x12) / r2_2
            + 4.0 * xi2 * x2 * x1 / r2_3 * (3.0 * b2 - x12));
    [c * s11, c * s22, c * s12]
}

/// The plane-strain stress at `point = [y, z]` of uniform dip slip `slip` (reverse positive) on
/// the [`DipSegment`] `(η cos δ, −depth + η sin δ)`, `η ∈ [aw1, aw2]`
/// (the source of [`edge_surface_displacement`]), in a half-space of the given `medium`
/// (its `μ` and `ν`) — the 2-D (infinitely long) limit of
/// [`okada::dc3d`](crate::okada::dc3d) with `U2 = slip`. Two edge dislocations, at the
/// up-dip end (`+`) and the down-dip end (`−`), each with its image and surface
/// correction (Segall 2010, eqs. 3.77–3.79 as corrected in the errata), evaluated in
/// Segall's frame `x1 = −(y − y_k)`, `x2 = −z` (a rotation by π, so
/// `σ_yy = σ11`, `σ_zz = σ22`, `σ_yz = σ12`) with Burgers vector
/// `(s1, s2) = slip (cos δ, sin δ)`, a sign convention fixed by the comparison with DC3D
/// in `tests/suite/two_d.rs`.
///
/// # Errors
/// [`Error::Parameter`] for non-finite input, `aw1 ≥ aw2` or a dip outside
/// `(0°, 180°)`; [`Error::SourceAboveSurface`] if the segment reaches above
/// `z = 0`; [`Error::AboveSurface`] for `z > 0`; [`Error::AtDislocation`] within
/// `10⁻⁹ (aw2 − aw1)` of an end of the segment.
pub fn edge_segment_stress(
    medium: &Medium,
    slip: f64,
    segment: DipSegment,
    point: [f64; 2],
) -> Result<PlaneStrainStress, Error> {
    let DipSegment { depth, dip_deg, aw } = segment;
    let [y, z] = point;
    let (mu, nu) = (medium.mu(), medium.nu());
    check_finite(&[("slip", slip), ("y", y), ("z", z)])?;
    segment.check()?;
    if z > 0.0 {
        return Err(Error::AboveSurface { z });
    }
    let (sd, cd) = sin_cos_snapped(dip_deg);
    let (d_top, d_bot) = (depth - aw[1] * sd, depth - aw[0] * sd);
    if d_top < 0.0 {
        return Err(Error::SourceAboveSurface { z_top: -d_top });
    }
    let c = mu / (2.0 * PI * (1.0 - nu));
    let near = 1e-9 * (aw[1] - aw[0]);
    let (s1, s2) = (slip * cd, slip * sd);
    let mut sigma = [0.0; 3];
    for (sign, yk, dk) in [(1.0, aw[1] * cd, d_top), (-1.0, aw[0] * cd, d_bot)] {
        let x1 = -(y - yk);
        if x1.hypot(-z - dk) <= near {
            return Err(Error::AtDislocation { x: y, z });
        }
        let e = segall_edge_stress(c, sign * s1, sign * s2, dk, x1, -z);
        for (t, v) in sigma.iter_mut().zip(e) {
            *t += v;
        }
    }
    let out = PlaneStrainStress {
        yy: sigma[0],
        zz: sigma[1],
        yz: sigma[2],
        xx: nu * (sigma[0] + sigma[1]),
    };
    if [out.yy, out.zz, out.yz, out.xx]
        .iter()
        .all(|v| v.is_finite())
    {
        Ok(out)
    } else {
        Err(Error::NonFinite {
            what: "plane-strain stress",
        })
    }
}
