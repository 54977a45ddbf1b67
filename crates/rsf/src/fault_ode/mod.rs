//! Quasi-dynamic runs condensed onto the fault: the equations of a model without inertia
//! and with radiation damping, written as an ODE in the fault's slip and state and
//! integrated by an explicit embedded Runge–Kutta pair with adaptive steps (docs/math.md
//! §12) — the formulation of boundary-element earthquake-cycle codes, with the
//! finite-element model's exact condensation as the elastic operator. Beyond the paper,
//! whose implicit scheme ([`Simulation`](crate::Simulation)) stays the default.

use std::time::Instant;

use rsf_direct::Condensation;
pub use rsf_direct::InteriorOrdering;
use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::{EmbeddedRungeKutta, Kinematics, OdeSystem, RungeKuttaState};

use crate::checkpoint::{bad_value, check_size, Checkpoint};
use crate::error::{invalid, Error, Result};
use crate::fault_alone::{free_fault_dofs, load_rate, Body, Elastic};
use crate::fault_kernel::{condensed_operator, SchurSource};
use crate::fault_operator::FaultOperator;
pub use crate::fault_operator::{FaultKernel, KernelReport, MAX_KERNEL_EPSILON};
use crate::method_state::{FaultOdeState, MethodState};
use crate::model::loading::TimeFunction;
use crate::model::Model;
use crate::normal_stress::{NormalCoupling, NormalStress, ScaledTractions};
use crate::observe::{FaultTractions, Observer};
use crate::problem::Problem;
use crate::report::StepReport;
use crate::run::{run_until, RunError, RunSummary, Stepping, Until};
use crate::simulation_state::SimulationState;
use crate::volume_probe::VolumeProbe;

mod linger;
mod options;
mod rates;
pub(crate) mod schur_only;
mod shared;

pub use crate::fault_alone::{SchurOnlySetup, SetupProgress};
pub use linger::LINGER;
pub use options::FaultOdeOptions;
use rates::{FaultRates, Rates};

