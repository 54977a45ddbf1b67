//! The condensation without the whole factor: a multifrontal elimination of the interior
//! that keeps no factor column, only the dense Schur complement on a kept set and the
//! condensed right-hand sides (docs/three-d.md, "The condensation without the whole
//! factor"); [`SchurOnly`] describes the method and its sources.

mod checkpoint;
mod extras;
mod front;
mod packed;
#[cfg(test)]
mod tests;
mod tree;

use std::ops::ControlFlow;
use std::path::PathBuf;
use std::time::Instant;

use faer::sparse::SparseColMatRef;

use crate::condensation::split_dofs;
use crate::error::{Error, Result};
use crate::ordering::InteriorOrdering;
use crate::partial_cholesky::PartialCholesky;
use checkpoint::{Checksum, Header};
use front::{Ordered, State, Workspace};
use packed::{packed_len, try_zeros};
use rsf_linalg::Csc;
use rsf_nonsmooth::BlockedMatrix;
use tree::{update_buffer, Tree};

pub use extras::{ExtraRows, InterfaceSchur};
pub use packed::PackedSymmetric;

/// A right-hand side to condense: `b` (length `n`; its fixed entries are not read) and
/// the values of the fixed dofs in `x_fixed` (length `n`; its free entries are not read).
/// Its condensed value is `g = b̃_K − A_KR A_RR⁻¹ b̃_R` with `b̃ = b − A_{·,fixed} x_fixed`
/// (as [`Condensation::condense`](crate::Condensation::condense)).
#[derive(Debug, Clone, Copy)]
pub struct RightHandSide<'a> {
    /// The load `b` (length `n`).
    pub b: &'a [f64],
    /// The fixed dofs' values (length `n`).
    pub x_fixed: &'a [f64],
}

/// When and where the elimination writes its state, to resume a set-up that was killed.
///
/// A checkpoint holds the position in the schedule, the pending contribution blocks, the
/// accumulated `S_KK` and the right-hand sides carried so far (about
/// [`SchurOnlyPlan::result_bytes`] plus the stack's current size): it is written to
/// `path.partial`, synced, and renamed over `path`. A call of
/// [`SchurOnly::eliminate`] with the same inputs (matrix pattern and values, fixed dofs,
/// blocks, extras, right-hand sides, ordering) and an existing `path` continues from it;
/// a checkpoint of other inputs is refused ([`Error::CheckpointMismatch`]) and left
/// alone.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckpointPolicy {
    /// The checkpoint file.
    pub path: PathBuf,
    /// Write after every this many fronts (`None`: not by count).
    pub every_fronts: Option<usize>,
    /// Write when this many seconds of wall time have passed since the last write or
    /// the start (`None`: not by time).
    pub every_seconds: Option<f64>,
    /// At the end, write the finished state (`true`: a later call with the same inputs
    /// reads the result instead of eliminating again) or remove the file (`false`).
    pub keep_result: bool,
}

impl CheckpointPolicy {
    /// Checkpoints at `path` every 10 minutes of wall time, the finished state kept.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        Self {
            path: path.into(),
            every_fronts: None,
            every_seconds: Some(600.0),
            keep_result: true,
        }
    }

    fn validate(&self) -> Result<()> {
        if self.every_fronts == Some(0) {
            return Err(Error::InvalidOption(
                "checkpoint every 0 fronts: give at least 1, or None".into(),
            ));
        }
        if let Some(s) = self.every_seconds {
            if !(s > 0.0 && s.is_finite()) {
                return Err(Error::InvalidOption(format!(
                    "checkpoint every {s} s: give a positive finite interval, or None"
                )));
            }
        }
        Ok(())
    }
}

/// Options of [`SchurOnly::eliminate`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SchurOnlyOptions {
    /// Refuse ([`Error::TooLarge`]) before allocating anything if the elimination would
    /// hold more than this many bytes ([`SchurOnlyPlan::total_bytes`]).
    pub max_bytes: Option<usize>,
    /// Checkpoints (none by default).
    pub checkpoint: Option<CheckpointPolicy>,
}

