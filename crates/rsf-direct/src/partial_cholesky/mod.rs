//! A sparse Cholesky factor ordered "interior first, interface last", with the partial
//! triangular solves that condensation onto the interface needs (docs/math.md §8).
//!
//! With the free dofs ordered `[R, F]` (`R` the interior, `F` the interface),
//!
//! ```text
//! A = [A_RR A_RF; A_FR A_FF] = L Lᵀ,   L = [L_R 0; B L_F],
//! ```
//!
//! so that `L_F L_Fᵀ = S = A_FF − A_FR A_RR⁻¹ A_RF` (the Schur complement) and
//! `B = A_FR L_R⁻ᵀ`. A forward sweep over the `R` columns turns `[b_R; b_F]` into
//! `[L_R⁻¹ b_R; b_F − B L_R⁻¹ b_R]`, whose `F` part is the condensed right-hand side; after
//! the interface values `x_F` are written into the `F` part, a backward sweep over the `R`
//! columns gives `x_R = A_RR⁻¹ (b_R − A_RF x_F)`. One forward and one backward sweep per
//! time step, whatever happens on the interface in between.
//!
//! **Two halves.** The interior is split by a separator `C` of the graph of `A_RR` (a
//! level of a breadth-first search from a pseudo-peripheral dof) into two parts `R₁`, `R₂`
//! without coupling; the order is `[R₁, R₂, C, F]`, each part in AMD order (one level of
//! nested dissection). Columns of `R₁` and `R₂` touch only their own rows and the rows of
//! `C ∪ F`, so the two halves of each sweep are independent: they run on two threads
//! (rayon) when the factor's [`Parallelism`] allows. Their contributions to the shared rows go through one buffer
//! per half, added in a fixed order, and the arithmetic does not depend on the number of
//! threads: results are bit-identical with one thread or two.
//!
//! The factorisation is faer's, supernodal and sequential; the sweeps run over its
//! supernodes (dense blocks), with `u32` row indices.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Par, Side};

use rsf_linalg::Parallelism;

use crate::error::{Error, Result};
use crate::ordering::{nested_dissection, InteriorOrdering};
use rsf_linalg::Csc;

mod interior_order;
mod supernodes;
#[cfg(test)]
pub(super) mod tests;

use interior_order::{amd_order, bisect, faer_err};
use rsf_nonsmooth::ProblemError;
use supernodes::{SplitRows, Supernodes};

/// `L` of `P A Pᵀ = L Lᵀ` for the ordering `[R₁, R₂, C, F]` (module docs).
#[derive(Debug)]
pub(super) struct PartialCholesky {
    /// Number of interior columns `|R|`.
    pub(super) nr: usize,
    /// Total dimension `|R| + |F|`.
    pub(super) n: usize,
    /// `R₁ = 0..p1`, `R₂ = p1..p2`, `C = p2..nr`.
    p1: usize,
    p2: usize,
    l: Supernodes,
    /// Shared-row buffers (rows `p2..n`) and scratch of the two halves.
    bufs: [Vec<f64>; 2],
    tmps: [Vec<f64>; 2],
    /// Whether the interior is large enough for two threads
    /// (`nr ≥` [`INTERIOR_PARALLEL_MIN`]).
    large: bool,
    /// The parallelism of the sweeps of a large interior.
    par: Parallelism,
    /// The ordering and symbolic factorisation, shared with every refactorisation.
    analysis: Arc<Analysis>,
}

/// The elimination order and supernodal layout of a partial Cholesky factor, without
/// values ([`PartialCholesky::symbolic_layout`]): supernode `s` covers the columns
/// `start[s]..start[s + 1]` of the order, and the rows of its columns below its diagonal
/// block are `rows[row_ptr[s]..row_ptr[s + 1]]` (increasing, elimination positions).
#[derive(Debug)]
pub(super) struct SymbolicLayout {
    /// Elimination order (`order[k]` = the row of `a` of column `k`).
    pub(super) order: Vec<usize>,
    /// First column of each supernode, and the total dimension last.
    pub(super) start: Vec<usize>,
    /// Start of each supernode's rows in `rows`.
    pub(super) row_ptr: Vec<usize>,
    /// The rows below the diagonal blocks.
    pub(super) rows: Vec<u32>,
}

