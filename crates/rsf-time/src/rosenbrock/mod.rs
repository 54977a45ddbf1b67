//! A linearly implicit integrator for stiff ODE systems `y' = f(t, y)` whose Jacobian is
//! only available as its action (docs/math.md §12, "Implicit steps"): the Rosenbrock-W
//! method ROS34PW2 of Rang & Angermann (2005, "New Rosenbrock W-methods of order 3 for
//! partial differential algebraic equations of index 1", BIT 45) — four stages, order
//! 3 (for any approximation of the Jacobian: a W-method), an embedded solution of order
//! 2, L-stable and stiffly accurate — in the transformed form of Hairer & Wanner
//! (*Solving ODEs II*, §IV.7, eq. (7.25)):
//!
//! ```text
//! (I/(hγ) − J) uᵢ = f(t + αᵢ h, y + Σⱼ<ᵢ aᵢⱼ uⱼ) + Σⱼ<ᵢ (cᵢⱼ/h) uⱼ + γᵢ h f_t,
//! y₁ = y + Σ mᵢ uᵢ,   error estimate Σ (mᵢ − m̂ᵢ) uᵢ.
//! ```
//!
//! Each stage's linear system `(I − hγ J) uᵢ = hγ (…)` is solved by restarted GMRES
//! without a matrix: `J v ≈ (f(t, y + σ v) − f(t, y))/σ` (one evaluation of `f` per
//! iteration), in the system's error weights ([`OdeSystem::error_weights`]: the
//! residual's Euclidean norm in units of the error tolerance is at most
//! [`RosenbrockOptions::krylov_tolerance`]), right-preconditioned by the blocks of
//! `I − hγ J_loc` that the system's cheap local Jacobian gives
//! ([`OdeSystem::local_jacobian`]; unpreconditioned without one). `f_t` by a finite
//! difference in time. A step costs the stages' three evaluations, one for `f_t`, the
//! local Jacobian (one evaluation for the fault ODE), the new point's rate and the
//! iterations: never a factorisation of the whole Jacobian, so an ℋ-matrix or a
//! condensed finite-element operator works as it is.
//!
//! Steps are controlled as the explicit pairs' (DOPRI5's PI controller with the
//! exponents of the embedded order 2, [`RungeKuttaOptions`]); a linear solve that does
//! not reach its tolerance within [`RosenbrockOptions::max_krylov_iterations`] rejects
//! the attempt and quarters the step (a smaller `hγ` brings `I − hγ J` towards `I`), and
//! below `dt_min` the integration stops with [`Error::LinearSolveFailed`]. The memory is
//! the controller's ([`RungeKuttaState`]): the local Jacobian and `f_t` are functions of
//! the step's start, recomputed at every accepted point, so a checkpoint's `(t, y)`, rate
//! and controller continue the integration bit for bit.

use crate::krylov::{BlockFactors, Gmres, JacobianBlocks, LinearOperator};
use crate::runge_kutta::{
    accepted_next, after_refusal, check_step, next_attempt, rate_or_refusal, rejected_next,
    OdeSystem, RungeKuttaOptions, RungeKuttaState, RungeKuttaStep,
};
use crate::{Error, Result};

/// ROS34PW2's coefficients (Rang & Angermann 2005, Table 4.1): `α` (strictly lower), `Γ`
/// (lower, diagonal `γ`), `b` and the embedded `b̂`.
mod ros34pw2 {
    pub const GAMMA: f64 = 4.358_665_215_084_59e-1;
    pub const ALPHA: [[f64; 4]; 4] = [
        [0.0, 0.0, 0.0, 0.0],
        [8.717_330_430_169_18e-1, 0.0, 0.0, 0.0],
        [
            8.445_706_001_536_942e-1,
            -1.129_906_423_648_418_5e-1,
            0.0,
            0.0,
        ],
        [0.0, 0.0, 1.0, 0.0],
    ];
    pub const GAMMA_IJ: [[f64; 4]; 4] = [
        [GAMMA, 0.0, 0.0, 0.0],
        [-8.717_330_430_169_18e-1, GAMMA, 0.0, 0.0],
        [
            -9.033_805_701_304_408e-1,
            5.418_067_238_809_533e-2,
            GAMMA,
            0.0,
        ],
        [
            2.421_238_070_609_534_6e-1,
            -1.223_250_583_904_514_7,
            5.452_602_553_351_021e-1,
            GAMMA,
        ],
    ];
    pub const B: [f64; 4] = [
        2.421_238_070_609_534_6e-1,
        -1.223_250_583_904_514_7,
        1.545_260_255_335_102,
        GAMMA,
    ];
    pub const B_HAT: [f64; 4] = [
        3.781_090_314_581_937e-1,
        -9.604_229_221_242_318e-2,
        0.5,
        2.179_332_607_542_295e-1,
    ];
}

