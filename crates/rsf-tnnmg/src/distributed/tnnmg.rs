//! TNNMG on ranks with distributed memory ([`DistributedTnnmg`]): its set-up, options,
//! counters and the solver interface; one iteration is in `tnnmg_step`.

use faer::sparse::{SparseColMat, SparseColMatRef};
use rsf_linalg::Csc;
use rsf_nonsmooth::BlockNonlinearity;

use super::active::ActiveGather;
use super::hierarchy::RankLevels;
use super::rank_hierarchy::RankHierarchy;
use super::tnnmg_options::{DistributedTnnmgOptions, TnnmgCounters};
use super::DistributedVCycle;
use crate::error::{Error, Result};
use crate::linear_correction::LinearCorrection;
use crate::multigrid::NewtonHierarchy;
use crate::problem::active_map;
use crate::tnnmg::NewtonOptions;
use rsf_nonsmooth::ProblemError;
use rsf_ranks::block::{load, masked_inverse, store, Block};
use rsf_ranks::halo::{AllGather, HaloCounters};
use rsf_ranks::{
    Colouring, DistributedCg, DistributedSweep, ExactSums, LocalRows, NodeGraph, RankGroup,
};

/// The energy-norm matrix's rows, their local columns mapped to the iterate's local nodes.
#[derive(Debug, Clone)]
pub(super) struct NormRows<const D: usize> {
    pub rows: LocalRows<D>,
    /// Local node of `rows` → local node of the iterate.
    pub remap: Vec<u32>,
}

/// TNNMG on ranks with distributed memory (issue 57; docs/math.md §5, docs/scaling.md
/// "Phase 4") for `J(v) = ½ vᵀAv − bᵀv + Σ_k φ_k(v_{p_k})`: per iteration multi-colour
/// nonlinear block Gauss–Seidel on the rank's owned nodes (one halo exchange per colour;
/// the node update of the one-process smoothers), the truncated linearisation (the rules of
/// [`Tnnmg`](crate::Tnnmg)'s, truncating nonsmooth and rigid blocks), the linear
/// correction on the truncated Newton system by distributed V-cycles
/// ([`DistributedVCycle`]; a stationary iteration or the preconditioner of conjugate
/// gradients, [`DistributedTnnmgOptions::linear_correction`]), the kink rule and the exact
/// line search. Its iterates have the same bits at every rank count and partition:
/// every value is computed by its owner with arithmetic that does not depend on the
/// partition, and every global sum (the line search's `g0 = cᵀ(Av − b)` and `h = cᵀAc`, the
/// energy norms of the correction and of the iterate, the energy) is exact, rounded once
/// (a reproducible reduction). It is not the one-process [`Tnnmg`](crate::Tnnmg)'s
/// iteration (another smoother order, exact sums), so their iterates differ in the last
/// bits; both converge to the same minimiser.
///
/// The caller's vectors are global and replicated: every rank passes the same `b` and
/// start `v` (length `D n`), and after [`solve`](rsf_nonsmooth::NonsmoothSolver::solve) every rank's `v`
/// holds the whole solution (one all-gather of the owned values). The nonlinearity is the
/// same global object on every rank; a rank applies the per-block operations to the
/// active blocks of the nodes it owns, and the linearisation and the line search (which
/// need all active blocks) to the active blocks' values gathered from their owners (one
/// all-gather of the iterate's and one of the correction's active blocks per iteration).
///
/// The hierarchy of the truncated Newton matrix is the rank's (docs/scaling.md "Phase
/// 7"): each rank computes the Galerkin rows of the coarse nodes it owns, from its rows
/// of the finer level and the `T = H F P` rows its neighbour ranks send it, with the
/// one-process multigrid's arithmetic (so with its bits), and all-gathers the coarsest
/// level; per iteration every rank updates the rows the active blocks reach
/// (incrementally) and refreshes its V-cycle's rows from them. Held whole on every rank:
/// the levels' patterns (no values), the fine diagonal blocks, masks and prolongations,
/// and global vectors for the active blocks' values. At set-up the fine matrix is read
/// whole (its blocks, the pattern and colouring), then freed. A
/// collective object: every rank calls every method in the same order. Allocation-free
/// per iteration after the first solve with a set of active blocks (the transport may
/// allocate).
pub struct DistributedTnnmg<const D: usize> {
    pub(super) halo: Box<dyn RankGroup>,
    pub(super) opts: DistributedTnnmgOptions,
    /// Global dofs.
    pub(super) n: usize,
    /// Node `p`'s rank.
    pub(super) owner: Vec<usize>,
    /// The nonlinear smoother on `A`'s rows.
    pub(super) sweep: DistributedSweep<D>,
    /// Per owned node: `masked_inverse` of `A_pp` on the free components, and those.
    pub(super) inverse: Vec<Block<D>>,
    pub(super) free: Vec<[bool; D]>,
    /// `A`'s diagonal blocks and the fixed dofs, whole (the replicated linearisation).
    pub(super) a_diag: Vec<Block<D>>,
    pub(super) fixed: Vec<bool>,
    pub(super) norm_rows: Option<NormRows<D>>,
    /// The rank's share of the truncated Newton matrix's hierarchy, and the active
    /// blocks of its last full update.
    pub(super) hierarchy: RankHierarchy<D>,
    pub(super) cached_active: Option<Vec<usize>>,
    pub(super) vcycle: DistributedVCycle<D>,
    /// Global node → local node of the owned nodes (`u32::MAX` elsewhere).
    pub(super) local_of: Vec<u32>,
    /// Per global node, its position in the active blocks (`usize::MAX` if linear).
    pub(super) active_of: Vec<usize>,
    pub(super) gather: Option<ActiveGather<D>>,
    /// Local vectors: the right-hand side, the iterate and the last one (later the
    /// correction of the step), the correction; owned only: `b − Av`, the Newton
    /// right-hand side.
    pub(super) b: Vec<f64>,
    pub(super) v: Vec<f64>,
    pub(super) v_old: Vec<f64>,
    pub(super) c: Vec<f64>,
    pub(super) res_a: Vec<f64>,
    pub(super) res: Vec<f64>,
    /// Global vectors holding the active blocks' gathered iterate and correction.
    pub(super) v_active: Vec<f64>,
    pub(super) c_active: Vec<f64>,
    /// The line search's sums (`g0`, `h`) and the norms' (correction, iterate, energy).
    pub(super) line_sums: ExactSums,
    pub(super) norm_sums: ExactSums,
    /// The linear correction's residual norms (with `linear_reduction`), and the owned
    /// residual of the truncated system.
    pub(super) linear_sums: ExactSums,
    pub(super) linear_res: Vec<f64>,
    /// The owned 0/1 factor of the Newton system's unmasked dofs, and the conjugate
    /// gradients' work space.
    pub(super) free_owned: Vec<f64>,
    pub(super) cg: DistributedCg,
    /// The iterate's norm and energy computed with the last correction's norm.
    pub(super) pending: (Option<f64>, Option<f64>),
    pub(super) solution: AllGather,
    pub(super) counters: TnnmgCounters,
}

