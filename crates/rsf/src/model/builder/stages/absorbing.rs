//! The absorbing parts (part of stage 4): their checks before assembly (inertia, the far
//! field, the medium's impedances) and their Lysmer–Kuhlemeyer dashpots after it.

use rsf_fem::{SimplexMesh, SparseMatrix};

use super::super::part::part_error;
use super::super::settings::Absorbing;
use super::constraints::Constraints;
use crate::error::Result;
use crate::model::absorbing::{assemble as assemble_dashpots, AbsorbingBoundary, ResolvedPart};
use crate::model::medium::Medium;

/// The checks of the absorbing parts that need no assembly (before it, so that a
/// medium the mass matrix would refuse, e.g. of zero density, is named here): inertia,
/// a finite far-field velocity, the medium's impedances finite and positive.
pub(crate) fn check<const D: usize, const C: usize>(
    absorbing: &[Absorbing<D, C>],
    material: &dyn Medium<D, C>,
    with_mass: bool,
) -> Result<()> {
    for a in absorbing {
        let name = a.part.name();
        if !with_mass {
            return Err(part_error(
                name,
                "absorbing parts need inertia (the model is built without_mass)",
            ));
        }
        if a.velocity.iter().any(|w| !w.is_finite()) {
            return Err(part_error(
                name,
                format!("far-field velocity {:?} must be finite", a.velocity),
            ));
        }
        // A medium with one impedance for the whole body is checked here; one that
        // varies (material regions) facet by facet at assembly.
        if material.impedances().is_some() {
            absorbing_impedances(material, name, None)?;
        }
    }
    Ok(())
}

/// The dashpots of the absorbing parts (Cartesian, unscaled), if any: each part
/// resolved, checked (inertia, the medium's impedances, no facet of Γ_F, a free dof under
/// `constraints`)
/// and lumped on the pattern of `stiffness` (its columns of the nodes `columns` only, if
/// given: a matrix of some columns).
pub(crate) fn dashpots<const D: usize, const C: usize>(
    absorbing: &[Absorbing<D, C>],
    mesh: &SimplexMesh<D>,
    material: &dyn Medium<D, C>,
    constraints: &Constraints<D, C>,
    stiffness: &SparseMatrix,
    columns: Option<&[bool]>,
) -> Result<Option<AbsorbingBoundary>> {
    let (gamma_f, fixed) = (&constraints.gamma_f, &constraints.fixed);
    if absorbing.is_empty() {
        return Ok(None);
    }
    let mut resolved = Vec::with_capacity(absorbing.len());
    for a in absorbing {
        let name = a.part.name();
        let part = a.part.resolve(mesh)?;
        let impedances = part
            .facets()
            .iter()
            .map(|&f| {
                let cell = mesh.cell(mesh.boundary_facet_cell(f));
                let centroid: [f64; D] = std::array::from_fn(|k| {
                    cell.iter().map(|&p| mesh.vertices()[p][k]).sum::<f64>() / (D + 1) as f64
                });
                absorbing_impedances(material, name, Some(&centroid))
            })
            .collect::<Result<Vec<[f64; 2]>>>()?;
        if let Some(f) = part
            .facets()
            .iter()
            .find(|f| gamma_f.facets().binary_search(f).is_ok())
        {
            return Err(part_error(
                name,
                format!(
                    "boundary facet {f} is also on the frictional boundary `{}`",
                    gamma_f.name()
                ),
            ));
        }
        if part
            .nodes()
            .iter()
            .all(|&p| (0..C).all(|c| fixed[C * p + c]))
        {
            return Err(part_error(
                name,
                "every dof of its nodes is fixed (Dirichlet): the dashpots would do nothing",
            ));
        }
        resolved.push((part, impedances, a.velocity));
    }
    let parts: Vec<ResolvedPart<'_, D, C>> = resolved
        .iter()
        .map(|(part, impedances, velocity)| ResolvedPart {
            part,
            impedances,
            velocity: *velocity,
        })
        .collect();
    let (damping, far_field_force) = assemble_dashpots(mesh, &parts, stiffness, columns)?;
    Ok(Some(AbsorbingBoundary {
        parts: absorbing.iter().map(|a| a.part.name().to_owned()).collect(),
        damping,
        far_field_force,
    }))
}

/// The medium's impedances `(ρc_p, ρc_s)` for absorbing part `name`, at `x` (m) inside the
/// body or its single ones, finite and positive.
fn absorbing_impedances<const D: usize, const C: usize>(
    material: &dyn Medium<D, C>,
    name: &str,
    x: Option<&[f64; D]>,
) -> Result<[f64; 2]> {
    let at = x.map_or(String::new(), |x| format!(" at {x:?} m"));
    let impedances = match x {
        Some(x) => material.impedances_at(x),
        None => material.impedances(),
    }
    .ok_or_else(|| {
        part_error(
            name,
            format!("the medium gives no impedances{at} (Medium::impedances_at) for its dashpots"),
        )
    })?;
    if impedances.iter().any(|z| !(z.is_finite() && *z > 0.0)) {
        let density = x.map_or(material.density(), |x| material.density_at(x));
        return Err(part_error(
            name,
            format!(
                "the medium's impedances (ρc_p, ρc_s) = {impedances:?} Pa·s/m{at} must be \
                 finite and positive (density ρ = {density} kg/m³)"
            ),
        ));
    }
    Ok(impedances)
}
