//! How a simulation solves its problem (docs/design.md, "Problem, method, state"): the
//! velocity integrator, the velocity solver, the fixed point iteration, the step control
//! and the state update, described by [`MethodOptions`] and built into a [`Method`].

pub(crate) mod fixed_point;
pub(crate) mod kind;
pub(crate) mod solver;
pub(crate) mod state_integrator;

pub use crate::friction_blocks::FrictionBlocks;
pub use fixed_point::{Acceleration, FixedPointOptions, FixedPointScheme, InnerSolves, Predictor};
pub use kind::MethodKind;
use rsf_linalg::Parallelism;
pub use rsf_state::{BuiltinStateLaw, StateLawKind};
pub use rsf_time::Integrator;
#[allow(deprecated)]
pub use solver::AUTO_DIRECT_MAX_EXTENSION;
pub use solver::{
    SolverKind, SolverOptions, TnnmgOnRanks, AUTO_DIRECT_MAX_CONDENSED, DEFAULT_MEMORY_BUDGET_BYTES,
};
pub use state_integrator::StateIntegrator;

use rsf_fem::{combine, SparseMatrix};
use rsf_nonsmooth::{ProblemError, StepSolver, Stopping};
use rsf_ranks::NodeAllGather;
use rsf_time::{LoadOperator, StepControl, VelocityIntegrator};

use crate::error::{invalid, Result};
use crate::model::Model;
use solver::VelocitySolver;

/// The description of a method: every choice, no built solver. What
/// [`SimulationBuilder`](crate::SimulationBuilder) collects and a [`Method`] is built from.
#[derive(Debug, Clone, PartialEq)]
pub struct MethodOptions<I> {
    /// The velocity integrator (`A = c_M M + c_K K`, right-hand side, kinematic update).
    pub integrator: I,
    /// Which velocity solver.
    pub solver: SolverKind,
    /// The options of the velocity solvers.
    pub solver_options: SolverOptions,
    /// The fixed point iteration of each step.
    pub fixed_point: FixedPointOptions,
    /// Adaptive time steps (`None`: a fixed τ).
    pub step_control: Option<StepControl>,
    /// How a step advances the state.
    pub state_integrator: StateIntegrator,
}

/// Solvers of other time steps kept by [`Method::set_time_step`].
const SOLVER_CACHE: usize = 8;

/// A built method: the [`MethodOptions`] and what they need at run time — the velocity
/// solver for the current τ (set-ups of earlier τ kept in a small cache, so that returning
/// to a step size costs nothing) and the operator of the integrator's right-hand side.
///
/// `D` is the spatial dimension, `C` the components per node (see [`Model`]).
pub struct Method<const D: usize, I, const C: usize = D> {
    options: MethodOptions<I>,
    /// The concrete solver ([`SolverKind::resolve`]).
    resolved: SolverKind,
    /// The stopping test of the inner solves.
    inner_stopping: Stopping,
    solver: VelocitySolver<C>,
    /// Solvers of earlier time steps, most recently used last.
    solver_cache: Vec<(f64, VelocitySolver<C>)>,
    load_operator: LoadOperator,
    /// On ranks (TNNMG on ranks, [`SolverOptions::ranks`]): the all-gather that completes
    /// the right-hand side, of which this rank's operator computes its owned nodes' rows.
    load_gather: Option<NodeAllGather<C>>,
    /// On ranks: the state update's share (each rank its own frictional nodes).
    state_share: Option<StateShare>,
    /// With one set-up for every τ (no inertia, see
    /// [`SolverOptions::setup_per_time_step`](crate::method::SolverOptions)): the radiation
    /// damping `q_k = η w_k` of each frictional node, moved from the matrix into the
    /// nonlinearity.
    tau_free: Option<Vec<f64>>,
    /// The radiation damping η of every frictional node (Pa·s/m; physics, not method).
    eta: Vec<f64>,
}

