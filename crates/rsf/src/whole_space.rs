//! A boundary-element fault operator for antiplane slip on a planar fault in a whole
//! space (docs/seas-bp6.md, "The boundary-element kernel"): the stress change at cell
//! centres of piecewise-constant slip on uniform cells — the kernel of SEAS BP6's
//! boundary-element codes — behind [`FaultOperator`], for a fault alone
//! ([`Model::fault_only`](crate::Model::fault_only),
//! [`SimulationBuilder::build_fault_ode_alone`](crate::SimulationBuilder::build_fault_ode_alone)).

use std::time::Instant;

use faer::Mat;
use rsf_hmatrix::{HMatrix, HOptions, Points};
use rsf_linalg::Parallelism;

use crate::error::{invalid, Result};
use crate::fault_kernel::{no_split, Kernel, KernelRows};
use crate::fault_operator::{FaultKernel, FaultOperator, KernelReport, RowSplit};

/// `S` of antiplane slip on `n` uniform cells of width `h` along a line in a whole space of
/// shear modulus `μ`: with slip `δ_j` constant on cell `j` (centre `ξ_j`), the shear
/// stress change at centre `z_i` is
///
/// ```text
/// Δτ_i = Σ_j K_ij δ_j,   K_ij = (μ/2π) [1/(ξ_j − h/2 − z_i) − 1/(ξ_j + h/2 − z_i)]
/// ```
///
/// (from `Δτ(z) = (μ/2π) p.v.∫ ∂δ/∂ξ /(ξ − z) dξ`; `K_ii = −2μ/(πh)`), and the operator
/// on the forces is `S_ij = −h K_ij` (N/m per m: per unit length out of the plane), which
/// on a uniform grid is symmetric (a function of `|i − j|`) and positive definite. Outside
/// the cells the slip is zero (a locked fault plane).
///
/// Stored dense (`n²` f64) or as an ℋ-matrix of accuracy ε built from its entries
/// (rsf-hmatrix's cross approximation on the cells' centres).
pub struct WholeSpaceAntiplane {
    kernel: Kernel,
    report: KernelReport,
    rows: Option<KernelRows>,
}

impl std::fmt::Debug for WholeSpaceAntiplane {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WholeSpaceAntiplane")
            .field("report", &self.report)
            .finish_non_exhaustive()
    }
}

/// `S_ij` for cells `h` apart: `(μh/2π)[1/(d + h/2) − 1/(d − h/2)]`, `d = (i − j) h`.
fn entry(mu: f64, h: f64, i: usize, j: usize) -> f64 {
    let d = (i as f64 - j as f64) * h;
    mu * h / (2.0 * std::f64::consts::PI) * (1.0 / (d + 0.5 * h) - 1.0 / (d - 0.5 * h))
}

impl WholeSpaceAntiplane {
    /// The operator of `cells` cells of width `h` (m) in a medium of shear modulus `mu`
    /// (Pa), stored as `kernel` says.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `cells` (fewer
    /// than 2, or a dense operator over 20 000 cells: 3.2 GB), `h`, `mu` (positive and
    /// finite) or the kernel's; [`Error::HMatrix`](crate::Error::HMatrix) from the
    /// compression.
    pub fn new(cells: usize, h: f64, mu: f64, kernel: FaultKernel) -> Result<Self> {
        kernel.validate()?;
        for (name, v) in [("h", h), ("mu", mu)] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(invalid(name, format!("{v} must be positive and finite")));
            }
        }
        if cells < 2 || (matches!(kernel, FaultKernel::Dense) && cells > 20_000) {
            return Err(invalid(
                "cells",
                format!("{cells}: at least 2, a dense operator at most 20 000"),
            ));
        }
        let clock = Instant::now();
        let (kernel, report) = match kernel {
            FaultKernel::Dense => (
                Kernel::Dense(Mat::from_fn(cells, cells, |i, j| entry(mu, h, i, j))),
                KernelReport::dense(cells),
            ),
            FaultKernel::Hierarchical { epsilon, leaf_size } => {
                let centres: Vec<[f64; 1]> = (0..cells).map(|i| [i as f64 * h]).collect();
                let options = HOptions {
                    epsilon,
                    leaf_size,
                    ..HOptions::default()
                };
                let hm = HMatrix::from_entries(
                    |i, j| entry(mu, h, i, j),
                    &Points::from_array(&centres)?,
                    &options,
                )?;
                let r = hm.report();
                let report = KernelReport {
                    kernel,
                    dim: cells,
                    relative_error: r.relative_error,
                    error_samples: match r.error_measure {
                        rsf_hmatrix::ErrorMeasure::Sampled { samples } => samples,
                        _ => 0,
                    },
                    setup_bytes: 0,
                    stored_entries: r.stored_entries,
                    dense_blocks: r.dense_blocks,
                    low_rank_blocks: r.low_rank_blocks,
                    max_rank: r.max_rank,
                    setup_seconds: clock.elapsed().as_secs_f64(),
                    part: None,
                };
                (Kernel::Hierarchical(Box::new(hm)), report)
            }
        };
        Ok(Self {
            kernel,
            report,
            rows: None,
        })
    }
}

