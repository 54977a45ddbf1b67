//! Scalar root finding helpers: the Wright omega function and a safeguarded Newton
//! method for increasing functions.

/// `ln ω(x)`, the logarithm of the Wright omega function `ω(x) = W₀(eˣ)`, i.e. the unique
/// real `y` with `e^y + y = x`.
///
/// Defined for all real `x` (`x = ±∞` give the limits `±∞`); never overflows: for large `x` it is `≈ ln x`, for very
/// negative `x` it is `x − eˣ`. Accurate to a few ulps of `max(1, |y|)` in `y` (so `ω = e^y`
/// is accurate to a few `ε·max(1, |y|)` relative; Newton on
/// `e^y + y − x`, which is convex and increasing in `y`, from an asymptotic start).
/// Returns NaN only for NaN input.
///
/// ```
/// let y = rsf_friction::wright_omega_ln(1.0); // ω(1) = 1
/// assert!(y.abs() < 1e-15);
/// ```
pub fn wright_omega_ln(x: f64) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    if x < -40.0 {
        // ω = eˣ(1 − eˣ + …): y = x − ω to full precision.
        return x - x.exp();
    }
    if x == f64::INFINITY {
        return f64::INFINITY;
    }
    let mut y = if x < -1.0 {
        x - x.exp()
    } else if x <= 1.0 {
        (0.567_143_290_409_783_8 + 0.361_896_256 * x).ln()
    } else {
        let lx = x.ln();
        (x - lx + lx / x).ln()
    };
    for _ in 0..50 {
        let e = y.exp();
        let f = (e - x) + y;
        let dy = f / (e + 1.0);
        y -= dy;
        if dy.abs() <= 2.0 * f64::EPSILON * y.abs().max(1.0) {
            break;
        }
    }
    y
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn omega_identity() {
        for &x in &[
            -1e300, -745.0, -50.0, -30.0, -5.0, -1.0, -0.3, 0.0, 0.5, 1.0, 2.0, 10.0, 700.0, 1e5,
            1e20, 1e300,
        ] {
            let y = wright_omega_ln(x);
            assert!(y.is_finite(), "x = {x}");
            let res = y.exp() + y - x;
            assert!(
                res.abs() <= 4.0 * f64::EPSILON * x.abs().max(1.0) * y.abs().max(1.0),
                "x = {x}, res = {res}"
            );
        }
        assert!((wright_omega_ln(0.0).exp() - 0.567_143_290_409_783_8).abs() < 1e-16);
    }
}