const STAGES: usize = 4;

/// The transformed coefficients of a Rosenbrock method (Hairer & Wanner §IV.7):
/// `A = α Γ⁻¹`, `C = diag(γ⁻¹) − Γ⁻¹`, `m = b Γ⁻¹`, `m̂ = b̂ Γ⁻¹`, the nodes `αᵢ` and the
/// time-derivative weights `γᵢ = Σⱼ≤ᵢ γᵢⱼ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Transformed {
    pub gamma: f64,
    pub a: [[f64; STAGES]; STAGES],
    pub c: [[f64; STAGES]; STAGES],
    pub m: [f64; STAGES],
    pub m_hat: [f64; STAGES],
    pub nodes: [f64; STAGES],
    pub gamma_sums: [f64; STAGES],
}

impl Transformed {
    pub(crate) fn ros34pw2() -> Self {
        use ros34pw2::*;
        let g = GAMMA_IJ;
        // Γ⁻¹ by forward substitution (lower triangular).
        let mut inv = [[0.0; STAGES]; STAGES];
        for j in 0..STAGES {
            for i in j..STAGES {
                let mut s = if i == j { 1.0 } else { 0.0 };
                for k in j..i {
                    s -= g[i][k] * inv[k][j];
                }
                inv[i][j] = s / g[i][i];
            }
        }
        let mut t = Self {
            gamma: GAMMA,
            a: [[0.0; STAGES]; STAGES],
            c: [[0.0; STAGES]; STAGES],
            m: [0.0; STAGES],
            m_hat: [0.0; STAGES],
            nodes: [0.0; STAGES],
            gamma_sums: [0.0; STAGES],
        };
        for i in 0..STAGES {
            for j in 0..STAGES {
                t.a[i][j] = (0..STAGES).map(|k| ALPHA[i][k] * inv[k][j]).sum();
                t.c[i][j] = if i == j { 1.0 / g[i][i] } else { 0.0 } - inv[i][j];
            }
            t.m[i] = (0..STAGES).map(|k| B[k] * inv[k][i]).sum();
            t.m_hat[i] = (0..STAGES).map(|k| B_HAT[k] * inv[k][i]).sum();
            t.nodes[i] = ALPHA[i].iter().sum();
            t.gamma_sums[i] = g[i][..=i].iter().sum();
        }
        t
    }
}

/// Options of [`Rosenbrock`] beyond the step limits ([`RungeKuttaOptions`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RosenbrockOptions {
    /// The Euclidean norm of a stage's linear residual, in the system's error weights
    /// (units of the error tolerance), at which GMRES stops (default 0.01: the solve's
    /// error is a hundredth of what the step may make). Positive.
    pub krylov_tolerance: f64,
    /// GMRES's restart length (default 30). At least 1.
    pub krylov_restart: usize,
    /// Most GMRES iterations of one stage's solve (default 120); a solve that needs more
    /// rejects the attempt. At least 1.
    pub max_krylov_iterations: usize,
}

impl Default for RosenbrockOptions {
    fn default() -> Self {
        Self {
            krylov_tolerance: 0.01,
            krylov_restart: 30,
            max_krylov_iterations: 120,
        }
    }
}

impl RosenbrockOptions {
    /// Checks the options.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first invalid option.
    pub fn validate(&self) -> Result<()> {
        if !(self.krylov_tolerance > 0.0 && self.krylov_tolerance.is_finite()) {
            return Err(Error::InvalidParameter {
                name: "krylov_tolerance",
                value: self.krylov_tolerance,
                requirement: "must be positive and finite",
            });
        }
        for (name, value) in [
            ("krylov_restart", self.krylov_restart),
            ("max_krylov_iterations", self.max_krylov_iterations),
        ] {
            if value == 0 || value > 100_000 {
                return Err(Error::InvalidParameter {
                    name,
                    value: value as f64,
                    requirement: "must be in [1, 100000]",
                });
            }
        }
        Ok(())
    }
}

