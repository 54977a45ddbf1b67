//! Exact line search for the convex function `s ↦ J(v + s c)`.

use rsf_nonsmooth::BlockNonlinearity;
use rsf_ranks::block::load;

/// One-sided derivatives `(ψ'⁻(s), ψ'⁺(s))` of `ψ(s) = J(v + s c)` where
/// `ψ(s) = ψ(0) + s g0 + ½ s² h + Σ_k φ_k(v_k + s c_k)`.
fn derivatives<const D: usize, N: BlockNonlinearity<D>>(
    nl: &N,
    v: &[f64],
    c: &[f64],
    g0: f64,
    h: f64,
    s: f64,
) -> (f64, f64) {
    let mut lo = g0 + s * h;
    let mut hi = lo;
    for (k, &p) in nl.active_blocks().iter().enumerate() {
        let d = load::<D>(c, p);
        if d.iter().all(|&x| x == 0.0) {
            continue;
        }
        let mut x = load::<D>(v, p);
        for i in 0..D {
            x[i] += s * d[i];
        }
        let (dl, dr) = nl.directional_derivatives(k, &x, &d);
        lo += dl;
        hi += dr;
    }
    (lo, hi)
}

/// Minimises the convex function `ψ(s) = J(v + s c)` over `s ≥ 0`, given
/// `g0 = cᵀ(Av − b)` and `h = cᵀAc > 0`. Uses bracketing plus the Illinois variant of
/// regula falsi on the (monotone) derivative, with bisection as a safeguard; ends when the
/// subdifferential contains 0 or the bracket is below `1e-13` relative width.
/// Returns the step `s` (0 if `c` is not a descent direction).
pub(crate) fn exact_line_search<const D: usize, N: BlockNonlinearity<D>>(
    nl: &N,
    v: &[f64],
    c: &[f64],
    g0: f64,
    h: f64,
) -> f64 {
    let (_, d0) = derivatives(nl, v, c, g0, h, 0.0);
    if !(d0 < 0.0) {
        return 0.0;
    }
    // Bracket: find s_hi with ψ'⁺(s_hi) ≥ 0 (ψ is coercive along c because h > 0).
    let (mut s_lo, mut f_lo) = (0.0, d0);
    let mut s_hi = 1.0;
    let mut f_hi;
    let mut expansions = 0;
    loop {
        let (dl, dr) = derivatives(nl, v, c, g0, h, s_hi);
        if dl <= 0.0 && dr >= 0.0 {
            return s_hi;
        }
        if dl > 0.0 {
            f_hi = dl;
            break;
        }
        s_lo = s_hi;
        f_lo = dr;
        s_hi *= 4.0;
        expansions += 1;
        if expansions > 200 || !s_hi.is_finite() {
            return s_lo;
        }
    }
    // Illinois regula falsi on the monotone derivative, with bisection safeguard.
    let mut side = 0i8;
    for it in 0..200 {
        let width = s_hi - s_lo;
        if width <= 1e-13 * s_hi {
            break;
        }
        let mut s = if it % 4 == 3 || !(f_hi - f_lo).is_finite() {
            0.5 * (s_lo + s_hi)
        } else {
            s_lo - f_lo * (s_hi - s_lo) / (f_hi - f_lo)
        };
        if !(s > s_lo && s < s_hi) {
            s = 0.5 * (s_lo + s_hi);
        }
        let (dl, dr) = derivatives(nl, v, c, g0, h, s);
        if dl <= 0.0 && dr >= 0.0 {
            return s;
        }
        if dr < 0.0 {
            s_lo = s;
            f_lo = dr;
            if side == -1 {
                f_hi *= 0.5;
            }
            side = -1;
        } else {
            s_hi = s;
            f_hi = dl;
            if side == 1 {
                f_lo *= 0.5;
            }
            side = 1;
        }
    }
    0.5 * (s_lo + s_hi)
}
