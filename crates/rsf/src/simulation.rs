//! The coupled time step: relaxed fixed point iteration between the velocity problem and
//! the state update (docs/math.md §4, paper §6.2), and the simulation loop.

use std::time::Instant;

use rsf_fem::{combine, SparseMatrix};
use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::{
    check_time_step, Kinematics, LoadOperator, StepControl, StepController, VelocityIntegrator,
};
use rsf_tnnmg::{StepSolver, Stopping};

use crate::checkpoint::Checkpoint;
use crate::error::{invalid, Error, Result};
use crate::fixed_point::{Accelerator, FixedPointOptions, Predictor};
use crate::friction_blocks::{norm, FrictionBlocks};
use crate::model::Model;
use crate::observer::{Observer, StepState};
use crate::solver::{SolverKind, VelocitySolver};
use crate::state_integrator::StateIntegrator;

/// What one time step did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepReport {
    /// Step index n (1-based).
    pub step: usize,
    /// Time t_n (s).
    pub time: f64,
    /// The time step τ of this step (s).
    pub tau: f64,
    /// Fixed point iterations (velocity solves) of this step.
    pub fixed_point_iterations: usize,
    /// Velocity-solver iterations summed over the fixed point iterations.
    pub solver_iterations: usize,
    /// Fixed point iterations that took a damped step (the paper's ω < 1, or the fallback
    /// of Anderson acceleration).
    pub relaxed_iterations: usize,
    /// Last fixed point correction `‖v^{ν+1} − v^ν‖` (energy norm).
    pub correction: f64,
    /// The quantity the fixed point test compared with the tolerance: the last correction,
    /// or the estimated error `θ/(1 − θ) · correction` (see
    /// [`FixedPointOptions::error_estimate`](crate::FixedPointOptions::error_estimate)).
    pub fixed_point_error: f64,
    /// Largest slip rate on Γ_F after the step (m/s).
    pub max_slip_rate: f64,
    /// Adaptive steps: attempts rejected before this step was accepted.
    pub rejected_attempts: usize,
    /// Adaptive steps: the scaled local error estimate of the accepted step (≤ 1).
    pub error_estimate: f64,
    /// Wall time of the step (s; not part of any numerical output).
    pub seconds: f64,
}

/// Summary of a run of several steps.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunSummary {
    /// Steps taken.
    pub steps: usize,
    /// Wall time (s).
    pub seconds: f64,
    /// Mean fixed point iterations per step.
    pub fpi_mean: f64,
    /// Maximum fixed point iterations of a step.
    pub fpi_max: usize,
    /// Total velocity-solver iterations.
    pub solver_iterations: usize,
    /// Steps in which a damped step was taken at least once.
    pub relaxed_steps: usize,
    /// Whether an observer ended the run before its end.
    pub stopped_by_observer: bool,
    /// Adaptive steps: rejected attempts over the run.
    pub rejected_attempts: usize,
}

/// Where [`Simulation::run_until`] ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Until {
    /// After this many steps.
    Steps(usize),
    /// At the first step with `t_n ≥ t` (s), up to round-off of `1e-9 min(τ, |t|)`. With a
    /// fixed τ the last step is not shortened to land on `t`; with adaptive steps it is, so
    /// the run ends at `t`.
    Time(f64),
}

/// Whether `time` has reached `t_end` for steps of `tau`, up to [`time_slack`].
pub(crate) fn time_reached(time: f64, t_end: f64, tau: f64) -> bool {
    time >= t_end - time_slack(t_end, tau)
}

/// Round-off allowance of a comparison with the time `t` for steps of `tau` (s):
/// `1e-9 · min(τ, |t|)`. Relative to τ, so that a time that lands next to `t` by round-off
/// is not followed by a sliver of a step; at most `1e-9 |t|`, so that a huge step (τ ≫ |t|)
/// does not swallow `t` itself.
pub(crate) fn time_slack(t: f64, tau: f64) -> f64 {
    1e-9 * tau.min(t.abs())
}

/// A placeholder state law for friction laws without state (plain Tresca): α never changes
/// and no state update is ever computed.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NoState;

impl StateLaw for NoState {
    fn dpsi_dalpha(&self, _alpha: f64, _v: f64) -> f64 {
        0.0
    }
    fn update(&self, alpha_prev: f64, _v: f64, _tau: f64) -> rsf_state::Result<f64> {
        Ok(alpha_prev)
    }
}

