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
    /// `K + M` with mass; `None` without, where it is `K` (copied from the stiffness only
    /// when the model is made, so that no stage transforms or holds it twice:
    /// [`Matrices::energy_norm_or_stiffness`]).
    pub energy_norm: Option<SparseMatrix>,
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
/// absorbing parts `absorbing` under `constraints`: whole, or only the columns of the nodes
/// with `columns[vertex]` ([`Medium::assemble_columns`]; the dashpots on the same columns).
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
    columns: Option<&[bool]>,
) -> Result<Matrices> {
    absorbing::check(absorbing, material, with_mass)?;
    let MediumMatrices {
        stiffness,
        mass,
        energy_norm,
    } = match columns {
        Some(keep) => material.assemble_columns(mesh, with_mass, keep)?,
        None => material.assemble(mesh, with_mass)?,
    };
    let absorbing =
        absorbing::dashpots(absorbing, mesh, material, constraints, &stiffness, columns)?;
    // Without mass the energy norm is the stiffness (Medium::assemble's contract): the
    // copy is dropped here and made again from the final stiffness (the same bits: every
    // later stage transforms both alike).
    let energy_norm = mass.is_some().then_some(energy_norm);
    Ok(Matrices {
        stiffness,
        mass,
        energy_norm,
        absorbing,
    })
}

impl Matrices {
    /// The columns of the nodes with `keep[vertex]` of every matrix (the dashpots' too), the
    /// others emptied (rows and bits of the kept ones unchanged); the far-field force stays
    /// whole.
    ///
    /// # Errors
    /// [`crate::Error::Fem`] if `keep` does not have one flag per node.
    pub fn node_columns(self, keep: &[bool]) -> Result<Self> {
        self.map(|a| Ok(rsf_fem::node_columns(&a, keep)?), Ok)
    }

    /// Every matrix through `matrix` — the dashpots', then `M`, `K` and the energy norm,
    /// one at a time, each original dropped once mapped (the peak is the matrices plus one
    /// map's work; issue 55) — and the dashpots' far-field force (`n` entries, or empty)
    /// through `force`: what a stage that transforms the system does to its matrices.
    ///
    /// # Errors
    /// The first error of `matrix` or `force`.
    pub fn map(
        self,
        mut matrix: impl FnMut(SparseMatrix) -> Result<SparseMatrix>,
        force: impl FnOnce(Vec<f64>) -> Result<Vec<f64>>,
    ) -> Result<Self> {
        let Self {
            stiffness,
            mass,
            energy_norm,
            absorbing,
        } = self;
        let absorbing = match absorbing {
            Some(mut a) => {
                a.damping = matrix(a.damping)?;
                a.far_field_force = force(std::mem::take(&mut a.far_field_force))?;
                Some(a)
            }
            None => None,
        };
        let mass = mass.map(&mut matrix).transpose()?;
        let stiffness = matrix(stiffness)?;
        let energy_norm = energy_norm.map(&mut matrix).transpose()?;
        Ok(Self {
            stiffness,
            mass,
            energy_norm,
            absorbing,
        })
    }

    /// The energy norm: `K + M`, or a copy of the stiffness `K` without mass.
    pub fn energy_norm_or_stiffness(&mut self) -> SparseMatrix {
        self.energy_norm
            .take()
            .unwrap_or_else(|| self.stiffness.clone())
    }
}
