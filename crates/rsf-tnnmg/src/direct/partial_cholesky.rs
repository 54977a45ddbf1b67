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

use std::ops::Range;
use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::{amd, SupernodalThreshold};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Par, Side};

use rsf_linalg::Parallelism;

use super::ordering::{nested_dissection, InteriorOrdering};
use crate::csc::Csc;
use crate::error::{Error, Result};

/// The supernodal layout of `L`: supernode `s` covers columns `start[s]..start[s + 1]`
/// (width `w`), its rows are the `w` diagonal-block rows followed by
/// `rows[row_ptr[s]..row_ptr[s + 1]]` (increasing), and its values are a dense
/// column-major `(w + p) × w` block at `val_ptr[s]`.
#[derive(Debug, Clone)]
struct Supernodes {
    start: Vec<usize>,
    row_ptr: Vec<usize>,
    rows: Vec<u32>,
    val_ptr: Vec<usize>,
    val: Vec<f64>,
}

impl Supernodes {
    /// The layout without the values.
    fn clone_layout(&self) -> Self {
        Self {
            start: self.start.clone(),
            row_ptr: self.row_ptr.clone(),
            rows: self.rows.clone(),
            val_ptr: self.val_ptr.clone(),
            val: Vec::new(),
        }
    }

    fn len(&self) -> usize {
        self.start.len() - 1
    }

    /// (first column, width, pattern below the diagonal block, values).
    #[inline]
    fn get(&self, s: usize) -> (usize, usize, &[u32], &[f64]) {
        let c0 = self.start[s];
        (
            c0,
            self.start[s + 1] - c0,
            &self.rows[self.row_ptr[s]..self.row_ptr[s + 1]],
            &self.val[self.val_ptr[s]..self.val_ptr[s + 1]],
        )
    }

    /// The supernodes that contain a column of `cols`.
    fn covering(&self, cols: &Range<usize>) -> Range<usize> {
        if cols.is_empty() {
            return 0..0;
        }
        let first = self.start.partition_point(|&c| c <= cols.start) - 1;
        let last = self.start.partition_point(|&c| c < cols.end);
        first..last
    }

    /// Forward sweep over the columns `cols`: `y_j ← y_j / L_jj`, then `y_i −= L_ij y_j` for
    /// the rows below. Rows below `split` live in `own` (at `row − own_off`), the others in
    /// `tail` (at `row − split`).
    fn forward(
        &self,
        cols: Range<usize>,
        own: &mut [f64],
        own_off: usize,
        tail: &mut [f64],
        split: usize,
        tmp: &mut Vec<f64>,
    ) {
        // Compiled for the SIMD level of the machine, chosen at run time (pulp); plain loops
        // whose floating-point operations keep their order, so the results are the same bits
        // on every machine.
        pulp::Arch::new().dispatch(|| self.forward_kernel(cols, own, own_off, tail, split, tmp));
    }

    #[inline(always)]
    fn forward_kernel(
        &self,
        cols: Range<usize>,
        own: &mut [f64],
        own_off: usize,
        tail: &mut [f64],
        split: usize,
        tmp: &mut Vec<f64>,
    ) {
        for s in self.covering(&cols) {
            let (c0, w, pattern, l) = self.get(s);
            let (j0, j1) = (cols.start.max(c0) - c0, cols.end.min(c0 + w) - c0);
            let ld = w + pattern.len();
            // Diagonal block: its rows below `split` are own rows, the rest tail rows.
            let d_own = split.saturating_sub(c0).min(w);
            for jj in j0..j1 {
                let col = &l[jj * ld..(jj + 1) * ld];
                let yj = own[c0 + jj - own_off] / col[jj];
                own[c0 + jj - own_off] = yj;
                if jj + 1 < d_own {
                    // Rows c0 + jj + 1 .. c0 + d_own (c0 + jj ≥ own_off: the column is own).
                    let (r0, r1) = (c0 + jj + 1 - own_off, c0 + d_own - own_off);
                    for (yi, lij) in own[r0..r1].iter_mut().zip(&col[jj + 1..d_own]) {
                        *yi -= lij * yj;
                    }
                }
                let lo = (jj + 1).max(d_own);
                if lo < w {
                    let t = c0 + lo - split;
                    for (yi, lij) in tail[t..t + w - lo].iter_mut().zip(&col[lo..w]) {
                        *yi -= lij * yj;
                    }
                }
            }
            let p = pattern.len();
            if tmp.len() < p {
                tmp.resize(p, 0.0);
            }
            let t = &mut tmp[..p];
            t.fill(0.0);
            for jj in j0..j1 {
                let yj = own[c0 + jj - own_off];
                if yj != 0.0 {
                    for (ti, lij) in t.iter_mut().zip(&col_below(l, ld, w, jj)[..p]) {
                        *ti += lij * yj;
                    }
                }
            }
            let k_own = pattern.partition_point(|&r| (r as usize) < split);
            for (&i, ti) in pattern[..k_own].iter().zip(&t[..k_own]) {
                own[i as usize - own_off] -= ti;
            }
            for (&i, ti) in pattern[k_own..].iter().zip(&t[k_own..]) {
                tail[i as usize - split] -= ti;
            }
        }
    }

