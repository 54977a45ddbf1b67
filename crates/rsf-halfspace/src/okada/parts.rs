//! The three parts of Okada's finite-source solution at one corner: `A` (the full-space
//! term, evaluated for the real and the image source), `B` and `C` (the surface
//! corrections), each for the three unit dislocations (strike, dip, tensile) and each as
//! the twelve numbers `u_x, u_y, u_z` and their `x`, `y`, `z` derivatives in the fault's
//! local frame (Okada 1992, §3: `f^A`, `f^B`, `f^C` and their derivatives;
//! docs/halfspace.md §2). Already divided by `2π`.

use super::geometry::{Corner, DipConsts};

/// Twelve values per unit dislocation: index `[component][k]`, `k` = displacement
/// `0..3`, then `∂/∂x` `3..6`, `∂/∂y` `6..9`, `∂/∂z` `9..12` (DC3D's order).
pub(crate) type Part = [[f64; 12]; 3];

const INV_2PI: f64 = 1.0 / (2.0 * std::f64::consts::PI);

fn scaled(mut p: Part) -> Part {
    for row in &mut p {
        for v in row.iter_mut() {
            *v *= INV_2PI;
        }
    }
    p
}

/// Part A.
pub(crate) fn part_a(c: &Corner, k: &DipConsts) -> Part {
    let (a1, a2) = (k.alp1, k.alp2);
    let (sd, cd) = (k.sd, k.cd);
    let Corner {
        xi,
        et,
        q,
        xi2,
        q2,
        r,
        r3,
        y,
        d,
        tt,
        alx,
        ale,
        x11,
        y11,
        y32,
        ey,
        ez,
        fy,
        fz,
        gy,
        gz,
        hy,
        hz,
        ..
    } = *c;
    let xy = xi * y11;
    let qx = q * x11;
    let qy = q * y11;
    let strike = [
        0.5 * tt + a2 * xi * qy,
        a2 * q / r,
        a1 * ale - a2 * q * qy,
        -a1 * qy - a2 * xi2 * q * y32,
        -a2 * xi * q / r3,
        a1 * xy + a2 * xi * q2 * y32,
        a1 * xy * sd + a2 * xi * fy + 0.5 * d * x11,
        a2 * ey,
        a1 * (cd / r + qy * sd) - a2 * q * fy,
        a1 * xy * cd + a2 * xi * fz + 0.5 * y * x11,
        a2 * ez,
        -a1 * (sd / r - qy * cd) - a2 * q * fz,
    ];
    let dip = [
        a2 * q / r,
        0.5 * tt + a2 * et * qx,
        a1 * alx - a2 * q * qx,
        -a2 * xi * q / r3,
        -0.5 * qy - a2 * et * q / r3,
        a1 / r + a2 * q2 / r3,
        a2 * ey,
        a1 * d * x11 + 0.5 * xy * sd + a2 * et * gy,
        a1 * y * x11 - a2 * q * gy,
        a2 * ez,
        a1 * y * x11 + 0.5 * xy * cd + a2 * et * gz,
        -a1 * d * x11 - a2 * q * gz,
    ];
    let tensile = [
        -a1 * ale - a2 * q * qy,
        -a1 * alx - a2 * q * qx,
        0.5 * tt - a2 * (et * qx + xi * qy),
        -a1 * xy + a2 * xi * q2 * y32,
        -a1 / r + a2 * q2 / r3,
        -a1 * qy - a2 * q * q2 * y32,
        -a1 * (cd / r + qy * sd) - a2 * q * fy,
        -a1 * y * x11 - a2 * q * gy,
        a1 * (d * x11 + xy * sd) + a2 * q * hy,
        a1 * (sd / r - qy * cd) - a2 * q * fz,
        a1 * d * x11 - a2 * q * gz,
        a1 * (y * x11 + xy * cd) + a2 * q * hz,
    ];
    scaled([strike, dip, tensile])
}

