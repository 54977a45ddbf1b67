//! What the examples that time a fault operator's products share (`element_operator_setup`,
//! `halfspace_scaling`): a module of each, by `#[path]`.

use std::time::Instant;

use rsf::fault_operator::{FaultOperator, KernelReport};
use rsf_programs::guard::{in_range, AnyError};

/// Checks the flags `--epsilon` (the ℋ-matrix's relative accuracy, up to 1e-2) and
/// `--products` (products timed, 1 to 1e5).
///
/// # Errors
/// A value out of its range, naming the flag.
pub fn check_epsilon_and_products(epsilon: f64, products: usize) -> Result<(), AnyError> {
    in_range(
        "--epsilon",
        epsilon,
        (f64::MIN_POSITIVE, 1e-2),
        "a relative accuracy",
    )?;
    in_range("--products", products as f64, (1.0, 1e5), "products timed")?;
    Ok(())
}

/// The median wall time (s) of `products` (at least 1) products `r −= K x` of `op` on one
/// thread, `x_i = sin(0.37 i)`.
///
/// # Errors
/// A product's error.
pub fn median_product_seconds<O: FaultOperator + ?Sized>(
    op: &mut O,
    products: usize,
) -> rsf::Result<f64> {
    let m = op.dim();
    let x: Vec<f64> = (0..m).map(|i| (0.37 * i as f64).sin()).collect();
    let mut r = vec![0.0; m];
    let mut times: Vec<f64> = (0..products)
        .map(|_| {
            let t = Instant::now();
            op.subtract_product(&x, &mut r, rsf::Parallelism::SEQ)
                .map(|()| t.elapsed().as_secs_f64())
        })
        .collect::<rsf::Result<_>>()?;
    times.sort_by(f64::total_cmp);
    Ok(times[times.len() / 2])
}

/// The table columns of an operator's blocks: `dense blocks | low-rank blocks | max rank |
/// ‖K − K_H‖_F/‖K‖_F (sampled)`, the last as `{:.2e} ({} samples)`.
pub fn block_columns(report: &KernelReport) -> String {
    format!(
        "{} | {} | {} | {:.2e} ({} samples)",
        report.dense_blocks,
        report.low_rank_blocks,
        report.max_rank,
        report.relative_error,
        report.error_samples
    )
}