    /// Backward sweep over the columns `cols` (in reverse):
    /// `y_j ← (y_j − Σ_{i>j} L_ij y_i) / L_jj`. Rows below `split` live in `own` (updated),
    /// the others in `tail` (read only).
    fn backward(
        &self,
        cols: Range<usize>,
        own: &mut [f64],
        own_off: usize,
        tail: &[f64],
        split: usize,
        tmp: &mut Vec<f64>,
    ) {
        pulp::Arch::new().dispatch(|| self.backward_kernel(cols, own, own_off, tail, split, tmp));
    }

    #[inline(always)]
    fn backward_kernel(
        &self,
        cols: Range<usize>,
        own: &mut [f64],
        own_off: usize,
        tail: &[f64],
        split: usize,
        tmp: &mut Vec<f64>,
    ) {
        for s in self.covering(&cols).rev() {
            let (c0, w, pattern, l) = self.get(s);
            let (j0, j1) = (cols.start.max(c0) - c0, cols.end.min(c0 + w) - c0);
            let ld = w + pattern.len();
            let p = pattern.len();
            if tmp.len() < p {
                tmp.resize(p, 0.0);
            }
            let t = &mut tmp[..p];
            let k_own = pattern.partition_point(|&r| (r as usize) < split);
            for (ti, &i) in t[..k_own].iter_mut().zip(&pattern[..k_own]) {
                *ti = own[i as usize - own_off];
            }
            for (ti, &i) in t[k_own..].iter_mut().zip(&pattern[k_own..]) {
                *ti = tail[i as usize - split];
            }
            for jj in j0..j1 {
                own[c0 + jj - own_off] -= dot(&col_below(l, ld, w, jj)[..p], t);
            }
            let d_own = split.saturating_sub(c0).min(w);
            for jj in (j0..j1).rev() {
                let col = &l[jj * ld..(jj + 1) * ld];
                let mut acc = own[c0 + jj - own_off];
                if jj + 1 < d_own {
                    let (r0, r1) = (c0 + jj + 1 - own_off, c0 + d_own - own_off);
                    acc -= dot(&col[jj + 1..d_own], &own[r0..r1]);
                }
                let lo = (jj + 1).max(d_own);
                if lo < w {
                    let tt = c0 + lo - split;
                    acc -= dot(&col[lo..w], &tail[tt..tt + w - lo]);
                }
                own[c0 + jj - own_off] = acc / col[jj];
            }
        }
    }
}

/// `r` right-hand sides stored row-major (`r` values per row) in two buffers: rows
/// `own_off..split` in `own`, rows `split..` in `tail`.
struct SplitRows<'a> {
    own: &'a mut [f64],
    own_off: usize,
    tail: &'a [f64],
    split: usize,
    r: usize,
}

impl Supernodes {
    /// [`backward`](Self::backward) for `r` right-hand sides at once ([`SplitRows`]). Every
    /// right-hand side goes through exactly the operations of a single backward sweep, in
    /// the same order ([`dot_rows`]), so each column of the result is bit-identical to a
    /// single sweep's; the factor is read once for all of them instead of once per column. (The per-step sweep keeps its own
    /// one-sided kernel: this one with `r = 1` made the main job 1.04× slower at j = 5,
    /// 3 paired runs.)
    fn backward_rows(&self, cols: Range<usize>, rows: SplitRows<'_>, tmp: &mut Vec<f64>) {
        pulp::Arch::new().dispatch(|| self.backward_rows_kernel(cols, rows, tmp));
    }