/// A running simulation of a [`Model`] with friction law `L`, state law `S` (one law value
/// per frictional node each, for heterogeneous faults) and velocity integrator `I`.
///
/// Each [`step`](Self::step) solves the coupled problem at `t_n = n τ` by the paper's
/// relaxed fixed point iteration. Everything is single-threaded and deterministic: the
/// same model, parameters and build give bit-identical results, also across
/// [`checkpoint`](Self::checkpoint) / [`restore`](Self::restore).
pub struct Simulation<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator> {
    model: Model<D>,
    friction: FrictionBlocks<L>,
    state_laws: Vec<S>,
    state_integrator: StateIntegrator,
    integrator: I,
    solver: VelocitySolver<D>,
    solver_kind: SolverKind,
    /// Solvers of earlier time steps, most recently used last (see `set_time_step`).
    solver_cache: Vec<(f64, VelocitySolver<D>)>,
    inner_stopping: Stopping,
    tau: f64,
    /// Time t_n (s) after `step` steps.
    time: f64,
    /// Step index and time where the current τ began: `t_n = t_s + (n − n_s) τ`.
    segment: (usize, f64),
    fixed_point: FixedPointOptions,
    accelerator: Accelerator,
    /// Adaptive time steps (None: fixed τ).
    controller: Option<StepController>,
    u_err: Vec<f64>,
    step: usize,
    kin: Kinematics,
    next: Kinematics,
    alpha: Vec<f64>,
    load_operator: LoadOperator,
    w_mass: Vec<f64>,
    w_stiffness: Vec<f64>,
    rhs: Vec<f64>,
    v: Vec<f64>,
    alpha_iter: Vec<f64>,
    alpha_trial: Vec<f64>,
    /// `alpha_trial` after local extrapolation, computed with the error estimate.
    alpha_extrapolated: Vec<f64>,
    slip: Vec<f64>,
    history: Vec<f64>,
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator> Simulation<D, L, S, I> {
    /// Sets up the simulation: assembles `A = c_M M + c_K K` (+ radiation damping), builds
    /// the solver, and starts from `u_0 = model.initial_displacement`, `v_0 = V_D(0)`,
    /// `a_0 = 0`, `α = alpha0` (one value per frictional node, in `model.frictional.nodes`
    /// order).
    ///
    /// `state_laws` has one law per frictional node, or may be empty when no friction law
    /// uses the state (Tresca).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for inconsistent lengths, τ ≤ 0 or non-finite values,
    /// a missing mass matrix for a dynamic integrator; the consistency errors
    /// [`Error::FreeNormal`] (a frictional node without fixed normal component),
    /// [`Error::StateVariableMismatch`] (friction and state law disagree on α),
    /// [`Error::StateLaw`] (a state law fails its monotonicity probe); set-up errors of the
    /// solver.
    pub fn new(
        model: Model<D>,
        friction_laws: Vec<L>,
        state_laws: Vec<S>,
        alpha0: Vec<f64>,
        integrator: I,
        tau: f64,
        solver: &SolverKind,
        fixed_point: FixedPointOptions,
    ) -> Result<Self> {
        crate::checks::check_construction(&model, &friction_laws, &state_laws, tau)?;
        model.validate()?;
        check_time_step(tau)
            .map_err(|_| invalid("time_step_s", format!("τ = {tau} must be finite and > 0")))?;
        let nf = model.frictional.len();
        if friction_laws.len() != nf {
            return Err(invalid(
                "friction",
                format!("{} laws for {nf} frictional nodes", friction_laws.len()),
            ));
        }
        if alpha0.len() != nf || alpha0.iter().any(|a| !a.is_finite()) {
            return Err(invalid("alpha0", format!("needs {nf} finite values")));
        }
        let uses_state = friction_laws.iter().any(|l| l.uses_state());
        if uses_state && state_laws.len() != nf {
            return Err(invalid(
                "state_law",
                format!("{} laws for {nf} frictional nodes", state_laws.len()),
            ));
        }
        fixed_point.validate()?;
        if integrator.uses_mass() && model.mass.is_none() {
            return Err(invalid(
                "mass",
                format!("{} needs the mass matrix", integrator.name()),
            ));
        }
        let load_operator = LoadOperator::new(
            model.mass.as_ref().filter(|_| integrator.uses_mass()),
            &model.stiffness,
        )?;
        let inner_stopping = solver.stopping();
        let solver_kind = solver.resolve(&model);
        let solver = build_solver(&model, &integrator, &solver_kind, tau)?;
        let accelerator = Accelerator::new(fixed_point.acceleration, &model.frictional.weights);
        let n = model.num_dofs();
        let mut kin = Kinematics::zeros(n);
        kin.u.copy_from_slice(&model.initial_displacement);
        let friction = FrictionBlocks::new(
            model.frictional.nodes.clone(),
            model.frictional.weights.clone(),
            friction_laws,
            &alpha0,
        );
        let mut sim = Self {
            friction,
            state_laws,
            state_integrator: StateIntegrator::BackwardEuler,
            integrator,
            solver,
            solver_kind,
            solver_cache: Vec::new(),
            inner_stopping,
            tau,
            time: 0.0,
            segment: (0, 0.0),
            fixed_point,
            accelerator,
            controller: None,
            u_err: vec![0.0; n],
            step: 0,
            next: Kinematics::zeros(n),
            alpha: alpha0,
            load_operator,
            w_mass: vec![0.0; n],
            w_stiffness: vec![0.0; n],
            rhs: vec![0.0; n],
            v: vec![0.0; n],
            alpha_iter: vec![0.0; nf],
            alpha_trial: vec![0.0; nf],
            alpha_extrapolated: vec![0.0; nf],
            slip: vec![0.0; nf],
            history: Vec::with_capacity(fixed_point.max_iterations),
            kin,
            model,
        };
        let mut v0 = std::mem::take(&mut sim.kin.v);
        sim.impose_dirichlet(0.0, &mut v0);
        sim.kin.v = v0;
        Ok(sim)
    }

    /// The model.
    pub fn model(&self) -> &Model<D> {
        &self.model
    }

    /// Current `(u, v, a)`.
    pub fn kinematics(&self) -> &Kinematics {
        &self.kin
    }

    /// Current state α per frictional node (`model.frictional.nodes` order).
    pub fn alpha(&self) -> &[f64] {
        &self.alpha
    }

    /// Steps taken so far.
    pub fn step_index(&self) -> usize {
        self.step
    }

    /// Current time `t_n` (s): `n τ` for a run at constant τ.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Time of step `n` of the current segment of constant τ: `t_s + (n − n_s) τ` (exactly
    /// `n τ` for a run at constant τ from the start).
    fn time_of(&self, n: usize) -> f64 {
        let (n0, t0) = self.segment;
        t0 + (n - n0) as f64 * self.tau
    }

    /// Changes the time step for the following steps (s). The matrix `A` of the velocity
    /// problem depends on τ, so its solver is rebuilt (or taken from a small cache of the
    /// last solvers used: returning to an earlier τ costs nothing). The dynamic state
    /// `(u, v, a, α)` carries over unchanged: the integrators are one-step methods.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `tau` unless `tau` is finite and positive and the
    /// matrix `c_M M + c_K K` is finite at it (e.g. `2/τ` overflows for τ < 1e-308); set-up
    /// errors of the solver (e.g. a factorisation that fails).
    pub fn set_time_step(&mut self, tau: f64) -> Result<()> {
        check_time_step(tau)
            .map_err(|_| invalid("tau", format!("τ = {tau} s must be finite and > 0")))?;
        if tau.to_bits() == self.tau.to_bits() {
            return Ok(());
        }
        let solver = match self
            .solver_cache
            .iter()
            .position(|(t, _)| t.to_bits() == tau.to_bits())
        {
            Some(i) => self.solver_cache.remove(i).1,
            None => self.solver.for_matrix(
                &self.solver_kind,
                &time_step_matrix(&self.model, &self.integrator, tau)?,
                &self.model,
            )?,
        };
        let old = std::mem::replace(&mut self.solver, solver);
        self.solver_cache.push((self.tau, old));
        if self.solver_cache.len() > SOLVER_CACHE {
            self.solver_cache.remove(0);
        }
        self.tau = tau;
        self.segment = (self.step, self.time);
        Ok(())
    }

    /// The time step τ (s).
    pub fn tau(&self) -> f64 {
        self.tau
    }

    /// Name of the velocity solver.
    pub fn solver_name(&self) -> &'static str {
        StepSolver::name(&self.solver)
    }

