//! The fixed point iteration of the coupled time step (docs/math.md §4, §8): options and
//! the acceleration of the state iterates.
//!
//! One sweep of the iteration is the map `G(α) = S(α_{n−1}, |R(α)|)` on the state of the
//! frictional nodes: solve the velocity problem `R` with the friction frozen at `α`, then
//! update the state by backward Euler `S` from the step's initial state. The paper relaxes
//! it ([`Acceleration::Relaxation`]); [`Acceleration::Anderson`] extrapolates from the last
//! few residuals `f = G(α) − α` instead, with a fallback to the paper's rule.

use crate::error::{invalid, Result};
use crate::method::solver::SolverKind;

/// A preset of the fixed point iteration (the choice of scenes and command lines).
///
/// Names (`name`, `FromStr`, serde, clap): `anderson`, `paper`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FixedPointScheme {
    /// Anderson acceleration from an extrapolated predictor
    /// ([`FixedPointOptions::default`]).
    #[default]
    Anderson,
    /// The paper's relaxed iteration ([`FixedPointOptions::paper`]; Fig. 6.1's counts).
    Paper,
}

impl FixedPointScheme {
    /// Every scheme, in declaration order.
    pub const ALL: [FixedPointScheme; 2] = [Self::Anderson, Self::Paper];

    /// The name (`anderson`, `paper`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Anderson => "anderson",
            Self::Paper => "paper",
        }
    }

    /// The options of the scheme ([`FixedPointOptions::default`] or
    /// [`FixedPointOptions::paper`]).
    pub fn options(self) -> FixedPointOptions {
        match self {
            Self::Anderson => FixedPointOptions::default(),
            Self::Paper => FixedPointOptions::paper(),
        }
    }
}

rsf_numeric::display_and_parse_by_name!(
    FixedPointScheme,
    "fixed point scheme",
    crate::Error,
    FixedPointScheme::ALL
);

/// How the next state iterate is formed from `α^ν` and `G(α^ν)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Acceleration {
    /// The paper's rule (§6.2): `α^{ν+1} = ω G(α^ν) + (1 − ω) α^ν` with `ω = 1` for the
    /// first two iterations and while `‖G(α^ν) − α^ν‖ ≤ ½ ‖α^ν − α^{ν−1}‖` (lumped
    /// L²(Γ_F) norm), else `ω = relaxation` (paper: 0.5).
    Relaxation {
        /// The damped ω ∈ (0, 1].
        relaxation: f64,
    },
    /// Anderson acceleration ("type II", Walker & Ni 2011) of depth `depth` on the residuals
    /// `f = G(α) − α` in the lumped L²(Γ_F) norm: `α^{ν+1} = G(α^ν) − ΔG γ` with `γ`
    /// minimising `‖f^ν − ΔF γ‖` over the last `depth` differences. Safeguard: when a
    /// residual grows by more than `restart_growth` over the previous one, the history is
    /// cleared and the iteration falls back to the paper's relaxed step with `relaxation`.
    Anderson {
        /// Number of stored differences (1–8).
        depth: usize,
        /// Growth factor of `‖f‖` that triggers a restart (> 0; e.g. 1).
        restart_growth: f64,
        /// ω of the fallback step (0, 1].
        relaxation: f64,
    },
}

/// The start of each step's iteration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Predictor {
    /// `v⁰ = v_{n−1}` (the paper).
    Previous,
    /// `v⁰ = v_{n−1} + τ a_{n−1}` (a first-order extrapolation; equals `v_{n−1}` for the
    /// quasistatic integrator, whose acceleration is 0).
    Extrapolated,
}

