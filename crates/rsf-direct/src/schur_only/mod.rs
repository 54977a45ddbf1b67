//! The condensation without the whole factor: a multifrontal elimination of the interior
//! that keeps no factor column, only the dense Schur complement on a kept set and the
//! condensed right-hand sides (docs/three-d.md, "The condensation without the whole
//! factor"); [`SchurOnly`] describes the method and its sources.

mod checkpoint;
mod eliminate;
mod extras;
mod front;
mod options;
mod packed;
mod report;
mod resume;
#[cfg(test)]
mod tests;
mod tree;

use faer::sparse::SparseColMatRef;

use crate::condensation::split_dofs;
use crate::error::{Error, Result};
use crate::ordering::InteriorOrdering;
use crate::partial_cholesky::PartialCholesky;
use checkpoint::Checksum;
use packed::packed_len;
use rsf_linalg::Csc;
use rsf_nonsmooth::BlockedMatrix;
use rsf_nonsmooth::ProblemError;
use tree::{update_buffer, Tree};

pub use extras::{ExtraRows, InterfaceSchur};
pub use options::{CheckpointPolicy, SchurOnlyOptions};
pub use packed::PackedSymmetric;
pub use report::{Progress, SchurOnlyPlan, SchurOnlyReport};

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
    /// [`ProblemError::InvalidMatrix`] / [`ProblemError::DimensionMismatch`] /
    /// [`ProblemError::NonFinite`] for invalid shapes, pattern or entries;
    /// [`ProblemError::InvalidOption`] for blocks or extras out of range, not increasing, fixed, or
    /// extras inside a block; [`Error::FeatureDisabled`] for [`InteriorOrdering::NestedDissection`]
    /// without the feature `metis`; [`Error::Factorisation`] if the ordering fails.
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
            return Err(ProblemError::InvalidOption(
                "extra kept dofs must be strictly increasing".into(),
            )
            .into());
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
                return Err(ProblemError::InvalidOption(format!(
                    "extra kept dof {e} is {why}: extras are free dofs outside the blocks"
                ))
                .into());
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
}
