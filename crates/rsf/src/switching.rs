//! Fully dynamic events in quasi-dynamic cycles: a run that switches between a
//! [`FaultOde`] (no inertia, radiation damping, explicit adaptive steps) while the fault
//! creeps and a [`Simulation`] with inertia (e.g. Newmark, no radiation damping, fixed
//! steps) while it slips fast — the approach of the fully dynamic codes of the SEAS
//! benchmark BP1-FD (Erickson et al. 2023, BSSA), docs/math.md §12.

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::VelocityIntegrator;

use crate::checkpoint::Checkpoint;
use crate::error::{invalid, Error, Result};
use crate::fault_ode::FaultOde;
use crate::method_state::MethodState;
pub use crate::method_state::{Phase, SwitchingStats};
use crate::model::fault::block_norm;
use crate::model::Model;
use crate::observe::FaultTractions;
use crate::report::StepReport;
use crate::run::{time_reached, Stepping};
use crate::simulation::Simulation;
use crate::simulation_state::SimulationState;

/// When and how a [`SwitchingRun`] changes between its two methods.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwitchingOptions {
    /// The quasi-dynamic run hands over to the dynamic one after the first step whose
    /// largest slip rate on Γ_F is at least this (m/s). Default 1e-3 m/s (the SEAS event
    /// threshold).
    pub to_dynamic: f64,
    /// The dynamic run hands back after the first step whose largest slip rate is below
    /// this (m/s), at most `to_dynamic` (hysteresis against switching back and forth).
    /// Default 1e-4 m/s.
    pub to_quasi_dynamic: f64,
    /// The time step of the dynamic phases (s), fixed; e.g. a fraction of the time a shear
    /// wave takes to cross an element on the fault.
    pub dynamic_tau: f64,
    /// The first trial step of a quasi-dynamic phase (s); its step control takes over.
    pub restart_dt: f64,
}

/// A run that is quasi-dynamic while the fault creeps and fully dynamic while it slips
/// fast. Both methods must work on the same model (the dynamic one's with a mass matrix):
/// at a switch to the dynamic phase the whole field `(u, v)` of the quasi-dynamic state
/// (its equilibrium, [`FaultOde::state_with_volume`]), α and the time become the dynamic
/// run's state with zero acceleration; at a switch back the displacement on Γ_F and α
/// become the quasi-dynamic state ([`FaultOde::restart_from`]; the waves of the volume are
/// dropped, as in any quasi-dynamic model).
///
/// A method like the others ([`Stepping`]): each step is one step of the active method;
/// the switch is decided before a step, from the largest slip rate of the current state
/// (so after every observer has seen the step that crossed the threshold), and a
/// checkpoint holds the phase with the active method's state: a run resumed from it is
/// bit-identical to an uninterrupted one.
pub struct SwitchingRun<
    const D: usize,
    L: FrictionLaw,
    S: StateLaw,
    I: VelocityIntegrator,
    const C: usize = D,
