//! The loading history: Dirichlet velocities scaled by a dimensionless function of time.

use std::sync::Arc;

use crate::error::{invalid, Result};

/// A dimensionless loading history `g(t)` that scales the prescribed Dirichlet
/// velocities: `v_i(t) = factor_i · g(t)` (see [`DirichletVelocity`]).
#[derive(Clone)]
pub enum TimeFunction {
    /// `g(t) = c` for all t.
    Constant(f64),
    /// The paper's ramp (docs/math.md §6): `g(t) = min(t / duration, 1)`; `duration = 0`
    /// is a step to 1 at t = 0.
    Ramp {
        /// Ramp duration (s), finite and ≥ 0.
        duration: f64,
    },
    /// Linear interpolation between `(t_k, g_k)` (s, dimensionless), constant before the
    /// first and after the last point. Times strictly increasing, values finite.
    PiecewiseLinear(Vec<(f64, f64)>),
    /// Any function of time (s). It must return finite values; a non-finite value makes
    /// the step fail (the velocity problem gets non-finite data).
    Custom(Arc<dyn Fn(f64) -> f64 + Send + Sync>),
}

impl TimeFunction {
    /// `g(t) = min(t / duration, 1)`.
    pub fn ramp(duration: f64) -> Self {
        TimeFunction::Ramp { duration }
    }

    /// A user function of time (s).
    pub fn custom(f: impl Fn(f64) -> f64 + Send + Sync + 'static) -> Self {
        TimeFunction::Custom(Arc::new(f))
    }

    /// `g(t)` (dimensionless).
    pub fn value(&self, t: f64) -> f64 {
        match self {
            TimeFunction::Constant(c) => *c,
            TimeFunction::Ramp { duration } => {
                if *duration > 0.0 && t < *duration {
                    t / duration
                } else {
                    1.0
                }
            }
            TimeFunction::PiecewiseLinear(points) => piecewise_linear(points, t),
            TimeFunction::Custom(f) => f(t),
        }
    }

    /// `G(t) = ∫₀ᵗ g(s) ds` (s) in closed form, for `t ≥ 0`: the displacement of a dof with
    /// Dirichlet velocity factor `f` is `u₀ + f G(t)`. `None` for a custom function (no
    /// closed form).
    pub fn integral(&self, t: f64) -> Option<f64> {
        match self {
            TimeFunction::Constant(c) => Some(c * t),
            TimeFunction::Ramp { duration } => Some(if *duration > 0.0 && t < *duration {
                0.5 * t * t / duration
            } else {
                t - 0.5 * duration
            }),
            TimeFunction::PiecewiseLinear(points) => Some(piecewise_linear_integral(points, t)),
            TimeFunction::Custom(_) => None,
        }
    }

    /// The first time strictly after `t` (s) at which `g` is not smooth, if `g` says so:
    /// the end of a ramp, the points of a piecewise-linear history (none for a constant or
    /// a custom function). Adaptive time steps end there instead of stepping over it
    /// (docs/math.md §9): an error estimate sees only smooth behaviour, and a step across a
    /// kink of the loading makes an error it cannot see.
    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        match self {
            TimeFunction::Ramp { duration } => (*duration > t).then_some(*duration),
            TimeFunction::PiecewiseLinear(points) => points.iter().map(|p| p.0).find(|&tk| tk > t),
            TimeFunction::Constant(_) | TimeFunction::Custom(_) => None,
        }
    }

    /// Checks the parameters (finite constant, finite `duration ≥ 0`, strictly increasing
    /// finite times with finite values) and, for a custom function, that `g(0)` is finite.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `loading`.
    pub fn validate(&self) -> Result<()> {
        let ok = match self {
            TimeFunction::Constant(c) => c.is_finite(),
            TimeFunction::Ramp { duration } => duration.is_finite() && *duration >= 0.0,
            TimeFunction::PiecewiseLinear(p) => {
                !p.is_empty()
                    && p.iter().all(|(t, g)| t.is_finite() && g.is_finite())
                    && p.windows(2).all(|w| w[0].0 < w[1].0)
            }
            TimeFunction::Custom(f) => f(0.0).is_finite(),
        };
        if ok {
            Ok(())
        } else {
            Err(invalid(
                "loading",
                format!(
                    "{self:?} is not admissible (finite values; ramp duration ≥ 0; \
                     piecewise-linear times strictly increasing, at least one point)"
                ),
            ))
        }
    }
}

/// `∫₀ᵗ` of [`piecewise_linear`] (trapezoids between the points, constant outside).
fn piecewise_linear_integral(points: &[(f64, f64)], t: f64) -> f64 {
    let mut total = 0.0;
    let mut a = 0.0;
    let mut ga = piecewise_linear(points, 0.0);
    let breaks = points.iter().map(|p| p.0).filter(|&tk| tk > 0.0 && tk < t);
    for b in breaks.chain(std::iter::once(t)) {
        let gb = piecewise_linear(points, b);
        total += 0.5 * (ga + gb) * (b - a);
        (a, ga) = (b, gb);
    }
    total
}

