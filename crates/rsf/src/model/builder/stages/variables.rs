//! Stage 8: the change of variables — the system in the model's unknowns `u = T u′`
//! through one [`DofTransform`]: the nodal frames of a slanted boundary fault
//! (`T = R = blockdiag(Q_p)`, docs/math.md §10.1), or the mean and jump of a fault inside
//! the body (docs/math.md §15); nothing (the same bits) where `T` is the identity.

use rsf_fem::DofTransform;

use super::matrices::{Matrices, System};
use crate::error::Result;

impl System {
    /// `Tᵀ A T` of every matrix (stiffness, mass, energy norm, dashpots; each made exactly
    /// symmetric), `Tᵀ F` of the load and of the dashpots' far-field force.
    ///
    /// # Errors
    /// The transform's ([`crate::Error::Fem`]).
    pub fn in_unknowns(self, t: &dyn DofTransform) -> Result<Self> {
        if t.is_identity() {
            return Ok(self);
        }
        let Self {
            matrices:
                Matrices {
                    stiffness,
                    mass,
                    energy_norm,
                    absorbing,
                },
            load,
        } = self;
        let congruence = |a: &rsf_fem::SparseMatrix| t.congruence(a);
        let absorbing = match absorbing {
            Some(mut a) => {
                a.damping = congruence(&a.damping)?;
                if !a.far_field_force.is_empty() {
                    a.far_field_force = t.pull_back(&a.far_field_force)?;
                }
                Some(a)
            }
            None => None,
        };
        // One matrix at a time, each original dropped once transformed: the peak is the
        // matrices plus one congruence's work (issue 55: this stage was a split 3-D model's
        // peak).
        let transformed = |a: rsf_fem::SparseMatrix| t.congruence(&a);
        let mass = mass.map(transformed).transpose()?;
        let stiffness = transformed(stiffness)?;
        let energy_norm = energy_norm.map(transformed).transpose()?;
        Ok(Self {
            matrices: Matrices {
                mass,
                stiffness,
                energy_norm,
                absorbing,
            },
            load: t.pull_back(&load)?,
        })
    }
}
