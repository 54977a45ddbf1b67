//! The quadratic part `½ vᵀAv − bᵀv`: its matrix with the fixed dofs, validated once for
//! every solver.

use rsf_linalg::Csc;

use crate::error::{ProblemError, Result};

/// A validated symmetric matrix with node-block structure and a fixed-dof mask, in scalar
/// CSC storage (the direct solver's format; TNNMG blocks it after these checks).
#[derive(Debug, Clone)]
pub struct BlockedMatrix<const D: usize> {
    /// The matrix (`n × n`, both triangles).
    pub a: Csc,
    /// The fixed-dof mask (length `n`).
    pub fixed: Vec<bool>,
}

impl<const D: usize> BlockedMatrix<D> {
    /// Validates `a` with block size `D` and the mask `fixed`.
    ///
    /// # Errors
    /// Non-symmetric pattern, missing diagonal, dimension not a multiple of `D`, mask of
    /// the wrong length, non-positive diagonal entry on a free dof.
    pub fn new(a: Csc, fixed: &[bool]) -> Result<Self> {
        a.check_symmetric_pattern()?;
        let n = a.nrows;
        if n % D != 0 {
            return Err(ProblemError::InvalidMatrix(format!(
                "dimension {n} is not a multiple of the block size {D}"
            )));
        }
        ProblemError::check_length("fixed mask", n, fixed.len())?;
        for (i, p) in a.diagonal_positions()?.into_iter().enumerate() {
            if !fixed[i] && a.val[p] <= 0.0 {
                return Err(ProblemError::NotPositiveDefinite(
                    "non-positive diagonal entry on a free dof",
                ));
            }
        }
        Ok(Self {
            a,
            fixed: fixed.to_vec(),
        })
    }
}