    /// The fixed point options.
    pub fn fixed_point_options(&self) -> &FixedPointOptions {
        &self.fixed_point
    }

    /// Slip rates `|v_p|` on Γ_F (m/s) into `out`, in `model.frictional.nodes` order.
    pub fn slip_rates(&self, out: &mut [f64]) {
        slip_rates::<D>(&self.model.frictional.nodes, &self.kin.v, out);
    }

    fn impose_dirichlet(&self, t: f64, v: &mut [f64]) {
        for (vi, &f) in v.iter_mut().zip(&self.model.fixed) {
            if f {
                *vi = 0.0;
            }
        }
        let speed = self.model.dirichlet.speed(t);
        for (&d, &f) in self
            .model
            .dirichlet
            .dofs
            .iter()
            .zip(&self.model.dirichlet.factors)
        {
            v[d] = f * speed;
        }
    }

    /// `|v_p|` of the solver's current iterate on Γ_F into `slip`.
    fn read_slip_rates(&mut self) {
        for (k, s) in self.slip.iter_mut().enumerate() {
            *s = norm::<D>(&self.solver.block(k));
        }
    }

    /// `α̃ = S(α_{n−1}, slip)`, the backward Euler state update (3.5) from the step's
    /// initial state, into `alpha_trial`.
    fn state_update(&mut self) -> Result<()> {
        for k in 0..self.slip.len() {
            self.alpha_trial[k] = self.state_integrator.update(
                &self.state_laws[k],
                self.alpha[k],
                self.slip[k],
                self.tau,
            )?;
        }
        Ok(())
    }