/// A quasi-dynamic run condensed onto the frictional boundary Γ_F and integrated in time
/// by an explicit embedded Runge–Kutta pair (docs/math.md §12).
///
/// The model has no inertia and radiation damping `η > 0`. With the stiffness `K`
/// condensed exactly onto the free components `F` of the frictional nodes (Schur
/// complement `S`, [`Condensation`]), equilibrium at time `t` is, node by node,
///
/// ```text
/// w_k (η V_k + ∂ϕ_k(|V_k|; α_k)) ∋ g(t) − (S u_F)_k,    g(t) = g₀ + G(t) g₁
/// ```
///
/// (`w_k` the node's lumped weight; `g₀` the condensed load with the fixed dofs at `u₀`,
/// `g₁` that of the unit Dirichlet velocities, `G(t) = ∫₀ᵗ g` of the loading history), so
/// the slip rate `V_k` is the exact minimiser of `½η|V|² − τ_k·V + ϕ_k(|V|)` with
/// `τ_k = (g(t) − S u_F)_k / w_k` ([`ConvexPotential::minimize_block`](rsf_friction::ConvexPotential::minimize_block)), and the ODE is
///
/// ```text
/// u̇_F = V(t, u_F, α),    α̇_k = −∂ψ/∂α(α_k, |V_k|).
/// ```
///
/// Each right-hand side costs one product with `S` (dense: `m²` multiply-adds, `m` the
/// number of free components; or with its ℋ-matrix, [`FaultKernel::Hierarchical`]:
/// `O(k m log m)`) and one scalar minimisation per node; the volume is never
/// touched during the steps. Observers see the same [`StepView`](crate::StepView) as in a
/// [`Simulation`](crate::Simulation): `u`, `v` on Γ_F and the fixed dofs always, the rest
/// of the field (one sparse forward and backward sweep for each of `u` and `v`) only if
/// an observer [reads the volume](Observer::reads_volume) — else it is NaN, except at the
/// few vertices observers [ask for](Observer::volume_vertices) (surface stations: one
/// dot product per component with precomputed rows of the extension operator).
///
/// Suited to quasi-dynamic earthquake-cycle problems (SEAS BP1): explicit steps are
/// limited by the stiffness `‖S‖/(w η)` of the damped fault, which the events' own time
/// scale already resolves, and the steps between events grow to months. A friction law
/// with a kink at `V = 0` (Tresca, Dieterich–Ruina below `V_m`) makes the right-hand side
/// non-smooth and the steps small; the implicit [`Simulation`](crate::Simulation) is the
/// better method there. Frictional nodes may be fully prescribed (their slip rate is the
/// Dirichlet velocity); a node with only some components fixed must have them at rest (a
/// bilateral normal).
///
/// ```
/// // A small BP1-like fault (docs/seas-bp1.md): 10 km deep, Δz = 500 m, 20 km domain.
/// let bp1 = rsf_scenes::SeasBp1 { w_f: 10e3, h_top: 2e3, h_transition: 1e3, ..rsf_scenes::SeasBp1::default() };
/// let grid = rsf_scenes::SeasBp1Grid { dz: 500.0, domain: 20e3, ratio: 1.1 };
/// let model = bp1.model(&grid, false)?;
/// let mut ode = bp1.fault_ode(model, bp1.fault_ode_options(1e-6)?)?;
/// // At most 10⁵ steps (a bound stated for this run: it takes a few hundred).
/// let ten_years = rsf::Until::TimeWithin { time: 10.0 * rsf::observe::SECONDS_PER_YEAR, max_steps: 100_000 };
/// let summary = ode.run_until(ten_years, &mut [])?;
/// assert_eq!(ode.condensed_dim(), 20); // 21 fault nodes, the one at W_f creeps
/// assert!(summary.steps > 0 && (ode.state().time / rsf::observe::SECONDS_PER_YEAR - 10.0).abs() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct FaultOde<const D: usize, L, S, const C: usize = D> {
    problem: Problem<D, L, S, C>,
    rates: FaultRates<C>,
    rk: EmbeddedRungeKutta,
    /// `[u_F (m free components); α (one per frictional node)]`.
    y: Vec<f64>,
    state: SimulationState,
    /// The dofs neither fixed nor condensed onto (NaN in the state unless computed).
    interior: Vec<usize>,
    /// The fixed dofs (velocity 0 but on the Dirichlet dofs): what a step writes of them
    /// costs their number, not the whole field's.
    fixed: Vec<usize>,
    /// Whether the state's `u` and `v` are NaN at every `interior` dof but the probe's
    /// (which it rewrites after every step): then a step without the volume writes only
    /// the fault's, the loading's and the probe's entries, not the whole field's.
    interior_is_nan: bool,
    zeros: Vec<f64>,
    /// The rate `[V_F; α̇]` at the current point.
    dy: Vec<f64>,
    options: FaultOdeOptions,
    evaluations: usize,
    /// The compression of the normal-stress operator `S_N`, if compressed.
    normal_kernel_report: Option<KernelReport>,
    /// With a normal stress that changes: the laws scaled by it at the last step.
    scaled_tractions: Option<ScaledTractions<L>>,
    /// With a pore pressure: the laws at `σ̄_n − p` of the last step.
    effective_tractions: Option<crate::pore_pressure::EffectiveTractions<L>>,
    /// The vertices off Γ_F that observers read without the volume
    /// ([`Observer::volume_vertices`]), computed after every step.
    probe: Option<VolumeProbe>,
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, const C: usize> FaultOde<D, L, S, C> {
    /// Sets up the run (called by
    /// [`SimulationBuilder::build_fault_ode`](crate::SimulationBuilder::build_fault_ode),
    /// which checks the laws and the model): condenses `K` onto Γ_F, the load and the
    /// Dirichlet velocities, and evaluates the slip rates at `t = 0`.
    pub(crate) fn new(
        problem: Problem<D, L, S, C>,
        alpha0: Vec<f64>,
        dt0: f64,
        options: FaultOdeOptions,
        elastic: Elastic,
    ) -> Result<Self> {
        options.validate()?;
        let model = problem.model();
        let eta = problem.radiation_damping().to_vec();
        if let Some((k, e)) = eta
            .iter()
            .enumerate()
            .find(|(_, e)| !(**e > 0.0 && e.is_finite()))
        {
            return Err(invalid(
                "radiation_damping",
                format!(
                    "η = {e} Pa·s/m at frictional node {k}: a run condensed onto the fault \
                     needs radiation damping η > 0 at every node (quasi-dynamic, \
                     SimulationBuilder::radiation_damping)"
                ),
            ));
        }
        if model.dirichlet.history.integral(0.0).is_none() {
            return Err(invalid(
                "loading",
                "a custom loading history has no closed-form integral; use a constant, ramp \
                 or piecewise-linear history",
            ));
        }
        let fb = &model.frictional_boundary;
        let n = model.num_dofs();
        let mut velocity_factor = vec![0.0; n];
        for (&dof, &f) in model.dirichlet.dofs.iter().zip(&model.dirichlet.factors) {
            velocity_factor[dof] = f;
        }
        for (k, &p) in fb.nodes.iter().enumerate() {
            let comps = C * p..C * p + C;
            let some_fixed = comps.clone().any(|i| model.fixed[i]);
            let all_fixed = comps.clone().all(|i| model.fixed[i]);
            if some_fixed && !all_fixed && comps.clone().any(|i| velocity_factor[i] != 0.0) {
                return Err(invalid(
                    "dirichlet",
                    format!(
                        "frictional node {k} (vertex {p}) has some components prescribed with a \
                         non-zero velocity; a run condensed onto the fault needs them at rest \
                         or the whole node prescribed"
                    ),
                ));
            }
        }
        // The watched vertices' rows: computed with the set-up without the factor, later
        // (watch_vertices) with it.
        let mut probe = None;
        let (body, operator, g0, g1, history, mut normal) = match elastic {
            Elastic::Condensed(operator) => {
                let mut cond = Condensation::<C>::with_ordering(
                    model.stiffness.as_ref(),
                    &model.fixed,
                    &fb.nodes,
                    options.ordering,
                )?;
                let m = cond.dim();
                let operator: Box<dyn FaultOperator> = match operator {
                    Some(op) if op.dim() != m => {
                        return Err(invalid(
                            "fault_operator",
                            format!(
                                "an operator of {} unknowns for a fault of {m} slip unknowns",
                                op.dim()
                            ),
                        ))
                    }
                    Some(op) => op,
                    None => Box::new(condensed_operator(
                        model,
                        &SchurSource::Factor(&cond),
                        options.kernel,
                    )?),
                };
                let big_g0 = model.dirichlet.history.integral(0.0).unwrap_or(0.0);
                let normal = NormalCoupling::new(
                    problem.normal_stress(),
                    model,
                    &mut cond,
                    problem.friction_laws(),
                    &velocity_factor,
                    big_g0,
                )?;
                let mut g0 = vec![0.0; m];
                cond.condense(&model.load, &model.initial_displacement, &mut g0)?;
                let mut g1 = vec![0.0; m];
                cond.condense(&vec![0.0; n], &velocity_factor, &mut g1)?;
                let history = model.dirichlet.history.clone();
                (
                    Body::Volume(Box::new(cond)),
                    operator,
                    g0,
                    g1,
                    history,
                    normal,
                )
            }
            Elastic::SchurOnly(setup) => {
                if problem.normal_stress() != NormalStress::Fixed {
                    return Err(invalid(
                        "normal_stress",
                        "a normal stress from slip needs the volume's factor (its extension \
                         onto the fault's normal dofs): build the fault ODE with \
                         build_fault_ode, not without the factor",
                    ));
                }
                let body = schur_only::condense(model, &options, &velocity_factor, setup)?;
                probe = body.probe;
                (
                    Body::Condensed { dofs: body.dofs },
                    Box::new(body.operator) as Box<dyn FaultOperator>,
                    body.g0,
                    body.g1,
                    model.dirichlet.history.clone(),
                    None,
                )
            }
            Elastic::Alone(mut alone) => {
                if problem.normal_stress() != NormalStress::Fixed {
                    return Err(invalid(
                        "normal_stress",
                        "a fault alone has no volume to take a normal stress from slip from: \
                         use NormalStress::Fixed",
                    ));
                }
                let g1 = load_rate(model, &mut alone, options.parallelism)?;
                let dofs = free_fault_dofs(model);
                let g0 = dofs.iter().map(|&i| model.load[i]).collect();
                // g(t) = g₀ + t S v_pl: the history's integral is t.
                let history = TimeFunction::Constant(1.0);
                (Body::Alone { dofs }, alone.operator, g0, g1, history, None)
            }
        };
        let m = body.dim();
        let normal_kernel_report = match (&mut normal, &body) {
            (Some(n), Body::Volume(cond)) => n.compress(model, cond, options.kernel)?,
            _ => None,
        };
        let scaled_tractions = normal.as_ref().map(|n| ScaledTractions {
            laws: problem.friction_laws().to_vec(),
            sigma0: n.initial().to_vec(),
            sigma: n.initial().to_vec(),
        });
        let zeros = vec![0.0; n];
        let mut first = Vec::with_capacity(fb.len() + 1);
        let mut fixed_velocity = Vec::with_capacity(fb.len());
        let mut count = 0;
        for &p in &fb.nodes {
            first.push(count);
            let mut f = [0.0; C];
            for (c, fc) in f.iter_mut().enumerate() {
                if model.fixed[C * p + c] {
                    *fc = velocity_factor[C * p + c];
                } else {
                    count += 1;
                }
            }
            fixed_velocity.push(f);
        }
        first.push(count);
        debug_assert_eq!(count, m);
        let mut in_interface = vec![false; n];
        for &dof in body.interface_dofs() {
            in_interface[dof] = true;
        }
        let interior = (0..n)
            .filter(|&i| !model.fixed[i] && !in_interface[i])
            .collect();
        let fixed = (0..n).filter(|&i| model.fixed[i]).collect();
        let mut y = Vec::with_capacity(m + fb.len());
        y.extend(
            body.interface_dofs()
                .iter()
                .map(|&dof| model.initial_displacement[dof]),
        );
        y.extend_from_slice(&alpha0);
        let rates = FaultRates {
            body,
            operator,
            par: options.parallelism,
            linger: options.linger,
            g0,
            g1,
            history,
            first,
            fixed_velocity,
            weights: fb.weights.clone(),
            eta,
            r: vec![0.0; m],
            tolerance: options.tolerance,
            slip_scale: options.slip_scale,
            sigma: normal.as_ref().map_or(Vec::new(), |n| n.initial().to_vec()),
            normal,
            parts: None,
            shared: None,
            pressure: problem.pore_pressure().map(|at_nodes| {
                let sigma_laws: Vec<f64> = problem
                    .friction_laws()
                    .iter()
                    .map(|l| l.normal_stress().unwrap_or(f64::NAN))
                    .collect();
                rates::PressureRates {
                    at_nodes: at_nodes.clone(),
                    effective: sigma_laws.clone(),
                    scratch: vec![0.0; sigma_laws.len()],
                    sigma_laws,
                }
            }),
        };
        let effective_tractions =
            rates
                .pressure
                .as_ref()
                .map(|p| crate::pore_pressure::EffectiveTractions {
                    laws: problem.friction_laws().to_vec(),
                    sigma: p.sigma_laws.clone(),
                });
        let mut kinematics = Kinematics::zeros(n);
        kinematics.u.copy_from_slice(&model.initial_displacement);
        let rk = EmbeddedRungeKutta::new(options.tableau, options.runge_kutta, y.len(), dt0)?;
        let state = SimulationState {
            step: 0,
            time: 0.0,
            tau: dt0,
            time_origin: (0, 0.0),
            kinematics,
            alpha: alpha0,
            controller: None,
        };
        let mut ode = Self {
            problem,
            rates,
            rk,
            y,
            state,
            interior,
            fixed,
            interior_is_nan: false,
            zeros,
            dy: Vec::new(),
            options,
            evaluations: 0,
            normal_kernel_report,
            scaled_tractions,
            effective_tractions,
            probe,
        };
        // The slip rates at t = 0 (a check that the initial state is admissible).
        let mut dy = vec![0.0; ode.y.len()];
        let y0 = ode.y.clone();
        ode.system().rate(0.0, &y0, &mut dy)?;
        if let Some(i) = dy.iter().position(|x| !x.is_finite()) {
            return Err(invalid(
                "initial_state",
                format!("the rate of unknown {i} at t = 0 is {}", dy[i]),
            ));
        }
        ode.dy = dy;
        ode.fill_state(false)?;
        Ok(ode)
    }

    fn system(&mut self) -> Rates<'_, L, S, C> {
        Rates {
            friction: self.problem.friction_laws(),
            state_laws: self.problem.state_laws(),
            uses_state: self.problem.uses_state(),
            data: &mut self.rates,
        }
    }

    /// The problem (model and laws).
    pub fn problem(&self) -> &Problem<D, L, S, C> {
        &self.problem
    }

    /// The model.
    pub fn model(&self) -> &Model<D, C> {
        self.problem.model()
    }

    /// The state after the last step: `u`, `v` on Γ_F and the fixed dofs, α, time, the next
    /// step in `tau`; the rest of `u`, `v` as the last step's observers needed it (NaN if
    /// none read the volume).
    pub fn state(&self) -> &SimulationState {
        &self.state
    }

    /// The options.
    pub fn options(&self) -> &FaultOdeOptions {
        &self.options
    }

    /// Number of condensed unknowns (free components on Γ_F).
    pub fn condensed_dim(&self) -> usize {
        self.rates.body.dim()
    }

    /// Entries of the volume's sparse Cholesky factor the condensation holds (what limits a
    /// 3-D run's memory with the operator's, docs/three-d.md).
    pub fn factor_nnz(&self) -> usize {
        self.rates.body.factor_nnz()
    }

    /// What the set-up measured of the operator `S` (or `S_H`): the kernel, its error
    /// `‖S − S_H‖_F/‖S‖_F`, storage and compression ratio. `Display` prints one line.
    pub fn kernel_report(&self) -> &KernelReport {
        self.rates.operator.report()
    }

    /// With a normal stress from slip ([`NormalStress::FromSlip`])
    /// and a hierarchical [`FaultOdeOptions::kernel`]: what the compression of the
    /// slip → normal-traction operator `S_N` (`nodes × m`, N/m) measured (the same
    /// accuracy and leaf size as `S`, one point per node). On a 2-D fault inside the body
    /// `S_N` is square and compressed whole; on a 3-D fault the columns of each slip
    /// component form a square ℋ-matrix on the nodes, and the report sums them:
    /// `dim` is `m`, `relative_error` is `‖S_N − S_N,H‖_F/‖S_N‖_F` (the components'
    /// errors weighed by their norms; sampled estimates where `error_samples > 0`),
    /// `stored_entries` against the dense `S_N`'s `nodes × m = m²/2` (its
    /// [`compression_ratio`](KernelReport::compression_ratio) counts `m²`, twice that),
    /// `setup_bytes` the dense `S_N` held until compressed. `None` where `S_N` is dense: no
    /// normal stress from slip, a dense kernel, or a 2-D fault whose rows and columns are
    /// on different points (a frictional node without a free component).
    pub fn normal_kernel_report(&self) -> Option<&KernelReport> {
        self.normal_kernel_report.as_ref()
    }

    /// Evaluations of the right-hand side so far (each one product with `S`).
    pub fn evaluations(&self) -> usize {
        self.evaluations
    }

    /// The method's own state: the controller, the rate at the current point and the
    /// evaluations so far (what a checkpoint saves besides the common state).
    pub fn fault_ode_state(&self) -> FaultOdeState {
        FaultOdeState {
            controller: self.rk.state(),
            rate: self.dy.clone(),
            evaluations: self.evaluations as u64,
        }
    }

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
        let o = self.options.runge_kutta;
        let dt = memory.controller.dt;
        if !(dt >= o.dt_min && dt <= o.dt_max) {
            return Err(invalid(
                "controller",
                format!("next step {dt} s must be in [{}, {}] s", o.dt_min, o.dt_max),
            ));
        }
        let m = self.rates.body.dim();
        let mut y = self.y.clone();
        for (yi, &dof) in y.iter_mut().zip(self.rates.body.interface_dofs()) {
            *yi = state.kinematics.u[dof];
        }
        y[m..].copy_from_slice(&state.alpha);
        if let Some(i) = y.iter().position(|x| !x.is_finite()) {
            return value("u on Γ_F or alpha", i, y[i], "finite");
        }
        if let Some(i) = memory.rate.iter().position(|x| !x.is_finite()) {
            return value("fault ODE rate", i, memory.rate[i], "finite");
        }
        self.y = y;
        self.dy.copy_from_slice(&memory.rate);
        self.rk.restore(memory.controller, &memory.rate)?;
        self.evaluations = usize::try_from(memory.evaluations).unwrap_or(usize::MAX);
        self.state.time = state.time;
        self.state.step = state.step;
        self.state.tau = dt;
        self.state.time_origin = state.time_origin;
        self.state.controller = None;
        self.state.kinematics.u.copy_from_slice(&state.kinematics.u);
        self.state.kinematics.v.copy_from_slice(&state.kinematics.v);
        self.state.kinematics.a.fill(0.0);
        self.interior_is_nan = false;
        self.fill_state(false)
    }

    /// The step controller's state (next step, PI memory).
    pub fn controller(&self) -> RungeKuttaState {
        self.rk.state()
    }

    /// The state with the whole field: computes `u` and `v` off Γ_F now (one forward and
    /// one backward sweep each), whatever the last step's observers read. E.g. to hand the
    /// state to a [`Simulation`](crate::Simulation) with inertia at the start of an event
    /// ([`Simulation::restore`](crate::Simulation::restore) of a
    /// [`Checkpoint::new`](crate::Checkpoint::new)).
    ///
    /// # Errors
    /// [`Error::Direct`] if the extension is not finite.
    pub fn state_with_volume(&mut self) -> Result<&SimulationState> {
        self.fill_state(true)?;
        Ok(&self.state)
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
        let o = self.options.runge_kutta;
        if !(dt >= o.dt_min && dt <= o.dt_max) {
            return Err(invalid(
                "dt",
                format!("{dt} s must be in [{}, {}] s", o.dt_min, o.dt_max),
            ));
        }
        let m = self.rates.body.dim();
        let mut y = self.y.clone();
        for (yi, &dof) in y.iter_mut().zip(self.rates.body.interface_dofs()) {
            *yi = state.kinematics.u[dof];
        }
        y[m..].copy_from_slice(&state.alpha);
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
        self.rk.set_state(RungeKuttaState {
            dt,
            previous_error: 1e-4,
        });
        self.state.time = state.time;
        self.state.step = state.step;
        self.state.tau = dt;
        self.state.kinematics.u.copy_from_slice(&state.kinematics.u);
        self.interior_is_nan = false;
        self.fill_state(false)
    }

    /// Writes the state after a step from `y` and its rate `self.dy`.
    fn fill_state(&mut self, volume: bool) -> Result<()> {
        let dy = &self.dy;
        let model = self.problem.model();
        let r = &mut self.rates;
        let m = r.body.dim();
        let t = self.state.time;
        let big_g = r.history.integral(t).unwrap_or(0.0);
        let kin = &mut self.state.kinematics;
        for (i, &dof) in r.body.interface_dofs().iter().enumerate() {
            kin.u[dof] = self.y[i];
            kin.v[dof] = dy[i];
        }
        for (&dof, &f) in model.dirichlet.dofs.iter().zip(&model.dirichlet.factors) {
            kin.u[dof] = model.initial_displacement[dof] + f * big_g;
        }
        for &i in &self.fixed {
            kin.v[i] = 0.0;
        }
        model.dirichlet.impose(t, &mut kin.v);
        if volume {
            if let Body::Condensed { .. } = r.body {
                return Err(invalid(
                    "reads_volume",
                    "the fault ODE was set up without the volume's factor \
                     (build_fault_ode_schur_only): it has the fault and the vertices given to \
                     its set-up, not the whole volume; build it with build_fault_ode to \
                     observe the volume",
                ));
            }
            self.interior_is_nan = false;
            if let Some(cond) = r.body.volume_mut() {
                cond.condense(&model.load, &kin.u, &mut r.r)
                    .and_then(|()| cond.extend(&mut kin.u))?;
                cond.condense(&self.zeros, &kin.v, &mut r.r)
                    .and_then(|()| cond.extend(&mut kin.v))?;
            }
        } else {
            if !self.interior_is_nan {
                for &i in &self.interior {
                    kin.u[i] = f64::NAN;
                    kin.v[i] = f64::NAN;
                }
                self.interior_is_nan = true;
            }
            if let Some(probe) = &self.probe {
                let speed = model.dirichlet.speed(t);
                probe.fill(&self.y[..m], &dy[..m], big_g, speed, &mut kin.u, &mut kin.v);
            }
        }
        self.state.alpha.copy_from_slice(&self.y[m..]);
        if let (Some(normal), Some(tr)) = (&mut r.normal, &mut self.scaled_tractions) {
            // Whole on every rank, not an exchange: a rank may fill its state alone (its
            // observers' vertices, `watch_vertices`, are rank 0's alone in the programs).
            normal.evaluate(t, big_g, &self.y[..m], &mut tr.sigma, r.par)?;
        }
        if let (Some(pr), Some(tr)) = (&mut r.pressure, &mut self.effective_tractions) {
            let base = self.scaled_tractions.as_ref().map(|s| &s.sigma[..]);
            pr.lower(t, base)?;
            tr.sigma.copy_from_slice(&pr.effective);
        }
        Ok(())
    }

    /// Runs until `until`, showing every accepted step to the observers: the one run loop
    /// of every method, [`run_until`]. A step's report counts its
    /// right-hand-side evaluations in `evaluations` (rejected attempts included); it has
    /// no fixed point and no velocity solver (their counts are 0).
    ///
    /// # Errors
    /// A [`RunError`] with the first step or observer error (e.g. a step below
    /// `runge_kutta.dt_min`: [`rsf_time::Error::StepTooSmall`]) and the summary of the
    /// steps before it; [`Error::InvalidParameter`] named `until` for a non-finite end.
    pub fn run_until(
        &mut self,
        until: Until,
        observers: &mut [&mut dyn Observer<D, C>],
    ) -> std::result::Result<RunSummary, RunError> {
        run_until(self, until, observers)
    }

    /// A checkpoint of the whole state (common and the fault ODE's own), for
    /// [`restore`](Self::restore).
    pub fn checkpoint(&self) -> Checkpoint {
        Stepping::checkpoint(self)
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

    /// One accepted step (at most up to `t_end`); `volume`: whether to compute the field
    /// off Γ_F after it.
    fn advance_step(&mut self, t_end: Option<f64>, volume: bool) -> Result<StepReport> {
        let clock = Instant::now();
        let mut t = self.state.time;
        let taken = {
            let mut sys = Rates {
                friction: self.problem.friction_laws(),
                state_laws: self.problem.state_laws(),
                uses_state: self.problem.uses_state(),
                data: &mut self.rates,
            };
            // A step ends at the pore pressure's next breakpoint (a shut-in) rather than
            // step over it.
            let t_end = match (
                t_end,
                sys.data
                    .pressure
                    .as_ref()
                    .and_then(|p| p.at_nodes.next_breakpoint(t)),
            ) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
            self.rk.step(&mut sys, &mut t, &mut self.y, t_end)?
        };
        self.dy
            .copy_from_slice(self.rk.current_rate().expect("set by an accepted step"));
        self.evaluations += taken.evaluations;
        self.state.time = t;
        self.state.step += 1;
        self.state.tau = self.rk.state().dt;
        self.fill_state(volume)?;
        let fb = &self.problem.model().frictional_boundary;
        let max_slip_rate = fb
            .nodes
            .iter()
            .map(|&p| crate::model::fault::block_norm::<C>(&self.state.kinematics.v, p))
            .fold(0.0, f64::max);
        Ok(StepReport {
            step: self.state.step,
            time: t,
            tau: taken.dt,
            evaluations: taken.evaluations,
            max_slip_rate,
            rejected_attempts: taken.rejected,
            rejected_normal_stress: taken.refused,
            error_estimate: taken.error,
            rejected_error: taken.rejected_error,
            seconds: clock.elapsed().as_secs_f64(),
            ..StepReport::default()
        })
    }
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, const C: usize> Stepping<D, C>
    for FaultOde<D, L, S, C>
{
    fn advance(&mut self, t_end: Option<f64>, reads_volume: bool) -> Result<StepReport> {
        self.advance_step(t_end, reads_volume)
    }
    /// The Runge–Kutta control's `dt_min`.
    fn step_floor(&self) -> Option<f64> {
        Some(self.options.runge_kutta.dt_min)
    }
    /// Precomputes the extension operator's rows at the vertices' dofs (one forward sweep
    /// per dof, kept while the same vertices are asked for) and fills them in the current
    /// state. Set up without the factor ([`SchurOnlySetup`]), the set-up's vertices (or
    /// some of them) are accepted and any other is refused.
    fn watch_vertices(&mut self, vertices: &[usize]) -> Result<()> {
        if let Body::Condensed { .. } = self.rates.body {
            // Set up without the factor: the probe of the set-up's vertices stays (it
            // cannot be made again); any of its vertices may be read.
            let watched = self.probe.as_ref().map_or(&[][..], |p| p.vertices());
            if vertices.iter().all(|v| watched.binary_search(v).is_ok()) {
                return Ok(());
            }
        }
        if vertices.is_empty() {
            self.probe = None;
            return Ok(());
        }
        if self.probe.as_ref().is_some_and(|p| p.watches(vertices)) {
            return Ok(());
        }
        let model = self.problem.model();
        let mut velocity_factor = vec![0.0; model.num_dofs()];
        for (&dof, &f) in model.dirichlet.dofs.iter().zip(&model.dirichlet.factors) {
            velocity_factor[dof] = f;
        }
        if let Body::Condensed { .. } = self.rates.body {
            return Err(invalid(
                "volume_vertices",
                format!(
                    "the fault ODE was set up without the volume's factor: it reads the \
                     vertices given to its set-up (SchurOnlySetup::watch_vertices{}), not \
                     {vertices:?}",
                    match &self.probe {
                        Some(p) => format!(": {:?}", p.vertices()),
                        None => ", none".to_string(),
                    }
                ),
            ));
        }
        let Some(cond) = self.rates.body.volume_mut() else {
            return Err(invalid(
                "volume_vertices",
                "a fault alone (FaultAlone) has no volume: an observer cannot read vertices \
                 off the fault",
            ));
        };
        self.probe = Some(VolumeProbe::new(model, cond, vertices, &velocity_factor)?);
        // Another probe's vertices are NaN again.
        self.interior_is_nan = false;
        self.fill_state(false)
    }
    fn model(&self) -> &Model<D, C> {
        self.problem.model()
    }
    fn state(&self) -> &SimulationState {
        &self.state
    }
    fn fault_tractions(&self) -> &dyn FaultTractions {
        if let Some(t) = &self.effective_tractions {
            return t;
        }
        match &self.scaled_tractions {
            Some(t) => t,
            None => self.problem.fault_tractions(),
        }
    }
    fn method_state(&self) -> MethodState {
        MethodState::FaultOde(self.fault_ode_state())
    }
    fn restore(&mut self, checkpoint: &Checkpoint) -> Result<()> {
        FaultOde::restore(self, checkpoint)
    }
}

impl<const D: usize, L, S, const C: usize> std::fmt::Debug for FaultOde<D, L, S, C> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FaultOde")
            .field("condensed_dim", &self.rates.body.dim())
            .field("time", &self.state.time)
            .field("step", &self.state.step)
            .field("options", &self.options)
            .finish_non_exhaustive()
    }
}
