//! The errors of the checks this crate makes for every solver.

/// Errors of the checks shared by the solvers (inputs, the matrix, the stopping test);
/// each solver's own error type converts them ([`NonsmoothSolver::Error`](crate::NonsmoothSolver::Error)).
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// Input arrays do not have matching lengths.
    #[error("dimension mismatch in {what}: expected {expected}, got {got}")]
    DimensionMismatch {
        /// Which argument.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        got: usize,
    },
    /// The matrix is not square, not symmetric in pattern, or misses a diagonal entry.
    #[error("invalid matrix: {0}")]
    InvalidMatrix(String),
    /// A non-finite number appeared in the input.
    #[error("non-finite value in {0}")]
    NonFinite(&'static str),
    /// A (sub)matrix that must be positive definite is not (numerically).
    #[error("matrix is not positive definite ({0})")]
    NotPositiveDefinite(&'static str),
    /// Invalid solver option (e.g. a stopping test).
    #[error("invalid option: {0}")]
    InvalidOption(String),
    /// Another failure of the shared sparse matrix ([`rsf_linalg::Error`]).
    #[error(transparent)]
    Linalg(rsf_linalg::Error),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;

impl From<rsf_linalg::Error> for Error {
    /// The checks of [`rsf_linalg::Csc`] as the same variants of this crate.
    fn from(e: rsf_linalg::Error) -> Self {
        match e {
            rsf_linalg::Error::InvalidMatrix(m) => Error::InvalidMatrix(m),
            rsf_linalg::Error::NonFinite(what) => Error::NonFinite(what),
            rsf_linalg::Error::DimensionMismatch {
                what,
                expected,
                got,
            } => Error::DimensionMismatch {
                what,
                expected,
                got,
            },
            other => Error::Linalg(other),
        }
    }
}
