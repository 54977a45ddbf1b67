//! One coupled time step: the relaxed fixed point iteration between the velocity problem
//! and the state update (docs/math.md §4, §8; paper §6.2), its commit, and changes of τ.

use rsf_friction::FrictionLaw;
use rsf_nonsmooth::{BlockNonlinearity, Scaled, SolveReport, StepSolver, Stopping};
use rsf_state::StateLaw;
use rsf_time::VelocityIntegrator;

use crate::error::{Error, Result};
use crate::friction_blocks::{evaluate_potentials, FrictionView};
use crate::method::fixed_point::Predictor;
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
        let fixed_point = *method.fixed_point();
        let mut v = std::mem::take(&mut work.v);
        v.copy_from_slice(&state.kinematics.v);
        if fixed_point.predictor == Predictor::Extrapolated {
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
        begun?;
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
        let state_laws = self.problem.state_laws();
        let fb = &model.frictional_boundary;
        // α = S(α_{n−1}, V) of this step, for the iterates and the commit.
        let update = StateUpdate {
            integrator: state_integrator,
            laws: state_laws,
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
                let stopping = match inexact {
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
                };
                let view = if let Some(pw) = &mut work.pressure {
                    // σ̄_n − p(t_n), σ̄_n the laws' or the iterate's from slip; the laws
                    // evaluated at it, the weights unscaled.
                    pw.lower_from(t, work.normal.as_ref().map(|n| &n.sigma[..]))?;
                    crate::pore_pressure::potentials_at(
                        laws,
                        &work.alpha_iter,
                        &pw.sigma,
                        &mut work.potentials,
                    );
                    FrictionView::<L>::new(fb, &work.potentials)
                } else {
                    evaluate_potentials(laws, &work.alpha_iter, &mut work.potentials);
                    match &work.normal {
                        None => FrictionView::<L>::new(fb, &work.potentials),
                        Some(normal) => FrictionView::<L> {
                            nodes: &fb.nodes,
                            weights: &normal.weights,
                            potentials: &work.potentials,
                        },
                    }
                };
                let r = solve(solver, &view, scaling, stopping)?;
                report.solver_iterations += r.iterations;
                report.fixed_point_iterations += 1;
                let c = solver.last_change();
                work.history.push(c);
                report.correction = c;
                last = c;
                let exact = stopping.absolute <= full.absolute;
                let tol = fixed_point.tolerance;
                let theta = c / previous;
                let estimate = if fixed_point.error_estimate
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
                if small && exact && !(nu == 0 && fixed_point.paper_first_iteration) {
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
        method
            .integrator()
            .advance(tau, &state.kinematics, &work.v, &mut work.next);
        if let Some(normal) = &mut work.normal {
            normal.reactions.evaluate(
                model,
                &work.next,
                t,
                &mut normal.sigma,
                &mut normal.weights,
            )?;
        }
        if let Some(pw) = &mut work.pressure {
            pw.lower_from(t, work.normal.as_ref().map(|n| &n.sigma[..]))?;
        }
        report.max_slip_rate = model
            .frictional_boundary
            .nodes
            .iter()
            .map(|&p| block_norm::<C>(&work.next.v, p))
            .fold(0.0, f64::max);
        Ok(report)
    }
}

/// `v` with the Dirichlet data of time `t`: fixed dofs 0, prescribed ones `factor · g(t)`.
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
