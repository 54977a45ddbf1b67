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
//! The factorisation is faer's (supernodal or simplicial, sequential); the factor is then
//! stored as a lower-triangular CSC matrix with `u32` row indices and the diagonal first in
//! every column, exact zeros of relaxed supernodes dropped, for the sweeps.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::{amd, SupernodalThreshold};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Par, Side};

use crate::csc::Csc;
use crate::error::{Error, Result};

/// `L` of `P A Pᵀ = L Lᵀ` for the ordering `[R (fill-reducing), F (as given)]`, in faer's
/// supernodal layout: supernode `s` covers columns `start[s]..start[s + 1]` (width `w`),
/// its rows are the `w` diagonal-block rows followed by `rows[row_ptr[s]..row_ptr[s + 1]]`,
/// and its values are a dense column-major `(w + p) × w` block at `val_ptr[s]`.
#[derive(Debug, Clone)]
pub(crate) struct PartialCholesky {
    /// Number of interior columns `|R|`.
    pub nr: usize,
    /// Total dimension `|R| + |F|`.
    pub n: usize,
    start: Vec<usize>,
    row_ptr: Vec<usize>,
    rows: Vec<u32>,
    val_ptr: Vec<usize>,
    val: Vec<f64>,
    /// Scratch of the length of the longest supernode pattern.
    tmp: Vec<f64>,
}

/// `Σ a_i b_i` with four independent partial sums (a fixed order: deterministic, and not
/// bound by the latency of one chain of additions).
#[inline]
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