> {
    quasi_dynamic: FaultOde<D, L, S, C>,
    dynamic: Simulation<D, L, S, I, C>,
    options: SwitchingOptions,
    phase: Phase,
    stats: SwitchingStats,
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    SwitchingRun<D, L, S, I, C>
{
    /// A switching run starting in the quasi-dynamic phase at the state of
    /// `quasi_dynamic`. `dynamic` is switched to fixed steps of `options.dynamic_tau`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `dynamic` if its integrator has no inertia, its
    /// model's dofs or frictional nodes differ, or its normal stress setting
    /// ([`SimulationBuilder::normal_stress`](crate::SimulationBuilder::normal_stress))
    /// differs, or naming the first invalid option
    /// (thresholds positive and ordered, steps positive and finite).
    pub fn new(
        quasi_dynamic: FaultOde<D, L, S, C>,
        mut dynamic: Simulation<D, L, S, I, C>,
        options: SwitchingOptions,
    ) -> Result<Self> {
        let o = options;
        if !(o.to_dynamic > 0.0 && o.to_dynamic.is_finite()) {
            return Err(invalid("to_dynamic", format!("{} m/s", o.to_dynamic)));
        }
        if !(o.to_quasi_dynamic > 0.0 && o.to_quasi_dynamic <= o.to_dynamic) {
            return Err(invalid(
                "to_quasi_dynamic",
                format!("{} m/s must be in (0, to_dynamic]", o.to_quasi_dynamic),
            ));
        }
        for (name, x) in [("dynamic_tau", o.dynamic_tau), ("restart_dt", o.restart_dt)] {
            if !(x > 0.0 && x.is_finite()) {
                return Err(invalid(name, format!("{x} s must be positive and finite")));
            }
        }
        if !dynamic.method().integrator().uses_mass() {
            return Err(invalid(
                "dynamic",
                "its integrator has no inertia (use Newmark or backward Euler)",
            ));
        }
        let (a, b) = (quasi_dynamic.model(), dynamic.model());
        if a.num_dofs() != b.num_dofs()
            || a.frictional_boundary.nodes != b.frictional_boundary.nodes
        {
            return Err(invalid(
                "dynamic",
                "its model differs from the quasi-dynamic one (dofs or frictional nodes)",
            ));
        }
        let (qn, dn) = (
            quasi_dynamic.problem().normal_stress(),
            dynamic.problem().normal_stress(),
        );
        if qn != dn {
            return Err(invalid(
                "dynamic",
                format!(
                    "its normal stress ({dn:?}) differs from the quasi-dynamic one's ({qn:?}): \
                     give both builders the same SimulationBuilder::normal_stress"
                ),
            ));
        }
        dynamic.set_step_control(None)?;
        dynamic.set_time_step(o.dynamic_tau)?;
        Ok(Self {
            quasi_dynamic,
            dynamic,
            options,
            phase: Phase::QuasiDynamic,
            stats: SwitchingStats::default(),
        })
    }

    /// The quasi-dynamic method.
    pub fn quasi_dynamic(&self) -> &FaultOde<D, L, S, C> {
        &self.quasi_dynamic
    }

    /// The dynamic method.
    pub fn dynamic(&self) -> &Simulation<D, L, S, I, C> {
        &self.dynamic
    }

    /// The options.
    pub fn options(&self) -> &SwitchingOptions {
        &self.options
    }

    /// The active method.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// What the run did so far.
    pub fn stats(&self) -> SwitchingStats {
        self.stats
    }

    /// The time of the current state (s).
    pub fn time(&self) -> f64 {
        Stepping::state(self).time
    }

    crate::run::run_until_method! {
        /// Runs until `until`, switching as the options say: the one run loop of every
        /// method, [`run_until`](crate::run_until).
        ///
        /// # Errors
        /// A [`RunError`](crate::RunError) with the first error of a step, an observer or a
        /// switch, and the summary of the steps before it.
    }

    /// A checkpoint of the whole state: the phase, the statistics and the active method's
    /// state.
    pub fn checkpoint(&self) -> Checkpoint {
        Stepping::checkpoint(self)
    }

    /// Continues from a checkpoint of a switching run on the same models; bit-identical
    /// to an uninterrupted run.
    ///
    /// # Errors
    /// [`Error::CheckpointMismatch`] (field `method`) for a checkpoint of another method;
    /// the active method's restore errors. Unchanged on error.
    pub fn restore(&mut self, checkpoint: &Checkpoint) -> Result<()> {
        let MethodState::Switching {
            phase,
            stats,
            fault_ode,
        } = &checkpoint.method
        else {
            return Err(Error::CheckpointMismatch {
                field: "method".into(),
                checkpoint: checkpoint.method.name().into(),
                run: "switching".into(),
            });
        };
        match (phase, fault_ode) {
            (Phase::QuasiDynamic, Some(memory)) => {
                if checkpoint.dim != D {
                    return Err(Error::CheckpointSize {
                        what: "space dimension",
                        checkpoint: checkpoint.dim,
                        simulation: D,
                    });
                }
                self.quasi_dynamic
                    .restore_parts(&checkpoint.state, memory)?;
            }
            (Phase::Dynamic, None) => {
                let mut c = checkpoint.clone();
                c.method = MethodState::Implicit;
                self.dynamic.restore(&c)?;
            }
            _ => {
                return Err(Error::CheckpointMismatch {
                    field: "method".into(),
                    checkpoint: format!("switching, {} phase without its state", phase.name()),
                    run: "switching".into(),
                })
            }
        }
        self.phase = *phase;
        self.stats = *stats;
        Ok(())
    }

    /// The largest slip rate on Γ_F of the current state (m/s).
    fn max_slip_rate(&self) -> f64 {
        let s = Stepping::state(self);
        Stepping::model(self)
            .frictional_boundary
            .nodes
            .iter()
            .map(|&p| block_norm::<C>(&s.kinematics.v, p))
            .fold(0.0, f64::max)
    }

    /// Hands the state over to the other method.
    fn switch(&mut self) -> Result<()> {
        match self.phase {
            Phase::QuasiDynamic => {
                let mut state = self.quasi_dynamic.state_with_volume()?.clone();
                state.tau = self.options.dynamic_tau;
                state.kinematics.a.fill(0.0);
                state.controller = None;
                state.time_origin = (state.step, state.time);
                self.dynamic.set_state(state)?;
                self.phase = Phase::Dynamic;
                self.stats.dynamic_phases += 1;
            }
            Phase::Dynamic => {
                // The dynamic phase began at its time origin (set at the switch above).
                let start = self.dynamic.state().time_origin.1;
                self.stats.dynamic_time += self.dynamic.time() - start;
                self.quasi_dynamic
                    .restart_from(self.dynamic.state(), self.options.restart_dt)?;
                self.phase = Phase::QuasiDynamic;
            }
        }
        Ok(())
    }
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    Stepping<D, C> for SwitchingRun<D, L, S, I, C>
{
    fn advance(&mut self, t_end: Option<f64>, reads_volume: bool) -> Result<StepReport> {
        let v = self.max_slip_rate();
        let switch = match self.phase {
            Phase::QuasiDynamic => v >= self.options.to_dynamic,
            Phase::Dynamic => v < self.options.to_quasi_dynamic,
        };
        if switch && self.state().step > 0 {
            self.switch()?;
        }
        let report = match self.phase {
            Phase::QuasiDynamic => self.quasi_dynamic.advance(t_end, reads_volume)?,
            Phase::Dynamic => self.dynamic.advance(t_end, reads_volume)?,
        };
        match self.phase {
            Phase::QuasiDynamic => self.stats.quasi_dynamic_steps += 1,
            Phase::Dynamic => self.stats.dynamic_steps += 1,
        }
        Ok(report)
    }
    /// The active phase's floor (the dynamic phase's fixed steps have none).
    fn step_floor(&self) -> Option<f64> {
        match self.phase {
            Phase::QuasiDynamic => self.quasi_dynamic.step_floor(),
            Phase::Dynamic => self.dynamic.step_floor(),
        }
    }
    /// The quasi-dynamic phase computes the watched vertices; the dynamic phase (the
    /// implicit scheme) has the whole field.
    fn watch_vertices(&mut self, vertices: &[usize]) -> Result<()> {
        Stepping::watch_vertices(&mut self.quasi_dynamic, vertices)
    }
    fn reached(&self, t_end: f64) -> bool {
        // As the nested runs of the phases did: the end is reached for the dynamic step or
        // for the active method's next step.
        let s = self.state();
        time_reached(s.time, t_end, self.options.dynamic_tau) || time_reached(s.time, t_end, s.tau)
    }
    fn model(&self) -> &Model<D, C> {
        match self.phase {
            Phase::QuasiDynamic => self.quasi_dynamic.model(),
            Phase::Dynamic => self.dynamic.model(),
        }
    }
    fn state(&self) -> &SimulationState {
        match self.phase {
            Phase::QuasiDynamic => self.quasi_dynamic.state(),
            Phase::Dynamic => self.dynamic.state(),
        }
    }
    fn fault_tractions(&self) -> &dyn FaultTractions {
        match self.phase {
            Phase::QuasiDynamic => Stepping::fault_tractions(&self.quasi_dynamic),
            Phase::Dynamic => Stepping::fault_tractions(&self.dynamic),
        }
    }
    fn method_state(&self) -> MethodState {
        MethodState::Switching {
            phase: self.phase,
            stats: self.stats,
            fault_ode: match self.phase {
                Phase::QuasiDynamic => Some(self.quasi_dynamic.fault_ode_state()),
                Phase::Dynamic => None,
            },
        }
    }
    fn restore(&mut self, checkpoint: &Checkpoint) -> Result<()> {
        SwitchingRun::restore(self, checkpoint)
    }
}
