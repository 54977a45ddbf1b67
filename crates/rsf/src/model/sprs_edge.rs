//! `sprs` matrices in and out of a [`Model`] (feature `sprs`): for users whose own sparse
//! code holds its matrices as `sprs::CsMat<f64>`.

use sprs::{CsMat, CsMatView};

use super::Model;
use crate::error::{invalid, Error, Result};

fn to_sprs(a: &rsf_fem::SparseMatrix) -> Result<CsMat<f64>> {
    rsf_linalg::to_sprs(a).map_err(|e| Error::Fem(e.into()))
}

fn from_sprs(name: &str, a: CsMatView<'_, f64>, n: usize) -> Result<rsf_fem::SparseMatrix> {
    if a.shape() != (n, n) {
        let (r, c) = a.shape();
        return Err(invalid(name, format!("is {r}x{c}, expected {n}x{n}")));
    }
    rsf_linalg::from_sprs(&a).map_err(|e| Error::Fem(e.into()))
}

impl<const D: usize, const C: usize> Model<D, C> {
    /// The stiffness matrix `K` as a `sprs` CSC matrix (`n × n`, `n = C · nodes`, node-major
    /// dofs; N/m, per unit thickness in 2D), entries in the model's order.
    ///
    /// # Errors
    /// [`Error::Fem`] if a column's row indices are not sorted and unique (sprs requires
    /// it; matrices assembled by rsf always are).
    pub fn stiffness_sprs(&self) -> Result<CsMat<f64>> {
        to_sprs(&self.stiffness)
    }

    /// The mass matrix `M` as a `sprs` CSC matrix (`n × n`; kg, per unit thickness in 2D),
    /// or `None` for a model without mass (quasistatic).
    ///
    /// # Errors
    /// As [`Model::stiffness_sprs`].
    pub fn mass_sprs(&self) -> Result<Option<CsMat<f64>>> {
        self.mass.as_ref().map(to_sprs).transpose()
    }

    /// Replaces the stiffness matrix and the mass matrix (`None`: no mass, quasistatic) by
    /// `sprs` CSC matrices (`n × n`, `n = C · nodes`, node-major dofs, SI units as the
    /// fields), and the energy norm by `K + M` (`K` without mass), as
    /// [`ModelBuilder`](crate::ModelBuilder) sets it (docs/math.md §3). Convert a CSR matrix
    /// with `to_csc()` first. Nothing else of the model changes; [`Model::validate`] (which
    /// every simulation runs) checks the result against the other fields.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `stiffness` or `mass` for a matrix that is not
    /// `n × n`; [`Error::Fem`] for a CSR matrix or an inconsistent structure. On error the
    /// model is unchanged.
    pub fn set_matrices_sprs(
        &mut self,
        stiffness: CsMatView<'_, f64>,
        mass: Option<CsMatView<'_, f64>>,
    ) -> Result<()> {
        let n = C * self.vertices.len();
        let k = from_sprs("stiffness", stiffness, n)?;
        let (m, energy) = match mass {
            Some(mass) => {
                let m = from_sprs("mass", mass, n)?;
                // Both are n × n CSC here (checked above), so the sum cannot panic.
                let sum: CsMat<f64> = &stiffness + &mass;
                (Some(m), from_sprs("energy_norm", sum.view(), n)?)
            }
            None => (None, k.clone()),
        };
        self.stiffness = k;
        self.mass = m;
        self.energy_norm = energy;
        Ok(())
    }
}