    #[inline(always)]
    fn backward_rows_kernel(&self, cols: Range<usize>, rows: SplitRows<'_>, tmp: &mut Vec<f64>) {
        let SplitRows {
            own,
            own_off,
            tail,
            split,
            r,
        } = rows;
        // Scratch: the gathered rows of the pattern (p × r), four partial sums (4 × r), one
        // dot product (r) and one running sum (r) per right-hand side.
        for s in self.covering(&cols).rev() {
            let (c0, w, pattern, l) = self.get(s);
            let (j0, j1) = (cols.start.max(c0) - c0, cols.end.min(c0 + w) - c0);
            let ld = w + pattern.len();
            let p = pattern.len();
            if tmp.len() < (p + 6) * r {
                tmp.resize((p + 6) * r, 0.0);
            }
            let (t, scratch) = tmp.split_at_mut(p * r);
            let (acc, scratch) = scratch.split_at_mut(4 * r);
            let (out, sums) = scratch.split_at_mut(r);
            let sums = &mut sums[..r];
            for (q, &i) in pattern.iter().enumerate() {
                let i = i as usize;
                let src = if i < split {
                    &own[(i - own_off) * r..(i - own_off + 1) * r]
                } else {
                    &tail[(i - split) * r..(i - split + 1) * r]
                };
                t[q * r..(q + 1) * r].copy_from_slice(src);
            }
            let t: &[f64] = t;
            for jj in j0..j1 {
                dot_rows(
                    &col_below(l, ld, w, jj)[..p],
                    |q| &t[q * r..(q + 1) * r],
                    acc,
                    out,
                );
                let row = c0 + jj - own_off;
                for (y, o) in own[row * r..(row + 1) * r].iter_mut().zip(out.iter()) {
                    *y -= o;
                }
            }
            let d_own = split.saturating_sub(c0).min(w);
            for jj in (j0..j1).rev() {
                let col = &l[jj * ld..(jj + 1) * ld];
                let row = c0 + jj - own_off;
                sums.copy_from_slice(&own[row * r..(row + 1) * r]);
                if jj + 1 < d_own {
                    let r0 = c0 + jj + 1 - own_off;
                    let own_ref: &[f64] = own;
                    dot_rows(
                        &col[jj + 1..d_own],
                        |q| &own_ref[(r0 + q) * r..(r0 + q + 1) * r],
                        acc,
                        out,
                    );
                    for (a, o) in sums.iter_mut().zip(out.iter()) {
                        *a -= o;
                    }
                }
                let lo = (jj + 1).max(d_own);
                if lo < w {
                    let tt = c0 + lo - split;
                    dot_rows(
                        &col[lo..w],
                        |q| &tail[(tt + q) * r..(tt + q + 1) * r],
                        acc,
                        out,
                    );
                    for (a, o) in sums.iter_mut().zip(out.iter()) {
                        *a -= o;
                    }
                }
                let diag = col[jj];
                for (y, a) in own[row * r..(row + 1) * r].iter_mut().zip(sums.iter()) {
                    *y = a / diag;
                }
            }
        }
    }
}

/// For each `k < r = out.len()`: `out[k] = Σ_i a_i · row(i)[k]`, summed exactly as [`dot`]
/// sums `Σ a_i b_i` (four partial sums over the blocks of four, then the rest in order), so
/// that each `out[k]` is bit-identical to `dot(a, b)` with `b_i = row(i)[k]`. `acc`: scratch
/// of at least `4 r`.
#[inline(always)]
fn dot_rows<'a>(a: &[f64], row: impl Fn(usize) -> &'a [f64], acc: &mut [f64], out: &mut [f64]) {
    let r = out.len();
    let acc = &mut acc[..4 * r];
    acc.fill(0.0);
    let n4 = a.len() - a.len() % 4;
    for c in (0..n4).step_by(4) {
        for q in 0..4 {
            let x = a[c + q];
            for (s, y) in acc[q * r..(q + 1) * r].iter_mut().zip(row(c + q)) {
                *s += x * y;
            }
        }
    }
    for k in 0..r {
        out[k] = (acc[k] + acc[r + k]) + (acc[2 * r + k] + acc[3 * r + k]);
    }
    for (i, &x) in a.iter().enumerate().skip(n4) {
        for (o, y) in out.iter_mut().zip(row(i)) {
            *o += x * y;
        }
    }
}

