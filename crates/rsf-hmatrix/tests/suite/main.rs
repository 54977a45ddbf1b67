//! The integration tests of `rsf-hmatrix`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf-hmatrix --test suite [module::test]`.

mod columns;
mod components;
mod hmatrix;

/// Asserts that the entries an ℋ-matrix stores grow like `n log n` over `sizes`: the
/// least-squares slope of `ln stored(n)` against `ln n` in (0.9, 1.3). `stored(n)` builds
/// the matrix of `n` points (with its own checks) and gives its stored entries.
fn assert_stored_entries_grow_like_n_log_n(
    sizes: &[usize],
    mut stored: impl FnMut(usize) -> usize,
) {
    let logs: Vec<(f64, f64)> = sizes
        .iter()
        .map(|&n| ((n as f64).ln(), (stored(n) as f64).ln()))
        .collect();
    let slope = log_log_slope(&logs);
    assert!(slope < 1.3 && slope > 0.9, "stored entries ~ n^{slope}");
}

/// The least-squares slope of `y` against `x` over `points` (here `(ln n, ln stored
/// entries)`: the observed exponent of the storage's growth).
fn log_log_slope(points: &[(f64, f64)]) -> f64 {
    let m = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / m, b + y / m));
    let (num, den) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx).powi(2))
    });
    num / den
}
