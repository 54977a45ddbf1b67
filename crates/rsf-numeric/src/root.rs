//! Scalar root finding for increasing functions: Newton's method safeguarded by bisection
//! (the `rtsafe` scheme of Press et al., *Numerical Recipes*, §9.4).

/// An increasing function `g` on a bracket, evaluated by the root finder.
///
/// The finder calls [`slope`](Self::slope) only at the point of its last
/// [`value`](Self::value) call, with that value, so an implementation that computes
/// `g` and `g'` together may return a slope saved by `value`.
pub trait IncreasingFunction {
    /// What an evaluation can fail with ([`std::convert::Infallible`] if it cannot).
    type Error;
    /// `g(x)`.
    ///
    /// # Errors
    /// Whatever the function reports; the finder returns it at once.
    fn value(&mut self, x: f64) -> Result<f64, Self::Error>;
    /// A slope `g'(x) > 0` at the point of the last [`value`](Self::value) call, whose
    /// result `value` was.
    ///
    /// # Errors
    /// As [`value`](Self::value).
    fn slope(&mut self, x: f64, value: f64) -> Result<f64, Self::Error>;
}

/// A bracket `[lo, hi]` of a root of an increasing `g`: `g(lo) ≤ 0 ≤ g(hi)`, `lo < hi`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bracket {
    /// Left end (`g(lo) ≤ 0`).
    pub lo: f64,
    /// Right end (`g(hi) ≥ 0`).
    pub hi: f64,
}

/// Where the iteration starts: a point of the bracket and `g` there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Start {
    /// The first iterate, in the bracket.
    pub x: f64,
    /// `g(x)`.
    pub value: f64,
}

/// When [`safeguarded_newton`] stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stopping {
    /// Converged once a step or the bracket is at most `tolerance · ε · max(1, |x|)`
    /// (`ε` = [`f64::EPSILON`]; 2 to 4 is machine precision).
    pub tolerance: f64,
    /// Number of iterations before giving up.
    pub max_iterations: usize,
}

/// The result of [`safeguarded_newton`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RootOutcome {
    /// The root to the tolerance (or an exact zero of `g`).
    Converged(f64),
    /// [`Stopping::max_iterations`] were done without convergence.
    IterationLimit {
        /// The last iterate.
        last: f64,
        /// The width of the remaining bracket.
        width: f64,
    },
}

/// Solves `g(x) = 0` for an increasing `g` on a [`Bracket`], by Newton's method safeguarded
/// with bisection: a Newton step is taken when it stays inside the bracket and at least
/// halves the step before it, a bisection step otherwise; the bracket shrinks to the
/// iterates' signs. Stops when `g(x) = 0`, when a Newton correction is at rounding level
/// (`≤ 2ε·max(1, |x|)`, returning the corrected point), or when a step or the bracket is
/// within [`Stopping::tolerance`]. Never leaves the bracket (for a finite bracket);
/// deterministic (the same calls in the same order for the same input).
///
/// # Errors
/// The first error of `g`'s [`value`](IncreasingFunction::value) or
/// [`slope`](IncreasingFunction::slope).
pub fn safeguarded_newton<G: IncreasingFunction>(
    g: &mut G,
    bracket: Bracket,
    start: Start,
    stopping: Stopping,
) -> Result<RootOutcome, G::Error> {
    match iterate(g, LowerEnd::Known(bracket.lo), bracket.hi, start, stopping)? {
        Some(outcome) => Ok(outcome),
        None => unreachable!("a known lower end is never asked for"),
    }
}

/// The bracket's left end: known, or known only to lie at or below a floor.
#[derive(Debug, Clone, Copy)]
enum LowerEnd {
    Known(f64),
    AtMost(f64),
}