/// What the elimination will hold and do, from the symbolic analysis alone
/// ([`SchurOnly::plan`]). Bytes are 8 per f64.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SchurOnlyPlan {
    /// Fronts (supernodes with a pivot in the interior).
    pub fronts: usize,
    /// Dofs eliminated, `|R|`.
    pub eliminated: usize,
    /// Dofs kept, `|K| = |F| + |P|`.
    pub kept: usize,
    /// The largest front as it is stored: the lower triangle of its pivot columns and of
    /// its interior update columns (its kept rows' and columns' block goes straight into
    /// `S_KK`).
    pub largest_front_bytes: usize,
    /// The stack of pending contribution blocks and the front being eliminated on top of
    /// them, at its peak.
    pub peak_pending_bytes: usize,
    /// The buffers every front reuses (with at most [`largest_order`](Self::largest_order)
    /// right-hand sides): a dense panel of up to 256 pivot columns of a front and the
    /// products of its updates (up to `256 (w + p)` each).
    pub workspace_bytes: usize,
    /// The largest order `w + p` of a front (pivots and update rows).
    pub largest_order: usize,
    /// `S_KK` in packed rows, `4 |K| (|K| + 1)`.
    pub result_bytes: usize,
    /// Each right-hand side carried through the elimination: one vector of `|R| + |K|`.
    pub bytes_per_rhs: usize,
    /// Floating-point operations without right-hand sides.
    pub flops: f64,
    /// Floating-point operations per right-hand side.
    pub flops_per_rhs: f64,
}

impl SchurOnlyPlan {
    /// Everything the elimination holds at its peak with `nrhs` right-hand sides, besides
    /// the [`SchurOnly`] itself (its copy of the matrix and the symbolic tree): result,
    /// workspace, pending blocks, the carried right-hand sides and their condensed
    /// copies, and the index map.
    pub fn total_bytes(&self, nrhs: usize) -> u128 {
        let n = (self.eliminated + self.kept) as u128;
        let more_rhs =
            update_buffer(self.largest_order, nrhs) - update_buffer(self.largest_order, 0);
        self.result_bytes as u128
            + self.workspace_bytes as u128
            + 8 * more_rhs as u128
            + self.peak_pending_bytes as u128
            + nrhs as u128 * (self.bytes_per_rhs as u128 + 8 * self.kept as u128)
            + 4 * n
    }
}

/// A progress report of a running elimination, given to the monitor of
/// [`SchurOnly::eliminate_with`] after every front.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Fronts done (of the schedule).
    pub fronts_done: usize,
    /// Fronts in all.
    pub fronts: usize,
    /// Floating-point operations done (before a resume included).
    pub flops_done: f64,
    /// Floating-point operations in all (the plan's count).
    pub flops: f64,
    /// Wall time of this call (s).
    pub seconds: f64,
    /// Checkpoints written (before a resume included).
    pub checkpoints_written: usize,
}

/// What an elimination held and did. Bytes are 8 per f64.
#[derive(Debug, Clone, PartialEq)]
pub struct SchurOnlyReport {
    /// Fronts eliminated (all of them, before a resume included).
    pub fronts: usize,
    /// The largest front met (as [`SchurOnlyPlan::largest_front_bytes`]).
    pub largest_front_bytes: usize,
    /// The stack of pending contribution blocks with the front on top, at its peak.
    pub peak_pending_bytes: usize,
    /// `S_KK` (packed rows) and the condensed right-hand sides.
    pub result_bytes: usize,
    /// Floating-point operations (counted as [`SchurOnlyPlan::flops`]).
    pub flops: f64,
    /// Wall time of this call (s).
    pub seconds: f64,
    /// Wall time of the elimination over all calls that worked on it (s).
    pub seconds_total: f64,
    /// The front this call resumed at from a checkpoint (`None`: started afresh).
    pub resumed_at: Option<usize>,
    /// Checkpoints written (before a resume included).
    pub checkpoints_written: usize,
    /// Wall time this call spent writing checkpoints (s).
    pub checkpoint_seconds: f64,
}

/// The Schur complement `S_KK` on the kept set and the condensed right-hand sides, from
/// [`SchurOnly::eliminate`].
#[derive(Clone)]
pub struct KeptSchur {
    s: PackedSymmetric,
    g: Vec<Vec<f64>>,
    kept: Vec<usize>,
    nf: usize,
    report: SchurOnlyReport,
}

impl std::fmt::Debug for KeptSchur {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("KeptSchur")
            .field("dim", &self.kept.len())
            .field("interface_len", &self.nf)
            .field("rhs", &self.g.len())
            .field("report", &self.report)
            .finish_non_exhaustive()
    }
}

