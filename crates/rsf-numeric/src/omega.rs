//! The Wright omega function `ω(x) = W₀(eˣ)`, overflow-safe for all real `x`.

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
/// let y = rsf_numeric::wright_omega_ln(1.0); // ω(1) = 1
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
    // Starting values (Corless & Jeffrey's regions): the exponential series below −2, the
    // Taylor series at x = 1 in between, the asymptotic expansion above.
    let mut y = if x <= -2.0 {
        let e = x.exp();
        x - e + 0.5 * e * e
    } else if x <= 3.0 {
        let t = x - 1.0;
        let w = 1.0 + t * (0.5 + t * (1.0 / 16.0 + t * (-1.0 / 192.0 + t * (-1.0 / 3072.0))));
        w.max(f64::MIN_POSITIVE).ln()
    } else {
        let lx = x.ln();
        (x - lx + lx / x).ln()
    };
    // Halley's iteration on f(y) = e^y + y − x (convex, increasing): cubic convergence, so
    // once a correction is below 1e-5·max(1, |y|) the remaining error is below an ulp.
    for _ in 0..50 {
        let e = y.exp();
        let f = (e - x) + y;
        let d1 = e + 1.0;
        let dy = 2.0 * f * d1 / (2.0 * d1 * d1 - f * e);
        let dy = if dy.is_finite() { dy } else { f / d1 };
        y -= dy;
        if dy.abs() <= 1e-5 * y.abs().max(1.0) {
            break;
        }
    }
    y
}

/// The Wright omega function `ω(x) = W₀(eˣ)`: the solution `w > 0` of `w + ln w = x`.
///
/// Defined for all real `x` without overflow (`eˣ` is never formed): `ω(x) ≈ eˣ` for very
/// negative `x` (underflows to 0 below about −745), `ω(x) ≈ x − ln x` for large `x`.
/// Relative accuracy a few ulps (a final Newton step on `w + ln w = x` for `x > 1`).
///
/// ```
/// use rsf_numeric::wright_omega;
/// assert!((wright_omega(1.0) - 1.0).abs() < 1e-15);
/// let w = wright_omega(1e6); // W(e^{1e6}) without overflow
/// assert!((w + w.ln() - 1e6).abs() < 1e-9);
/// ```
pub fn wright_omega(x: f64) -> f64 {
    let y = wright_omega_ln(x);
    let w = y.exp();
    if x > 1.0 && w.is_finite() {
        let f = (w - x) + w.ln();
        w - f / (1.0 + 1.0 / w)
    } else {
        w
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_lambert_w_in_the_middle_range() {
        let mut x: f64 = -30.0;
        while x <= 30.0 {
            let reference = lambert_w::lambert_w0(x.exp());
            let w = wright_omega(x);
            assert!(
                (w - reference).abs() <= 4e-15 * reference,
                "x = {x}: {w} vs {reference}"
            );
            x += 0.37;
        }
    }

    #[test]
    fn extreme_arguments() {
        assert_eq!(wright_omega(-1e4), 0.0);
        assert!((wright_omega_ln(-1e4) + 1e4).abs() < 1e-12);
        let w = wright_omega(1e300);
        assert!(w.is_finite() && (w - 1e300).abs() < 1e-12 * 1e300);
        assert!(wright_omega_ln(1e300).is_finite());
        assert!(wright_omega(f64::INFINITY).is_infinite());
    }
}
