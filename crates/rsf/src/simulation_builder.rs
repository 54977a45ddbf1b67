//! Constructing a [`Simulation`] with defaults, laws given per node or by position.

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::{Newmark, StepControl, VelocityIntegrator};

use crate::error::{invalid, Error, Result};
use crate::fixed_point::FixedPointOptions;
use crate::model::Model;
use crate::simulation::{NoState, Simulation};
use crate::solver::SolverKind;
use crate::state_integrator::StateIntegrator;

/// The friction-law type of a [`SimulationBuilder`] before a law is chosen: `build` is
/// only available once [`friction`](SimulationBuilder::friction) or
/// [`friction_at`](SimulationBuilder::friction_at) has been called.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Unset;

/// Builds a [`Simulation`] from a [`Model`]: the friction law (required), the state law,
/// the initial state, the velocity integrator (default [`Newmark`]), the time step τ
/// (required; the initial one with [`step_control`](Self::step_control)), the velocity
/// solver (default [`SolverKind::default`], direct or TNNMG by size), the fixed point
/// options (default [`FixedPointOptions::default`]) and the state update (default backward
/// Euler, [`StateIntegrator`]).
///
/// Laws and initial states are either uniform or functions of the node position `x` (m),
/// evaluated at the frictional nodes ([`Model::on_frictional_nodes`]): a heterogeneous fault
/// needs no knowledge of the node order. Errors of those functions (e.g. invalid
/// parameters) are reported by [`build`](Self::build).
///
/// ```no_run
/// use rsf::friction::{DieterichRuina, RateStateParams};
/// use rsf::state::Aging;
/// use rsf::{SimulationBuilder, SliderScene};
///
/// let model = SliderScene::default().build_model()?;
/// let p = RateStateParams { mu0: 0.6, a: 0.010, b: 0.015, v0: 1e-6, l: 1e-5, sigma_n: 49_050.0 };
/// let mut sim = SimulationBuilder::new(model)
///     // velocity strengthening (a > b) outside 1 m < x < 4 m
///     .friction_at(|x| {
///         let b = if (1.0..4.0).contains(&x[0]) { p.b } else { 0.005 };
///         DieterichRuina::new(RateStateParams { b, ..p })
///     })
///     .state_law(Aging::new(p.l)?)
///     .initial_state(-10.0)
///     .time_step(1.5e-3)
///     .build()?;
/// sim.run(100, &mut [])?;
/// # Ok::<(), rsf::Error>(())
/// ```
pub struct SimulationBuilder<const D: usize, L, S, I> {
    model: Model<D>,
    friction: Result<Vec<L>>,
    state: Result<Vec<S>>,
    alpha0: Option<Vec<f64>>,
    integrator: I,
    tau: Option<f64>,
    solver: SolverKind,
    fixed_point: FixedPointOptions,
    step_control: Option<StepControl>,
    state_integrator: StateIntegrator,
}

impl<const D: usize> SimulationBuilder<D, Unset, NoState, Newmark> {
    /// A builder for `model` with the defaults above.
    pub fn new(model: Model<D>) -> Self {
        Self {
            model,
            friction: Ok(Vec::new()),
            state: Ok(Vec::new()),
            alpha0: None,
            integrator: Newmark,
            tau: None,
            solver: SolverKind::default(),
            fixed_point: FixedPointOptions::default(),
            step_control: None,
            state_integrator: StateIntegrator::default(),
        }
    }
}

/// `f` at every frictional node, collecting the first error.
fn per_node<const D: usize, T, E: Into<Error>>(
    model: &Model<D>,
    f: impl FnMut(&[f64; D]) -> std::result::Result<T, E>,
) -> Result<Vec<T>> {
    model
        .on_frictional_nodes(f)
        .into_iter()
        .map(|r| r.map_err(Into::into))
        .collect()
}

/// The parts of a builder whose types change with the laws and the integrator.
type Laws<L, S, I> = (Result<Vec<L>>, Result<Vec<S>>, I);

impl<const D: usize, L, S, I> SimulationBuilder<D, L, S, I> {
    fn retype<L2, S2, I2>(
        self,
        f: impl FnOnce(Laws<L, S, I>) -> Laws<L2, S2, I2>,
    ) -> SimulationBuilder<D, L2, S2, I2> {
        let Self {
            model,
            friction,
            state,
            alpha0,
            integrator,
            tau,
            solver,
            fixed_point,
            step_control,
            state_integrator,
        } = self;
        let (friction, state, integrator) = f((friction, state, integrator));
        SimulationBuilder {
            model,
            friction,
            state,
            alpha0,
            integrator,
            tau,
            solver,
            fixed_point,
            step_control,
            state_integrator,
        }
    }

    /// The model.
    pub fn model(&self) -> &Model<D> {
        &self.model
    }

