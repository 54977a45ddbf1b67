//! Stage 3: the constraints — the Dirichlet parts resolved on the model's mesh, Γ_F
//! resolved with the frames of its nodes, bilateral contact (the normal component of every
//! frictional node fixed), the prescribed velocities in the basis of their node.

use rsf_fem::{BoundaryPart, NodalFrames, SimplexMesh};
use rsf_numeric::normal_component;

use super::super::settings::{Dirichlet, Faults};
use super::frames::{fault_frames, internal_fault_frames, normal_axis, same_block_size};
use super::inputs::FaultPart;
use crate::error::{invalid, Result};
use crate::model::internal::InternalFault;
use crate::model::loading::{DirichletVelocity, TimeFunction};

/// The constraints of the model's dofs (node-major, `C` per vertex of the model's mesh).
pub(crate) struct Constraints<const D: usize, const C: usize> {
    /// Per dof: constrained (Dirichlet, bilateral contact, a tied normal jump).
    pub fixed: Vec<bool>,
    /// Per dof: the velocity factor `w_i` (m/s, of `u`; times `g(t)`) of a Dirichlet dof, in
    /// its node's basis (a slanted fault node's frame, Cartesian elsewhere); `None` where
    /// nothing is prescribed (a fixed dof without data moves with velocity 0).
    pub velocity: Vec<Option<f64>>,
    /// Per dof: the displacement (m) of a held dof in the initial equilibrium, in its node's
    /// basis as `velocity` ([`ModelBuilder::dirichlet_displacement`](crate::ModelBuilder::dirichlet_displacement),
    /// a prescribed slip); `None` where nothing is given (0).
    pub displacement: Vec<Option<f64>>,
    /// Γ_F on the model's mesh.
    pub gamma_f: BoundaryPart<D>,
    /// The frames of Γ_F's nodes: a boundary fault's slanted nodes (the model's basis there)
    /// and the faults inside the body's pair frames at the jump blocks.
    pub frames: NodalFrames<C>,
    /// The frames of the frictional boundary's slanted nodes alone (the part of
    /// [`frames`](Self::frames) the faults' transform takes besides its own).
    pub boundary_frames: NodalFrames<C>,
    /// The frictional boundary alone (beside faults inside the body; `gamma_f` without
    /// their faces), if one was given.
    pub boundary: Option<BoundaryPart<D>>,
}

/// The constraints on `mesh` of the Dirichlet parts `dirichlet` (in order), of bilateral
/// contact on Γ_F `fault_part` (a vector field; its frames by the kink limit and the 3-D
/// tangent of `faults`), or of a fault inside the body `fault` (its normal jump tied).
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `dirichlet` for
/// components out of range, a non-finite velocity, two parts prescribing different
/// velocities to one dof, a slanted fault node or a split pair with only some components
/// fixed; the parts' resolution errors; [`frames`](super::frames)'.
pub(crate) fn constrain<const D: usize, const C: usize>(
    mesh: &SimplexMesh<D>,
    dirichlet: &[Dirichlet<D, C>],
    fault_part: &FaultPart<'_, D>,
    fault: Option<&InternalFault<D>>,
    faults: &Faults<D>,
) -> Result<Constraints<D, C>> {
    let Held {
        mut fixed,
        mut velocity,
        mut displacement,
    } = dirichlet_dofs(mesh, dirichlet)?;
    let gamma_f = fault_part.resolve(mesh)?;
    let boundary = fault_part.boundary(mesh)?;
    // A fault on the boundary: a vector field slides tangentially (normal component fixed,
    // nodal frames on slanted nodes); a scalar field's one component is tangential to any
    // in-plane Γ_F.
    let boundary_frames: NodalFrames<C> = match &boundary {
        Some(part) if C == D => {
            if let Some(f) = fault {
                disjoint_from_faults(part, f)?;
            }
            let name = part.name().to_owned();
            same_block_size(fault_frames(
                mesh,
                part,
                &name,
                faults.max_kink_degrees,
                faults.tangent,
            )?)
        }
        _ => NodalFrames::default(),
    };
    if let (Some(part), true) = (&boundary, C == D) {
        for (&p, nrm) in part.nodes().iter().zip(&part.normals(mesh)?) {
            if let Some(c) = normal_axis(nrm) {
                fixed[C * p + c] = true;
            }
        }
    }
    if let Some(part) = &boundary {
        in_frames(
            &boundary_frames,
            part.name(),
            &mut fixed,
            [&mut velocity, &mut displacement],
        )?;
    }
    // Faults inside the body: the pair frames (kept for outputs; the matrices take `T`).
    let frames = match fault {
        Some(f) => {
            let pairs: NodalFrames<C> = internal_fault_frames(f, &fixed)?;
            // The normal jump is tied (no opening); a scalar field has only the slip. At a
            // junction the block that keeps the slips single-valued is tied whole.
            if C == D {
                for node in f.slip_nodes() {
                    fixed[C * node.vertex + normal_component(C)] = true;
                }
            }
            for blocks in &f.transform.junctions {
                fixed[C * blocks.tied..C * blocks.tied + C].fill(true);
            }
            merged(pairs, &boundary_frames)
        }
        None => boundary_frames.clone(),
    };
    Ok(Constraints {
        fixed,
        velocity,
        displacement,
        gamma_f,
        frames,
        boundary_frames,
        boundary,
    })
}

