//! The sparse Cholesky wrapper: both orderings solve SPD systems, refactorisation from a
//! matrix and from a value array agree bit for bit, and misuse gives typed errors.

use faer::sparse::{SparseColMat, Triplet};
use rsf_linalg::{spmv_add, Cholesky, Error, FillOrdering, ProblemError, SparseMatrix};

/// A node-major 2-component field on a path of `n` nodes: `c·I + L ⊗ [[2, 1], [1, 2]]`
/// with `L` the path Laplacian (SPD for `c > 0`; full `2 × 2` node blocks, both triangles).
fn block_laplacian(n: usize, c: f64) -> SparseMatrix {
    let mut t = Vec::new();
    let block = [[2.0, 1.0], [1.0, 2.0]];
    for p in 0..n {
        for (q, w) in [(p.wrapping_sub(1), -1.0), (p, 2.0), (p + 1, -1.0)] {
            if q >= n {
                continue;
            }
            let w = if p == q && (p == 0 || p + 1 == n) {
                1.0
            } else {
                w
            };
            for a in 0..2 {
                for b in 0..2 {
                    let shift = if p == q && a == b { c } else { 0.0 };
                    t.push(Triplet::new(2 * p + a, 2 * q + b, w * block[a][b] + shift));
                }
            }
        }
    }
    SparseColMat::try_new_from_triplets(2 * n, 2 * n, &t).unwrap()
}

fn residual(a: &SparseMatrix, x: &[f64], b: &[f64]) -> f64 {
    let mut r: Vec<f64> = b.iter().map(|v| -v).collect();
    spmv_add(a.as_ref(), 1.0, x, &mut r);
    r.iter().fold(0.0, |m, v| m.max(v.abs()))
}

#[test]
fn both_orderings_solve_and_refactorise() {
    let n = 40;
    let a = block_laplacian(n, 0.5);
    let b: Vec<f64> = (0..2 * n).map(|i| (i as f64 * 0.7).sin()).collect();
    for ordering in [FillOrdering::GroupedAmd, FillOrdering::Amd] {
        let mut ch = Cholesky::analyze_with(a.symbolic(), ordering).unwrap();
        assert_eq!(ch.dim(), 2 * n);
        ch.factorize(a.as_ref()).unwrap();
        let x = ch.solve(&b).unwrap();
        assert!(residual(&a, &x, &b) < 1e-12, "{ordering:?}");
        // New values on the same pattern, once as a matrix and once as a value array.
        let a2 = block_laplacian(n, 3.0);
        ch.factorize(a2.as_ref()).unwrap();
        let x_matrix = ch.solve(&b).unwrap();
        assert!(residual(&a2, &x_matrix, &b) < 1e-12);
        ch.factorize_values(a2.val()).unwrap();
        let mut x_values = b.clone();
        ch.solve_in_place(&mut x_values).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&x_matrix), bits(&x_values));
    }
}

#[test]
fn typed_errors() {
    let a = block_laplacian(5, 1.0);
    let mut ch = Cholesky::analyze(a.symbolic()).unwrap();
    let mut rhs = vec![1.0; 10];
    assert!(matches!(
        ch.solve_in_place(&mut rhs),
        Err(Error::NotPositiveDefinite { .. })
    ));
    ch.factorize(a.as_ref()).unwrap();
    assert!(matches!(
        ch.solve(&rhs[1..]),
        Err(Error::Problem(ProblemError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        ch.factorize_values(&a.val()[1..]),
        Err(Error::Problem(ProblemError::DimensionMismatch { .. }))
    ));
    // The path Laplacian without shift is singular, with a negative shift indefinite.
    let indefinite = block_laplacian(5, -1.0);
    assert!(matches!(
        ch.factorize(indefinite.as_ref()),
        Err(Error::NotPositiveDefinite { .. })
    ));
    assert!(matches!(
        ch.solve(&rhs),
        Err(Error::NotPositiveDefinite { .. })
    ));
    let other = block_laplacian(6, 1.0);
    assert_eq!(ch.factorize(other.as_ref()), Err(Error::PatternMismatch));
    let rectangular =
        SparseColMat::try_new_from_triplets(3, 2, &[Triplet::new(0, 0, 1.0)]).unwrap();
    assert!(matches!(
        Cholesky::analyze(rectangular.symbolic()),
        Err(Error::Problem(ProblemError::DimensionMismatch { .. }))
    ));
}
