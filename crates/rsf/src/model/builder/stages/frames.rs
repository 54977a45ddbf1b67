//! The frames of Γ_F's nodes (part of stage 3): nodal frames `Q_p` at the slanted nodes of
//! a fault on the boundary, after checking its geometry (corners, folds, degenerate facets),
//! or the pair frames of a fault inside the body (for outputs).

use rsf_fem::{BoundaryPart, NodalFrames, SimplexMesh};

use super::domain::checked_tangent;
use crate::error::{invalid, Error, Result};
use crate::model::internal::InternalFault;

/// Tolerance on `|n_c| = 1` for a frictional normal along a coordinate axis.
const AXIS_TOLERANCE: f64 = 1e-9;

/// A facet of Γ_F shorter (smaller) than this fraction of the mean facet measure counts as
/// degenerate ([`Error::DegenerateFaultFacet`]).
const DEGENERATE_FACET: f64 = 1e-12;

/// At a node of Γ_F whose facets' area-weighted normal sum is shorter than this fraction of
/// their total measure the boundary folds back ([`Error::FaultFoldsBack`]).
const FOLD: f64 = 1e-6;

/// The nodal frames of the slanted nodes of Γ_F `gamma_f` (part `name`; normal not along a
/// coordinate axis), in increasing node order, the first tangent of 3-D frames the
/// projection of `tangent` (default: the axis with the smallest `|n_k|`); checks corners
/// (facet normals at a node further apart than `max_kink_degrees`), folds and degenerate
/// facets at every node.
///
/// # Errors
/// [`Error::InvalidParameter`] named `max_fault_kink` or `fault_tangent`;
/// [`Error::DegenerateFaultFacet`], [`Error::FaultCorner`], [`Error::FaultFoldsBack`]
/// naming the node; [`rsf_fem::Error::TangentAlongNormal`].
pub(crate) fn fault_frames<const D: usize>(
    mesh: &SimplexMesh<D>,
    gamma_f: &BoundaryPart<D>,
    name: &str,
    max_kink_degrees: f64,
    tangent: Option<[f64; D]>,
) -> Result<NodalFrames<D>> {
    let limit = max_kink_degrees;
    if !(0.0..=180.0).contains(&limit) {
        return Err(invalid(
            "max_fault_kink",
            format!("{limit} must be in [0, 180] degrees"),
        ));
    }
    checked_tangent(tangent)?;
    let facets = gamma_f.facets();
    let mean = facets
        .iter()
        .map(|&f| mesh.boundary_facet_measure(f))
        .sum::<f64>()
        / facets.len() as f64;
    // Per node: the unit normals of its facets, and their area-weighted sum with the
    // total area (a fold: the sum cancels).
    let mut at_node: Vec<Vec<[f64; D]>> = vec![Vec::new(); mesh.num_vertices()];
    let mut resultant = vec![([0.0; D], 0.0); mesh.num_vertices()];
    for &f in facets {
        let a = mesh.boundary_facet_measure(f);
        let vs = mesh.boundary_facet(f);
        if !(a.is_finite() && a > DEGENERATE_FACET * mean) {
            return Err(Error::DegenerateFaultFacet {
                part: name.to_owned(),
                node: vs[0],
                facet: f,
                measure: a,
            });
        }
        let nf = mesh.boundary_facet_normal(f);
        for &v in vs {
            at_node[v].push(nf);
            let (sum, total) = &mut resultant[v];
            sum.iter_mut().zip(&nf).for_each(|(s, n)| *s += a * n);
            *total += a;
        }
    }
    for &p in gamma_f.nodes() {
        let ns = &at_node[p];
        let mut worst = 0.0f64;
        for (i, a) in ns.iter().enumerate() {
            for b in &ns[i + 1..] {
                let dot: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
                worst = worst.max(dot.clamp(-1.0, 1.0).acos().to_degrees());
            }
        }
        if worst > limit {
            return Err(Error::FaultCorner {
                part: name.to_owned(),
                node: p,
                position: mesh.vertices()[p].to_vec(),
                angle_degrees: worst,
                limit_degrees: limit,
            });
        }
        let (sum, total) = &resultant[p];
        if sum.iter().map(|s| s * s).sum::<f64>().sqrt() <= FOLD * total {
            return Err(Error::FaultFoldsBack {
                part: name.to_owned(),
                node: p,
                position: mesh.vertices()[p].to_vec(),
            });
        }
    }
    // Frames at the slanted nodes only (an axis-aligned node keeps the Cartesian basis,
    // whatever the tangent there): a fault tangent (nearly) normal at one of them is
    // an error naming it (rsf_fem::Error::TangentAlongNormal), not another tangent.
    let normals = gamma_f.normals(mesh)?;
    let mut slanted: Vec<(usize, [[f64; D]; D])> = gamma_f
        .nodes()
        .iter()
        .zip(&normals)
        .filter(|(_, n)| normal_axis(n).is_none())
        .map(|(&p, n)| {
            let q = rsf_fem::frame_from_normal(n, tangent.as_ref());
            q.map(|q| (p, q))
                .ok_or_else(|| rsf_fem::Error::TangentAlongNormal {
                    vertex: p,
                    position: mesh.vertices()[p].to_vec(),
                    normal: n.to_vec(),
                    direction: tangent.map_or_else(Vec::new, |t| t.to_vec()),
                })
        })
        .collect::<std::result::Result<_, _>>()?;
    slanted.sort_by_key(|&(p, _)| p);
    Ok(NodalFrames {
        nodes: slanted.iter().map(|&(p, _)| p).collect(),
        rotations: slanted.into_iter().map(|(_, q)| q).collect(),
    })
}

