//! The nonsmooth convex problem of every velocity solve of the rsf crates, as an interface:
//!
//! ```text
//! J(v) = ½ vᵀAv − bᵀv + Σ_k φ_k(v_{p_k})
//! ```
//!
//! with `A` sparse symmetric positive definite on the free dofs, `v` in node blocks
//! `v_p ∈ R^D` (node-major, dof `D p + c`), some dofs fixed and each `φ_k` a convex function
//! of one block (lumped friction). This crate holds what the solvers and their users share,
//! and no solver:
//!
//! - [`BlockNonlinearity`] (with [`Linearization`], [`NoNonlinearity`], [`Scaled`]): the
//!   seam between the solvers and the physics (`rsf`'s friction blocks implement it);
//! - [`NonsmoothSolver`] (one solve) and [`StepSolver`] (the fixed point iterations of a
//!   time step), with [`Stopping`] and [`SolveReport`]; [`FullStep`] turns any
//!   `NonsmoothSolver` into a `StepSolver`;
//! - the checks every solver makes: [`BlockedMatrix`] (the matrix and its fixed dofs) and
//!   [`check_inputs`], with their error, [`ProblemError`] (the workspace's one
//!   vocabulary for the failures of a solver's input, defined in `rsf-linalg`);
//! - [`SolveWatch`]: progress reports and a wall-clock cap on a long solve.
//!
//! The solvers live in `rsf-tnnmg` (TNNMG, nonlinear Gauss–Seidel) and `rsf-direct` (exact
//! condensation onto the nonsmooth blocks); each has its own error type
//! ([`NonsmoothSolver::Error`], [`StepSolver::Error`]), which holds [`ProblemError`] as its
//! variant `Problem` instead of repeating its variants.
#![warn(missing_docs)]

mod error;
mod matrix;
mod nonlinearity;
mod solver;
mod step;
mod watch;

pub use error::{ProblemError, Result};
pub use matrix::BlockedMatrix;
pub use nonlinearity::{BlockNonlinearity, Linearization, NoNonlinearity, Scaled};
pub use solver::{check_inputs, energy_norm_matrix, NonsmoothSolver, SolveReport, Stopping};
pub use step::{FullStep, StepSolver};
pub use watch::{SolveProgress, SolveWatch, WatchVerdict};
