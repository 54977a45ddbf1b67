//! A boundary-element fault operator for antiplane slip on a planar fault in a whole
//! space (docs/seas-bp6.md, "The elastic kernels"): the stress change at cell centres of
//! piecewise-constant slip on uniform cells — the kernel of SEAS BP6's boundary-element
//! codes — behind [`FaultOperator`], for a fault alone
//! ([`Model::fault_only`](crate::Model::fault_only),
//! [`SimulationBuilder::build_fault_ode_alone`](crate::SimulationBuilder::build_fault_ode_alone)).

use std::sync::Arc;
use std::time::Instant;

use faer::Mat;
use rsf_hmatrix::{HMatrix, HOptions, Points};
use rsf_linalg::Parallelism;
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

use crate::error::{invalid, Result};
use crate::fault_kernel::{no_split, Kernel, KernelRows};
use crate::fault_operator::{FaultKernel, FaultOperator, KernelReport, RowSplit};

/// How a [`WholeSpaceAntiplane`] stores and applies its kernel.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum WholeSpaceKernel {
    /// The matrix is Toeplitz (on uniform cells `S_ij` depends on `i − j` only): embedded
    /// in a circulant matrix of order `L`, the power of two at least `2n − 1`, whose
    /// eigenvalues are the discrete Fourier transform of its first column, `S x` is one
    /// forward and one inverse FFT of length `L` (rustfft) and `L` complex products —
    /// `O(n log n)` per product, `2L` f64 stored, and no approximation: exact up to the
    /// round-off of the transforms (relative to `‖S‖ ‖x‖`, of the order of `ε log₂ L`;
    /// measured against the dense product in the tests). The default.
    #[default]
    Fft,
    /// Stored as a fault kernel: dense (`n²` f64) or an ℋ-matrix of accuracy ε
    /// ([`FaultKernel`]).
    Stored(FaultKernel),
}

impl From<FaultKernel> for WholeSpaceKernel {
    fn from(kernel: FaultKernel) -> Self {
        Self::Stored(kernel)
    }
}

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
/// Applied through FFTs of its circulant embedding ([`WholeSpaceKernel::Fft`], the
/// default), or stored dense (`n²` f64) or as an ℋ-matrix of accuracy ε built from its
/// entries (rsf-hmatrix's cross approximation on the cells' centres).
pub struct WholeSpaceAntiplane {
    product: Product,
    report: KernelReport,
    rows: Option<KernelRows>,
}