    /// Advances one time step.
    ///
    /// # Errors
    /// [`Error::FixedPointNotConverged`] with the correction history; solver and state
    /// update errors. On error the simulation state is unchanged.
    pub fn step(&mut self) -> Result<StepReport> {
        let start = Instant::now();
        let mut report = match self.controller.is_some() {
            false => {
                let r = self.attempt()?;
                self.commit(&r);
                r
            }
            true => self.adaptive_step(None)?,
        };
        report.seconds = start.elapsed().as_secs_f64();
        Ok(report)
    }

    /// Attempts with the controller's step until one is accepted (docs/math.md §9). A step
    /// that would pass `t_end` or a breakpoint of the loading
    /// ([`TimeFunction::next_breakpoint`](crate::TimeFunction::next_breakpoint)) is
    /// shortened to end there (off the ladder; the controller keeps its step for later).
    fn adaptive_step(&mut self, t_end: Option<f64>) -> Result<StepReport> {
        let mut rejected = 0;
        // A breakpoint closer than the round-off allowance is taken as reached (no sliver of
        // a step).
        let tau_now = self.controller.as_ref().expect("adaptive").tau();
        let breakpoint = self
            .model
            .dirichlet
            .history
            .next_breakpoint(self.time + time_slack(self.time, tau_now));
        let stop = match (t_end, breakpoint) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        loop {
            let mut tau = self.controller.as_ref().expect("adaptive").tau();
            let mut clipped = false;
            if let Some(stop) = stop {
                let left = stop - self.time;
                if left < tau * (1.0 - 1e-9) {
                    tau = left;
                    clipped = true;
                }
            }
            self.set_time_step(tau)?;
            let attempt = self.attempt();
            let controller = self.controller.as_mut().expect("adaptive");
            match attempt {
                Ok(mut report) => {
                    let (err, state_change) = self.error_estimate();
                    let controller = self.controller.as_mut().expect("adaptive");
                    if err <= 1.0 {
                        if !clipped {
                            controller.accept(err, state_change);
                        }
                        report.rejected_attempts = rejected;
                        report.error_estimate = err;
                        if self
                            .controller
                            .as_ref()
                            .expect("adaptive")
                            .options()
                            .state_extrapolation
                        {
                            self.extrapolate_state();
                        }
                        self.commit(&report);
                        return Ok(report);
                    }
                    controller.reject(err)?;
                }
                Err(e) if recoverable(&e) => {
                    if controller.reject(f64::INFINITY).is_err() {
                        return Err(e);
                    }
                }
                Err(e) => return Err(e),
            }
            rejected += 1;
        }
    }