/// What one accepted [`Rosenbrock`] step did beyond [`RungeKuttaStep`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RosenbrockStep {
    /// The step (its `evaluations` include the GMRES iterations, `f_t`, the local
    /// Jacobian's and the new point's rate).
    pub step: RungeKuttaStep,
    /// GMRES iterations of its attempts (each one evaluation of `f`).
    pub krylov_iterations: usize,
    /// Attempts rejected because a linear solve did not converge.
    pub linear_failures: usize,
    /// Whether its solves were preconditioned by the system's local Jacobian.
    pub preconditioned: bool,
}

/// The ROS34PW2 integrator with adaptive steps and matrix-free GMRES solves: call
/// [`step`](Self::step) for one accepted step at a time. Allocates its vectors once; a
/// step allocates nothing.
#[derive(Debug, Clone)]
pub struct Rosenbrock {
    options: RungeKuttaOptions,
    ros: RosenbrockOptions,
    coefficients: Transformed,
    state: RungeKuttaState,
    /// `f(t, y)` at the current point (valid if `fsal`).
    f0: Vec<f64>,
    fsal: bool,
    /// Whether `ft`, `blocks` and `weights` belong to the current point.
    fresh: bool,
    ft: Vec<f64>,
    weights: Vec<f64>,
    blocks: JacobianBlocks,
    preconditioned: bool,
    factors: BlockFactors,
    u: [Vec<f64>; STAGES],
    stage: Vec<f64>,
    rhs: Vec<f64>,
    scaled: Vec<f64>,
    probe: Vec<f64>,
    probe_rate: Vec<f64>,
    gmres: Gmres,
}

impl Rosenbrock {
    /// An integrator for systems of dimension `n` with the first step `dt0` (s).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid options or `dt0` outside
    /// `[dt_min, dt_max]`.
    pub fn new(
        options: RungeKuttaOptions,
        ros: RosenbrockOptions,
        n: usize,
        dt0: f64,
    ) -> Result<Self> {
        options.validate()?;
        ros.validate()?;
        if !(dt0 >= options.dt_min && dt0 <= options.dt_max) {
            return Err(Error::InvalidParameter {
                name: "dt0",
                value: dt0,
                requirement: "must be in [dt_min, dt_max]",
            });
        }
        let z = || vec![0.0; n];
        Ok(Self {
            options,
            ros,
            coefficients: Transformed::ros34pw2(),
            state: RungeKuttaState {
                dt: dt0,
                previous_error: 1e-4,
            },
            f0: z(),
            fsal: false,
            fresh: false,
            ft: z(),
            weights: z(),
            blocks: JacobianBlocks::new(),
            preconditioned: false,
            factors: BlockFactors::default(),
            u: [z(), z(), z(), z()],
            stage: z(),
            rhs: z(),
            scaled: z(),
            probe: z(),
            probe_rate: z(),
            gmres: Gmres::new(n, ros.krylov_restart.min(n.max(1))),
        })
    }

    /// The controller's state (for checkpoints).
    pub fn state(&self) -> RungeKuttaState {
        self.state
    }

    /// Continues from a saved controller state; the next step evaluates `f` afresh.
    pub fn set_state(&mut self, state: RungeKuttaState) {
        self.state = state;
        self.fsal = false;
        self.fresh = false;
    }

    /// Continues from a saved controller state and the saved rate `f(t, y)` of the
    /// current point: bit-identical to the integration that saved them.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for a rate of another length.
    pub fn restore(&mut self, state: RungeKuttaState, rate: &[f64]) -> Result<()> {
        if rate.len() != self.f0.len() {
            return Err(Error::DimensionMismatch {
                what: "saved rate",
                expected: self.f0.len(),
                got: rate.len(),
            });
        }
        self.state = state;
        self.f0.copy_from_slice(rate);
        self.fsal = true;
        self.fresh = false;
        Ok(())
    }

    /// `f(t, y)` of the current point, if known (after a step: the new point's).
    pub fn current_rate(&self) -> Option<&[f64]> {
        self.fsal.then_some(self.f0.as_slice())
    }