#[inline(always)]
fn col_below(l: &[f64], ld: usize, w: usize, jj: usize) -> &[f64] {
    &l[jj * ld + w..(jj + 1) * ld]
}

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

/// `Σ a_i b_i` with four independent partial sums (a fixed order: deterministic, and not
/// bound by the latency of one chain of additions).
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (a4, ar) = a.split_at(a.len() - a.len() % 4);
    let (b4, br) = b.split_at(a4.len());
    for (x, y) in a4.chunks_exact(4).zip(b4.chunks_exact(4)) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for (x, y) in ar.iter().zip(br) {
        s += x * y;
    }
    s
}

fn faer_err(e: impl std::fmt::Debug) -> Error {
    Error::Factorisation(format!("{e:?}"))
}

/// Local CSC pattern (no values) of the rows/columns `idx` of `a`, and the map back.
fn local_pattern(a: &Csc, idx: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut local = vec![usize::MAX; a.nrows];
    for (k, &i) in idx.iter().enumerate() {
        local[i] = k;
    }
    let mut col_ptr = Vec::with_capacity(idx.len() + 1);
    let mut row_idx = Vec::new();
    col_ptr.push(0);
    for &j in idx {
        let (rows, _) = a.col(j);
        row_idx.extend(rows.iter().map(|&i| local[i]).filter(|&i| i != usize::MAX));
        col_ptr.push(row_idx.len());
    }
    (col_ptr, row_idx)
}

/// Fill-reducing (AMD) order of the rows/columns `idx` of the symmetric matrix `a`:
/// returns the entries of `idx` reordered.
fn amd_order(a: &Csc, idx: &[usize]) -> Result<Vec<usize>> {
    let n = idx.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let (col_ptr, row_idx) = local_pattern(a, idx);
    let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    let mut perm = vec![0usize; n];
    let mut perm_inv = vec![0usize; n];
    let nnz = pattern.row_idx().len();
    let mut mem =
        MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(n, nnz)).map_err(faer_err)?;
    amd::order_maybe_unsorted(
        &mut perm,
        &mut perm_inv,
        pattern.as_ref(),
        Default::default(),
        MemStack::new(&mut mem),
    )
    .map_err(faer_err)?;
    Ok(perm.iter().map(|&k| idx[k]).collect())
}