fn piecewise_linear(points: &[(f64, f64)], t: f64) -> f64 {
    let k = points.partition_point(|p| p.0 <= t);
    match (k.checked_sub(1).map(|i| points[i]), points.get(k)) {
        (None, Some(first)) => first.1,
        (Some(last), None) => last.1,
        (Some((t0, g0)), Some((t1, g1))) => g0 + (g1 - g0) * ((t - t0) / (t1 - t0)),
        (None, None) => 0.0,
    }
}

impl std::fmt::Debug for TimeFunction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TimeFunction::Constant(c) => write!(f, "Constant({c})"),
            TimeFunction::Ramp { duration } => write!(f, "Ramp {{ duration: {duration} }}"),
            TimeFunction::PiecewiseLinear(p) => write!(f, "PiecewiseLinear({p:?})"),
            TimeFunction::Custom(_) => write!(f, "Custom(..)"),
        }
    }
}

impl PartialEq for TimeFunction {
    /// Equal parameters; custom functions are equal only if they are the same `Arc`.
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (TimeFunction::Constant(a), TimeFunction::Constant(b)) => a == b,
            (TimeFunction::Ramp { duration: a }, TimeFunction::Ramp { duration: b }) => a == b,
            (TimeFunction::PiecewiseLinear(a), TimeFunction::PiecewiseLinear(b)) => a == b,
            (TimeFunction::Custom(a), TimeFunction::Custom(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

/// Time-dependent Dirichlet velocity `v_i(t) = factor_i · g(t)` on the listed dofs, with a
/// dimensionless loading history `g` (the paper's ramp, docs/math.md §6, or any
/// [`TimeFunction`]). The factors carry the velocity (m/s): a Dirichlet part moving with
/// velocity `w` (a vector) gives factor `w_c` to component `c` of each of its nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct DirichletVelocity {
    /// Dofs with a prescribed non-zero velocity (a subset of the fixed dofs; all other
    /// fixed dofs have velocity 0).
    pub dofs: Vec<usize>,
    /// Velocity per dof at `g = 1` (m/s), same order as `dofs`.
    pub factors: Vec<f64>,
    /// The loading history `g(t)`.
    pub history: TimeFunction,
}

impl DirichletVelocity {
    /// No prescribed velocity: every fixed dof is at rest.
    pub fn none() -> Self {
        Self {
            dofs: Vec::new(),
            factors: Vec::new(),
            history: TimeFunction::Constant(0.0),
        }
    }

    /// The loading history `g(t)` (dimensionless); the velocity of dof `dofs[k]` is
    /// `factors[k] · g(t)`.
    pub fn speed(&self, t: f64) -> f64 {
        self.history.value(t)
    }

    /// The prescribed dofs' velocities at `t` into `v` (the other dofs untouched).
    ///
    /// # Panics
    /// If a dof is out of range for `v`.
    pub(crate) fn impose(&self, t: f64, v: &mut [f64]) {
        let speed = self.speed(t);
        for (&d, &f) in self.dofs.iter().zip(&self.factors) {
            v[d] = f * speed;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::TimeFunction;

    #[test]
    fn integrals_match_a_quadrature_of_the_history() {
        let histories = [
            TimeFunction::Constant(2.5),
            TimeFunction::ramp(3.0),
            TimeFunction::ramp(0.0),
            TimeFunction::PiecewiseLinear(vec![(-1.0, 1.0), (1.0, 3.0), (2.5, -1.0), (4.0, 0.5)]),
        ];
        for h in &histories {
            for t in [0.0, 0.7, 1.0, 2.0, 3.0, 5.5] {
                // Composite midpoint rule on a fine grid (exact for the linear pieces up to
                // the kinks, which it straddles at most once per kink).
                let n = 200_000;
                let q: f64 = (0..n)
                    .map(|i| h.value((i as f64 + 0.5) * t / n as f64) * t / n as f64)
                    .sum();
                let g = h.integral(t).unwrap();
                assert!(
                    (g - q).abs() < 1e-9 * (1.0 + q.abs()),
                    "{h:?} at {t}: {g} vs {q}"
                );
            }
        }
        assert_eq!(TimeFunction::custom(|_| 1.0).integral(1.0), None);
    }

    #[test]
    fn breakpoints_are_the_kinks_after_the_given_time() {
        let ramp = TimeFunction::ramp(2.0);
        assert_eq!(ramp.next_breakpoint(0.0), Some(2.0));
        assert_eq!(ramp.next_breakpoint(2.0), None);
        assert_eq!(TimeFunction::ramp(0.0).next_breakpoint(0.0), None);
        let pl = TimeFunction::PiecewiseLinear(vec![(-1.0, 0.0), (1.0, 1.0), (3.0, 0.5)]);
        assert_eq!(pl.next_breakpoint(-2.0), Some(-1.0));
        assert_eq!(pl.next_breakpoint(0.0), Some(1.0));
        assert_eq!(pl.next_breakpoint(1.0), Some(3.0));
        assert_eq!(pl.next_breakpoint(3.0), None);
        assert_eq!(TimeFunction::Constant(1.0).next_breakpoint(0.0), None);
        assert_eq!(TimeFunction::custom(|t| t).next_breakpoint(0.0), None);
    }
}
