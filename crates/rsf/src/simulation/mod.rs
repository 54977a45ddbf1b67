//! A simulation: the problem, the method and the state together, stepping by the coupled
//! fixed point iteration (docs/math.md §4; paper §6.2), and its run loop.

pub(crate) mod adaptive;
pub(crate) mod builder;
pub(crate) mod checks;
pub(crate) mod step;
pub(crate) mod workspace;

pub use crate::any_run::Run;
pub use crate::problem::{NoState, Problem};
pub use builder::{SimulationBuilder, Unset};

use std::time::Instant;

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::{Kinematics, StepControl, VelocityIntegrator};

use crate::checkpoint::{bad_value, check_size, Checkpoint};
use crate::error::{Error, Result};
use crate::method::state_integrator::StateIntegrator;
use crate::method::Method;
use crate::method_state::MethodState;
use crate::model::fault::block_norm;
use crate::model::Model;
use crate::observe::{FaultTractions, Observer};
use crate::report::StepReport;
use crate::run::{RunError, RunSummary, Stepping, Until};
use crate::simulation_state::SimulationState;

use step::Stepper;
use workspace::Workspace;

/// A running simulation of a [`Model`] with friction law `L`, state law `S` (one law value
/// per frictional node each, for heterogeneous faults) and velocity integrator `I`: the
/// [`Problem`] (model and laws), the [`Method`] (integrator, velocity solver, fixed point,
/// step control, state update) and the [`SimulationState`] (what a checkpoint saves),
/// plus the scratch space of a step. Built by [`SimulationBuilder`]
/// (or a scene built on it).
///
/// Each [`step`](Self::step) solves the coupled problem at `t_n` by the paper's relaxed
/// fixed point iteration. Everything is deterministic: the same model, parameters and build
/// give bit-identical results, also across [`checkpoint`](Self::checkpoint) /
/// [`restore`](Self::restore).
///
/// `D` is the spatial dimension, `C` the components per node (default `D`; `C = 1` for a
/// scalar field such as antiplane shear, see [`Model`]).
pub struct Simulation<
    const D: usize,
    L: FrictionLaw,
    S: StateLaw,
    I: VelocityIntegrator,
    const C: usize = D,
