//! The velocity solver: which one ([`SolverKind`]), its options ([`SolverOptions`]), and
//! the built solvers of a simulation, one per time step size used.

use std::sync::Arc;

use rsf_direct::{DirectMemory, DirectOptions, DirectSolver};
use rsf_fem::SparseMatrix;
use rsf_linalg::Parallelism;
use rsf_nonsmooth::{BlockNonlinearity, FullStep, SolveReport, StepSolver, Stopping};
use rsf_ranks::TransportFactory;
use rsf_tnnmg::distributed::{DistributedTnnmg, DistributedTnnmgOptions};
use rsf_tnnmg::{NonlinearGaussSeidel, Tnnmg, TnnmgOptions};

use crate::model::Model;

/// Which solver handles the velocity problems of the fixed point iterations.
///
/// Names (`name`, `FromStr`, serde, clap): `auto`, `tnnmg`, `direct`, `gauss-seidel`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SolverKind {
    /// [`Direct`](Self::Direct) while the condensed problem is small and the direct
    /// solver fits in the memory budget, else [`Tnnmg`](Self::Tnnmg): see
    /// [`SolverKind::resolve_within`] for the rule.
    #[default]
    Auto,
    /// TNNMG over the model's refinement hierarchy (the paper's choice, §6.2): every fixed
    /// point iteration solves the whole problem.
    Tnnmg,
    /// Exact condensation onto Γ_F (docs/math.md §8): the fixed point iterations work on the
    /// frictional unknowns only; the interior is eliminated once per step.
    Direct,
    /// Nonlinear block Gauss–Seidel alone (baseline; slow on fine meshes).
    GaussSeidel,
}

impl SolverKind {
    /// Every kind, in declaration order.
    pub const ALL: [SolverKind; 4] = [Self::Auto, Self::Tnnmg, Self::Direct, Self::GaussSeidel];

    /// The name (`auto`, `tnnmg`, `direct`, `gauss-seidel`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Tnnmg => "tnnmg",
            Self::Direct => "direct",
            Self::GaussSeidel => "gauss-seidel",
        }
    }

    /// The concrete choice for `model`: [`Auto`](Self::Auto) becomes
    /// [`Direct`](Self::Direct) when the number of free components on Γ_F is at most
    /// [`AUTO_DIRECT_MAX_CONDENSED`], else [`Tnnmg`](Self::Tnnmg) (or Direct if the model
    /// has no hierarchy). The count is the measured crossover of the cost per step
    /// (docs/scaling.md); the direct solver's memory beyond its factor is `O(|F|²)` since
    /// its harmonic extension is formed block by block when large
    /// ([`DirectOptions::max_extension_bytes`](rsf_direct::DirectOptions)), so `n · |F|` no
    /// longer enters the choice. The memory budget is applied on top by
    /// [`resolve_within`](Self::resolve_within), which simulations use.
    pub fn resolve<const D: usize, const C: usize>(self, model: &Model<D, C>) -> SolverKind {
        match self {
            SolverKind::Auto => {
                let condensed = model.condensed_unknowns();
                if condensed <= AUTO_DIRECT_MAX_CONDENSED || model.prolongations.is_empty() {
                    SolverKind::Direct
                } else {
                    SolverKind::Tnnmg
                }
            }
            other => other,
        }
    }

    /// The concrete choice for `model` with the time-step matrix `a` under the memory
    /// budget of `options`: as [`resolve`](Self::resolve), and where that picks the direct
    /// solver for [`Auto`](Self::Auto), its memory estimate
    /// ([`rsf_direct::DirectMemory::estimate`]: ordering and symbolic factorisation, no
    /// numeric work) must fit in [`SolverOptions::memory_budget_bytes`]; otherwise TNNMG.
    /// Explicit kinds are returned unchanged. On ranks ([`SolverOptions::ranks`]) the
    /// velocity problems are TNNMG's: [`Auto`](Self::Auto) is TNNMG whatever the size.
    ///
    /// # Errors
    /// [`Error::MemoryBudget`](crate::Error::MemoryBudget) if the direct solver does not fit and the model has no
    /// refinement hierarchy; errors of the estimate (invalid matrix). On ranks,
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `ranks` for
    /// another explicit kind (its solves are not shared) or a model without a refinement
    /// hierarchy (TNNMG on ranks runs V-cycles).
    pub fn resolve_within<const D: usize, const C: usize>(
        self,
        model: &Model<D, C>,
        a: &SparseMatrix,
        options: &SolverOptions,
    ) -> crate::Result<SolverKind> {
        if options.ranks.is_some() {
            return match self {
                SolverKind::Auto | SolverKind::Tnnmg if !model.prolongations.is_empty() => {
                    Ok(SolverKind::Tnnmg)
                }
                SolverKind::Auto | SolverKind::Tnnmg => Err(crate::error::invalid(
                    "ranks",
                    "TNNMG on ranks runs V-cycles: the model has no refinement hierarchy",
                )),
                other => Err(crate::error::invalid(
                    "ranks",
                    format!(
                        "on ranks the velocity problems are solved by TNNMG: the {other} \
                         solver's solves are not shared (use tnnmg or auto)"
                    ),
                )),
            };
        }
        let by_count = self.resolve(model);
        if self != SolverKind::Auto || by_count != SolverKind::Direct {
            return Ok(by_count);
        }
        let needed = DirectMemory::estimate::<C>(
            a.as_ref(),
            &model.fixed,
            &model.frictional_boundary.nodes,
            true,
            &options.direct,
        )?
        .total_bytes();
        if needed <= options.memory_budget_bytes {
            Ok(SolverKind::Direct)
        } else if model.prolongations.is_empty() {
            Err(crate::Error::MemoryBudget {
                needed_bytes: needed,
                budget_bytes: options.memory_budget_bytes,
            })
        } else {
            Ok(SolverKind::Tnnmg)
        }
    }
}

