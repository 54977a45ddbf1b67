//! Bounds of the direct solver's stopping norm by the Euclidean norm, which let its
//! iteration skip evaluating the norm where the outcome of a test is already certain.
//!
//! The stopping norm of the condensed iteration is `‖x‖_N = ‖Lᵀx‖₂` for the Cholesky factor
//! `L` of the norm's matrix `N` (`m × m`): `m²/2` multiply–adds per evaluation, a pass over
//! the factor. On the fault of SEAS BP1-FD at Δz = 25 m (`m = 1601`) these passes (three
//! per iteration, one more per solve) took about 40 % of the time of a dynamic step in a
//! profile (docs/performance.md, "The direct solver on a long fault"). Far from convergence, though, every test the
//! iteration makes ("is the sweep's correction above the absolute tolerance?", "is the
//! correction below the stopping tolerance?") has a certain answer, which a bound tells
//! from `‖x‖₂` in `O(m)`.
//!
//! **The bounds hold for the computed norm, not only the exact one.** For `x ∈ Rᵐ`, the
//! exact `‖Lᵀx‖₂` lies between `‖x‖₂ / ‖L⁻¹‖₂` and `‖L‖₂ ‖x‖₂`, and `‖·‖₂ ≤ ‖·‖_F`. The
//! computed column sums `(Lᵀx)_j` differ from the exact ones by at most
//! `γ_m Σ_i |L_ij x_i|` (`γ_m = m u / (1 − m u)`, `u` the unit round-off; Higham, *Accuracy
//! and Stability of Numerical Algorithms*, 2nd ed., §3.1), so the computed norm differs
//! from the exact one by at most `γ_m ‖L‖_F ‖x‖₂` (plus a relative `(m + 2) u` for the
//! squares, their sum and the root):
//!
//! ```text
//! lower ‖x‖₂ ≤ computed ‖x‖_N ≤ upper ‖x‖₂,
//! lower = (1 / ‖L⁻¹‖_F − 2 γ_m ‖L‖_F) · (1 − margin),   upper = ‖L‖_F (1 + 2 γ_m) (1 + margin).
//! ```
//!
//! `‖L⁻¹‖_F` comes from a computed inverse, whose error is of order `m u ‖L‖ ‖L⁻¹‖` in
//! relative terms; the bounds are used only while that is below [`MAX_CONDITION_EPS`], and
//! `margin` (10 %) covers it and the Euclidean norm's own round-off many times over. With
//! these bounds a test decided by them gives the answer the computed norm would: the
//! iteration's bits do not change.

use faer::linalg::triangular_inverse::invert_lower_triangular;
use faer::{Mat, Par};

/// Smallest number of free components for which the bounds are set up: below it a norm
/// costs little more than its bound, and the set-up (`m³/3` multiply–adds for the inverse of
/// `L`) would not pay.
pub(super) const NORM_BOUNDS_MIN: usize = 128;

/// Largest `m u ‖L‖_F ‖L⁻¹‖_F` for which the bounds are used (above it the computed
/// inverse's norm is not trusted to the margin).
const MAX_CONDITION_EPS: f64 = 1e-4;

/// Relative margin on both bounds.
const MARGIN: f64 = 0.1;

/// `lower ‖x‖₂ ≤ ‖x‖_N ≤ upper ‖x‖₂` for the computed stopping norm (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct NormBounds {
    /// Positive lower bound factor.
    pub lower: f64,
    /// Upper bound factor.
    pub upper: f64,
}

impl NormBounds {
    /// The bounds for the factor `l` (`m × m` row-major lower triangle, zero above the
    /// diagonal), or None if `L` is too ill-conditioned for them to be trusted.
    pub(super) fn of_factor(l: &[f64], m: usize) -> Option<Self> {
        if m == 0 {
            return None;
        }
        let frob = l.iter().map(|v| v * v).sum::<f64>().sqrt();
        let lower_factor = Mat::from_fn(m, m, |i, j| if i >= j { l[i * m + j] } else { 0.0 });
        let mut inverse = Mat::<f64>::zeros(m, m);
        invert_lower_triangular(inverse.as_mut(), lower_factor.as_ref(), Par::Seq);
        let mut inv_sq = 0.0;
        for j in 0..m {
            for i in j..m {
                inv_sq += inverse[(i, j)] * inverse[(i, j)];
            }
        }
        let inv_frob = inv_sq.sqrt();
        let u = f64::EPSILON / 2.0;
        let mu = m as f64 * u;
        if !(frob.is_finite() && inv_frob.is_finite() && inv_frob > 0.0)
            || mu * frob * inv_frob > MAX_CONDITION_EPS
        {
            return None;
        }
        let gamma = mu / (1.0 - mu);
        let lower = (1.0 / inv_frob - 2.0 * gamma * frob) * (1.0 - MARGIN);
        let upper = frob * (1.0 + 2.0 * gamma) * (1.0 + MARGIN);
        (lower > 0.0 && upper.is_finite()).then_some(Self { lower, upper })
    }
}