/// What a factorisation of a matrix with a given pattern reuses for another matrix with
/// the same pattern ([`PartialCholesky::refactor`]): the ordering, the submatrix pattern
/// and faer's symbolic (supernodal) factorisation.
struct Analysis {
    /// The pattern of `a` that was analysed (to check a refactorisation against).
    a_col_ptr: Vec<usize>,
    a_row_idx: Vec<usize>,
    /// Positions in `a`'s values of the submatrix entries, in the order of `pattern`.
    gather: Vec<usize>,
    /// Pattern of the submatrix on `interior ∪ interface` (rows and columns sorted).
    pattern: SymbolicSparseColMat<usize>,
    symbolic: SymbolicCholesky<usize>,
    /// Elimination order (`order[k]` = the row of `a` of column `k` of `L`).
    order: Vec<usize>,
}

impl std::fmt::Debug for Analysis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Analysis")
            .field("n", &self.pattern.ncols())
            .field("nnz", &self.gather.len())
            .finish_non_exhaustive()
    }
}

/// Smallest interior swept on two threads (if the factor's [`Parallelism`] allows). Below it, waking a second thread costs more
/// than it saves: main job, quiet machine, paired runs, two threads against one: j = 4
/// (2.7 k interior unknowns) 1.025× the wall time, j = 5 (10.6 k) 0.85×.
pub const INTERIOR_PARALLEL_MIN: usize = 5000;

impl PartialCholesky {
    /// [`with_ordering`](Self::with_ordering) with [`InteriorOrdering::Amd`].
    #[cfg(test)]
    pub(super) fn new(
        a: &Csc,
        interior: &[usize],
        interface: &[usize],
    ) -> Result<(Self, Vec<usize>)> {
        Self::with_ordering(a, interior, interface, (InteriorOrdering::Amd, 1))
    }

    /// Factorises the principal submatrix of `a` (symmetric, both triangles stored) on the
    /// rows/columns `interior ∪ interface`, eliminating `interior` first (two halves and a
    /// separator, in the fill-reducing order `ordering.0`; nested dissection orders the
    /// graph of nodes of `ordering.1` dofs) and `interface` last (in the given order).
    /// Returns the factor and the elimination order (`order[k]` = the row of `a` of column
    /// `k` of `L`).
    ///
    /// # Errors
    /// [`ProblemError::NotPositiveDefinite`] if the submatrix is not numerically SPD;
    /// [`Error::Factorisation`] if faer or METIS fails (e.g. out of memory) or the factor
    /// has more than `u32::MAX` rows; [`Error::FeatureDisabled`] for nested dissection
    /// without the feature `metis`.
    pub(super) fn with_ordering(
        a: &Csc,
        interior: &[usize],
        interface: &[usize],
        ordering: (InteriorOrdering, usize),
    ) -> Result<(Self, Vec<usize>)> {
        let (analysis, layout, p1, p2) = Self::analyse(a, interior, interface, ordering, true)?;
        let factor = Self::numeric(a, Arc::new(analysis), layout, interior.len(), p1, p2)?;
        let order = factor.analysis.order.clone();
        Ok((factor, order))
    }

    /// Stored entries of the factor [`with_ordering`](Self::with_ordering) would compute
    /// with AMD for these arguments, by the ordering and symbolic factorisation alone (no
    /// numeric work; the memory of the numeric factor is 8 bytes per entry).
    ///
    /// # Errors
    /// As [`new`](Self::new) without the numeric failures.
    pub(super) fn planned_nnz(a: &Csc, interior: &[usize], interface: &[usize]) -> Result<usize> {
        let (analysis, ..) =
            Self::analyse(a, interior, interface, (InteriorOrdering::Amd, 1), false)?;
        Ok(analysis.symbolic.len_val())
    }

