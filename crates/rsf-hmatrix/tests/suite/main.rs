//! The integration tests of `rsf-hmatrix`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf-hmatrix --test suite [module::test]`.

mod columns;
mod components;
mod hmatrix;

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
