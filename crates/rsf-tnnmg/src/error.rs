//! Error type of the solvers.

use rsf_nonsmooth::ProblemError;

/// Errors returned by the solvers of this crate.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A failure of the input that every solver shares (the workspace's one vocabulary,
    /// [`ProblemError`], defined in `rsf-linalg` and re-exported by `rsf-nonsmooth`): a
    /// dimension mismatch, an invalid matrix, a non-finite number in the input or in an
    /// iterate, a (sub)matrix that is not positive definite, an invalid option.
    #[error(transparent)]
    Problem(#[from] ProblemError),
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

impl From<rsf_ranks::Error> for Error {
    /// The distributed linear algebra's failures as the same variants: [`Error::Problem`]
    /// and [`Error::InvalidPartition`].
    fn from(e: rsf_ranks::Error) -> Self {
        match e {
            rsf_ranks::Error::Problem(p) => Error::Problem(p),
            rsf_ranks::Error::InvalidPartition(s) => Error::InvalidPartition(s),
            // `rsf_ranks::Error` is non-exhaustive: a variant added there is a failure of
            // the input until it gets its own variant here.
            other => Error::Problem(ProblemError::InvalidOption(other.to_string())),
        }
    }
}

impl From<rsf_linalg::Error> for Error {
    /// The shared checks ([`rsf_linalg::Error::Problem`]) as [`Error::Problem`]; anything
    /// else is a failure of the factorisation.
    fn from(e: rsf_linalg::Error) -> Self {
        match e {
            rsf_linalg::Error::Problem(p) => Error::Problem(p),
            other => Error::Factorisation(other.to_string()),
        }
    }
}
