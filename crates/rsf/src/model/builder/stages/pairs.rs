//! Stage 7 (a fault inside the body): the jump shared between the sides by their stiffness
//! at each pair, and the pairs whose slip is prescribed — both sides clamped by Dirichlet
//! parts, or in the creeping section — with their data in the mean–jump unknowns.

use rsf_fem::{SimplexMesh, SparseMatrix};
use rsf_numeric::normal_component;

use super::constraints::Constraints;
use crate::error::{invalid, Result};
use crate::model::creep::CreepField;
use crate::model::internal::InternalFault;

/// A fault inside the body ready for the change of variables.
pub(crate) struct SharedFault<const D: usize> {
    /// The fault, its jump shared by the sides' stiffness
    /// ([`InternalFault::shared_by_stiffness`]).
    pub fault: InternalFault<D>,
    /// Per pair ([`InternalFault::pairs`]): its slip is prescribed (not a frictional node).
    pub prescribed: Vec<bool>,
}

/// `fault` with its jump shared by `stiffness` (Cartesian, of the split mesh `mesh`), and
/// its prescribed pairs (both sides fully fixed in `constraints`, or `creep` giving a rate
/// at the minus vertex) fixed in `constraints` with their velocities in the mean–jump
/// unknowns.
///
/// # Errors
/// The transform's; [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
/// `dirichlet` for clamped sides that open or close the fault, `internal_creep` for a rate
/// [`CreepRate`](crate::model::CreepRate) refuses.
pub(crate) fn share_and_prescribe<const D: usize, const C: usize>(
    fault: InternalFault<D>,
    stiffness: &SparseMatrix,
    mesh: &SimplexMesh<D>,
    creep: Option<&CreepField<D>>,
    constraints: &mut Constraints<D, C>,
) -> Result<SharedFault<D>> {
    let fault = fault.shared_by_stiffness::<C>(stiffness)?;
    let prescribed = prescribed_pairs::<D, C>(
        &fault,
        mesh,
        creep,
        &mut constraints.fixed,
        &mut constraints.velocity,
    )?;
    Ok(SharedFault { fault, prescribed })
}

/// Per pair of the internal fault `fault`: whether its slip is prescribed. A pair whose
/// two sides are fully fixed by Dirichlet parts gets their velocities in its
/// mean–jump unknowns (`j = Rᵀ(v⁺ − v⁻)`, `w = (1 − β) v⁻ + β v⁺`; an opening is
/// refused); a pair in the creeping section gets its jump's tangential component fixed
/// at the creep rate.
fn prescribed_pairs<const D: usize, const C: usize>(
    fault: &InternalFault<D>,
    mesh: &SimplexMesh<D>,
    creep: Option<&CreepField<D>>,
    fixed: &mut [bool],
    velocity: &mut [Option<f64>],
) -> Result<Vec<bool>> {
    let mut prescribed = Vec::with_capacity(fault.pairs().len());
    for (k, &(mi, pl)) in fault.pairs().iter().enumerate() {
        let beta = fault.transform.minus_share[k];
        if fixed[C * mi] {
            // Both sides fully fixed (checked by internal_fault_frames).
            let v = |p: usize| -> [f64; C] {
                std::array::from_fn(|c| velocity[C * p + c].unwrap_or(0.0))
            };
            let (vm, vp) = (v(mi), v(pl));
            let dv: [f64; C] = std::array::from_fn(|c| vp[c] - vm[c]);
            let vector = C == D && C > 1;
            let j: [f64; C] = if vector {
                let r = fault.transform.frames[k];
                std::array::from_fn(|a| (0..C).map(|b| r[b][a] * dv[b]).sum())
            } else {
                dv
            };
            let scale = vm.iter().chain(&vp).fold(0.0f64, |m, x| m.max(x.abs()));
            if vector && j[normal_component(C)].abs() > 1e-12 * scale {
                return Err(invalid(
                    "dirichlet",
                    format!(
                        "the Dirichlet parts at split node {mi} of the internal fault `{}` \
                         open or close it (normal jump {:e} m/s): the fault's normal jump \
                         is tied",
                        fault.sides.name(),
                        j[normal_component(C)]
                    ),
                ));
            }
            for c in 0..C {
                let tied = c == normal_component(C) && vector;
                velocity[C * mi + c] = Some(if tied { 0.0 } else { j[c] });
                velocity[C * pl + c] = Some((1.0 - beta) * vm[c] + beta * vp[c]);
            }
            prescribed.push(true);
        } else if let Some(rate) = creep.and_then(|creep| creep(&mesh.vertices()[mi])) {
            let x = &mesh.vertices()[mi];
            let j = rate.in_frame::<C>(&fault.transform.frames[k], x)?;
            let tangential = if C == D && C > 1 { C - 1 } else { 1 };
            for (c, &jc) in j.iter().enumerate().take(tangential) {
                fixed[C * mi + c] = true;
                velocity[C * mi + c] = Some(jc);
            }
            prescribed.push(true);
        } else {
            prescribed.push(false);
        }
    }
    Ok(prescribed)
}
