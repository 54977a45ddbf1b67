//! The exponential integral `E₁(x) = ∫₁^∞ e^{−xs}/s ds` (Abramowitz & Stegun 5.1.1) for
//! the closed forms of an injection on an unbounded fault surface (docs/pore-pressure.md).

/// Euler's constant γ.
const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;

/// `Ein(x) = ∫₀ˣ (1 − e^{−s})/s ds = Σ_{k≥1} (−1)^{k+1} xᵏ/(k·k!)` (A&S 5.1.11, 5.1.39),
/// for `0 ≤ x ≤ 1`: `E₁(x) = −γ − ln x + Ein(x)`. The series' terms fall below 1e-17 of
/// its value within 20 terms.
fn ein(x: f64) -> f64 {
    let (mut sum, mut term) = (0.0, 1.0);
    for k in 1..=30 {
        let k = k as f64;
        term *= -x / k;
        let add = -term / k;
        sum += add;
        if add.abs() <= 1e-17 * sum.abs() {
            break;
        }
    }
    sum
}

/// `E₁(x)` for `x > 0` (`+∞` at 0, NaN below): the series `−γ − ln x + Ein(x)` up to
/// `x = 1`, above it the continued fraction `e^{−x}/(x + 1 − 1²/(x + 3 − 2²/(x + 5 − …)))`
/// (A&S 5.1.22) by the modified Lentz method, to a relative 1e-15 (as Numerical Recipes'
/// `expint`). `0` where `e^{−x}` underflows.
pub(crate) fn exp_integral_e1(x: f64) -> f64 {
    if x.is_nan() || x < 0.0 {
        return f64::NAN;
    }
    if x == 0.0 {
        return f64::INFINITY;
    }
    if x <= 1.0 {
        return -EULER_GAMMA - x.ln() + ein(x);
    }
    if x > 750.0 {
        return 0.0;
    }
    let tiny = 1e-300;
    let mut b = x + 1.0;
    let mut c = 1.0 / tiny;
    let mut d = 1.0 / b;
    let mut h = d;
    for i in 1..=200 {
        let a = -((i * i) as f64);
        b += 2.0;
        d = 1.0 / (a * d + b);
        c = b + a / c;
        let del = c * d;
        h *= del;
        if (del - 1.0).abs() <= 1e-16 {
            break;
        }
    }
    h * (-x).exp()
}

/// `E₁(a) − E₁(b)` for `0 < a ≤ b`, as `ln(b/a) + Ein(a) − Ein(b)` where both are at most 1
/// (no cancellation of the two logarithms near 0).
pub(crate) fn exp_integral_e1_difference(a: f64, b: f64) -> f64 {
    if b <= 1.0 && a > 0.0 {
        (b / a).ln() + ein(a) - ein(b)
    } else {
        exp_integral_e1(a) - exp_integral_e1(b)
    }
}
