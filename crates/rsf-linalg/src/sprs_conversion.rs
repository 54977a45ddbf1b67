//! Conversions between [`SparseMatrix`] and `sprs::CsMat<f64>` in CSC storage (feature
//! `sprs`), through the raw column pointers, row indices and values.

use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use std::ops::Deref;

use sprs::{CsMat, CsMatBase};

use crate::error::{Error, ProblemError, Result};
use crate::ops::SparseMatrix;

/// Checks a compressed sparse column structure: `col_ptr` of length `ncols + 1` starting
/// at 0 and nondecreasing, `row_idx` and `values` of length `col_ptr[ncols]`, row indices
/// strictly increasing within each column (sorted, no duplicates) and below `nrows`.
fn check_csc(nrows: usize, col_ptr: &[usize], row_idx: &[usize], values: &[f64]) -> Result<()> {
    let ncols = col_ptr.len().saturating_sub(1);
    if col_ptr.first() != Some(&0) {
        return Err(Error::InvalidStructure {
            column: 0,
            reason: "the column pointers do not start at 0",
        });
    }
    let nnz = col_ptr[ncols];
    for (what, len) in [("row indices", row_idx.len()), ("values", values.len())] {
        if len != nnz {
            return Err(ProblemError::DimensionMismatch {
                what,
                expected: nnz,
                got: len,
            }
            .into());
        }
    }
    for j in 0..ncols {
        let (start, end) = (col_ptr[j], col_ptr[j + 1]);
        if end < start || end > nnz {
            return Err(Error::InvalidStructure {
                column: j,
                reason: "the column pointers decrease or exceed the number of entries",
            });
        }
        let rows = &row_idx[start..end];
        if rows.iter().any(|&i| i >= nrows) {
            return Err(Error::InvalidStructure {
                column: j,
                reason: "a row index is not below the number of rows",
            });
        }
        if rows.windows(2).any(|w| w[0] >= w[1]) {
            return Err(Error::InvalidStructure {
                column: j,
                reason: "the row indices are not strictly increasing (unsorted or duplicated)",
            });
        }
    }
    Ok(())
}

/// `a` as a `sprs::CsMat<f64>` in CSC storage, same shape, entries and order (explicit
/// zeros are kept).
///
/// # Errors
/// [`Error::InvalidStructure`] if `a`'s row indices are not sorted and unique in every
/// column (faer admits unsorted matrices, sprs does not).
pub fn to_sprs(a: &SparseMatrix) -> Result<CsMat<f64>> {
    let (nrows, ncols) = (a.nrows(), a.ncols());
    let nnz = a.compute_nnz();
    let mut col_ptr = Vec::with_capacity(ncols + 1);
    let mut row_idx = Vec::with_capacity(nnz);
    let mut values = Vec::with_capacity(nnz);
    col_ptr.push(0);
    // Column by column, so that a faer matrix with per-column counts (`col_nnz`) is
    // compacted.
    for j in 0..ncols {
        row_idx.extend_from_slice(a.row_idx_of_col_raw(j));
        values.extend_from_slice(a.val_of_col(j));
        col_ptr.push(row_idx.len());
    }
    check_csc(nrows, &col_ptr, &row_idx, &values)?;
    CsMat::try_new_csc((nrows, ncols), col_ptr, row_idx, values).map_err(|_| {
        Error::InvalidStructure {
            column: 0,
            reason: "rejected by sprs",
        }
    })
}

/// A `sprs` CSC matrix (a `CsMat<f64>` or a view such as `CsMatView<f64>`) as a
/// [`SparseMatrix`], same shape, entries and order (explicit zeros are kept).
///
/// # Errors
/// [`Error::RowStorage`] for a CSR matrix (convert it with `to_csc()` first);
/// [`Error::InvalidStructure`] or [`ProblemError::DimensionMismatch`] for an inconsistent
/// structure (not expected from a valid `CsMat`).
pub fn from_sprs<IptrStorage, IndStorage, DataStorage>(
    a: &CsMatBase<f64, usize, IptrStorage, IndStorage, DataStorage>,
) -> Result<SparseMatrix>
where
    IptrStorage: Deref<Target = [usize]>,
    IndStorage: Deref<Target = [usize]>,
    DataStorage: Deref<Target = [f64]>,
{
    if !a.is_csc() {
        return Err(Error::RowStorage);
    }
    let (nrows, ncols) = a.shape();
    // A view into a larger matrix has pointers that do not start at 0 (its indices and
    // values are already the view's own).
    let col_ptr: Vec<usize> = a.indptr().to_proper().to_vec();
    ProblemError::check_length("sprs column pointers", ncols + 1, col_ptr.len())?;
    let (row_idx, values) = (a.indices().to_vec(), a.data().to_vec());
    check_csc(nrows, &col_ptr, &row_idx, &values)?;
    Ok(SparseColMat::new(
        SymbolicSparseColMat::new_checked(nrows, ncols, col_ptr, None, row_idx),
        values,
    ))
}