/// Refuses a frictional boundary that shares a vertex with a fault inside the body.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `frictional_boundary`.
fn disjoint_from_faults<const D: usize>(
    part: &BoundaryPart<D>,
    fault: &InternalFault<D>,
) -> Result<()> {
    for &p in part.nodes() {
        if fault.pair_of(p).is_some() || fault.junction_of(p).is_some() {
            return Err(invalid(
                "frictional_boundary",
                format!(
                    "node {p} of the frictional boundary `{}` is a split node of a fault \
                     inside the body: a fault may not end on the frictional boundary",
                    part.name()
                ),
            ));
        }
    }
    Ok(())
}

/// The frames of `a` and `b` (on disjoint nodes) in increasing node order.
fn merged<const C: usize>(a: NodalFrames<C>, b: &NodalFrames<C>) -> NodalFrames<C> {
    if b.nodes.is_empty() {
        return a;
    }
    let mut all: Vec<(usize, [[f64; C]; C])> = a
        .nodes
        .into_iter()
        .zip(a.rotations)
        .chain(b.nodes.iter().copied().zip(b.rotations.iter().copied()))
        .collect();
    all.sort_by_key(|f| f.0);
    NodalFrames {
        nodes: all.iter().map(|f| f.0).collect(),
        rotations: all.into_iter().map(|f| f.1).collect(),
    }
}

/// The dofs the Dirichlet parts hold, with their data (Cartesian, per dof).
struct Held {
    fixed: Vec<bool>,
    velocity: Vec<Option<f64>>,
    displacement: Vec<Option<f64>>,
}

/// The Dirichlet parts resolved on `mesh`, in order: the fixed dofs, their velocities and
/// held displacements.
fn dirichlet_dofs<const D: usize, const C: usize>(
    mesh: &SimplexMesh<D>,
    dirichlet: &[Dirichlet<D, C>],
) -> Result<Held> {
    let n = C * mesh.num_vertices();
    let mut fixed = vec![false; n];
    let mut velocity: Vec<Option<f64>> = vec![None; n];
    let mut displacement: Vec<Option<f64>> = vec![None; n];
    for d in dirichlet {
        let name = d.part.name();
        if d.components.is_empty() || d.components.iter().any(|&c| c >= C) {
            return Err(invalid(
                "dirichlet",
                format!(
                    "part `{name}`: components {:?} must be in 0..{C}",
                    d.components
                ),
            ));
        }
        if d.velocity.iter().any(|c| !c.is_finite()) {
            return Err(invalid(
                "dirichlet",
                format!("part `{name}`: velocity {:?} must be finite", d.velocity),
            ));
        }
        let part = d.part.resolve(mesh)?;
        for &p in part.nodes() {
            let held = match &d.displacement {
                Some(u) => {
                    let x = &mesh.vertices()[p];
                    let u = u(x);
                    if u.iter().any(|c| !c.is_finite()) {
                        return Err(invalid(
                            "dirichlet",
                            format!(
                                "part `{name}`: the displacement {u:?} m at {x:?} m must be \
                                 finite"
                            ),
                        ));
                    }
                    Some(u)
                }
                None => None,
            };
            for &c in &d.components {
                if let Some(u) = held {
                    let i = C * p + c;
                    match displacement[i] {
                        Some(old) if old != u[c] => {
                            return Err(invalid(
                                "dirichlet",
                                format!(
                                    "node {p} component {c}: part `{name}` holds it at {} m, \
                                     an earlier part at {old} m",
                                    u[c]
                                ),
                            ))
                        }
                        _ => displacement[i] = Some(u[c]),
                    }
                }
                let i = C * p + c;
                let w = d.velocity[c];
                match velocity[i] {
                    Some(old) if old != w => {
                        return Err(invalid(
                            "dirichlet",
                            format!(
                                "node {p} component {c}: part `{name}` prescribes {w} m/s, \
                                 an earlier part {old} m/s"
                            ),
                        ))
                    }
                    _ => velocity[i] = Some(w),
                }
                fixed[i] = true;
            }
        }
    }
    Ok(Held {
        fixed,
        velocity,
        displacement,
    })
}

