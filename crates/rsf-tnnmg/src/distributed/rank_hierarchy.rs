//! TNNMG's Newton hierarchy on ranks, each rank computing its own rows
//! ([`RankHierarchy`]): the Galerkin products `C = P_tᵀ H P_t` of every level by the
//! owners of their rows, with the one-process arithmetic row by row.

use std::collections::BTreeMap;

use crate::coarse::excluded;
use crate::error::Result;
use crate::galerkin::Pattern;
use crate::multigrid::NewtonHierarchy;
use rsf_linalg::Csc;
use rsf_ranks::block::Block;
use rsf_ranks::bsr::BlockCsr;
use rsf_ranks::bsr::NodePattern;
use rsf_ranks::halo::HaloCounters;
use rsf_ranks::{LocalRows, NodeGraph, NodePlan, RankGroup};

/// One Galerkin product between level `l + 1` (fine) and level `l` on a rank: the whole
/// structure, the values of `T`'s rows the rank computes (its owned fine nodes) or
/// receives (fine nodes in the support of its owned coarse nodes).
#[derive(Debug)]
struct RankGalerkin<const D: usize> {
    pattern: Pattern<D>,
    /// Fine nodes whose `T` row this rank computes, and coarse nodes whose `C` row.
    owned_fine: Vec<usize>,
    owned_coarse: Vec<usize>,
    /// Per fine node, the start of its `T` row in `t_val` (`usize::MAX`: not held).
    t_start: Vec<usize>,
    t_val: Vec<Block<D>>,
    /// Dense accumulator over the coarse nodes (zero between uses).
    acc: Vec<Block<D>>,
    /// `T` rows with the fine node's `free` values (`D + D² · len` values each).
    rows: NodePlan,
    /// Per incremental update: the owned `T` rows and `C` rows to recompute.
    t_some: Vec<usize>,
    c_some: Vec<usize>,
    /// The rows plan restricted to the incremental update's `T` rows.
    rows_some: NodePlan,
}

/// One coarse level (below the fine level) on a rank: the whole pattern, the values of
/// its owned rows (all rows on the coarsest level, gathered), the masks of its owned
/// nodes and ghosts (all on the coarsest).
#[derive(Debug)]
struct CoarseLevel<const D: usize> {
    a: BlockCsr<D>,
    mask: Vec<bool>,
    free: Vec<f64>,
    /// The diagonal of the last full update (owned nodes), the reference of the
    /// incremental updates' masks.
    ref_diag: Vec<f64>,
    /// The ghosts' masks (`D` values of `free` per node), whole and for the incremental
    /// updates' nodes.
    ghosts: NodePlan,
    ghosts_some: NodePlan,
}

/// TNNMG's truncated Newton hierarchy on ranks (issue 57, docs/scaling.md "Phase 7"):
/// the fine level's Newton diagonal blocks and mask whole (the replicated linearisation),
/// its off-diagonal blocks the rank's rows of `A`; on every coarser level the rank
/// computes the Galerkin rows of the coarse nodes it owns (node `i` of every level is
/// owned by `owner[i]`), from the `T = H F P` rows of its owned fine nodes and those it
/// receives of the fine nodes in its coarse nodes' support (one exchange per level and
/// update), then exchanges its ghosts' masks; the coarsest level's rows are all-gathered.
/// Every row is computed by one rank with the one-process multigrid's arithmetic
/// ([`Pattern::t_row_of`], [`Pattern::c_row_of`]), so every value has the bits of the
/// replicated hierarchy's at any rank count. What a rank stores of the values: its rows,
/// not the whole levels (the coarse levels keep their whole pattern and whole-length
/// value arrays, an eighth of the fine level's and less).
#[derive(Debug)]
pub(crate) struct RankHierarchy<const D: usize> {
    rank: usize,
    owner: Vec<usize>,
    /// `pairs[l]` maps level `l + 1` to level `l`.
    pairs: Vec<RankGalerkin<D>>,
    /// Levels `0..nl − 1`, coarsest first (the fine level is `fine_*`).
    coarse: Vec<CoarseLevel<D>>,
    fine_diag: Vec<Block<D>>,
    fine_mask: Vec<bool>,
    fine_free: Vec<f64>,
    /// The fine level's node graph, whole.
    fine_pattern: NodeGraph,
    /// The coarsest level's rows all-gathered: counts per rank, buffers.
    coarsest_counts: Vec<usize>,
    coarsest_send: Vec<f64>,
    coarsest_recv: Vec<f64>,
    /// Where each rank's next record starts in `coarsest_recv` (work space).
    coarsest_starts: Vec<usize>,
    /// Per level, the nodes an incremental update may change (global lists, every rank
    /// the same).
    variable: Vec<Vec<usize>>,
    counters: HaloCounters,
}

