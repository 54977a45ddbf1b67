//! Stage 7 (a fault inside the body): the jump shared between the sides by their stiffness
//! at each pair, and the pairs whose slip is prescribed — both sides clamped by Dirichlet
//! parts, in the creeping section, or slipped by a kinematic source — with their data
//! (velocities, held displacements) in the mean–jump unknowns.

use rsf_fem::{SimplexMesh, SparseMatrix};
use rsf_numeric::normal_component;

use super::constraints::Constraints;
use crate::error::{invalid, Result};
use crate::model::creep::{CreepField, SlipField};
use crate::model::internal::InternalFault;

/// A fault inside the body ready for the change of variables.
pub(crate) struct SharedFault<const D: usize> {
    /// The fault, its jump shared by the sides' stiffness
    /// ([`InternalFault::shared_by_stiffness`]).
    pub fault: InternalFault<D>,
    /// Per slip node ([`InternalFault::slip_nodes`]): its slip is prescribed (not a
    /// frictional node).
    pub prescribed: Vec<bool>,
}

/// What prescribes a fault inside the body's pairs besides Dirichlet parts.
pub(crate) struct Kinematics<'a, const D: usize> {
    /// The creeping section's rates.
    pub creep: Option<&'a CreepField<D>>,
    /// The kinematic source's slips.
    pub slip: Option<&'a SlipField<D>>,
}

/// `fault` with its jump shared by `stiffness` (Cartesian, of the split mesh `mesh`), and
/// its prescribed pairs (both sides fully fixed in `constraints`, or `kinematics` giving a
/// rate or a slip at the minus vertex) fixed in `constraints` with their velocities and
/// held displacements in the mean–jump unknowns.
///
/// # Errors
/// The transform's; [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
/// `dirichlet` for clamped sides that open or close the fault, `internal_creep` for a rate
/// [`CreepRate`](crate::model::CreepRate) refuses, `internal_slip` for a slip
/// [`PrescribedSlip`](crate::model::PrescribedSlip) refuses or one at clamped sides.
pub(crate) fn share_and_prescribe<const D: usize, const C: usize>(
    fault: InternalFault<D>,
    stiffness: &SparseMatrix,
    mesh: &SimplexMesh<D>,
    kinematics: Kinematics<'_, D>,
    constraints: &mut Constraints<D, C>,
) -> Result<SharedFault<D>> {
    let fault = fault.shared_by_stiffness::<C>(stiffness)?;
    let prescribed = prescribed_pairs::<D, C>(&fault, mesh, kinematics, constraints)?;
    Ok(SharedFault { fault, prescribed })
}

/// Stage 7 of the build: a fault inside the body (if any) shared by the sides'
/// stiffness with its prescribed pairs ([`share_and_prescribe`]), and the slanted nodes
/// of a frictional boundary beside it in their frames.
///
/// # Errors
/// Those of [`share_and_prescribe`]; a boundary frame the fault's transform refuses.
pub(crate) fn share_fault<const D: usize, const C: usize>(
    fault: Option<InternalFault<D>>,
    stiffness: &SparseMatrix,
    mesh: &SimplexMesh<D>,
    kinematics: Kinematics<'_, D>,
    constraints: &mut Constraints<D, C>,
) -> Result<Option<SharedFault<D>>> {
    let Some(fault) = fault else {
        return Ok(None);
    };
    let f = share_and_prescribe(fault, stiffness, mesh, kinematics, constraints)?;
    Ok(Some(SharedFault {
        fault: f.fault.with_boundary_frames(&constraints.boundary_frames)?,
        ..f
    }))
}