/// The pair frames of an internal fault on its minus nodes, in increasing node order (for
/// outputs: the jump block rotated back is the Cartesian jump); none for a scalar field.
/// A Dirichlet constraint on a split node is refused: its Cartesian data would mix the
/// mean and the jump.
pub(crate) fn internal_fault_frames<const D: usize, const C: usize>(
    fault: &InternalFault<D>,
    fixed: &[bool],
) -> Result<NodalFrames<C>> {
    for (k, &(mi, pl)) in fault.pairs().iter().enumerate() {
        let count = [mi, pl]
            .iter()
            .map(|&p| (0..C).filter(|&c| fixed[C * p + c]).count())
            .sum::<usize>();
        if count != 0 && count != 2 * C {
            let p = if (0..C).any(|c| fixed[C * mi + c]) {
                mi
            } else {
                pl
            };
            return Err(invalid(
                "dirichlet",
                format!(
                    "node {p} is a split node of the internal fault `{}` and Dirichlet parts \
                     fix only some components of its two sides; fix every component of both \
                     sides (e.g. each side's far-field motion) or none",
                    fault.fault_name(fault.pair_fault(k))
                ),
            ));
        }
    }
    for (j, blocks) in fault.transform.junctions.iter().enumerate() {
        if let Some(s) = blocks
            .sectors
            .iter()
            .find(|s| (0..C).any(|c| fixed[C * s.copy + c]))
        {
            let [a, b] = fault.network.junctions()[j].kind().faults();
            return Err(invalid(
                "dirichlet",
                format!(
                    "node {} is a copy of the junction of the internal faults `{}` and `{}`, \
                     which Dirichlet parts may not fix (keep junctions inside the body)",
                    s.copy,
                    fault.fault_name(a),
                    fault.fault_name(b)
                ),
            ));
        }
    }
    if C != D || C == 1 {
        return Ok(NodalFrames::default());
    }
    let mut frames: Vec<(usize, [[f64; C]; C])> = fault
        .slip_nodes()
        .iter()
        .map(|node| {
            let r = &fault.transform.frames[node.frame];
            (
                node.vertex,
                std::array::from_fn(|a| std::array::from_fn(|b| r[a][b])),
            )
        })
        .collect();
    frames.sort_by_key(|f| f.0);
    Ok(NodalFrames {
        nodes: frames.iter().map(|f| f.0).collect(),
        rotations: frames.into_iter().map(|f| f.1).collect(),
    })
}

/// `frames` as frames of `C`-component blocks, for `C = D` (where they are the same type).
///
/// # Panics
/// If `C ≠ D` and there are frames (internal invariant: only vector fields have frames).
pub(crate) fn same_block_size<const D: usize, const C: usize>(
    frames: NodalFrames<D>,
) -> NodalFrames<C> {
    assert!(C == D || frames.nodes.is_empty(), "frames need C = D");
    NodalFrames {
        nodes: frames.nodes,
        rotations: frames
            .rotations
            .into_iter()
            .map(|q| std::array::from_fn(|r| std::array::from_fn(|c| q[r][c])))
            .collect(),
    }
}

/// The coordinate axis `c` with `|n_c| = 1` (within [`AXIS_TOLERANCE`]), if any.
pub(crate) fn normal_axis<const D: usize>(n: &[f64; D]) -> Option<usize> {
    (0..D).find(|&c| (n[c].abs() - 1.0).abs() <= AXIS_TOLERANCE)
}
