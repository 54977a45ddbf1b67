//! Hierarchical low-rank (ℋ-matrix) representation of dense kernel matrices, made for the
//! stiffness condensed onto a fault (the Schur complement `S` of the quasi-dynamic runs,
//! docs/math.md §12) but usable for any square matrix whose rows and columns belong to
//! points in 1–3 dimensions and whose far-apart blocks have low numerical rank (elastic
//! and other asymptotically smooth kernels).
//!
//! - [`Points`]: one point per unknown (validated coordinates).
//! - [`HMatrix::from_dense`]: from a dense matrix, admissible blocks by truncated SVD.
//! - [`HMatrix::from_entries`]: from an entry function, admissible blocks by adaptive
//!   cross approximation (only `O(k (m + n))` entries of an `m × n` block) and
//!   recompression; for matrices too large to form ([`HMatrix::from_entries_par`]: the
//!   blocks on rayon's threads, the same bits). [`HOptions::components`] for vector
//!   kernels (interleaved components per point).
//! - [`HMatrix::from_symmetric_columns`]: from batches of whole columns of a symmetric
//!   matrix (each column one solve, as for a Schur complement), every column asked for
//!   once, nothing `n × n` formed; [`ColumnReport`] for its cost and error bound.
//! - [`HMatrix::apply_add`]: `y ← y + α S_H x`, allocation-free, bit-identical run to run
//!   and between sequential and parallel runs.
//! - [`HMatrix::split_rows`] and [`HMatrix::apply_by_parts`]: the product by parts of the
//!   rows, each part's rows ([`PartRows`]) handed to the caller's function inside the
//!   part's own task — row-wise work on the product in the same parallel region.
//! - [`SetupReport`]: the measured (or estimated) error `‖S − S_H‖_F / ‖S‖_F`, memory,
//!   ranks, blocks.
//!
//! The mathematics (cluster tree, admissibility, compression, error measure, cost) is in
//! docs/math.md §13.

#![warn(missing_docs)]

mod aca;
mod block;
mod cluster;
mod columns;
mod error;
mod hmatrix;
pub mod kernels;
mod lowrank;
mod options;
mod points;
mod product;
mod rng;

pub use error::{ColumnsError, Error};
pub use hmatrix::HMatrix;
pub use options::{ColumnReport, ErrorMeasure, HOptions, RowPart, SetupReport};
pub use points::Points;
pub use product::PartRows;
