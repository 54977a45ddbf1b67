//! Load vectors (body force, boundary traction) and lumped boundary weights, any `D`.

use crate::element::simplex_quadrature;
use crate::mesh::SimplexMesh;
use crate::part::BoundaryPart;
use crate::{Error, Result};

/// The point with barycentric coordinates `l` (first `n` used) in the simplex `x`.
#[inline]
fn point<const D: usize>(x: &[[f64; D]], l: &[f64; 4]) -> [f64; D] {
    let mut p = [0.0; D];
    for r in 0..D {
        let mut s = l[0] * x[0][r];
        for a in 1..x.len() {
            s += l[a] * x[a][r];
        }
        p[r] = s;
    }
    p
}

/// Adds `scale · l_a · v` to the node-major entries of the simplex `nodes` (the point
/// load of one quadrature point).
///
/// # Errors
/// [`Error::NonFiniteValue`] (naming `what`) if `v` is not finite.
#[inline]
fn scatter<const C: usize>(
    out: &mut [f64],
    nodes: &[usize],
    scale: f64,
    l: &[f64; 4],
    v: [f64; C],
    what: &'static str,
) -> Result<()> {
    if v.iter().any(|c| !c.is_finite()) {
        return Err(Error::NonFiniteValue(what));
    }
    for (a, &p) in nodes.iter().enumerate() {
        for r in 0..C {
            out[C * p + r] += scale * l[a] * v[r];
        }
    }
    Ok(())
}

/// Body-force load `F_i = ∫ f·φ_i dx` for a force density `f(x)` (N/m³; N/m² per unit
/// thickness in 2D; gravity is `[0, −ρ g]` in 2D), node-major, length
/// `D · num_vertices`. Integrated with the degree-5 rules
/// ([`crate::element::triangle_quadrature`], [`crate::element::tetrahedron_quadrature`]).
///
/// # Errors
/// [`Error::NonFiniteValue`] if `f` returns a non-finite value.
pub fn body_force_load<const D: usize>(
    mesh: &SimplexMesh<D>,
    f: impl Fn(&[f64; D]) -> [f64; D],
) -> Result<Vec<f64>> {
    body_force_load_components::<D, D>(mesh, f)
}

/// [`body_force_load`] for a field of `C` components per vertex (`C = 1`: a scalar field,
/// e.g. the antiplane body force density in N/m³); node-major, length `C · num_vertices`.
///
/// # Errors
/// [`Error::NonFiniteValue`] if `f` returns a non-finite value.
pub fn body_force_load_components<const D: usize, const C: usize>(
    mesh: &SimplexMesh<D>,
    f: impl Fn(&[f64; D]) -> [f64; C],
) -> Result<Vec<f64>> {
    let mut out = vec![0.0; C * mesh.num_vertices()];
    let q = simplex_quadrature(D);
    for c in 0..mesh.num_cells() {
        let x = mesh.cell_coords(c);
        let measure = mesh.cell_measure(c);
        let cell = mesh.cell(c);
        for (l, w) in &q {
            let fv = f(&point(&x[..D + 1], l));
            scatter(&mut out, cell, w * measure, l, fv, "body force")?;
        }
    }
    Ok(out)
}

/// Neumann load `F_i = ∫_Γ g·φ_i ds` for a traction `g(x)` (Pa; N/m per unit thickness in
/// 2D) on a boundary part (a [`BoundaryPart`] or a [`crate::BoundarySegment`]); node-major,
/// length `D · num_vertices`. Degree-5 rules on the facets.
///
/// # Errors
/// [`Error::NonFiniteValue`] if `g` returns a non-finite value;
/// [`Error::DimensionMismatch`] if the part was built on another mesh.
pub fn traction_load<const D: usize, P: AsRef<BoundaryPart<D>> + ?Sized>(
    mesh: &SimplexMesh<D>,
    part: &P,
    g: impl Fn(&[f64; D]) -> [f64; D],
) -> Result<Vec<f64>> {
    traction_load_components::<D, D, P>(mesh, part, g)
}

/// [`traction_load`] for a field of `C` components per vertex (`C = 1`: a scalar field,
/// e.g. the antiplane shear traction in Pa); node-major, length `C · num_vertices`.
///
/// # Errors
/// As [`traction_load`].
pub fn traction_load_components<const D: usize, const C: usize, P>(
    mesh: &SimplexMesh<D>,
    part: &P,
    g: impl Fn(&[f64; D]) -> [f64; C],
) -> Result<Vec<f64>>
where
    P: AsRef<BoundaryPart<D>> + ?Sized,
{
    let part = part.as_ref();
    part.check_mesh(mesh)?;
    let mut out = vec![0.0; C * mesh.num_vertices()];
    let q = simplex_quadrature(D - 1);
    let v = mesh.vertices();
    for &f in part.facets() {
        let e = mesh.boundary_facet(f);
        let mut x = [[0.0; D]; 3];
        for (k, &p) in e.iter().enumerate() {
            x[k] = v[p];
        }
        let measure = mesh.boundary_facet_measure(f);
        for (l, w) in &q {
            let gv = g(&point(&x[..D], l));
            scatter(&mut out, e, w * measure, l, gv, "traction")?;
        }
    }
    Ok(out)
}

/// Lumped boundary weights `w_p = ∫_Γ λ_p ds` (m in 2D, m² in 3D) per node of a boundary
/// part, in the order of its nodes ([`BoundaryPart::weights`]; docs/math.md §3:
/// Φ_h = Σ_p w_p ϕ(|v_p|, α_p)). They sum to the part's measure.
///
/// # Panics
/// If the part was built on another mesh (use [`BoundaryPart::weights`] for an error).
pub fn lumped_weights<const D: usize, P: AsRef<BoundaryPart<D>> + ?Sized>(
    mesh: &SimplexMesh<D>,
    part: &P,
) -> Vec<f64> {
    part.as_ref()
        .weights(mesh)
        .expect("the boundary part belongs to this mesh")
}