    /// The scaled local error of the attempted step (in `next`, `alpha_trial`) and the
    /// largest change of the state: the largest of `rms(e_u) / (atol + tol · rms(u − u₀))`
    /// over the free dofs, with the integrator's estimate `e_u`, of the slip test
    /// `(Δ ln(V_p + V_f))² / (12 tol)` at each frictional node p (if enabled), and the
    /// maximum over Γ_F of the state update's estimated local error over
    /// `tol + state_atol/θ` ([`StateIntegrator`]; backward Euler: `(τ/2)|α̇_n − α̇_{n−1}|`,
    /// i.e. `τ²/2 · α̈`, docs/math.md §9; a non-finite estimate rejects the step). Leaves
    /// the locally extrapolated states in `alpha_extrapolated`.
    fn error_estimate(&mut self) -> (f64, f64) {
        let c = *self.controller.as_ref().expect("adaptive").options();
        let mut u_err = std::mem::take(&mut self.u_err);
        self.integrator
            .displacement_error(self.tau, &self.kin, &self.next, &mut u_err);
        let u0 = &self.model.initial_displacement;
        // Root mean square over the free dofs (a discrete L² norm on the uniform meshes of
        // this crate's scenes): the displacement error is a property of the whole body.
        let (mut e2, mut d2, mut count) = (0.0, 0.0, 0usize);
        for i in 0..u_err.len() {
            if self.model.fixed[i] {
                continue;
            }
            let d = (self.kin.u[i] - u0[i])
                .abs()
                .max((self.next.u[i] - u0[i]).abs());
            e2 += u_err[i] * u_err[i];
            d2 += d * d;
            count += 1;
        }
        let count = count.max(1) as f64;
        let scale = c.displacement_atol + c.tolerance * (d2 / count).sqrt();
        let mut err = (e2 / count).sqrt() / scale;
        if let Some(v_floor) = c.slip_rate_floor {
            // The relative error of the slip of the step at each frictional node: the
            // trapezoidal slip (τ/2)(V_{n−1} + V_n) of a slip rate exponential in time is
            // off by (Δ ln V)²/12 (docs/math.md §9).
            for &p in &self.model.frictional.nodes {
                let v0 = block_norm::<D>(&self.kin.v, p);
                let v1 = block_norm::<D>(&self.next.v, p);
                let d = ((v1 + v_floor) / (v0 + v_floor)).ln();
                err = err.max(d * d / (12.0 * c.tolerance));
            }
        }
        if err.is_nan() {
            err = f64::INFINITY;
        }
        self.u_err = u_err;
        let mut state_change: f64 = 0.0;
        if self.friction.uses_state() {
            for (k, &p) in self.model.frictional.nodes.iter().enumerate() {
                let (a0, a1) = (self.alpha[k], self.alpha_trial[k]);
                let v0 = block_norm::<D>(&self.kin.v, p);
                let v1 = block_norm::<D>(&self.next.v, p);
                let (e, extrapolated) = self.state_integrator.local_error(
                    &self.state_laws[k],
                    (a0, v0),
                    (a1, v1),
                    self.tau,
                );
                self.alpha_extrapolated[k] = extrapolated.unwrap_or(a1);
                // |δθ| ≤ state_atol + tol·θ, i.e. |δα| ≤ tol + state_atol/θ (θ = e^α the
                // larger state of the step); an overflowing 1/θ leaves the absolute part.
                let scale = if c.state_atol > 0.0 {
                    c.tolerance + c.state_atol * (-a0.max(a1)).exp()
                } else {
                    c.tolerance
                };
                err = err.max(if e.is_finite() {
                    e / scale
                } else {
                    f64::INFINITY
                });
                state_change = state_change.max((a1 - a0).abs());
            }
        }
        (err, state_change)
    }

    /// Local extrapolation of the attempted state `alpha_trial` (docs/math.md §9), with the
    /// values [`error_estimate`](Self::error_estimate) computed for this attempt: backward
    /// Euler's estimated local error `(τ/2)(α̇_{n−1} − α̇_n)` added, damped by
    /// `1 / (1 + τ ∂²ψ/∂α²)` where the state equation is stiff (skipped at a node where the
    /// correction is not finite or the law has no second derivative); for the exact update
    /// at constant slip rate, the mean of the updates with the step's two slip rates.
    fn extrapolate_state(&mut self) {
        if self.friction.uses_state() {
            self.alpha_trial.copy_from_slice(&self.alpha_extrapolated);
        }
    }

    /// Makes the attempted step (in `next`, `alpha_trial`) the current state.
    fn commit(&mut self, report: &StepReport) {
        std::mem::swap(&mut self.kin, &mut self.next);
        if self.friction.uses_state() {
            self.alpha.copy_from_slice(&self.alpha_trial);
        }
        self.step = report.step;
        self.time = report.time;
    }

