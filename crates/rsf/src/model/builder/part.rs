//! Which boundary facets a condition applies to: [`Part`] (a tag, a predicate on facet
//! midpoints, or a [`BoundaryPart`] of the finest mesh), resolved on the model's mesh.

use rsf_fem::{BoundaryPart, SimplexMesh};

use crate::error::{Error, Result};

/// A selection of boundary facets by their midpoint.
pub type FacetPredicate<const D: usize> = Box<dyn Fn(&[f64; D]) -> bool>;

/// Which boundary facets of the finest mesh form a part: a tag (e.g. a Gmsh physical
/// group), a predicate on facet midpoints, or a [`BoundaryPart`] built on the finest mesh.
pub enum Part<const D: usize> {
    /// Facets carrying this tag.
    Tag(String),
    /// Facets whose midpoint satisfies the predicate, under a name for messages.
    Predicate {
        /// Name of the part (used in errors).
        name: String,
        /// Selects facets by their midpoint (m).
        predicate: FacetPredicate<D>,
    },
    /// A part built by the caller on the finest mesh.
    Facets(BoundaryPart<D>),
}

impl<const D: usize> Part<D> {
    /// Facets tagged `tag`.
    pub fn tag(tag: impl Into<String>) -> Self {
        Part::Tag(tag.into())
    }

    /// Facets whose midpoint `x` satisfies `predicate(x)`, named `name`.
    pub fn predicate(
        name: impl Into<String>,
        predicate: impl Fn(&[f64; D]) -> bool + 'static,
    ) -> Self {
        Part::Predicate {
            name: name.into(),
            predicate: Box::new(predicate),
        }
    }

    /// The part's name (for messages).
    pub fn name(&self) -> &str {
        match self {
            Part::Tag(t) => t,
            Part::Predicate { name, .. } => name,
            Part::Facets(p) => p.name(),
        }
    }

    /// The part's facets on `mesh` (the model's finest mesh, split along an internal fault
    /// if there is one).
    ///
    /// # Errors
    /// [`Error::BoundaryPart`] for a part that selects nothing or was built on another
    /// mesh; other mesh errors as [`Error::Fem`].
    pub(crate) fn resolve(&self, mesh: &SimplexMesh<D>) -> Result<BoundaryPart<D>> {
        let part = match self {
            Part::Tag(t) => BoundaryPart::from_tag(mesh, t),
            Part::Predicate { name, predicate } => {
                BoundaryPart::from_predicate(mesh, name, predicate)
            }
            Part::Facets(p) => p.check_mesh(mesh).map(|()| p.clone()),
        };
        part.map_err(|e| match e {
            rsf_fem::Error::EmptySegment { .. } => {
                part_error(self.name(), "selects no boundary facet")
            }
            rsf_fem::Error::DimensionMismatch { .. } => part_error(
                self.name(),
                "was built on another mesh (use the finest level)",
            ),
            e => Error::Fem(e),
        })
    }
}

impl<const D: usize> From<&str> for Part<D> {
    fn from(tag: &str) -> Self {
        Part::tag(tag)
    }
}

impl<const D: usize> From<String> for Part<D> {
    fn from(tag: String) -> Self {
        Part::Tag(tag)
    }
}

impl<const D: usize> From<BoundaryPart<D>> for Part<D> {
    fn from(part: BoundaryPart<D>) -> Self {
        Part::Facets(part)
    }
}

/// [`Error::BoundaryPart`] naming `part`.
pub(crate) fn part_error(part: &str, reason: impl Into<String>) -> Error {
    Error::BoundaryPart {
        part: part.to_owned(),
        reason: reason.into(),
    }
}
