//! Why a comparison with Okada's half-space could not be made.

/// Why a comparison with Okada's half-space ([`super`]) could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ComparisonError {
    /// The model: its mesh, its build (the static solve included: a solver stopped by its
    /// cap), its data.
    #[error(transparent)]
    Model(#[from] crate::Error),
    /// The half-space kernels (a rectangle above the surface, a point on an edge).
    #[error("half-space kernel: {0}")]
    HalfSpace(#[from] rsf_halfspace::Error),
    /// The fault or the mesh asked for does not fit the comparison (a size not on the
    /// coarsest grid, a slip the comparison does not make, too few nodes).
    #[error("{0}")]
    Setup(String),
}

impl From<rsf_fem::Error> for ComparisonError {
    fn from(e: rsf_fem::Error) -> Self {
        Self::Model(crate::Error::Fem(e))
    }
}

/// Result alias of the comparisons.
pub type Result<T> = std::result::Result<T, ComparisonError>;