impl<const D: usize> RankHierarchy<D> {
    /// The hierarchy of rank `rank` among `size` ranks: the fine level's node graph
    /// `fine` (whole), the fine diagonal blocks `diag` and masked dofs `fixed`
    /// (whole), the prolongations
    /// (`ps[l]` maps level `l` to `l + 1`, node-major) and the owners of the fine nodes.
    /// Values are set by the first update ([`with`](Self::with)), which reads the rank's
    /// rows of the fine level.
    ///
    /// # Errors
    /// As [`Pattern::new`].
    pub(crate) fn new(
        fine: NodeGraph,
        diag: Vec<Block<D>>,
        fixed: &[bool],
        ps: &[Csc],
        owner: &[usize],
        (rank, size): (usize, usize),
    ) -> Result<Self> {
        let nl = ps.len() + 1;
        let mut pairs_rev = Vec::new();
        let mut coarse_rev: Vec<BlockCsr<D>> = Vec::new();
        for p in ps.iter().rev() {
            let (pattern, c) = match coarse_rev.last() {
                Some(finer) => Pattern::new(finer, p)?,
                None => Pattern::new(&fine, p)?,
            };
            let nf = pattern.p_ptr.len() - 1;
            pairs_rev.push(RankGalerkin::new(pattern, nf, c.nodes(), owner, rank));
            coarse_rev.push(c);
        }
        pairs_rev.reverse();
        coarse_rev.reverse();
        let coarse = coarse_rev
            .into_iter()
            .enumerate()
            .map(|(l, a)| CoarseLevel::new(a, owner, rank, l == 0))
            .collect::<Vec<_>>();
        let coarsest_counts = {
            let a = &coarse[0].a;
            let mut counts = vec![0; size];
            for p in 0..a.nodes() {
                counts[owner[p]] += coarsest_record::<D>(a, p);
            }
            counts
        };
        let free = fixed.iter().map(|&f| if f { 0.0 } else { 1.0 }).collect();
        debug_assert_eq!(coarse.len(), nl - 1);
        Ok(Self {
            rank,
            owner: owner.to_vec(),
            pairs: pairs_rev,
            coarsest_send: vec![0.0; coarsest_counts[rank]],
            coarsest_recv: vec![0.0; coarsest_counts.iter().sum()],
            coarsest_starts: vec![0; size],
            coarsest_counts,
            coarse,
            fine_diag: diag,
            fine_mask: fixed.to_vec(),
            fine_free: free,
            fine_pattern: fine,
            variable: Vec::new(),
            counters: HaloCounters::default(),
        })
    }

    /// Number of levels.
    pub(crate) fn num_levels(&self) -> usize {
        self.coarse.len() + 1
    }

    /// Level `l`'s matrix below the fine level (`l < num_levels() − 1`): the owned rows'
    /// values (all rows on level 0).
    pub(crate) fn coarse_matrix(&self, l: usize) -> &BlockCsr<D> {
        &self.coarse[l].a
    }

    /// Level `l`'s masked dofs (whole length; valid on the owned nodes and ghosts, all on
    /// the fine and coarsest levels).
    pub(crate) fn mask(&self, l: usize) -> &[bool] {
        match self.coarse.get(l) {
            Some(c) => &c.mask,
            None => &self.fine_mask,
        }
    }