/// How accurately the velocity problem of each fixed point iteration is solved
/// (docs/math.md §8). Whatever the rule, a step is only accepted after a solve at the
/// solver's own tolerance whose change passes the fixed point test, so every rule
/// converges to the same fixed point within the tolerances.
///
/// Names (serde): `exact`, `by-solver`, `{ inexact = { factor = 0.1, first = true } }`.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum InnerSolves {
    /// Every solve to the solver's own tolerance (the paper).
    #[default]
    Exact,
    /// The solve of iteration ν ≥ 1 stops at `max(solver tolerance, factor · c_{ν−1})`,
    /// `c_{ν−1} = ‖v^ν − v^{ν−1}‖` the previous iteration's change: a state iterate that
    /// is still far from the fixed point is not worth a velocity to 1e-10. With `first`,
    /// the first solve of a step stops after one solver iteration (its distance to the
    /// fixed point is not known yet; the predictor's error dominates it); without, it is
    /// exact (it is then often the last, e.g. for the direct solver).
    Inexact {
        /// The factor on the previous change (`> 0`; with TNNMG's reduction of about
        /// 1e-3 per iteration any factor in `[1e-3, 1]` gives one iteration per fixed point
        /// iteration until the tolerance is near).
        factor: f64,
        /// Whether the first solve of a step stops after one iteration.
        first: bool,
    },
    /// [`BY_SOLVER_INEXACT`](Self::BY_SOLVER_INEXACT) for TNNMG, which iterates on the
    /// whole body, [`Exact`](Self::Exact) for the other solvers (the direct solver's
    /// condensed iterations are cheap and its first solve is usually the last; nonlinear
    /// Gauss–Seidel is not measured). Measured on the 3-D slider at level 3
    /// (docs/scaling.md): 5.1 TNNMG iterations per step against 9.3, the same events.
    BySolver,
}

impl InnerSolves {
    /// The inexact rule of [`BySolver`](Self::BySolver) for TNNMG.
    pub const BY_SOLVER_INEXACT: InnerSolves = InnerSolves::Inexact {
        factor: 0.1,
        first: true,
    };

    /// Whether this is [`Exact`](Self::Exact) (for serde's `skip_serializing_if`).
    pub fn is_exact(&self) -> bool {
        *self == InnerSolves::Exact
    }

    /// `(factor, first)` of the rule for the solver `kind` (resolved), `None` for exact
    /// solves.
    pub fn rule(self, kind: SolverKind) -> Option<(f64, bool)> {
        let resolved = match self {
            InnerSolves::BySolver => match kind {
                SolverKind::Tnnmg => Self::BY_SOLVER_INEXACT,
                _ => InnerSolves::Exact,
            },
            other => other,
        };
        match resolved {
            InnerSolves::Inexact { factor, first } => Some((factor, first)),
            _ => None,
        }
    }
}

/// Options of the fixed point iteration of each time step (docs/math.md §4, §8).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedPointOptions {
    /// Stop when the velocity correction `‖v^{ν+1} − v^ν‖` is at most `tolerance` in the
    /// energy norm (paper: 1e-10).
    pub tolerance: f64,
    /// Iteration budget per step; exceeding it is
    /// [`Error::FixedPointNotConverged`](crate::Error::FixedPointNotConverged).
    pub max_iterations: usize,
    /// How the state iterates are formed.
    pub acceleration: Acceleration,
    /// The start of the iteration.
    pub predictor: Predictor,
    /// How accurately each iteration's velocity problem is solved ([`InnerSolves`]).
    pub inner_solves: InnerSolves,
    /// The paper compares the first velocity iterate with `v_{n−1}`, which differs from it by
    /// the step's change of the bulk velocity, so a step never ends after one iteration.
    /// With `true` the first iteration is never accepted, which reproduces the paper's
    /// iteration counts (Fig. 6.1); with `false` it is compared with the predictor (for the
    /// direct solver: its discrete harmonic extension) and may be accepted.
    pub paper_first_iteration: bool,
    /// Accept a step also when the *estimated error* of the last iterate is below the
    /// tolerance: with the observed contraction `θ = c_ν / c_{ν−1}` of the velocity
    /// corrections `c_ν = ‖v^{ν+1} − v^ν‖`, the distance of `v^{ν+1}` to the fixed point is
    /// about `θ/(1 − θ) c_ν` (the classical test of simplified Newton iterations, Hairer &
    /// Wanner, *Solving ODEs II*, §IV.8). Used only while `θ ≤ ½` and `c_ν ≤ 100 ·
    /// tolerance` (a guard against an unrepresentative ratio). The paper's test
    /// (`c_ν ≤ tolerance`) leaves an error of about `θ · tolerance`, far below the
    /// tolerance when the iteration contracts fast; this one stops one iteration earlier
    /// with the error still below the tolerance (docs/math.md §8).
    pub error_estimate: bool,
}

