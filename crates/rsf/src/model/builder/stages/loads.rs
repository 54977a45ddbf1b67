//! Stage 5: the load `F` — gravity `ρ g` (a vector field), a body force, the Neumann parts'
//! tractions — Cartesian, in the unknown `u`.

use rsf_fem::{body_force_load_components, traction_load_components, SimplexMesh};

use super::super::settings::{Body, Boundary};
use crate::error::Result;
use crate::model::medium::Medium;

/// `F` on `mesh` (`C` entries per vertex, N; N/m per unit thickness in 2-D): the body
/// forces of `body` (gravity with the density of `material` at each point, plus the body
/// force density) and the tractions of the Neumann parts of `boundary`, in that order.
///
/// # Errors
/// The parts' resolution errors; a non-finite force or traction ([`crate::Error::Fem`]).
pub(crate) fn load<const D: usize, const C: usize>(
    mesh: &SimplexMesh<D>,
    material: &dyn Medium<D, C>,
    body: &Body<D, C>,
    boundary: &Boundary<D, C>,
) -> Result<Vec<f64>> {
    let n = C * mesh.num_vertices();
    // Gravity only for vector fields: its setter needs C = D.
    let gravity = |g: [f64; D], x: &[f64; D]| -> [f64; C] {
        let rho = material.density_at(x);
        std::array::from_fn(|c| rho * g[c])
    };
    let mut load = match (body.gravity, &body.body_force) {
        (None, None) => vec![0.0; n],
        (Some(g), None) => body_force_load_components(mesh, |x| gravity(g, x))?,
        (None, Some(f)) => body_force_load_components(mesh, f)?,
        (Some(g), Some(f)) => body_force_load_components(mesh, |x| {
            let mut v = f(x);
            for (vc, gc) in v.iter_mut().zip(gravity(g, x)) {
                *vc += gc;
            }
            v
        })?,
    };
    for (part, traction) in &boundary.neumann {
        let t = traction_load_components(mesh, &part.resolve(mesh)?, traction)?;
        for (l, ti) in load.iter_mut().zip(t) {
            *l += ti;
        }
    }
    Ok(load)
}
