//! A minimal compressed-sparse-column matrix used inside the solvers.
//!
//! The solvers' public APIs (`rsf-tnnmg`, `rsf-direct`) take and return
//! `faer::sparse::SparseColMat<usize, f64>`; internally they keep plain arrays so that
//! kernels (Gauss–Seidel, Galerkin products, the partial Cholesky's scatter) are simple,
//! allocation-free loops over a fixed pattern.

use crate::error::ProblemError;

/// The result of [`Csc`]'s checks: the shared vocabulary of the solvers' inputs.
type Result<T> = std::result::Result<T, ProblemError>;
use crate::parallelism::Parallelism;
use crate::reduce::ordered_sum;
use faer::sparse::SparseColMatRef;

/// Compressed sparse column matrix with sorted row indices in every column (the solvers'
/// internal format; `rsf-tnnmg` and `rsf-direct` share it).
#[derive(Debug, Clone, PartialEq)]
pub struct Csc {
    /// Number of rows.
    pub nrows: usize,
    /// Number of columns.
    pub ncols: usize,
    /// Start of each column in `row_idx` and `val` (length `ncols + 1`).
    pub col_ptr: Vec<usize>,
    /// Row index of each stored entry, increasing within a column.
    pub row_idx: Vec<usize>,
    /// Value of each stored entry.
    pub val: Vec<f64>,
}

impl Csc {
    /// Copies a faer matrix (any column storage; rows sorted and duplicates summed here).
    ///
    /// # Errors
    /// [`ProblemError::NonFinite`] for a non-finite entry.
    pub fn from_faer(m: SparseColMatRef<'_, usize, f64>) -> Result<Self> {
        let (nrows, ncols) = (m.nrows(), m.ncols());
        let mut col_ptr = Vec::with_capacity(ncols + 1);
        // At most the stored entries (duplicates merge): no growth by doubling, which held
        // up to twice a large matrix's memory and copied it while growing.
        let nnz = m.compute_nnz();
        let mut row_idx = Vec::with_capacity(nnz);
        let mut val = Vec::with_capacity(nnz);
        col_ptr.push(0);
        let mut entries: Vec<(usize, f64)> = Vec::new();
        for j in 0..ncols {
            entries.clear();
            entries.extend(m.row_idx_of_col(j).zip(m.val_of_col(j).iter().copied()));
            entries.sort_by_key(|e| e.0);
            for &(i, v) in entries.iter() {
                if !v.is_finite() {
                    return Err(ProblemError::NonFinite("matrix entries"));
                }
                if row_idx.len() > col_ptr[j] && *row_idx.last().unwrap() == i {
                    *val.last_mut().unwrap() += v;
                } else {
                    row_idx.push(i);
                    val.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        Ok(Self {
            nrows,
            ncols,
            col_ptr,
            row_idx,
            val,
        })
    }

    /// The nonzero entries of a dense matrix (rows of `dense`), for tests.
    pub fn from_dense(dense: &[Vec<f64>]) -> Self {
        let (nrows, ncols) = (dense.len(), dense.first().map_or(0, Vec::len));
        let mut col_ptr = vec![0];
        let (mut row_idx, mut val) = (Vec::new(), Vec::new());
        for j in 0..ncols {
            for (i, row) in dense.iter().enumerate() {
                if row[j] != 0.0 {
                    row_idx.push(i);
                    val.push(row[j]);
                }
            }
            col_ptr.push(row_idx.len());
        }
        Self {
            nrows,
            ncols,
            col_ptr,
            row_idx,
            val,
        }
    }

    /// Row indices and values of column `j`.
    #[inline]
    pub fn col(&self, j: usize) -> (&[usize], &[f64]) {
        let r = self.col_ptr[j]..self.col_ptr[j + 1];
        (&self.row_idx[r.clone()], &self.val[r])
    }

    /// Position of entry (i, j) in `val`, if structurally present.
    pub fn position(&self, i: usize, j: usize) -> Option<usize> {
        let r = self.col_ptr[j]..self.col_ptr[j + 1];
        self.row_idx[r.clone()]
            .binary_search(&i)
            .ok()
            .map(|k| r.start + k)
    }

    /// Positions of the diagonal entries.
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] if one is missing.
    pub fn diagonal_positions(&self) -> Result<Vec<usize>> {
        (0..self.ncols)
            .map(|j| {
                self.position(j, j).ok_or_else(|| {
                    ProblemError::InvalidMatrix(format!("diagonal entry ({j}, {j}) missing"))
                })
            })
            .collect()
    }

    /// `y = A x` for symmetric A (a reference for the block kernels' tests) (reads columns as rows; valid for any A as `y = Aᵀ x`
    /// computed row-wise, which equals `A x` when A is symmetric).
    pub fn sym_mul(&self, x: &[f64], y: &mut [f64]) {
        for (j, yj) in y.iter_mut().enumerate() {
            let (rows, vals) = self.col(j);
            let mut s = 0.0;
            for (&i, &a) in rows.iter().zip(vals) {
                s += a * x[i];
            }
            *yj = s;
        }
    }

    /// Row `j` dot `x` for symmetric A.
    pub fn sym_row_dot(&self, j: usize, x: &[f64]) -> f64 {
        let (rows, vals) = self.col(j);
        let mut s = 0.0;
        for (&i, &a) in rows.iter().zip(vals) {
            s += a * x[i];
        }
        s
    }

    /// `xᵀ A x` for symmetric A (the energy norms of `rsf_nonsmooth::FullStep`): the
    /// columns' terms `x_j (A x)_j` (for `x_j ≠ 0`) computed on `par`'s threads and added
    /// in increasing `j` ([`ordered_sum`]), the same bits for every thread count.
    /// `scratch` (one entry per column) is kept by the caller.
    pub fn quadratic_form_par(
        &self,
        x: &[f64],
        par: Parallelism,
        scratch: &mut Vec<Option<[f64; 1]>>,
    ) -> f64 {
        ordered_sum(self.ncols, par, scratch, |j| {
            (x[j] != 0.0).then(|| [x[j] * self.sym_row_dot(j, x)])
        })
    }

    /// Checks that the matrix is square and structurally symmetric with a full diagonal.
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] naming the first entry that breaks it.
    pub fn check_symmetric_pattern(&self) -> Result<()> {
        if self.nrows != self.ncols {
            return Err(ProblemError::InvalidMatrix(format!(
                "matrix is {}x{}, expected square",
                self.nrows, self.ncols
            )));
        }
        for j in 0..self.ncols {
            let (rows, vals) = self.col(j);
            for (&i, &v) in rows.iter().zip(vals) {
                match self.position(j, i) {
                    Some(p) => {
                        let w = self.val[p];
                        if (v - w).abs() > 1e-10 * (v.abs() + w.abs()) {
                            return Err(ProblemError::InvalidMatrix(format!(
                                "not symmetric at ({i}, {j}): {v} vs {w}"
                            )));
                        }
                    }
                    None => {
                        return Err(ProblemError::InvalidMatrix(format!(
                            "pattern not symmetric at ({i}, {j})"
                        )))
                    }
                }
            }
        }
        self.diagonal_positions().map(|_| ())
    }
}
