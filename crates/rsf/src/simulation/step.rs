//! One coupled time step: the relaxed fixed point iteration between the velocity problem
//! and the state update (docs/math.md §4, §8; paper §6.2), its commit, and changes of τ.

use rsf_friction::FrictionLaw;
use rsf_nonsmooth::{BlockNonlinearity, Scaled, SolveReport, StepSolver, Stopping};
use rsf_state::StateLaw;
use rsf_time::VelocityIntegrator;

use crate::error::{Error, Result};
use crate::friction_blocks::FrictionView;
use crate::method::fixed_point::{FixedPointOptions, Predictor};
use crate::method::solver::VelocitySolver;
use crate::method::state_integrator::StateIntegrator;
use crate::method::{Method, StateShare, StepParts};
use crate::model::fault::{block_norm, norm};
use crate::model::Model;
use crate::problem::Problem;
use crate::report::StepReport;
use crate::simulation_state::SimulationState;

use super::checks;
use super::workspace::{NormalWork, Workspace};

/// The error estimate of the fixed point test is used only while the last correction is at
/// most this multiple of the tolerance: a guard against a contraction ratio of two
/// corrections that does not represent the iteration.
const ESTIMATE_GUARD: f64 = 100.0;

/// The parts of a simulation, borrowed for one step.
pub(crate) struct Stepper<'a, const D: usize, L: FrictionLaw, S, I, const C: usize> {
    pub problem: &'a Problem<D, L, S, C>,
    pub method: &'a mut Method<D, I, C>,
    pub state: &'a mut SimulationState,
    pub work: &'a mut Workspace<L>,
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    Stepper<'_, D, L, S, I, C>
{
    /// Changes the time step (s) for the following steps: the method's solver is replaced
    /// (see [`Method::set_time_step`]); a new segment of constant τ starts at the current
    /// step.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `tau`; set-up errors of the solver. On error
    /// nothing changed.
    pub fn set_time_step(&mut self, tau: f64) -> Result<()> {
        checks::time_step(tau)?;
        if tau.to_bits() == self.state.tau.to_bits() {
            return Ok(());
        }
        self.method
            .set_time_step(self.problem.model(), self.state.tau, tau)?;
        self.state.tau = tau;
        self.state.time_origin = (self.state.step, self.state.time);
        Ok(())
    }

    /// Makes the attempted step (in the workspace's `next`, `alpha_trial`) the current
    /// state.
    pub fn commit(&mut self, report: &StepReport) {
        std::mem::swap(&mut self.state.kinematics, &mut self.work.next);
        if let Some(normal) = &mut self.work.normal {
            normal.tractions.sigma.copy_from_slice(&normal.sigma);
        }
        if let Some(pw) = &mut self.work.pressure {
            pw.tractions.sigma.copy_from_slice(&pw.sigma);
        }
        if self.problem.uses_state() {
            self.state.alpha.copy_from_slice(&self.work.alpha_trial);
        }
        self.state.step = report.step;
        self.state.time = report.time;
    }

    /// Solves the coupled problem of the next step at the current τ, leaving the new state
    /// in the workspace (`next`: kinematics, `alpha_trial`: state) without committing it.
    /// Its stages: the velocity problem's right-hand side and predictor
    /// ([`begin_velocity_problem`]), one solve for a law without state or the fixed point
    /// iteration with the state update, then the step's end ([`end_of_step`]).
    ///
    /// # Errors
    /// [`Error::FixedPointNotConverged`] with the correction history; solver and state
    /// update errors.
    pub fn attempt(&mut self) -> Result<StepReport> {
        let model = self.problem.model();
        let state = &*self.state;
        let work = &mut *self.work;
        let method = &mut *self.method;
        let n = state.step + 1;
        let t = state.time_of(n);
        let tau = state.tau;
        let mut report = StepReport {
            step: n,
            time: t,
            tau,
            ..Default::default()
        };
        begin_velocity_problem(method, model, state, work)?;
        let fixed_point = *method.fixed_point();
        // A normal stress from slip needs the iterates' kinematics.
        let integrator = work.normal.as_ref().map(|_| method.integrator().clone());
        work.history.clear();
        let full = method.inner_stopping();
        let inexact = fixed_point.inner_solves.rule(method.solver_kind());
        let state_integrator = method.state_integrator();
        let StepParts {
            solver,
            scaling,
            state_share: mut share,
        } = method.step_parts(tau);
        let laws = self.problem.friction_laws();
        let fb = &model.frictional_boundary;
        // α = S(α_{n−1}, V) of this step, for the iterates and the commit.
        let update = StateUpdate {
            integrator: state_integrator,
            laws: self.problem.state_laws(),
            alpha_prev: &state.alpha,
            tau,
        };
        if !self.problem.uses_state() {
            if let Some(pw) = &mut work.pressure {
                // The bound of a rate-independent law at the end of the step: its normal
                // stress less the pressure of t_n.
                pw.lower_from(t, None)?;
                crate::pore_pressure::potentials_at(
                    laws,
                    &state.alpha,
                    &pw.sigma,
                    &mut work.potentials,
                );
            }
            let r = solve(
                solver,
                &FrictionView::<L>::new(fb, &work.potentials),
                scaling,
                full,
            )?;
            report.solver_iterations += r.iterations;
            report.fixed_point_iterations = 1;
            report.correction = solver.last_change();
            report.fixed_point_error = 0.0;
        } else {
            // α⁰ = S(α_{n−1}, |v⁰|), then the fixed point iteration (docs/math.md §4, §8).
            read_slip_rates(solver, &mut work.slip);
            update.apply(&work.slip, &mut work.alpha_trial, share.as_deref_mut())?;
            work.alpha_iter.copy_from_slice(&work.alpha_trial);
            if let (Some(normal), Some(integrator)) = (&mut work.normal, &integrator) {
                normal_stress_of_iterate(normal, solver, integrator, model, state, &work.v)?;
            }
            let first: f64 = {
                let w = &model.frictional_boundary.weights;
                (0..w.len())
                    .map(|k| w[k] * (work.alpha_iter[k] - state.alpha[k]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            };
            work.accelerator.begin(first);
            let mut converged = false;
            let mut last = f64::INFINITY;
            let mut previous = f64::INFINITY;
            for nu in 0..fixed_point.max_iterations {
                let stopping = inner_stopping(inexact, nu, last, full);
                let view = work.friction_view(laws, fb, t)?;
                let r = solve(solver, &view, scaling, stopping)?;
                report.solver_iterations += r.iterations;
                report.fixed_point_iterations += 1;
                let c = solver.last_change();
                work.history.push(c);
                report.correction = c;
                last = c;
                let exact = stopping.absolute <= full.absolute;
                let estimate = error_estimate(&fixed_point, nu, c, previous);
                report.fixed_point_error = estimate;
                previous = c;
                if estimate <= fixed_point.tolerance
                    && exact
                    && !(nu == 0 && fixed_point.paper_first_iteration)
                {
                    converged = true;
                    break;
                }
                // Next state iterate from G(α^ν) = S(α_{n−1}, |v^{ν+1}|), and the normal
                // stress of v^{ν+1}.
                read_slip_rates(solver, &mut work.slip);
                update.apply(&work.slip, &mut work.alpha_trial, share.as_deref_mut())?;
                if let (Some(normal), Some(integrator)) = (&mut work.normal, &integrator) {
                    normal_stress_of_iterate(normal, solver, integrator, model, state, &work.v)?;
                }
                work.accelerator
                    .next(&mut work.alpha_iter, &work.alpha_trial);
            }
            report.relaxed_iterations = work.accelerator.damped;
            if !converged {
                return Err(Error::FixedPointNotConverged {
                    step: n,
                    time: t,
                    iterations: fixed_point.max_iterations,
                    history: work.history.clone(),
                });
            }
        }
        // Commit: v_n from the solver (bulk recovery), α_n = S(α_{n−1}, |v_n|), (u, a).
        let mut v = std::mem::take(&mut work.v);
        let finished = solver.finish_step(&mut v);
        work.v = v;
        finished?;
        if self.problem.uses_state() {
            read_slip_rates(solver, &mut work.slip);
            update.apply(&work.slip, &mut work.alpha_trial, share)?;
        }
        report.max_slip_rate = end_of_step(method.integrator(), model, state, work)?;
        Ok(report)
    }
}

/// The velocity problem of the step after `state`: the integrator's mass and stiffness
/// combinations at τ, the right-hand side (the absorbing boundaries' far-field force
/// added, scaled where one set-up of the solver serves every τ), the predictor `v⁰` (the
/// last velocity, extrapolated by `τ a` if asked) with the Dirichlet data of `t_n`, and
/// the solver begun on them.
///
/// # Errors
/// The integrator's and the solver's.
fn begin_velocity_problem<const D: usize, L: FrictionLaw, I: VelocityIntegrator, const C: usize>(
    method: &mut Method<D, I, C>,
    model: &Model<D, C>,
    state: &SimulationState,
    work: &mut Workspace<L>,
) -> Result<()> {
    let t = state.time_of(state.step + 1);
    let tau = state.tau;
    method.integrator().load_combinations(
        tau,
        &state.kinematics,
        &mut work.w_mass,
        &mut work.w_stiffness,
    )?;
    method.apply_load(&model.load, &work.w_mass, &work.w_stiffness, &mut work.rhs);
    if let Some(absorbing) = &model.absorbing {
        // The dashpots act on v − v_far: the far field's force g(t_n) C w.
        if !absorbing.far_field_force.is_empty() {
            let g = model.dirichlet.speed(t);
            for (r, f) in work.rhs.iter_mut().zip(&absorbing.far_field_force) {
                *r += g * f;
            }
        }
    }
    // Predictor v⁰ with the Dirichlet data of t_n.
    let mut v = std::mem::take(&mut work.v);
    v.copy_from_slice(&state.kinematics.v);
    if method.fixed_point().predictor == Predictor::Extrapolated {
        for (vi, ai) in v.iter_mut().zip(&state.kinematics.a) {
            *vi += tau * ai;
        }
    }
    impose_dirichlet(model, t, &mut v);
    let (solver, scaling) = method.solver_and_scaling(tau);
    if let Some((s, _)) = scaling {
        for r in &mut work.rhs {
            *r *= s;
        }
    }
    let begun = solver.begin_step(&work.rhs, &v, &model.frictional_boundary.nodes);
    work.v = v;
    begun
}

/// The stopping rule of the inner solve of fixed point iteration `nu` (`last` the
/// previous correction): the full rule, or with inexact inner solves (`inexact`: the
/// factor κ, and whether the first iteration takes one solver iteration) an absolute
/// tolerance of `κ · last` from the second iteration on.
fn inner_stopping(inexact: Option<(f64, bool)>, nu: usize, last: f64, full: Stopping) -> Stopping {
    match inexact {
        Some((kappa, _)) if nu > 0 => Stopping {
            absolute: full.absolute.max(kappa * last),
            ..full
        },
        // One solver iteration: any finite correction passes.
        Some((_, true)) => Stopping {
            absolute: f64::MAX,
            ..full
        },
        _ => full,
    }
}

/// The fixed point test's error after iteration `nu` with correction `c` (`previous` the
/// one before): with the error estimate on, `θ/(1 − θ) c` for a contraction ratio
/// `θ = c/previous ≤ ½` while `c` is at most [`ESTIMATE_GUARD`] tolerances; otherwise `c`.
fn error_estimate(fixed_point: &FixedPointOptions, nu: usize, c: f64, previous: f64) -> f64 {
    let tol = fixed_point.tolerance;
    let theta = c / previous;
    if fixed_point.error_estimate && nu > 0 && theta <= 0.5 && c <= ESTIMATE_GUARD * tol {
        theta / (1.0 - theta) * c
    } else {
        c
    }
}

/// The end of the step from its velocity `work.v`: the kinematics `(u, v, a)` advanced
/// by the integrator, the normal stress of the new state from slip (if any) and the
/// effective normal stress at `t_n`. Returns the largest slip rate on Γ_F (m/s).
///
/// # Errors
/// The normal stress's and the pressure's.
fn end_of_step<const D: usize, L: FrictionLaw, I: VelocityIntegrator, const C: usize>(
    integrator: &I,
    model: &Model<D, C>,
    state: &SimulationState,
    work: &mut Workspace<L>,
) -> Result<f64> {
    let t = state.time_of(state.step + 1);
    integrator.advance(state.tau, &state.kinematics, &work.v, &mut work.next);
    if let Some(normal) = &mut work.normal {
        normal
            .reactions
            .evaluate(model, &work.next, t, &mut normal.sigma, &mut normal.weights)?;
    }
    if let Some(pw) = &mut work.pressure {
        pw.lower_from(t, work.normal.as_ref().map(|n| &n.sigma[..]))?;
    }
    Ok(model
        .frictional_boundary
        .nodes
        .iter()
        .map(|&p| block_norm::<C>(&work.next.v, p))
        .fold(0.0, f64::max))
}

/// One solve of the velocity problem with the friction `nl`, scaled when one set-up of the
/// solver serves every τ (see `Method::solver_and_scaling`).
fn solve<const C: usize, N: BlockNonlinearity<C>>(
    solver: &mut VelocitySolver<C>,
    nl: &N,
    scaling: Option<(f64, &[f64])>,
    stopping: Stopping,
) -> Result<SolveReport> {
    match scaling {
        Some((scale, quadratic)) => solver.solve_step(
            &Scaled {
                inner: nl,
                scale,
                quadratic,
            },
            stopping,
        ),
        None => solver.solve_step(nl, stopping),
    }
}

/// `v` with the Dirichlet data of time `t`: fixed dofs 0, prescribed ones `factor · g(t)`.
pub(crate) fn impose_dirichlet<const D: usize, const C: usize>(
    model: &Model<D, C>,
    t: f64,
    v: &mut [f64],
) {
    for (vi, &f) in v.iter_mut().zip(&model.fixed) {
        if f {
            *vi = 0.0;
        }
    }
    model.dirichlet.impose(t, v);
}

/// `σ̄_n` of the solver's current iterate (a normal stress from slip): the whole iterate
/// (the fixed dofs from `v_fixed`), its kinematics at the end of the step, the reactions at
/// the tied normal jumps; the scaled friction weights with it.
fn normal_stress_of_iterate<
    const D: usize,
    const C: usize,
    L: FrictionLaw,
    I: VelocityIntegrator,
>(
    normal: &mut NormalWork<L>,
    solver: &mut VelocitySolver<C>,
    integrator: &I,
    model: &Model<D, C>,
    state: &SimulationState,
    v_fixed: &[f64],
) -> Result<()> {
    normal.v.copy_from_slice(v_fixed);
    solver.current_iterate(&mut normal.v)?;
    integrator.advance(state.tau, &state.kinematics, &normal.v, &mut normal.next);
    let t = state.time_of(state.step + 1);
    normal.reactions.evaluate(
        model,
        &normal.next,
        t,
        &mut normal.sigma,
        &mut normal.weights,
    )
}

/// `|v_p|` of the solver's current iterate on Γ_F into `slip`.
fn read_slip_rates<const C: usize>(solver: &VelocitySolver<C>, slip: &mut [f64]) {
    for (k, s) in slip.iter_mut().enumerate() {
        *s = norm::<C>(&solver.block(k));
    }
}

/// The state update `α̃ = S(α_{n−1}, V)` of a step (docs/math.md §2; backward Euler (3.5)
/// by default), node by node.
struct StateUpdate<'a, S> {
    integrator: StateIntegrator,
    laws: &'a [S],
    alpha_prev: &'a [f64],
    tau: f64,
}

impl<S: StateLaw> StateUpdate<'_, S> {
    /// `out[k] = S(α_{n−1,k}, slip[k])`; on ranks (`share`) each rank its own nodes, then
    /// one all-gather (collective).
    fn apply(&self, slip: &[f64], out: &mut [f64], share: Option<&mut StateShare>) -> Result<()> {
        let update = |k: usize| -> Result<f64> {
            Ok(self
                .integrator
                .update(&self.laws[k], self.alpha_prev[k], slip[k], self.tau)?)
        };
        match share {
            Some(share) => share.apply(out, update),
            None => {
                for (k, o) in out.iter_mut().enumerate().take(slip.len()) {
                    *o = update(k)?;
                }
                Ok(())
            }
        }
    }
}