/// [`safeguarded_newton`]'s iteration, with the left end possibly known only by a floor:
/// then every decision is taken from the floor where the floor decides it (rounding is
/// monotone: `hi − lo ≥ hi − floor` and `(hi − lo)·g' ≥ (hi − floor)·g'` in floating point
/// too), and `None` is returned where it does not (the caller forms the left end and
/// solves again). With a known left end the result is always `Some`.
fn iterate<G: IncreasingFunction>(
    g: &mut G,
    mut lo: LowerEnd,
    mut hi: f64,
    start: Start,
    stopping: Stopping,
) -> Result<Option<RootOutcome>, G::Error> {
    let Start {
        mut x,
        value: mut fx,
    } = start;
    // The first step's bound `hi − lo`: exact, or a lower bound of it.
    let (mut dx_old, mut dx_exact) = match lo {
        LowerEnd::Known(lo) => (hi - lo, true),
        LowerEnd::AtMost(floor) => (hi - floor, false),
    };
    for _ in 0..stopping.max_iterations {
        if fx == 0.0 {
            return Ok(Some(RootOutcome::Converged(x)));
        }
        if fx < 0.0 {
            lo = LowerEnd::Known(x);
        } else {
            hi = x;
        }
        let df = g.slope(x, fx)?;
        let newton = x - fx / df;
        if (newton - x).abs() <= 2.0 * f64::EPSILON * x.abs().max(1.0) {
            // Converged: the Newton correction is at rounding level.
            return Ok(Some(RootOutcome::Converged(newton)));
        }
        let halves = (2.0 * fx).abs() <= (dx_old * df).abs();
        if !halves && !dx_exact {
            return Ok(None);
        }
        let above_lo = match lo {
            LowerEnd::Known(lo) => newton > lo,
            LowerEnd::AtMost(floor) if newton > floor => true,
            LowerEnd::AtMost(_) => return Ok(None),
        };
        let accept = newton.is_finite() && above_lo && newton < hi && halves;
        let x_new = if accept {
            newton
        } else {
            match lo {
                LowerEnd::Known(lo) => 0.5 * (lo + hi),
                LowerEnd::AtMost(_) => return Ok(None),
            }
        };
        dx_old = (x_new - x).abs();
        dx_exact = true;
        x = x_new;
        fx = g.value(x)?;
        let tol = stopping.tolerance * f64::EPSILON * x.abs().max(1.0);
        let narrow = match lo {
            LowerEnd::Known(lo) => hi - lo <= tol,
            LowerEnd::AtMost(floor) if hi - floor > tol => false,
            LowerEnd::AtMost(_) => return Ok(None),
        };
        if dx_old <= tol || narrow {
            return Ok(Some(RootOutcome::Converged(x)));
        }
    }
    Ok(match lo {
        LowerEnd::Known(lo) => Some(RootOutcome::IterationLimit {
            last: x,
            width: hi - lo,
        }),
        LowerEnd::AtMost(_) => None,
    })
}

/// `g` given as one closure returning `(g(x), g'(x))`; the slope of the last evaluation is
/// kept for [`IncreasingFunction::slope`].
struct ValueAndSlope<F> {
    g: F,
    slope: f64,
}

impl<F: Fn(f64) -> (f64, f64)> IncreasingFunction for ValueAndSlope<F> {
    type Error = std::convert::Infallible;
    fn value(&mut self, x: f64) -> Result<f64, Self::Error> {
        let (value, slope) = (self.g)(x);
        self.slope = slope;
        Ok(value)
    }
    fn slope(&mut self, _x: f64, _value: f64) -> Result<f64, Self::Error> {
        Ok(self.slope)
    }
}

/// Solves `g(x) = 0` for an increasing `g` with `g(lo) ≤ 0 ≤ g(hi)` by
/// [`safeguarded_newton`] (tolerance `2ε·max(1, |x|)`, at most 300 iterations), starting at
/// `x0` if it lies in `[lo, hi]` and at the midpoint otherwise. `g` returns
/// `(g(x), g'(x))`. Returns the final iterate (the last one if 300 iterations did not
/// converge); never leaves `[lo, hi]`; returns `min(lo, hi)` if `lo < hi` fails (an
/// empty or NaN bracket).
///
/// ```
/// // √2 as the root of x² − 2 on [0, 2].
/// let x = rsf_numeric::solve_increasing(|x| (x * x - 2.0, 2.0 * x), 0.0, 2.0, 1.0);
/// assert!((x - 2f64.sqrt()).abs() <= 2.0 * f64::EPSILON);
/// ```
pub fn solve_increasing(g: impl Fn(f64) -> (f64, f64), lo: f64, hi: f64, x0: f64) -> f64 {
    if !(lo < hi) {
        return lo.min(hi);
    }
    let x = if x0 >= lo && x0 <= hi {
        x0
    } else {
        0.5 * (lo + hi)
    };
    let mut g = ValueAndSlope { g, slope: 0.0 };
    let Ok(value) = g.value(x);
    newton_from(g, lo, hi, x, value)
}

