//! Block compressed sparse row storage with `D × D` node blocks: the solvers' working
//! format for Gauss–Seidel sweeps (row access, one 32-bit column index per node block).
//!
//! Rows and columns are nodes (node-major numbering: dof `D p + c`). A symmetric matrix is
//! kept as its diagonal blocks plus the strictly upper and the strictly lower off-diagonal
//! blocks, each triangle by rows in its own arrays (the lower one holds the transposes of
//! the upper one). A forward Gauss–Seidel sweep then streams only the upper triangle and a
//! backward sweep only the lower one, the couplings to already updated nodes being
//! accumulated ("pushed") through the transposed blocks: half the matrix traffic of a sweep
//! over full rows, which is what bounds the sweeps on large levels. Matrices that differ
//! only on their diagonal blocks (TNNMG's `A + ∇²Φ`) share the triangles (reference
//! counted).

use std::sync::Arc;

use faer::sparse::SparseColMatRef;

use crate::block::{load, mul_vec, store, sub_mul_t_vec, sub_mul_vec, Block};
use crate::error::Result;
use rsf_linalg::{for_node_rows, ordered_sum, Csc, Parallelism, ProblemError};

/// Nodes below which [`BlockCsr::residual_rows`] stays on one thread.
const RESIDUAL_PARALLEL_MIN: usize = 2048;

/// Block `p` of `w`, leaving zeros behind.
#[inline(always)]
fn take<const D: usize>(w: &mut [f64], p: usize) -> [f64; D] {
    let out = load::<D>(w, p);
    w[D * p..D * p + D].fill(0.0);
    out
}

/// One strictly triangular part of the off-diagonal blocks, by rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Triangle<const D: usize> {
    /// Row `p`'s blocks are `ptr[p]..ptr[p + 1]` (length `nodes + 1`).
    pub ptr: Vec<usize>,
    /// Column node of every block, increasing within a row.
    pub col: Vec<u32>,
    /// The blocks, in the order of `col`.
    pub val: Vec<Block<D>>,
}

impl<const D: usize> Triangle<D> {
    /// The positions of row `p`'s blocks in `col` and `val`.
    #[inline]
    pub fn range(&self, p: usize) -> std::ops::Range<usize> {
        self.ptr[p]..self.ptr[p + 1]
    }

    /// `s −= Σ_k B_k x_{col_k}` over row `p`.
    #[inline(always)]
    fn sub_row(&self, p: usize, x: &[f64], s: &mut [f64; D]) {
        let r = self.range(p);
        for (&q, blk) in self.col[r.clone()].iter().zip(&self.val[r]) {
            sub_mul_vec(s, blk, &load::<D>(x, q as usize));
        }
    }

    /// `w_{col_k} −= B_kᵀ y` over row `p` (the transposed couplings of node `p`).
    #[inline(always)]
    fn push_row(&self, p: usize, y: &[f64; D], w: &mut [f64]) {
        let r = self.range(p);
        for (&q, blk) in self.col[r.clone()].iter().zip(&self.val[r]) {
            let q = q as usize;
            let mut wq = load::<D>(w, q);
            sub_mul_t_vec(&mut wq, blk, y);
            store(w, q, &wq);
        }
    }
}

/// Square symmetric block matrix (see the module documentation). Structurally absent
/// entries inside a stored block are zeros.
#[derive(Debug, Clone)]
pub struct BlockCsr<const D: usize> {
    /// Blocks left of the diagonal, by rows.
    pub lower: Arc<Triangle<D>>,
    /// Blocks right of the diagonal, by rows.
    pub upper: Arc<Triangle<D>>,
    /// Diagonal block of every node.
    pub diag: Vec<Block<D>>,
}

/// The order of a [`BlockCsr::sweep`]: which way it runs over the nodes and whether it
/// starts from `x = 0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SweepOrder {
    /// Decreasing node order (a backward sweep) instead of increasing.
    pub reverse: bool,
    /// Start from `x = 0` whatever `x` holds.
    pub zero_start: bool,
}

impl SweepOrder {
    /// A sweep from the current `x`, backward when `reverse`.
    pub fn from_x(reverse: bool) -> Self {
        Self {
            reverse,
            zero_start: false,
        }
    }
}