impl FaultOperator for WholeSpaceAntiplane {
    fn dim(&self) -> usize {
        self.report.dim
    }

    fn subtract_product(&mut self, x: &[f64], r: &mut [f64], par: Parallelism) -> Result<()> {
        self.kernel.subtract_product(x, r, par)
    }

    fn hierarchical_mut(&mut self) -> Option<&mut HMatrix> {
        self.kernel.hierarchical_mut()
    }

    fn report(&self) -> &KernelReport {
        &self.report
    }

    fn split_rows(&mut self, parts: usize, work_per_row: f64) -> Result<RowSplit> {
        let rows = self.kernel.split_rows(parts, work_per_row);
        let split = rows.split.clone();
        self.rows = Some(rows);
        Ok(split)
    }

    fn part_subtract(&mut self, x: &[f64], part: usize, r: &mut [f64]) -> Result<()> {
        let rows = self.rows.as_ref().ok_or_else(no_split)?;
        self.kernel.part_subtract(rows, x, part, r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Δτ = −S δ / h of `slip` on `n` cells of width `h`.
    fn stress(op: &mut WholeSpaceAntiplane, slip: &[f64], h: f64) -> Vec<f64> {
        let mut r = vec![0.0; slip.len()];
        op.subtract_product(slip, &mut r, Parallelism::SEQ).unwrap();
        r.iter().map(|x| x / h).collect()
    }

    /// A Mode-III crack of half-length `a` under a stress drop Δσ has the elliptic slip
    /// `2(Δσ/μ)√(a² − z²)` (a closed form independent of the kernel's derivation): the
    /// kernel gives `Δτ = −Δσ` inside, to first order in `h` away from the tips.
    #[test]
    fn elliptic_crack_has_uniform_stress_drop() {
        let (mu, a, drop) = (32.04e9, 1e3, 1e6);
        let mut errors = Vec::new();
        for n in [100, 200, 400] {
            let h = 2.0 * a / n as f64;
            let slip: Vec<f64> = (0..n)
                .map(|i| {
                    let z = -a + (i as f64 + 0.5) * h;
                    2.0 * drop / mu * (a * a - z * z).sqrt()
                })
                .collect();
            let mut op = WholeSpaceAntiplane::new(n, h, mu, FaultKernel::Dense).unwrap();
            let tau = stress(&mut op, &slip, h);
            // Inside |z| < a/2.
            let worst = (n / 4..3 * n / 4)
                .map(|i| (tau[i] + drop).abs() / drop)
                .fold(0.0_f64, f64::max);
            errors.push(worst);
        }
        eprintln!("max |Δτ + Δσ|/Δσ on |z| < a/2 at n = 100, 200, 400: {errors:?}");
        assert!(errors[2] < 2e-3, "{errors:?}");
        assert!(errors[2] < 0.6 * errors[0], "{errors:?}");
    }

    /// Symmetric, diagonal 2μ/π, and the ℋ-matrix agrees with the dense operator to its ε.
    #[test]
    fn dense_and_hierarchical_operators_agree() {
        let (n, h, mu) = (600, 10.0, 3e10);
        let mut dense = WholeSpaceAntiplane::new(n, h, mu, FaultKernel::Dense).unwrap();
        let eps = 1e-8;
        let mut hier = WholeSpaceAntiplane::new(n, h, mu, FaultKernel::hierarchical(eps)).unwrap();
        assert!(hier.report().compression_ratio() > 1.5, "{}", hier.report());
        assert!((entry(mu, h, 3, 3) - 2.0 * mu / std::f64::consts::PI).abs() < 1e-6 * mu);
        assert_eq!(entry(mu, h, 3, 10), entry(mu, h, 10, 3));
        let x: Vec<f64> = (0..n)
            .map(|i| ((i * 7919) % 101) as f64 / 50.0 - 1.0)
            .collect();
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        dense
            .subtract_product(&x, &mut a, Parallelism::SEQ)
            .unwrap();
        hier.subtract_product(&x, &mut b, Parallelism::SEQ).unwrap();
        let norm = |v: &[f64]| v.iter().map(|y| y * y).sum::<f64>().sqrt();
        let diff: Vec<f64> = a.iter().zip(&b).map(|(p, q)| p - q).collect();
        assert!(
            norm(&diff) <= 10.0 * eps * norm(&a),
            "{}",
            norm(&diff) / norm(&a)
        );
        // x S x > 0.
        assert!(a.iter().zip(&x).map(|(p, q)| -p * q).sum::<f64>() > 0.0);
    }
}
