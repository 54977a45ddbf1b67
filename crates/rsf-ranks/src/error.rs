//! Error type of the distributed linear algebra.

use rsf_linalg::ProblemError;

/// Errors returned by this crate's set-ups (the transports themselves return none: see the
/// crate's documentation).
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A failure of the input that every solver shares (the workspace's one vocabulary,
    /// [`ProblemError`], defined in `rsf-linalg`): a dimension mismatch, an invalid matrix
    /// (not square, a pattern that is not symmetric, more than 2³² nodes), a non-finite
    /// entry.
    #[error(transparent)]
    Problem(#[from] ProblemError),
    /// The nodes' split into ranks does not fit the transport or the matrix (an owner that
    /// is not a rank, a colouring of another matrix).
    #[error("invalid partition: {0}")]
    InvalidPartition(String),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;
