//! Constructing a [`Simulation`] with defaults, laws given per node or by position: the
//! only way in.

use rsf_fem::DofTransform;
use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::{Kinematics, Newmark, StepControl, VelocityIntegrator};

use crate::error::{invalid, Error, Result};
use crate::fault_alone::{Elastic, FaultAlone};
use crate::fault_ode::{FaultOde, FaultOdeOptions, SchurOnlySetup};
use crate::fault_operator::FaultOperator;
use crate::method::fixed_point::FixedPointOptions;
use crate::method::solver::{SolverKind, SolverOptions};
use crate::method::state_integrator::StateIntegrator;
use crate::method::{Method, MethodOptions};
use crate::model::Model;
use crate::normal_stress::{NormalReactions, NormalStress};
use crate::problem::{NoState, Problem};
use crate::simulation_state::SimulationState;

use super::checks::Parts;
use super::step::impose_dirichlet;
use super::workspace::{NormalWork, Workspace};
use super::Simulation;

/// The friction-law type of a [`SimulationBuilder`] before a law is chosen: `build` is
/// only available once [`friction`](SimulationBuilder::friction) or
/// [`friction_at`](SimulationBuilder::friction_at) has been called.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Unset;

/// Builds a [`Simulation`] from a [`Model`] — the only way to construct one: the friction
/// law (required), the state law, the initial state, the velocity integrator (default
/// [`Newmark`]), the time step τ (required; the initial one with
/// [`step_control`](Self::step_control)), the velocity solver (default
/// [`SolverKind::Auto`], direct or TNNMG by size) and its options, the fixed point options
/// (default [`FixedPointOptions::default`]) and the state update (default backward Euler,
/// [`StateIntegrator`]). Setters only record; [`build`](Self::build) checks everything
/// once (naming the part as its setter does), then assembles.
///
/// Laws and initial states are either uniform or functions of the node position `x` (m),
/// evaluated at the frictional nodes ([`Model::on_frictional_nodes`]): a heterogeneous fault
/// needs no knowledge of the node order. Errors of those functions (e.g. invalid
/// parameters) are reported by [`build`](Self::build).
///
/// ```no_run
/// use rsf::friction::{DieterichRuina, RateStateParams};
/// use rsf::state::Aging;
/// use rsf::SimulationBuilder;
/// use rsf_scenes::SliderScene;
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
///
/// `D` is the spatial dimension, `C` the components per node (default `D`; see [`Model`]).
pub struct SimulationBuilder<const D: usize, L, S, I, const C: usize = D> {
    model: Model<D, C>,
    friction: Result<Vec<L>>,
    state: Result<Vec<S>>,
    alpha0: Option<Vec<f64>>,
    v0: Option<Vec<f64>>,
    tau: Option<f64>,
    /// The radiation damping η (Pa·s/m) of every frictional node given by
    /// [`radiation_damping`](Self::radiation_damping) or
    /// [`radiation_damping_at`](Self::radiation_damping_at).
    eta: Option<Vec<f64>>,
    /// How the fault's normal stress is found ([`normal_stress`](Self::normal_stress)).
    normal_stress: NormalStress,
    /// The pore pressure ([`pore_pressure`](Self::pore_pressure)).
    pore_pressure: Option<PressureField<D>>,
    method: MethodOptions<I>,
    /// The settings of the implicit method given explicitly (by their setters' names):
    /// a method that does not use one of them refuses to be built.
    implicit_settings: Vec<&'static str>,
}

impl<const D: usize, const C: usize> SimulationBuilder<D, Unset, NoState, Newmark, C> {
    /// A builder for `model` with the defaults above.
    pub fn new(model: Model<D, C>) -> Self {
        Self {
            model,
            friction: Ok(Vec::new()),
            state: Ok(Vec::new()),
            alpha0: None,
            v0: None,
            tau: None,
            eta: None,
            normal_stress: NormalStress::Fixed,
            pore_pressure: None,
            implicit_settings: Vec::new(),
            method: MethodOptions {
                integrator: Newmark,
                solver: SolverKind::default(),
                solver_options: SolverOptions::default(),
                fixed_point: FixedPointOptions::default(),
                step_control: None,
                state_integrator: StateIntegrator::default(),
            },
        }
    }
}

