//! An object-safe view of a simulation, for scene-level code that chooses laws and
//! integrators at run time (the hot path stays generic inside).

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::{Kinematics, StepControl, StepController, VelocityIntegrator};

use crate::checkpoint::Checkpoint;
use crate::error::Result;
use crate::model::Model;
use crate::observer::Observer;
use crate::simulation::{RunSummary, Simulation, StepReport, Until};

/// The operations of [`Simulation`] without its type parameters.
pub trait AnySimulation<const D: usize> {
    /// See [`Simulation::step`].
    fn step(&mut self) -> Result<StepReport>;
    /// See [`Simulation::run`].
    fn run(&mut self, steps: usize, observers: &mut [&mut dyn Observer<D>]) -> Result<RunSummary>;
    /// See [`Simulation::run_until`].
    fn run_until(
        &mut self,
        until: Until,
        observers: &mut [&mut dyn Observer<D>],
    ) -> Result<RunSummary>;
    /// See [`Simulation::checkpoint`].
    fn checkpoint(&self) -> Checkpoint;
    /// See [`Simulation::restore`].
    fn restore(&mut self, c: &Checkpoint) -> Result<()>;
    /// See [`Simulation::model`].
    fn model(&self) -> &Model<D>;
    /// See [`Simulation::kinematics`].
    fn kinematics(&self) -> &Kinematics;
    /// See [`Simulation::alpha`].
    fn alpha(&self) -> &[f64];
    /// See [`Simulation::time`].
    fn time(&self) -> f64;
    /// See [`Simulation::tau`].
    fn tau(&self) -> f64;
    /// See [`Simulation::step_index`].
    fn step_index(&self) -> usize;
    /// See [`Simulation::set_time_step`].
    fn set_time_step(&mut self, tau: f64) -> Result<()>;
    /// See [`Simulation::set_step_control`].
    fn set_step_control(&mut self, control: Option<StepControl>) -> Result<()>;
    /// See [`Simulation::step_controller`].
    fn step_controller(&self) -> Option<&StepController>;
    /// See [`Simulation::solver_name`].
    fn solver_name(&self) -> &'static str;
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator> AnySimulation<D>
    for Simulation<D, L, S, I>
{
    fn step(&mut self) -> Result<StepReport> {
        Simulation::step(self)
    }
    fn run(&mut self, steps: usize, observers: &mut [&mut dyn Observer<D>]) -> Result<RunSummary> {
        Simulation::run(self, steps, observers)
    }
    fn run_until(
        &mut self,
        until: Until,
        observers: &mut [&mut dyn Observer<D>],
    ) -> Result<RunSummary> {
        Simulation::run_until(self, until, observers)
    }
    fn checkpoint(&self) -> Checkpoint {
        Simulation::checkpoint(self)
    }
    fn restore(&mut self, c: &Checkpoint) -> Result<()> {
        Simulation::restore(self, c)
    }
    fn model(&self) -> &Model<D> {
        Simulation::model(self)
    }
    fn kinematics(&self) -> &Kinematics {
        Simulation::kinematics(self)
    }
    fn alpha(&self) -> &[f64] {
        Simulation::alpha(self)
    }
    fn time(&self) -> f64 {
        Simulation::time(self)
    }
    fn tau(&self) -> f64 {
        Simulation::tau(self)
    }
    fn step_index(&self) -> usize {
        Simulation::step_index(self)
    }
    fn set_time_step(&mut self, tau: f64) -> Result<()> {
        Simulation::set_time_step(self, tau)
    }
    fn set_step_control(&mut self, control: Option<StepControl>) -> Result<()> {
        Simulation::set_step_control(self, control)
    }
    fn step_controller(&self) -> Option<&StepController> {
        Simulation::step_controller(self)
    }
    fn solver_name(&self) -> &'static str {
        Simulation::solver_name(self)
    }
}