    /// Level `l`'s mask as a 0/1 factor (as [`mask`](Self::mask)).
    pub(crate) fn free(&self, l: usize) -> &[f64] {
        match self.coarse.get(l) {
            Some(c) => &c.free,
            None => &self.fine_free,
        }
    }

    /// The fine level's mask (whole).
    pub(crate) fn fine_mask(&self) -> &[bool] {
        &self.fine_mask
    }

    /// The fine level's Newton diagonal blocks (whole).
    pub(crate) fn fine_diag(&self) -> &[Block<D>] {
        &self.fine_diag
    }

    /// The nodes of level `l` an incremental update may change.
    pub(crate) fn variable_nodes(&self, l: usize) -> &[usize] {
        self.variable.get(l).map_or(&[], |v| &v[..])
    }

    /// What the updates have sent since set-up.
    pub(crate) fn counters(&self) -> HaloCounters {
        self.counters
    }

    /// What one full update sends by its plans.
    pub(crate) fn per_full_update(&self) -> HaloCounters {
        self.per_update(true)
    }

    /// What one incremental update sends by its plans (after
    /// [`set_variable`](Self::set_variable)).
    pub(crate) fn per_incremental_update(&self) -> HaloCounters {
        self.per_update(false)
    }

    fn per_update(&self, full: bool) -> HaloCounters {
        let plan = NodePlan::per_send;
        let mut c = HaloCounters {
            collectives: 1,
            collective_values: self.coarsest_send.len() as u64,
            ..HaloCounters::default()
        };
        for pair in &self.pairs {
            c += plan(if full { &pair.rows } else { &pair.rows_some });
        }
        for level in &self.coarse[1..] {
            c += plan(if full {
                &level.ghosts
            } else {
                &level.ghosts_some
            });
        }
        c
    }

    /// Sets the counters to zero.
    pub(crate) fn reset_counters(&mut self) {
        self.counters = HaloCounters::default();
    }