/// Fill-reducing (AMD) order of the rows/columns `idx` of the symmetric matrix `a`:
/// returns the entries of `idx` reordered.
fn amd_order(a: &Csc, idx: &[usize]) -> Result<Vec<usize>> {
    let n = idx.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let mut local = vec![usize::MAX; a.nrows];
    for (k, &i) in idx.iter().enumerate() {
        local[i] = k;
    }
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::new();
    col_ptr.push(0);
    for &j in idx {
        let (rows, _) = a.col(j);
        row_idx.extend(rows.iter().map(|&i| local[i]).filter(|&i| i != usize::MAX));
        col_ptr.push(row_idx.len());
    }
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

impl PartialCholesky {
    /// Factorises the principal submatrix of `a` (symmetric, both triangles stored) on the
    /// rows/columns `interior ∪ interface`, eliminating `interior` first (in a fill-reducing
    /// order) and `interface` last (in the given order). Returns the factor and the
    /// elimination order (`order[k]` = the row of `a` of column `k` of `L`).
    ///
    /// # Errors
    /// [`Error::NotPositiveDefinite`] if the submatrix is not numerically SPD;
    /// [`Error::Factorisation`] if faer fails (e.g. out of memory) or the factor has more
    /// than `u32::MAX` rows.
    pub fn new(a: &Csc, interior: &[usize], interface: &[usize]) -> Result<(Self, Vec<usize>)> {
        let mut order = amd_order(a, interior)?;
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
        let mut values = Vec::new();
        col_ptr.push(0);
        for &j in &sorted {
            let (rows, vals) = a.col(j);
            for (&i, &v) in rows.iter().zip(vals) {
                if local[i] != usize::MAX {
                    row_idx.push(local[i]);
                    values.push(v);
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
        let req: StackReq =
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
        let mut mem = MemBuffer::try_new(req).map_err(faer_err)?;
        let mut l_values = vec![0.0; symbolic.len_val()];
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut l_values,
                SparseColMatRef::new(pattern.as_ref(), &values),
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|_| Error::NotPositiveDefinite("A on the free dofs"))?;
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
        let longest = (0..ns)
            .map(|s| row_ptr[s + 1] - row_ptr[s])
            .max()
            .unwrap_or(0);
        let factor = Self {
            nr: interior.len(),
            n,
            start,
            row_ptr,
            rows,
            val_ptr,
            val: l_values,
            tmp: vec![0.0; longest],
        };
        Ok((factor, order))
    }

    /// Supernode `s`: (first column, width, pattern below the diagonal block, values).
    #[inline]
    fn supernode(&self, s: usize) -> (usize, usize, &[u32], &[f64]) {
        let c0 = self.start[s];
        let w = self.start[s + 1] - c0;
        (
            c0,
            w,
            &self.rows[self.row_ptr[s]..self.row_ptr[s + 1]],
            &self.val[self.val_ptr[s]..self.val_ptr[s + 1]],
        )
    }

    fn num_supernodes(&self) -> usize {
        self.start.len() - 1
    }

    /// Stored entries of `L` (including explicit zeros of relaxed supernodes).
    pub fn nnz(&self) -> usize {
        self.val.len()
    }

    /// Forward sweep over the interior columns: `y ← [L_R⁻¹ y_R; y_F − B L_R⁻¹ y_R]`
    /// (`y` in elimination order, length `n`).
    pub fn forward_interior(&mut self, y: &mut [f64]) {
        let mut tmp = std::mem::take(&mut self.tmp);
        for s in 0..self.num_supernodes() {
            let (c0, w, pattern, l) = self.supernode(s);
            if c0 >= self.nr {
                break;
            }
            let wr = w.min(self.nr - c0);
            let ld = w + pattern.len();
            for jj in 0..wr {
                let col = &l[jj * ld..(jj + 1) * ld];
                let yj = y[c0 + jj] / col[jj];
                y[c0 + jj] = yj;
                for (yi, lij) in y[c0 + jj + 1..c0 + w].iter_mut().zip(&col[jj + 1..w]) {
                    *yi -= lij * yj;
                }
            }
            let tmp = &mut tmp[..pattern.len()];
            tmp.fill(0.0);
            for jj in 0..wr {
                let yj = y[c0 + jj];
                if yj != 0.0 {
                    let below = &l[jj * ld + w..(jj + 1) * ld];
                    for (t, lij) in tmp.iter_mut().zip(below) {
                        *t += lij * yj;
                    }
                }
            }
            for (&i, t) in pattern.iter().zip(tmp.iter()) {
                y[i as usize] -= t;
            }
        }
        self.tmp = tmp;
    }

    /// Backward sweep over the interior columns: `y_R ← L_R⁻ᵀ (y_R − Bᵀ y_F)`.
    pub fn backward_interior(&mut self, y: &mut [f64]) {
        let mut tmp = std::mem::take(&mut self.tmp);
        for s in (0..self.num_supernodes()).rev() {
            let (c0, w, pattern, l) = self.supernode(s);
            if c0 >= self.nr {
                continue;
            }
            let wr = w.min(self.nr - c0);
            let ld = w + pattern.len();
            let tmp = &mut tmp[..pattern.len()];
            for (t, &i) in tmp.iter_mut().zip(pattern) {
                *t = y[i as usize];
            }
            for jj in 0..wr {
                let below = &l[jj * ld + w..(jj + 1) * ld];
                y[c0 + jj] -= dot(below, tmp);
            }
            for jj in (0..wr).rev() {
                let col = &l[jj * ld..(jj + 1) * ld];
                let mut acc = y[c0 + jj];
                for (lij, yi) in col[jj + 1..w].iter().zip(&y[c0 + jj + 1..c0 + w]) {
                    acc -= lij * yi;
                }
                y[c0 + jj] = acc / col[jj];
            }
        }
        self.tmp = tmp;
    }

    /// `S = L_F L_Fᵀ`, the Schur complement on the interface, dense column-major
    /// (`|F| × |F|`, symmetric).
    pub fn schur_complement(&self) -> Vec<f64> {
        let (nr, nf) = (self.nr, self.n - self.nr);
        // Dense L_F (lower, column-major).
        let mut lf = vec![0.0; nf * nf];
        for s in 0..self.num_supernodes() {
            let (c0, w, pattern, l) = self.supernode(s);
            let ld = w + pattern.len();
            for jj in 0..w {
                let j = c0 + jj;
                if j < nr {
                    continue;
                }
                let col = &l[jj * ld..(jj + 1) * ld];
                for ii in jj..w {
                    lf[(j - nr) * nf + (c0 + ii - nr)] = col[ii];
                }
                for (k, &i) in pattern.iter().enumerate() {
                    lf[(j - nr) * nf + (i as usize - nr)] = col[w + k];
                }
            }
        }
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
mod tests {
    use super::*;

    /// 1-D Laplacian plus identity, n × n.
    fn matrix(n: usize) -> Csc {
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut val = Vec::new();
        for j in 0..n {
            for i in j.saturating_sub(1)..(j + 2).min(n) {
                row_idx.push(i);
                val.push(if i == j { 3.0 } else { -1.0 });
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

    /// The sweeps reproduce the condensed right-hand side, the Schur complement and the
    /// interior recovery computed densely.
    #[test]
    fn partial_sweeps_match_dense_condensation() {
        let n = 12;
        let a = matrix(n);
        let ad = dense(&a);
        let interface = [3usize, 7, 11];
        let interior: Vec<usize> = (0..n).filter(|i| !interface.contains(i)).collect();
        let (mut l, order) = PartialCholesky::new(&a, &interior, &interface).unwrap();
        assert_eq!(&order[interior.len()..], &interface);
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
        // Dense reference: S = A_FF − A_FR A_RR⁻¹ A_RF via Gaussian elimination.
        let nr = interior.len();
        let solve_rr = |rhs: &[f64]| -> Vec<f64> {
            // Gauss on the interior block.
            let mut m: Vec<Vec<f64>> = interior
                .iter()
                .map(|&i| interior.iter().map(|&j| ad[i][j]).collect())
                .collect();
            let mut x = rhs.to_vec();
            for p in 0..nr {
                for r in p + 1..nr {
                    let f = m[r][p] / m[p][p];
                    for c in p..nr {
                        m[r][c] -= f * m[p][c];
                    }
                    x[r] -= f * x[p];
                }
            }
            for p in (0..nr).rev() {
                let mut s = x[p];
                for c in p + 1..nr {
                    s -= m[p][c] * x[c];
                }
                x[p] = s / m[p][p];
            }
            x
        };
        let z = solve_rr(&interior.iter().map(|&i| b[i]).collect::<Vec<_>>());
        let mut y: Vec<f64> = order.iter().map(|&i| b[i]).collect();
        l.forward_interior(&mut y);
        for (f, &i) in interface.iter().enumerate() {
            let g: f64 = b[i]
                - interior
                    .iter()
                    .zip(&z)
                    .map(|(&r, zr)| ad[i][r] * zr)
                    .sum::<f64>();
            assert!((y[nr + f] - g).abs() < 1e-13, "condensed rhs {f}");
        }
        let s = l.schur_complement();
        for (fj, &j) in interface.iter().enumerate() {
            let col: Vec<f64> = interior.iter().map(|&r| ad[r][j]).collect();
            let w = solve_rr(&col);
            for (fi, &i) in interface.iter().enumerate() {
                let sij = ad[i][j]
                    - interior
                        .iter()
                        .zip(&w)
                        .map(|(&r, wr)| ad[i][r] * wr)
                        .sum::<f64>();
                assert!((s[fj * 3 + fi] - sij).abs() < 1e-13, "S[{fi},{fj}]");
            }
        }
        // Recovery with interface values x_F.
        let x_f = [0.3, -1.0, 2.0];
        for (f, &xf) in x_f.iter().enumerate() {
            y[nr + f] = xf;
        }
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
        let x_r = solve_rr(&rhs);
        for k in 0..nr {
            let pos = order.iter().position(|&i| i == interior[k]).unwrap();
            assert!((y[pos] - x_r[k]).abs() < 1e-13);
        }
    }
}
