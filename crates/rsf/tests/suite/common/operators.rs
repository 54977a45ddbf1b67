//! Two fault operators compared on one slip vector (`element_operator`,
//! `halfspace_operator`): the dense operator against its ℋ-matrix.

use rsf::fault_operator::FaultOperator;
use rsf::Parallelism;

/// The slip vector `x_i = (37 i mod 11) − 5` (whole numbers in [−5, 5]) of length `m`.
pub fn mixed_slip(m: usize) -> Vec<f64> {
    (0..m).map(|i| ((i * 37) % 11) as f64 - 5.0).collect()
}

/// `‖(S_a − S_b) x‖/‖S_a x‖`: the relative difference of the products of `a` and `b` with
/// `x` (of length `a.dim()`), each product `subtract_product`'s on one thread from zero.
///
/// # Panics
/// If a product fails.
pub fn relative_product_difference(
    a: &mut impl FaultOperator,
    b: &mut impl FaultOperator,
    x: &[f64],
) -> f64 {
    let m = x.len();
    let (mut ra, mut rb) = (vec![0.0; m], vec![0.0; m]);
    a.subtract_product(x, &mut ra, Parallelism::SEQ).unwrap();
    b.subtract_product(x, &mut rb, Parallelism::SEQ).unwrap();
    let norm = |v: &[f64]| v.iter().map(|c| c * c).sum::<f64>().sqrt();
    let diff: Vec<f64> = ra.iter().zip(&rb).map(|(p, q)| p - q).collect();
    norm(&diff) / norm(&ra)
}
