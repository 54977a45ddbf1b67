//! The sparse helpers against closed forms.

use faer::sparse::{SparseColMat, Triplet};
use rsf_linalg::quadratic_form;

/// `xᵀ A x` of the 1-D Laplacian `tridiag(−1, 2, −1)` is `x₁² + x_n² + Σ (x_i − x_{i+1})²`.
#[test]
fn quadratic_form_of_the_laplacian_is_the_sum_of_squared_differences() {
    let n = 9;
    let mut t = Vec::new();
    for i in 0..n {
        t.push(Triplet::new(i, i, 2.0));
        if i + 1 < n {
            t.push(Triplet::new(i, i + 1, -1.0));
            t.push(Triplet::new(i + 1, i, -1.0));
        }
    }
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
    let x: Vec<f64> = (0..n).map(|i| (0.7 * i as f64).sin() + 0.1).collect();
    let closed = x[0] * x[0]
        + x[n - 1] * x[n - 1]
        + x.windows(2).map(|w| (w[0] - w[1]).powi(2)).sum::<f64>();
    let q = quadratic_form(a.as_ref(), &x);
    assert!((q - closed).abs() < 1e-14 * closed, "{q} against {closed}");
}