impl<const D: usize, I: VelocityIntegrator, const C: usize> Method<D, I, C> {
    /// Builds the method for `model` with radiation damping `eta` (Pa·s/m, the problem's,
    /// one per frictional node)
    /// at the time step `tau` (s).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `tau` if the
    /// time-step matrix is not finite; set-up errors of the solver.
    pub(crate) fn new(
        options: MethodOptions<I>,
        model: &Model<D, C>,
        tau: f64,
        eta: &[f64],
    ) -> Result<Self> {
        let mass = model
            .mass
            .as_ref()
            .filter(|_| options.integrator.uses_mass());
        // On ranks each rank keeps its owned nodes' rows of the right-hand side's operator
        // (its share of the memory) and gathers the others' rows.
        let (load_operator, load_gather) = match &options.solver_options.ranks {
            // On ranks the solver is TNNMG's (or `resolve_within` below refuses).
            Some(ranks) => {
                if ranks.owner.len() != model.num_nodes() {
                    return Err(rsf_tnnmg::Error::from(ProblemError::DimensionMismatch {
                        what: "owner (one rank per node)",
                        expected: model.num_nodes(),
                        got: ranks.owner.len(),
                    })
                    .into());
                }
                let gather = NodeAllGather::<C>::new(&ranks.owner, (ranks.transport)())
                    .map_err(rsf_tnnmg::Error::from)?;
                let rank = gather.rank();
                let keep: Vec<bool> = (0..C * ranks.owner.len())
                    .map(|i| ranks.owner[i / C] == rank)
                    .collect();
                (
                    LoadOperator::for_rows(mass, &model.stiffness, &keep)?,
                    Some(gather),
                )
            }
            _ => (LoadOperator::new(mass, &model.stiffness)?, None),
        };
        // On ranks each rank updates the state of its own frictional nodes.
        let state_share = match &options.solver_options.ranks {
            Some(ranks) => Some(StateShare::new(model, ranks)?),
            None => None,
        };
        let load_operator = load_operator.with_parallelism(options.solver_options.parallelism);
        let inner_stopping = options.solver_options.stopping(options.solver);
        let tau_free = (!options.integrator.uses_mass()
            && !options.solver_options.setup_per_time_step)
            .then(|| {
                let w = &model.frictional_boundary.weights;
                w.iter()
                    .zip(eta)
                    .map(|(w, eta)| eta * w)
                    .collect::<Vec<f64>>()
            });
        let a = match tau_free {
            // A/c_K without the damping: K, whatever τ.
            Some(_) => {
                check_time_step_matrix(model, &options.integrator, tau)?;
                model.stiffness.clone()
            }
            None => time_step_matrix(model, &options.integrator, tau, eta)?,
        };
        let resolved = options
            .solver
            .resolve_within(model, &a, &options.solver_options)?;
        let solver = VelocitySolver::new(resolved, &options.solver_options, a, model)?;
        Ok(Self {
            options,
            resolved,
            inner_stopping,
            solver,
            solver_cache: Vec::new(),
            load_operator,
            load_gather,
            state_share,
            tau_free,
            eta: eta.to_vec(),
        })
    }

    /// The options the method was built from.
    pub fn options(&self) -> &MethodOptions<I> {
        &self.options
    }

    /// The velocity integrator.
    pub fn integrator(&self) -> &I {
        &self.options.integrator
    }

    /// The velocity solver in use (never [`SolverKind::Auto`]).
    pub fn solver_kind(&self) -> SolverKind {
        self.resolved
    }

    /// The parallelism the built parts run with, as given by
    /// [`SolverOptions::parallelism`](crate::method::SolverOptions::parallelism): the one of the
    /// integrator's right-hand side operator and, for the direct solver, of the solver.
    pub fn parallelism(&self) -> Parallelism {
        let par = self.load_operator.parallelism();
        debug_assert!(self.solver.parallelism().is_none_or(|p| p == par));
        par
    }

    /// The parallelism of the velocity solver in use (`None` for the sequential ones).
    pub fn solver_parallelism(&self) -> Option<Parallelism> {
        self.solver.parallelism()
    }