    /// The ordering (two halves, a separator, the interface last; the interior by
    /// `ordering`) and faer's symbolic factorisation of the submatrix of `a` on
    /// `interior ∪ interface`, with the layout of the supernodes and the ends `p1`, `p2`
    /// of the two halves in the order. With `numeric` false, what only a numeric
    /// factorisation reads (the positions of the submatrix's values in `a`, the copy of
    /// `a`'s pattern a refactorisation is checked against) is left empty.
    fn analyse(
        a: &Csc,
        interior: &[usize],
        interface: &[usize],
        (ordering, node): (InteriorOrdering, usize),
        numeric: bool,
    ) -> Result<(Analysis, Supernodes, usize, usize)> {
        let (mut order, p1, p2) = match ordering {
            InteriorOrdering::Amd => {
                let (r1, r2, c) = bisect(a, interior);
                let mut order = amd_order(a, &r1)?;
                let p1 = order.len();
                order.extend(amd_order(a, &r2)?);
                let p2 = order.len();
                order.extend(amd_order(a, &c)?);
                (order, p1, p2)
            }
            InteriorOrdering::NestedDissection => nested_dissection(a, interior, node)?,
        };
        order.extend_from_slice(interface);
        let n = order.len();
        if n > u32::MAX as usize {
            return Err(Error::Factorisation("more than u32::MAX unknowns".into()));
        }
        // The submatrix in the natural order of `a` (sorted positions), and the ordering as a
        // permutation of those positions.
        let mut sorted = order.clone();
        sorted.sort_unstable();
        let mut local = vec![usize::MAX; a.nrows];
        for (k, &i) in sorted.iter().enumerate() {
            local[i] = k;
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        let mut gather = Vec::new();
        col_ptr.push(0);
        for &j in &sorted {
            let base = a.col_ptr[j];
            let (rows, _) = a.col(j);
            for (k, &i) in rows.iter().enumerate() {
                if local[i] != usize::MAX {
                    row_idx.push(local[i]);
                    if numeric {
                        gather.push(base + k);
                    }
                }
            }
            col_ptr.push(row_idx.len());
        }
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let fwd: Vec<usize> = order.iter().map(|&i| local[i]).collect();
        let mut inv = vec![0usize; n];
        for (k, &j) in fwd.iter().enumerate() {
            inv[j] = k;
        }
        let symbolic = factorize_symbolic_cholesky(
            pattern.as_ref(),
            Side::Lower,
            SymmetricOrdering::Custom(PermRef::new_checked(&fwd, &inv, n)),
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .map_err(faer_err)?;
        let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
            return Err(Error::Factorisation("expected a supernodal factor".into()));
        };
        let ns = sn.n_supernodes();
        let mut start: Vec<usize> = sn.supernode_begin().to_vec();
        start.push(n);
        let row_ptr = sn.col_ptr_for_row_idx()[..=ns].to_vec();
        let rows: Vec<u32> = sn.row_idx()[..row_ptr[ns]]
            .iter()
            .map(|&i| i as u32)
            .collect();
        let val_ptr = sn.col_ptr_for_val()[..=ns].to_vec();
        let layout = Supernodes {
            start,
            row_ptr,
            rows,
            val_ptr,
            val: Vec::new(),
        };
        let (a_col_ptr, a_row_idx) = if numeric {
            (a.col_ptr.clone(), a.row_idx.clone())
        } else {
            (Vec::new(), Vec::new())
        };
        let analysis = Analysis {
            a_col_ptr,
            a_row_idx,
            gather,
            pattern,
            symbolic,
            order,
        };
        Ok((analysis, layout, p1, p2))
    }

    /// The elimination order and the supernodal layout (no values) that
    /// [`with_ordering`](Self::with_ordering) would factor into, without the numeric
    /// factorisation: the ordering and the symbolic analysis are this factor's, without
    /// the maps a numeric factorisation and a refactorisation read. For an
    /// elimination that keeps no factor ([`SchurOnly`](crate::SchurOnly)).
    ///
    /// # Errors
    /// As [`with_ordering`](Self::with_ordering) without the numeric failures.
    pub(super) fn symbolic_layout(
        a: &Csc,
        interior: &[usize],
        interface: &[usize],
        ordering: (InteriorOrdering, usize),
    ) -> Result<SymbolicLayout> {
        let (analysis, layout, ..) = Self::analyse(a, interior, interface, ordering, false)?;
        let Supernodes {
            start,
            row_ptr,
            rows,
            ..
        } = layout;
        Ok(SymbolicLayout {
            order: analysis.order,
            start,
            row_ptr,
            rows,
        })
    }

    /// Whether this factor was computed for the pattern of `a` with these interior and
    /// interface dofs, so that [`refactor`](Self::refactor) applies.
    pub(super) fn analysed_for(&self, a: &Csc, interior: &[usize], interface: &[usize]) -> bool {
        let an = &self.analysis;
        if a.col_ptr != an.a_col_ptr
            || a.row_idx != an.a_row_idx
            || interior.len() != self.nr
            || an.order[self.nr..] != *interface
        {
            return false;
        }
        // The same interior set (the analysed order holds each dof once).
        let mut analysed = vec![false; a.nrows];
        for &i in &an.order[..self.nr] {
            analysed[i] = true;
        }
        interior.iter().all(|&i| i < a.nrows && analysed[i])
    }

    /// The elimination order (`order[k]` = the row of `a` of column `k` of `L`).
    pub(super) fn order(&self) -> &[usize] {
        &self.analysis.order
    }

    /// The factorisation of `a`, a matrix with the pattern this factor was computed for
    /// (e.g. `c_M M + c_K K` at another time step): the same ordering and symbolic
    /// factorisation, only the numeric one is done again.
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] if the pattern of `a` differs;
    /// [`ProblemError::NotPositiveDefinite`] as [`new`](Self::new).
    pub(super) fn refactor(&self, a: &Csc) -> Result<Self> {
        let an = &self.analysis;
        if a.col_ptr != an.a_col_ptr
            || a.row_idx != an.a_row_idx
            || a.val.len() != an.a_row_idx.len()
        {
            return Err(ProblemError::InvalidMatrix(
                "refactorisation of a matrix with another pattern".into(),
            )
            .into());
        }
        Self::numeric(
            a,
            Arc::clone(an),
            self.l.clone_layout(),
            self.nr,
            self.p1,
            self.p2,
        )
    }