rsf_numeric::display_and_parse_by_name!(SolverKind, "solver", crate::Error, SolverKind::ALL);

/// Largest number of condensed unknowns (free components on Γ_F) for which
/// [`SolverKind::Auto`] picks the direct solver. Its set-up stores the discrete harmonic
/// extension of every frictional unknown (`n × |F|` values) and a dense `|F|²` Schur
/// complement; the measurements behind the value are in `docs/performance.md`.
pub const AUTO_DIRECT_MAX_CONDENSED: usize = 1500;

/// Largest `n · |F|` (values of the stored harmonic extension, 8 bytes each) for which
/// [`SolverKind::Auto`] picked the direct solver before the extension could be formed block
/// by block: 2.5e8 values = 2 GB. No longer part of the choice.
#[deprecated(
    note = "the direct solver forms its harmonic extension block by block above \
            DirectOptions::max_extension_bytes; SolverKind::Auto no longer limits n·|F|"
)]
pub const AUTO_DIRECT_MAX_EXTENSION: usize = 250_000_000;

/// Default of [`SolverOptions::memory_budget_bytes`]: 8 GiB, a third of the 24 GiB of the
/// machines this project is measured and tested on (docs/scaling.md). A stated number,
/// not a reading of the machine: the solver [`SolverKind::Auto`] picks, and with it the
/// bits of a run, depend on the scene and the options only.
pub const DEFAULT_MEMORY_BUDGET_BYTES: usize = 8 << 30;

