//! The constants of Okada's formulas: those of the medium and the dip (DC3D's `DCCON0`)
//! and those of one corner of the rectangle seen from the observation point (`DCCON2`),
//! in the notation of Okada (1992), §3 (docs/halfspace.md §2).

/// Medium and dip constants.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DipConsts {
    /// `(1 − α)/2`.
    pub alp1: f64,
    /// `α/2`.
    pub alp2: f64,
    /// `(1 − α)/α`.
    pub alp3: f64,
    /// `1 − α`.
    pub alp4: f64,
    /// `α`.
    pub alp5: f64,
    /// `sin δ` (±1 when `|cos δ|` is below [`COS_ZERO`]).
    pub sd: f64,
    /// `cos δ` (exactly 0 when `|cos δ|` is below [`COS_ZERO`]).
    pub cd: f64,
}

/// Below this `|cos δ|` the fault is taken as vertical, `cos δ = 0` exactly, and the
/// vertical-fault forms of the part-B integrals are used (as DC3D does).
pub(crate) const COS_ZERO: f64 = 1e-6;

impl DipConsts {
    /// For `α = (λ + μ)/(λ + 2μ)` and the dip in degrees.
    pub fn new(alpha: f64, dip_deg: f64) -> Self {
        let (mut sd, mut cd) = dip_deg.to_radians().sin_cos();
        if cd.abs() < COS_ZERO {
            cd = 0.0;
            if sd > 0.0 {
                sd = 1.0;
            } else if sd < 0.0 {
                sd = -1.0;
            }
        }
        Self {
            alp1: 0.5 * (1.0 - alpha),
            alp2: 0.5 * alpha,
            alp3: (1.0 - alpha) / alpha,
            alp4: 1.0 - alpha,
            alp5: alpha,
            sd,
            cd,
        }
    }
}

/// `R + a` for `R = √(a² + b2)`, without the cancellation of `R + a` for `a < 0`:
/// `b2/(R − a)` there (the same number in exact arithmetic). Near the negative extension
/// of an edge (`b2 ≪ a²`) the plain sum loses `log₁₀(a²/b2)` digits, which the corner
/// sums then amplify; DC3D uses the plain sum.
fn sum_with_r(r: f64, a: f64, b2: f64) -> f64 {
    if a < 0.0 {
        b2 / (r - a)
    } else {
        r + a
    }
}

/// Okada's `(ln(R + a), 1/(R (R + a)), (2R + a)/(R³ (R + a)²))` for a corner coordinate `a`
/// (`ξ`: `ALX, X11, X32`; `η`: `ALE, Y11, Y32`) with `b2` the sum of the other two
/// squares, `R + a` by [`sum_with_r`]; `(−ln(R − a), 0, 0)` where `R + a` vanishes
/// (`r_plus_a_zero`, [`Corner::new`]).
fn log_terms(r: f64, a: f64, b2: f64, r_plus_a_zero: bool) -> (f64, f64, f64) {
    if r_plus_a_zero {
        (-(r - a).ln(), 0.0, 0.0)
    } else {
        let ra = sum_with_r(r, a, b2);
        let a11 = 1.0 / (r * ra);
        (ra.ln(), a11, (r + ra) * a11 * a11 / r)
    }
}

/// The quantities of one corner `(ξ, η)` of the rectangle at distance `q` from its plane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Corner {
    pub xi: f64,
    pub et: f64,
    pub q: f64,
    pub xi2: f64,
    pub et2: f64,
    pub q2: f64,
    pub r: f64,
    pub r2: f64,
    pub r3: f64,
    pub r5: f64,
    /// `ỹ = η cos δ + q sin δ`.
    pub y: f64,
    /// `d̃ = η sin δ − q cos δ`.
    pub d: f64,
    /// `θ = atan(ξη/(qR))` (0 for `q = 0`).
    pub tt: f64,
    /// `ln(R + ξ)`.
    pub alx: f64,
    /// `ln(R + η)`.
    pub ale: f64,
    /// `X11 = 1/(R(R + ξ))`.
    pub x11: f64,
    /// `Y11 = 1/(R(R + η))`.
    pub y11: f64,
    /// `X32 = (2R + ξ)/(R³(R + ξ)²)`.
    pub x32: f64,
    /// `Y32 = (2R + η)/(R³(R + η)²)`.
    pub y32: f64,
    pub ey: f64,
    pub ez: f64,
    pub fy: f64,
    pub fz: f64,
    pub gy: f64,
    pub gz: f64,
    pub hy: f64,
    pub hz: f64,
}

impl Corner {
    /// The corner `(ξ, η, q)`; `r_plus_xi_zero`, `r_plus_eta_zero` say that `R + ξ`,
    /// resp. `R + η`, vanishes (the point is on the negative extension of an edge), where
    /// the logarithm is replaced by `−ln(R − ξ)` and `X11`, `X32` (resp. `Y11`, `Y32`) by
    /// 0: the singular parts cancel in the sum over the corners (Okada 1992, §3, the
    /// remarks on the singular cases). `None` if `R = 0` (the point is the corner).
    #[expect(
        clippy::too_many_arguments,
        reason = "Okada's (1992) variables of one corner, as his DC3D passes them"
    )]
    pub(crate) fn new(
        xi: f64,
        et: f64,
        q: f64,
        k: &DipConsts,
        r_plus_xi_zero: bool,
        r_plus_eta_zero: bool,
        eps: f64,
    ) -> Option<Self> {
        let snap = |v: f64| if v.abs() < eps { 0.0 } else { v };
        let (xi, et, q) = (snap(xi), snap(et), snap(q));
        let (xi2, et2, q2) = (xi * xi, et * et, q * q);
        let r2 = xi2 + et2 + q2;
        let r = r2.sqrt();
        if !(r > 0.0) {
            return None;
        }
        let r3 = r * r2;
        let r5 = r3 * r2;
        let (sd, cd) = (k.sd, k.cd);
        let y = et * cd + q * sd;
        let d = et * sd - q * cd;
        let tt = if q == 0.0 {
            0.0
        } else {
            (xi * et / (q * r)).atan()
        };
        let (alx, x11, x32) = log_terms(r, xi, et2 + q2, r_plus_xi_zero);
        let (ale, y11, y32) = log_terms(r, et, xi2 + q2, r_plus_eta_zero);
        Some(Self {
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
            tt,
            alx,
            ale,
            x11,
            y11,
            x32,
            y32,
            ey: sd / r - y * q / r3,
            ez: cd / r + d * q / r3,
            fy: d / r3 + xi2 * y32 * sd,
            fz: y / r3 + xi2 * y32 * cd,
            gy: 2.0 * x11 * sd - y * q * x32,
            gz: 2.0 * x11 * cd + d * q * x32,
            hy: d * q * x32 + xi * q * y32 * sd,
            hz: y * q * x32 + xi * q * y32 * cd,
        })
    }
}
