//! Conversions between faer's `SparseMatrix` and `sprs::CsMat<f64>` (feature `sprs`).

use faer::sparse::{SparseColMat, SymbolicSparseColMat, Triplet};
use rsf_linalg::{from_sprs, spmv_add, to_sprs, Error, SparseMatrix};
use sprs::{CsMat, TriMat};

/// The 1-D Laplacian `tridiag(-1, 2, -1)` of size `n` plus a rectangular corner, with
/// repeated triplets (summed) and an explicit zero.
fn entries(n: usize) -> Vec<(usize, usize, f64)> {
    let mut t = Vec::new();
    for i in 0..n {
        t.push((i, i, 1.0));
        t.push((i, i, 1.0));
        if i + 1 < n {
            t.push((i + 1, i, -1.0));
            t.push((i, i + 1, -1.0));
        }
    }
    t.push((0, n - 1, 0.0));
    t.push((n, 2, 0.5));
    t
}

fn faer_matrix(n: usize) -> SparseMatrix {
    let t: Vec<_> = entries(n)
        .into_iter()
        .map(|(i, j, v)| Triplet::new(i, j, v))
        .collect();
    SparseColMat::try_new_from_triplets(n + 1, n, &t).unwrap()
}

fn sprs_matrix(n: usize) -> CsMat<f64> {
    let mut t = TriMat::new((n + 1, n));
    for (i, j, v) in entries(n) {
        t.add_triplet(i, j, v);
    }
    t.to_csc()
}

fn same(a: &SparseMatrix, b: &SparseMatrix) -> bool {
    let bits = |m: &SparseMatrix| m.val().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    a.nrows() == b.nrows()
        && a.ncols() == b.ncols()
        && a.symbolic().col_ptr() == b.symbolic().col_ptr()
        && a.symbolic().row_idx() == b.symbolic().row_idx()
        && bits(a) == bits(b)
}

#[test]
fn round_trip_is_exact() {
    let a = faer_matrix(7);
    let s = to_sprs(&a).unwrap();
    assert!(s.is_csc());
    assert_eq!(s.shape(), (8, 7));
    assert_eq!(s.nnz(), a.compute_nnz());
    let back = from_sprs(&s).unwrap();
    assert!(same(&a, &back));
}

#[test]
fn a_matrix_built_in_sprs_equals_the_faer_one() {
    // Both libraries sum the repeated triplets; the results agree entry by entry and as
    // operators.
    let a = faer_matrix(6);
    let s = sprs_matrix(6);
    let from = from_sprs(&s).unwrap();
    assert!(same(&a, &from), "{:?}\n{:?}", a, from);
    for j in 0..6 {
        for i in 0..7 {
            let fa = a
                .row_idx_of_col_raw(j)
                .iter()
                .position(|&r| r == i)
                .map_or(0.0, |k| a.val_of_col(j)[k]);
            assert_eq!(fa, s.get(i, j).copied().unwrap_or(0.0), "({i}, {j})");
        }
    }
    let x: Vec<f64> = (0..6).map(|k| 1.0 + k as f64 * 0.25).collect();
    let mut y = vec![0.0; 7];
    spmv_add(a.as_ref(), 1.0, &x, &mut y);
    let ys = &s * &sprs::CsVec::new(6, (0..6).collect(), x.clone());
    for i in 0..7 {
        assert_eq!(y[i], ys.get(i).copied().unwrap_or(0.0));
    }
}

#[test]
fn a_view_into_a_larger_sprs_matrix_converts() {
    // Columns 2..5 of a CSC matrix: its column pointers do not start at 0.
    let s = sprs_matrix(6);
    let view = s.slice_outer(2..5).to_owned();
    let sub = from_sprs(&view).unwrap();
    assert_eq!((sub.nrows(), sub.ncols()), (7, 3));
    let a = faer_matrix(6);
    for j in 0..3 {
        assert_eq!(sub.row_idx_of_col_raw(j), a.row_idx_of_col_raw(j + 2));
        assert_eq!(sub.val_of_col(j), a.val_of_col(j + 2));
    }
    let sub_view = from_sprs(&s.slice_outer(2..5)).unwrap();
    assert!(same(&sub, &sub_view));
}

#[test]
fn typed_errors() {
    // CSR storage is refused, not transposed silently.
    let csr = sprs_matrix(4).to_csr();
    assert!(matches!(from_sprs(&csr), Err(Error::RowStorage)));
    // faer admits unsorted row indices; sprs does not.
    let unsorted = SparseColMat::new(
        SymbolicSparseColMat::new_unsorted_checked(3, 2, vec![0, 2, 3], None, vec![2, 0, 1]),
        vec![1.0, 2.0, 3.0],
    );
    assert!(matches!(
        to_sprs(&unsorted),
        Err(Error::InvalidStructure { column: 0, .. })
    ));
}
