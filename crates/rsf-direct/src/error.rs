//! Error type of the condensation and the direct solver.

use rsf_nonsmooth::ProblemError;

/// Errors of the condensation, its orderings and the direct solver.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A failure of the input that every solver shares (the workspace's one vocabulary,
    /// [`ProblemError`], defined in `rsf-linalg` and re-exported by `rsf-nonsmooth`): a
    /// dimension mismatch, an invalid matrix, a non-finite number in the input or in an
    /// iterate, a (sub)matrix that is not positive definite, an invalid option.
    #[error(transparent)]
    Problem(#[from] ProblemError),
    /// The direct solver's Newton iteration on the condensed unknowns used its iteration
    /// budget without meeting the tolerance.
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
    /// A choice that needs a cargo feature this build does not have (e.g.
    /// [`InteriorOrdering::NestedDissection`](crate::InteriorOrdering::NestedDissection)
    /// without `metis`).
    #[error("{what} needs the cargo feature `{feature}` (of rsf-direct, or rsf's `{feature}`)")]
    FeatureDisabled {
        /// What was asked for.
        what: &'static str,
        /// The feature to enable.
        feature: &'static str,
    },
    /// An elimination met a pivot that is not positive (the matrix is not numerically
    /// positive definite there): `dof` is the row of the input matrix whose pivot failed.
    #[error("matrix is not positive definite: non-positive pivot at dof {dof} ({what})")]
    NonPositivePivot {
        /// Which elimination.
        what: &'static str,
        /// The dof (row of the input matrix, or of the kept set for a post-step).
        dof: usize,
    },
    /// What a computation would hold exceeds the limit it was given, or the index range:
    /// refused before allocating it.
    #[error("{what} needs {bytes} bytes, above the limit of {limit} bytes")]
    TooLarge {
        /// What would be held.
        what: &'static str,
        /// The bytes it needs.
        bytes: u128,
        /// The limit (`usize::MAX` for the address space).
        limit: usize,
    },
    /// An allocation of a large buffer failed (the system refused it).
    #[error("could not allocate {bytes} bytes for {what}")]
    OutOfMemory {
        /// The buffer.
        what: &'static str,
        /// Its size.
        bytes: usize,
    },
    /// A checkpoint file could not be written or read, or is damaged.
    #[error("checkpoint {path}: {reason}")]
    Checkpoint {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// A checkpoint file belongs to another problem (matrix, sets, right-hand sides or
    /// ordering): it is refused and left as it is.
    #[error("checkpoint {path} is of another problem: {reason}")]
    CheckpointMismatch {
        /// The file.
        path: String,
        /// Which input differs.
        reason: String,
    },
    /// A long computation was stopped by its caller's progress monitor after `done` of
    /// `total` steps (its last checkpoint, if any, stays for a resumed call).
    #[error("stopped by the caller after {done} of {total} steps")]
    Stopped {
        /// Steps done.
        done: usize,
        /// Steps in all.
        total: usize,
    },
    /// Failure inside the sparse factorisation (faer's symbolic or numeric Cholesky).
    #[error("sparse factorisation failed: {0}")]
    Factorisation(String),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;

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