impl KeptSchur {
    /// `|K|`.
    pub fn dim(&self) -> usize {
        self.kept.len()
    }

    /// The kept dofs in the order of `S_KK`'s rows: the free components of the blocks
    /// (block by block, components in order: [`Condensation::interface_dofs`]'s order),
    /// then the extras.
    ///
    /// [`Condensation::interface_dofs`]: crate::Condensation::interface_dofs
    pub fn kept_dofs(&self) -> &[usize] {
        &self.kept
    }

    /// `|F|`: the first `|F|` kept dofs are the blocks' free components.
    pub fn interface_len(&self) -> usize {
        self.nf
    }

    /// `S_KK = A_KK − A_KR A_RR⁻¹ A_RK` (`|K| × |K|`, packed rows).
    pub fn schur(&self) -> &PackedSymmetric {
        &self.s
    }

    /// The condensed right-hand sides `g_K` (one of length `|K|` per
    /// [`RightHandSide`], in the order given).
    pub fn condensed_rhs(&self) -> &[Vec<f64>] {
        &self.g
    }

    /// What the elimination held and did.
    pub fn report(&self) -> &SchurOnlyReport {
        &self.report
    }
}

/// The elimination of the interior of `A` (`n × n`, symmetric, positive definite on its
/// free dofs) onto a kept set, analysed and ready to run: the ordering, the symbolic
/// factorisation and the schedule of fronts.
///
/// [`Condensation`](crate::Condensation) holds the whole sparse Cholesky factor of `A`
/// (`O(n^{4/3})` entries for a 3-D volume with nested dissection), which it needs for
/// its forward and backward sweeps. A quasi-dynamic fault needs only `S` and a few
/// condensed right-hand sides, and the factor is then the set-up's memory wall. The
/// multifrontal method (Duff & Reid 1983, "The multifrontal solution of indefinite sparse
/// symmetric linear equations", ACM TOMS 9; Liu 1992, "The multifrontal method for sparse
/// matrix solution: theory and practice", SIAM Review 34) computes the same elimination
/// front by front: each supernode's columns of the matrix and its children's
/// contribution blocks are assembled into a dense front, its pivots are factored, and the
/// update of the rows below is passed to the parent. Nothing needs a factor column once
/// its front is done, so none is kept: what the elimination holds at once is the kept
/// block `S_KK`, the largest front, and the stack of contribution blocks waiting for
/// their parents. This is what MUMPS computes when asked for a Schur complement
/// (`ICNTL(19)`), with the factor columns dropped instead of stored.
///
/// - The ordering and the supernodes are [`Condensation`](crate::Condensation)'s (the
///   same [`InteriorOrdering`], the same symbolic analysis by faer), with the kept set
///   `K = F ∪ P` last: `F` the free components of the blocks, `P` optional extra free
///   dofs (e.g. the dofs observers read). A supernode that straddles the interior's end
///   is split there.
/// - A front is stored on top of the stack (above its children's blocks) as the packed
///   lower triangle of its pivot and interior update columns; its pivots are factored 256
///   at a time (right-looking), each panel forgotten once its update of the rest of the
///   front is applied. The part of an update whose rows and columns are both in `K` is
///   added straight into `S_KK` (never stored in a front, never travelling); what remains
///   of the front, its contribution block, moves down over the children's blocks.
/// - The fronts are processed in a postorder whose children come in decreasing order of
///   (subtree peak − contribution block), which minimises the stack's peak for the tree
///   (Liu 1986, "On the storage requirement in the out-of-core multifrontal method for
///   sparse factorization", ACM TOMS 12); [`SchurOnly::plan`] gives that peak before any
///   numeric work.
/// - Right-hand sides ride along (forward substitution interleaved), so their condensed
///   values `g_K = b̃_K − A_KR A_RR⁻¹ b̃_R` come out with `S_KK`.
/// - A post-step ([`KeptSchur::onto_interface`]) eliminates `P` again densely, giving the
///   Schur complement on `F` alone and the rows of the extension at `P`.
///
/// Every dense kernel is faer's with `Par::Seq` and every sum has a fixed order: the
/// results are the same bits whatever the thread count, and a set-up killed and resumed
/// from a checkpoint ([`CheckpointPolicy`]) gives the bits of an uninterrupted one (on the
/// same machine and build: faer picks its SIMD kernels at run time).
///
/// Measured against the full factor on 3-D elasticity boxes: docs/three-d.md, "The
/// condensation without the whole factor".
///
/// ```
/// use faer::sparse::{SparseColMat, Triplet};
/// use rsf_direct::{Condensation, RightHandSide, SchurOnly, SchurOnlyOptions, InteriorOrdering};
///
/// // 1-D Laplacian, ends fixed at 1 and 2, condensed onto node 3 (block size 1).
/// let n = 7;
/// let mut t = Vec::new();
/// for i in 0..n {
///     t.push(Triplet::new(i, i, 2.0));
///     if i + 1 < n {
///         t.push(Triplet::new(i, i + 1, -1.0));
///         t.push(Triplet::new(i + 1, i, -1.0));
///     }
/// }
/// let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
/// let mut fixed = vec![false; n];
/// (fixed[0], fixed[n - 1]) = (true, true);
/// let b = vec![0.5; n];
/// let mut x = vec![0.0; n];
/// (x[0], x[n - 1]) = (1.0, 2.0);
/// let elim = SchurOnly::<1>::new(a.as_ref(), &fixed, &[3], &[], InteriorOrdering::Amd).unwrap();
/// let rhs = [RightHandSide { b: &b, x_fixed: &x }];
/// let kept = elim.eliminate(&rhs, &SchurOnlyOptions::default()).unwrap();
/// // The same as the condensation that keeps the whole factor.
/// let mut cond = Condensation::<1>::new(a.as_ref(), &fixed, &[3]).unwrap();
/// let mut g = vec![0.0; 1];
/// cond.condense(&b, &x, &mut g).unwrap();
/// assert!((kept.schur().entry(0, 0) - cond.schur_complement()[0]).abs() < 1e-14);
/// assert!((kept.condensed_rhs()[0][0] - g[0]).abs() < 1e-14);
/// ```
pub struct SchurOnly<const D: usize> {
    a: Csc,
    fixed: Vec<bool>,
    blocks: Vec<usize>,
    extras: Vec<usize>,
    ordering: InteriorOrdering,
    /// Kept dofs: `F` then `P`.
    kept: Vec<usize>,
    nf: usize,
    order: Vec<usize>,
    pos: Vec<usize>,
    tree: Tree,
    layout_sum: [u64; 2],
}

