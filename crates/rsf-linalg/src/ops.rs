//! The CSC matrix type and the elementary sparse operations on it.

use faer::sparse::{SparseColMat, SparseColMatRef};

use crate::error::{faer_err, Error, Result};

/// Sparse matrix type used throughout rsf: compressed sparse columns, `usize` indices,
/// `f64` values (faer's `SparseColMat`).
pub type SparseMatrix = SparseColMat<usize, f64>;

/// `c_a A + c_b B` for two matrices with the **same pattern** (e.g. `A = c_M M + c_K K`
/// of docs/math.md §2, both from one `rsf_fem::Assembler`).
///
/// # Errors
/// [`Error::PatternMismatch`] if the shapes or patterns differ; [`Error::Faer`] if the
/// pattern cannot be copied (allocation failure).
pub fn combine(ca: f64, a: &SparseMatrix, cb: f64, b: &SparseMatrix) -> Result<SparseMatrix> {
    if a.nrows() != b.nrows()
        || a.ncols() != b.ncols()
        || a.symbolic().col_ptr() != b.symbolic().col_ptr()
        || a.symbolic().row_idx() != b.symbolic().row_idx()
    {
        return Err(Error::PatternMismatch);
    }
    let vals = a
        .val()
        .iter()
        .zip(b.val())
        .map(|(x, y)| ca * x + cb * y)
        .collect();
    Ok(SparseColMat::new(
        a.symbolic().to_owned().map_err(faer_err)?,
        vals,
    ))
}

/// `y ← y + α A x` for a CSC matrix (no allocation).
///
/// # Panics
/// If the lengths do not match `A`'s shape (internal invariant of callers).
pub fn spmv_add(a: SparseColMatRef<'_, usize, f64>, alpha: f64, x: &[f64], y: &mut [f64]) {
    assert_eq!(x.len(), a.ncols());
    assert_eq!(y.len(), a.nrows());
    for j in 0..a.ncols() {
        let xj = alpha * x[j];
        if xj == 0.0 {
            continue;
        }
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            y[i] += v * xj;
        }
    }
}

/// The quadratic form `xᵀ A x` of a CSC matrix (no allocation; summed column by column,
/// so the result is the same on every machine and thread count).
///
/// # Panics
/// If `x.len()` is not `A`'s size (internal invariant of callers).
pub fn quadratic_form(a: SparseColMatRef<'_, usize, f64>, x: &[f64]) -> f64 {
    assert_eq!(x.len(), a.ncols());
    assert_eq!(x.len(), a.nrows());
    let mut s = 0.0;
    for j in 0..a.ncols() {
        let mut col = 0.0;
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            col += v * x[i];
        }
        s += col * x[j];
    }
    s
}