/// `‖x‖₂`.
#[inline(always)]
pub(super) fn euclidean(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::NormBounds;
    use crate::dense::{lower_cholesky, norm_via_factor};

    /// An `m × m` matrix by its entries.
    type Entries = Box<dyn Fn(usize, usize) -> f64>;

    /// Row-major lower Cholesky factor of the `m × m` SPD matrix `a(i, j)`, as the solver
    /// computes it.
    fn factor(m: usize, a: impl Fn(usize, usize) -> f64) -> Vec<f64> {
        let dense: Vec<f64> = (0..m * m).map(|k| a(k % m, k / m)).collect();
        lower_cholesky(&dense, m).expect("SPD")
    }

    /// The bounds enclose the computed norm for vectors at both ends of its range: smooth
    /// and oscillating ones, and the columns of `L⁻ᵀ`, where `‖Lᵀx‖ / ‖x‖` is near its
    /// minimum. Matrices: a 1-D Laplacian plus a shift (condition ~4/shift) and a dense
    /// kernel-like one.
    #[test]
    fn bounds_enclose_the_computed_norm() {
        let m = 150;
        let matrices: Vec<(&str, Entries)> = vec![
            (
                "laplacian + 1e-3",
                Box::new(|i, j| match i.abs_diff(j) {
                    0 => 2.001,
                    1 => -1.0,
                    _ => 0.0,
                }),
            ),
            (
                "kernel",
                Box::new(|i, j| {
                    1.0 / (1.0 + (i as f64 - j as f64).powi(2)) + (i == j) as u8 as f64
                }),
            ),
        ];
        for (name, a) in matrices {
            let l = factor(m, a);
            let b = NormBounds::of_factor(&l, m).expect("well-conditioned");
            let mut ratios = Vec::new();
            let mut check = |x: &[f64]| {
                let e = x.iter().map(|v| v * v).sum::<f64>().sqrt();
                let n = norm_via_factor(&l, x);
                assert!(
                    b.lower * e <= n && n <= b.upper * e,
                    "{name}: {n} vs {e}, {b:?}"
                );
                ratios.push(n / e);
            };
            for k in [1.0, 7.0, 60.0, 149.0] {
                let x: Vec<f64> = (0..m).map(|i| (k * i as f64 * 0.021).sin()).collect();
                check(&x);
            }
            // x = L⁻ᵀ e_j by back substitution.
            for j in [0, m / 2, m - 1] {
                let mut x = vec![0.0; m];
                x[j] = 1.0;
                for i in (0..m).rev() {
                    let mut s = x[i];
                    for k in i + 1..m {
                        s -= l[k * m + i] * x[k];
                    }
                    x[i] = s / l[i * m + i];
                }
                check(&x);
            }
            let (lo, hi) = ratios
                .iter()
                .fold((f64::INFINITY, 0.0_f64), |(a, b), &r| (a.min(r), b.max(r)));
            println!(
                "{name}: {:.3e} ≤ {lo:.3e} … {hi:.3e} ≤ {:.3e}",
                b.lower, b.upper
            );
        }
    }

    /// A factor whose condition times `m u` exceeds the limit gets no bounds (the tests
    /// then evaluate the norm), and so does an empty one.
    #[test]
    fn ill_conditioned_factors_get_no_bounds() {
        let m = 130;
        let l = factor(m, |i, j| match (i == j, i) {
            (true, 0) => 1e-24,
            (true, _) => 1.0,
            _ => 0.0,
        });
        assert_eq!(NormBounds::of_factor(&l, m), None);
        assert_eq!(NormBounds::of_factor(&[], 0), None);
    }
}
