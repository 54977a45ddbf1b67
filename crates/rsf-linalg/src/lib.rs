//! Sparse linear algebra shared by the rsf crates (it depends on faer only):
//!
//! * [`SparseMatrix`] — the CSC matrix type of the workspace (faer's
//!   `SparseColMat<usize, f64>`): finite element matrices (`rsf-fem`), the time
//!   integrators' operators (`rsf-time`), the solvers' inputs (`rsf-tnnmg`).
//! * [`Cholesky`] — sparse `A = L Lᵀ` with the symbolic analysis done once, numeric
//!   refactorisation without allocation and solves in place (the initial equilibrium in
//!   `rsf-fem`, the coarsest multigrid level in `rsf-tnnmg`).
//! * [`combine`] (`c_a A + c_b B` on one pattern) and [`spmv_add`] (`y ← y + α A x`).
//! * With the `sprs` feature, [`to_sprs`] and [`from_sprs`]: conversions to and from
//!   `sprs::CsMat<f64>` in CSC storage.
//!
//! * [`Parallelism`] — the one parallelism parameter of the workspace (faer's `Par` with
//!   a default, names and a deterministic two-way [`join`](Parallelism::join)).
//!
//! * [`Csc`] — the solvers' internal compressed-sparse-column matrix (plain arrays, sorted
//!   rows), shared by `rsf-tnnmg` and `rsf-direct`.
//! * [`ordered_sum`] and [`for_node_rows`] — work over rows on several threads with the
//!   bits of one thread (the solvers' deterministic sums and row-by-row writes).
//!
//! * [`ProblemError`] — the one vocabulary of the failures of a solver's input (dimension
//!   mismatch, invalid matrix, non-finite value, not positive definite, invalid option),
//!   returned by [`Csc`]'s checks and held as the variant `Problem` by this crate's [`Error`]
//!   and the solvers' errors (`rsf-nonsmooth` re-exports it).
//!
//! The factorisation and the products are sequential (`Par::Seq`); the parallel helpers
//! keep the bits of one thread, so results are bit-for-bit reproducible.
#![warn(missing_docs)]

mod cholesky;
mod csc;
mod error;
mod ops;
mod parallelism;
mod reduce;
#[cfg(feature = "sprs")]
mod sprs_conversion;

pub use cholesky::{Cholesky, FillOrdering};
pub use csc::Csc;
pub use error::{try_filled, Error, ProblemError, Result};
pub use ops::{combine, quadratic_form, spmv_add, SparseMatrix};
pub use parallelism::Parallelism;
pub use reduce::{for_node_rows, ordered_sum, SUM_PARALLEL_MIN};
#[cfg(feature = "sprs")]
pub use sprs_conversion::{from_sprs, to_sprs};