impl<const D: usize> std::fmt::Debug for DistributedTnnmg<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DistributedTnnmg")
            .field("rank", &self.sweep.rows().rank())
            .field("n", &self.n)
            .field("opts", &self.opts)
            .field("counters", &self.counters)
            .finish_non_exhaustive()
    }
}

impl<const D: usize> DistributedTnnmg<D> {
    /// The solver of rank `halo.rank()` of `halo.size()` for the symmetric positive
    /// definite (on the free dofs) matrix `a` (`D n × D n`, node-major, both triangles
    /// stored, symmetric pattern) with the dofs where `fixed` (length `D n`) is true
    /// held at the start's values; `prolongations[l]` maps level `l` to level `l + 1`
    /// (`D n_{l+1} × D n_l`, node-major, coarsest first; at least one: the linear correction
    /// is a V-cycle), fine node `i`'s coarse counterparts owned by the same rank (node `i`
    /// of every level is owned by `owner[i]`, as rsf-fem's nested hierarchies number
    /// them); `energy_norm` the matrix of the stopping norm (`D n × D n`, its couplings a
    /// subset of `a`'s), `None` for `a`; node `p` owned by rank `owner[p]` (length `n`).
    /// The solver keeps `halo` (its transport) for its solves.
    ///
    /// Of `a` and `energy_norm` a rank reads only **the columns of the nodes it owns**
    /// (each column as the row of the symmetric matrix): every rank may pass the whole
    /// matrices, or only its own columns with the others empty (what a rank that assembles
    /// its part holds; docs/scaling.md "Phase 7"). The rest of the fine level that the
    /// set-up needs whole — its node graph and diagonal blocks — is all-gathered from the
    /// ranks, and the graph checked symmetric.
    ///
    /// # Errors
    /// As [`Tnnmg::new`](crate::Tnnmg::new) for the matrices (on the rank's columns: a
    /// non-finite entry or a non-positive diagonal entry on a free dof, the dimensions),
    /// [`ProblemError::InvalidMatrix`] if the gathered node graph is not symmetric;
    /// [`ProblemError::InvalidOption`] for options out of range or no prolongation;
    /// [`ProblemError::DimensionMismatch`] if `owner` does not have one entry per node;
    /// [`Error::InvalidPartition`] if an owner is not a rank of `halo`, or on every other
    /// rank when one rank's columns are refused (the ranks agree before going on: no rank
    /// is left waiting); [`ProblemError::InvalidMatrix`] if `energy_norm` couples nodes that `a`
    /// does not.
    #[expect(
        clippy::too_many_arguments,
        reason = "Tnnmg::new's problem and options, plus the partition and the transport"
    )]
    pub fn new(
        a: SparseColMatRef<'_, usize, f64>,
        fixed: &[bool],
        prolongations: &[SparseColMatRef<'_, usize, f64>],
        energy_norm: Option<SparseColMatRef<'_, usize, f64>>,
        opts: DistributedTnnmgOptions,
        owner: &[usize],
        halo: Box<dyn RankGroup>,
    ) -> Result<Self> {
        let rows = |owner: &[usize], rank| owned_rows::<D>(a, owner, rank);
        Self::build(rows, fixed, prolongations, energy_norm, opts, owner, halo)
    }

    /// As [`new`](Self::new), taking the matrix `a`: it is freed as soon as the rank's
    /// rows are read from it, not held through the rest of the set-up.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    #[expect(clippy::too_many_arguments, reason = "as new")]
    pub fn new_owned(
        a: SparseColMat<usize, f64>,
        fixed: &[bool],
        prolongations: &[SparseColMatRef<'_, usize, f64>],
        energy_norm: Option<SparseColMatRef<'_, usize, f64>>,
        opts: DistributedTnnmgOptions,
        owner: &[usize],
        halo: Box<dyn RankGroup>,
    ) -> Result<Self> {
        let rows = move |owner: &[usize], rank| owned_rows::<D>(a.as_ref(), owner, rank);
        Self::build(rows, fixed, prolongations, energy_norm, opts, owner, halo)
    }

    #[expect(clippy::too_many_arguments, reason = "new's arguments")]
    fn build(
        rows: impl FnOnce(&[usize], usize) -> Result<LocalRows<D>>,
        fixed: &[bool],
        prolongations: &[SparseColMatRef<'_, usize, f64>],
        energy_norm: Option<SparseColMatRef<'_, usize, f64>>,
        opts: DistributedTnnmgOptions,
        owner: &[usize],
        mut halo: Box<dyn RankGroup>,
    ) -> Result<Self> {
        opts.check_newton()?;
        if prolongations.is_empty() {
            return Err(ProblemError::InvalidOption(
                "TNNMG on ranks needs at least one prolongation (a V-cycle)".into(),
            )
            .into());
        }
        let (rank, size) = (halo.rank(), halo.size());
        let nodes = owner.len();
        let n = D * nodes;
        if let Some(p) = owner.iter().position(|&r| r >= size) {
            return Err(Error::InvalidPartition(format!(
                "node {p} is owned by rank {}, but there are {size} ranks",
                owner[p]
            )));
        }
        // The rank's rows, read from its owned columns (`a`, if owned, is dropped with
        // the closure), checked here and agreed by every rank before any other
        // collective, so that a bad matrix on one rank ends every rank's set-up.
        let local = rows(owner, rank).and_then(|rows| {
            check_rows(&rows, fixed, n)?;
            Ok(rows)
        });
        let mut counters = HaloCounters::default();
        let rows = agree(local, &mut *halo, &mut counters)?;
        // The whole node graph and diagonal blocks (no values of other rows).
        let (graph, a_diag) = NodeGraph::gather(&rows, owner, &mut *halo, &mut counters)?;
        let colouring = Colouring::of_pattern(&graph);
        let sweep = DistributedSweep::of_rows(rows, &colouring)?;
        let ps = prolongations
            .iter()
            .map(|p| Csc::from_faer(*p).map_err(Error::from))
            .collect::<Result<Vec<_>>>()?;
        // The rank's hierarchy: the fine level's graph and diagonal blocks whole, its
        // values computed from the rank's rows (the sweep's) by the first update; the
        // linearisation keeps the diagonal blocks.
        let mut hierarchy =
            RankHierarchy::new(graph, a_diag.clone(), fixed, &ps, owner, (rank, size))?;
        drop(ps);
        hierarchy.with(&mut *halo, sweep.rows()).update()?;
        let vcycle = DistributedVCycle::of_levels(
            &RankLevels::new(sweep.rows(), colouring, &hierarchy, prolongations),
            owner,
            opts.smoothing,
            &*halo,
        )?;
        let fixed = fixed.to_vec();
        let rows = sweep.rows();
        debug_assert_eq!(rows.global_nodes(), vcycle.rows().global_nodes());
        let norm_rows = energy_norm
            .map(|e| norm_rows(e, n, owner, rows))
            .transpose()?;
        let owned = rows.owned();
        let free: Vec<[bool; D]> = rows.global_nodes()[..owned]
            .iter()
            .map(|&p| std::array::from_fn(|c| !fixed[D * p + c]))
            .collect();
        let inverse = (0..owned)
            .map(|p| masked_inverse(rows.diag(p), &free[p]))
            .collect();
        let mut local_of = vec![u32::MAX; nodes];
        for (q, &p) in rows.global_nodes()[..owned].iter().enumerate() {
            local_of[p] = q as u32;
        }
        let local = D * rows.len();
        Ok(Self {
            opts,
            n,
            owner: owner.to_vec(),
            inverse,
            free,
            a_diag,
            fixed,
            norm_rows,
            hierarchy,
            cached_active: None,
            vcycle,
            local_of,
            active_of: Vec::new(),
            gather: None,
            b: vec![0.0; local],
            v: vec![0.0; local],
            v_old: vec![0.0; local],
            c: vec![0.0; local],
            res_a: vec![0.0; D * owned],
            res: vec![0.0; D * owned],
            v_active: vec![0.0; n],
            c_active: vec![0.0; n],
            line_sums: ExactSums::new(2, rank, size),
            norm_sums: ExactSums::new(1, rank, size),
            linear_sums: ExactSums::new(1, rank, size),
            linear_res: vec![0.0; D * owned],
            free_owned: vec![0.0; D * owned],
            cg: DistributedCg::new(D * owned, local, rank, size),
            pending: (None, None),
            solution: AllGather::new(owner, rank, size, D),
            counters: TnnmgCounters {
                setup: counters,
                ..TnnmgCounters::default()
            },
            sweep,
            halo,
        })
    }

    /// The options in use.
    pub fn options(&self) -> &DistributedTnnmgOptions {
        &self.opts
    }

    /// The rank's rows of `A` (its owned nodes and ghosts).
    pub fn rows(&self) -> &LocalRows<D> {
        self.sweep.rows()
    }

    /// What the rank has sent since set-up (or [`reset_counters`](Self::reset_counters)).
    pub fn counters(&self) -> TnnmgCounters {
        let mut c = self.counters;
        c.smoother = self.sweep.counters();
        c.cycles = self.vcycle.counters();
        c.hierarchy = self.hierarchy.counters();
        c.reductions = self.line_sums.counters()
            + self.norm_sums.counters()
            + self.linear_sums.counters()
            + self.cg.counters();
        c
    }

    /// Sets the counters to zero.
    pub fn reset_counters(&mut self) {
        self.counters = TnnmgCounters::default();
        self.sweep.reset_counters();
        self.vcycle.reset_counters();
        self.hierarchy.reset_counters();
        self.line_sums.reset_counters();
        self.norm_sums.reset_counters();
        self.linear_sums.reset_counters();
        self.cg.reset_counters();
    }

    /// What one iteration sends by the plans, for the active blocks of the last solve
    /// (`iterations` = 1; `full_updates` and `solution` zero): `nonlinear_sweeps` sweeps,
    /// `v_cycles` V-cycles, an incremental update of the hierarchy, two all-gathers of
    /// the active blocks, two reductions (the
    /// second with one sum, plus one for a relative stopping test and one for the energy
    /// record), and the linear correction's reductions. With
    /// [`linear_reduction`](DistributedTnnmgOptions::linear_reduction) or conjugate
    /// gradients an iteration may stop its cycles early; the plan counts the most. A
    /// recorded energy adds one reduction at the start of each solve. `None` before the
    /// first solve.
    pub fn per_iteration(&self) -> Option<TnnmgCounters> {
        let gather = self.gather.as_ref()?.per_gather();
        Some(TnnmgCounters {
            iterations: 1,
            smoother: self
                .sweep
                .per_sweep()
                .times(self.opts.nonlinear_sweeps as u64),
            cycles: self.vcycle.per_cycle().times(self.opts.v_cycles as u64),
            gathers: gather.times(2),
            reductions: self.line_sums.per_reduction()
                + self.norm_sums.per_reduction()
                + self.linear_per_iteration(),
            solution: HaloCounters::default(),
            full_updates: 0,
            hierarchy: self.hierarchy.per_incremental_update(),
            setup: HaloCounters::default(),
        })
    }

    /// The most reductions of one linear correction: with `linear_reduction`, the initial
    /// norm and a check after every cycle but the last (`Cycles`) or in every step (CG);
    /// CG's two per step.
    fn linear_per_iteration(&self) -> HaloCounters {
        let (cycles, checked) = (
            self.opts.v_cycles as u64,
            self.opts.linear_reduction.is_some(),
        );
        let norm = self.linear_sums.per_reduction();
        match (self.opts.linear_correction, checked) {
            (LinearCorrection::Cycles, false) => HaloCounters::default(),
            (LinearCorrection::Cycles, true) => norm.times(cycles),
            (LinearCorrection::PreconditionedCg, _) => {
                self.cg.per_step(checked).times(cycles) + norm.times(u64::from(checked))
            }
        }
    }

    /// What one full update of the rank's hierarchy sends (the first iteration of a
    /// solve with new active blocks, and the set-up): per level below the fine one an
    /// exchange of `T` rows, above the coarsest one of the ghosts' masks, and the
    /// coarsest level's all-gather.
    pub fn per_full_update(&self) -> HaloCounters {
        self.hierarchy.per_full_update()
    }

    /// What the all-gather of the solution at the end of a solve sends.
    pub fn per_solution(&self) -> HaloCounters {
        self.solution.per_gather()
    }

    /// Rounds each rank's terms of the line search's sums in floating point before their
    /// exact combination (a reduction whose bits depend on the partition): a broken solver
    /// for the test that must detect it.
    #[cfg(test)]
    pub(crate) fn with_naive_line_sums(mut self) -> Self {
        self.line_sums.use_naive_partial_sums();
        self
    }

    /// Starts a solve: the active map and gather, the local vectors from the global ones.
    pub(super) fn start<N: BlockNonlinearity<D>>(
        &mut self,
        b: &[f64],
        nl: &N,
        v: &[f64],
    ) -> Result<()> {
        active_map(nl, self.n / D, &mut self.active_of)?;
        let rows = self.sweep.rows();
        if self.gather.as_ref().map(|g| g.active()) != Some(nl.active_blocks()) {
            let size = self.halo.size();
            self.gather = Some(ActiveGather::new(
                nl.active_blocks(),
                rows,
                &self.owner,
                size,
            ));
        }
        let sums = 1
            + usize::from(self.opts.stopping.relative > 0.0)
            + usize::from(self.opts.record_energy);
        if self.norm_sums.sums() != sums {
            let kept = self.norm_sums.counters();
            self.norm_sums = ExactSums::new(sums, rows.rank(), self.halo.size());
            self.norm_sums.add_counters(kept);
        }
        rows.gather(b, &mut self.b);
        rows.gather(v, &mut self.v);
        self.pending = (None, None);
        Ok(())
    }

    /// Makes the caller's `v` the whole current iterate on every rank: every rank's owned
    /// values, gathered in one collective.
    pub(super) fn finish(&mut self, v: &mut [f64]) {
        let rows = self.sweep.rows();
        for (q, &p) in rows.global_nodes()[..rows.owned()].iter().enumerate() {
            store(v, p, &load::<D>(&self.v, q));
        }
        self.solution
            .gather(v, &mut *self.halo, &mut self.counters.solution);
    }
}

/// The energy-norm matrix's rows on the iterate's local nodes.
fn norm_rows<const D: usize>(
    e: SparseColMatRef<'_, usize, f64>,
    n: usize,
    owner: &[usize],
    rows: &LocalRows<D>,
) -> Result<NormRows<D>> {
    if e.nrows() != n || e.ncols() != n {
        return Err(ProblemError::DimensionMismatch {
            what: "energy-norm matrix",
            expected: n,
            got: e.nrows(),
        }
        .into());
    }
    // Only the owned columns are read: no whole copy of `e` on any rank.
    let e_rows = LocalRows::<D>::of_columns(e, owner, rows.rank())?;
    let mut local = vec![u32::MAX; owner.len()];
    for (q, &p) in rows.global_nodes().iter().enumerate() {
        local[p] = q as u32;
    }
    let remap = e_rows
        .global_nodes()
        .iter()
        .map(|&p| match local[p] {
            u32::MAX => Err(ProblemError::InvalidMatrix(format!(
                "the energy-norm matrix couples node {p} to a node of rank {} that the \
                 matrix does not",
                rows.rank()
            ))
            .into()),
            q => Ok(q),
        })
        .collect::<Result<_>>()?;
    Ok(NormRows {
        rows: e_rows,
        remap,
    })
}

// `solve` is collective: every rank calls it with the same `b`, `nl` and `v`; afterwards
// every rank's `v` is the whole solution (also when it returns an error, which every rank
// returns alike).
crate::report::iterative_solver!(
    DistributedTnnmg,
    "tnnmg-ranks",
    dim: [n],
    options: [opts],
    watch: [],
    reset: [],
    extra: {
        /// `√(xᵀ E x)` with the ranks' rows of `E` (the energy-norm matrix, or `A` without
        /// one) and an exact sum: collective, every rank passes the same global `x` (length
        /// `D n`) and gets the same bits at every rank count. Between solves (it uses the
        /// correction's local vector as scratch).
        ///
        /// # Panics
        /// If `x` is not `D n` long.
        fn energy_norm_of(&mut self, x: &[f64]) -> Option<f64> {
            assert_eq!(x.len(), self.n, "a global vector of the solver's length");
            let mut local = std::mem::take(&mut self.c);
            for (q, &p) in self.sweep.rows().global_nodes().iter().enumerate() {
                local[D * q..D * q + D].copy_from_slice(&x[D * p..D * p + D]);
            }
            self.add_norm_terms(&local, 0);
            self.c = local;
            Some(self.norm_sums.reduce(&mut *self.halo)[0].max(0.0).sqrt())
        }
    }
);

/// The rows of `a` owned by `rank`, read from its owned columns.
fn owned_rows<const D: usize>(
    a: SparseColMatRef<'_, usize, f64>,
    owner: &[usize],
    rank: usize,
) -> Result<LocalRows<D>> {
    Ok(LocalRows::of_columns(a, owner, rank)?)
}

/// The checks of [`NodalProblem::new`](crate::problem::NodalProblem::new) that a rank can
/// make on its rows: `n` dofs in `fixed`, finite values, a positive diagonal on the free
/// dofs (the pattern's symmetry is checked on the gathered graph).
fn check_rows<const D: usize>(rows: &LocalRows<D>, fixed: &[bool], n: usize) -> Result<()> {
    ProblemError::check_length("fixed mask", n, fixed.len())?;
    for (q, &p) in rows.global_nodes()[..rows.owned()].iter().enumerate() {
        let blocks = std::iter::once(rows.diag(q)).chain(rows.neighbours(q).map(|(_, b)| b));
        if blocks.flatten().flatten().any(|x| !x.is_finite()) {
            return Err(ProblemError::InvalidMatrix(format!(
                "a non-finite entry in the row of node {p}"
            ))
            .into());
        }
        for c in 0..D {
            if !fixed[D * p + c] && rows.diag(q)[c][c] <= 0.0 {
                return Err(ProblemError::NotPositiveDefinite(
                    "non-positive diagonal entry on a free dof",
                )
                .into());
            }
        }
    }
    Ok(())
}

/// Every rank's verdict on its part: this rank's error, or — if another rank failed —
/// [`Error::InvalidPartition`] naming it, on every rank (one all-gather). Collective.
fn agree<T>(local: Result<T>, halo: &mut dyn RankGroup, counters: &mut HaloCounters) -> Result<T> {
    let size = halo.size();
    let mut all = vec![0.0; size];
    halo.all_gather(
        &[f64::from(u8::from(local.is_err()))],
        &vec![1; size],
        &mut all,
    );
    counters.collectives += 1;
    counters.collective_values += 1;
    let local = local?;
    match all.iter().position(|&f| f != 0.0) {
        Some(r) => Err(Error::InvalidPartition(format!(
            "rank {r} found its part of the matrix invalid"
        ))),
        None => Ok(local),
    }
}