    /// Solves the coupled problem of the next step at the current τ, leaving the new state
    /// in `next` (kinematics) and `alpha_trial` (state) without committing it.
    fn attempt(&mut self) -> Result<StepReport> {
        let n = self.step + 1;
        let t = self.time_of(n);
        let mut report = StepReport {
            step: n,
            time: t,
            tau: self.tau,
            ..Default::default()
        };
        self.integrator.load_combinations(
            self.tau,
            &self.kin,
            &mut self.w_mass,
            &mut self.w_stiffness,
        )?;
        self.load_operator.apply(
            &self.model.load,
            &self.w_mass,
            &self.w_stiffness,
            &mut self.rhs,
        );
        // Predictor v⁰ with the Dirichlet data of t_n.
        let mut v = std::mem::take(&mut self.v);
        v.copy_from_slice(&self.kin.v);
        if self.fixed_point.predictor == Predictor::Extrapolated {
            for (vi, ai) in v.iter_mut().zip(&self.kin.a) {
                *vi += self.tau * ai;
            }
        }
        self.impose_dirichlet(t, &mut v);
        let begun = self
            .solver
            .begin_step(&self.rhs, &v, &self.model.frictional.nodes);
        self.v = v;
        begun?;
        self.history.clear();
        let full = self.inner_stopping;
        if !self.friction.uses_state() {
            let r = self.solver.solve_step(&self.friction, full)?;
            report.solver_iterations += r.iterations;
            report.fixed_point_iterations = 1;
            report.correction = self.solver.last_change();
            report.fixed_point_error = 0.0;
        } else {
            // α⁰ = S(α_{n−1}, |v⁰|), then the fixed point iteration (docs/math.md §4, §8).
            self.read_slip_rates();
            self.state_update()?;
            self.alpha_iter.copy_from_slice(&self.alpha_trial);
            let first: f64 = {
                let w = &self.model.frictional.weights;
                (0..w.len())
                    .map(|k| w[k] * (self.alpha_iter[k] - self.alpha[k]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            };
            self.accelerator.begin(first);
            let mut converged = false;
            let mut last = f64::INFINITY;
            let mut previous = f64::INFINITY;
            for nu in 0..self.fixed_point.max_iterations {
                let stopping = match self.fixed_point.inexact_factor {
                    Some(kappa) if nu > 0 => Stopping {
                        absolute: full.absolute.max(kappa * last),
                        ..full
                    },
                    _ => full,
                };
                self.friction.set_state(&self.alpha_iter);
                let r = self.solver.solve_step(&self.friction, stopping)?;
                report.solver_iterations += r.iterations;
                report.fixed_point_iterations += 1;
                let c = self.solver.last_change();
                self.history.push(c);
                report.correction = c;
                last = c;
                let exact = stopping.absolute <= full.absolute;
                let tol = self.fixed_point.tolerance;
                let theta = c / previous;
                let estimate = if self.fixed_point.error_estimate
                    && nu > 0
                    && theta <= 0.5
                    && c <= ESTIMATE_GUARD * tol
                {
                    theta / (1.0 - theta) * c
                } else {
                    c
                };
                report.fixed_point_error = estimate;
                let small = estimate <= tol;
                previous = c;
                if small && exact && !(nu == 0 && self.fixed_point.paper_first_iteration) {
                    converged = true;
                    break;
                }
                // Next state iterate from G(α^ν) = S(α_{n−1}, |v^{ν+1}|).
                self.read_slip_rates();
                self.state_update()?;
                self.accelerator
                    .next(&mut self.alpha_iter, &self.alpha_trial);
            }
            report.relaxed_iterations = self.accelerator.damped;
            if !converged {
                return Err(Error::FixedPointNotConverged {
                    step: n,
                    time: t,
                    iterations: self.fixed_point.max_iterations,
                    history: self.history.clone(),
                });
            }
        }
        // Commit: v_n from the solver (bulk recovery), α_n = S(α_{n−1}, |v_n|), (u, a).
        let mut v = std::mem::take(&mut self.v);
        let finished = self.solver.finish_step(&mut v);
        self.v = v;
        finished?;
        if self.friction.uses_state() {
            self.read_slip_rates();
            self.state_update()?;
        }
        self.integrator
            .advance(self.tau, &self.kin, &self.v, &mut self.next);
        report.max_slip_rate = self
            .model
            .frictional
            .nodes
            .iter()
            .map(|&p| block_norm::<D>(&self.next.v, p))
            .fold(0.0, f64::max);
        Ok(report)
    }

    /// Takes `steps` steps, showing each to the observers; an observer may end the run
    /// early ([`Flow::Break`](crate::Flow)). Same as [`run_until`](Self::run_until) with
    /// [`Until::Steps`].
    ///
    /// # Errors
    /// The first step or observer error (the simulation keeps the state of the last
    /// successful step).
    pub fn run(
        &mut self,
        steps: usize,
        observers: &mut [&mut dyn Observer<D>],
    ) -> Result<RunSummary> {
        self.run_until(Until::Steps(steps), observers)
    }

    /// Steps until `until` is reached or an observer returns [`Flow::Break`](crate::Flow) (after every
    /// observer has seen that step), then calls every observer's
    /// [`finish`](Observer::finish).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-finite end time; the first step or observer
    /// error (the simulation keeps the state of the last successful step).
    pub fn run_until(
        &mut self,
        until: Until,
        observers: &mut [&mut dyn Observer<D>],
    ) -> Result<RunSummary> {
        if let Until::Time(t) = until {
            if !t.is_finite() {
                return Err(invalid("until", format!("end time {t} s must be finite")));
            }
        }
        let start = Instant::now();
        let mut summary = RunSummary::default();
        let mut fpi_total = 0usize;
        loop {
            let more = match until {
                Until::Steps(k) => summary.steps < k,
                Until::Time(t_end) => !time_reached(self.time, t_end, self.tau),
            };
            if !more {
                break;
            }
            let report = match (until, self.controller.is_some()) {
                (Until::Time(t_end), true) => {
                    let start = Instant::now();
                    let mut r = self.adaptive_step(Some(t_end))?;
                    r.seconds = start.elapsed().as_secs_f64();
                    r
                }
                _ => self.step()?,
            };
            fpi_total += report.fixed_point_iterations;
            summary.fpi_max = summary.fpi_max.max(report.fixed_point_iterations);
            summary.solver_iterations += report.solver_iterations;
            summary.relaxed_steps += usize::from(report.relaxed_iterations > 0);
            summary.rejected_attempts += report.rejected_attempts;
            summary.steps += 1;
            let state = StepState {
                model: &self.model,
                kinematics: &self.kin,
                alpha: &self.alpha,
                report: &report,
                time_origin: self.segment,
                controller: self.controller.as_ref(),
            };
            let mut stop = false;
            for o in observers.iter_mut() {
                stop |= o.observe(&state)?.is_break();
            }
            if stop {
                summary.stopped_by_observer = true;
                break;
            }
        }
        for o in observers.iter_mut() {
            o.finish()?;
        }
        summary.fpi_mean = if summary.steps > 0 {
            fpi_total as f64 / summary.steps as f64
        } else {
            0.0
        };
        summary.seconds = start.elapsed().as_secs_f64();
        Ok(summary)
    }

    /// The complete dynamic state, for [`restore`](Self::restore).
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            dim: D,
            step: self.step,
            time: self.time,
            tau: self.tau,
            time_origin: self.segment,
            controller: self
                .controller
                .as_ref()
                .map_or_else(Vec::new, StepController::to_state),
            u: self.kin.u.clone(),
            v: self.kin.v.clone(),
            a: self.kin.a.clone(),
            alpha: self.alpha.clone(),
        }
    }