/// At every frame node of a boundary fault (Γ_F named `name`): bilateral contact fixes the
/// normal component in the frame, or a fully clamped node gets its velocity (or held
/// displacement, the same way) in the frame (`Q_pᵀ w`).
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `dirichlet` for a
/// node with only some Cartesian components fixed.
fn in_frames<const C: usize>(
    frames: &NodalFrames<C>,
    name: &str,
    fixed: &mut [bool],
    [velocity, displacement]: [&mut [Option<f64>]; 2],
) -> Result<()> {
    for (&p, q) in frames.nodes.iter().zip(&frames.rotations) {
        let dofs = C * p..C * p + C;
        match fixed[dofs.clone()].iter().filter(|&&f| f).count() {
            // Bilateral contact: the normal component in the frame.
            0 => fixed[C * p + normal_component(C)] = true,
            // A Dirichlet node on the slanted fault: its prescribed velocity in the frame.
            k if k == C => {
                rotate(q, p, velocity);
                if dofs.clone().any(|i| displacement[i].is_some()) {
                    rotate(q, p, displacement);
                }
            }
            _ => {
                return Err(invalid(
                    "dirichlet",
                    format!(
                        "node {p} is on the slanted frictional boundary `{name}` (it has a \
                         nodal frame) and a Dirichlet part fixes only some of its \
                         Cartesian components; fix all of them or none"
                    ),
                ))
            }
        }
    }
    Ok(())
}

/// Node `p`'s block of `values` (Cartesian, `None` read as 0) in its frame `q`: `Q_pᵀ w`.
fn rotate<const C: usize>(q: &[[f64; C]; C], p: usize, values: &mut [Option<f64>]) {
    let w: [f64; C] = std::array::from_fn(|c| values[C * p + c].unwrap_or(0.0));
    for c in 0..C {
        let wc: f64 = (0..C).map(|r| q[r][c] * w[r]).sum();
        values[C * p + c] = Some(wc);
    }
}

impl<const D: usize, const C: usize> Constraints<D, C> {
    /// The held displacements of the model's unknown `s·u` (`s` the slip factor) on every
    /// dof (0 where none is given), or `None` if none is given anywhere (every fixed dof
    /// at 0, as before held displacements existed).
    pub fn held_displacement(&self, s: f64) -> Option<Vec<f64>> {
        self.displacement.iter().any(Option::is_some).then(|| {
            self.displacement
                .iter()
                .map(|u| u.map_or(0.0, |u| s * u))
                .collect()
        })
    }

    /// The prescribed velocities `v_i(t) = s w_i g(t)` of the model's unknown `s·u` (`s`
    /// the slip factor): the dofs with a non-zero velocity factor, in increasing order.
    pub fn dirichlet_velocity(&self, s: f64, history: TimeFunction) -> DirichletVelocity {
        let (dofs, factors): (Vec<usize>, Vec<f64>) = self
            .velocity
            .iter()
            .enumerate()
            .filter_map(|(i, w)| w.filter(|w| *w != 0.0).map(|w| (i, s * w)))
            .unzip();
        DirichletVelocity {
            dofs,
            factors,
            history,
        }
    }
}