/// The options of every velocity solver (whichever [`SolverKind`] picks).
#[derive(Debug, Clone, PartialEq)]
pub struct SolverOptions {
    /// Options of TNNMG, among them the smoother order `tnnmg.smoother`
    /// ([`rsf_tnnmg::SmootherOrder`]: default lexicographic, the trajectories before the
    /// option bit for bit; multi-colour and red–black chunks change them once, to
    /// round-off of the solver tolerance, and run on [`parallelism`](Self::parallelism);
    /// the 3-D slider scene of `rsf-scenes` sets red–black chunks).
    pub tnnmg: TnnmgOptions,
    /// Options of the direct solver.
    pub direct: DirectOptions,
    /// Stopping test of nonlinear Gauss–Seidel.
    pub gauss_seidel: Stopping,
    /// Set up the solver for every time step's matrix even where one set-up serves all
    /// step sizes. Without inertia (the quasistatic integrator) `A = τK + H` with `H` the
    /// radiation damping on Γ_F, so by default the solver is set up once for `K` and each
    /// step solves the same problem divided by τ (the damping and friction scaled by
    /// `1/τ` on Γ_F, [`rsf_nonsmooth::Scaled`]; docs/math.md §11); `true` restores one set-up
    /// per step size (the same solution up to round-off). Default `false`.
    pub setup_per_time_step: bool,
    /// Memory (bytes) that [`SolverKind::Auto`] may give the direct solver: its estimate
    /// ([`rsf_direct::DirectMemory`]: sparse factor, dense matrices on Γ_F, the set-up's
    /// harmonic extension) must fit, else TNNMG is chosen (docs/scaling.md). Not applied
    /// to an explicitly chosen solver. Default [`DEFAULT_MEMORY_BUDGET_BYTES`].
    pub memory_budget_bytes: usize,
    /// The threads of every parallel part of a step, set once here (docs/design.md,
    /// "Parallelism"): the direct solver's sweeps over two halves of the interior and its
    /// harmonic extension (from [`rsf_direct::INTERIOR_PARALLEL_MIN`] interior unknowns),
    /// its dense Newton factorisations (from [`rsf_direct::DENSE_PARALLEL_MIN`] unknowns)
    /// and the integrator's right-hand side rows (from
    /// [`rsf_time::LOAD_PARALLEL_MIN_ROWS`] rows), and TNNMG's smoothers and residuals when
    /// `tnnmg.smoother` is [`rsf_tnnmg::SmootherOrder::MultiColour`] (the nonlinear sweeps)
    /// or [`rsf_tnnmg::SmootherOrder::RedBlackChunks`] (also the linear multigrid's fine
    /// level). TNNMG's lexicographic smoother (the default here) and Gauss–Seidel are
    /// sequential.
    /// Results are bit-identical for every value (tested per crate and on whole runs,
    /// `tests/reference_hashes.rs`), so the default is the fast one:
    /// [`Parallelism::default`], every core of the machine (as
    /// [`FaultOdeOptions::parallelism`](crate::fault_ode::FaultOdeOptions::parallelism);
    /// before issue 59 a stated two).
    pub parallelism: Parallelism,
    /// TNNMG's solves shared by the ranks of a job ([`TnnmgOnRanks`]; docs/scaling.md,
    /// "Phase 5"): when set, the solver is TNNMG (`auto` resolves to it whatever the size;
    /// the direct solver and Gauss–Seidel are refused), and every velocity problem is solved by
    /// [`DistributedTnnmg`] (each rank its owned nodes' rows, the solution all-gathered;
    /// the step's change measured with the ranks' rows of the energy norm), and each rank
    /// keeps and evaluates its owned nodes' rows of the integrator's right-hand side (one
    /// all-gather per step), and updates the state of its own frictional nodes (one
    /// all-gather per update), while everything else of a step (the integrator's update,
    /// the fixed point iteration, the friction potentials) stays replicated on every rank.
    /// Default `None`
    /// (one process).
    pub ranks: Option<TnnmgOnRanks>,
}

/// TNNMG on the ranks of a job (issue 57, docs/scaling.md "Phase 5"): replicated time
/// stepping, distributed velocity solves. Every rank runs the same simulation (the same
/// model, steps and state updates on whole vectors); only TNNMG's solves are shared, by
/// [`DistributedTnnmg`], whose solution has the same bits at every rank count and is
/// all-gathered on every rank, so every rank holds the same bits everywhere and a
/// trajectory is bit-identical at any rank count.
///
/// The iteration is not the one-process [`Tnnmg`]'s: its nonlinear smoother sweeps in the
/// multi-colour order of the distributed smoother whatever
/// [`TnnmgOptions::smoother`] says, and its global sums are exact, so trajectories on
/// ranks differ from the one-process runs (the red–black default of the 3-D slider
/// included) by round-off of the solver tolerance. The one-process reference of a run on
/// ranks is the same solver on one rank (a `owner` of zeros and a one-rank transport).
///
/// Equality (for [`SolverOptions`]' `PartialEq`): the same owner vector and the same
/// transport factory (the same `Arc`).
#[derive(Clone)]
pub struct TnnmgOnRanks {
    /// Fine node `p`'s rank (length the model's node count, every entry below the
    /// transport's rank count); the coarse levels' node `p` has the same owner (nested
    /// hierarchies number the coarse nodes first). The same on every rank.
    pub owner: Arc<[usize]>,
    /// This rank's transports ([`rsf_ranks::TransportFactory`]): called once per built
    /// method (the all-gather of the integrator's right-hand side, before its first
    /// solver) and once per built solver (every rank builds its methods and solvers in the
    /// same order, one solver per time-step size used), it returns this rank's end of a
    /// fresh group of the job's ranks (e.g. a duplicated MPI communicator, or the next
    /// group of thread ranks: `rsf_ranks::Processes::transports`).
    pub transport: TransportFactory,
}

impl TnnmgOnRanks {
    /// The owner vector `owner` (fine node → rank) and this rank's transport factory.
    pub fn new(owner: impl Into<Arc<[usize]>>, transport: TransportFactory) -> Self {
        Self {
            owner: owner.into(),
            transport,
        }
    }

