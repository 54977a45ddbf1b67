//! The linear V-cycle of one rank on a nested hierarchy: per level its rows, a multi-colour
//! block Gauss–Seidel sweep, the residual and the transfers; the coarsest problem gathered
//! on every rank and solved there redundantly.

use super::hierarchy::{LevelSource, VCycleHierarchy, VCycleShape};
use super::rank_hierarchy::RankHierarchy;
use super::DistributedTransfer;
use crate::coarse::CoarseSolver;
use crate::error::Result;
use rsf_nonsmooth::ProblemError;
use rsf_ranks::block::{load, store};
use rsf_ranks::halo::{AllGather, HaloCounters};
use rsf_ranks::{BlockGaussSeidel, DistributedSweep, LocalRows, Preconditioner, RankGroup};

/// One rank's part of a level above the coarsest.
#[derive(Debug, Clone)]
struct RankLevel<const D: usize> {
    sweep: DistributedSweep<D>,
    /// The node update, holding the level's owned right-hand side.
    gs: BlockGaussSeidel<D>,
    /// 1 on free dofs, 0 on masked ones (local vector).
    free: Vec<f64>,
    /// The owned residual.
    r: Vec<f64>,
    /// The level's iterate (local vector; empty on the fine level, whose iterate is the
    /// caller's).
    x: Vec<f64>,
    /// Restriction to, and prolongation from, the next coarser level.
    transfer: DistributedTransfer<D>,
}

/// One rank's part of the coarsest level: its owned nodes' right-hand side and solution,
/// and the gathered global problem.
#[derive(Debug)]
struct Coarsest {
    /// Owned nodes (global, increasing).
    owned: Vec<usize>,
    rhs: Vec<f64>,
    x: Vec<f64>,
    /// The global vector the gather fills and the solve overwrites.
    global: Vec<f64>,
    free: Vec<f64>,
    gather: AllGather,
    counters: HaloCounters,
    solver: CoarseSolver,
}

/// One rank's linear V-cycle on a nested hierarchy (a whole [`VCycleHierarchy`], or inside
/// TNNMG on ranks the rank's own rows of every level), with the bits of the one-process
/// [`ColouredVCycle`](super::ColouredVCycle) at every rank count.
///
/// Node `i` of every level is owned by the rank that owns fine node `i` (rsf-fem's
/// `MeshHierarchy` keeps a coarse vertex's index on the finer levels). On each level but
/// the coarsest the rank holds its rows ([`DistributedSweep`], with that level's global
/// colouring and halo plan), its owned right-hand side and residual, and the transfers to
/// the next coarser level ([`DistributedTransfer`]). A cycle on level `l`: `pre` sweeps
/// (increasing colours; a coarse level starts from 0, whose ghosts are current), the
/// residual on the owned rows, the restriction (one exchange), the coarse correction, the
/// prolongation (one exchange), one ghost update (the owned values changed outside a
/// sweep, and the post-sweeps and the next residual read the ghosts), `post` sweeps
/// (decreasing colours). The coarsest level: an all-gather of the owned right-hand sides
/// in one collective ([`RankGroup::all_gather`]: every rank contributes its owned
/// values and receives every other rank's; the global vector is assembled by node index,
/// so its bits do not depend on the rank count), then
/// every rank that owns a coarsest node solves the whole coarsest problem with the same
/// factorisation and keeps its owned values. No reduction is made: every value is
/// computed by one rank with the one-process arithmetic.
///
/// Allocation-free per cycle (the transport may allocate).
#[derive(Debug)]
pub struct DistributedVCycle<const D: usize> {
    rank: usize,
    shape: VCycleShape,
    /// `levels[l − 1]` is level `l ≥ 1`; the last the fine level.
    levels: Vec<RankLevel<D>>,
    coarsest: Coarsest,
    /// Per level `l ≥ 1` (index `l − 1`): the local nodes an incremental refresh visits
    /// ([`set_variable_nodes`](Self::set_variable_nodes)).
    variable: Vec<Vec<u32>>,
    /// Leaves out the ghost update after each prolongation: a broken cycle, for the test
    /// that must detect it.
    #[cfg(test)]
    pub(crate) skip_ghost_update: bool,
}