/// Splits `idx` (rows/columns of `a`) into `(R₁, R₂, C)`: `C` is the middle level of a
/// breadth-first search from a pseudo-peripheral vertex of the graph of `a` restricted to
/// `idx`, so there is no entry of `a` between `R₁` and `R₂`. Parts that are too small to
/// pay (or a disconnected graph) give empty `R₂` and `C`.
fn bisect(a: &Csc, idx: &[usize]) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
    let n = idx.len();
    let whole = || (idx.to_vec(), Vec::new(), Vec::new());
    if n < 64 {
        return whole();
    }
    let (col_ptr, row_idx) = local_pattern(a, idx);
    let bfs = |root: usize, level: &mut Vec<usize>| -> (usize, usize) {
        level.fill(usize::MAX);
        level[root] = 0;
        let mut queue = vec![root];
        let mut head = 0;
        while head < queue.len() {
            let v = queue[head];
            head += 1;
            for &u in &row_idx[col_ptr[v]..col_ptr[v + 1]] {
                if level[u] == usize::MAX {
                    level[u] = level[v] + 1;
                    queue.push(u);
                }
            }
        }
        let last = *queue.last().expect("root");
        (queue.len(), last)
    };
    let mut level = vec![usize::MAX; n];
    let (mut reached, mut far) = bfs(0, &mut level);
    for _ in 0..3 {
        let (r, f) = bfs(far, &mut level);
        reached = r;
        if f == far {
            break;
        }
        far = f;
    }
    if reached < n {
        return whole();
    }
    let depth = level.iter().copied().max().unwrap_or(0);
    let mut count = vec![0usize; depth + 1];
    for &l in &level {
        count[l] += 1;
    }
    // The level where the cumulative count passes half.
    let mut acc = 0;
    let mut mid = 0;
    for (l, &c) in count.iter().enumerate() {
        if acc + c / 2 >= n / 2 {
            mid = l;
            break;
        }
        acc += c;
    }
    if mid == 0 || mid == depth {
        return whole();
    }
    let (mut r1, mut r2, mut c) = (Vec::new(), Vec::new(), Vec::new());
    for (k, &l) in level.iter().enumerate() {
        match l.cmp(&mid) {
            std::cmp::Ordering::Less => r1.push(idx[k]),
            std::cmp::Ordering::Greater => r2.push(idx[k]),
            std::cmp::Ordering::Equal => c.push(idx[k]),
        }
    }
    (r1, r2, c)
}

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
    /// [`Error::NotPositiveDefinite`] if the submatrix is not numerically SPD;
    /// [`Error::Factorisation`] if faer or METIS fails (e.g. out of memory) or the factor
    /// has more than `u32::MAX` rows; [`Error::FeatureDisabled`] for nested dissection
    /// without the feature `metis`.
    pub(super) fn with_ordering(
        a: &Csc,
        interior: &[usize],
        interface: &[usize],
        ordering: (InteriorOrdering, usize),
    ) -> Result<(Self, Vec<usize>)> {
        let (analysis, layout, p1, p2) = Self::analyse(a, interior, interface, ordering)?;
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
        let (analysis, ..) = Self::analyse(a, interior, interface, (InteriorOrdering::Amd, 1))?;
        Ok(analysis.symbolic.len_val())
    }

    /// The ordering (two halves, a separator, the interface last; the interior by
    /// `ordering`) and faer's symbolic factorisation of the submatrix of `a` on
    /// `interior ∪ interface`, with the layout of the supernodes and the ends `p1`, `p2`
    /// of the two halves in the order.
    fn analyse(
        a: &Csc,
        interior: &[usize],
        interface: &[usize],
        (ordering, node): (InteriorOrdering, usize),
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
                    gather.push(base + k);
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
        let analysis = Analysis {
            a_col_ptr: a.col_ptr.clone(),
            a_row_idx: a.row_idx.clone(),
            gather,
            pattern,
            symbolic,
            order,
        };
        Ok((analysis, layout, p1, p2))
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
    /// [`Error::InvalidMatrix`] if the pattern of `a` differs;
    /// [`Error::NotPositiveDefinite`] as [`new`](Self::new).
    pub(super) fn refactor(&self, a: &Csc) -> Result<Self> {
        let an = &self.analysis;
        if a.col_ptr != an.a_col_ptr
            || a.row_idx != an.a_row_idx
            || a.val.len() != an.a_row_idx.len()
        {
            return Err(Error::InvalidMatrix(
                "refactorisation of a matrix with another pattern".into(),
            ));
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
        let mut l_values = vec![0.0; symbolic.len_val()];
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
            .map_err(|_| Error::NotPositiveDefinite("A on the free dofs"))?;
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
        let mut s = faer::Mat::<f64>::zeros(nf, nf);
        faer::linalg::matmul::matmul(
            s.as_mut(),
            faer::Accum::Replace,
            l,
            l.transpose(),
            1.0,
            Par::Seq,
        );
        let mut out = vec![0.0; nf * nf];
        for j in 0..nf {
            for i in 0..nf {
                // Symmetrise against round-off.
                out[j * nf + i] = 0.5 * (s[(i, j)] + s[(j, i)]);
            }
        }
        out
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// 5-point Laplacian plus identity on an `m × m` grid (node `i + m j`).
    pub(crate) fn grid(m: usize) -> Csc {
        let n = m * m;
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut val = Vec::new();
        for j in 0..n {
            let (x, y) = (j % m, j / m);
            let mut entries = vec![(j, 5.0)];
            if x > 0 {
                entries.push((j - 1, -1.0));
            }
            if x + 1 < m {
                entries.push((j + 1, -1.0));
            }
            if y > 0 {
                entries.push((j - m, -1.0));
            }
            if y + 1 < m {
                entries.push((j + m, -1.0));
            }
            entries.sort_by_key(|e| e.0);
            for (i, v) in entries {
                row_idx.push(i);
                val.push(v);
            }
            col_ptr.push(row_idx.len());
        }
        Csc {
            nrows: n,
            ncols: n,
            col_ptr,
            row_idx,
            val,
        }
    }

    fn dense(a: &Csc) -> Vec<Vec<f64>> {
        let mut d = vec![vec![0.0; a.ncols]; a.nrows];
        for j in 0..a.ncols {
            let (r, v) = a.col(j);
            for (&i, &x) in r.iter().zip(v) {
                d[i][j] = x;
            }
        }
        d
    }

    /// Dense solve of `M x = b` (Gaussian elimination without pivoting; M is SPD).
    fn solve_dense(mut m: Vec<Vec<f64>>, mut x: Vec<f64>) -> Vec<f64> {
        let n = x.len();
        for p in 0..n {
            for r in p + 1..n {
                let f = m[r][p] / m[p][p];
                if f != 0.0 {
                    for c in p..n {
                        m[r][c] -= f * m[p][c];
                    }
                    x[r] -= f * x[p];
                }
            }
        }
        for p in (0..n).rev() {
            let mut s = x[p];
            for c in p + 1..n {
                s -= m[p][c] * x[c];
            }
            x[p] = s / m[p][p];
        }
        x
    }

    /// The sweeps reproduce the condensed right-hand side, the Schur complement and the
    /// interior recovery computed densely, on a grid large enough to be split in halves.
    #[test]
    fn partial_sweeps_match_dense_condensation() {
        let m = 14;
        let a = grid(m);
        let n = m * m;
        let ad = dense(&a);
        // Interface: the bottom row of the grid.
        let interface: Vec<usize> = (0..m).collect();
        let interior: Vec<usize> = (m..n).collect();
        let (mut l, order) = PartialCholesky::new(&a, &interior, &interface).unwrap();
        assert!(
            l.p1 > 0 && l.p2 > l.p1 && l.nr > l.p2,
            "the interior is split"
        );
        assert_eq!(&order[interior.len()..], interface.as_slice());
        let nr = interior.len();
        let a_rr: Vec<Vec<f64>> = interior
            .iter()
            .map(|&i| interior.iter().map(|&j| ad[i][j]).collect())
            .collect();
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
        let z = solve_dense(a_rr.clone(), interior.iter().map(|&i| b[i]).collect());
        let mut y: Vec<f64> = order.iter().map(|&i| b[i]).collect();
        l.forward_interior(&mut y);
        for (f, &i) in interface.iter().enumerate() {
            let g = b[i]
                - interior
                    .iter()
                    .zip(&z)
                    .map(|(&r, zr)| ad[i][r] * zr)
                    .sum::<f64>();
            assert!((y[nr + f] - g).abs() < 1e-12, "condensed rhs {f}");
        }
        let s = l.schur_complement();
        let nf = interface.len();
        for (fj, &j) in interface.iter().enumerate() {
            let w = solve_dense(a_rr.clone(), interior.iter().map(|&r| ad[r][j]).collect());
            for (fi, &i) in interface.iter().enumerate() {
                let sij = ad[i][j]
                    - interior
                        .iter()
                        .zip(&w)
                        .map(|(&r, wr)| ad[i][r] * wr)
                        .sum::<f64>();
                assert!((s[fj * nf + fi] - sij).abs() < 1e-12, "S[{fi},{fj}]");
            }
        }
        // Recovery with interface values x_F.
        let x_f: Vec<f64> = (0..nf).map(|f| (f as f64).cos()).collect();
        y[nr..].copy_from_slice(&x_f);
        l.backward_interior(&mut y);
        let rhs: Vec<f64> = interior
            .iter()
            .map(|&r| {
                b[r] - interface
                    .iter()
                    .zip(&x_f)
                    .map(|(&f, xf)| ad[r][f] * xf)
                    .sum::<f64>()
            })
            .collect();
        let x_r = solve_dense(a_rr, rhs);
        for (k, &i) in order[..nr].iter().enumerate() {
            let pos = interior.iter().position(|&r| r == i).unwrap();
            assert!((y[k] - x_r[pos]).abs() < 1e-12);
        }
    }

    /// The two halves give bit-identical results for every parallelism, in the global
    /// pool and in pools of one and two threads.
    #[test]
    fn sweeps_are_bit_identical_for_every_thread_count() {
        let m = 20;
        let a = grid(m);
        let interface: Vec<usize> = (0..m).collect();
        let interior: Vec<usize> = (m..m * m).collect();
        let run = |par: Parallelism| {
            let (mut l, order) = PartialCholesky::new(&a, &interior, &interface).unwrap();
            l.large = true; // this small grid would otherwise stay on one thread
            l.set_parallelism(par);
            assert_eq!(l.interior_par(), par);
            let mut y: Vec<f64> = order.iter().map(|&i| (i as f64).sqrt().sin()).collect();
            l.forward_interior(&mut y);
            l.backward_interior(&mut y);
            y.iter().map(|x| x.to_bits()).collect::<Vec<u64>>()
        };
        let reference = run(Parallelism::SEQ);
        for threads in [1, 2, 4] {
            assert_eq!(run(Parallelism::rayon(threads)), reference, "{threads}");
        }
        for pool_threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(pool_threads)
                .build()
                .unwrap();
            assert_eq!(pool.install(|| run(Parallelism::rayon(2))), reference);
        }
    }

    #[test]
    fn refactorisation_equals_a_fresh_factorisation_and_checks_the_pattern() {
        let m = 20;
        let a = grid(m);
        let interface: Vec<usize> = (0..m).collect();
        let interior: Vec<usize> = (m..m * m).collect();
        let (l, order) = PartialCholesky::new(&a, &interior, &interface).unwrap();
        // Another matrix with the same pattern (as c_M M + c_K K at another τ).
        let mut b = a.clone();
        for (k, v) in b.val.iter_mut().enumerate() {
            *v *= if *v > 0.0 {
                2.0 + (k % 7) as f64 * 0.1
            } else {
                1.3
            };
        }
        assert!(l.analysed_for(&b, &interior, &interface));
        let re = l.refactor(&b).unwrap();
        let (fresh, fresh_order) = PartialCholesky::new(&b, &interior, &interface).unwrap();
        assert_eq!(re.order(), &fresh_order[..]);
        assert_eq!(order, fresh_order);
        let bits = |f: &PartialCholesky| f.l.val.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&re), bits(&fresh));
        assert_eq!(re.schur_complement(), fresh.schur_complement());
        // Another pattern, or other interface dofs: no reuse.
        let c = grid(m + 1);
        assert!(!l.analysed_for(&c, &interior, &interface));
        assert!(matches!(l.refactor(&c), Err(Error::InvalidMatrix(_))));
        let other_interface: Vec<usize> = (1..=m).collect();
        assert!(!l.analysed_for(&b, &interior, &other_interface));
        let mut other_interior = interior.clone();
        other_interior[0] = 0; // an interface dof in place of an interior one
        assert!(!l.analysed_for(&b, &other_interior, &interface));
        // A matrix that is not positive definite is still reported as such.
        let mut d = a.clone();
        for v in d.val.iter_mut() {
            *v = -*v;
        }
        assert!(matches!(l.refactor(&d), Err(Error::NotPositiveDefinite(_))));
    }

    #[test]
    fn sweeps_of_many_right_hand_sides_equal_single_sweeps_bitwise() {
        let m = 20;
        let a = grid(m);
        let interface: Vec<usize> = (0..m).collect();
        let interior: Vec<usize> = (m..m * m).collect();
        let (l, _) = PartialCholesky::new(&a, &interior, &interface).unwrap();
        assert!(
            l.p1 > 0 && l.p2 > l.p1 && l.nr > l.p2,
            "two halves and a separator"
        );
        let n = l.n;
        let rhs = |k: usize| -> Vec<f64> {
            (0..n)
                .map(|i| {
                    ((i * 7 + k * 13) as f64 * 0.37).sin() * if i % 5 == k % 5 { 0.0 } else { 1.0 }
                })
                .collect()
        };
        for r in [1, 3, 8] {
            let mut single = Vec::new();
            let mut tmp = Vec::new();
            for k in 0..r {
                let mut y = rhs(k);
                l.backward_interior_with(&mut y, &mut tmp);
                single.push(y);
            }
            let mut rows = vec![0.0; n * r];
            for k in 0..r {
                for (i, v) in rhs(k).into_iter().enumerate() {
                    rows[i * r + k] = v;
                }
            }
            l.backward_interior_rows(&mut rows, r, &mut tmp);
            for k in 0..r {
                for i in 0..n {
                    assert_eq!(
                        rows[i * r + k].to_bits(),
                        single[k][i].to_bits(),
                        "r = {r}, right-hand side {k}, row {i}"
                    );
                }
            }
        }
    }
}
