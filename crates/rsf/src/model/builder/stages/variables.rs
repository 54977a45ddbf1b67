//! Stage 8: the change of variables — the system in the model's unknowns `u = T u′`
//! through one [`DofTransform`]: the nodal frames of a slanted boundary fault
//! (`T = R = blockdiag(Q_p)`, docs/math.md §10.1), or the mean and jump of a fault inside
//! the body (docs/math.md §15); nothing (the same bits) where `T` is the identity.

use rsf_fem::DofTransform;

use super::matrices::System;
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
        let matrices = self.matrices.map(
            |a| Ok(t.congruence(&a)?),
            |force| {
                if force.is_empty() {
                    Ok(force)
                } else {
                    Ok(t.pull_back(&force)?)
                }
            },
        )?;
        Ok(Self {
            matrices,
            load: t.pull_back(&self.load)?,
        })
    }
}