impl Default for FixedPointOptions {
    /// Anderson acceleration of depth 3 from an extrapolated predictor, exact inner solves,
    /// tolerance 1e-10, 100 iterations.
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 100,
            acceleration: Acceleration::Anderson {
                depth: 3,
                restart_growth: 1.0,
                relaxation: 0.5,
            },
            predictor: Predictor::Extrapolated,
            inner_solves: InnerSolves::Exact,
            paper_first_iteration: false,
            error_estimate: true,
        }
    }
}

impl FixedPointOptions {
    /// The paper's iteration (§6.2): relaxation 0.5, predictor `v_{n−1}`, exact inner
    /// solves, tolerance 1e-10, 100 iterations; iteration counts as in Fig. 6.1.
    pub fn paper() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 100,
            acceleration: Acceleration::Relaxation { relaxation: 0.5 },
            predictor: Predictor::Previous,
            inner_solves: InnerSolves::Exact,
            paper_first_iteration: true,
            error_estimate: false,
        }
    }

    /// Checks the options.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming the option.
    pub fn validate(&self) -> Result<()> {
        if !(self.tolerance > 0.0 && self.tolerance.is_finite()) {
            return Err(invalid(
                "fixed_point.tolerance",
                format!("{} must be finite and > 0", self.tolerance),
            ));
        }
        if self.max_iterations == 0 {
            return Err(invalid("fixed_point.max_iterations", "must be at least 1"));
        }
        let omega_ok = |w: f64| w > 0.0 && w <= 1.0;
        match self.acceleration {
            Acceleration::Relaxation { relaxation } if !omega_ok(relaxation) => {
                return Err(invalid(
                    "fixed_point.relaxation",
                    format!("{relaxation} must lie in (0, 1]"),
                ))
            }
            Acceleration::Anderson {
                depth,
                restart_growth,
                relaxation,
            } => {
                if !(1..=8).contains(&depth) {
                    return Err(invalid(
                        "fixed_point.anderson_depth",
                        format!("{depth} must lie in 1..=8"),
                    ));
                }
                if !(restart_growth > 0.0 && restart_growth.is_finite()) {
                    return Err(invalid(
                        "fixed_point.restart_growth",
                        format!("{restart_growth} must be finite and > 0"),
                    ));
                }
                if !omega_ok(relaxation) {
                    return Err(invalid(
                        "fixed_point.relaxation",
                        format!("{relaxation} must lie in (0, 1]"),
                    ));
                }
            }
            _ => {}
        }
        if let InnerSolves::Inexact { factor, .. } = self.inner_solves {
            if !(factor > 0.0 && factor.is_finite()) {
                return Err(invalid(
                    "fixed_point.inner_solves.factor",
                    format!("{factor} must be finite and > 0"),
                ));
            }
        }
        Ok(())
    }
}

/// The state of the acceleration within one step: the last iterates and residuals.
#[derive(Debug, Clone)]
pub(crate) struct Accelerator {
    opts: Acceleration,
    weights: Vec<f64>,
    /// Differences of residuals and of G-values, most recent last (ring of `depth`).
    df: Vec<Vec<f64>>,
    dg: Vec<Vec<f64>>,
    count: usize,
    f_prev: Vec<f64>,
    g_prev: Vec<f64>,
    have_prev: bool,
    f: Vec<f64>,
    /// Orthonormalised columns for the least-squares problem (scaled by √w).
    q: Vec<Vec<f64>>,
    r: Vec<Vec<f64>>,
    gamma: Vec<f64>,
    prev_norm: f64,
    prev_increment: f64,
    iteration: usize,
    /// Iterations of this step that used a damped (fallback or paper) step.
    pub damped: usize,
}

fn weighted_norm(w: &[f64], x: &[f64]) -> f64 {
    w.iter().zip(x).map(|(w, x)| w * x * x).sum::<f64>().sqrt()
}

