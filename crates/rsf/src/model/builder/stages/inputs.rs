//! Stage 2: the settings that need no mesh data, checked — the medium, the slip factor,
//! which part is Γ_F, the loading history, gravity.

use rsf_fem::{BoundaryPart, FaultSides, SimplexMesh};

use super::super::part::Part;
use super::super::settings::{Body, Boundary, Faults};
use crate::error::{invalid, Result};
use crate::model::internal::InternalFault;
use crate::model::medium::Medium;

/// The parts that are Γ_F: the caller's frictional boundary, the minus faces of the faults
/// inside the body, or both.
pub(crate) struct FaultPart<'b, const D: usize> {
    /// [`ModelBuilder::frictional_boundary`](crate::ModelBuilder::frictional_boundary).
    pub given: Option<&'b Part<D>>,
    /// The faces tagged `{name}_minus` of the split mesh, one tag per fault inside the body.
    pub minus_faces: Vec<String>,
}

impl<const D: usize> FaultPart<'_, D> {
    /// The parts' names (for messages): the given part's and the faults' minus tags.
    pub fn name(&self) -> String {
        let mut names: Vec<&str> = self.given.iter().map(|p| p.name()).collect();
        names.extend(self.minus_faces.iter().map(String::as_str));
        names.join(", ")
    }

    /// Γ_F on `mesh` (the model's split mesh): the given part and every fault's minus faces
    /// (the given part alone: resolved as it is; one fault alone: [`BoundaryPart::from_tag`]
    /// of its tag).
    ///
    /// # Errors
    /// As [`Part::resolve`](super::super::part::Part).
    pub fn resolve(&self, mesh: &SimplexMesh<D>) -> Result<BoundaryPart<D>> {
        match (self.given, &self.minus_faces[..]) {
            (Some(p), []) => p.resolve(mesh),
            (None, [one]) => Part::from(one.as_str()).resolve(mesh),
            _ => {
                let mut facets: Vec<usize> = match self.given {
                    Some(p) => p.resolve(mesh)?.facets().to_vec(),
                    None => Vec::new(),
                };
                facets.extend(
                    self.minus_faces
                        .iter()
                        .flat_map(|t| mesh.facets_with_tag(t)),
                );
                Ok(BoundaryPart::from_facets(mesh, &self.name(), facets)?)
            }
        }
    }

    /// The given frictional boundary on `mesh`, if there is one.
    ///
    /// # Errors
    /// As [`Part::resolve`](super::super::part::Part).
    pub fn boundary(&self, mesh: &SimplexMesh<D>) -> Result<Option<BoundaryPart<D>>> {
        self.given.map(|p| p.resolve(mesh)).transpose()
    }
}

/// The checked settings the later stages take.
pub(crate) struct Inputs<'b, const D: usize, const C: usize> {
    /// The medium.
    pub material: &'b dyn Medium<D, C>,
    /// The antisymmetry factor `s` (finite, positive; 1 with a fault inside the body).
    pub slip_factor: f64,
    /// Γ_F.
    pub fault_part: FaultPart<'b, D>,
}

/// Checks the settings in the order of their errors: a creeping section or a prescribed
/// slip without a fault inside the body, the medium, the slip factor, Γ_F (one of a frictional boundary and a
/// fault inside the body), the slip factor against a fault inside the body, the loading
/// history, gravity.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `internal_creep`,
/// `internal_slip`, `material`, `slip_factor`, `frictional_boundary`, `gravity`; the loading history's.
pub(crate) fn check<'b, const D: usize, const C: usize>(
    body: &'b Body<D, C>,
    boundary: &Boundary<D, C>,
    faults: &'b Faults<D>,
    fault: Option<&InternalFault<D>>,
) -> Result<Inputs<'b, D, C>> {
    if faults.creep.is_some() && fault.is_none() {
        return Err(invalid(
            "internal_creep",
            "a creeping section needs an internal fault (ModelBuilder::internal_fault)",
        ));
    }
    if faults.slip.is_some() && fault.is_none() {
        return Err(invalid(
            "internal_slip",
            "a prescribed slip needs an internal fault (ModelBuilder::internal_fault)",
        ));
    }
    let material = body
        .material
        .as_deref()
        .ok_or_else(|| invalid("material", "not set"))?;
    let s = faults.slip_factor;
    if !(s.is_finite() && s > 0.0) {
        return Err(invalid(
            "slip_factor",
            format!("{s} must be finite and positive"),
        ));
    }
    let fault_part = FaultPart {
        given: faults.frictional_boundary.as_ref(),
        minus_faces: fault.map_or_else(Vec::new, |f| {
            f.faults().iter().map(FaultSides::minus_tag).collect()
        }),
    };
    if fault_part.given.is_none() && fault_part.minus_faces.is_empty() {
        return Err(invalid(
            "frictional_boundary",
            "not set (ModelBuilder::frictional_boundary or internal_fault)",
        ));
    }
    if fault.is_some() && s != 1.0 {
        return Err(invalid(
            "slip_factor",
            "an internal fault's slip is its jump: no antisymmetric_fault with it",
        ));
    }
    boundary.loading.validate()?;
    if let Some(g) = body.gravity {
        if g.iter().any(|c| !c.is_finite()) {
            return Err(invalid("gravity", format!("{g:?} must be finite")));
        }
    }
    Ok(Inputs {
        material,
        slip_factor: s,
        fault_part,
    })
}