    /// The options of [`DistributedTnnmg`] that correspond to `tnnmg`: the same stopping
    /// test, sweeps, cycles, linear correction, inexact-Newton factor, smoothing and
    /// energy record; the smoother order is the distributed multi-colour one (see the
    /// type's documentation).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
    /// `tnnmg.cycle_index` unless it is 1 (the distributed linear correction runs
    /// V-cycles).
    pub fn options(tnnmg: &TnnmgOptions) -> crate::Result<DistributedTnnmgOptions> {
        DistributedTnnmgOptions::from_tnnmg(tnnmg).ok_or_else(|| {
            crate::error::invalid(
                "tnnmg.cycle_index",
                format!(
                    "TNNMG on ranks runs V-cycles (cycle index 1), not {}",
                    tnnmg.cycle_index
                ),
            )
        })
    }
}

impl std::fmt::Debug for TnnmgOnRanks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let ranks = self.owner.iter().max().map_or(0, |&r| r + 1);
        f.debug_struct("TnnmgOnRanks")
            .field("nodes", &self.owner.len())
            .field("ranks_owning_nodes", &ranks)
            .finish_non_exhaustive()
    }
}

impl PartialEq for TnnmgOnRanks {
    fn eq(&self, other: &Self) -> bool {
        self.owner == other.owner && Arc::ptr_eq(&self.transport, &other.transport)
    }
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            tnnmg: TnnmgOptions::default(),
            direct: DirectOptions::default(),
            gauss_seidel: Stopping::default(),
            setup_per_time_step: false,
            memory_budget_bytes: DEFAULT_MEMORY_BUDGET_BYTES,
            parallelism: Parallelism::default(),
            ranks: None,
        }
    }
}

impl SolverOptions {
    /// The stopping test of the inner solves of the fixed point iteration for the solver
    /// `kind` as given (not resolved): [`SolverKind::Auto`] uses TNNMG's test whichever
    /// solver it picks, so that its fixed point iterations do not depend on the choice.
    pub fn stopping(&self, kind: SolverKind) -> Stopping {
        match kind {
            SolverKind::Auto | SolverKind::Tnnmg => self.tnnmg.stopping,
            SolverKind::Direct => self.direct.stopping,
            SolverKind::GaussSeidel => self.gauss_seidel,
        }
    }
}

/// A built velocity solver of any concrete [`SolverKind`], dispatching statically inside
/// each call.
/// `C` is the block size (components per node).
pub(crate) enum VelocitySolver<const C: usize> {
    /// See [`SolverKind::Tnnmg`].
    Tnnmg(Box<FullStep<C, Tnnmg<C>>>),
    /// [`SolverKind::Tnnmg`] on ranks ([`SolverOptions::ranks`]).
    TnnmgOnRanks(Box<FullStep<C, DistributedTnnmg<C>>>),
    /// See [`SolverKind::Direct`].
    Direct(Box<DirectSolver<C>>),
    /// See [`SolverKind::GaussSeidel`].
    GaussSeidel(Box<FullStep<C, NonlinearGaussSeidel<C>>>),
}

impl<const C: usize> VelocitySolver<C> {
    /// The parallelism the solver runs with (`None` for the sequential solvers).
    pub(crate) fn parallelism(&self) -> Option<Parallelism> {
        match self {
            VelocitySolver::Direct(d) => Some(d.parallelism()),
            VelocitySolver::Tnnmg(t) => Some(t.inner().parallelism()),
            _ => None,
        }
    }