/// The integrals `I1…I4`, `J1…J6`, `K1…K4` of part B (Okada 1992, §3), in the general
/// form for `cos δ ≠ 0` and the limiting form for a vertical fault.
struct PartBIntegrals {
    i1: f64,
    i2: f64,
    i3: f64,
    i4: f64,
    j1: f64,
    j2: f64,
    j3: f64,
    j4: f64,
    j5: f64,
    j6: f64,
    k1: f64,
    k2: f64,
    k3: f64,
    k4: f64,
    /// `1/(R(R + d̃))`.
    d11: f64,
}

impl PartBIntegrals {
    fn new(c: &Corner, k: &DipConsts) -> Self {
        let (sd, cd) = (k.sd, k.cd);
        let Corner {
            xi,
            et,
            q,
            xi2,
            q2,
            r,
            y,
            d,
            ale,
            y11,
            ..
        } = *c;
        let rd = r + d;
        let d11 = 1.0 / (r * rd);
        let j2 = xi * y / rd * d11;
        let j5 = -(d + y * y / rd) * d11;
        let (i3, i4, k1, k3, j3, j6);
        if cd != 0.0 {
            let cdcd = cd * cd;
            let sdcd = sd * cd;
            i4 = if xi == 0.0 {
                0.0
            } else {
                let x = (xi2 + q2).sqrt();
                (xi / rd * sdcd
                    + 2.0 * ((et * (x + q * cd) + x * (r + x) * sd) / (xi * (r + x) * cd)).atan())
                    / cdcd
            };
            i3 = (y * cd / rd - ale + sd * rd.ln()) / cdcd;
            k1 = xi * (d11 - y11 * sd) / cd;
            k3 = (q * y11 - y * d11) / cd;
            j3 = (k1 - j2 * sd) / cd;
            j6 = (k3 - j5 * sd) / cd;
        } else {
            let rd2 = rd * rd;
            i3 = 0.5 * (et / rd + y * q / rd2 - ale);
            i4 = 0.5 * xi * y / rd2;
            k1 = xi * q / rd * d11;
            k3 = sd / rd * (xi2 * d11 - 1.0);
            j3 = -xi / rd2 * (q2 * d11 - 0.5);
            j6 = -y / rd2 * (xi2 * d11 - 0.5);
        }
        let xy = xi * y11;
        Self {
            i1: -xi / rd * cd - i4 * sd,
            i2: rd.ln() + i3 * sd,
            i3,
            i4,
            j1: j5 * cd - j6 * sd,
            j2,
            j3,
            j4: -xy - j2 * cd + j3 * sd,
            j5,
            j6,
            k1,
            k2: 1.0 / r + k3 * sd,
            k3,
            k4: xy * cd - k1 * sd,
            d11,
        }
    }
}

