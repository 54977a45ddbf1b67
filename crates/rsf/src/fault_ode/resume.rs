//! Continuing a fault ODE: from a checkpoint of its own, or from another method's state.

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::OdeSystem;

use super::FaultOde;
use crate::checkpoint::{bad_value, check_size, Checkpoint};
use crate::error::{invalid, Error, Result};
use crate::method_state::{FaultOdeState, MethodState};
use crate::simulation_state::SimulationState;

impl<const D: usize, L: FrictionLaw, S: StateLaw, const C: usize> FaultOde<D, L, S, C> {
    /// Continues from the common `state` and the method's own `memory` (of a checkpoint of
    /// this run): bit-identical to the run that wrote them.
    ///
    /// # Errors
    /// [`Error::CheckpointSize`] for lengths other than this model's,
    /// [`Error::CheckpointValue`] for a negative or non-finite time or a non-finite value on
    /// Γ_F; [`Error::InvalidParameter`] named `controller` for a step outside the
    /// Runge–Kutta options' `[dt_min, dt_max]`. Unchanged on error.
    pub(crate) fn restore_parts(
        &mut self,
        state: &SimulationState,
        memory: &FaultOdeState,
    ) -> Result<()> {
        let n = self.problem.model().num_dofs();
        let size = check_size;
        size("length of u", state.kinematics.u.len(), n)?;
        size("length of v", state.kinematics.v.len(), n)?;
        size(
            "number of frictional nodes (length of alpha)",
            state.alpha.len(),
            self.state.alpha.len(),
        )?;
        size(
            "length of the fault ODE's rate",
            memory.rate.len(),
            self.y.len(),
        )?;
        let value =
            |what, index, value, requirement| Err(bad_value(what, index, value, requirement));
        if !(state.time.is_finite() && state.time >= 0.0) {
            return value("time", 0, state.time, "finite and >= 0 (s)");
        }
        self.check_dt("controller", "next step ", memory.controller.dt)?;
        let y = self.unknowns_of(state);
        if let Some(i) = y.iter().position(|x| !x.is_finite()) {
            return value("u on Γ_F or alpha", i, y[i], "finite");
        }
        if let Some(i) = memory.rate.iter().position(|x| !x.is_finite()) {
            return value("fault ODE rate", i, memory.rate[i], "finite");
        }
        self.y = y;
        self.dy.copy_from_slice(&memory.rate);
        self.rk
            .restore(memory.controller, memory.stabilized.as_ref(), &memory.rate)?;
        self.evaluations = usize::try_from(memory.evaluations).unwrap_or(usize::MAX);
        self.state.time = state.time;
        self.state.step = state.step;
        self.state.tau = self.rk.controller().dt;
        self.state.time_origin = state.time_origin;
        self.state.controller = None;
        self.state.kinematics.u.copy_from_slice(&state.kinematics.u);
        self.state.kinematics.v.copy_from_slice(&state.kinematics.v);
        self.state.kinematics.a.fill(0.0);
        self.interior_is_nan = false;
        self.fill_state(false)
    }

    /// [`Error::InvalidParameter`] named `name` (the step `dt` in s, `what` before it in
    /// the message) unless `dt` is in the Runge–Kutta options' `[dt_min, dt_max]`.
    fn check_dt(&self, name: &'static str, what: &str, dt: f64) -> Result<()> {
        let o = self.options.runge_kutta;
        if !(dt >= o.dt_min && dt <= o.dt_max) {
            return Err(invalid(
                name,
                format!("{what}{dt} s must be in [{}, {}] s", o.dt_min, o.dt_max),
            ));
        }
        Ok(())
    }

    /// The ODE's unknowns of `state` (of this model's sizes): the displacement on Γ_F's
    /// free components, then α.
    fn unknowns_of(&self, state: &SimulationState) -> Vec<f64> {
        let m = self.rates.body.dim();
        let mut y = self.y.clone();
        for (yi, &dof) in y.iter_mut().zip(self.rates.body.interface_dofs()) {
            *yi = state.kinematics.u[dof];
        }
        y[m..].copy_from_slice(&state.alpha);
        y
    }

    /// Continues from `state` (of a model with the same frictional boundary, e.g. a
    /// [`Simulation`](crate::Simulation) with inertia at the end of an event): its time,
    /// step count, the displacement on Γ_F's free components and α; the slip rates follow
    /// from the stress, the next trial step is `dt` (s). The volume's own state (waves) is
    /// not carried over: a quasi-dynamic run has none.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `state` for lengths other than this model's, a
    /// negative or non-finite time, non-finite values on Γ_F; named `dt` outside the
    /// Runge–Kutta options' `[dt_min, dt_max]`.
    pub fn restart_from(&mut self, state: &SimulationState, dt: f64) -> Result<()> {
        let n = self.problem.model().num_dofs();
        let nf = self.state.alpha.len();
        if state.kinematics.u.len() != n || state.alpha.len() != nf {
            return Err(invalid(
                "state",
                format!(
                    "{} dofs and {} states for a model of {n} dofs and {nf} frictional nodes",
                    state.kinematics.u.len(),
                    state.alpha.len()
                ),
            ));
        }
        if !(state.time.is_finite() && state.time >= 0.0) {
            return Err(invalid("state", format!("time {} s", state.time)));
        }
        self.check_dt("dt", "", dt)?;
        let y = self.unknowns_of(state);
        if let Some(i) = y.iter().position(|x| !x.is_finite()) {
            return Err(invalid("state", format!("unknown {i} on Γ_F is {}", y[i])));
        }
        let mut dy = vec![0.0; y.len()];
        self.system().rate(state.time, &y, &mut dy)?;
        if let Some(i) = dy.iter().position(|x| !x.is_finite()) {
            return Err(invalid(
                "state",
                format!("the rate of unknown {i} is {}", dy[i]),
            ));
        }
        self.y = y;
        self.dy = dy;
        self.rk.restart(dt);
        self.state.time = state.time;
        self.state.step = state.step;
        self.state.tau = dt;
        self.state.kinematics.u.copy_from_slice(&state.kinematics.u);
        self.interior_is_nan = false;
        self.fill_state(false)
    }

    /// Continues from a checkpoint of this run (or of a fault ODE on the same model);
    /// the continuation is bit-identical to an uninterrupted run.
    ///
    /// # Errors
    /// [`Error::CheckpointMismatch`] (field `method`) for a checkpoint of another method;
    /// [`Error::CheckpointSize`], [`Error::CheckpointValue`] naming what differs.
    /// Unchanged on error.
    pub fn restore(&mut self, checkpoint: &Checkpoint) -> Result<()> {
        match &checkpoint.method {
            MethodState::FaultOde(memory) => {
                if checkpoint.dim != D {
                    return Err(Error::CheckpointSize {
                        what: "space dimension",
                        checkpoint: checkpoint.dim,
                        simulation: D,
                    });
                }
                self.restore_parts(&checkpoint.state, memory)
            }
            other => Err(Error::CheckpointMismatch {
                field: "method".into(),
                checkpoint: other.name().into(),
                run: "fault-ode".into(),
            }),
        }
    }
}
