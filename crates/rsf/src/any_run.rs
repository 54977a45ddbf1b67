//! The choice of method apart from the problem ([`MethodKind`]) and a built run of any of
//! the three ([`Run`]), driven by the one run loop ([`run_until`](crate::run_until)).

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::VelocityIntegrator;

use crate::checkpoint::Checkpoint;
use crate::error::Result;
use crate::fault_ode::FaultOde;
use crate::method_state::MethodState;
use crate::model::Model;
use crate::observe::{FaultTractions, Observer};
use crate::problem::Problem;
use crate::report::StepReport;
use crate::run::{run_until, RunError, RunSummary, Stepping, Until};
use crate::simulation::Simulation;
use crate::simulation_state::SimulationState;
use crate::switching::SwitchingRun;

/// Which method advances a problem in time.
///
/// Names (`name`, `FromStr`, serde, clap): `implicit`, `fault-ode`, `switching`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MethodKind {
    /// The paper's implicit scheme ([`Simulation`]): a velocity integrator (Newmark,
    /// backward Euler or quasistatic), each step a fixed point of a convex velocity problem
    /// (TNNMG or the direct solver) and the state update (docs/math.md §2–4).
    #[default]
    Implicit,
    /// Quasi-dynamic, condensed onto the fault and integrated by an explicit embedded
    /// Runge–Kutta pair ([`FaultOde`], docs/math.md §12): needs radiation damping and no
    /// inertia.
    FaultOde,
    /// The fault ODE between events and the implicit scheme with inertia during them
    /// ([`SwitchingRun`]).
    Switching,
}

impl MethodKind {
    /// Every kind, in declaration order.
    pub const ALL: [MethodKind; 3] = [Self::Implicit, Self::FaultOde, Self::Switching];

    /// The name (`implicit`, `fault-ode`, `switching`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Implicit => "implicit",
            Self::FaultOde => "fault-ode",
            Self::Switching => "switching",
        }
    }
}

impl std::fmt::Display for MethodKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for MethodKind {
    type Err = crate::Error;

    /// A [`name`](MethodKind::name); `runge-kutta` is accepted for `fault-ode`.
    fn from_str(s: &str) -> crate::Result<Self> {
        if s == "runge-kutta" {
            return Ok(Self::FaultOde);
        }
        Ok(rsf_numeric::parse_name(
            "method",
            s,
            &Self::ALL,
            Self::name,
            &[],
        )?)
    }
}

/// A built run of any of the three methods on one problem: what a program that lets its
/// user choose the method ([`MethodKind`]) holds. It steps, checkpoints and restores like
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
        match $self {
            Run::Implicit($m) => $e,
            Run::FaultOde($m) => $e,
            Run::Switching($m) => $e,
        }
    };
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    Run<D, L, S, I, C>
{
    /// Which method this is.
    pub fn kind(&self) -> MethodKind {
        match self {
            Run::Implicit(_) => MethodKind::Implicit,
            Run::FaultOde(_) => MethodKind::FaultOde,
            Run::Switching(_) => MethodKind::Switching,
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

    /// Runs until `until`: [`run_until`](crate::run_until).
    ///
    /// # Errors
    /// As [`run_until`](crate::run_until).
    pub fn run_until(
        &mut self,
        until: Until,
        observers: &mut [&mut dyn Observer<D, C>],
    ) -> std::result::Result<RunSummary, RunError> {
        run_until(self, until, observers)
    }
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    Stepping<D, C> for Run<D, L, S, I, C>
{
    fn advance(&mut self, t_end: Option<f64>, reads_volume: bool) -> Result<StepReport> {
        dispatch!(self, m => m.advance(t_end, reads_volume))
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

#[cfg(test)]
mod tests {
    use super::MethodKind;

    #[test]
    fn names_round_trip() {
        for k in MethodKind::ALL {
            assert_eq!(k.name().parse::<MethodKind>().unwrap(), k);
        }
        assert_eq!(
            "runge-kutta".parse::<MethodKind>().unwrap(),
            MethodKind::FaultOde
        );
        assert!("rk4".parse::<MethodKind>().is_err());
    }
}
