//! Element routines (local matrices and quadrature), separated from global assembly.
//!
//! Local dof numbering is node-major: local dof `D·a + r` is component `r` of the
//! `a`-th vertex of the cell; local matrices are row-major `(D(D+1)) × (D(D+1))`.

use crate::{Error, Result};

/// Isotropic linear elasticity `σ = λ tr ε(u) I + 2μ ε(u)` (Lamé parameters in Pa in 3D,
/// N/m per unit thickness in 2D); the same type serves every dimension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearElasticity {
    /// First Lamé parameter λ.
    pub lambda: f64,
    /// Shear modulus μ.
    pub mu: f64,
}

impl LinearElasticity {
    /// Isotropic elasticity from Young's modulus `e` and Poisson's ratio `nu`
    /// (docs/math.md §1, §10): λ = Eν/((1+ν)(1−2ν)), μ = E/(2(1+ν)). These are the 3D
    /// Lamé parameters; in 2D they give plane strain ([`LinearElasticity::plane_strain`]).
    ///
    /// # Errors
    /// [`Error::InvalidYoungsModulus`] unless `e > 0` and finite;
    /// [`Error::InvalidPoissonRatio`] unless `−1 < nu < 0.5`.
    pub fn isotropic(e: f64, nu: f64) -> Result<Self> {
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

    /// Plane strain (2D) from Young's modulus `e` and Poisson's ratio `nu`
    /// (docs/math.md §1): the 3D Lamé parameters of [`LinearElasticity::isotropic`] with
    /// `ε_zz = 0`.
    ///
    /// # Errors
    /// As [`LinearElasticity::isotropic`].
    pub fn plane_strain(e: f64, nu: f64) -> Result<Self> {
        Self::isotropic(e, nu)
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
    p1_mass_components::<D, D>(measure, rho, out);
}

/// Local consistent mass matrix with `C` components per vertex (`C = D` is [`p1_mass`];
/// `C = 1` the scalar mass): `out` has `(C(D+1))²` entries, overwritten.
#[inline]
pub fn p1_mass_components<const D: usize, const C: usize>(measure: f64, rho: f64, out: &mut [f64]) {
    let n = C * (D + 1);
    debug_assert_eq!(out.len(), n * n);
    out.fill(0.0);
    let base = rho * measure / ((D + 1) * (D + 2)) as f64;
    for a in 0..=D {
        for b in 0..=D {
            let m = if a == b { 2.0 * base } else { base };
            for r in 0..C {
                out[(C * a + r) * n + C * b + r] = m;
            }
        }
    }
}

/// Local scalar stiffness of a P1 simplex, `K_ab = μ |T| ∇λ_a·∇λ_b` (the antiplane
/// operator `−∇·(μ∇u)`); `out` has `(D+1)²` entries, overwritten. Rows sum to zero.
#[inline]
pub fn p1_laplace<const D: usize>(grads: &[[f64; D]; 4], measure: f64, mu: f64, out: &mut [f64]) {
    let k = D + 1;
    debug_assert_eq!(out.len(), k * k);
    for a in 0..k {
        for b in 0..k {
            let mut dot = 0.0;
            for r in 0..D {
                dot += grads[a][r] * grads[b][r];
            }
            out[a * k + b] = measure * mu * dot;
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

/// Quadrature on the reference tetrahedron exact for degree 5 (14 points, positive weights;
/// two 4-point orbits `(a, a, a, 1 − 3a)` and one 6-point orbit `(b, b, ½ − b, ½ − b)`):
/// `(barycentric coordinates, weight)`, weights summing to 1 (multiply by the volume).
pub fn tetrahedron_quadrature() -> [([f64; 4], f64); 14] {
    const A: [(f64, f64); 2] = [
        (0.310_885_919_263_300_6, 0.112_687_925_718_015_85),
        (0.092_735_250_310_891_23, 0.073_493_043_116_361_95),
    ];
    const B: (f64, f64) = (0.045_503_704_125_649_65, 0.042_546_020_777_081_47);
    let mut q = [([0.0; 4], 0.0); 14];
    let mut k = 0;
    for (a, w) in A {
        for i in 0..4 {
            let mut l = [a; 4];
            l[i] = 1.0 - 3.0 * a;
            q[k] = (l, w);
            k += 1;
        }
    }
    let (b, w) = B;
    for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
        let mut l = [0.5 - b; 4];
        l[i] = b;
        l[j] = b;
        q[k] = (l, w);
        k += 1;
    }
    q
}

/// The degree-5 rule on the `dim`-simplex (`dim ≤ 3`; a single point for `dim = 0`) with
/// barycentric coordinates padded to 4 entries.
pub(crate) fn simplex_quadrature(dim: usize) -> Vec<([f64; 4], f64)> {
    fn pad<const N: usize>(l: [f64; N]) -> [f64; 4] {
        let mut p = [0.0; 4];
        p[..N].copy_from_slice(&l);
        p
    }
    match dim {
        0 => vec![([1.0, 0.0, 0.0, 0.0], 1.0)],
        1 => segment_quadrature()
            .into_iter()
            .map(|(l, w)| (pad(l), w))
            .collect(),
        2 => triangle_quadrature()
            .into_iter()
            .map(|(l, w)| (pad(l), w))
            .collect(),
        _ => tetrahedron_quadrature().to_vec(),
    }
}