    /// The error weights, `f_t` and the local Jacobian at the current point; returns the
    /// evaluations they took.
    fn prepare<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
    ) -> std::result::Result<usize, S::Error> {
        if !sys.error_weights(y, &mut self.weights) {
            self.scaled.fill(1.0);
            let c = sys.scaled_error(y, y, &self.scaled);
            self.weights.fill(c);
        }
        // f_t by a forward difference in time (the step's scale or the time's).
        let dt = (f64::EPSILON.sqrt() * t.abs().max(self.state.dt)).max(f64::MIN_POSITIVE);
        let t1 = t + dt;
        let dt = t1 - t;
        sys.rate(t1, y, &mut self.ft)?;
        for (d, &f) in self.ft.iter_mut().zip(&self.f0) {
            *d = (*d - f) / dt;
        }
        let mut evaluations = 1;
        match sys.local_jacobian(t, y, &self.f0, &mut self.blocks)? {
            Some(e) => {
                self.blocks.validate(y.len())?;
                self.preconditioned = !self.blocks.is_empty();
                evaluations += e;
            }
            None => self.preconditioned = false,
        }
        self.fresh = true;
        Ok(evaluations)
    }

    /// One accepted step from `(t, y)`, updating both; at most up to `t_end` (the step is
    /// shortened to land on it, and the controller's proposal is kept for the next one).
    /// A stage outside the system's domain ([`OdeSystem::outside_domain`]) rejects the
    /// attempt and shrinks the step by `refusal_shrink`; a non-finite stage by 10; a
    /// linear solve that does not converge by 4.
    ///
    /// # Errors
    /// [`Error::StepTooSmall`], [`Error::TrialPointRefused`] (as
    /// [`EmbeddedRungeKutta::step`](crate::EmbeddedRungeKutta::step));
    /// [`Error::LinearSolveFailed`] when a solve does not converge and the step cannot
    /// shrink further; [`Error::DimensionMismatch`], [`Error::InvalidParameter`] for a
    /// `t_end` not after `t` or an invalid block structure; the system's errors.
    pub fn step<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: &mut f64,
        y: &mut [f64],
        t_end: Option<f64>,
    ) -> std::result::Result<RosenbrockStep, S::Error> {
        check_step(self.f0.len(), y, *t, t_end)?;
        let o = self.options;
        let mut evaluations = 0;
        if !self.fsal {
            sys.rate(*t, y, &mut self.f0)?;
            evaluations += 1;
            self.fsal = true;
        }
        if !self.fresh {
            evaluations += self.prepare(sys, *t, y)?;
        }
        let (mut rejected, mut refused, mut linear_failures) = (0, 0, 0);
        let mut krylov_iterations = 0;
        let mut rejected_error = 0.0;
        loop {
            let (dt, landing) = next_attempt(&o, *t, self.state.dt, t_end)?;
            let attempt = self.attempt(sys, (*t, dt), y)?;
            evaluations += attempt.evaluations;
            krylov_iterations += attempt.krylov_iterations;
            let error = match attempt.end {
                End::Refused(e) => {
                    rejected += 1;
                    refused += 1;
                    rejected_error = f64::INFINITY;
                    self.state.dt = after_refusal(&o, (*t, dt), refused, &e)?;
                    continue;
                }
                End::Linear {
                    iterations,
                    residual,
                } => {
                    rejected += 1;
                    linear_failures += 1;
                    rejected_error = f64::INFINITY;
                    let next = dt / 4.0;
                    if next < o.dt_min {
                        return Err(Error::LinearSolveFailed {
                            time: *t,
                            dt,
                            iterations,
                            residual,
                        }
                        .into());
                    }
                    self.state.dt = next;
                    continue;
                }
                End::NonFinite => f64::INFINITY,
                End::Error(e) => e,
            };
            if error <= 1.0 {
                // The new point's rate (the next step's first stage).
                let t_new = if landing {
                    t_end.unwrap_or(*t + dt)
                } else {
                    *t + dt
                };
                let evaluated = sys.rate(t_new, &self.stage, &mut self.probe_rate);
                evaluations += 1;
                let finite = match evaluated {
                    Ok(()) => self.probe_rate.iter().all(|x| x.is_finite()),
                    Err(e) if sys.outside_domain(&e) => {
                        rejected += 1;
                        refused += 1;
                        rejected_error = f64::INFINITY;
                        self.state.dt = after_refusal(&o, (*t, dt), refused, &e)?;
                        continue;
                    }
                    Err(e) => return Err(e),
                };
                if finite {
                    let next = accepted_next(&o, &mut self.state, (dt, error), 2);
                    if !landing || next < self.state.dt {
                        self.state.dt = next;
                    }
                    y.copy_from_slice(&self.stage);
                    *t = t_new;
                    std::mem::swap(&mut self.f0, &mut self.probe_rate);
                    self.fresh = false;
                    return Ok(RosenbrockStep {
                        step: RungeKuttaStep {
                            dt,
                            rejected,
                            refused,
                            error,
                            rejected_error,
                            evaluations,
                        },
                        krylov_iterations,
                        linear_failures,
                        preconditioned: self.preconditioned,
                    });
                }
            }
            let error = if error <= 1.0 { f64::INFINITY } else { error };
            rejected += 1;
            rejected_error = if error.is_nan() { f64::INFINITY } else { error };
            self.state.dt = rejected_next(&o, dt, error, 2);
            if self.state.dt < o.dt_min {
                return Err(Error::StepTooSmall {
                    tau: self.state.dt,
                    tau_min: o.dt_min,
                }
                .into());
            }
        }
    }

    /// One attempt of a step `dt` from `(t, y)`: the stages and their solves; the new
    /// point into `stage`, its scaled error estimate in the outcome.
    fn attempt<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        (t, dt): (f64, f64),
        y: &[f64],
    ) -> std::result::Result<Attempt<S::Error>, S::Error> {
        let co = self.coefficients;
        let h_gamma = dt * co.gamma;
        if self.preconditioned {
            self.factors.factor(&self.blocks, h_gamma);
        }
        let mut out = Attempt {
            evaluations: 0,
            krylov_iterations: 0,
            end: End::NonFinite,
        };
        // The finite difference's size in the error weights (√ε relative to y, at most a
        // tenth of the tolerance).
        let mut ynorm = 0.0_f64;
        for (&yi, &w) in y.iter().zip(&self.weights) {
            ynorm = ynorm.max((yi * w).abs());
        }
        let fd = (f64::EPSILON.sqrt() * ynorm.max(1.0)).min(0.1);
        for i in 0..STAGES {
            // The stage's point and rate.
            let rate_is_f0 = i == 0;
            if !rate_is_f0 {
                self.stage.copy_from_slice(y);
                for j in 0..i {
                    let a = co.a[i][j];
                    if a != 0.0 {
                        for (s, &u) in self.stage.iter_mut().zip(&self.u[j]) {
                            *s += a * u;
                        }
                    }
                }
                let refusal =
                    rate_or_refusal(sys, t + co.nodes[i] * dt, &self.stage, &mut self.rhs)?;
                out.evaluations += 1;
                if let Some(e) = refusal {
                    out.end = End::Refused(e);
                    return Ok(out);
                }
            } else {
                self.rhs.copy_from_slice(&self.f0);
            }
            // rhs = F + Σ (c_ij/h) u_j + γ_i h f_t, scaled by hγ and the weights.
            for j in 0..i {
                let c = co.c[i][j] / dt;
                for (r, &u) in self.rhs.iter_mut().zip(&self.u[j]) {
                    *r += c * u;
                }
            }
            let g = co.gamma_sums[i] * dt;
            for ((r, &ft), &w) in self.rhs.iter_mut().zip(&self.ft).zip(&self.weights) {
                *r = (*r + g * ft) * h_gamma * w;
            }
            if self.rhs.iter().any(|x| !x.is_finite()) {
                return Ok(out);
            }
            let mut op = StageOperator {
                sys: &mut *sys,
                t,
                y,
                f0: &self.f0,
                weights: &self.weights,
                h_gamma,
                fd,
                probe: &mut self.probe,
                probe_rate: &mut self.probe_rate,
                blocks: self.preconditioned.then_some((&self.blocks, &self.factors)),
                refusal: None,
            };
            let solved = self.gmres.solve(
                &mut op,
                &self.rhs,
                &mut self.scaled,
                (self.ros.krylov_tolerance, self.ros.max_krylov_iterations),
            );
            let refusal = op.refusal.take();
            let solved = match solved {
                Ok(s) => s,
                Err(()) => {
                    match refusal {
                        Some(Probe::Refused(e)) => out.end = End::Refused(e),
                        Some(Probe::Failed(e)) => return Err(e),
                        None => {}
                    }
                    return Ok(out);
                }
            };
            out.evaluations += solved.applications;
            out.krylov_iterations += solved.iterations;
            if !solved.converged {
                out.end = if solved.residual.is_finite() {
                    End::Linear {
                        iterations: solved.iterations,
                        residual: solved.residual,
                    }
                } else {
                    End::NonFinite
                };
                return Ok(out);
            }
            for ((u, &x), &w) in self.u[i].iter_mut().zip(&self.scaled).zip(&self.weights) {
                *u = x / w;
            }
        }
        // y₁ and the error estimate.
        self.stage.copy_from_slice(y);
        self.rhs.fill(0.0);
        for i in 0..STAGES {
            let (m, e) = (co.m[i], co.m[i] - co.m_hat[i]);
            for ((s, r), &u) in self
                .stage
                .iter_mut()
                .zip(self.rhs.iter_mut())
                .zip(&self.u[i])
            {
                *s += m * u;
                *r += e * u;
            }
        }
        if self.stage.iter().all(|x| x.is_finite()) {
            out.end = End::Error(sys.scaled_error(y, &self.stage, &self.rhs));
        }
        Ok(out)
    }
}

