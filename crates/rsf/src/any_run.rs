//! A built run of any of the three methods ([`Run`]; the choice is a
//! [`MethodKind`](crate::MethodKind)), driven by the one run loop
//! ([`run_until`](crate::run_until)).

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::VelocityIntegrator;

use crate::checkpoint::Checkpoint;
use crate::error::Result;
use crate::fault_ode::FaultOde;
use crate::method_state::MethodState;
use crate::model::Model;
use crate::observe::FaultTractions;
use crate::problem::Problem;
use crate::report::StepReport;
use crate::run::Stepping;
use crate::simulation::Simulation;
use crate::simulation_state::SimulationState;
use crate::switching::SwitchingRun;

/// A built run of any of the three methods on one problem: what a program that lets its
/// user choose the method ([`MethodKind`](crate::MethodKind)) holds. It steps, checkpoints and restores like
/// each of them ([`Stepping`]); [`run_until`](Self::run_until) is the one run loop.
///
/// `D` is the spatial dimension, `C` the components per node (see [`Model`]); `I` the
/// implicit scheme's velocity integrator.
pub enum Run<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize = D>
{
    /// The paper's implicit scheme.
    Implicit(Box<Simulation<D, L, S, I, C>>),
    /// The quasi-dynamic fault ODE.
    FaultOde(Box<FaultOde<D, L, S, C>>),
    /// The switching run.
    Switching(Box<SwitchingRun<D, L, S, I, C>>),
}

/// The active method of a [`Run`], as a [`Stepping`].
macro_rules! dispatch {
    ($self:expr, $m:ident => $e:expr) => {
        dispatch_variants!($self, Run { Implicit, FaultOde, Switching }, $m => $e)
    };
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    Run<D, L, S, I, C>
{
    /// Which method this is.
    pub fn kind(&self) -> crate::MethodKind {
        match self {
            Run::Implicit(_) => crate::MethodKind::Implicit,
            Run::FaultOde(_) => crate::MethodKind::FaultOde,
            Run::Switching(_) => crate::MethodKind::Switching,
        }
    }

    /// The problem (model and laws) of the active method.
    pub fn problem(&self) -> &Problem<D, L, S, C> {
        match self {
            Run::Implicit(s) => s.problem(),
            Run::FaultOde(s) => s.problem(),
            Run::Switching(s) => s.quasi_dynamic().problem(),
        }
    }

    crate::run::run_until_method! {
        /// Runs until `until`: [`run_until`](crate::run_until).
        ///
        /// # Errors
        /// As [`run_until`](crate::run_until).
    }
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    Stepping<D, C> for Run<D, L, S, I, C>
{
    fn advance(&mut self, t_end: Option<f64>, reads_volume: bool) -> Result<StepReport> {
        dispatch!(self, m => m.advance(t_end, reads_volume))
    }
    fn watch_vertices(&mut self, vertices: &[usize]) -> Result<()> {
        dispatch!(self, m => m.watch_vertices(vertices))
    }
    fn model(&self) -> &Model<D, C> {
        dispatch!(self, m => Stepping::model(&**m))
    }
    fn state(&self) -> &SimulationState {
        dispatch!(self, m => Stepping::state(&**m))
    }
    fn fault_tractions(&self) -> &dyn FaultTractions {
        dispatch!(self, m => Stepping::fault_tractions(&**m))
    }
    fn method_state(&self) -> MethodState {
        dispatch!(self, m => m.method_state())
    }
    fn reached(&self, t_end: f64) -> bool {
        dispatch!(self, m => m.reached(t_end))
    }
    fn step_floor(&self) -> Option<f64> {
        dispatch!(self, m => m.step_floor())
    }
    fn checkpoint(&self) -> Checkpoint {
        dispatch!(self, m => Stepping::checkpoint(&**m))
    }
    fn restore(&mut self, checkpoint: &Checkpoint) -> Result<()> {
        dispatch!(self, m => Stepping::restore(&mut **m, checkpoint))
    }
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    From<Simulation<D, L, S, I, C>> for Run<D, L, S, I, C>
{
    fn from(s: Simulation<D, L, S, I, C>) -> Self {
        Run::Implicit(Box::new(s))
    }
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    From<FaultOde<D, L, S, C>> for Run<D, L, S, I, C>
{
    fn from(s: FaultOde<D, L, S, C>) -> Self {
        Run::FaultOde(Box::new(s))
    }
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    From<SwitchingRun<D, L, S, I, C>> for Run<D, L, S, I, C>
{
    fn from(s: SwitchingRun<D, L, S, I, C>) -> Self {
        Run::Switching(Box::new(s))
    }
}