> {
    problem: Problem<D, L, S, C>,
    method: Method<D, I, C>,
    state: SimulationState,
    work: Workspace<L>,
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    Simulation<D, L, S, I, C>
{
    fn stepper(&mut self) -> Stepper<'_, D, L, S, I, C> {
        Stepper {
            problem: &self.problem,
            method: &mut self.method,
            state: &mut self.state,
            work: &mut self.work,
        }
    }

    /// The problem: model and laws.
    pub fn problem(&self) -> &Problem<D, L, S, C> {
        &self.problem
    }

    /// The method: integrator, solver, fixed point, step control, state update.
    pub fn method(&self) -> &Method<D, I, C> {
        &self.method
    }

    /// The state after the last step.
    pub fn state(&self) -> &SimulationState {
        &self.state
    }

    /// The model.
    pub fn model(&self) -> &Model<D, C> {
        self.problem.model()
    }

    /// Current `(u, v, a)`.
    pub fn kinematics(&self) -> &Kinematics {
        &self.state.kinematics
    }

    /// Current state α per frictional node (`model.frictional_boundary.nodes` order).
    pub fn alpha(&self) -> &[f64] {
        &self.state.alpha
    }

    /// Steps taken so far.
    pub fn step_index(&self) -> usize {
        self.state.step
    }

    /// Current time `t_n` (s): `n τ` for a run at constant τ.
    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// The time step τ of the next step (s).
    pub fn tau(&self) -> f64 {
        self.state.tau
    }

    /// Slip rates `|v_p|` on Γ_F (m/s) into `out`, in `model.frictional_boundary.nodes` order.
    pub fn slip_rates(&self, out: &mut [f64]) {
        let nodes = &self.model().frictional_boundary.nodes;
        for (o, &p) in out.iter_mut().zip(nodes) {
            *o = block_norm::<C>(&self.state.kinematics.v, p);
        }
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
        self.stepper().set_time_step(tau)
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
        self.state.controller = match &control {
            Some(c) => Some(c.start(self.state.tau)?),
            None => None,
        };
        self.method.set_step_control(control);
        Ok(())
    }

    /// Chooses how a step advances the state ([`StateIntegrator`]; default backward Euler,
    /// the paper's). Takes effect from the next step.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `state_integrator` if a frictional node's state law
    /// does not support it.
    pub fn set_state_integrator(&mut self, integrator: StateIntegrator) -> Result<()> {
        if self.problem.uses_state() {
            for law in self.problem.state_laws() {
                integrator.check(law)?;
            }
        }
        self.method.set_state_integrator(integrator);
        Ok(())
    }

    /// Advances one time step (with adaptive steps: until an attempt is accepted).
    ///
    /// # Errors
    /// [`Error::FixedPointNotConverged`] with the correction history; solver and state
    /// update errors. On error the simulation state is unchanged.
    pub fn step(&mut self) -> Result<StepReport> {
        self.step_until(None)
    }

    /// One step; with adaptive steps ending at `t_end` at the latest.
    fn step_until(&mut self, t_end: Option<f64>) -> Result<StepReport> {
        let start = Instant::now();
        let adaptive = self.state.controller.is_some() && self.method.step_control().is_some();
        let mut stepper = self.stepper();
        let mut report = if adaptive {
            stepper.adaptive_step(t_end)?
        } else {
            let attempted = stepper.attempt();
            let state = &*stepper.state;
            let r = attempted.map_err(|e| match e {
                // A fixed step cannot be retried smaller: say so.
                Error::NormalStressNotPositive { .. } => Error::TrialStateRefused {
                    step: state.step + 1,
                    time: state.time,
                    tau: state.tau,
                    refusals: 1,
                    reason: Box::new(e),
                    remedy: "a fixed time step cannot be retried smaller; lower tau or \
                             use adaptive step control (SimulationBuilder::step_control)",
                },
                e => e,
            })?;
            stepper.commit(&r);
            r
        };
        report.seconds = start.elapsed().as_secs_f64();
        Ok(report)
    }

    /// Takes `steps` steps, showing each to the observers; an observer may end the run
    /// early ([`Flow::Break`](crate::Flow)). Same as [`run_until`](Self::run_until) with
    /// [`Until::Steps`].
    ///
    /// # Errors
    /// As [`run_until`](Self::run_until).
    pub fn run(
        &mut self,
        steps: usize,
        observers: &mut [&mut dyn Observer<D, C>],
    ) -> std::result::Result<RunSummary, RunError> {
        self.run_until(Until::Steps(steps), observers)
    }

    crate::run::run_until_method! {
        /// Steps until `until` is reached or an observer returns [`Flow::Break`](crate::Flow)
        /// (after every observer has seen that step), then calls every observer's
        /// [`finish`](Observer::finish) — also when the run fails: the one run loop of every
        /// method, [`run_until`](crate::run_until). The summary says why the run ended
        /// ([`Termination`](crate::Termination)).
        ///
        /// # Errors
        /// A [`RunError`] with the first step or observer error (or, after the steps, the first
        /// error of a `finish`) and the summary of the steps taken; the simulation keeps the
        /// state of the last successful step. [`Error::InvalidParameter`] named `until` for a
        /// non-finite end time.
    }

    /// A checkpoint of the state, for [`restore`](Self::restore).
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint::new(D, self.state.clone())
    }

    /// Sets the state to `state` of a model with the same dofs and frictional nodes
    /// (e.g. another method's state at a switch): as [`restore`](Self::restore) of a
    /// checkpoint of it.
    ///
    /// # Errors
    /// As [`restore`](Self::restore).
    pub(crate) fn set_state(&mut self, state: SimulationState) -> Result<()> {
        self.restore(&Checkpoint::new(D, state))
    }

    /// Continues from a checkpoint of a simulation of the same model; the continuation is
    /// bit-identical to an uninterrupted run. The checkpoint's τ becomes the time step
    /// (see [`set_time_step`](Self::set_time_step)).
    ///
    /// # Errors
    /// [`Error::CheckpointSize`] naming what differs (dimension, number of nodes, lengths
    /// of `v`, `a`, α); [`Error::CheckpointValue`] naming a non-finite value, a negative
    /// time or a non-positive τ (and its entry); [`Error::CheckpointMismatch`] for a
    /// checkpoint of another method (field `method`); solver set-up errors for a new τ.
    /// The simulation is unchanged on error.
    pub fn restore(&mut self, c: &Checkpoint) -> Result<()> {
        if c.method != MethodState::Implicit {
            return Err(Error::CheckpointMismatch {
                field: "method".into(),
                checkpoint: c.method.name().into(),
                run: MethodState::Implicit.name().into(),
            });
        }
        let n = self.model().num_dofs();
        let s = &c.state;
        let k = &s.kinematics;
        let size = check_size;
        size("space dimension", c.dim, D)?;
        if k.u.len() % C == 0 {
            size("number of nodes", k.u.len() / C, n / C)?;
        } else {
            size("length of u", k.u.len(), n)?;
        }
        size("length of v", k.v.len(), n)?;
        size("length of a", k.a.len(), n)?;
        size(
            "number of frictional nodes (length of alpha)",
            s.alpha.len(),
            self.state.alpha.len(),
        )?;
        let value =
            |what, index, value, requirement| Err(bad_value(what, index, value, requirement));
        if !(s.time.is_finite() && s.time >= 0.0) {
            return value("time", 0, s.time, "finite and >= 0 (s)");
        }
        if !(s.tau.is_finite() && s.tau > 0.0) {
            return value("time step tau", 0, s.tau, "finite and > 0 (s)");
        }
        for (what, x) in [("u", &k.u), ("v", &k.v), ("a", &k.a), ("alpha", &s.alpha)] {
            if let Some((i, &y)) = x.iter().enumerate().find(|(_, y)| !y.is_finite()) {
                return value(what, i, y, "finite");
            }
        }
        self.set_time_step(s.tau)?;
        if self.state.controller.is_some() {
            if let Some(c) = s.controller {
                self.state.controller = Some(c);
            }
        }
        self.state.step = s.step;
        self.state.time = s.time;
        // A checkpoint written by a simulation satisfies t = t_s + (n − n_s) τ exactly; an
        // edited one (another τ, another time) starts a new segment of constant τ here.
        let (n0, t0) = s.time_origin;
        self.state.time_origin =
            if n0 <= s.step && (t0 + (s.step - n0) as f64 * s.tau).to_bits() == s.time.to_bits() {
                s.time_origin
            } else {
                (s.step, s.time)
            };
        self.state.kinematics.u.copy_from_slice(&k.u);
        self.state.kinematics.v.copy_from_slice(&k.v);
        self.state.kinematics.a.copy_from_slice(&k.a);
        self.state.alpha.copy_from_slice(&s.alpha);
        if let Some(pw) = &mut self.work.pressure {
            // The tractions observers see at the restored time.
            let base = self.work.normal.as_ref().map(|n| &n.tractions.sigma[..]);
            pw.lower_from(s.time, base)?;
            pw.tractions.sigma.copy_from_slice(&pw.sigma);
        }
        Ok(())
    }
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    Stepping<D, C> for Simulation<D, L, S, I, C>
{
    fn advance(&mut self, t_end: Option<f64>, _reads_volume: bool) -> Result<StepReport> {
        self.step_until(t_end)
    }
    /// The adaptive step control's `tau_min` (`None` for fixed steps).
    fn step_floor(&self) -> Option<f64> {
        self.method.step_control().map(|c| c.tau_min)
    }
    fn model(&self) -> &Model<D, C> {
        self.problem.model()
    }
    fn state(&self) -> &SimulationState {
        &self.state
    }
    fn fault_tractions(&self) -> &dyn FaultTractions {
        if let Some(pw) = &self.work.pressure {
            return &pw.tractions;
        }
        match &self.work.normal {
            Some(normal) => &normal.tractions,
            None => self.problem.fault_tractions(),
        }
    }
    fn method_state(&self) -> MethodState {
        MethodState::Implicit
    }
    fn checkpoint(&self) -> Checkpoint {
        Simulation::checkpoint(self)
    }
    fn restore(&mut self, checkpoint: &Checkpoint) -> Result<()> {
        Simulation::restore(self, checkpoint)
    }
}
