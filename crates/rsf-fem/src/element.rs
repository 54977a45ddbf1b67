//! Element routines (local matrices and quadrature), separated from global assembly.
//!
//! Local dof numbering is node-major: local dof `D·a + r` is component `r` of the
//! `a`-th vertex of the cell; local matrices are row-major `(D(D+1)) × (D(D+1))`.

use crate::{Error, Result};

/// Isotropic linear elasticity `σ = λ tr ε(u) I + 2μ ε(u)` (Lamé parameters in N/m in 2D).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearElasticity {
    /// First Lamé parameter λ.
    pub lambda: f64,
    /// Shear modulus μ.
    pub mu: f64,
}

impl LinearElasticity {
    /// Plane strain from Young's modulus `e` and Poisson's ratio `nu` (docs/math.md §1):
    /// λ = Eν/((1+ν)(1−2ν)), μ = E/(2(1+ν)).
    ///
    /// # Errors
    /// [`Error::InvalidYoungsModulus`] unless `e > 0` and finite;
    /// [`Error::InvalidPoissonRatio`] unless `−1 < nu < 0.5`.
    pub fn plane_strain(e: f64, nu: f64) -> Result<Self> {
        if !(e > 0.0 && e.is_finite()) {
            return Err(Error::InvalidYoungsModulus(e));
        }
        if !(nu > -1.0 && nu < 0.5) {
            return Err(Error::InvalidPoissonRatio(nu));
        }
        Ok(Self {
            lambda: e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            mu: e / (2.0 * (1.0 + nu)),
        })
    }

    /// Energy density `½ σ:ε = μ ε:ε + ½ λ (tr ε)²` of a (symmetric) strain `eps`.
    pub fn energy_density<const D: usize>(&self, eps: &[[f64; D]; D]) -> f64 {
        let mut tr = 0.0;
        let mut ee = 0.0;
        for i in 0..D {
            tr += eps[i][i];
            for j in 0..D {
                ee += eps[i][j] * eps[i][j];
            }
        }
        self.mu * ee + 0.5 * self.lambda * tr * tr
    }
}

/// Local stiffness matrix of a P1 simplex:
/// `K_{(a,r),(b,s)} = |T| (λ ∂_r λ_a ∂_s λ_b + μ (∂_s λ_a ∂_r λ_b + δ_rs ∇λ_a·∇λ_b))`.
///
/// `grads[a]`: gradient of the barycentric coordinate `a` (first `D + 1` used);
/// `measure`: cell area/volume; `out`: `(D(D+1))²` entries, overwritten.
#[inline]
pub fn p1_stiffness<const D: usize>(
    grads: &[[f64; D]; 4],
    measure: f64,
    mat: &LinearElasticity,
    out: &mut [f64],
) {
    let n = D * (D + 1);
    debug_assert_eq!(out.len(), n * n);
    for a in 0..=D {
        for b in 0..=D {
            let mut dot = 0.0;
            for k in 0..D {
                dot += grads[a][k] * grads[b][k];
            }
            for r in 0..D {
                for s in 0..D {
                    let mut v =
                        mat.lambda * grads[a][r] * grads[b][s] + mat.mu * grads[a][s] * grads[b][r];
                    if r == s {
                        v += mat.mu * dot;
                    }
                    out[(D * a + r) * n + D * b + s] = measure * v;
                }
            }
        }
    }
}

/// Local consistent mass matrix of a P1 simplex with density `rho`:
/// `M_{(a,r),(b,s)} = ρ |T| (1 + δ_ab) / ((D+1)(D+2)) δ_rs`. `out` as in [`p1_stiffness`].
#[inline]
pub fn p1_mass<const D: usize>(measure: f64, rho: f64, out: &mut [f64]) {
    let n = D * (D + 1);
    debug_assert_eq!(out.len(), n * n);
    out.fill(0.0);
    let base = rho * measure / ((D + 1) * (D + 2)) as f64;
    for a in 0..=D {
        for b in 0..=D {
            let m = if a == b { 2.0 * base } else { base };
            for r in 0..D {
                out[(D * a + r) * n + D * b + r] = m;
            }
        }
    }
}

/// Quadrature on the reference triangle exact for degree 5 (Dunavant, 7 points):
/// `(barycentric coordinates, weight)`, weights summing to 1 (multiply by the area).
pub fn triangle_quadrature() -> [([f64; 3], f64); 7] {
    let s = 15f64.sqrt();
    let (b1, b2) = ((6.0 + s) / 21.0, (6.0 - s) / 21.0);
    let (a1, a2) = (1.0 - 2.0 * b1, 1.0 - 2.0 * b2);
    let (w1, w2) = ((155.0 + s) / 1200.0, (155.0 - s) / 1200.0);
    [
        ([1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0], 0.225),
        ([a1, b1, b1], w1),
        ([b1, a1, b1], w1),
        ([b1, b1, a1], w1),
        ([a2, b2, b2], w2),
        ([b2, a2, b2], w2),
        ([b2, b2, a2], w2),
    ]
}

/// 3-point Gauss rule on a segment (exact for degree 5): `(barycentric coords, weight)`,
/// weights summing to 1 (multiply by the length).
pub fn segment_quadrature() -> [([f64; 2], f64); 3] {
    let d = 0.5 * (0.6f64).sqrt();
    [
        ([0.5 + d, 0.5 - d], 5.0 / 18.0),
        ([0.5, 0.5], 8.0 / 18.0),
        ([0.5 - d, 0.5 + d], 5.0 / 18.0),
    ]
}