/// The product's storage.
enum Product {
    Stored(Kernel),
    Fft(Box<CirculantProduct>),
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

/// The product with a symmetric Toeplitz matrix of order `n` through its circulant
/// embedding of order `L` (a power of two, `L ≥ 2n − 1`): first column
/// `c = (t₀, t₁, …, t_{n−1}, 0, …, 0, t_{n−1}, …, t₁)`, eigenvalues `λ = F c`, and
/// `T x = (F⁻¹ (λ ⊙ F [x; 0]))[..n]`. Scratch kept: no allocation per product.
struct CirculantProduct {
    n: usize,
    /// `λ / L` (the inverse transform's scaling folded in).
    spectrum: Vec<Complex<f64>>,
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
    buffer: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl CirculantProduct {
    /// The embedding of the symmetric Toeplitz matrix with first row `t(0), …, t(n − 1)`.
    fn new(n: usize, t: impl Fn(usize) -> f64) -> Self {
        let len = (2 * n - 1).next_power_of_two();
        let mut planner = FftPlanner::new();
        let forward = planner.plan_fft_forward(len);
        let inverse = planner.plan_fft_inverse(len);
        let zero = Complex::new(0.0, 0.0);
        let mut spectrum = vec![zero; len];
        for k in 0..n {
            spectrum[k].re = t(k);
            if k > 0 {
                spectrum[len - k].re = t(k);
            }
        }
        let scratch_len = forward
            .get_inplace_scratch_len()
            .max(inverse.get_inplace_scratch_len());
        let mut scratch = vec![zero; scratch_len];
        forward.process_with_scratch(&mut spectrum, &mut scratch);
        let scale = 1.0 / len as f64;
        for s in &mut spectrum {
            *s *= scale;
        }
        Self {
            n,
            spectrum,
            forward,
            inverse,
            buffer: vec![zero; len],
            scratch,
        }
    }

    /// `r ← r − T x`. A non-finite `x` gives a non-finite `r` (NaN spreads through the
    /// transforms).
    fn subtract(&mut self, x: &[f64], r: &mut [f64]) {
        let n = self.n;
        for (b, &xi) in self.buffer.iter_mut().zip(x) {
            *b = Complex::new(xi, 0.0);
        }
        for b in &mut self.buffer[n..] {
            *b = Complex::new(0.0, 0.0);
        }
        self.forward
            .process_with_scratch(&mut self.buffer, &mut self.scratch);
        for (b, s) in self.buffer.iter_mut().zip(&self.spectrum) {
            *b *= s;
        }
        self.inverse
            .process_with_scratch(&mut self.buffer, &mut self.scratch);
        for (ri, b) in r.iter_mut().zip(&self.buffer[..n]) {
            *ri -= b.re;
        }
    }
}

impl WholeSpaceAntiplane {
    /// The operator of `cells` cells of width `h` (m) in a medium of shear modulus `mu`
    /// (Pa), applied as `kernel` says (a [`FaultKernel`] converts into a stored kernel).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `cells` (fewer
    /// than 2, more than 10⁷, or a dense operator over 20 000 cells: 3.2 GB), `h`, `mu`
    /// (positive and finite) or the kernel's; [`Error::HMatrix`](crate::Error::HMatrix)
    /// from the compression.
    pub fn new(cells: usize, h: f64, mu: f64, kernel: impl Into<WholeSpaceKernel>) -> Result<Self> {
        let kernel = kernel.into();
        if let WholeSpaceKernel::Stored(k) = kernel {
            k.validate()?;
        }
        for (name, v) in [("h", h), ("mu", mu)] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(invalid(name, format!("{v} must be positive and finite")));
            }
        }
        let dense = matches!(kernel, WholeSpaceKernel::Stored(FaultKernel::Dense));
        if !(2..=10_000_000).contains(&cells) || (dense && cells > 20_000) {
            return Err(invalid(
                "cells",
                format!("{cells}: at least 2, at most 10⁷, a dense operator at most 20 000"),
            ));
        }
        let clock = Instant::now();
        let (product, report) = match kernel {
            WholeSpaceKernel::Fft => {
                let circulant = CirculantProduct::new(cells, |k| entry(mu, h, k, 0));
                let report = KernelReport {
                    // Exact up to round-off, as the dense kernel.
                    stored_entries: 2 * circulant.spectrum.len(),
                    setup_bytes: 0,
                    setup_seconds: clock.elapsed().as_secs_f64(),
                    ..KernelReport::dense(cells)
                };
                (Product::Fft(Box::new(circulant)), report)
            }
            WholeSpaceKernel::Stored(FaultKernel::Dense) => (
                Product::Stored(Kernel::Dense(Mat::from_fn(cells, cells, |i, j| {
                    entry(mu, h, i, j)
                }))),
                KernelReport::dense(cells),
            ),
            WholeSpaceKernel::Stored(kernel @ FaultKernel::Hierarchical { epsilon, leaf_size }) => {
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
                let report = KernelReport::hierarchical(kernel, cells, hm.report(), 0, clock);
                (Product::Stored(Kernel::Hierarchical(Box::new(hm))), report)
            }
        };
        Ok(Self {
            product,
            report,
            rows: None,
        })
    }

    /// Whether the product is the FFT of the circulant embedding
    /// ([`WholeSpaceKernel::Fft`]).
    pub fn is_fft(&self) -> bool {
        matches!(self.product, Product::Fft(_))
    }

    /// A line describing the product (the kernel report, or the FFT's length).
    pub fn describe(&self) -> String {
        match &self.product {
            Product::Fft(c) => format!(
                "FFT product of the Toeplitz kernel: m = {}, circulant embedding of order {} \
                 ({} f64 stored), set up in {:.2} s",
                self.report.dim,
                c.spectrum.len(),
                self.report.stored_entries,
                self.report.setup_seconds
            ),
            Product::Stored(_) => self.report.to_string(),
        }
    }
}