impl<const D: usize> DistributedVCycle<D> {
    /// The V-cycle of rank `halo.rank()` of `halo.size()` on `h`, fine node `i` owned by
    /// rank `owner[i]` (length: the fine level's nodes), with `shape`; the fine right-hand
    /// side zero ([`set_rhs`](Self::set_rhs)).
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] if `owner` does not have one entry per fine node;
    /// [`Error::InvalidPartition`](crate::Error::InvalidPartition) if an owner is not a rank of
    /// `halo`; [`ProblemError::NotPositiveDefinite`] as [`VCycleHierarchy::new`]'s factorisation.
    pub fn new<H: RankGroup + ?Sized>(
        h: &VCycleHierarchy<D>,
        owner: &[usize],
        shape: VCycleShape,
        halo: &H,
    ) -> Result<Self> {
        Self::of_levels(h, owner, shape, halo)
    }

    /// As [`new`](Self::new), from any source of the levels (a [`VCycleHierarchy`], or a
    /// rank's hierarchy: [`RankLevels`](super::hierarchy::RankLevels)).
    pub(crate) fn of_levels<H: RankGroup + ?Sized>(
        h: &impl LevelSource<D>,
        owner: &[usize],
        shape: VCycleShape,
        halo: &H,
    ) -> Result<Self> {
        let (rank, size) = (halo.rank(), halo.size());
        let nl = h.num_levels();
        let fine_nodes = h.nodes(nl - 1);
        ProblemError::check_length("owner (one rank per fine node)", fine_nodes, owner.len())?;
        let mut levels = Vec::with_capacity(nl - 1);
        for l in 1..nl {
            let own = &owner[..h.nodes(l)];
            let sweep = h.sweep(l, own, halo)?;
            let rows = sweep.rows();
            let local = |v: &[f64]| {
                let mut out = vec![0.0; D * rows.len()];
                rows.gather(v, &mut out);
                out
            };
            let mut fixed = vec![false; D * rows.len()];
            rows.gather(h.fixed(l), &mut fixed);
            let free = local(h.free(l));
            let gs = BlockGaussSeidel::new(rows, &vec![0.0; D * rows.owned()], &fixed)?;
            let transfer = DistributedTransfer::new(h.prolongation(l - 1), own, halo)?;
            let x = if l + 1 < nl {
                vec![0.0; D * rows.len()]
            } else {
                Vec::new()
            };
            levels.push(RankLevel {
                r: vec![0.0; D * rows.owned()],
                sweep,
                gs,
                free,
                x,
                transfer,
            });
        }
        let n0 = h.nodes(0);
        let own0 = &owner[..n0];
        let owned: Vec<usize> = (0..n0).filter(|&i| own0[i] == rank).collect();
        let coarsest = Coarsest {
            rhs: vec![0.0; D * owned.len()],
            x: vec![0.0; D * owned.len()],
            owned,
            global: vec![0.0; D * n0],
            free: h.free(0).to_vec(),
            gather: AllGather::new(own0, rank, size, D),
            counters: HaloCounters::default(),
            solver: h.coarse_solver()?,
        };
        Ok(Self {
            rank,
            shape,
            levels,
            coarsest,
            variable: Vec::new(),
            #[cfg(test)]
            skip_ghost_update: false,
        })
    }

    /// The rank's rows of the fine level and their local numbering (the iterate is a
    /// local vector of these rows).
    pub fn rows(&self) -> &LocalRows<D> {
        self.fine().sweep.rows()
    }

    /// The rank's rows of level `l ≥ 1` (0 is the coarsest level, which has no rows).
    ///
    /// # Panics
    /// If `l == 0` or `l` is not a level.
    pub fn level_rows(&self, l: usize) -> &LocalRows<D> {
        self.levels[l - 1].sweep.rows()
    }

    /// Number of coarsest nodes the rank owns.
    pub fn coarsest_owned(&self) -> usize {
        self.coarsest.owned.len()
    }

    fn fine(&self) -> &RankLevel<D> {
        self.levels.last().expect("two levels or more")
    }

    /// Sets the fine right-hand side from the owned nodes' values: the first
    /// `D · rows().owned()` values of `b` (a local vector's owned part; further values are
    /// not read).
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] if `b` is shorter than that.
    pub fn set_rhs(&mut self, b: &[f64]) -> Result<()> {
        let rhs = self
            .levels
            .last_mut()
            .expect("two levels or more")
            .gs
            .rhs_mut();
        if b.len() < rhs.len() {
            return Err(ProblemError::DimensionMismatch {
                what: "b (owned fine values)",
                expected: rhs.len(),
                got: b.len(),
            }
            .into());
        }
        let n = rhs.len();
        rhs.copy_from_slice(&b[..n]);
        Ok(())
    }

    /// Takes the variable nodes of `h` (after its `set_variable_nodes`): the local nodes
    /// of each level above the coarsest that an incremental [`refresh`](Self::refresh)
    /// visits.
    pub(crate) fn set_variable_nodes(&mut self, h: &RankHierarchy<D>) {
        self.variable = self
            .levels
            .iter()
            .enumerate()
            .map(|(i, level)| {
                let rows = level.sweep.rows();
                let nodes = h.free(i + 1).len() / D;
                let mut local = vec![u32::MAX; nodes];
                for (q, &g) in rows.global_nodes().iter().enumerate() {
                    local[g] = q as u32;
                }
                let mut list: Vec<u32> = h
                    .variable_nodes(i + 1)
                    .iter()
                    .map(|&g| local[g])
                    .filter(|&q| q != u32::MAX)
                    .collect();
                list.sort_unstable();
                list
            })
            .collect();
    }

    /// Takes the values of `h` (the rank's hierarchy this cycle was built from, same
    /// patterns, owners and colourings; its values changed by an update): on every level
    /// above the coarsest the rank's rows (on the fine level their diagonal blocks: its
    /// off-diagonal blocks do not change), local solves and masks — of every local node
    /// when `all`, else of the nodes of [`set_variable_nodes`](Self::set_variable_nodes) —
    /// and the coarsest mask and factorisation. No communication.
    ///
    /// # Errors
    /// [`ProblemError::NotPositiveDefinite`] if the coarsest operator cannot be factorised.
    pub(crate) fn refresh(&mut self, h: &RankHierarchy<D>, all: bool) -> Result<()> {
        let fine = self.levels.len();
        for (i, level) in self.levels.iter_mut().enumerate() {
            let l = i + 1;
            let (mask, free) = (h.mask(l), h.free(l));
            let every: Vec<u32>;
            let nodes = if all {
                every = (0..level.sweep.rows().len() as u32).collect();
                &every[..]
            } else {
                &self.variable[i][..]
            };
            let owned = level.sweep.rows().owned();
            for &q in nodes {
                let q = q as usize;
                let g = level.sweep.rows().global_nodes()[q];
                level.free[D * q..D * q + D].copy_from_slice(&free[D * g..D * g + D]);
                if q < owned {
                    if l == fine {
                        let diag = &h.fine_diag()[g];
                        level.sweep.rows_mut().set_diag(q, diag);
                        level.gs.set_node(q, diag, &mask[D * g..D * g + D]);
                    } else {
                        let a = h.coarse_matrix(l);
                        let off = a.neighbours(g).map(|(_, b)| b);
                        level.sweep.rows_mut().set_row(q, &a.diag[g], off);
                        level.gs.set_node(q, &a.diag[g], &mask[D * g..D * g + D]);
                    }
                }
            }
        }
        self.coarsest.free.copy_from_slice(h.free(0));
        self.coarsest
            .solver
            .factorize(h.coarse_matrix(0), h.mask(0))
    }

    /// Refreshes every ghost of the fine iterate `x` (a local vector of
    /// [`rows`](Self::rows)): once before the first [`cycle`](Self::cycle), or after the
    /// caller changed owned values. Collective.
    ///
    /// # Panics
    /// If `x` has the wrong length or `halo` is another rank's.
    pub fn update_ghosts<H: RankGroup + ?Sized>(&mut self, x: &mut [f64], halo: &mut H) {
        let fine = self.levels.last_mut().expect("two levels or more");
        fine.sweep.update_ghosts(x, halo);
    }

    /// One V-cycle on the fine iterate `x` (a local vector of [`rows`](Self::rows), its
    /// ghosts current; its fixed dofs are left as they are). Afterwards every owned and
    /// ghost value is current. Collective.
    ///
    /// # Panics
    /// If `x` has the wrong length or `halo` is another rank's.
    pub fn cycle<H: RankGroup + ?Sized>(&mut self, x: &mut [f64], halo: &mut H) {
        assert_eq!(halo.rank(), self.rank, "the transport of another rank");
        let l = self.levels.len();
        self.level_cycle(l, x, false, halo);
    }

    /// One cycle on level `l ≥ 1` (the coarsest level is solved inside level 1's).
    fn level_cycle<H: RankGroup + ?Sized>(
        &mut self,
        l: usize,
        x: &mut [f64],
        zero_start: bool,
        halo: &mut H,
    ) {
        let shape = self.shape;
        let (below, here) = self.levels.split_at_mut(l - 1);
        let level = &mut here[0];
        if zero_start {
            x.fill(0.0);
        }
        level.smooth(x, shape.pre, false, halo);
        level.sweep.rows().residual(level.gs.rhs(), x, &mut level.r);
        let coarse_rhs = match below.last_mut() {
            Some(coarse) => coarse.gs.rhs_mut(),
            None => &mut self.coarsest.rhs[..],
        };
        level
            .transfer
            .restrict(&level.r, &level.free, coarse_rhs, halo);
        if l == 1 {
            // The coarsest solution stays in place: the prolongation reads it there.
            self.coarsest.solve::<D, H>(halo);
            let level = &mut self.levels[0];
            level
                .transfer
                .prolong_add(&self.coarsest.x, &level.free, x, halo);
        } else {
            let mut xc = std::mem::take(&mut self.levels[l - 2].x);
            self.level_cycle(l - 1, &mut xc, true, halo);
            let level = &mut self.levels[l - 1];
            level.transfer.prolong_add(&xc, &level.free, x, halo);
            self.levels[l - 2].x = xc;
        }
        let level = &mut self.levels[l - 1];
        #[cfg(test)]
        let skip = self.skip_ghost_update;
        #[cfg(not(test))]
        let skip = false;
        if !skip {
            level.sweep.update_ghosts(x, halo);
        }
        level.smooth(x, shape.post, true, halo);
    }

    /// What the rank has sent since set-up (or [`reset_counters`](Self::reset_counters)),
    /// over all levels: sweeps, ghost updates, transfers and the coarsest gathers.
    pub fn counters(&self) -> HaloCounters {
        let mut c = self.coarsest.counters;
        for level in &self.levels {
            c += level.sweep.counters() + level.transfer.counters();
        }
        c
    }

    /// Sets the counters to zero.
    pub fn reset_counters(&mut self) {
        self.coarsest.counters = HaloCounters::default();
        for level in &mut self.levels {
            level.sweep.reset_counters();
            level.transfer.reset_counters();
        }
    }

    /// What one cycle sends by the plans: per level above the coarsest `pre + post` sweeps,
    /// one ghost update, one restriction and one prolongation; one gather of the coarsest
    /// level.
    pub fn per_cycle(&self) -> HaloCounters {
        let sweeps = (self.shape.pre + self.shape.post) as u64;
        let mut c = self.coarsest.gather.per_gather();
        for level in &self.levels {
            c += level.sweep.per_sweep().times(sweeps)
                + level.sweep.per_ghost_update()
                + level.transfer.per_transfer_pair();
        }
        c
    }
}