    /// Name of the velocity solver in use.
    pub fn solver_name(&self) -> &'static str {
        StepSolver::name(&self.solver)
    }

    /// The fixed point options.
    pub fn fixed_point(&self) -> &FixedPointOptions {
        &self.options.fixed_point
    }

    /// The options of adaptive time steps, if any.
    pub fn step_control(&self) -> Option<&StepControl> {
        self.options.step_control.as_ref()
    }

    /// How a step advances the state.
    pub fn state_integrator(&self) -> StateIntegrator {
        self.options.state_integrator
    }

    pub(crate) fn set_step_control(&mut self, control: Option<StepControl>) {
        self.options.step_control = control;
    }

    pub(crate) fn set_state_integrator(&mut self, integrator: StateIntegrator) {
        self.options.state_integrator = integrator;
    }

    pub(crate) fn inner_stopping(&self) -> Stopping {
        self.inner_stopping
    }

    /// The solver and, when one set-up serves every τ, the scaling of the step's problem
    /// at `tau`: `(1/c_K(τ), q)` — divide the right-hand side by `c_K` and solve with the
    /// nonlinearity [`Scaled`](rsf_nonsmooth::Scaled) by `1/c_K` with the damping `q`.
    pub(crate) fn solver_and_scaling(
        &mut self,
        tau: f64,
    ) -> (&mut VelocitySolver<C>, Option<(f64, &[f64])>) {
        let parts = self.step_parts(tau);
        (parts.solver, parts.scaling)
    }

    /// [`solver_and_scaling`](Self::solver_and_scaling) and, on ranks, the state update's
    /// share.
    pub(crate) fn step_parts(&mut self, tau: f64) -> StepParts<'_, C> {
        let scaling = self.tau_free.as_deref().map(|q| {
            let (_, c_k) = self.options.integrator.coefficients(tau);
            (1.0 / c_k, q)
        });
        StepParts {
            solver: &mut self.solver,
            scaling,
            state_share: self.state_share.as_mut(),
        }
    }

    /// `out = load + M w_mass − K w_stiffness` (length `n`): on ranks each rank computes
    /// its owned rows and one all-gather completes `out` (the same bits as one process's
    /// operator on every row).
    pub(crate) fn apply_load(
        &mut self,
        load: &[f64],
        w_mass: &[f64],
        w_stiffness: &[f64],
        out: &mut [f64],
    ) {
        self.load_operator.apply(load, w_mass, w_stiffness, out);
        if let Some(gather) = &mut self.load_gather {
            gather.gather(out);
        }
    }

    /// Replaces the solver for `old_tau` by one for `tau` (s): from the cache if `tau` was
    /// used before, else set up for the new matrix (the direct solver reuses its symbolic
    /// analysis). The replaced solver goes to the cache.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub(crate) fn set_time_step(
        &mut self,
        model: &Model<D, C>,
        old_tau: f64,
        tau: f64,
    ) -> Result<()> {
        if self.tau_free.is_some() {
            return check_time_step_matrix(model, &self.options.integrator, tau);
        }
        let solver = match self
            .solver_cache
            .iter()
            .position(|(t, _)| t.to_bits() == tau.to_bits())
        {
            Some(i) => self.solver_cache.remove(i).1,
            None => self.solver.for_matrix(
                self.resolved,
                &self.options.solver_options,
                time_step_matrix(model, &self.options.integrator, tau, &self.eta)?,
                model,
            )?,
        };
        let old = std::mem::replace(&mut self.solver, solver);
        self.solver_cache.push((old_tau, old));
        if self.solver_cache.len() > SOLVER_CACHE {
            self.solver_cache.remove(0);
        }
        Ok(())
    }
}