impl Accelerator {
    /// For `weights` (lumped L²(Γ_F) weights, one per frictional node).
    pub fn new(opts: Acceleration, weights: &[f64]) -> Self {
        let n = weights.len();
        let depth = match opts {
            Acceleration::Anderson { depth, .. } => depth,
            Acceleration::Relaxation { .. } => 0,
        };
        Self {
            opts,
            weights: weights.to_vec(),
            df: vec![vec![0.0; n]; depth],
            dg: vec![vec![0.0; n]; depth],
            count: 0,
            f_prev: vec![0.0; n],
            g_prev: vec![0.0; n],
            have_prev: false,
            f: vec![0.0; n],
            q: vec![vec![0.0; n]; depth],
            r: vec![vec![0.0; depth]; depth],
            gamma: vec![0.0; depth],
            prev_norm: f64::INFINITY,
            prev_increment: f64::INFINITY,
            iteration: 0,
            damped: 0,
        }
    }

    /// Starts a step: `first_increment` is `‖α^0 − α_{n−1}‖` of the unrelaxed first update
    /// (the paper's rule compares later increments with it).
    pub fn begin(&mut self, first_increment: f64) {
        self.count = 0;
        self.have_prev = false;
        self.prev_norm = f64::INFINITY;
        self.prev_increment = first_increment;
        self.iteration = 1;
        self.damped = 0;
    }

    /// Replaces `alpha` (the current iterate `α^ν`) by the next iterate, given
    /// `g = G(α^ν)`.
    pub fn next(&mut self, alpha: &mut [f64], g: &[f64]) {
        for ((f, a), g) in self.f.iter_mut().zip(alpha.iter()).zip(g) {
            *f = g - a;
        }
        let norm = weighted_norm(&self.weights, &self.f);
        let relaxed_step = |alpha: &mut [f64], omega: f64, f: &[f64]| {
            for (a, f) in alpha.iter_mut().zip(f) {
                *a += omega * f;
            }
        };
        match self.opts {
            Acceleration::Relaxation { relaxation } => {
                let omega = if self.iteration <= 1 || norm <= 0.5 * self.prev_increment {
                    1.0
                } else {
                    self.damped += 1;
                    relaxation
                };
                relaxed_step(alpha, omega, &self.f);
                self.prev_increment = omega * norm;
            }
            Acceleration::Anderson {
                depth,
                restart_growth,
                relaxation,
            } => {
                if norm > restart_growth * self.prev_norm {
                    // Safeguard: forget the history, take the paper's damped step.
                    self.count = 0;
                    self.have_prev = false;
                    self.damped += 1;
                    relaxed_step(alpha, relaxation, &self.f);
                    self.prev_norm = norm;
                    self.iteration += 1;
                    return;
                }
                if self.have_prev {
                    // Append the newest differences (ring buffer of `depth`).
                    let slot = if self.count < depth {
                        self.count += 1;
                        self.count - 1
                    } else {
                        self.df.rotate_left(1);
                        self.dg.rotate_left(1);
                        depth - 1
                    };
                    for i in 0..self.f.len() {
                        self.df[slot][i] = self.f[i] - self.f_prev[i];
                        self.dg[slot][i] = g[i] - self.g_prev[i];
                    }
                }
                self.f_prev.copy_from_slice(&self.f);
                self.g_prev.copy_from_slice(g);
                self.have_prev = true;
                self.prev_norm = norm;
                let m = self.least_squares();
                // α^{ν+1} = G(α^ν) − ΔG γ.
                for i in 0..alpha.len() {
                    let mut a = g[i];
                    for j in 0..m {
                        a -= self.dg[j][i] * self.gamma[j];
                    }
                    alpha[i] = a;
                }
            }
        }
        self.iteration += 1;
    }