/// The error of a split asked of the FFT product (its rows are not computed apart).
fn fft_rows() -> crate::Error {
    invalid(
        "ranks",
        "the whole space's FFT product computes every row at once (FaultOperator::split_rows): \
         use a stored kernel on ranks",
    )
}

impl FaultOperator for WholeSpaceAntiplane {
    fn dim(&self) -> usize {
        self.report.dim
    }

    fn subtract_product(&mut self, x: &[f64], r: &mut [f64], par: Parallelism) -> Result<()> {
        match &mut self.product {
            Product::Stored(k) => k.subtract_product(x, r, par),
            Product::Fft(c) => {
                let n = c.n;
                if x.len() != n || r.len() != n {
                    return Err(invalid(
                        "x",
                        format!("lengths {} and {} for an operator of {n}", x.len(), r.len()),
                    ));
                }
                c.subtract(x, r);
                Ok(())
            }
        }
    }

    fn hierarchical_mut(&mut self) -> Option<&mut HMatrix> {
        match &mut self.product {
            Product::Stored(k) => k.hierarchical_mut(),
            Product::Fft(_) => None,
        }
    }

    fn report(&self) -> &KernelReport {
        &self.report
    }

    fn operator_origin(&self) -> crate::fault_operator::OperatorOrigin {
        crate::fault_operator::OperatorOrigin::WholeSpace
    }

    fn split_rows(&mut self, parts: usize, work_per_row: f64) -> Result<RowSplit> {
        let Product::Stored(kernel) = &mut self.product else {
            return Err(fft_rows());
        };
        let rows = kernel.split_rows(parts, work_per_row);
        let split = rows.split.clone();
        self.rows = Some(rows);
        Ok(split)
    }