/// `f` at every frictional node, collecting the first error.
fn per_node<const D: usize, const C: usize, T, E: Into<Error>>(
    model: &Model<D, C>,
    f: impl FnMut(&[f64; D]) -> std::result::Result<T, E>,
) -> Result<Vec<T>> {
    model
        .on_frictional_nodes(f)
        .into_iter()
        .map(|r| r.map_err(Into::into))
        .collect()
}

fn per_fault_point<const D: usize, const C: usize, T, E: Into<Error>>(
    model: &Model<D, C>,
    f: impl FnMut(crate::model::FaultPoint<'_, D>) -> std::result::Result<T, E>,
) -> Result<Vec<T>> {
    model
        .on_fault_points(f)
        .into_iter()
        .map(|r| r.map_err(Into::into))
        .collect()
}

/// What a checked builder passes on besides the laws.
struct Checked<const D: usize, I, const C: usize> {
    model: Model<D, C>,
    v0: Option<Vec<f64>>,
    method: MethodOptions<I>,
    /// The problem's radiation damping η (Pa·s/m) of every frictional node.
    eta: Vec<f64>,
    normal_stress: NormalStress,
    pore_pressure: Option<PressureField<D>>,
    implicit_settings: Vec<&'static str>,
}

/// A pore-pressure field as the builder holds it.
type PressureField<const D: usize> = std::sync::Arc<dyn crate::pore_pressure::PorePressure<D>>;

/// The parts of a builder whose types change with the laws and the integrator.
type Laws<L, S, I> = (Result<Vec<L>>, Result<Vec<S>>, I);

impl<const D: usize, L, S, I, const C: usize> SimulationBuilder<D, L, S, I, C> {
    fn retype<L2, S2, I2>(
        self,
        f: impl FnOnce(Laws<L, S, I>) -> Laws<L2, S2, I2>,
    ) -> SimulationBuilder<D, L2, S2, I2, C> {
        let Self {
            model,
            friction,
            state,
            alpha0,
            v0,
            tau,
            eta,
            normal_stress,
            pore_pressure,
            method,
            implicit_settings,
        } = self;
        let MethodOptions {
            integrator,
            solver,
            solver_options,
            fixed_point,
            step_control,
            state_integrator,
        } = method;
        let (friction, state, integrator) = f((friction, state, integrator));
        SimulationBuilder {
            model,
            friction,
            state,
            alpha0,
            v0,
            tau,
            eta,
            normal_stress,
            pore_pressure,
            method: MethodOptions {
                integrator,
                solver,
                solver_options,
                fixed_point,
                step_control,
                state_integrator,
            },
            implicit_settings,
        }
    }

    /// Records that the implicit method's setting `name` was given.
    fn implicit_setting(mut self, name: &'static str) -> Self {
        if !self.implicit_settings.contains(&name) {
            self.implicit_settings.push(name);
        }
        self
    }

    /// The model.
    pub fn model(&self) -> &Model<D, C> {
        &self.model
    }

    /// The method's options set so far.
    pub fn method(&self) -> &MethodOptions<I> {
        &self.method
    }

    /// The time step τ set so far (s).
    pub fn tau(&self) -> Option<f64> {
        self.tau
    }

    /// The same friction law at every frictional node.
    pub fn friction<L2: FrictionLaw>(self, law: L2) -> SimulationBuilder<D, L2, S, I, C> {
        let laws = Ok(vec![law; self.model.frictional_boundary.len()]);
        self.retype(|(_, s, i)| (laws, s, i))
    }

    /// The friction law at each frictional node from its position `x` (m).
    pub fn friction_at<L2: FrictionLaw, E: Into<Error>>(
        self,
        law: impl FnMut(&[f64; D]) -> std::result::Result<L2, E>,
    ) -> SimulationBuilder<D, L2, S, I, C> {
        let laws = per_node(&self.model, law);
        self.retype(|(_, s, i)| (laws, s, i))
    }

    /// The friction law at each frictional node from its fault and position
    /// ([`FaultPoint`](crate::model::FaultPoint)): each fault of a network its own law and
    /// parameters (docs/fault-networks.md).
    ///
    /// ```
    /// use rsf::fem::{rectangle, Diagonal};
    /// use rsf::friction::{DieterichRuina, RateStateParams};
    /// use rsf::{Material, ModelBuilder, Part, SimulationBuilder};
    /// let block = rectangle([-2.0, -1.0], [4.0, 2.0], 17, 9, Diagonal::Forward)?;
    /// let model = ModelBuilder::new(block)
    ///     .material(Material::new(1e10, 0.25, 2700.0))
    ///     .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-9, 0.0])
    ///     .dirichlet(Part::predicate("bottom", |x| x[1] < -1.0 + 1e-9), [-1e-9, 0.0])
    ///     .internal_fault("west", [-1.0, -0.5], [-1.0, 0.5])
    ///     .internal_fault("east", [1.0, -0.5], [1.0, 0.5])
    ///     .build()?;
    /// let params = |b: f64| RateStateParams { mu0: 0.6, a: 0.01, b, v0: 1e-6, l: 1e-4, sigma_n: 5e7 };
    /// // The west fault velocity weakening, the east one strengthening.
    /// let sim = SimulationBuilder::new(model).friction_on_faults(|p| {
    ///     DieterichRuina::new(params(if p.fault == "west" { 0.015 } else { 0.005 }))
    /// });
    /// # let _ = sim;
    /// # Ok::<(), rsf::Error>(())
    /// ```
    pub fn friction_on_faults<L2: FrictionLaw, E: Into<Error>>(
        self,
        law: impl FnMut(crate::model::FaultPoint<'_, D>) -> std::result::Result<L2, E>,
    ) -> SimulationBuilder<D, L2, S, I, C> {
        let laws = per_fault_point(&self.model, law);
        self.retype(|(_, s, i)| (laws, s, i))
    }

    /// The state law at each frictional node from its fault and position
    /// ([`FaultPoint`](crate::model::FaultPoint)).
    pub fn state_law_on_faults<S2: StateLaw, E: Into<Error>>(
        self,
        law: impl FnMut(crate::model::FaultPoint<'_, D>) -> std::result::Result<S2, E>,
    ) -> SimulationBuilder<D, L, S2, I, C> {
        let laws = per_fault_point(&self.model, law);
        self.retype(|(f, _, i)| (f, laws, i))
    }

    /// The initial state α₀ at each frictional node from its fault and position
    /// ([`FaultPoint`](crate::model::FaultPoint)).
    pub fn initial_state_on_faults(
        mut self,
        alpha0: impl FnMut(crate::model::FaultPoint<'_, D>) -> f64,
    ) -> Self {
        self.alpha0 = Some(self.model.on_fault_points(alpha0));
        self
    }

    /// The radiation damping η (Pa·s/m, ≥ 0) at each frictional node from its fault and
    /// position ([`FaultPoint`](crate::model::FaultPoint)); as
    /// [`radiation_damping_at`](Self::radiation_damping_at) otherwise.
    pub fn radiation_damping_on_faults(
        mut self,
        eta: impl FnMut(crate::model::FaultPoint<'_, D>) -> f64,
    ) -> Self {
        self.eta = Some(self.model.on_fault_points(eta));
        self
    }

    /// The same state law at every frictional node (not needed if the friction law does
    /// not use the state, e.g. Tresca).
    pub fn state_law<S2: StateLaw>(self, law: S2) -> SimulationBuilder<D, L, S2, I, C> {
        let laws = Ok(vec![law; self.model.frictional_boundary.len()]);
        self.retype(|(f, _, i)| (f, laws, i))
    }

    /// The state law at each frictional node from its position `x` (m).
    pub fn state_law_at<S2: StateLaw, E: Into<Error>>(
        self,
        law: impl FnMut(&[f64; D]) -> std::result::Result<S2, E>,
    ) -> SimulationBuilder<D, L, S2, I, C> {
        let laws = per_node(&self.model, law);
        self.retype(|(f, _, i)| (f, laws, i))
    }

    /// The velocity integrator (of the implicit method; a quasi-dynamic [`FaultOde`] takes
    /// only a [`Quasistatic`](rsf_time::Quasistatic) one, for the radiation damping it may
    /// carry).
    pub fn integrator<I2: VelocityIntegrator>(
        self,
        integrator: I2,
    ) -> SimulationBuilder<D, L, S, I2, C> {
        self.retype(|(f, s, _)| (f, s, integrator))
    }

    /// The radiation damping η on Γ_F (Pa·s/m, ≥ 0; default 0): physics, used by every
    /// method — a damping term `η|V|²/2` per unit area in the implicit scheme's velocity
    /// problem, the `η V` of the fault ODE's stress balance (docs/math.md §11–12). Given
    /// here or (the older way) by an integrator
    /// [`Quasistatic::with_radiation_damping`](rsf_time::Quasistatic::with_radiation_damping),
    /// not both.
    pub fn radiation_damping(mut self, eta: f64) -> Self {
        self.eta = Some(vec![eta; self.model.frictional_boundary.len()]);
        self
    }

    /// The radiation damping η (Pa·s/m, ≥ 0) of each frictional node from its position `x`
    /// (m): e.g. `μ/(2c_s)` of the material there, on a fault between materials or through
    /// layers. As [`radiation_damping`](Self::radiation_damping) otherwise (a uniform η is
    /// the same as giving it there, to the bit).
    ///
    /// # Errors (at `build`, `build_fault_ode`)
    /// As [`radiation_damping`](Self::radiation_damping), naming the first node whose η is
    /// negative or not finite.
    pub fn radiation_damping_at(mut self, eta: impl FnMut(&[f64; D]) -> f64) -> Self {
        self.eta = Some(self.model.on_frictional_nodes(eta));
        self
    }

    /// How the fault's normal stress `σ̄_n` is found (default [`NormalStress::Fixed`], the
    /// friction laws' own). [`NormalStress::FromSlip`] on a fault inside the body
    /// ([`ModelBuilder::internal_fault`](crate::ModelBuilder::internal_fault), plane
    /// strain) makes it change with the slip and the loading: explicitly in every
    /// evaluation of the fault ODE, inside the fixed point (like the state) in the implicit
    /// scheme (docs/faults-inside.md "Normal stress").
    ///
    /// # Errors (at `build`, `build_fault_ode`)
    /// [`Error::InvalidParameter`] named `normal_stress` without an internal fault, for a
    /// scalar field, or for a law without a normal stress it is proportional to
    /// ([`FrictionLaw::proportional_to_normal_stress`]); in the implicit scheme also for
    /// laws without a state (no fixed point to iterate it in).
    pub fn normal_stress(mut self, choice: NormalStress) -> Self {
        self.normal_stress = choice;
        self
    }

    /// A pore pressure `p(x, t)` on the fault (default none): every friction law is
    /// evaluated at the effective normal stress `σ̄_n − p` of its node
    /// ([`FrictionLaw::potential_at_normal_stress`]; `σ̄_n` the law's own or, with
    /// [`NormalStress::FromSlip`], the one from slip) — in every evaluation of the fault ODE
    /// (its stages: the step-size control sees the pressure's time dependence; steps end
    /// at the field's [breakpoints](crate::pore_pressure::PorePressure::breakpoints)) and at the end of
    /// every step of the implicit scheme (docs/seas-bp6.md). A constant pressure `p₀` gives
    /// the bits of the laws built with `σ̄_n − p₀`.
    ///
    /// # Errors (at `build`, `build_fault_ode`)
    /// [`Error::InvalidParameter`] named `pore_pressure` for a law without a normal stress
    /// or one that cannot be evaluated at another; in a run,
    /// [`Error::NormalStressNotPositive`](crate::Error::NormalStressNotPositive) (node and
    /// time) where `σ̄_n − p ≤ 0` at an accepted time (a Runge–Kutta stage there only
    /// rejects the step).
    pub fn pore_pressure(
        mut self,
        field: impl crate::pore_pressure::PorePressure<D> + 'static,
    ) -> Self {
        self.pore_pressure = Some(std::sync::Arc::new(field));
        self
    }

    /// The same initial state α₀ at every frictional node (`ln θ₀` with θ₀ in s for the
    /// rate-and-state laws). Required if the friction law uses the state.
    pub fn initial_state(mut self, alpha0: f64) -> Self {
        self.alpha0 = Some(vec![alpha0; self.model.frictional_boundary.len()]);
        self
    }

    /// The initial state at each frictional node from its position `x` (m).
    pub fn initial_state_at(mut self, alpha0: impl FnMut(&[f64; D]) -> f64) -> Self {
        self.alpha0 = Some(self.model.on_frictional_nodes(alpha0));
        self
    }

    /// The initial velocity `v_0(x)` (m/s) of every node from its position `x` (m);
    /// default rest. The constrained components take their Dirichlet values at `t = 0`
    /// whatever this gives (0, or the prescribed velocity).
    /// `v_0` is given in Cartesian components (rotated into the nodal frames of a slanted
    /// fault, [`Model::to_model`]) for the displacement `u` (multiplied by
    /// the frictional boundary's `slip_factor` on a model of an antisymmetric fault, whose
    /// unknown is `s·u`). On a model with a fault inside the body each copy of a split
    /// vertex takes the value at a point moved into its own side by 10⁻⁹ of the largest
    /// coordinate (so a velocity that jumps across the fault, e.g. each side's rigid
    /// motion, is seen by the two copies), and the field goes into the mean–jump unknowns.
    pub fn initial_velocity_at(mut self, mut v0: impl FnMut(&[f64; D]) -> [f64; C]) -> Self {
        let model = &self.model;
        let s = model.frictional_boundary.slip_factor;
        self.v0 = Some(match &model.internal_fault {
            // Each side's own value at a split vertex, then mean and jump.
            Some(f) => {
                let cartesian: Vec<f64> = model
                    .vertices
                    .iter()
                    .enumerate()
                    .flat_map(|(p, x)| v0(&f.moved_into_side(p, x)).map(|v| s * v))
                    .collect();
                // T⁻¹ of a field of the model's size; a fault whose transform does not fit
                // the model leaves it empty and is refused by Model::validate at `build`.
                f.transform.to_model(&cartesian).unwrap_or_default()
            }
            None => model
                .vertices
                .iter()
                .enumerate()
                .flat_map(|(p, x)| model.to_model(p, v0(x).map(|v| s * v)))
                .collect(),
        });
        self
    }

    /// The time step τ (s); required (with [`step_control`](Self::step_control), the
    /// initial step).
    pub fn time_step(mut self, tau: f64) -> Self {
        self.tau = Some(tau);
        self
    }

    /// The velocity solver.
    pub fn solver(mut self, solver: SolverKind) -> Self {
        self.method.solver = solver;
        self.implicit_setting("solver")
    }

    /// The options of the velocity solvers.
    pub fn solver_options(mut self, options: SolverOptions) -> Self {
        self.method.solver_options = options;
        self.implicit_setting("solver_options")
    }

    /// The fixed point options.
    pub fn fixed_point(mut self, options: FixedPointOptions) -> Self {
        self.method.fixed_point = options;
        self.implicit_setting("fixed_point")
    }

    /// How a step advances the state (default backward Euler, the paper's).
    pub fn state_integrator(mut self, integrator: StateIntegrator) -> Self {
        self.method.state_integrator = integrator;
        self.implicit_setting("state_integrator")
    }

    /// Adaptive time steps with error control from the initial τ of
    /// [`time_step`](Self::time_step) (default: fixed τ).
    pub fn step_control(mut self, control: StepControl) -> Self {
        self.method.step_control = Some(control);
        self.implicit_setting("step_control")
    }
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    SimulationBuilder<D, L, S, I, C>
{
    /// The checks of [`build`](Self::build) and [`build_fault_ode`](Self::build_fault_ode):
    /// the builder (with its model and method), the laws, `α₀` (0 where unset) and τ.
    #[allow(clippy::type_complexity)]
    fn checked(self) -> Result<(Checked<D, I, C>, Vec<L>, Vec<S>, Vec<f64>, f64)> {
        let friction = self.friction?;
        let state_laws = self.state?;
        let nf = self.model.frictional_boundary.len();
        let tau = Parts {
            model: &self.model,
            friction_laws: &friction,
            state_laws: &state_laws,
            alpha0: self.alpha0.as_deref(),
            v0: self.v0.as_deref(),
            tau: self.tau,
            method: &self.method,
        }
        .check()?;
        let alpha0 = self.alpha0.unwrap_or_else(|| vec![0.0; nf]);
        let eta = match (self.eta, self.method.integrator.radiation_damping()) {
            (None, eta) => vec![eta; nf],
            (Some(eta), 0.0) => {
                if let Some((k, e)) = eta
                    .iter()
                    .enumerate()
                    .find(|(_, e)| !(e.is_finite() && **e >= 0.0))
                {
                    return Err(invalid(
                        "radiation_damping",
                        format!("η = {e} Pa·s/m at frictional node {k} must be finite and >= 0"),
                    ));
                }
                eta
            }
            (Some(eta), by_integrator) => {
                let eta = eta.first().copied().unwrap_or(0.0);
                return Err(invalid(
                    "radiation_damping",
                    format!(
                        "η = {eta} Pa·s/m given twice: also {by_integrator} Pa·s/m by the \
                         integrator (give it once, with SimulationBuilder::radiation_damping)"
                    ),
                ));
            }
        };
        let this = Checked {
            model: self.model,
            v0: self.v0,
            method: self.method,
            eta,
            normal_stress: self.normal_stress,
            pore_pressure: self.pore_pressure,
            implicit_settings: self.implicit_settings,
        };
        Ok((this, friction, state_laws, alpha0, tau))
    }

    /// Checks every part once and builds the simulation: assembles
    /// `A = c_M M + c_K K` (+ the absorbing parts' dashpots `C`, + radiation damping), sets up the solver, and starts from
    /// `u_0 = model.initial_displacement`, `v_0` = the Dirichlet velocities at `t = 0` on
    /// constrained dofs and [`initial_velocity_at`](Self::initial_velocity_at) (default 0)
    /// elsewhere, `a_0 = 0`, `α = α₀`, at step 0 and time 0.
    ///
    /// # Errors
    /// The first error of a per-node function; the checks' errors: τ, `initial_state` or a
    /// state law not set where needed ([`Error::InvalidParameter`] naming `tau`,
    /// `initial_state`, `state_law`), the model ([`Model::validate`], e.g.
    /// [`Error::FreeNormal`]), a missing mass matrix (`mass`), [`Error::StateVariableMismatch`],
    /// [`Error::StateLaw`] (monotonicity probe), the fixed point options
    /// (`fixed_point.*`), the step control, the state integrator (`state_integrator`);
    /// then set-up errors of the solver (e.g. `tau` for a non-finite time-step matrix);
    /// [`Error::InvalidParameter`] named `absorbing` for a model with absorbing parts
    /// ([`Model::absorbing`]) and an integrator without inertia (dashpots on a
    /// quasistatic model would damp its slow deformation, not radiate waves; the fault ODE,
    /// [`build_fault_ode`](Self::build_fault_ode), treats them as traction-free instead).
    pub fn build(self) -> Result<Simulation<D, L, S, I, C>> {
        let (this, friction, state_laws, alpha0, tau) = self.checked()?;
        if this.model.absorbing.is_some() && !this.method.integrator.uses_mass() {
            return Err(invalid(
                "absorbing",
                format!(
                    "the model has absorbing parts and the integrator ({}) has no inertia: \
                     use Newmark or backward Euler",
                    this.method.integrator.name()
                ),
            ));
        }
        let controller = match &this.method.step_control {
            Some(c) => Some(c.start(tau)?),
            None => None,
        };
        let method = Method::new(this.method, &this.model, tau, &this.eta)?;
        let n = this.model.num_dofs();
        let mut kinematics = Kinematics::zeros(n);
        kinematics
            .u
            .copy_from_slice(&this.model.initial_displacement);
        if let Some(v0) = &this.v0 {
            kinematics.v.copy_from_slice(v0);
        }
        impose_dirichlet(&this.model, 0.0, &mut kinematics.v);
        let mut work = Workspace::new(
            n,
            &friction,
            &alpha0,
            &this.model.frictional_boundary.weights,
            method.fixed_point(),
        );
        if this.normal_stress != NormalStress::Fixed
            && !friction.iter().any(FrictionLaw::uses_state)
        {
            return Err(invalid(
                "normal_stress",
                "a normal stress from slip is iterated with the state in the implicit \
                 scheme's fixed point; laws without a state have none (use the fault ODE, \
                 or a law with a state)",
            ));
        }
        work.normal =
            NormalReactions::new(this.normal_stress, &this.model, &friction, &kinematics)?
                .map(|r| NormalWork::new(r, n, &friction, &this.model.frictional_boundary.weights));
        let problem = Problem::new(this.model, friction, state_laws, this.eta)
            .with_normal_stress(this.normal_stress)
            .with_pore_pressure(this.pore_pressure)?;
        if let Some(at_nodes) = problem.pore_pressure() {
            let mut pw =
                crate::pore_pressure::PressureWork::new(at_nodes.clone(), problem.friction_laws());
            let base = work.normal.as_ref().map(|n| n.sigma.clone());
            pw.lower_from(0.0, base.as_deref())?;
            pw.tractions.sigma.copy_from_slice(&pw.sigma);
            work.pressure = Some(pw);
        }
        let state = SimulationState {
            step: 0,
            time: 0.0,
            tau,
            time_origin: (0, 0.0),
            kinematics,
            alpha: alpha0,
            controller,
        };
        Ok(Simulation {
            problem,
            method,
            state,
            work,
        })
    }

    /// Checks every part as [`build`](Self::build) does and builds a quasi-dynamic run
    /// condensed onto the fault and integrated by an explicit Runge–Kutta pair
    /// ([`FaultOde`], docs/math.md §12) instead of the implicit simulation: the problem
    /// (model, laws, `α₀`, the radiation damping η > 0) and the time step of
    /// [`time_step`](Self::time_step) as the first trial step. The settings of the
    /// implicit method (velocity solver and its options, fixed point, step control, state
    /// integrator) do not apply to it: given, they are an error (a method is given only
    /// the settings it uses); an initial velocity is ignored (the slip rates follow from
    /// the stress). Absorbing parts of the model ([`Model::absorbing`]) are traction-free
    /// here: a quasi-dynamic model has no waves in the volume, and the dashpots' force
    /// `ρc |v − v_far|` is dropped (for SEAS BP1 between events `ρc_s V_p ≈ 1e-2 Pa`).
    ///
    /// # Errors
    /// As [`build`](Self::build); [`Error::InvalidParameter`] named after the first
    /// implicit-method setting given (`solver`, `solver_options`, `fixed_point`,
    /// `step_control`, `state_integrator`), `integrator` for an integrator with inertia,
    /// `radiation_damping` for η ≤ 0, `loading` for a custom loading history, `dirichlet`
    /// for a frictional node with some components prescribed at a non-zero velocity; the
    /// options' errors; [`Error::Direct`] if `K` is not positive definite on the free dofs.
    pub fn build_fault_ode(self, options: FaultOdeOptions) -> Result<FaultOde<D, L, S, C>> {
        self.fault_ode(options, Elastic::Condensed(None))
    }

    /// As [`build_fault_ode`](Self::build_fault_ode) with the elastic operator `S` given
    /// instead of condensed from the model's stiffness ([`FaultOperator`]): e.g. a
    /// boundary-element half-space operator on the fault's nodes, to compare with the
    /// finite-element one on the same problem. The model still gives everything else: the
    /// unknowns (the free components of the frictional nodes, in their order), the loads
    /// condensed onto them, the volume between steps. `options.kernel` is not used.
    ///
    /// # Errors
    /// As [`build_fault_ode`](Self::build_fault_ode); [`Error::InvalidParameter`] named
    /// `fault_operator` if the operator's dimension is not the fault's number of slip
    /// unknowns.
    pub fn build_fault_ode_with_operator(
        self,
        options: FaultOdeOptions,
        operator: Box<dyn FaultOperator>,
    ) -> Result<FaultOde<D, L, S, C>> {
        self.fault_ode(options, Elastic::Condensed(Some(operator)))
    }

    /// As [`build_fault_ode`](Self::build_fault_ode) without ever holding the volume's
    /// whole factor (issue 70; docs/three-d.md, "The condensation without the whole
    /// factor"): the Schur complement `S`, the condensed loads and the rows of
    /// `setup.watch_vertices` come from one multifrontal elimination that drops each
    /// front's factor once its update is passed on ([`rsf_direct::SchurOnly`]), so the
    /// set-up's memory is its largest fronts and pending blocks, not the factor; it can be
    /// checkpointed and resumed, bounded in memory and watched ([`SchurOnlySetup`]). The
    /// same `S` as [`build_fault_ode`](Self::build_fault_ode)'s up to round-off (another
    /// summation order: another trajectory at the level of round-off, so a run keeps one
    /// set-up). What it gives up: observers read the fault and the watched vertices only
    /// (one that [reads the volume](crate::Observer::reads_volume) ends the run with an
    /// error), and the normal stress must be fixed.
    ///
    /// # Errors
    /// As [`build_fault_ode`](Self::build_fault_ode); [`Error::InvalidParameter`] named
    /// `normal_stress` for a normal stress from slip, `volume_vertices` for a vertex that
    /// is not the model's; the elimination's ([`Error::Direct`]).
    pub fn build_fault_ode_schur_only(
        self,
        options: FaultOdeOptions,
        setup: SchurOnlySetup,
    ) -> Result<FaultOde<D, L, S, C>> {
        self.fault_ode(options, Elastic::SchurOnly(setup))
    }

    /// As [`build_fault_ode`](Self::build_fault_ode) for a fault without a volume
    /// ([`Model::fault_only`]): the elastic operator and the plate motion that loads the
    /// fault by back slip are `alone`'s ([`FaultAlone`]: `g₀ − S (u_F − t v_pl)` on the
    /// right-hand side, `g₀` the model's load), the laws, state and damping the builder's.
    /// Observers see the fault only (an observer asking for vertices off it is refused).
    /// `options.kernel` is not used.
    ///
    /// # Errors
    /// As [`build_fault_ode`](Self::build_fault_ode); [`Error::InvalidParameter`] named
    /// `stiffness` for a model with a stiffness (a body: use
    /// [`build_fault_ode_with_operator`](Self::build_fault_ode_with_operator)),
    /// `dirichlet` for prescribed velocities, `fault_operator` for an operator of another
    /// dimension than the fault's slip unknowns, `plate_velocity` for another length or
    /// non-finite entries, `normal_stress` for a normal stress from slip.
    pub fn build_fault_ode_alone(
        self,
        options: FaultOdeOptions,
        alone: FaultAlone,
    ) -> Result<FaultOde<D, L, S, C>> {
        self.fault_ode(options, Elastic::Alone(alone))
    }

    fn fault_ode(self, options: FaultOdeOptions, elastic: Elastic) -> Result<FaultOde<D, L, S, C>> {
        let (this, friction, state_laws, alpha0, tau) = self.checked()?;
        if let Some(name) = this.implicit_settings.first() {
            return Err(invalid(
                name,
                "a setting of the implicit method, which the fault ODE does not use (its \
                 steps are controlled by FaultOdeOptions)",
            ));
        }
        if this.method.integrator.uses_mass() {
            return Err(invalid(
                "integrator",
                "a run condensed onto the fault is quasi-dynamic: use Quasistatic with \
                 radiation damping, not an integrator with inertia",
            ));
        }
        FaultOde::new(
            Problem::new(this.model, friction, state_laws, this.eta)
                .with_normal_stress(this.normal_stress)
                .with_pore_pressure(this.pore_pressure)?,
            alpha0,
            tau,
            options,
            elastic,
        )
    }
}