/// The matrix `A = c_M M + c_K K` (+ the absorbing parts' dashpots `C` with inertia,
/// + radiation damping `eta`, Pa·s/m per frictional node) of the velocity problem at `tau`.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `tau` for a
/// non-finite entry.
pub(crate) fn time_step_matrix<const D: usize, const C: usize, I: VelocityIntegrator>(
    model: &Model<D, C>,
    integrator: &I,
    tau: f64,
    eta: &[f64],
) -> Result<SparseMatrix> {
    let (c_m, c_k) = integrator.coefficients(tau);
    let mut a = match (&model.mass, integrator.uses_mass()) {
        (Some(m), true) => combine(c_m, m, c_k, &model.stiffness),
        _ => combine(0.0, &model.stiffness, c_k, &model.stiffness),
    }
    .map_err(rsf_fem::Error::from)?;
    if let Some(absorbing) = model.absorbing.as_ref().filter(|_| integrator.uses_mass()) {
        // Lysmer–Kuhlemeyer dashpots: c_M M + C + c_K K (docs/math.md "Absorbing
        // boundaries"); the multigrid levels get C through their Galerkin products.
        a = combine(1.0, &a, 1.0, &absorbing.damping).map_err(rsf_fem::Error::from)?;
    }
    if eta.iter().any(|&eta| eta > 0.0) {
        add_radiation_damping(&mut a, model, eta);
    }
    if let Some(x) = a.val().iter().find(|x| !x.is_finite()) {
        return Err(invalid(
            "tau",
            format!(
                "τ = {tau:e} s gives a non-finite entry ({x}) of the time-step matrix \
                 c_M M + c_K K (c_M = {c_m:e}, c_K = {c_k:e})"
            ),
        ));
    }
    Ok(a)
}

/// Checks that the time-step matrix at `tau` would be finite (what
/// [`time_step_matrix`] checks), without forming it: `c_K` finite and positive.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `tau`.
pub(crate) fn check_time_step_matrix<const D: usize, const C: usize, I: VelocityIntegrator>(
    _model: &Model<D, C>,
    integrator: &I,
    tau: f64,
) -> Result<()> {
    let (c_m, c_k) = integrator.coefficients(tau);
    if !(c_k.is_finite() && c_k > 0.0 && c_m.is_finite()) {
        return Err(invalid(
            "tau",
            format!("τ = {tau:e} s gives the time-step coefficients c_M = {c_m:e}, c_K = {c_k:e}"),
        ));
    }
    Ok(())
}

/// Adds `η_p w_p` to the diagonal of every component of each frictional node `p`: the
/// Hessian of the radiation damping term `Σ_p w_p η_p/2 |v_p|²`.
fn add_radiation_damping<const D: usize, const C: usize>(
    a: &mut SparseMatrix,
    model: &Model<D, C>,
    eta: &[f64],
) {
    let (sym, vals) = a.parts_mut();
    for ((&p, &w), &eta) in model
        .frictional_boundary
        .nodes
        .iter()
        .zip(&model.frictional_boundary.weights)
        .zip(eta)
    {
        for c in 0..C {
            let j = C * p + c;
            let range = sym.col_ptr()[j]..sym.col_ptr()[j + 1];
            if let Ok(k) = sym.row_idx()[range.clone()].binary_search(&j) {
                vals[range.start + k] += eta * w;
            }
        }
    }
}

/// What a step's fixed point iteration uses of the method ([`Method::step_parts`]).
pub(crate) struct StepParts<'a, const C: usize> {
    pub solver: &'a mut VelocitySolver<C>,
    /// As [`Method::solver_and_scaling`]'s.
    pub scaling: Option<(f64, &'a [f64])>,
    /// On ranks, the state update's share.
    pub state_share: Option<&'a mut StateShare>,
}

/// The state update on ranks: each rank updates the state of the frictional nodes it owns
/// (the owner of their mesh node) and one all-gather gives every rank every node's new
/// state (a node's update is its own arithmetic, so the bits are one process's at every
/// rank count).
pub(crate) struct StateShare {
    gather: NodeAllGather<1>,
    /// Positions `k` on Γ_F of this rank's frictional nodes, increasing.
    owned: Vec<usize>,
}

impl StateShare {
    fn new<const D: usize, const C: usize>(
        model: &Model<D, C>,
        ranks: &solver::TnnmgOnRanks,
    ) -> Result<Self> {
        let owner: Vec<usize> = model
            .frictional_boundary
            .nodes
            .iter()
            .map(|&p| ranks.owner.get(p).copied().unwrap_or(usize::MAX))
            .collect();
        Self::with_owner(&owner, (ranks.transport)())
    }