    /// Switches to adaptive time steps with error control (docs/math.md §9) starting from
    /// the current τ, or back to a fixed τ (`None`, keeping the current τ). Adaptive steps
    /// are shortened to end on the breakpoints of the loading history
    /// ([`TimeFunction::next_breakpoint`](crate::TimeFunction::next_breakpoint)) and on the
    /// end time of [`run_until`](Self::run_until).
    ///
    /// # Errors
    /// Invalid options (the crate `rsf_time`'s error).
    pub fn set_step_control(&mut self, control: Option<StepControl>) -> Result<()> {
        self.controller = match control {
            Some(c) => Some(StepController::new(c, self.tau)?),
            None => None,
        };
        Ok(())
    }

    /// Chooses how a step advances the state ([`StateIntegrator`]; default backward Euler,
    /// the paper's). Takes effect from the next step.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `state_integrator` if a frictional node's state law
    /// does not support it.
    pub fn set_state_integrator(&mut self, integrator: StateIntegrator) -> Result<()> {
        if self.friction.uses_state() {
            for law in &self.state_laws {
                integrator.check(law)?;
            }
        }
        self.state_integrator = integrator;
        Ok(())
    }

    /// How a step advances the state.
    pub fn state_integrator(&self) -> StateIntegrator {
        self.state_integrator
    }

    /// The step controller of adaptive time steps, if any.
    pub fn step_controller(&self) -> Option<&StepController> {
        self.controller.as_ref()
    }

    /// Continues from a checkpoint of a simulation of the same model; the continuation is
    /// bit-identical to an uninterrupted run. The checkpoint's τ becomes the time step
    /// (see [`set_time_step`](Self::set_time_step)).
    ///
    /// # Errors
    /// [`Error::Checkpoint`] if dimensions or sizes differ or values are not finite;
    /// solver set-up errors for a new τ.
    pub fn restore(&mut self, c: &Checkpoint) -> Result<()> {
        let n = self.model.num_dofs();
        if c.dim != D
            || c.u.len() != n
            || c.v.len() != n
            || c.a.len() != n
            || c.alpha.len() != self.alpha.len()
        {
            return Err(Error::Checkpoint(
                "sizes do not match this simulation".into(),
            ));
        }
        if !(c.time.is_finite() && c.time >= 0.0)
            || [&c.u, &c.v, &c.a, &c.alpha]
                .iter()
                .any(|x| x.iter().any(|y| !y.is_finite()))
        {
            return Err(Error::Checkpoint(
                "non-finite time, displacement, velocity, acceleration or state".into(),
            ));
        }
        self.set_time_step(c.tau)
            .map_err(|e| Error::Checkpoint(format!("τ = {}: {e}", c.tau)))?;
        if let Some(ctrl) = self.controller.as_mut() {
            if !c.controller.is_empty() {
                ctrl.restore_state(&c.controller)
                    .map_err(|e| Error::Checkpoint(format!("controller state: {e}")))?;
            }
        }
        self.step = c.step;
        self.time = c.time;
        // A checkpoint written by a simulation satisfies t = t_s + (n − n_s) τ exactly; an
        // edited one (another τ, another time) starts a new segment of constant τ here.
        let (n0, t0) = c.time_origin;
        self.segment =
            if n0 <= c.step && (t0 + (c.step - n0) as f64 * c.tau).to_bits() == c.time.to_bits() {
                c.time_origin
            } else {
                (c.step, c.time)
            };
        self.kin.u.copy_from_slice(&c.u);
        self.kin.v.copy_from_slice(&c.v);
        self.kin.a.copy_from_slice(&c.a);
        self.alpha.copy_from_slice(&c.alpha);
        Ok(())
    }
}

