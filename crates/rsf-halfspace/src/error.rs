//! The crate's error type.

/// Errors of the half-space kernels and of the boundary-element operator.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is out of its range (NaN, infinite, not positive, …).
    #[error("{name} = {value} is invalid: expected {expected}")]
    Parameter {
        /// Name of the parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The range it must be in.
        expected: &'static str,
    },
    /// The observation point is above the free surface (Okada's `z > 0`; DC3D's
    /// `IRET = 2`).
    #[error("observation point z = {z} is above the free surface z = 0")]
    AboveSurface {
        /// The point's `z` (m).
        z: f64,
    },
    /// The source rectangle reaches above the free surface.
    #[error("the source's top edge is at z = {z_top} > 0, above the free surface")]
    SourceAboveSurface {
        /// `z` of the rectangle's top edge (m).
        z_top: f64,
    },
    /// The observation point lies on an edge of the dislocation, where displacement
    /// derivatives are singular (DC3D's `IRET = 1`; DC3D returns zeros there).
    #[error("observation point {point:?} lies on an edge of the dislocation (singular)")]
    OnEdge {
        /// The point (m).
        point: [f64; 3],
    },
    /// The observation point is an end of a 2-D dislocation segment (singular).
    #[error("observation point ({x}, {z}) is an end of the dislocation segment (singular)")]
    AtDislocation {
        /// Horizontal coordinate (m).
        x: f64,
        /// Vertical coordinate (m).
        z: f64,
    },
    /// A result is NaN or infinite (inputs so large or so close to a singular line that
    /// the formulas overflow).
    #[error("{what} is not finite")]
    NonFinite {
        /// What was computed.
        what: &'static str,
    },
    /// An index is out of range.
    #[error("index {index} out of range 0..{len}")]
    Index {
        /// The index asked for.
        index: usize,
        /// The number of rows or columns.
        len: usize,
    },
    /// Too many elements (the operator's dimension would overflow).
    #[error("{n_strike} × {n_dip} elements is too many")]
    TooManyElements {
        /// Elements along strike.
        n_strike: usize,
        /// Elements along dip.
        n_dip: usize,
    },
    /// Two elements of a set have the same centre (their rows of the operator would be
    /// equal).
    #[error("elements {first} and {second} have the same centre")]
    CoincidentCentres {
        /// The first element.
        first: usize,
        /// The second.
        second: usize,
    },
    /// An ℋ-matrix could not be built.
    #[error("ℋ-matrix: {0}")]
    HMatrix(#[from] rsf_hmatrix::Error),
}

/// [`Error::Parameter`] for the first `(name, value)` of `values` that is not `ok`, with
/// what is `expected` of it.
pub(crate) fn check_parameters<const K: usize>(
    values: [(&'static str, f64); K],
    ok: impl Fn(f64) -> bool,
    expected: &'static str,
) -> Result<(), Error> {
    match values.into_iter().find(|&(_, value)| !ok(value)) {
        Some((name, value)) => Err(Error::Parameter {
            name,
            value,
            expected,
        }),
        None => Ok(()),
    }
}

/// [`Error::Parameter`] for the first `(name, value)` of `values` that is not finite.
pub(crate) fn check_finite<const K: usize>(values: [(&'static str, f64); K]) -> Result<(), Error> {
    check_parameters(values, f64::is_finite, "finite")
}