/// Part B.
pub(crate) fn part_b(c: &Corner, k: &DipConsts) -> Part {
    let a3 = k.alp3;
    let (sd, cd) = (k.sd, k.cd);
    let (sdsd, sdcd) = (sd * sd, sd * cd);
    let Corner {
        xi,
        et,
        q,
        xi2,
        q2,
        r,
        r3,
        y,
        d,
        tt,
        x11,
        y11,
        y32,
        ey,
        ez,
        fy,
        fz,
        gy,
        gz,
        hy,
        hz,
        ..
    } = *c;
    let PartBIntegrals {
        i1,
        i2,
        i3,
        i4,
        j1,
        j2,
        j3,
        j4,
        j5,
        j6,
        k1,
        k2,
        k3,
        k4,
        d11,
    } = PartBIntegrals::new(c, k);
    let rd = r + d;
    let xy = xi * y11;
    let qx = q * x11;
    let qy = q * y11;
    let strike = [
        -xi * qy - tt - a3 * i1 * sd,
        -q / r + a3 * y / rd * sd,
        q * qy - a3 * i2 * sd,
        xi2 * q * y32 - a3 * j1 * sd,
        xi * q / r3 - a3 * j2 * sd,
        -xi * q2 * y32 - a3 * j3 * sd,
        -xi * fy - d * x11 + a3 * (xy + j4) * sd,
        -ey + a3 * (1.0 / r + j5) * sd,
        q * fy - a3 * (qy - j6) * sd,
        -xi * fz - y * x11 + a3 * k1 * sd,
        -ez + a3 * y * d11 * sd,
        q * fz + a3 * k2 * sd,
    ];
    let dip = [
        -q / r + a3 * i3 * sdcd,
        -et * qx - tt - a3 * xi / rd * sdcd,
        q * qx + a3 * i4 * sdcd,
        xi * q / r3 + a3 * j4 * sdcd,
        et * q / r3 + qy + a3 * j5 * sdcd,
        -q2 / r3 + a3 * j6 * sdcd,
        -ey + a3 * j1 * sdcd,
        -et * gy - xy * sd + a3 * j2 * sdcd,
        q * gy + a3 * j3 * sdcd,
        -ez - a3 * k3 * sdcd,
        -et * gz - xy * cd - a3 * xi * d11 * sdcd,
        q * gz - a3 * k4 * sdcd,
    ];
    let tensile = [
        q * qy - a3 * i3 * sdsd,
        q * qx + a3 * xi / rd * sdsd,
        et * qx + xi * qy - tt - a3 * i4 * sdsd,
        -xi * q2 * y32 - a3 * j4 * sdsd,
        -q2 / r3 - a3 * j5 * sdsd,
        q * q2 * y32 - a3 * j6 * sdsd,
        q * fy - a3 * j1 * sdsd,
        q * gy - a3 * j2 * sdsd,
        -q * hy - a3 * j3 * sdsd,
        q * fz + a3 * k3 * sdsd,
        q * gz + a3 * xi * d11 * sdsd,
        -q * hz + a3 * k4 * sdsd,
    ];
    scaled([strike, dip, tensile])
}

