//! Stage 9: Γ_F in the order of the fault indices, with the lumped weights of its nodes —
//! a boundary fault's nodes sorted by their coordinates (lexicographically), a fault
//! inside the body's free pairs' minus vertices in order along it.

use rsf_fem::{BoundaryPart, SimplexMesh};

use super::pairs::SharedFault;
use crate::error::Result;
use crate::model::fault::FrictionalBoundary;

/// The frictional boundary of Γ_F `gamma_f` on `mesh` with slip factor `s` (weights `w/s`):
/// every node of `gamma_f` by its coordinates, or, for a fault inside the body, the minus
/// vertices of the pairs whose slip is not prescribed, in the fault's order, with the
/// minus face's weights.
///
/// A fault inside the body whose every pair is prescribed (a kinematic source) has no
/// frictional node: [`FrictionalBoundary::empty`].
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
/// `frictional_boundary` for no node on a boundary fault; the weights' errors.
pub(crate) fn frictional_boundary<const D: usize>(
    mesh: &SimplexMesh<D>,
    gamma_f: &BoundaryPart<D>,
    s: f64,
    fault: Option<&SharedFault<D>>,
) -> Result<FrictionalBoundary> {
    let mut weights = gamma_f.weights(mesh)?;
    if s != 1.0 {
        for w in &mut weights {
            *w /= s;
        }
    }
    let (names, faults_along): (Vec<String>, Vec<usize>) = match fault {
        Some(SharedFault { fault, prescribed }) => (
            fault.faults().iter().map(|f| f.name().to_owned()).collect(),
            fault
                .slip_nodes_along()
                .into_iter()
                .filter(|&(k, _)| !prescribed[k])
                .map(|(k, _)| fault.slip_nodes()[k].fault)
                .collect(),
        ),
        None => (
            vec![gamma_f.name().to_owned()],
            vec![0; gamma_f.num_nodes()],
        ),
    };
    let (nodes_along, weights_along): (Vec<usize>, Vec<f64>) = match fault {
        // The slip nodes in order along each fault (a tip does not slip), with the minus
        // face's weights; a junction's jump with its fault's own edges' (half each).
        Some(SharedFault { fault, prescribed }) => {
            let mut weight_of = vec![f64::NAN; mesh.num_vertices()];
            for (&p, &w) in gamma_f.nodes().iter().zip(&weights) {
                weight_of[p] = w;
            }
            fault
                .slip_nodes_along()
                .into_iter()
                .filter(|&(k, _)| !prescribed[k])
                .map(|(k, i)| {
                    let node = fault.slip_nodes()[k];
                    let w = match node.pair {
                        Some(_) => weight_of[node.vertex],
                        None => {
                            let sides = &fault.faults()[node.fault];
                            let facets = sides.minus_facets();
                            [i.wrapping_sub(1), i]
                                .into_iter()
                                .filter(|&e| e < facets.len())
                                .map(|e| 0.5 * mesh.boundary_facet_measure(facets[e]) / s)
                                .sum()
                        }
                    };
                    (node.vertex, w)
                })
                .unzip()
        }
        None => {
            let vertices = mesh.vertices();
            let mut order: Vec<usize> = (0..gamma_f.num_nodes()).collect();
            order.sort_by(|&a, &b| {
                let (xa, xb) = (&vertices[gamma_f.nodes()[a]], &vertices[gamma_f.nodes()[b]]);
                xa.iter()
                    .zip(xb)
                    .map(|(u, v)| u.total_cmp(v))
                    .find(|o| o.is_ne())
                    .unwrap_or(std::cmp::Ordering::Equal)
            });
            order
                .iter()
                .map(|&k| (gamma_f.nodes()[k], weights[k]))
                .unzip()
        }
    };
    if nodes_along.is_empty() && fault.is_some() {
        return Ok(FrictionalBoundary::empty());
    }
    FrictionalBoundary::new(&nodes_along, &weights_along)?
        .with_slip_factor(s)?
        .with_faults(names, &faults_along)
}