/// [`solve_increasing`] started at a point `x0` of `[lo, hi]` where `g` has already been
/// evaluated: `known = g(x0)` (value and slope, as `g` returns them). The same iterates
/// and result as `solve_increasing(g, lo, hi, x0)` with one evaluation of `g` fewer —
/// for callers that evaluate `g` at the ends of the bracket to choose where to start. If
/// `x0` is not in `[lo, hi]`, `known` is not used and the result is `solve_increasing`'s.
///
/// ```
/// let g = |x: f64| (x * x - 2.0, 2.0 * x);
/// let x = rsf_numeric::solve_increasing_from(g, 0.0, 2.0, 2.0, g(2.0));
/// assert_eq!(x, rsf_numeric::solve_increasing(g, 0.0, 2.0, 2.0));
/// ```
pub fn solve_increasing_from(
    g: impl Fn(f64) -> (f64, f64),
    lo: f64,
    hi: f64,
    x0: f64,
    known: (f64, f64),
) -> f64 {
    if !(lo < hi && x0 >= lo && x0 <= hi) {
        return solve_increasing(g, lo, hi, x0);
    }
    let (value, slope) = known;
    newton_from(ValueAndSlope { g, slope }, lo, hi, x0, value)
}

/// [`safeguarded_newton`] with [`solve_increasing`]'s stopping rule from `x` in the bracket,
/// `value = g(x)` and `g.slope` its slope.
/// [`solve_increasing`]'s stopping rule: `2ε·max(1, |x|)`, at most 300 iterations.
const SOLVE_STOPPING: Stopping = Stopping {
    tolerance: 2.0,
    max_iterations: 300,
};

fn newton_from<F: Fn(f64) -> (f64, f64)>(
    mut g: ValueAndSlope<F>,
    lo: f64,
    hi: f64,
    x: f64,
    value: f64,
) -> f64 {
    match safeguarded_newton(
        &mut g,
        Bracket { lo, hi },
        Start { x, value },
        SOLVE_STOPPING,
    ) {
        Ok(RootOutcome::Converged(x) | RootOutcome::IterationLimit { last: x, .. }) => x,
    }
}

