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
    let (nodes_along, weights_along): (Vec<usize>, Vec<f64>) = match fault {
        // The pairs' minus nodes in order along the fault (a tip does not slip).
        Some(SharedFault { fault, prescribed }) => {
            let mut weight_of = vec![f64::NAN; mesh.num_vertices()];
            for (&p, &w) in gamma_f.nodes().iter().zip(&weights) {
                weight_of[p] = w;
            }
            fault
                .pairs()
                .iter()
                .zip(prescribed)
                .filter(|(_, &given)| !given)
                .map(|(&(mi, _), _)| (mi, weight_of[mi]))
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
    FrictionalBoundary::new(&nodes_along, &weights_along)?.with_slip_factor(s)
}