    /// The numeric factorisation of `a` for `analysis`, into the supernodal `layout`.
    fn numeric(
        a: &Csc,
        analysis: Arc<Analysis>,
        mut layout: Supernodes,
        nr: usize,
        p1: usize,
        p2: usize,
    ) -> Result<Self> {
        let values: Vec<f64> = analysis.gather.iter().map(|&p| a.val[p]).collect();
        let symbolic = &analysis.symbolic;
        let req: StackReq =
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
        let mut mem = MemBuffer::try_new(req).map_err(faer_err)?;
        let mut l_values =
            rsf_linalg::try_filled("the condensation's sparse factor", symbolic.len_val(), 0.0)?;
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut l_values,
                SparseColMatRef::new(analysis.pattern.as_ref(), &values),
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|_| ProblemError::NotPositiveDefinite("A on the free dofs"))?;
        layout.val = l_values;
        let n = analysis.pattern.ncols();
        let ns = layout.len();
        let longest = (0..ns)
            .map(|s| layout.row_ptr[s + 1] - layout.row_ptr[s])
            .max()
            .unwrap_or(0);
        Ok(Self {
            nr,
            large: nr >= INTERIOR_PARALLEL_MIN,
            par: Parallelism::default(),
            n,
            p1,
            p2,
            l: layout,
            bufs: [vec![0.0; n - p2], vec![0.0; n - p2]],
            tmps: [vec![0.0; longest], vec![0.0; longest]],
            analysis,
        })
    }

    /// Sets the parallelism of the work over the interior (default
    /// [`Parallelism::default`]); results do not depend on it.
    pub(super) fn set_parallelism(&mut self, par: Parallelism) {
        self.par = par;
    }

    /// The parallelism given by [`set_parallelism`](Self::set_parallelism).
    pub(super) fn parallelism(&self) -> Parallelism {
        self.par
    }

    /// The parallelism of work over the interior: the factor's for interiors of at least
    /// [`INTERIOR_PARALLEL_MIN`] unknowns, else one thread (a second costs more than it saves).
    pub(super) fn interior_par(&self) -> Parallelism {
        if self.large {
            self.par
        } else {
            Parallelism::SEQ
        }
    }

    /// Stored entries of `L` (including explicit zeros of relaxed supernodes).
    pub(super) fn nnz(&self) -> usize {
        self.l.val.len()
    }

    /// Forward sweep over the interior columns: `y ← [L_R⁻¹ y_R; y_F − B L_R⁻¹ y_R]`
    /// (`y` in elimination order, length `n`).
    pub(super) fn forward_interior(&mut self, y: &mut [f64]) {
        let par = self.interior_par();
        let (p1, p2, nr) = (self.p1, self.p2, self.nr);
        let (y1, rest) = y.split_at_mut(p1);
        let (y2, shared) = rest.split_at_mut(p2 - p1);
        let l = &self.l;
        let [b1, b2] = &mut self.bufs;
        let [t1, t2] = &mut self.tmps;
        b1.fill(0.0);
        b2.fill(0.0);
        par.join(
            || l.forward(0..p1, y1, 0, b1, p2, t1),
            || l.forward(p1..p2, y2, p1, b2, p2, t2),
        );
        for ((s, x1), x2) in shared.iter_mut().zip(b1.iter()).zip(b2.iter()) {
            *s += *x1;
            *s += *x2;
        }
        let n = self.n;
        l.forward(p2..nr, shared, p2, &mut [], n, t1);
    }

    /// The forward sweep of [`forward_interior`](Self::forward_interior) on one thread with
    /// caller-provided scratch (`[b1, b2, tmp]`, resized here): the same arithmetic in the
    /// same order, so the same bits.
    pub(super) fn forward_interior_with(&self, y: &mut [f64], scratch: &mut [Vec<f64>; 3]) {
        let (p1, p2, nr, n) = (self.p1, self.p2, self.nr, self.n);
        let (y1, rest) = y.split_at_mut(p1);
        let (y2, shared) = rest.split_at_mut(p2 - p1);
        let [b1, b2, tmp] = scratch;
        for b in [&mut *b1, &mut *b2] {
            b.clear();
            b.resize(n - p2, 0.0);
        }
        tmp.resize(self.tmps[0].len(), 0.0);
        self.l.forward(0..p1, y1, 0, b1, p2, tmp);
        self.l.forward(p1..p2, y2, p1, b2, p2, tmp);
        for ((s, x1), x2) in shared.iter_mut().zip(b1.iter()).zip(b2.iter()) {
            *s += *x1;
            *s += *x2;
        }
        self.l.forward(p2..nr, shared, p2, &mut [], n, tmp);
    }

    /// Backward sweep over the interior columns: `y_R ← L_R⁻ᵀ (y_R − Bᵀ y_F)`.
    pub(super) fn backward_interior(&mut self, y: &mut [f64]) {
        let par = self.interior_par();
        let (p1, p2, nr, n) = (self.p1, self.p2, self.nr, self.n);
        let (y1, rest) = y.split_at_mut(p1);
        let (y2, shared) = rest.split_at_mut(p2 - p1);
        let l = &self.l;
        let [t1, t2] = &mut self.tmps;
        l.backward(p2..nr, shared, p2, &[], n, t1);
        let shared: &[f64] = shared;
        par.join(
            || l.backward(0..p1, y1, 0, shared, p2, t1),
            || l.backward(p1..p2, y2, p1, shared, p2, t2),
        );
    }

    /// The backward sweep of [`backward_interior`](Self::backward_interior) on one thread
    /// with caller-provided scratch (same arithmetic, same results): the reference of
    /// [`backward_interior_rows`](Self::backward_interior_rows) in the tests.
    #[cfg(test)]
    pub(super) fn backward_interior_with(&self, y: &mut [f64], tmp: &mut Vec<f64>) {
        let (p1, p2, nr, n) = (self.p1, self.p2, self.nr, self.n);
        let (y1, rest) = y.split_at_mut(p1);
        let (y2, shared) = rest.split_at_mut(p2 - p1);
        self.l.backward(p2..nr, shared, p2, &[], n, tmp);
        self.l.backward(0..p1, y1, 0, shared, p2, tmp);
        self.l.backward(p1..p2, y2, p1, shared, p2, tmp);
    }

    /// The backward sweep of [`backward_interior`](Self::backward_interior) on one thread
    /// for `r` right-hand sides at once, stored row-major (`y[i r + k]` = row `i` of
    /// right-hand side `k`, `n × r`): each column of the result is bit-identical to a
    /// single sweep's, and the factor is read once instead of `r` times.
    pub(super) fn backward_interior_rows(&self, y: &mut [f64], r: usize, tmp: &mut Vec<f64>) {
        let (p1, p2, nr, n) = (self.p1, self.p2, self.nr, self.n);
        debug_assert_eq!(y.len(), n * r);
        let (y1, rest) = y.split_at_mut(p1 * r);
        let (y2, shared) = rest.split_at_mut((p2 - p1) * r);
        self.l.backward_rows(
            p2..nr,
            SplitRows {
                own: shared,
                own_off: p2,
                tail: &[],
                split: n,
                r,
            },
            tmp,
        );
        self.l.backward_rows(
            0..p1,
            SplitRows {
                own: y1,
                own_off: 0,
                tail: shared,
                split: p2,
                r,
            },
            tmp,
        );
        self.l.backward_rows(
            p1..p2,
            SplitRows {
                own: y2,
                own_off: p1,
                tail: shared,
                split: p2,
                r,
            },
            tmp,
        );
    }

    /// Every stored entry `(i, j, L_ij)` of the interface block `L_F` of the factor
    /// (lower triangle, `i ≥ j`, both counted from the interface's first unknown), column
    /// by column.
    fn for_each_interface_entry(&self, mut f: impl FnMut(usize, usize, f64)) {
        let nr = self.nr;
        for s in self.l.covering(&(nr..self.n)) {
            let (c0, w, pattern, l) = self.l.get(s);
            let ld = w + pattern.len();
            for jj in 0..w {
                let j = c0 + jj;
                if j < nr {
                    continue;
                }
                let col = &l[jj * ld..(jj + 1) * ld];
                for ii in jj..w {
                    f(c0 + ii - nr, j - nr, col[ii]);
                }
                for (k, &i) in pattern.iter().enumerate() {
                    f(i as usize - nr, j - nr, col[w + k]);
                }
            }
        }
    }

    /// The interface block `L_F` of the factor as packed rows (row `i` of the lower
    /// triangle at `i(i+1)/2`, entries `0..=i`): `m(m+1)/2` f64 for `m` interface unknowns.
    pub(super) fn interface_rows(&self) -> Vec<f64> {
        let nf = self.n - self.nr;
        let mut packed = vec![0.0; nf * (nf + 1) / 2];
        self.for_each_interface_entry(|i, j, v| packed[i * (i + 1) / 2 + j] = v);
        packed
    }

    /// `S = L_F L_Fᵀ`, the Schur complement on the interface, dense column-major
    /// (`|F| × |F|`, symmetric).
    pub(super) fn schur_complement(&self) -> Vec<f64> {
        let nf = self.n - self.nr;
        // Dense L_F (lower, column-major).
        let mut lf = vec![0.0; nf * nf];
        self.for_each_interface_entry(|i, j, v| lf[j * nf + i] = v);
        let l = faer::MatRef::from_column_major_slice(&lf, nf, nf);
        crate::dense::symmetric_product(l, l.transpose())
    }
}