impl<const D: usize> std::fmt::Debug for SchurOnly<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SchurOnly")
            .field("n", &self.a.nrows)
            .field("kept", &self.kept.len())
            .field("interface", &self.nf)
            .field("ordering", &self.ordering)
            .field("fronts", &self.tree.fronts.len())
            .finish_non_exhaustive()
    }
}

impl<const D: usize> SchurOnly<D> {
    /// The elimination of `a` (`n × n`, symmetric, both triangles stored, positive
    /// definite on the free dofs; `n` a multiple of `D`) with fixed dofs `fixed` (length
    /// `n`) onto the free components of `blocks` (node indices, strictly increasing) and
    /// the free dofs `extras` (strictly increasing, outside the blocks), the interior
    /// ordered by `ordering`. Does the ordering and the symbolic analysis (no numeric
    /// work); [`plan`](Self::plan) says what [`eliminate`](Self::eliminate) will hold.
    ///
    /// # Errors
    /// [`Error::InvalidMatrix`] / [`Error::DimensionMismatch`] / [`Error::NonFinite`] for
    /// invalid shapes, pattern or entries; [`Error::InvalidOption`] for blocks or extras
    /// out of range, not increasing, fixed, or extras inside a block;
    /// [`Error::FeatureDisabled`] for [`InteriorOrdering::NestedDissection`] without the
    /// feature `metis`; [`Error::Factorisation`] if the ordering fails.
    pub fn new(
        a: SparseColMatRef<'_, usize, f64>,
        fixed: &[bool],
        blocks: &[usize],
        extras: &[usize],
        ordering: InteriorOrdering,
    ) -> Result<Self> {
        let BlockedMatrix { a, fixed } = BlockedMatrix::<D>::new(Csc::from_faer(a)?, fixed)?;
        let n_all = a.nrows;
        let (mut interior, mut kept) = split_dofs::<D>(n_all, &fixed, blocks)?;
        let nf = kept.len();
        if extras.windows(2).any(|w| w[0] >= w[1]) {
            return Err(Error::InvalidOption(
                "extra kept dofs must be strictly increasing".into(),
            ));
        }
        let mut in_block = vec![false; n_all];
        for &p in blocks {
            in_block[D * p..D * p + D].fill(true);
        }
        for &e in extras {
            let why = if e >= n_all {
                Some("out of range")
            } else if fixed[e] {
                Some("fixed")
            } else if in_block[e] {
                Some("a component of a block")
            } else {
                None
            };
            if let Some(why) = why {
                return Err(Error::InvalidOption(format!(
                    "extra kept dof {e} is {why}: extras are free dofs outside the blocks"
                )));
            }
        }
        if !extras.is_empty() {
            let mut is_extra = vec![false; n_all];
            for &e in extras {
                is_extra[e] = true;
            }
            interior.retain(|&i| !is_extra[i]);
            kept.extend_from_slice(extras);
        }
        let mut layout = PartialCholesky::symbolic_layout(&a, &interior, &kept, (ordering, D))?;
        let nr = interior.len();
        drop(interior);
        let tree = Tree::new(&layout, nr)?;
        let order = std::mem::take(&mut layout.order);
        drop(layout);
        let mut pos = vec![usize::MAX; n_all];
        for (k, &i) in order.iter().enumerate() {
            pos[i] = k;
        }
        let mut sum = Checksum::new("rsf-direct schur-only layout v1");
        sum.usizes(&order);
        for (t, f) in tree.fronts.iter().enumerate() {
            sum.words([f.c0 as u64, f.w as u64, f.r as u64]);
            sum.words(tree.rows_of(t).iter().map(|&g| g as u64));
            sum.words(tree.children_of(t).iter().map(|&c| c as u64));
        }
        Ok(Self {
            a,
            fixed,
            blocks: blocks.to_vec(),
            extras: extras.to_vec(),
            ordering,
            kept,
            nf,
            order,
            pos,
            tree,
            layout_sum: sum.finish(),
        })
    }