impl<const D: usize> BlockCsr<D> {
    /// Zero matrix whose row `p` has off-diagonal blocks in the columns `rows[p]`
    /// (increasing, `p` excluded, symmetric pattern).
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] with more than 2³² nodes.
    pub fn zeros(rows: impl Iterator<Item = Vec<usize>>) -> Result<Self> {
        let empty = || Triangle {
            ptr: vec![0],
            col: Vec::new(),
            val: Vec::new(),
        };
        let (mut lower, mut upper) = (empty(), empty());
        let mut nodes = 0;
        for (p, cols) in rows.enumerate() {
            for q in cols {
                debug_assert!(q != p);
                let t = if q < p { &mut lower } else { &mut upper };
                t.col.push(u32::try_from(q).map_err(|_| {
                    ProblemError::InvalidMatrix("more than 2^32 nodes are not supported".into())
                })?);
            }
            lower.ptr.push(lower.col.len());
            upper.ptr.push(upper.col.len());
            nodes = p + 1;
        }
        for t in [&mut lower, &mut upper] {
            // No spare capacity kept from the growth.
            t.col.shrink_to_fit();
            t.val = vec![[[0.0; D]; D]; t.col.len()];
        }
        Ok(Self {
            lower: Arc::new(lower),
            upper: Arc::new(upper),
            diag: vec![[[0.0; D]; D]; nodes],
        })
    }

    /// The block matrix of the symmetric-pattern faer matrix `a` (`D n × D n`, node-major),
    /// checked: [`from_csc`](Self::from_csc) of its copy after
    /// [`Csc::check_symmetric_pattern`].
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] if `a` is not square, its pattern is not symmetric,
    /// its dimension is not a multiple of `D`, or it has more than 2³² nodes;
    /// [`ProblemError::NonFinite`] for a non-finite entry.
    pub fn from_symmetric(a: SparseColMatRef<'_, usize, f64>) -> Result<Self> {
        let csc = Csc::from_faer(a)?;
        csc.check_symmetric_pattern()?;
        Self::from_csc(&csc)
    }

    /// Blocks a square scalar matrix with symmetric pattern and dimension divisible by `D`
    /// (node-major).
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] if the matrix is not square or its dimension is not a
    /// multiple of `D`.
    pub fn from_csc(a: &Csc) -> Result<Self> {
        if a.nrows != a.ncols || a.nrows % D != 0 {
            return Err(ProblemError::InvalidMatrix(format!(
                "matrix is {}x{}, expected square with a dimension divisible by the block size {D}",
                a.nrows, a.ncols
            ))
            .into());
        }
        let nodes = a.nrows / D;
        // Column j of A is read as row j (the entry (i, j) is stored as (j, i)): exact for
        // a symmetric matrix, and a single pass over the columns.
        let mut marker = vec![usize::MAX; nodes];
        let rows = (0..nodes).map(|p| {
            let mut cols = Vec::new();
            for c in 0..D {
                for &i in a.col(D * p + c).0 {
                    let q = i / D;
                    if q != p && marker[q] != p {
                        marker[q] = p;
                        cols.push(q);
                    }
                }
            }
            cols.sort_unstable();
            cols
        });
        let mut m = Self::zeros(rows)?;
        let (lower, upper) = (Arc::make_mut(&mut m.lower), Arc::make_mut(&mut m.upper));
        for p in 0..nodes {
            for c in 0..D {
                let (rows, vals) = a.col(D * p + c);
                for (&i, &v) in rows.iter().zip(vals) {
                    let (q, cc) = (i / D, i % D);
                    let blk = if q == p {
                        &mut m.diag[p]
                    } else {
                        let t = if q < p { &mut *lower } else { &mut *upper };
                        let r = t.range(p);
                        let k = r.start
                            + t.col[r]
                                .binary_search(&(q as u32))
                                .expect("column in pattern");
                        &mut t.val[k]
                    };
                    blk[c][cc] = v;
                }
            }
        }
        Ok(m)
    }

    /// Number of node rows.
    #[inline]
    pub fn nodes(&self) -> usize {
        self.diag.len()
    }

    /// Number of scalar rows.
    #[inline]
    pub fn n(&self) -> usize {
        D * self.diag.len()
    }

    /// Off-diagonal blocks of row `p` in increasing column order: `(q, A_pq)`.
    pub fn neighbours(&self, p: usize) -> impl Iterator<Item = (usize, &Block<D>)> {
        let (l, u) = (self.lower.range(p), self.upper.range(p));
        let lower = self.lower.col[l.clone()].iter().zip(&self.lower.val[l]);
        let upper = self.upper.col[u.clone()].iter().zip(&self.upper.val[u]);
        lower.chain(upper).map(|(&q, b)| (q as usize, b))
    }

    /// `res = rhs − A x`, one pass over the upper triangle (the lower couplings are
    /// pushed through the transposed blocks into `w`, which must be 0 on entry and is 0
    /// on return).
    pub fn residual(&self, rhs: &[f64], x: &[f64], res: &mut [f64], w: &mut [f64]) {
        for p in 0..self.nodes() {
            let xp = load::<D>(x, p);
            let mut s = take::<D>(w, p);
            for (sc, r) in s.iter_mut().zip(&rhs[D * p..D * p + D]) {
                *sc += r;
            }
            sub_mul_vec(&mut s, &self.diag[p], &xp);
            self.upper.sub_row(p, x, &mut s);
            store(res, p, &s);
            self.upper.push_row(p, &xp, w);
        }
    }

    /// `res = rhs − A x` row by row over full rows (diagonal block, then the off-diagonal
    /// blocks in increasing column order), the rows split into at most `par.threads()`
    /// contiguous chunks: each row is computed by one thread with the same arithmetic, so
    /// the result is bit-identical for every thread count (but rounds differently from
    /// [`residual`](Self::residual)).
    pub fn residual_rows(&self, rhs: &[f64], x: &[f64], res: &mut [f64], par: Parallelism) {
        for_node_rows::<D>(res, (par, RESIDUAL_PARALLEL_MIN), |p, out| {
            let mut s = load::<D>(rhs, p);
            sub_mul_vec(&mut s, &self.diag[p], &load::<D>(x, p));
            for (q, blk) in self.neighbours(p) {
                sub_mul_vec(&mut s, blk, &load::<D>(x, q));
            }
            out.copy_from_slice(&s);
        });
    }

    /// `xᵀ A x` (one pass over the upper triangle).
    pub fn quadratic_form(&self, x: &[f64]) -> f64 {
        self.quadratic_form_par(x, Parallelism::SEQ, &mut Vec::new())
    }

    /// [`quadratic_form`](Self::quadratic_form) with the rows' terms computed on `par`'s
    /// threads and added in the sequential order ([`ordered_sum`]): the same bits for
    /// every thread count. `scratch` (one entry per node) is kept by the caller.
    pub fn quadratic_form_par(
        &self,
        x: &[f64],
        par: Parallelism,
        scratch: &mut Vec<Option<[f64; D]>>,
    ) -> f64 {
        ordered_sum(self.nodes(), par, scratch, |p| {
            let xp = load::<D>(x, p);
            if xp.iter().all(|&v| v == 0.0) {
                return None;
            }
            let d = mul_vec(&self.diag[p], &xp);
            let mut s = [0.0; D];
            self.upper.sub_row(p, x, &mut s);
            Some(std::array::from_fn(|c| xp[c] * (d[c] - 2.0 * s[c])))
        })
    }

    /// One Gauss–Seidel sweep over the nodes (increasing order, or decreasing when
    /// `order.reverse`): for each node `p`, `s = rhs_p − Σ_{q≠p} A_pq x_q` (with the already
    /// updated values of the nodes visited before) and `local(p, s, x_p)` updates the block
    /// `x_p` in place (e.g. `x_p = A_pp⁻¹ s`). With `order.zero_start` the sweep starts from
    /// `x = 0` whatever `x` holds (the couplings to nodes not yet visited are skipped and
    /// `local` sees `x_p = 0`), so a first sweep needs no zeroed vector and half the work.
    ///
    /// The forward sweep reads only the upper triangle, the backward one only the lower
    /// one: the couplings to nodes already visited were pushed into `w` when those nodes
    /// were updated. `w` (length `n`) must be 0 on entry and is 0 on return.
    pub fn sweep<F>(
        &self,
        rhs: &[f64],
        x: &mut [f64],
        w: &mut [f64],
        order: SweepOrder,
        mut local: F,
    ) where
        F: FnMut(usize, &[f64; D], &mut [f64; D]),
    {
        let SweepOrder {
            reverse,
            zero_start,
        } = order;
        let nodes = self.nodes();
        let ahead = if reverse { &self.lower } else { &self.upper };
        for k in 0..nodes {
            let p = if reverse { nodes - 1 - k } else { k };
            // w_p = −Σ (couplings of p to the nodes visited before p); no later pushes.
            let mut s = take::<D>(w, p);
            for (sc, r) in s.iter_mut().zip(&rhs[D * p..D * p + D]) {
                *sc += r;
            }
            let mut xp = [0.0; D];
            if !zero_start {
                ahead.sub_row(p, x, &mut s);
                xp = load::<D>(x, p);
            }
            local(p, &s, &mut xp);
            store(x, p, &xp);
            ahead.push_row(p, &xp, w);
        }
    }

    /// The matrix as CSC with every stored block dense (explicit zeros kept), rows sorted;
    /// `map[k]` is the position of CSC entry `k` in the order of
    /// [`flat_value`](Self::flat_value).
    pub fn csc_pattern(&self) -> (Csc, Vec<usize>) {
        let nodes = self.nodes();
        let dd = D * D;
        let (lower_base, upper_base) = (nodes * dd, (nodes + self.lower.col.len()) * dd);
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut map = Vec::new();
        for q in 0..nodes {
            // Column D q + c: the rows of block row q (symmetric pattern); entry
            // (D p + rr, D q + c) = entry (D q + c, D p + rr), read from row q's block p.
            let blocks = self
                .lower
                .range(q)
                .map(|k| (self.lower.col[k] as usize, lower_base + k * dd));
            let diag = std::iter::once((q, q * dd));
            let upper = self
                .upper
                .range(q)
                .map(|k| (self.upper.col[k] as usize, upper_base + k * dd));
            let row: Vec<(usize, usize)> = blocks.chain(diag).chain(upper).collect();
            for c in 0..D {
                for &(p, flat) in &row {
                    for rr in 0..D {
                        row_idx.push(D * p + rr);
                        map.push(flat + c * D + rr);
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        let nnz = row_idx.len();
        (
            Csc {
                nrows: D * nodes,
                ncols: D * nodes,
                col_ptr,
                row_idx,
                val: vec![0.0; nnz],
            },
            map,
        )
    }

    /// Entry `k` of the flat value order: the diagonal blocks (`D²` per node, row-major),
    /// then the lower and the upper triangle's blocks.
    #[inline]
    pub fn flat_value(&self, k: usize) -> f64 {
        let dd = D * D;
        let (nodes, nl) = (self.nodes(), self.lower.col.len());
        let (blk, within) = if k < nodes * dd {
            (&self.diag[k / dd], k % dd)
        } else if k < (nodes + nl) * dd {
            let k = k - nodes * dd;
            (&self.lower.val[k / dd], k % dd)
        } else {
            let k = k - (nodes + nl) * dd;
            (&self.upper.val[k / dd], k % dd)
        };
        blk[within / D][within % D]
    }
}

/// A symmetric node pattern: the nodes and each node's neighbours in increasing order
/// (what the colourings, the Galerkin patterns and the incremental updates' row sets
/// are derived from; no values).
pub trait NodePattern {
    /// Number of nodes.
    fn nodes(&self) -> usize;
    /// The neighbours of node `p` (`q ≠ p` with a stored block), increasing.
    fn node_neighbours(&self, p: usize) -> impl Iterator<Item = usize> + '_;
}

impl<const D: usize> NodePattern for BlockCsr<D> {
    fn nodes(&self) -> usize {
        BlockCsr::nodes(self)
    }
    fn node_neighbours(&self, p: usize) -> impl Iterator<Item = usize> + '_ {
        self.neighbours(p).map(|(q, _)| q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric matrix with a 2×2 block structure and missing entries.
    fn sample() -> Csc {
        let n = 8;
        let mut dense = vec![vec![0.0; n]; n];
        for i in 0..n {
            dense[i][i] = 10.0 + i as f64;
            for j in 0..i {
                if (i * 7 + j * 3) % 4 == 0 {
                    let v = ((i * 5 + j) % 7) as f64 - 3.0;
                    dense[i][j] = v;
                    dense[j][i] = v;
                }
            }
        }
        Csc::from_dense(&dense)
    }

    /// Residual, quadratic form, the CSC copy and both sweep directions (replayed with
    /// explicit scalar row products) against the scalar matrix.
    #[test]
    fn block_kernels_match_the_scalar_matrix() {
        let a = sample();
        let b = BlockCsr::<2>::from_csc(&a).unwrap();
        let x: Vec<f64> = (0..8).map(|i| (i as f64 * 0.7).sin()).collect();
        let rhs: Vec<f64> = (0..8).map(|i| i as f64 - 3.5).collect();
        let mut ax = vec![0.0; 8];
        a.sym_mul(&x, &mut ax);
        let close = |y: &[f64], z: &[f64]| y.iter().zip(z).all(|(a, b)| (a - b).abs() < 1e-12);
        let mut res = vec![0.0; 8];
        let mut w = vec![0.0; 8];
        b.residual(&rhs, &x, &mut res, &mut w);
        assert!(w.iter().all(|&v| v == 0.0));
        let want: Vec<f64> = rhs.iter().zip(&ax).map(|(r, y)| r - y).collect();
        assert!(close(&res, &want));
        let q = b.quadratic_form(&x);
        assert!(
            (q - a.quadratic_form_par(&x, Parallelism::SEQ, &mut Vec::new())).abs()
                < 1e-12 * q.abs()
        );
        let (mut c, map) = b.csc_pattern();
        for (v, &k) in c.val.iter_mut().zip(&map) {
            *v = b.flat_value(k);
        }
        let mut y = vec![0.0; 8];
        c.sym_mul(&x, &mut y);
        assert!(close(&y, &ax));
        for reverse in [false, true] {
            let mut xs = x.clone();
            let mut w = vec![0.0; 8];
            let local = |p: usize, s: &[f64; 2], xp: &mut [f64; 2]| {
                xp[0] = 0.1 * s[0] + p as f64 + 0.01 * xp[1];
                xp[1] = 0.05 * s[1];
            };
            b.sweep(&rhs, &mut xs, &mut w, SweepOrder::from_x(reverse), local);
            assert!(w.iter().all(|&v| v == 0.0));
            // A zero start on garbage equals a sweep from zero.
            let (mut from_zero, mut garbage) = (vec![0.0; 8], vec![7.0; 8]);
            b.sweep(
                &rhs,
                &mut from_zero,
                &mut w,
                SweepOrder::from_x(reverse),
                local,
            );
            let from_zero_order = SweepOrder {
                reverse,
                zero_start: true,
            };
            b.sweep(&rhs, &mut garbage, &mut w, from_zero_order, local);
            assert_eq!(from_zero, garbage);
            // Replay the sweep with explicit row products.
            let mut xr = x.clone();
            let order: Vec<usize> = if reverse {
                (0..4).rev().collect()
            } else {
                (0..4).collect()
            };
            for p in order {
                let mut s = [rhs[2 * p], rhs[2 * p + 1]];
                for r in 0..2 {
                    let i = 2 * p + r;
                    let (rows, vals) = a.col(i);
                    for (&j, &v) in rows.iter().zip(vals) {
                        if j / 2 != p {
                            s[r] -= v * xr[j];
                        }
                    }
                }
                xr[2 * p] = 0.1 * s[0] + p as f64 + 0.01 * xr[2 * p + 1];
                xr[2 * p + 1] = 0.05 * s[1];
            }
            assert!(close(&xs, &xr), "reverse {reverse}");
        }
    }
}
