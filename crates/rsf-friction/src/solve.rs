//! Scalar root finding: a safeguarded Newton method for increasing functions. (The Wright
//! omega function comes from `rsf-state`, which owns it and its tests.)

/// Solves `g(x) = 0` for an increasing function `g` given a bracket `g(lo) ≤ 0 ≤ g(hi)`,
/// by Newton's method safeguarded with bisection (Numerical Recipes `rtsafe` style).
/// `g` returns `(g(x), g'(x))`. Returns the final iterate; never leaves `[lo, hi]`.
pub(crate) fn solve_increasing(
    g: impl Fn(f64) -> (f64, f64),
    mut lo: f64,
    mut hi: f64,
    x0: f64,
) -> f64 {
    if !(lo < hi) {
        return lo.min(hi);
    }
    let mut x = if x0 >= lo && x0 <= hi {
        x0
    } else {
        0.5 * (lo + hi)
    };
    let mut dx_old = hi - lo;
    let (mut f, mut df) = g(x);
    for _ in 0..300 {
        if f == 0.0 {
            return x;
        }
        if f < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let newton = x - f / df;
        if (newton - x).abs() <= 2.0 * f64::EPSILON * x.abs().max(1.0) {
            // Converged: the Newton correction is at rounding level.
            return newton;
        }
        let use_newton = newton.is_finite()
            && newton > lo
            && newton < hi
            && (2.0 * f).abs() <= (dx_old * df).abs();
        let x_new = if use_newton { newton } else { 0.5 * (lo + hi) };
        dx_old = (x_new - x).abs();
        let tol = 2.0 * f64::EPSILON * x_new.abs().max(1.0);
        x = x_new;
        (f, df) = g(x);
        if dx_old <= tol || hi - lo <= tol {
            break;
        }
    }
    x
}