/// Per pair of the internal fault `fault`: whether its slip is prescribed. A pair whose
/// two sides are fully fixed by Dirichlet parts gets their velocities (and held
/// displacements) in its mean–jump unknowns (`j = Rᵀ(v⁺ − v⁻)`, `w = (1 − β) v⁻ + β v⁺`;
/// an opening is refused); a pair in the creeping section or with a prescribed slip gets
/// its jump's tangential components fixed at the creep rate (else 0) and, held, at the
/// slip (else 0).
fn prescribed_pairs<const D: usize, const C: usize>(
    fault: &InternalFault<D>,
    mesh: &SimplexMesh<D>,
    kinematics: Kinematics<'_, D>,
    constraints: &mut Constraints<D, C>,
) -> Result<Vec<bool>> {
    let Constraints {
        fixed,
        velocity,
        displacement,
        ..
    } = constraints;
    let vector = C == D && C > 1;
    let tangential = if vector { C - 1 } else { 1 };
    let mut prescribed = Vec::with_capacity(fault.slip_nodes().len());
    for node in fault.slip_nodes() {
        let mi = node.vertex;
        let x = &mesh.vertices()[mi];
        let slip = kinematics.slip.and_then(|slip| slip(x));
        // Both sides fully fixed (checked by internal_fault_frames; a junction's copies
        // never are).
        if let Some((k, pl)) = node
            .pair
            .filter(|_| fixed[C * mi])
            .map(|k| (k, fault.pairs()[k].1))
        {
            if slip.is_some() {
                return Err(invalid(
                    "internal_slip",
                    format!(
                        "the pair at {x:?} m of the internal fault `{}` has both sides held \
                         by Dirichlet parts, whose data give its jump: no prescribed slip there",
                        fault.fault_name(node.fault)
                    ),
                ));
            }
            let held = displacement[C * mi..C * mi + C]
                .iter()
                .chain(&displacement[C * pl..C * pl + C])
                .any(Option::is_some);
            in_mean_and_jump::<D, C>(fault, k, velocity, "m/s")?;
            if held {
                in_mean_and_jump::<D, C>(fault, k, displacement, "m")?;
            }
            prescribed.push(true);
            continue;
        }
        let rate = kinematics.creep.and_then(|creep| creep(x));
        if rate.is_none() && slip.is_none() {
            prescribed.push(false);
            continue;
        }
        let frame = &fault.transform.frames[node.frame];
        let j_rate = match rate {
            Some(rate) => Some(rate.in_frame::<C>(frame, x)?),
            None => None,
        };
        let j_slip = match slip {
            Some(slip) => Some(slip.in_frame::<C>(frame, x)?),
            None => None,
        };
        for c in 0..tangential {
            fixed[C * mi + c] = true;
            // A creep rate only where one is given: a slipped pair without one keeps its
            // velocity `None` (0), so that the model's data are what they were without
            // the slip.
            if let Some(j) = j_rate {
                velocity[C * mi + c] = Some(j[c]);
            }
            if let Some(j) = j_slip {
                displacement[C * mi + c] = Some(j[c]);
            }
        }
        prescribed.push(true);
    }
    Ok(prescribed)
}

/// The Cartesian data `values` (velocities or held displacements, in `unit`) of pair `k`'s
/// two fully fixed sides written in its mean–jump unknowns: the minus vertex's block the
/// jump `Rᵀ(w⁺ − w⁻)` (its normal component tied, 0), the plus vertex's the mean
/// `(1 − β) w⁻ + β w⁺`.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `dirichlet` if the
/// data open or close the fault (a normal jump above `1e-12` of their size).
fn in_mean_and_jump<const D: usize, const C: usize>(
    fault: &InternalFault<D>,
    k: usize,
    values: &mut [Option<f64>],
    unit: &str,
) -> Result<()> {
    let (mi, pl) = fault.pairs()[k];
    let beta = fault.transform.minus_share[k];
    let v = |p: usize| -> [f64; C] { std::array::from_fn(|c| values[C * p + c].unwrap_or(0.0)) };
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
                "the Dirichlet parts at split node {mi} of the internal fault `{}` open or \
                 close it (normal jump {:e} {unit}): the fault's normal jump is tied",
                fault.fault_name(fault.pair_fault(k)),
                j[normal_component(C)]
            ),
        ));
    }
    for c in 0..C {
        let tied = c == normal_component(C) && vector;
        values[C * mi + c] = Some(if tied { 0.0 } else { j[c] });
        values[C * pl + c] = Some((1.0 - beta) * vm[c] + beta * vp[c]);
    }
    Ok(())
}