/// Part C, at the observation depth `z ≤ 0`.
pub(crate) fn part_c(c: &Corner, k: &DipConsts, z: f64) -> Part {
    let (a4, a5) = (k.alp4, k.alp5);
    let (sd, cd) = (k.sd, k.cd);
    let (sdsd, cdcd, sdcd) = (sd * sd, cd * cd, sd * cd);
    let Corner {
        xi,
        et,
        q,
        xi2,
        et2,
        q2,
        r,
        r2,
        r3,
        r5,
        y,
        d,
        x11,
        y11,
        x32,
        y32,
        ..
    } = *c;
    let cc = d + z;
    let x53 = (8.0 * r2 + 9.0 * r * xi + 3.0 * xi2) * x11 * x11 * x11 / r2;
    let y53 = (8.0 * r2 + 9.0 * r * et + 3.0 * et2) * y11 * y11 * y11 / r2;
    let h = q * cd - z;
    let z32 = sd / r3 - h * y32;
    let z53 = 3.0 * sd / r5 - h * y53;
    let y0 = y11 - xi2 * y32;
    let z0 = z32 - xi2 * z53;
    let ppy = cd / r3 + q * y32 * sd;
    let ppz = sd / r3 - q * y32 * cd;
    let qq = z * y32 + z32 + z0;
    let qqy = 3.0 * cc * d / r5 - qq * sd;
    let qqz = 3.0 * cc * y / r5 - qq * cd + q * y32;
    let xy = xi * y11;
    let qy = q * y11;
    let qr = 3.0 * q / r5;
    let cdr = (cc + d) / r3;
    let yy0 = y / r3 - y0 * cd;
    let strike = [
        a4 * xy * cd - a5 * xi * q * z32,
        a4 * (cd / r + 2.0 * qy * sd) - a5 * cc * q / r3,
        a4 * qy * cd - a5 * (cc * et / r3 - z * y11 + xi2 * z32),
        a4 * y0 * cd - a5 * q * z0,
        -a4 * xi * (cd / r3 + 2.0 * q * y32 * sd) + a5 * cc * xi * qr,
        -a4 * xi * q * y32 * cd + a5 * xi * (3.0 * cc * et / r5 - qq),
        -a4 * xi * ppy * cd - a5 * xi * qqy,
        a4 * 2.0 * (d / r3 - y0 * sd) * sd - y / r3 * cd - a5 * (cdr * sd - et / r3 - cc * y * qr),
        -a4 * q / r3 + yy0 * sd + a5 * (cdr * cd + cc * d * qr - (y0 * cd + q * z0) * sd),
        a4 * xi * ppz * cd - a5 * xi * qqz,
        a4 * 2.0 * (y / r3 - y0 * cd) * sd + d / r3 * cd - a5 * (cdr * cd + cc * d * qr),
        yy0 * cd - a5 * (cdr * sd - cc * y * qr - y0 * sdsd + q * z0 * cd),
    ];
    let dip = [
        a4 * cd / r - qy * sd - a5 * cc * q / r3,
        a4 * y * x11 - a5 * cc * et * q * x32,
        -d * x11 - xy * sd - a5 * cc * (x11 - q2 * x32),
        -a4 * xi / r3 * cd + a5 * cc * xi * qr + xi * q * y32 * sd,
        -a4 * y / r3 + a5 * cc * et * qr,
        d / r3 - y0 * sd + a5 * cc / r3 * (1.0 - 3.0 * q2 / r2),
        -a4 * et / r3 + y0 * sdsd - a5 * (cdr * sd - cc * y * qr),
        a4 * (x11 - y * y * x32) - a5 * cc * ((d + 2.0 * q * cd) * x32 - y * et * q * x53),
        xi * ppy * sd + y * d * x32 + a5 * cc * ((y + 2.0 * q * sd) * x32 - y * q2 * x53),
        -q / r3 + y0 * sdcd - a5 * (cdr * cd + cc * d * qr),
        a4 * y * d * x32 - a5 * cc * ((y - 2.0 * q * sd) * x32 + d * et * q * x53),
        -xi * ppz * sd + x11 - d * d * x32 - a5 * cc * ((d - 2.0 * q * cd) * x32 - d * q2 * x53),
    ];
    let tensile = [
        -a4 * (sd / r + qy * cd) - a5 * (z * y11 - q2 * z32),
        a4 * 2.0 * xy * sd + d * x11 - a5 * cc * (x11 - q2 * x32),
        a4 * (y * x11 + xy * cd) + a5 * q * (cc * et * x32 + xi * z32),
        a4 * xi / r3 * sd + xi * q * y32 * cd + a5 * xi * (3.0 * cc * et / r5 - 2.0 * z32 - z0),
        a4 * 2.0 * y0 * sd - d / r3 + a5 * cc / r3 * (1.0 - 3.0 * q2 / r2),
        -a4 * yy0 - a5 * (cc * et * qr - q * z0),
        a4 * (q / r3 + y0 * sdcd) + a5 * (z / r3 * cd + cc * d * qr - q * z0 * sd),
        -a4 * 2.0 * xi * ppy * sd - y * d * x32
            + a5 * cc * ((y + 2.0 * q * sd) * x32 - y * q2 * x53),
        -a4 * (xi * ppy * cd - x11 + y * y * x32)
            + a5 * (cc * ((d + 2.0 * q * cd) * x32 - y * et * q * x53) + xi * qqy),
        -et / r3 + y0 * cdcd - a5 * (z / r3 * sd - cc * y * qr - y0 * sdsd + q * z0 * cd),
        a4 * 2.0 * xi * ppz * sd - x11 + d * d * x32
            - a5 * cc * ((d - 2.0 * q * cd) * x32 - d * q2 * x53),
        a4 * (xi * ppz * cd + y * d * x32)
            + a5 * (cc * ((y - 2.0 * q * sd) * x32 + d * et * q * x53) + xi * qqz),
    ];
    scaled([strike, dip, tensile])
}
