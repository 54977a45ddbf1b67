//! Stage 1: the mesh the model lives on — the hierarchy's finest level, or a copy cut open
//! along a fault inside the body.

use rsf_fem::{MeshHierarchy, SimplexMesh, SparseMatrix};

use super::super::settings::Faults;
use crate::error::{invalid, Result};
use crate::model::internal::InternalFault;

/// The mesh of the model and, for a fault inside the body, the scalar prolongations between
/// the levels cut open along it.
pub(crate) struct Domain<'h, const D: usize> {
    /// The refinement hierarchy (unsplit).
    pub hierarchy: &'h MeshHierarchy<D>,
    /// The finest mesh cut open along the fault, if there is one.
    split: Option<SimplexMesh<D>>,
    /// `P_j` (scalar, Cartesian) between the split (or unsplit) levels, one per level above
    /// the coarsest; `None` without a fault inside the body.
    pub split_prolongations: Option<Vec<SparseMatrix>>,
}

impl<'h, const D: usize> Domain<'h, D> {
    /// Cuts `hierarchy` open along the faults inside the body of `faults` (with the
    /// checked 3-D tangent of their pair frames), or takes its finest level as it is; with
    /// the faults (their jump shared half and half).
    ///
    /// # Errors
    /// [`checked_tangent`]'s; the splitting's (e.g. a fault the mesh does not resolve).
    pub fn cut(
        hierarchy: &'h MeshHierarchy<D>,
        faults: &Faults<D>,
    ) -> Result<(Self, Option<InternalFault<D>>)> {
        let tangent = faults.tangent;
        let Some(split) = faults.network_split.filter(|_| !faults.internal.is_empty()) else {
            let domain = Self {
                hierarchy,
                split: None,
                split_prolongations: None,
            };
            return Ok((domain, None));
        };
        let s = split(
            hierarchy,
            checked_tangent(tangent)?.as_ref(),
            &faults.internal,
        )?;
        let domain = Self {
            hierarchy,
            split: Some(s.mesh),
            split_prolongations: Some(s.prolongations),
        };
        Ok((domain, Some(s.fault)))
    }

    /// The model's mesh: the finest level, split along a fault inside the body.
    pub fn mesh(&self) -> &SimplexMesh<D> {
        self.split
            .as_ref()
            .unwrap_or_else(|| self.hierarchy.finest())
    }
}

/// The [`fault_tangent`](crate::ModelBuilder::fault_tangent), checked: 3-D only, finite,
/// non-zero.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `fault_tangent`.
pub(crate) fn checked_tangent<const D: usize>(
    tangent: Option<[f64; D]>,
) -> Result<Option<[f64; D]>> {
    if let Some(t) = tangent {
        if D != 3 {
            return Err(invalid(
                "fault_tangent",
                format!(
                    "{t:?} given in {D}-D: it orients the 3-D nodal frames only; in \
                     {D}-D the tangent is t = (-n_y, n_x), fixed by the normal (remove \
                     the call)"
                ),
            ));
        }
        if t.iter().any(|c| !c.is_finite()) || t.iter().all(|&c| c == 0.0) {
            return Err(invalid(
                "fault_tangent",
                format!("{t:?} must be finite and non-zero"),
            ));
        }
    }
    Ok(tangent)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tangent_is_3d_finite_and_non_zero() {
        assert_eq!(checked_tangent::<3>(None).unwrap(), None);
        assert_eq!(
            checked_tangent(Some([1.0, 0.0, 0.0])).unwrap(),
            Some([1.0, 0.0, 0.0])
        );
        for t in [[0.0; 3], [f64::NAN, 1.0, 0.0]] {
            let e = checked_tangent(Some(t)).unwrap_err();
            assert!(
                matches!(e, crate::Error::InvalidParameter { ref name, .. } if name == "fault_tangent"),
                "{e}"
            );
        }
        let e = checked_tangent(Some([1.0, 0.0])).unwrap_err().to_string();
        assert!(e.contains("2-D"), "{e}");
    }

    #[test]
    fn without_a_fault_inside_the_domain_is_the_finest_level() {
        let mesh =
            rsf_fem::rectangle([0.0; 2], [1.0; 2], 2, 2, rsf_fem::Diagonal::Forward).unwrap();
        let hierarchy = MeshHierarchy::refine_uniformly(mesh, 1);
        // A tangent is not looked at without a fault inside the body (Γ_F's frames check it).
        let faults = Faults {
            tangent: Some([1.0, 0.0]),
            ..Faults::default()
        };
        let (domain, fault) = Domain::cut(&hierarchy, &faults).unwrap();
        assert!(fault.is_none() && domain.split_prolongations.is_none());
        assert!(std::ptr::eq(domain.mesh(), hierarchy.finest()));
    }
}