    /// `|K|`, the dimension of `S_KK`.
    pub fn dim(&self) -> usize {
        self.kept.len()
    }

    /// The kept dofs in the order of `S_KK` ([`KeptSchur::kept_dofs`]).
    pub fn kept_dofs(&self) -> &[usize] {
        &self.kept
    }

    /// The blocks' free components `F` (the first [`KeptSchur::interface_len`] kept dofs).
    pub fn interface_dofs(&self) -> &[usize] {
        &self.kept[..self.nf]
    }

    /// The extra kept dofs `P`.
    pub fn extra_dofs(&self) -> &[usize] {
        &self.extras
    }

    /// What [`eliminate`](Self::eliminate) will hold and do.
    pub fn plan(&self) -> SchurOnlyPlan {
        let t = &self.tree;
        SchurOnlyPlan {
            fronts: t.fronts.len(),
            eliminated: t.nr,
            kept: t.nk,
            largest_front_bytes: 8 * t.max_front,
            peak_pending_bytes: 8 * t.peak_stack,
            workspace_bytes: 8 * (t.max_panel + update_buffer(t.max_order, 0)),
            largest_order: t.max_order,
            result_bytes: 8 * packed_len(t.nk).unwrap_or(usize::MAX / 8),
            bytes_per_rhs: 8 * (t.nr + t.nk),
            flops: t.flops,
            flops_per_rhs: t.flops_per_rhs,
        }
    }