/// One V-cycle from zero on the right-hand side `r`: the preconditioner of the conjugate
/// gradients on ranks ([`DistributedCg`](rsf_ranks::DistributedCg)), `H` the cycle's fine
/// rows.
impl<const D: usize> Preconditioner<D> for DistributedVCycle<D> {
    fn rows(&self) -> &LocalRows<D> {
        DistributedVCycle::rows(self)
    }

    fn apply<H: RankGroup + ?Sized>(&mut self, r: &[f64], z: &mut [f64], halo: &mut H) {
        self.set_rhs(r)
            .expect("the owned right-hand side has the rows' length");
        self.cycle(z, halo);
    }
}

impl<const D: usize> RankLevel<D> {
    /// `sweeps` sweeps of `x` (decreasing colours when `reverse`).
    fn smooth<H: RankGroup + ?Sized>(
        &mut self,
        x: &mut [f64],
        sweeps: usize,
        reverse: bool,
        halo: &mut H,
    ) {
        let gs = &self.gs;
        for _ in 0..sweeps {
            self.sweep
                .sweep(x, reverse, halo, |rows, p, x| gs.update(rows, p, x));
        }
    }
}

impl Coarsest {
    /// Gathers the owned right-hand sides into the global vector, solves, keeps the owned
    /// values of the solution.
    fn solve<const D: usize, H: RankGroup + ?Sized>(&mut self, halo: &mut H) {
        for (k, &i) in self.owned.iter().enumerate() {
            store(&mut self.global, i, &load::<D>(&self.rhs, k));
        }
        self.gather
            .gather(&mut self.global, halo, &mut self.counters);
        if self.owned.is_empty() {
            return;
        }
        self.solver.solve(&mut self.global, &self.free);
        for (k, &i) in self.owned.iter().enumerate() {
            store(&mut self.x, k, &load::<D>(&self.global, i));
        }
    }
}