    /// The same friction law at every frictional node.
    pub fn friction<L2: FrictionLaw>(self, law: L2) -> SimulationBuilder<D, L2, S, I> {
        let laws = Ok(vec![law; self.model.frictional.len()]);
        self.retype(|(_, s, i)| (laws, s, i))
    }

    /// The friction law at each frictional node from its position `x` (m).
    pub fn friction_at<L2: FrictionLaw, E: Into<Error>>(
        self,
        law: impl FnMut(&[f64; D]) -> std::result::Result<L2, E>,
    ) -> SimulationBuilder<D, L2, S, I> {
        let laws = per_node(&self.model, law);
        self.retype(|(_, s, i)| (laws, s, i))
    }

    /// The same state law at every frictional node (not needed if the friction law does
    /// not use the state, e.g. Tresca).
    pub fn state_law<S2: StateLaw>(self, law: S2) -> SimulationBuilder<D, L, S2, I> {
        let laws = Ok(vec![law; self.model.frictional.len()]);
        self.retype(|(f, _, i)| (f, laws, i))
    }

    /// The state law at each frictional node from its position `x` (m).
    pub fn state_law_at<S2: StateLaw, E: Into<Error>>(
        self,
        law: impl FnMut(&[f64; D]) -> std::result::Result<S2, E>,
    ) -> SimulationBuilder<D, L, S2, I> {
        let laws = per_node(&self.model, law);
        self.retype(|(f, _, i)| (f, laws, i))
    }

    /// The velocity integrator.
    pub fn integrator<I2: VelocityIntegrator>(
        self,
        integrator: I2,
    ) -> SimulationBuilder<D, L, S, I2> {
        self.retype(|(f, s, _)| (f, s, integrator))
    }

    /// The same initial state α₀ at every frictional node (`ln θ₀` with θ₀ in s for the
    /// rate-and-state laws). Required if the friction law uses the state.
    pub fn initial_state(mut self, alpha0: f64) -> Self {
        self.alpha0 = Some(vec![alpha0; self.model.frictional.len()]);
        self
    }

    /// The initial state at each frictional node from its position `x` (m).
    pub fn initial_state_at(mut self, alpha0: impl FnMut(&[f64; D]) -> f64) -> Self {
        self.alpha0 = Some(self.model.on_frictional_nodes(alpha0));
        self
    }

    /// The time step τ (s); required.
    pub fn time_step(mut self, tau: f64) -> Self {
        self.tau = Some(tau);
        self
    }

    /// The velocity solver.
    pub fn solver(mut self, solver: SolverKind) -> Self {
        self.solver = solver;
        self
    }

    /// The fixed point options.
    pub fn fixed_point(mut self, options: FixedPointOptions) -> Self {
        self.fixed_point = options;
        self
    }

    /// How a step advances the state ([`Simulation::set_state_integrator`]; default
    /// backward Euler, the paper's).
    pub fn state_integrator(mut self, integrator: StateIntegrator) -> Self {
        self.state_integrator = integrator;
        self
    }

    /// Adaptive time steps with error control from the initial τ of
    /// [`time_step`](Self::time_step) ([`Simulation::set_step_control`]; default: fixed τ).
    pub fn step_control(mut self, control: StepControl) -> Self {
        self.step_control = Some(control);
        self
    }
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator>
    SimulationBuilder<D, L, S, I>
{
    /// The time step τ set so far (s).
    pub fn tau(&self) -> Option<f64> {
        self.tau
    }

    /// The velocity solver set so far.
    pub fn solver_kind(&self) -> &SolverKind {
        &self.solver
    }

    /// The fixed point options set so far.
    pub fn fixed_point_options(&self) -> &FixedPointOptions {
        &self.fixed_point
    }

    /// Builds the simulation ([`Simulation::new`] with the parts set).
    ///
    /// # Errors
    /// The first error of a per-node function; [`Error::InvalidParameter`] named
    /// `time_step` or `initial_state` if they are needed and not set; the errors of
    /// [`Simulation::new`] (consistency checks, solver set-up) and of
    /// [`Simulation::set_step_control`].
    pub fn build(self) -> Result<Simulation<D, L, S, I>> {
        let friction = self.friction?;
        let state = self.state?;
        let tau = self
            .tau
            .ok_or_else(|| invalid("time_step", "not set (SimulationBuilder::time_step)"))?;
        let nf = self.model.frictional.len();
        let alpha0 = match self.alpha0 {
            Some(a) => a,
            None if friction.iter().any(FrictionLaw::uses_state) => {
                return Err(invalid(
                    "initial_state",
                    "not set, and the friction law uses the state",
                ))
            }
            None => vec![0.0; nf],
        };
        let mut sim = Simulation::new(
            self.model,
            friction,
            state,
            alpha0,
            self.integrator,
            tau,
            &self.solver,
            self.fixed_point,
        )?;
        if self.step_control.is_some() {
            sim.set_step_control(self.step_control)?;
        }
        sim.set_state_integrator(self.state_integrator)?;
        Ok(sim)
    }
}
