//! Stage 9: Γ_F in the order of the fault indices, with the lumped weights of its nodes —
//! the faults inside the body's free slip nodes in order along each (fault after fault),
//! then a boundary fault's nodes sorted by their coordinates (lexicographically); each
//! node with its fault's name.

use rsf_fem::{BoundaryPart, SimplexMesh};

use super::pairs::SharedFault;
use crate::error::Result;
use crate::model::fault::FrictionalBoundary;

/// The frictional boundary of Γ_F `gamma_f` (every frictional facet) on `mesh` with slip
/// factor `s` (weights `w/s`): for faults inside the body `fault`, the slip nodes whose slip
/// is not prescribed in order along each fault, with the minus faces' weights (a junction's
/// jump with its fault's own two edges', half each); for a frictional boundary `boundary`
/// (alone, or beside faults inside the body), its nodes by their coordinates. Each node
/// carries its fault: the faults inside the body by name, then the boundary by its part's.
///
/// Faults inside the body whose every slip node is prescribed (a kinematic source), with
/// no frictional boundary, have no frictional node: [`FrictionalBoundary::empty`].
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
/// `frictional_boundary` for no node on a boundary fault; the weights' errors.
pub(crate) fn frictional_boundary<const D: usize>(
    mesh: &SimplexMesh<D>,
    gamma_f: &BoundaryPart<D>,
    s: f64,
    fault: Option<&SharedFault<D>>,
    boundary: Option<&BoundaryPart<D>>,
) -> Result<FrictionalBoundary> {
    let mut weights = gamma_f.weights(mesh)?;
    if s != 1.0 {
        for w in &mut weights {
            *w /= s;
        }
    }
    let mut weight_of = vec![f64::NAN; mesh.num_vertices()];
    for (&p, &w) in gamma_f.nodes().iter().zip(&weights) {
        weight_of[p] = w;
    }
    let mut names = Vec::new();
    let (mut nodes_along, mut weights_along, mut faults_along) = (vec![], vec![], vec![]);
    // The slip nodes in order along each fault (a tip does not slip).
    if let Some(SharedFault { fault, prescribed }) = fault {
        names.extend(fault.faults().iter().map(|f| f.name().to_owned()));
        for (k, i) in fault.slip_nodes_along() {
            if prescribed[k] {
                continue;
            }
            let node = fault.slip_nodes()[k];
            let w = match node.pair {
                Some(_) => weight_of[node.vertex],
                None => {
                    let facets = fault.faults()[node.fault].minus_facets();
                    [i.wrapping_sub(1), i]
                        .into_iter()
                        .filter(|&e| e < facets.len())
                        .map(|e| 0.5 * mesh.boundary_facet_measure(facets[e]) / s)
                        .sum()
                }
            };
            nodes_along.push(node.vertex);
            weights_along.push(w);
            faults_along.push(node.fault);
        }
    }
    if let Some(part) = boundary {
        let f = names.len();
        names.push(part.name().to_owned());
        let vertices = mesh.vertices();
        let mut order: Vec<usize> = part.nodes().to_vec();
        order.sort_by(|&a, &b| {
            vertices[a]
                .iter()
                .zip(&vertices[b])
                .map(|(u, v)| u.total_cmp(v))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        for p in order {
            nodes_along.push(p);
            weights_along.push(weight_of[p]);
            faults_along.push(f);
        }
    }
    if nodes_along.is_empty() && fault.is_some() && boundary.is_none() {
        return Ok(FrictionalBoundary::empty());
    }
    FrictionalBoundary::new(&nodes_along, &weights_along)?
        .with_slip_factor(s)?
        .with_faults(names, &faults_along)
}