/// Errors after which an adaptive step is retried with a smaller τ.
fn recoverable(e: &Error) -> bool {
    matches!(
        e,
        Error::FixedPointNotConverged { .. }
            | Error::Solver(rsf_tnnmg::Error::NotConverged { .. })
            | Error::Solver(rsf_tnnmg::Error::NonFinite(_))
            | Error::State(_)
    )
}

/// The error estimate of the fixed point test is used only while the last correction is at
/// most this multiple of the tolerance: a guard against a contraction ratio of two
/// corrections that does not represent the iteration.
const ESTIMATE_GUARD: f64 = 100.0;

/// Solvers of other time steps kept by [`Simulation::set_time_step`].
const SOLVER_CACHE: usize = 8;

/// `A = c_M M + c_K K` (+ radiation damping on Γ_F) for τ and its solver.
fn build_solver<const D: usize, I: VelocityIntegrator>(
    model: &Model<D>,
    integrator: &I,
    kind: &SolverKind,
    tau: f64,
) -> Result<VelocitySolver<D>> {
    let a = time_step_matrix(model, integrator, tau)?;
    Ok(VelocitySolver::new(kind, &a, model)?)
}

/// The matrix `A = c_M M + c_K K` (+ radiation damping) of the velocity problem at `tau`.
fn time_step_matrix<const D: usize, I: VelocityIntegrator>(
    model: &Model<D>,
    integrator: &I,
    tau: f64,
) -> Result<SparseMatrix> {
    let (c_m, c_k) = integrator.coefficients(tau);
    let mut a = match (&model.mass, integrator.uses_mass()) {
        (Some(m), true) => combine(c_m, m, c_k, &model.stiffness)?,
        _ => combine(0.0, &model.stiffness, c_k, &model.stiffness)?,
    };
    let eta = integrator.radiation_damping();
    if eta > 0.0 {
        add_radiation_damping::<D>(&mut a, model, eta);
    }
    if let Some(x) = a.val().iter().find(|x| !x.is_finite()) {
        return Err(invalid(
            "tau",
            format!(
                "τ = {tau:e} s gives a non-finite entry ({x}) of the time-step matrix \
                 c_M M + c_K K (c_M = {c_m:e}, c_K = {c_k:e})"
            ),
        ));
    }
    Ok(a)
}

#[inline]
pub(crate) fn block_norm<const D: usize>(v: &[f64], p: usize) -> f64 {
    let mut x = [0.0; D];
    x.copy_from_slice(&v[D * p..D * p + D]);
    norm(&x)
}

/// `|v_p|` for the listed nodes.
pub(crate) fn slip_rates<const D: usize>(nodes: &[usize], v: &[f64], out: &mut [f64]) {
    for (o, &p) in out.iter_mut().zip(nodes) {
        *o = block_norm::<D>(v, p);
    }
}

/// Adds `η w_p` to the diagonal of every component of each frictional node: the Hessian of
/// the radiation damping term `Σ_p w_p η/2 |v_p|²`.
fn add_radiation_damping<const D: usize>(a: &mut SparseMatrix, model: &Model<D>, eta: f64) {
    let (sym, vals) = a.parts_mut();
    for (&p, &w) in model.frictional.nodes.iter().zip(&model.frictional.weights) {
        for c in 0..D {
            let j = D * p + c;
            let range = sym.col_ptr()[j]..sym.col_ptr()[j + 1];
            if let Ok(k) = sym.row_idx()[range.clone()].binary_search(&j) {
                vals[range.start + k] += eta * w;
            }
        }
    }
}