    fn part_subtract(&mut self, x: &[f64], part: usize, r: &mut [f64]) -> Result<()> {
        let Product::Stored(kernel) = &mut self.product else {
            return Err(fft_rows());
        };
        let rows = self.rows.as_ref().ok_or_else(no_split)?;
        kernel.part_subtract(rows, x, part, r)
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
            let mut fft = WholeSpaceAntiplane::new(n, h, mu, WholeSpaceKernel::Fft).unwrap();
            let tau_fft = stress(&mut fft, &slip, h);
            let gap = tau
                .iter()
                .zip(&tau_fft)
                .fold(0.0_f64, |g, (p, q)| g.max((p - q).abs()));
            assert!(gap <= 1e-9 * drop, "FFT against dense: {gap:e} Pa");
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

    /// The FFT of the circulant embedding gives the dense product up to round-off: at
    /// several sizes (a power of two and others, so embeddings of several orders) and for
    /// a rough and a smooth slip, `max |S x − (S x)_FFT|` is below `1e-13 max_i Σ_j |S_ij
    /// x_j|` (the scale of the dense sum's own round-off); a NaN in `x` gives NaN.
    #[test]
    fn fft_product_equals_the_dense_product() {
        let (h, mu) = (10.0, 32.04e9);
        for n in [2, 3, 64, 600, 1025] {
            let mut dense = WholeSpaceAntiplane::new(n, h, mu, FaultKernel::Dense).unwrap();
            let mut fft = WholeSpaceAntiplane::new(n, h, mu, WholeSpaceKernel::Fft).unwrap();
            assert!(fft.is_fft() && !dense.is_fft());
            assert_eq!(fft.dim(), n);
            let rough: Vec<f64> = (0..n)
                .map(|i| ((i * 7919) % 101) as f64 / 50.0 - 1.0)
                .collect();
            let smooth: Vec<f64> = (0..n)
                .map(|i| 0.2 * (1.0 - ((2.0 * i as f64 + 1.0) / n as f64 - 1.0).powi(2)))
                .collect();
            for x in [rough, smooth] {
                let (mut a, mut b) = (vec![1.0; n], vec![1.0; n]);
                dense
                    .subtract_product(&x, &mut a, Parallelism::SEQ)
                    .unwrap();
                fft.subtract_product(&x, &mut b, Parallelism::rayon(2))
                    .unwrap();
                let scale = (0..n)
                    .map(|i| {
                        (0..n)
                            .map(|j| (entry(mu, h, i, j) * x[j]).abs())
                            .sum::<f64>()
                    })
                    .fold(0.0_f64, f64::max);
                let gap = a
                    .iter()
                    .zip(&b)
                    .fold(0.0_f64, |g, (p, q)| g.max((p - q).abs()));
                eprintln!("n = {n}: max gap {:.2e} of the scale", gap / scale);
                assert!(gap <= 1e-13 * scale, "n = {n}: {gap:e} of {scale:e}");
            }
            let mut x = vec![0.0; n];
            x[n / 2] = f64::NAN;
            let mut r = vec![0.0; n];
            fft.subtract_product(&x, &mut r, Parallelism::SEQ).unwrap();
            assert!(r.iter().all(|v| v.is_nan()));
            assert!(fft.split_rows(2, 0.0).is_err());
            assert!(fft
                .subtract_product(&x[1..], &mut r, Parallelism::SEQ)
                .is_err());
        }
        assert!(WholeSpaceAntiplane::new(1, h, mu, WholeSpaceKernel::Fft).is_err());
        assert!(WholeSpaceAntiplane::new(4, -h, mu, WholeSpaceKernel::Fft).is_err());
    }

    /// `Model::set_fault_stiffness` with this operator: the fault alone's `K u` is `S u`
    /// on the slip components (to the round-off of the symmetrisation, against the
    /// operator's own product), `K` is symmetric, the fixed normal components have a
    /// diagonal entry alone, and the energy norm is `K`; a second call (a stiffness
    /// already), an operator of another size are typed errors.
    #[test]
    fn a_fault_alone_takes_the_kernel_as_its_stiffness() {
        let (n, h, mu) = (9, 25.0, 32.04e9);
        let centres: Vec<[f64; 2]> = (0..n).map(|i| [0.0, i as f64 * h]).collect();
        let mut model = crate::Model::fault_only(centres.clone(), &vec![h; n], 0).unwrap();
        let mut op = WholeSpaceAntiplane::new(n, h, mu, WholeSpaceKernel::Fft).unwrap();
        model
            .set_fault_stiffness(&mut op, Parallelism::SEQ)
            .unwrap();
        let k = &model.stiffness;
        let dense = |i: usize, j: usize| {
            k.row_idx_of_col(j)
                .zip(k.val_of_col(j))
                .find(|(r, _)| *r == i)
                .map_or(0.0, |(_, &v)| v)
        };
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
        let mut sx = vec![0.0; n];
        op.subtract_product(&x, &mut sx, Parallelism::SEQ).unwrap();
        let scale = sx.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for i in 0..n {
            // Slip component of cell i: dof 2i + 1.
            let kx: f64 = (0..n).map(|j| dense(2 * i + 1, 2 * j + 1) * x[j]).sum();
            assert!(
                (kx + sx[i]).abs() <= 1e-12 * scale,
                "row {i}: {kx} vs {}",
                -sx[i]
            );
            for j in 0..2 * n {
                assert_eq!(dense(2 * i + 1, j), dense(j, 2 * i + 1));
            }
            assert!(dense(2 * i, 2 * i) > 0.0);
            for j in (0..2 * n).filter(|&j| j != 2 * i) {
                assert_eq!(dense(2 * i, j), 0.0);
            }
        }
        assert_eq!(model.energy_norm.val_of_col(1), k.val_of_col(1));
        let again = model.set_fault_stiffness(&mut op, Parallelism::SEQ);
        assert!(
            matches!(again, Err(crate::Error::InvalidParameter { ref name, .. }) if name == "stiffness")
        );
        let mut fresh = crate::Model::fault_only(centres, &vec![h; n], 0).unwrap();
        let mut small = WholeSpaceAntiplane::new(n - 1, h, mu, WholeSpaceKernel::Fft).unwrap();
        let wrong = fresh.set_fault_stiffness(&mut small, Parallelism::SEQ);
        assert!(
            matches!(wrong, Err(crate::Error::InvalidParameter { ref name, .. }) if name == "fault_operator")
        );
    }
}
