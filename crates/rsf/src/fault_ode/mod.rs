//! Quasi-dynamic runs condensed onto the fault: the equations of a model without inertia
//! and with radiation damping, written as an ODE in the fault's slip and state and
//! integrated by an explicit embedded Runge–Kutta pair with adaptive steps (docs/math.md
//! §12) — the formulation of boundary-element earthquake-cycle codes, with the
//! finite-element model's exact condensation as the elastic operator. Beyond the paper,
//! whose implicit scheme ([`Simulation`](crate::Simulation)) stays the default.

pub use rsf_direct::InteriorOrdering;
use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::{OdeStepper, OdeSystem, RungeKuttaState};

use crate::checkpoint::Checkpoint;
pub use crate::fault_operator::{
    FaultKernel, KernelReport, MAX_KERNEL_EPSILON, MIN_KERNEL_EPSILON,
};
use crate::method_state::FaultOdeState;
use crate::model::Model;
use crate::normal_stress::ScaledTractions;
use crate::problem::Problem;
use crate::run::Stepping;
use crate::simulation_state::SimulationState;
use crate::volume_probe::VolumeProbe;

mod linger;
mod load_change;
mod options;
mod rates;
mod resume;
pub(crate) mod schur_only;
mod setup;
mod shared;
mod step;

pub use crate::fault_alone::{SchurOnlySetup, SetupProgress};
pub use linger::LINGER;
pub use load_change::LoadChange;
pub use options::{integrator_fingerprint, FaultOdeOptions};
use rates::{FaultRates, Rates};
pub use rsf_time::{AutoOptions, OdeIntegrator, RkcOptions, RosenbrockOptions, StepperStats};

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
/// an observer [reads the volume](crate::Observer::reads_volume) — else it is NaN, except at the
/// few vertices observers [ask for](crate::Observer::volume_vertices) (surface stations: one
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
///
/// [`Condensation`]: rsf_direct::Condensation
pub struct FaultOde<const D: usize, L, S, const C: usize = D> {
    problem: Problem<D, L, S, C>,
    rates: FaultRates<C>,
    rk: OdeStepper,
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
    /// ([`Observer::volume_vertices`](crate::Observer::volume_vertices)), computed after
    /// every step.
    probe: Option<VolumeProbe>,
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, const C: usize> FaultOde<D, L, S, C> {
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

    /// The elastic operator `S` of the run ([`FaultOperator`]: slip unknowns → forces),
    /// to apply it from outside — as [`GreensFunctions`] do. Its products do not change
    /// the run (the operator keeps no state between products but scratch space).
    ///
    /// [`FaultOperator`]: crate::fault_operator::FaultOperator
    /// [`GreensFunctions`]: crate::greens::GreensFunctions
    pub fn fault_operator_mut(&mut self) -> &mut dyn crate::fault_operator::FaultOperator {
        &mut *self.rates.operator
    }

    /// The Green's functions of the run's faults ([`GreensFunctions`]): the slip unknowns
    /// of its operator `S` — faults, positions, weights, slip directions — its origin
    /// (the finite-element condensation or a boundary-element operator) and accuracy.
    /// Apply `S` with [`GreensFunctions::apply`] on
    /// [`fault_operator_mut`](Self::fault_operator_mut).
    ///
    /// # Errors
    /// Those of [`GreensFunctions::new`] (a run sharing its rows among ranks).
    ///
    /// [`GreensFunctions`]: crate::greens::GreensFunctions
    /// [`GreensFunctions::apply`]: crate::greens::GreensFunctions::apply
    /// [`GreensFunctions::new`]: crate::greens::GreensFunctions::new
    pub fn greens_functions(&self) -> crate::Result<crate::greens::GreensFunctions> {
        crate::greens::GreensFunctions::new(self.model(), &*self.rates.operator)
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
    ///
    /// [`NormalStress::FromSlip`]: crate::normal_stress::NormalStress::FromSlip
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
            controller: self.rk.explicit_state(),
            rate: self.dy.clone(),
            evaluations: self.evaluations as u64,
            stabilized: self.rk.stabilized_memory(),
        }
    }

    /// The step controller's state of the method in use (next step, error memory).
    pub fn controller(&self) -> RungeKuttaState {
        self.rk.controller()
    }

