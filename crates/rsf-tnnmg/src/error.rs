//! Error type of the solvers.

/// Errors returned by the solvers of this crate.
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
    /// A non-finite number appeared in the input or in an iterate.
    #[error("non-finite value in {0}")]
    NonFinite(&'static str),
    /// A (sub)matrix that must be positive definite is not (numerically).
    #[error("matrix is not positive definite ({0})")]
    NotPositiveDefinite(&'static str),
    /// The solver used its iteration budget without meeting the tolerance.
    #[error(
        "{solver} did not converge in {iterations} iterations \
         (last correction {correction:.3e} in the energy norm, tolerance {tolerance:.3e})"
    )]
    NotConverged {
        /// Solver name.
        solver: &'static str,
        /// Iterations performed.
        iterations: usize,
        /// Energy norm of the last correction.
        correction: f64,
        /// The tolerance that was asked for.
        tolerance: f64,
    },
    /// The solve reached the time limit of its [`SolveWatch`](rsf_nonsmooth::SolveWatch)
    /// before the tolerance.
    #[error(
        "{solver} stopped at its time limit of {limit:.1} s after {iterations} iterations \
         ({seconds:.1} s; last correction {correction:.3e} in the energy norm, tolerance \
         {tolerance:.3e})"
    )]
    TimeLimit {
        /// Solver name.
        solver: &'static str,
        /// Iterations performed.
        iterations: usize,
        /// Energy norm of the last correction.
        correction: f64,
        /// What the correction had to reach (`absolute + relative · ‖v‖` at the last
        /// iterate).
        tolerance: f64,
        /// Wall time of the solve (s).
        seconds: f64,
        /// The limit (s).
        limit: f64,
    },
    /// Invalid solver option.
    #[error("invalid option: {0}")]
    InvalidOption(String),
    /// The nodes' split into ranks does not fit the transport or the matrix (an owner that
    /// is not a rank, a colouring of another matrix).
    #[error("invalid partition: {0}")]
    InvalidPartition(String),
    /// Failure inside the sparse factorisation library.
    #[error("sparse factorisation failed: {0}")]
    Factorisation(String),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;

impl From<rsf_linalg::Error> for Error {
    /// The shared sparse matrix's checks ([`rsf_linalg::Csc`]) as this crate reported them
    /// before it moved to `rsf-linalg`; anything else is a failure of the factorisation.
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
            other => Error::Factorisation(other.to_string()),
        }
    }
}

impl From<rsf_nonsmooth::Error> for Error {
    /// The checks shared by the solvers (`rsf-nonsmooth`) as the same variants of this crate.
    fn from(e: rsf_nonsmooth::Error) -> Self {
        match e {
            rsf_nonsmooth::Error::DimensionMismatch {
                what,
                expected,
                got,
            } => Error::DimensionMismatch {
                what,
                expected,
                got,
            },
            rsf_nonsmooth::Error::InvalidMatrix(m) => Error::InvalidMatrix(m),
            rsf_nonsmooth::Error::NonFinite(what) => Error::NonFinite(what),
            rsf_nonsmooth::Error::NotPositiveDefinite(what) => Error::NotPositiveDefinite(what),
            rsf_nonsmooth::Error::InvalidOption(m) => Error::InvalidOption(m),
            rsf_nonsmooth::Error::Linalg(e) => e.into(),
            other => Error::InvalidOption(other.to_string()),
        }
    }
}
