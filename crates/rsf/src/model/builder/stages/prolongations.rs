//! Stage 10: the prolongations of the refinement hierarchy for multigrid, node-major with
//! `C` components per vertex, the finest onto the model's unknowns (`T⁻¹ P`: `Rᵀ P` for
//! nodal frames, the mean–jump unknowns of a fault inside the body; coarser levels stay
//! Cartesian).

use rsf_fem::{vectorize, DofTransform, SparseMatrix};

use super::domain::Domain;
use crate::error::Result;

/// `P_j` from level `j − 1` to level `j` (`j = 1, …`, coarse to fine) of `domain`'s
/// hierarchy (split along a fault inside the body where it resolves it), the finest taken
/// onto the unknowns of `t`.
///
/// # Errors
/// The transform's ([`crate::Error::Fem`]).
pub(crate) fn prolongations<const D: usize, const C: usize>(
    domain: &Domain<'_, D>,
    t: &dyn DofTransform,
) -> Result<Vec<SparseMatrix>> {
    let hierarchy = domain.hierarchy;
    let mut prolongations: Vec<_> = match &domain.split_prolongations {
        // Split levels: Cartesian coarse spaces, discontinuous across the fault.
        Some(split) => split.iter().map(vectorize::<C>).collect(),
        None => (1..hierarchy.num_levels())
            .map(|j| match C {
                1 => hierarchy.prolongation(j).clone(),
                _ if C == D => hierarchy.vector_prolongation(j).clone(),
                _ => vectorize::<C>(hierarchy.prolongation(j)),
            })
            .collect(),
    };
    if let Some(p) = prolongations.last_mut().filter(|_| !t.is_identity()) {
        *p = t.prolongation(p)?;
    }
    Ok(prolongations)
}