    /// Builds the solver `kind` (resolved) for the matrix `a` of the velocity problem of
    /// `model`. Stopping norms are the model's energy norm.
    ///
    /// # Errors
    /// Set-up errors of the solvers.
    pub fn new<const D: usize>(
        kind: SolverKind,
        options: &SolverOptions,
        a: SparseMatrix,
        model: &Model<D, C>,
    ) -> crate::Result<Self> {
        let e = model.energy_norm.as_ref();
        Ok(match kind.resolve(model) {
            SolverKind::Tnnmg if options.ranks.is_some() => {
                let ranks = options.ranks.as_ref().expect("matched");
                let opts = TnnmgOnRanks::options(&options.tnnmg)?;
                let ps: Vec<_> = model.prolongations.iter().map(|p| p.as_ref()).collect();
                VelocitySolver::TnnmgOnRanks(Box::new(
                    FullStep::new(
                        // Given `a`: freed once blocked, before the hierarchy's set-up.
                        DistributedTnnmg::new_owned(
                            a,
                            &model.fixed,
                            &ps,
                            Some(e),
                            opts,
                            &ranks.owner,
                            (ranks.transport)(),
                        )?,
                        // No whole copy of `e`: the changes are measured with the ranks'
                        // rows of it.
                        None,
                    )?
                    .with_norm_from_solver()
                    // Its corrections are measured in `e` too.
                    .with_correction_from_solver(),
                ))
            }
            SolverKind::Tnnmg => VelocitySolver::Tnnmg(Box::new(
                FullStep::new(
                    Tnnmg::new(
                        a.as_ref(),
                        &model.fixed,
                        &model.prolongations,
                        Some(e),
                        options.tnnmg.clone(),
                    )?
                    .with_parallelism(options.parallelism),
                    Some(e),
                )?
                .with_parallelism(options.parallelism)
                // TNNMG measures its corrections in `e` too.
                .with_correction_from_solver(),
            )),
            SolverKind::Direct => {
                let mut d = DirectSolver::new(a.as_ref(), &model.fixed, options.direct.clone())?
                    .with_energy_norm(e)?
                    .with_parallelism(options.parallelism);
                d.prepare(&model.frictional_boundary.nodes)?;
                VelocitySolver::Direct(Box::new(d))
            }
            SolverKind::GaussSeidel => VelocitySolver::GaussSeidel(Box::new(FullStep::new(
                NonlinearGaussSeidel::new(
                    a.as_ref(),
                    &model.fixed,
                    Some(e),
                    options.gauss_seidel,
                    false,
                )?,
                Some(e),
            )?)),
            SolverKind::Auto => unreachable!("resolved above"),
        })
    }

    /// The solver of the same kind for another matrix `a` of `model` with the same pattern
    /// (the velocity problem at another time step): the direct solver reuses its ordering
    /// and symbolic factorisation ([`DirectSolver::for_matrix`]); the others are set up
    /// as by [`new`](Self::new).
    ///
    /// # Errors
    /// Set-up errors of the solvers.
    pub fn for_matrix<const D: usize>(
        &self,
        kind: SolverKind,
        options: &SolverOptions,
        a: SparseMatrix,
        model: &Model<D, C>,
    ) -> crate::Result<Self> {
        match self {
            VelocitySolver::Direct(d) => {
                Ok(VelocitySolver::Direct(Box::new(d.for_matrix(a.as_ref())?)))
            }
            _ => Self::new(kind, options, a, model),
        }
    }
}

/// The solver a [`VelocitySolver`] holds.
macro_rules! dispatch {
    ($self:ident, $s:ident => $e:expr) => {
        dispatch_variants!($self, VelocitySolver { Tnnmg, TnnmgOnRanks, Direct, GaussSeidel }, $s => $e)
    };
}

/// One dispatch for the three solvers, whose errors are their crates' (`rsf_tnnmg::Error`,
/// `rsf_direct::Error`): as [`crate::Error`].
impl<const C: usize> StepSolver<C> for VelocitySolver<C> {
    type Error = crate::Error;

    fn name(&self) -> &'static str {
        dispatch!(self, s => StepSolver::name(s.as_ref()))
    }
    fn dim(&self) -> usize {
        dispatch!(self, s => StepSolver::dim(s.as_ref()))
    }
    fn begin_step(&mut self, b: &[f64], v: &[f64], active: &[usize]) -> crate::Result<()> {
        dispatch!(self, s => s.begin_step(b, v, active).map_err(crate::Error::from))
    }
    fn solve_step<N: BlockNonlinearity<C>>(
        &mut self,
        nl: &N,
        stopping: Stopping,
    ) -> crate::Result<SolveReport> {
        dispatch!(self, s => s.solve_step(nl, stopping).map_err(crate::Error::from))
    }
    fn block(&self, k: usize) -> [f64; C] {
        dispatch!(self, s => s.block(k))
    }
    fn last_change(&self) -> f64 {
        dispatch!(self, s => s.last_change())
    }
    fn finish_step(&mut self, v: &mut [f64]) -> crate::Result<()> {
        dispatch!(self, s => s.finish_step(v).map_err(crate::Error::from))
    }
    fn current_iterate(&mut self, v: &mut [f64]) -> crate::Result<()> {
        dispatch!(self, s => s.current_iterate(v).map_err(crate::Error::from))
    }
}