/// How an attempt ended.
enum End<E> {
    /// Its scaled error estimate.
    Error(f64),
    /// A non-finite stage or solve.
    NonFinite,
    /// A stage outside the system's domain.
    Refused(E),
    /// A linear solve that did not converge.
    Linear { iterations: usize, residual: f64 },
}

struct Attempt<E> {
    evaluations: usize,
    krylov_iterations: usize,
    end: End<E>,
}

/// Why a probe of the Jacobian's action stopped GMRES.
enum Probe<E> {
    Refused(E),
    Failed(E),
}

/// `I − hγ J` in the error weights (`ṽ = w ⊙ v`), `J v` by a finite difference at
/// `(t, y)`, and the blocks' preconditioner.
struct StageOperator<'a, S: OdeSystem> {
    sys: &'a mut S,
    t: f64,
    y: &'a [f64],
    f0: &'a [f64],
    weights: &'a [f64],
    h_gamma: f64,
    /// The difference's size in the weighted max norm.
    fd: f64,
    probe: &'a mut Vec<f64>,
    probe_rate: &'a mut Vec<f64>,
    blocks: Option<(&'a JacobianBlocks, &'a BlockFactors)>,
    refusal: Option<Probe<S::Error>>,
}

impl<S: OdeSystem> LinearOperator for StageOperator<'_, S> {
    type Error = ();

    fn apply(&mut self, v: &[f64], out: &mut [f64]) -> std::result::Result<(), ()> {
        let vnorm = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        if vnorm == 0.0 {
            out.fill(0.0);
            return Ok(());
        }
        if !vnorm.is_finite() {
            out.fill(f64::NAN);
            return Ok(());
        }
        let sigma = self.fd / vnorm;
        for (((p, &yi), &vi), &w) in self.probe.iter_mut().zip(self.y).zip(v).zip(self.weights) {
            *p = yi + sigma * vi / w;
        }
        match self.sys.rate(self.t, self.probe, self.probe_rate) {
            Ok(()) => {}
            Err(e) if self.sys.outside_domain(&e) => {
                self.refusal = Some(Probe::Refused(e));
                return Err(());
            }
            Err(e) => {
                self.refusal = Some(Probe::Failed(e));
                return Err(());
            }
        }
        let c = self.h_gamma / sigma;
        for ((((o, &vi), &fp), &f0), &w) in out
            .iter_mut()
            .zip(v)
            .zip(self.probe_rate.iter())
            .zip(self.f0)
            .zip(self.weights)
        {
            *o = vi - c * (fp - f0) * w;
        }
        Ok(())
    }

    fn precondition(&self, v: &mut [f64]) {
        if let Some((blocks, factors)) = self.blocks {
            for (x, &w) in v.iter_mut().zip(self.weights) {
                *x /= w;
            }
            factors.solve(blocks, v);
            for (x, &w) in v.iter_mut().zip(self.weights) {
                *x *= w;
            }
        }
    }
}

#[cfg(test)]
mod tests;