    /// The updates with `halo` (collective) and the rank's rows of the fine level
    /// `fine_rows` (of `A` or of the Newton matrix: only their off-diagonal blocks are
    /// read): see [`NewtonHierarchy`].
    pub(crate) fn with<'a>(
        &'a mut self,
        halo: &'a mut dyn RankGroup,
        fine_rows: &'a LocalRows<D>,
    ) -> RankUpdate<'a, D> {
        RankUpdate {
            h: self,
            halo,
            fine_rows,
        }
    }

    /// Recomputes the rank's rows of every coarse level (all of them when `full`, else
    /// those the variable nodes reach), exchanging `T` rows and ghost masks, and gathers
    /// the coarsest level. Collective.
    fn update(&mut self, halo: &mut dyn RankGroup, fine_rows: &LocalRows<D>, full: bool) {
        let nl = self.num_levels();
        if full {
            for (f, &m) in self.fine_free.iter_mut().zip(&self.fine_mask) {
                *f = if m { 0.0 } else { 1.0 };
            }
        } else {
            for &p in &self.variable[nl - 1] {
                for c in 0..D {
                    self.fine_free[D * p + c] = if self.fine_mask[D * p + c] { 0.0 } else { 1.0 };
                }
            }
        }
        for l in (0..nl - 1).rev() {
            let (lo, hi) = self.coarse.split_at_mut(l + 1);
            let coarse = &mut lo[l];
            let pair = &mut self.pairs[l];
            // The finer level's rows and masks.
            let (finer_free, finer_rows): (&mut Vec<f64>, FinerRows<'_, D>) = match hi.first_mut() {
                Some(c) => (&mut c.free, FinerRows::Coarse(&c.a)),
                None => (
                    &mut self.fine_free,
                    FinerRows::Fine {
                        diag: &self.fine_diag,
                        rows: fine_rows,
                    },
                ),
            };
            pair.compute_t(&finer_rows, finer_free, full);
            pair.exchange_t(halo, finer_free, full, &mut self.counters);
            pair.compute_c(finer_free, coarse, full);
            if l > 0 {
                coarse.exchange_masks(halo, full, &mut self.counters);
            }
        }
        self.gather_coarsest(halo);
    }

    /// Every rank's owned rows and masks of the coarsest level, in one all-gather.
    fn gather_coarsest(&mut self, halo: &mut dyn RankGroup) {
        let c = &mut self.coarse[0];
        let n = c.a.nodes();
        let mut at = 0;
        for p in (0..n).filter(|&p| self.owner[p] == self.rank) {
            at += write_record(&c.a, &c.free, p, &mut self.coarsest_send[at..]);
        }
        halo.all_gather(
            &self.coarsest_send,
            &self.coarsest_counts,
            &mut self.coarsest_recv,
        );
        self.counters.collectives += 1;
        self.counters.collective_values += self.coarsest_send.len() as u64;
        // Rank r's records in increasing node order, the ranks in turn.
        let starts = &mut self.coarsest_starts;
        let mut first = 0;
        for (s, &k) in starts.iter_mut().zip(&self.coarsest_counts) {
            *s = first;
            first += k;
        }
        for p in 0..n {
            let r = self.owner[p];
            if r != self.rank {
                let used = read_record(&mut c.a, &mut c.free, p, &self.coarsest_recv[starts[r]..]);
                starts[r] += used;
            } else {
                starts[r] += coarsest_record::<D>(&c.a, p);
            }
        }
        for (m, &f) in c.mask.iter_mut().zip(&c.free) {
            *m = f == 0.0;
        }
    }

    /// Declares the fine nodes whose diagonal blocks or masks may change between
    /// incremental updates and derives, as the one-process multigrid's
    /// `Galerkin::affected`, the `T` and `C` rows of every level they reach (the same
    /// lists on every rank), the rank's share of them and the incremental plans.
    fn set_variable(&mut self, fine_nodes: &[usize]) {
        let nl = self.num_levels();
        self.variable = vec![Vec::new(); nl];
        self.variable[nl - 1] = fine_nodes.to_vec();
        for l in (0..nl - 1).rev() {
            let finer_nodes = match self.coarse.get(l + 1) {
                Some(c) => c.a.nodes(),
                None => self.fine_diag.len(),
            };
            let mut changed = vec![false; finer_nodes];
            for &i in &self.variable[l + 1] {
                changed[i] = true;
            }
            let t_changed: Vec<bool> = (0..finer_nodes)
                .map(|i| {
                    changed[i]
                        || match self.coarse.get(l + 1) {
                            Some(c) => c.a.neighbours(i).any(|(q, _)| changed[q]),
                            None => self.fine_pattern.node_neighbours(i).any(|q| changed[q]),
                        }
                })
                .collect();
            let pair = &mut self.pairs[l];
            let (pt_ptr, pt) = (&pair.pattern.pt_ptr, &pair.pattern.pt);
            let c_rows: Vec<usize> = (0..pt_ptr.len() - 1)
                .filter(|&ic| {
                    pt[pt_ptr[ic]..pt_ptr[ic + 1]]
                        .iter()
                        .any(|&(i, _)| t_changed[i as usize])
                })
                .collect();
            pair.set_some(&t_changed, &c_rows);
            let coarse = &mut self.coarse[l];
            let mut on = vec![false; coarse.a.nodes()];
            for &p in &c_rows {
                on[p] = true;
            }
            coarse.ghosts_some.clone_from(&coarse.ghosts);
            coarse.ghosts_some.select(|p| on[p], |_| D);
            self.variable[l] = c_rows;
        }
    }
}

/// The rows `T` is computed from: the fine level's (whole Newton diagonal, the rank's
/// rows of `A`) or a coarse level's (its owned rows).
enum FinerRows<'a, const D: usize> {
    Fine {
        diag: &'a [Block<D>],
        rows: &'a LocalRows<D>,
    },
    Coarse(&'a BlockCsr<D>),
}