    /// What the integrator did in this process: steps, simulated time and evaluations of
    /// the explicit pair and of RKC2, `auto`'s changes of method, the spectral radius
    /// estimates and the largest stage count (docs/math.md §12, "Stiff steps").
    pub fn integrator_stats(&self) -> StepperStats {
        self.rk.stats()
    }

    crate::run::run_until_method! {
        /// Runs until `until`, showing every accepted step to the observers: the one run loop
        /// of every method, [`run_until`](crate::run_until). A step's report counts its
        /// right-hand-side evaluations in `evaluations` (rejected attempts included); it has
        /// no fixed point and no velocity solver (their counts are 0).
        ///
        /// # Errors
        /// A [`RunError`] with the first step or observer error (e.g. a step below
        /// `runge_kutta.dt_min`: [`rsf_time::Error::StepTooSmall`]) and the summary of the
        /// steps before it; [`Error::InvalidParameter`] named `until` for a non-finite end.
        ///
        /// [`RunError`]: crate::RunError
        /// [`Error::InvalidParameter`]: crate::Error::InvalidParameter
    }

    /// A checkpoint of the whole state (common and the fault ODE's own), for
    /// [`restore`](Self::restore).
    pub fn checkpoint(&self) -> Checkpoint {
        Stepping::checkpoint(self)
    }

    /// The run with the constant forces `forces` added to the load of its slip unknowns
    /// (N, one per slip unknown in its own component, as [`LoadChange::forces`]): the
    /// balance of every node becomes `g(t) + f − S u_F = w (τ(V, α) + η V)`, e.g. a
    /// prestress given node by node, `f = w τ⁰(x_k)`, rather than as tractions the
    /// assembly integrates against the hat functions (which mixes a node's prestress with
    /// its neighbours' where `τ⁰` jumps). Adds to a [`LoadChange`]'s base too, whichever
    /// comes first. Physics, not state: a checkpoint holds none of it, and a resumed run
    /// must be given the same forces (the programs put what makes them in their
    /// fingerprint).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `forces` for
    /// another length or a non-finite force; the evaluation's errors.
    pub fn with_load_added(mut self, forces: &[f64]) -> crate::Result<Self> {
        if forces.len() != self.rates.g0.len() || !forces.iter().all(|f| f.is_finite()) {
            return Err(crate::error::invalid(
                "forces",
                format!(
                    "{} forces for {} slip unknowns, every one finite",
                    forces.len(),
                    self.rates.g0.len()
                ),
            ));
        }
        for (g, f) in self.rates.g0.iter_mut().zip(forces) {
            *g += f;
        }
        if let Some(change) = self.rates.load_change.as_mut() {
            change.add_to_base(forces);
        }
        self.reloaded()
    }

    /// The run with the load of its slip unknowns changed by `h(t) f` from now on
    /// ([`LoadChange`]; it replaces an earlier one): the rate at the current point is
    /// evaluated again with it, and the steps end at its breakpoints; after steps were
    /// taken the integrator starts afresh (as [`restart_from`](Self::restart_from)).
    /// Give a resumed run the same change before [`restore`](Self::restore).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
    /// `load_change.forces` (not one finite force per slip unknown),
    /// `load_change.history` (`h` not finite at the current time) or
    /// `load_change.breakpoints`; the evaluation's errors.
    pub fn with_load_change(mut self, change: LoadChange) -> crate::Result<Self> {
        let base = match self.rates.load_change.take() {
            Some(old) => old.base,
            None => self.rates.g0.clone(),
        };
        let t = self.state.time;
        self.rates.load_change = Some(load_change::LoadChangeRates::new(base, change, t)?);
        self.reloaded()
    }

    /// After a change of the load: the rate at the current point evaluated again, and
    /// after steps were taken the integrator started afresh (its rate at the current point
    /// is the old load's).
    fn reloaded(mut self) -> crate::Result<Self> {
        let (t, y) = (self.state.time, self.y.clone());
        let mut dy = vec![0.0; y.len()];
        self.system().rate(t, &y, &mut dy)?;
        self.dy = dy;
        if self.state.step > 0 {
            self.rk.restart(self.state.tau);
        }
        self.fill_state(false)?;
        Ok(self)
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