/// [`solve_increasing_from`] started at the bracket's right end `hi` (`known = (g(hi),
/// g'(hi))`), when only a floor of its left end is known (`lo ≤ floor < hi`, `g(lo) ≤ 0`,
/// and `|g(hi)| ≤ |g(lo)|`, so that the full solve would start at `hi` too): the same
/// iterates and the same result, bit for bit, where the floor suffices for every decision
/// of the iteration; `None` where one needs the left end itself (form it, then call
/// [`solve_increasing_from`]). For solves whose left end costs more than the iteration
/// (the friction solves' lower end takes an exponential and a logarithm).
pub fn solve_increasing_from_upper_end(
    g: impl Fn(f64) -> (f64, f64),
    floor: f64,
    hi: f64,
    known: (f64, f64),
) -> Option<f64> {
    if !(floor < hi) {
        return None;
    }
    let (value, slope) = known;
    let mut g = ValueAndSlope { g, slope };
    let start = Start { x: hi, value };
    match iterate(&mut g, LowerEnd::AtMost(floor), hi, start, SOLVE_STOPPING) {
        Ok(Some(RootOutcome::Converged(x) | RootOutcome::IterationLimit { last: x, .. })) => {
            Some(x)
        }
        Ok(None) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_roots_of_smooth_and_kinked_functions() {
        // Smooth: e^x + x − 3 (root by Newton) against a bisection to one ulp.
        let g = |x: f64| (x.exp() + x - 3.0, x.exp() + 1.0);
        let x = solve_increasing(g, -10.0, 10.0, 5.0);
        let (mut lo, mut hi) = (-10.0_f64, 10.0_f64);
        while hi - lo > 4.0 * f64::EPSILON {
            let mid = 0.5 * (lo + hi);
            if g(mid).0 < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        assert!((x - lo).abs() <= 8.0 * f64::EPSILON, "{x} vs {lo}");
        // A jump at 1 (a subdifferential): bisection closes onto the jump.
        let step = |x: f64| (if x < 1.0 { -1.0 } else { 1.0 } + (x - 1.0), 1.0);
        let x = solve_increasing(step, 0.0, 3.0, 0.0);
        assert!((x - 1.0).abs() <= 8.0 * f64::EPSILON, "{x}");
    }

    #[test]
    fn a_known_start_gives_the_same_iterates_with_one_evaluation_fewer() {
        use std::cell::Cell;
        // Increasing functions with a smooth part, a kink and steep exponentials, started at
        // either end of the bracket (as the friction solves do) and inside it.
        type ValueAndSlopeFn = fn(f64) -> (f64, f64);
        let cases: [(ValueAndSlopeFn, f64, f64); 3] = [
            (|x| (x.exp() + x - 3.0, x.exp() + 1.0), -10.0, 10.0),
            (
                |x| (x.sinh() + 0.3 * x.abs() - 0.2, x.cosh() + 0.3),
                -40.0,
                3.0,
            ),
            (
                |x| ((5.0 * x).exp() - 7.0, 5.0 * (5.0 * x).exp()),
                -100.0,
                1.0,
            ),
        ];
        for (f, lo, hi) in cases {
            for x0 in [lo, hi, 0.25 * lo + 0.75 * hi] {
                let count = Cell::new(0_usize);
                let counted = |x: f64| {
                    count.set(count.get() + 1);
                    f(x)
                };
                let plain = solve_increasing(counted, lo, hi, x0);
                let plain_calls = count.replace(0);
                let from = solve_increasing_from(counted, lo, hi, x0, f(x0));
                assert_eq!(plain.to_bits(), from.to_bits(), "x0 = {x0}");
                assert_eq!(count.get() + 1, plain_calls, "x0 = {x0}");
                assert!(f(from).0.abs() <= 1e-12 * f(from).1.max(1.0), "x0 = {x0}");
            }
        }
        // Outside the bracket the known value is not used.
        let g = |x: f64| (x - 0.25, 1.0);
        assert_eq!(
            solve_increasing_from(g, 0.0, 1.0, 7.0, (f64::NAN, f64::NAN)),
            0.25
        );
    }

    #[test]
    fn a_floor_of_the_left_end_gives_the_same_iterates_or_none() {
        // Started at the right end: with a floor far below the root the iteration never
        // needs the left end (Some, the same bits for every left end below the floor); with
        // a floor near the root a decision does (None), never a different number.
        type ValueAndSlopeFn = fn(f64) -> (f64, f64);
        let cases: [(ValueAndSlopeFn, f64); 3] = [
            (|x| (x.exp() + x - 3.0, x.exp() + 1.0), 1.2),
            (|x| (x.sinh() + 0.3 * x - 0.2, x.cosh() + 0.3), 0.5),
            (|x| ((5.0 * x).exp() - 7.0, 5.0 * (5.0 * x).exp()), 0.45),
        ];
        let (mut some, mut none) = (0, 0);
        for (f, hi) in cases {
            for floor in [-50.0, -5.0, -1.0, 0.0, 0.2, 0.35, 0.38] {
                if !(floor < hi) {
                    continue;
                }
                match solve_increasing_from_upper_end(f, floor, hi, f(hi)) {
                    Some(x) => {
                        some += 1;
                        for lo in [floor, floor - 1.0, floor - 30.0] {
                            let full = solve_increasing_from(f, lo, hi, hi, f(hi));
                            assert_eq!(x.to_bits(), full.to_bits(), "{hi} {floor} {lo}");
                        }
                    }
                    None => none += 1,
                }
            }
        }
        assert!(some >= 8 && none >= 1, "{some} {none}");
        assert_eq!(
            solve_increasing_from_upper_end(|x| (x.exp(), x.exp()), 1.0, 1.0, (1.0, 1.0)),
            None
        );
    }

    #[test]
    fn empty_bracket_and_start_outside() {
        assert_eq!(solve_increasing(|x| (x, 1.0), 2.0, 1.0, 0.0), 1.0);
        assert_eq!(
            solve_increasing(|x| (x, 1.0), f64::NAN, 1.0, 0.0).to_bits(),
            1f64.to_bits()
        );
        let x = solve_increasing(|x| (x - 0.25, 1.0), 0.0, 1.0, 7.0);
        assert_eq!(x, 0.25);
    }

    #[test]
    fn reports_the_iteration_limit_and_errors() {
        struct Slow;
        impl IncreasingFunction for Slow {
            type Error = ();
            fn value(&mut self, x: f64) -> Result<f64, ()> {
                Ok(x - 0.3)
            }
            // A far too small slope: every Newton step leaves the bracket, so bisection.
            fn slope(&mut self, _x: f64, _v: f64) -> Result<f64, ()> {
                Ok(1e-300)
            }
        }
        let bracket = Bracket { lo: 0.0, hi: 1.0 };
        let start = Start {
            x: 0.0,
            value: -0.3,
        };
        let few = Stopping {
            tolerance: 2.0,
            max_iterations: 3,
        };
        match safeguarded_newton(&mut Slow, bracket, start, few) {
            Ok(RootOutcome::IterationLimit { width, .. }) => assert_eq!(width, 0.25),
            other => panic!("{other:?}"),
        }
        struct Failing;
        impl IncreasingFunction for Failing {
            type Error = &'static str;
            fn value(&mut self, _x: f64) -> Result<f64, &'static str> {
                Err("no value")
            }
            fn slope(&mut self, _x: f64, _v: f64) -> Result<f64, &'static str> {
                Ok(1.0)
            }
        }
        assert_eq!(
            safeguarded_newton(&mut Failing, bracket, start, few),
            Err("no value")
        );
    }
}