impl<const D: usize> RankGalerkin<D> {
    fn new(pattern: Pattern<D>, nf: usize, nc: usize, owner: &[usize], rank: usize) -> Self {
        let owned_fine: Vec<usize> = (0..nf).filter(|&i| owner[i] == rank).collect();
        let owned_coarse: Vec<usize> = (0..nc).filter(|&i| owner[i] == rank).collect();
        // Received: the fine nodes of the owned coarse nodes' support that others own.
        let mut need = vec![false; nf];
        for &ic in &owned_coarse {
            for &(i, _) in &pattern.pt[pattern.pt_ptr[ic]..pattern.pt_ptr[ic + 1]] {
                need[i as usize] = owner[i as usize] != rank;
            }
        }
        let mut recv: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        for i in (0..nf).filter(|&i| need[i]) {
            recv.entry(owner[i]).or_default().push(i);
        }
        // Sent: an owned fine node to the owners of its coarse nodes.
        let mut send: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        let mut ranks = Vec::new();
        for &i in &owned_fine {
            ranks.clear();
            ranks.extend(
                pattern.p_col[pattern.p_ptr[i]..pattern.p_ptr[i + 1]]
                    .iter()
                    .map(|&ic| owner[ic as usize])
                    .filter(|&r| r != rank),
            );
            ranks.sort_unstable();
            ranks.dedup();
            for &r in &ranks {
                send.entry(r).or_default().push(i);
            }
        }
        let mut t_start = vec![usize::MAX; nf];
        let mut held = 0;
        for i in (0..nf).filter(|&i| owner[i] == rank || need[i]) {
            t_start[i] = held;
            held += pattern.t_len(i);
        }
        let len = |i: usize| D + D * D * pattern.t_len(i);
        let rows = NodePlan::new(send, recv, len);
        Self {
            owned_fine,
            owned_coarse,
            t_start,
            t_val: vec![[[0.0; D]; D]; held],
            acc: vec![[[0.0; D]; D]; nc],
            rows_some: rows.clone(),
            rows,
            t_some: Vec::new(),
            c_some: Vec::new(),
            pattern,
        }
    }

    fn set_some(&mut self, t_changed: &[bool], c_rows: &[usize]) {
        self.t_some = self
            .owned_fine
            .iter()
            .copied()
            .filter(|&i| t_changed[i])
            .collect();
        let mut on = vec![false; self.acc.len()];
        for &ic in c_rows {
            on[ic] = true;
        }
        self.c_some = self
            .owned_coarse
            .iter()
            .copied()
            .filter(|&ic| on[ic])
            .collect();
        self.rows_some.clone_from(&self.rows);
        let pattern = &self.pattern;
        self.rows_some
            .select(|i| t_changed[i], |i| D + D * D * pattern.t_len(i));
    }

    /// The owned `T` rows (all, or the incremental update's).
    fn compute_t(&mut self, finer: &FinerRows<'_, D>, free: &[f64], full: bool) {
        let rows = if full { &self.owned_fine } else { &self.t_some };
        for &i in rows {
            let out = &mut self.t_val[self.t_start[i]..self.t_start[i] + self.pattern.t_len(i)];
            match finer {
                FinerRows::Fine { diag, rows: local } => {
                    let q = local.local_of_owned(i);
                    let global = local.global_nodes();
                    let row = std::iter::once((i, &diag[i]))
                        .chain(local.neighbours(q).map(|(lq, b)| (global[lq], b)));
                    self.pattern.t_row_of(row, free, i, &mut self.acc, out);
                }
                FinerRows::Coarse(a) => {
                    let row = std::iter::once((i, &a.diag[i])).chain(a.neighbours(i));
                    self.pattern.t_row_of(row, free, i, &mut self.acc, out);
                }
            }
        }
    }