    /// The share of the rank of `halo` with frictional node `k` on rank `owner[k]`.
    fn with_owner(owner: &[usize], halo: Box<dyn rsf_ranks::RankGroup>) -> Result<Self> {
        let gather = NodeAllGather::<1>::new(owner, halo).map_err(rsf_tnnmg::Error::from)?;
        let rank = gather.rank();
        let owned = (0..owner.len()).filter(|&k| owner[k] == rank).collect();
        Ok(Self { gather, owned })
    }

    /// `out[k] = update(k)` for this rank's frictional nodes, then every other node's from
    /// its rank (one collective). A failed node's value is sent as NaN, so every rank
    /// learns of it: this rank returns its own node's error, the others an error naming the
    /// node and its rank. Collective.
    ///
    /// # Errors
    /// This rank's first failed update; [`Error::StateLaw`](crate::Error::StateLaw) for a
    /// node another rank could not update.
    pub(crate) fn apply(
        &mut self,
        out: &mut [f64],
        mut update: impl FnMut(usize) -> Result<f64>,
    ) -> Result<()> {
        let mut failed = None;
        for &k in &self.owned {
            out[k] = match update(k) {
                Ok(a) => a,
                Err(e) => {
                    failed.get_or_insert(e);
                    f64::NAN
                }
            };
        }
        self.gather.gather(out);
        if let Some(e) = failed {
            return Err(e);
        }
        match out.iter().position(|a| a.is_nan()) {
            Some(k) => Err(crate::Error::StateLaw {
                node: k,
                source: rsf_state::Error::InvalidInput {
                    name: "alpha",
                    value: f64::NAN,
                    requirement: "a state its rank could update (that rank reports why)",
                },
            }),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::StateShare;
    use rsf_ranks::ThreadRanks;

    /// The state update on 1–3 thread ranks: every rank gets every node's value (the
    /// owner's) with one collective; a node that fails on its rank (rank 1's node 4) ends
    /// the update on every rank: that rank with its own error, the others naming the node.
    #[test]
    fn each_rank_updates_its_own_nodes_and_a_failure_ends_every_rank() {
        let owner = [0, 1, 0, 2, 1, 2, 0];
        let want: Vec<f64> = (0..owner.len()).map(|k| 0.5 * k as f64 - 1.0).collect();
        for size in 1..=3 {
            let owner: Vec<usize> = owner.iter().map(|&r| r % size).collect();
            let results: Vec<_> = std::thread::scope(|s| {
                let handles: Vec<_> = ThreadRanks::group(size)
                    .into_iter()
                    .map(|halo| {
                        let (owner, want) = (&owner, &want);
                        s.spawn(move || {
                            let mut share = StateShare::with_owner(owner, Box::new(halo)).unwrap();
                            let mut out = vec![0.0; owner.len()];
                            share.apply(&mut out, |k| Ok(want[k])).unwrap();
                            let mut broken = vec![0.0; owner.len()];
                            let failed = share.apply(&mut broken, |k| match k {
                                4 => Err(crate::Error::from(rsf_state::Error::InvalidInput {
                                    name: "v",
                                    value: -1.0,
                                    requirement: "a slip rate ≥ 0",
                                })),
                                _ => Ok(want[k]),
                            });
                            (out, failed.err().map(|e| e.to_string()))
                        })
                    })
                    .collect();
                handles.into_iter().map(|h| h.join().unwrap()).collect()
            });
            for (rank, (out, failed)) in results.iter().enumerate() {
                assert_eq!(out, &want, "rank {rank} of {size}");
                let failed = failed.as_deref().expect("every rank fails");
                if owner[4] == rank {
                    assert!(failed.contains("v = -1"), "rank {rank} of {size}: {failed}");
                } else {
                    assert!(failed.contains("k = 4"), "rank {rank} of {size}: {failed}");
                }
            }
        }
    }
}
