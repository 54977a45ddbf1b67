//! Stage 4: the matrices — stiffness, mass and energy norm of the medium and the dashpots
//! of absorbing parts, Cartesian, in the unknown `u`; with the load (stage 5), the
//! [`System`] the later stages transform.

use rsf_fem::{SimplexMesh, SparseMatrix};

use super::super::settings::Absorbing;
use super::absorbing;
use super::constraints::Constraints;
use crate::error::Result;
use crate::model::absorbing::AbsorbingBoundary;
use crate::model::medium::{Medium, MediumMatrices};

/// The model's matrices (`n × n`, `n = C · vertices`, node-major, one pattern).
pub(crate) struct Matrices {
    /// `K`.
    pub stiffness: SparseMatrix,
    /// `M`, with inertia.
    pub mass: Option<SparseMatrix>,
    /// `K + M` (`K` without mass).
    pub energy_norm: SparseMatrix,
    /// The dashpots of absorbing parts, if any.
    pub absorbing: Option<AbsorbingBoundary>,
}

/// The matrices and the load (N) of the model, in the unknowns the last stage left them.
pub(crate) struct System {
    /// The matrices.
    pub matrices: Matrices,
    /// `F` (`n` entries).
    pub load: Vec<f64>,
}

/// The matrices of `material` on `mesh` (with mass if `with_mass`) and the dashpots of the
/// absorbing parts `absorbing` under `constraints`.
///
/// # Errors
/// The absorbing parts' checks (before assembly, so that a medium the mass matrix would
/// refuse is named by them, and after: a facet on Γ_F, every dof fixed); the medium's
/// assembly errors.
pub(crate) fn assemble<const D: usize, const C: usize>(
    mesh: &SimplexMesh<D>,
    material: &dyn Medium<D, C>,
    with_mass: bool,
    absorbing: &[Absorbing<D, C>],
    constraints: &Constraints<D, C>,
) -> Result<Matrices> {
    absorbing::check(absorbing, material, with_mass)?;
    let MediumMatrices {
        stiffness,
        mass,
        energy_norm,
    } = material.assemble(mesh, with_mass)?;
    let absorbing = absorbing::dashpots(
        absorbing,
        mesh,
        material,
        &constraints.gamma_f,
        &constraints.fixed,
        &stiffness,
    )?;
    Ok(Matrices {
        stiffness,
        mass,
        energy_norm,
        absorbing,
    })
}
