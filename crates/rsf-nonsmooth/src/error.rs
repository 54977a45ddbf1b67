//! The errors of the checks this crate makes for every solver.
//!
//! They are the workspace's one vocabulary for the failures of a solver's input,
//! [`ProblemError`], defined in `rsf-linalg` (whose matrix checks return it too) and
//! re-exported here, at the solvers' interface: each solver's error type holds it as one
//! variant, `Problem` ([`NonsmoothSolver::Error`](crate::NonsmoothSolver::Error)).

pub use rsf_linalg::ProblemError;

/// Result alias of this crate: its checks fail with the shared [`ProblemError`].
pub type Result<T> = std::result::Result<T, ProblemError>;