    /// [`eliminate_with`](Self::eliminate_with) without a monitor.
    ///
    /// # Errors
    /// As [`eliminate_with`](Self::eliminate_with) (never [`Error::Stopped`]).
    pub fn eliminate(
        &self,
        rhs: &[RightHandSide<'_>],
        options: &SchurOnlyOptions,
    ) -> Result<KeptSchur> {
        self.eliminate_with(rhs, options, &mut |_| ControlFlow::Continue(()))
    }

    /// Eliminates the interior: `S_KK` and the condensed right-hand sides `g_K` of `rhs`,
    /// front by front, keeping no factor column. `monitor` sees the [`Progress`] after
    /// every front (and after the checkpoint written there, if any); returning
    /// `ControlFlow::Break(())` stops the elimination at once, as a kill would: nothing
    /// more is written, and a later call resumes from the last checkpoint.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for a right-hand side of another length;
    /// [`Error::NonFinite`] for a non-finite value read from one, or a non-finite result;
    /// [`Error::InvalidOption`] for an invalid [`CheckpointPolicy`];
    /// [`Error::TooLarge`] if [`SchurOnlyPlan::total_bytes`] exceeds
    /// [`SchurOnlyOptions::max_bytes`] (before any allocation); [`Error::OutOfMemory`] if a
    /// large buffer cannot be allocated; [`Error::NonPositivePivot`] at the first dof whose
    /// pivot is not positive (`A` not positive definite on the interior);
    /// [`Error::Checkpoint`] for a checkpoint that cannot be written or read, or is
    /// damaged; [`Error::CheckpointMismatch`] for a checkpoint of other inputs;
    /// [`Error::Stopped`] if `monitor` stopped it.
    pub fn eliminate_with(
        &self,
        rhs: &[RightHandSide<'_>],
        options: &SchurOnlyOptions,
        monitor: &mut dyn FnMut(&Progress) -> ControlFlow<()>,
    ) -> Result<KeptSchur> {
        let clock = Instant::now();
        let n_all = self.a.nrows;
        for r in rhs {
            for (what, v) in [("right-hand side", r.b), ("fixed values", r.x_fixed)] {
                if v.len() != n_all {
                    return Err(Error::DimensionMismatch {
                        what,
                        expected: n_all,
                        got: v.len(),
                    });
                }
            }
            if (0..n_all).any(|i| {
                let v = if self.fixed[i] { r.x_fixed[i] } else { r.b[i] };
                !v.is_finite()
            }) {
                return Err(Error::NonFinite("right-hand side or fixed values"));
            }
        }
        if let Some(cp) = &options.checkpoint {
            cp.validate()?;
        }
        let plan = self.plan();
        let need = plan.total_bytes(rhs.len());
        let limit = options.max_bytes.unwrap_or(usize::MAX);
        if need > limit as u128 || packed_len(self.tree.nk).is_none() {
            return Err(Error::TooLarge {
                what: "the Schur-only elimination",
                bytes: need,
                limit,
            });
        }
        let mut log = Log::new(
            clock,
            options
                .checkpoint
                .as_ref()
                .map(|cp| (cp, self.input_sum(rhs))),
        );
        let resumed = match log.policy {
            Some((cp, inputs)) => checkpoint::open(&cp.path)?
                .map(|reader| {
                    let h = reader.header;
                    log.resumed(h.done, h.written, h.seconds);
                    self.resume(reader, inputs, rhs.len(), &cp.path)
                })
                .transpose()?,
            None => None,
        };
        let resumed_at = resumed.as_ref().map(|st| st.done);
        let mut st = match resumed {
            Some(st) => st,
            None => self.fresh(rhs)?,
        };
        let mut ws = Workspace::new(&self.tree, rhs.len())?;
        let ordered = Ordered {
            a: &self.a,
            pos: &self.pos,
            order: &self.order,
        };
        let total = self.tree.fronts.len();
        let flops_all = plan.flops + rhs.len() as f64 * plan.flops_per_rhs;
        while st.done < total {
            front::eliminate(st.done, &self.tree, &ordered, &mut st, &mut ws)?;
            st.done += 1;
            if st.done < total && log.due(st.done) {
                log.write(self, &st)?;
            }
            let progress = Progress {
                fronts_done: st.done,
                fronts: total,
                flops_done: st.flops,
                flops: flops_all,
                seconds: log.clock.elapsed().as_secs_f64(),
                checkpoints_written: log.written,
            };
            if monitor(&progress).is_break() {
                return Err(Error::Stopped {
                    done: st.done,
                    total,
                });
            }
        }
        log.finish(self, &st)?;
        drop(ws);
        let (nr, nk) = (self.tree.nr, self.tree.nk);
        let n = nr + nk;
        let g: Vec<Vec<f64>> = (0..rhs.len())
            .map(|k| st.y[k * n + nr..(k + 1) * n].to_vec())
            .collect();
        drop(std::mem::take(&mut st.y));
        if !st.s.iter().all(|v| v.is_finite()) || !g.iter().flatten().all(|v| v.is_finite()) {
            return Err(Error::NonFinite("the Schur complement on the kept set"));
        }
        let seconds = log.clock.elapsed().as_secs_f64();
        let report = SchurOnlyReport {
            fronts: st.done,
            largest_front_bytes: 8 * st.largest_front,
            peak_pending_bytes: 8 * st.peak_stack,
            result_bytes: 8 * (st.s.len() + nk * rhs.len()),
            flops: st.flops,
            seconds,
            seconds_total: log.seconds_before + seconds,
            resumed_at,
            checkpoints_written: log.written,
            checkpoint_seconds: log.seconds,
        };
        Ok(KeptSchur {
            s: PackedSymmetric::from_rows(nk, std::mem::take(&mut st.s)),
            g,
            kept: self.kept.clone(),
            nf: self.nf,
            report,
        })
    }

    /// An empty stack with room for its planned peak (it never grows after).
    fn empty_stack(&self) -> Result<Vec<f64>> {
        let mut stack = Vec::new();
        stack
            .try_reserve_exact(self.tree.peak_stack)
            .map_err(|_| Error::OutOfMemory {
                what: "the stack of contribution blocks",
                bytes: 8 * self.tree.peak_stack,
            })?;
        Ok(stack)
    }

    /// The state before the first front: `S_KK = A_KK`, the right-hand sides `b̃` in
    /// elimination order, an empty stack with room for its peak.
    fn fresh(&self, rhs: &[RightHandSide<'_>]) -> Result<State> {
        let (nr, nk) = (self.tree.nr, self.tree.nk);
        let n = nr + nk;
        let stack = self.empty_stack()?;
        let mut s = PackedSymmetric::zeros(nk)?.into_packed_rows();
        for c in nr..n {
            let (rows, vals) = self.a.col(self.order[c]);
            let kj = c - nr;
            for (&i, &v) in rows.iter().zip(vals) {
                let pi = self.pos[i];
                if pi != usize::MAX && pi >= c {
                    let ki = pi - nr;
                    s[ki * (ki + 1) / 2 + kj] += v;
                }
            }
        }
        let mut y = try_zeros(n * rhs.len(), "the carried right-hand sides")?;
        for (k, r) in rhs.iter().enumerate() {
            let y = &mut y[k * n..(k + 1) * n];
            for (yc, &i) in y.iter_mut().zip(&self.order) {
                *yc = r.b[i];
            }
            // b̃ = b − A_{·,fixed} x_fixed, column by column as the condensation does.
            for j in (0..self.a.nrows).filter(|&j| self.fixed[j]) {
                let xj = r.x_fixed[j];
                if xj != 0.0 {
                    let (rows, vals) = self.a.col(j);
                    for (&i, &v) in rows.iter().zip(vals) {
                        if self.pos[i] != usize::MAX {
                            y[self.pos[i]] -= v * xj;
                        }
                    }
                }
            }
        }
        Ok(State {
            done: 0,
            stack,
            s,
            y,
            largest_front: 0,
            peak_stack: 0,
            flops: 0.0,
        })
    }

    /// Checksum of everything the result depends on: the matrix (pattern and values after
    /// sorting and summing duplicates), the fixed dofs, the blocks and extras, the
    /// ordering, and the values read from each right-hand side.
    fn input_sum(&self, rhs: &[RightHandSide<'_>]) -> [u64; 2] {
        let mut sum = Checksum::new("rsf-direct schur-only inputs v1");
        sum.words([D as u64, self.a.nrows as u64]);
        sum.bytes(self.ordering.to_string().as_bytes());
        sum.usizes(&self.a.col_ptr);
        sum.usizes(&self.a.row_idx);
        sum.f64s(&self.a.val);
        sum.words(self.fixed.iter().map(|&f| f as u64));
        sum.usizes(&self.blocks);
        sum.usizes(&self.extras);
        sum.word(rhs.len() as u64);
        for r in rhs {
            sum.words((0..self.a.nrows).map(|i| {
                if self.fixed[i] {
                    r.x_fixed[i].to_bits()
                } else {
                    r.b[i].to_bits()
                }
            }));
        }
        sum.finish()
    }

    /// The state of an opened checkpoint, if it is of these inputs and consistent.
    fn resume(
        &self,
        reader: checkpoint::Reader,
        inputs: [u64; 2],
        nrhs: usize,
        path: &std::path::Path,
    ) -> Result<State> {
        let h = reader.header;
        let mismatch = |reason: &str| Error::CheckpointMismatch {
            path: path.display().to_string(),
            reason: reason.into(),
        };
        if h.inputs != inputs {
            return Err(mismatch(
                "the matrix, the fixed dofs, the blocks, the extras, the right-hand sides or \
                 the ordering differ",
            ));
        }
        if h.layout != self.layout_sum {
            return Err(mismatch(
                "the same inputs with another elimination order or schedule (another build \
                 of faer or METIS?)",
            ));
        }
        let n = self.tree.nr + self.tree.nk;
        if h.done > self.tree.fronts.len()
            || Some(h.s_len) != packed_len(self.tree.nk)
            || h.y_len != n * nrhs
            || h.stack_len != self.tree.stack_after(h.done)
        {
            return Err(Error::Checkpoint {
                path: path.display().to_string(),
                reason: "damaged: its sizes do not match its problem".into(),
            });
        }
        let mut stack = self.empty_stack()?;
        stack.resize(h.stack_len, 0.0);
        let mut s = try_zeros(h.s_len, "the packed Schur complement")?;
        let mut y = try_zeros(h.y_len, "the carried right-hand sides")?;
        reader.read_arrays([&mut stack, &mut s, &mut y])?;
        Ok(State {
            done: h.done,
            stack,
            s,
            y,
            largest_front: h.largest_front,
            peak_stack: h.peak_stack,
            flops: h.flops,
        })
    }
}

/// The checkpoints of one call: the policy and the inputs' checksum (none without a
/// policy), how many were written (with those of the calls before it), when, and the time
/// they took.
struct Log<'p> {
    policy: Option<(&'p CheckpointPolicy, [u64; 2])>,
    /// The call's start.
    clock: Instant,
    /// The last write (or the start).
    last: Instant,
    /// The position of the last checkpoint written or resumed from.
    at: Option<usize>,
    written: usize,
    /// Wall time of the calls before a resume, and this call's time writing.
    seconds_before: f64,
    seconds: f64,
}

impl<'p> Log<'p> {
    fn new(clock: Instant, policy: Option<(&'p CheckpointPolicy, [u64; 2])>) -> Self {
        Self {
            policy,
            clock,
            last: clock,
            at: None,
            written: 0,
            seconds_before: 0.0,
            seconds: 0.0,
        }
    }

    /// A resume from a checkpoint at `done` fronts, the `written`-th, after `seconds` of
    /// earlier calls.
    fn resumed(&mut self, done: usize, written: usize, seconds: f64) {
        (self.at, self.written, self.seconds_before) = (Some(done), written, seconds);
    }

    /// Whether the policy asks for a checkpoint after `done` fronts.
    fn due(&self, done: usize) -> bool {
        self.policy.is_some_and(|(cp, _)| {
            cp.every_fronts.is_some_and(|k| done % k == 0)
                || cp
                    .every_seconds
                    .is_some_and(|s| self.last.elapsed().as_secs_f64() >= s)
        })
    }

    /// Writes the state `st` of `elim`'s elimination.
    fn write<const D: usize>(&mut self, elim: &SchurOnly<D>, st: &State) -> Result<()> {
        let Some((cp, inputs)) = self.policy else {
            return Ok(());
        };
        let t = Instant::now();
        self.written += 1;
        let header = Header {
            inputs,
            layout: elim.layout_sum,
            done: st.done,
            stack_len: st.stack.len(),
            s_len: st.s.len(),
            y_len: st.y.len(),
            largest_front: st.largest_front,
            peak_stack: st.peak_stack,
            flops: st.flops,
            seconds: self.seconds_before + self.clock.elapsed().as_secs_f64(),
            written: self.written,
        };
        checkpoint::write(&cp.path, &header, [&st.stack, &st.s, &st.y])?;
        self.seconds += t.elapsed().as_secs_f64();
        self.last = Instant::now();
        self.at = Some(st.done);
        Ok(())
    }

    /// At the end: the finished state kept (unless it is the file already) or the file
    /// removed, as the policy says.
    fn finish<const D: usize>(&mut self, elim: &SchurOnly<D>, st: &State) -> Result<()> {
        let Some((cp, _)) = self.policy else {
            return Ok(());
        };
        if cp.keep_result {
            if self.at != Some(st.done) {
                self.write(elim, st)?;
            }
            return Ok(());
        }
        match std::fs::remove_file(&cp.path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(Error::Checkpoint {
                path: cp.path.display().to_string(),
                reason: e.to_string(),
            }),
            _ => Ok(()),
        }
    }
}
