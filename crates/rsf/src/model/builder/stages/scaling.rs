//! Stage 6: an antisymmetric fault (docs/math.md §11) — the model's unknown is `ũ = s·u`
//! (`s` the slip factor), so every block on Γ_F is the slip: `K/s²`, `M/s²`, dashpots
//! `C/s²`, `F/s` and the far-field force `C w / s`.

use rsf_fem::combine;

use super::matrices::System;
use crate::error::Result;

impl System {
    /// The system in the unknown `s·u`; unchanged (the same bits) for `s = 1`.
    ///
    /// # Errors
    /// [`crate::Error::Fem`] on allocation failure.
    pub fn scaled(self, s: f64) -> Result<Self> {
        if s == 1.0 {
            return Ok(self);
        }
        let Self { matrices, mut load } = self;
        let k = 1.0 / (s * s);
        for l in &mut load {
            *l /= s;
        }
        let matrices = matrices.map(
            |a| Ok(combine(0.0, &a, k, &a).map_err(rsf_fem::Error::from)?),
            // C̃ (s w) = C w / s.
            |mut force| {
                force.iter_mut().for_each(|f| *f /= s);
                Ok(force)
            },
        )?;
        Ok(Self { matrices, load })
    }
}