    /// Sends the owned `T` rows (with their nodes' `free` values) to the ranks that need
    /// them and receives those it needs (into `t_val` and `free`). Collective.
    fn exchange_t(
        &mut self,
        halo: &mut dyn RankGroup,
        free: &mut [f64],
        full: bool,
        counters: &mut HaloCounters,
    ) {
        let plan = if full {
            &mut self.rows
        } else {
            &mut self.rows_some
        };
        let (t_start, t_val, pattern) = (&self.t_start, &mut self.t_val, &self.pattern);
        let len = |i: usize| D + D * D * pattern.t_len(i);
        plan.pack(len, |i, out| {
            out[..D].copy_from_slice(&free[D * i..D * i + D]);
            let row = &t_val[t_start[i]..t_start[i] + pattern.t_len(i)];
            for (o, b) in out[D..].chunks_exact_mut(D * D).zip(row) {
                for r in 0..D {
                    o[D * r..D * r + D].copy_from_slice(&b[r]);
                }
            }
        });
        plan.send(halo, counters);
        plan.unpack(len, |i, values| {
            free[D * i..D * i + D].copy_from_slice(&values[..D]);
            let row = &mut t_val[t_start[i]..t_start[i] + pattern.t_len(i)];
            for (b, v) in row.iter_mut().zip(values[D..].chunks_exact(D * D)) {
                for r in 0..D {
                    b[r].copy_from_slice(&v[D * r..D * r + D]);
                }
            }
        });
    }

    /// The owned `C` rows (all, or the incremental update's) into `coarse`, with their
    /// masks: on a full update a dof is masked if its diagonal is excluded (and the
    /// diagonal is kept as the reference), on an incremental one if it is not above
    /// `1e-13` times the reference (the one-process multigrid's rules).
    fn compute_c(&mut self, free: &[f64], coarse: &mut CoarseLevel<D>, full: bool) {
        let rows = if full {
            &self.owned_coarse
        } else {
            &self.c_some
        };
        let (t_start, t_val, pattern) = (&self.t_start, &self.t_val, &self.pattern);
        let a = &mut coarse.a;
        let (lower, upper) = (
            std::sync::Arc::make_mut(&mut a.lower),
            std::sync::Arc::make_mut(&mut a.upper),
        );
        let zero = [[0.0; D]; D];
        for &ic in rows {
            pattern.c_row_of(
                free,
                |i| &t_val[t_start[i]..t_start[i] + pattern.t_len(i)],
                ic,
                &mut self.acc,
            );
            a.diag[ic] = std::mem::replace(&mut self.acc[ic], zero);
            for t in [&mut *lower, &mut *upper] {
                let r = t.range(ic);
                for (v, &q) in t.val[r.clone()].iter_mut().zip(&t.col[r]) {
                    *v = std::mem::replace(&mut self.acc[q as usize], zero);
                }
            }
            for c in 0..D {
                let (d, i) = (a.diag[ic][c][c], D * ic + c);
                let masked = if full {
                    coarse.ref_diag[i] = d.max(0.0);
                    excluded(d)
                } else {
                    !(d > 1e-13 * coarse.ref_diag[i])
                };
                coarse.mask[i] = masked;
                coarse.free[i] = if masked { 0.0 } else { 1.0 };
            }
        }
    }
}

impl<const D: usize> CoarseLevel<D> {
    /// Level `a` (zero values) of the nodes owned by `owner`, seen from `rank`: its
    /// ghosts' plan (none on the coarsest level, which is gathered).
    fn new(a: BlockCsr<D>, owner: &[usize], rank: usize, coarsest: bool) -> Self {
        let n = a.nodes();
        let (mut send, mut recv): (BTreeMap<usize, Vec<usize>>, BTreeMap<usize, Vec<usize>>) =
            Default::default();
        if !coarsest {
            let mut ghost = vec![false; n];
            let mut ranks = Vec::new();
            for p in (0..n).filter(|&p| owner[p] == rank) {
                ranks.clear();
                for (q, _) in a.neighbours(p) {
                    if owner[q] != rank {
                        ghost[q] = true;
                        ranks.push(owner[q]);
                    }
                }
                ranks.sort_unstable();
                ranks.dedup();
                for &r in &ranks {
                    send.entry(r).or_default().push(p);
                }
            }
            for q in (0..n).filter(|&q| ghost[q]) {
                recv.entry(owner[q]).or_default().push(q);
            }
        }
        let ghosts = NodePlan::new(send, recv, |_| D);
        Self {
            mask: vec![false; D * n],
            free: vec![1.0; D * n],
            ref_diag: vec![0.0; D * n],
            ghosts_some: ghosts.clone(),
            ghosts,
            a,
        }
    }