    /// Solves `min ‖f − ΔF γ‖_W` by modified Gram–Schmidt on the stored columns (scaled by
    /// √w), dropping the oldest columns while the problem is ill-conditioned. Returns the
    /// number of columns used (`gamma[..m]`, referring to the newest `m` columns of the
    /// ring, re-indexed from the oldest kept one).
    fn least_squares(&mut self) -> usize {
        loop {
            let m = self.count;
            if m == 0 {
                return 0;
            }
            let n = self.f.len();
            let mut ok = true;
            for j in 0..m {
                for i in 0..n {
                    self.q[j][i] = self.df[j][i] * self.weights[i].sqrt();
                }
                let norm0 = self.q[j].iter().map(|x| x * x).sum::<f64>().sqrt();
                for k in 0..j {
                    let d: f64 = self.q[k].iter().zip(&self.q[j]).map(|(a, b)| a * b).sum();
                    self.r[k][j] = d;
                    let (lo, hi) = self.q.split_at_mut(j);
                    for (x, y) in hi[0].iter_mut().zip(&lo[k]) {
                        *x -= d * y;
                    }
                }
                let nj = self.q[j].iter().map(|x| x * x).sum::<f64>().sqrt();
                if !(nj > 1e-10 * norm0) || nj == 0.0 {
                    ok = false;
                    break;
                }
                self.r[j][j] = nj;
                for x in self.q[j].iter_mut() {
                    *x /= nj;
                }
            }
            if !ok {
                // Drop the oldest column and retry.
                self.df.rotate_left(1);
                self.dg.rotate_left(1);
                self.count -= 1;
                continue;
            }
            // γ = R⁻¹ Qᵀ (√w f).
            for j in 0..m {
                self.gamma[j] = self.q[j]
                    .iter()
                    .zip(&self.f)
                    .zip(&self.weights)
                    .map(|((q, f), w)| q * f * w.sqrt())
                    .sum();
            }
            for j in (0..m).rev() {
                let mut s = self.gamma[j];
                for k in j + 1..m {
                    s -= self.r[j][k] * self.gamma[k];
                }
                self.gamma[j] = s / self.r[j][j];
            }
            return m;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a linear contraction G(α) = Bα + c, Anderson with depth ≥ dim reaches the fixed
    /// point in dim + 1 steps (it is GMRES in disguise), while plain iteration needs many.
    #[test]
    fn anderson_solves_a_linear_fixed_point_problem_in_dim_plus_one_steps() {
        let b = [[0.9, 0.05, 0.0], [0.02, 0.8, 0.1], [0.0, 0.1, 0.85]];
        let c = [1.0, -2.0, 0.5];
        let g = |a: &[f64]| -> Vec<f64> {
            (0..3)
                .map(|i| c[i] + (0..3).map(|j| b[i][j] * a[j]).sum::<f64>())
                .collect()
        };
        let w = [1.0, 2.0, 0.5];
        let mut acc = Accelerator::new(
            Acceleration::Anderson {
                depth: 3,
                restart_growth: 1e6,
                relaxation: 0.5,
            },
            &w,
        );
        acc.begin(f64::INFINITY);
        let mut alpha = vec![0.0; 3];
        for _ in 0..4 {
            let ga = g(&alpha);
            acc.next(&mut alpha, &ga);
        }
        let ga = g(&alpha);
        let res: f64 = ga.iter().zip(&alpha).map(|(x, y)| (x - y).abs()).sum();
        assert!(res < 1e-10, "residual {res}");
        // Plain Picard from the same start is still far off after 5 steps.
        let mut p = vec![0.0; 3];
        for _ in 0..5 {
            p = g(&p);
        }
        let res_p: f64 = g(&p).iter().zip(&p).map(|(x, y)| (x - y).abs()).sum();
        assert!(res_p > 1e-2, "Picard residual {res_p}");
    }

    /// The relaxation rule damps exactly when the increments stop halving.
    #[test]
    fn paper_rule_damps_when_increments_stop_halving() {
        let w = [1.0];
        let mut acc = Accelerator::new(Acceleration::Relaxation { relaxation: 0.5 }, &w);
        acc.begin(1.0);
        let mut a = vec![0.0];
        acc.next(&mut a, &[0.9]); // iteration 1: ω = 1 always
        assert_eq!(a[0], 0.9);
        acc.next(&mut a, &[1.3]); // increment 0.4 ≤ ½·0.9: ω = 1
        assert_eq!(a[0], 1.3);
        acc.next(&mut a, &[1.6]); // increment 0.3 > ½·0.4: ω = 0.5
        assert!((a[0] - 1.45).abs() < 1e-15);
        assert_eq!(acc.damped, 1);
    }
}
