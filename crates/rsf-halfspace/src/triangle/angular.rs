//! The angular dislocation: a semi-infinite wedge of constant Burgers vector bounded by two
//! half-lines, in a full space (Comninou & Dundurs 1975, in the form of Nikkhoo & Walter
//! 2015, Appendix A, the "incomplete" displacements without the Burgers function) and the
//! harmonic function that, with an image, frees the surface of a half-space (Nikkhoo &
//! Walter 2015, Appendix B, from Comninou & Dundurs 1975 with their corrections). Each
//! function gives the response to the three unit Burgers vector components at once, in
//! the angular dislocation's own coordinate system (ADCS): `out[b][i]` is displacement
//! component `i` for a unit component `b` (docs/halfspace.md §6).

use crate::dual::Real;

/// Displacement (ADCS) of an angular dislocation of angle `alpha` (rad) in a full space
/// at `(x, y, z)`, without the Burgers function: `out[b][i]`, `b` the Burgers vector's
/// component. Nikkhoo & Walter (2015), eqs. A1–A3 ("AngDisDisp").
pub(super) fn full_space<T: Real>(x: T, y: T, z: T, alpha: f64, nu: f64) -> [[T; 3]; 3] {
    let (sin_a, cos_a) = alpha.sin_cos();
    let eta = y * cos_a - z * sin_a;
    let mut zeta = y * sin_a + z * cos_a;
    let r = (x * x + y * y + z * z).sqrt();
    // ζ ≤ r and z ≤ r hold exactly; round-off must not make the logarithms complex.
    if zeta.value() > r.value() {
        zeta = r;
    }
    let z = if z.value() > r.value() { r } else { z };
    let k = 1.0 / (8.0 * std::f64::consts::PI * (1.0 - nu));
    let nu2 = 1.0 - 2.0 * nu;
    let rz = r - z;
    let rzeta = r - zeta;
    let r_rz = r * rz;
    let r_rzeta = r * rzeta;
    let (ln_rz, ln_rzeta) = (rz.ln(), rzeta.ln());
    let x2 = x * x;
    let bx = [
        (x * y / r_rz - x * eta / r_rzeta) * k,
        (eta * sin_a / rzeta - y * eta / r_rzeta + y * y / r_rz + (ln_rzeta * cos_a - ln_rz) * nu2)
            * k,
        (eta * cos_a / rzeta - y / r - eta * z / r_rzeta - ln_rzeta * (nu2 * sin_a)) * k,
    ];
    let by = [
        (x2 * cos_a / r_rzeta - x2 / r_rz - (ln_rzeta * cos_a - ln_rz) * nu2) * k,
        x * (y * cos_a / r_rzeta - T::cst(sin_a * cos_a) / rzeta - y / r_rz) * k,
        x * (z * cos_a / r_rzeta - T::cst(cos_a * cos_a) / rzeta + r.recip()) * k,
    ];
    let bz = [
        (ln_rzeta * nu2 - x2 / r_rzeta) * (k * sin_a),
        x * (T::cst(sin_a) / rzeta - y / r_rzeta) * (k * sin_a),
        x * (T::cst(cos_a) / rzeta - z / r_rzeta) * (k * sin_a),
    ];
    [bx, by, bz]
}

