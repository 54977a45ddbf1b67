//! Isotropic linear elasticity: the medium's constants and Hooke's law
//! `σ = λ tr(ε) I + 2μ ε`, `ε = (∇u + ∇uᵀ)/2` (docs/halfspace.md §3).

use crate::error::Error;

/// A homogeneous isotropic elastic medium (Lamé constants in Pa).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Medium {
    lambda: f64,
    mu: f64,
}

impl Medium {
    /// From the Lamé constants `λ` and `μ` (Pa).
    ///
    /// # Errors
    /// [`Error::Parameter`] unless both are finite, `μ > 0` and `3λ + 2μ > 0` (a positive
    /// bulk modulus, `−1 < ν < ½`).
    pub fn new(lambda: f64, mu: f64) -> Result<Self, Error> {
        if !(mu.is_finite() && mu > 0.0) {
            return Err(Error::Parameter {
                name: "mu",
                value: mu,
                expected: "finite and > 0",
            });
        }
        if !(lambda.is_finite() && 3.0 * lambda + 2.0 * mu > 0.0) {
            return Err(Error::Parameter {
                name: "lambda",
                value: lambda,
                expected: "finite and > -2 mu / 3",
            });
        }
        Ok(Self { lambda, mu })
    }

    /// From the shear modulus `μ` (Pa) and Poisson's ratio `ν`:
    /// `λ = 2μν/(1 − 2ν)`.
    ///
    /// # Errors
    /// [`Error::Parameter`] unless `μ` is finite and positive and `−1 < ν < ½`.
    pub fn from_shear_poisson(mu: f64, nu: f64) -> Result<Self, Error> {
        if !(nu > -1.0 && nu < 0.5) {
            return Err(Error::Parameter {
                name: "nu",
                value: nu,
                expected: "in (-1, 0.5)",
            });
        }
        Self::new(2.0 * mu * nu / (1.0 - 2.0 * nu), mu)
    }

    /// `λ` (Pa).
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// `μ` (Pa).
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// Poisson's ratio `ν = λ/(2(λ + μ))`.
    pub fn nu(&self) -> f64 {
        self.lambda / (2.0 * (self.lambda + self.mu))
    }

    /// Okada's medium constant `α = (λ + μ)/(λ + 2μ) = 1/(2(1 − ν))`.
    pub fn alpha(&self) -> f64 {
        (self.lambda + self.mu) / (self.lambda + 2.0 * self.mu)
    }

    /// The stress (Pa) of the displacement gradient `grad[i][j] = ∂u_i/∂x_j`:
    /// `σ_ij = λ (∂u_k/∂x_k) δ_ij + μ (∂u_i/∂x_j + ∂u_j/∂x_i)`, symmetric, tension
    /// positive.
    pub fn stress(&self, grad: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let div = grad[0][0] + grad[1][1] + grad[2][2];
        let mut s = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                s[i][j] = self.mu * (grad[i][j] + grad[j][i]);
            }
            s[i][i] += self.lambda * div;
        }
        s
    }
}

/// The traction `t = σ n` on a plane of unit normal `n`.
pub fn traction(stress: &[[f64; 3]; 3], n: &[f64; 3]) -> [f64; 3] {
    let mut t = [0.0; 3];
    for i in 0..3 {
        t[i] = stress[i][0] * n[0] + stress[i][1] * n[1] + stress[i][2] * n[2];
    }
    t
}