    /// Sends the owned nodes' masks to the ranks where they are ghosts, receives the
    /// ghosts' (all, or the incremental update's nodes). Collective.
    fn exchange_masks(
        &mut self,
        halo: &mut dyn RankGroup,
        full: bool,
        counters: &mut HaloCounters,
    ) {
        let plan = if full {
            &mut self.ghosts
        } else {
            &mut self.ghosts_some
        };
        let (free, mask) = (&mut self.free, &mut self.mask);
        plan.pack(|_| D, |p, out| out.copy_from_slice(&free[D * p..D * p + D]));
        plan.send(halo, counters);
        plan.unpack(
            |_| D,
            |p, v| {
                free[D * p..D * p + D].copy_from_slice(v);
                for c in 0..D {
                    mask[D * p + c] = v[c] == 0.0;
                }
            },
        );
    }
}

/// The number of values of node `p`'s record of the coarsest level: its `free` values,
/// diagonal block and off-diagonal blocks.
fn coarsest_record<const D: usize>(a: &BlockCsr<D>, p: usize) -> usize {
    D + D * D * (1 + a.lower.range(p).len() + a.upper.range(p).len())
}

/// Writes node `p`'s record (see [`coarsest_record`]) to the front of `out`; returns its
/// length.
fn write_record<const D: usize>(a: &BlockCsr<D>, free: &[f64], p: usize, out: &mut [f64]) -> usize {
    out[..D].copy_from_slice(&free[D * p..D * p + D]);
    let blocks = std::iter::once(&a.diag[p])
        .chain(&a.lower.val[a.lower.range(p)])
        .chain(&a.upper.val[a.upper.range(p)]);
    let mut at = D;
    for b in blocks {
        for r in 0..D {
            out[at..at + D].copy_from_slice(&b[r]);
            at += D;
        }
    }
    at
}

/// Reads node `p`'s record from the front of `values` into `a` and `free`; returns its
/// length.
fn read_record<const D: usize>(
    a: &mut BlockCsr<D>,
    free: &mut [f64],
    p: usize,
    values: &[f64],
) -> usize {
    free[D * p..D * p + D].copy_from_slice(&values[..D]);
    let (lr, ur) = (a.lower.range(p), a.upper.range(p));
    let (lower, upper) = (
        std::sync::Arc::make_mut(&mut a.lower),
        std::sync::Arc::make_mut(&mut a.upper),
    );
    let blocks = std::iter::once(&mut a.diag[p])
        .chain(&mut lower.val[lr])
        .chain(&mut upper.val[ur]);
    let mut at = D;
    for b in blocks {
        for r in 0..D {
            b[r].copy_from_slice(&values[at..at + D]);
            at += D;
        }
    }
    at
}

/// [`RankHierarchy`] with the transport its updates use: what
/// [`linearize_blocks`](crate::tnnmg::linearize_blocks) updates.
pub(crate) struct RankUpdate<'a, const D: usize> {
    h: &'a mut RankHierarchy<D>,
    halo: &'a mut dyn RankGroup,
    fine_rows: &'a LocalRows<D>,
}

impl<const D: usize> NewtonHierarchy<D> for RankUpdate<'_, D> {
    fn fine_diag_mut(&mut self) -> &mut [Block<D>] {
        &mut self.h.fine_diag
    }
    fn fine_mask_mut(&mut self) -> &mut [bool] {
        &mut self.h.fine_mask
    }
    fn update(&mut self) -> Result<()> {
        self.h.update(self.halo, self.fine_rows, true);
        Ok(())
    }
    fn update_incremental(&mut self) -> Result<()> {
        self.h.update(self.halo, self.fine_rows, false);
        Ok(())
    }
    fn set_variable_nodes(&mut self, fine_nodes: &[usize]) {
        self.h.set_variable(fine_nodes);
    }
}