/// The harmonic function of an angular dislocation of angle `beta` (rad) whose vertex is
/// at depth `a` (m, positive) below a free surface, at `(y1, y2, y3)` (ADCS: `y3` down):
/// `out[b][i]`. Nikkhoo & Walter (2015), Appendix B ("AngDisDispFSC"); the products
/// `cot β · (…/cos β)` are written `…/sin β`, finite where `cos β` vanishes (a horizontal
/// side).
pub(super) fn surface_correction<T: Real>(y: [T; 3], beta: f64, nu: f64, a: f64) -> [[T; 3]; 3] {
    let [y1, y2, y3] = y;
    let (sin_b, cos_b) = beta.sin_cos();
    let cot_b = cos_b / sin_b;
    let cot_half = 1.0 / (0.5 * beta).tan();
    let (nu1, nu2) = (1.0 - nu, 1.0 - 2.0 * nu);
    let k = 1.0 / (4.0 * std::f64::consts::PI * nu1);
    let y3b = y3 + 2.0 * a;
    let z1b = y1 * cos_b + y3b * sin_b;
    let z3b = y3b * cos_b - y1 * sin_b;
    let rb = (y1 * y1 + y2 * y2 + y3b * y3b).sqrt();
    let fib = (-y2).atan_ratio(y1 - (rb + y3b) * cot_half) * 2.0;
    let ry = rb + y3b;
    let rz = rb + z3b;
    let ya = y3b - a;
    let ar = T::cst(a) / rb;
    let rb2 = rb * rb;
    let rb3 = rb2 * rb;
    let (ln_ry, ln_rz) = (ry.ln(), rz.ln());
    let rcos = rb * cos_b + y3b;
    let rsin = rb * sin_b - y1;
    let (c2, cot2) = (cos_b * cos_b, cot_b * cot_b);
    let (y1s, y2s) = (y1 * y1, y2 * y2);
    let cos_ar = ar + cos_b;
    // cot β (1 + a/(r̄ cos β)).
    let cot_plus = ar / sin_b + cot_b;

    let v1b1 = fib * (-2.0 * nu1 * nu2 * cot2)
        + y2 / ry * ((-ar + nu2) * cot_b - y1 / ry * (ar + nu)) * nu2
        + y2 * cos_ar / rz * (nu2 * cos_b * cot_b)
        + y2 * ya / rb3 * (a * cot_b)
        + y2 * ya / (rb * ry) * (y1 / ry * (ar + 2.0 * nu) + y1 * a / rb2 - nu2 * cot_b)
        + y2 * ya / (rb * rz)
            * (T::cst(cos_b) / rz
                * (rcos * (-ar + nu2 * cos_b) * cot_b + rsin * (2.0 * nu1 * cos_b))
                - y3b / rb2 * (a * cos_b * cot_b));
    let v2b1 = (ln_ry * (2.0 * nu1 * cot2 - nu) - ln_rz * ((2.0 * nu1 * cot2 + nu2) * cos_b)) * nu2
        - (y1 * cot_b * (-ar + nu2) + y3b * nu - a + y2s / ry * (ar + nu)) / ry * nu2
        - z1b * cos_ar / rz * (nu2 * cot_b)
        - y1 * ya / rb3 * (a * cot_b)
        + ya / ry
            * ((y1 * (nu2 * cot_b) - a) / rb - 2.0 * nu
                + y2s / (rb * ry) * (ar + 2.0 * nu)
                + y2s / rb3 * a)
        + ya / rz
            * (T::cst(c2) - (z1b * (nu2 * cot_b) + a * cos_b) / rb + y3b * z1b / rb3 * (a * cot_b)
                - (y2s * c2 - z1b * (a * cot_b) / rb * rcos) / (rb * rz));
    let v3b1 = (fib * (nu2 * cot_b) + y2 / ry * (ar + 2.0 * nu) - y2 * cos_ar / rz * cos_b)
        * (2.0 * nu1)
        + y2 * ya / rb * (T::cst(2.0 * nu) / ry + T::cst(a) / rb2)
        + y2 * ya / (rb * rz) * (T::cst(nu2) - rcos / rz * cos_ar - y3b / rb2 * a) * cos_b;

    let v1b2 = (ln_ry * (2.0 * nu1 * cot2 + nu) - ln_rz * ((2.0 * nu1 * cot2 + 1.0) * cos_b)) * nu2
        + (y1 * (-nu2 * cot_b) + y3b * nu - a + y1 / rb * (a * cot_b) + y1s / ry * (ar + nu)) / ry
            * nu2
        - (z1b * (cos_b * cot_b) - rsin / rb * (a / sin_b)) / rz * nu2
        - y1 * ya / rb3 * (a * cot_b)
        + ya / ry
            * ((y1 * (nu2 * cot_b) + a) / rb + 2.0 * nu
                - y1s / (rb * ry) * (ar + 2.0 * nu)
                - y1s / rb3 * a)
        + ya / rz
            * (y1 * y3b / rb3 * (a / sin_b) - c2
                + rsin / rb * (T::cst(2.0 * nu1 * cos_b * cot_b) - rcos / rz * cot_plus));
    let v2b2 = fib * (2.0 * nu1 * nu2 * cot2)
        + y2 / ry * ((ar - nu2) * cot_b + y1 / ry * (ar + nu)) * nu2
        - y2 / rz * cot_plus * nu2
        - y2 * ya / rb3 * (a * cot_b)
        + y2 * ya / (rb * ry)
            * (T::cst(nu2 * cot_b)
                - y1 / ry * (2.0 * nu)
                - y1 * a / rb * (rb.recip() + ry.recip()))
        + y2 * ya / (rb * rz)
            * (rcos / rz * cot_plus + y3b / rb2 * (a / sin_b) - 2.0 * nu1 * cos_b * cot_b);
    let v3b2 = (ln_ry - ln_rz * cos_b) * (-2.0 * nu1 * nu2 * cot_b)
        - y1 / ry * (ar + 2.0 * nu) * (2.0 * nu1)
        + z1b / rz * cos_ar * (2.0 * nu1)
        + ya / rb * (T::cst(nu2 * cot_b) - y1 / ry * (2.0 * nu) - y1 / rb2 * a)
        - ya / rz
            * (rcos * cot_b / rb * (T::cst(2.0 * nu1 * cos_b) - rcos / rz)
                + ar * (T::cst(sin_b) - y3b * z1b / rb2 - z1b * rcos / (rb * rz))
                + sin_b * cos_b);

    let v1b3 = (y2 / ry * (ar + 1.0) - y2 * cos_ar / rz * cos_b) * nu2
        - y2 * ya / rb * (T::cst(a) / rb2 + ry.recip())
        + y2 * ya / (rb * rz) * (rcos / rz * cos_ar + y3b / rb2 * a) * cos_b;
    let v2b3 = (ln_rz * (-sin_b) - y1 / ry * (ar + 1.0) + z1b / rz * cos_ar) * nu2
        + y1 * ya / rb * (T::cst(a) / rb2 + ry.recip())
        - ya / rz
            * ((-ar + cos_b) * sin_b + z1b / rb * (y3b / rb2 * a + 1.0)
                - (y2s * (cos_b * sin_b) - z1b * a / rb * rcos) / (rb * rz));
    let v3b3 = fib * (2.0 * nu1)
        + y2 * cos_ar / rz * (2.0 * nu1 * sin_b)
        + y2 * ya / (rb * rz) * (rcos / rz * cos_ar + y3b / rb2 * a + 1.0) * sin_b;

    [[v1b1, v2b1, v3b1], [v1b2, v2b2, v3b2], [v1b3, v2b3, v3b3]].map(|row| row.map(|v| v * k))
}
