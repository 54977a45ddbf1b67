//! Nonsmooth convex minimisation for rate-and-state friction problems.
//!
//! Every time step of the variational method of Pipping, Sander and Kornhuber needs the
//! minimiser of
//!
//! ```text
//! J(v) = ½ vᵀAv − bᵀv + Σ_k φ_k(v_{p_k})
//! ```
//!
//! where `A` is sparse symmetric positive definite (on the free dofs), `v` consists of
//! node blocks `v_p ∈ R^D` (node-major numbering, dof `D p + c`), some dofs are fixed
//! (Dirichlet values, bilateral contact) and each `φ_k` is a convex function of one block
//! (lumped friction). This crate knows nothing of friction laws or meshes: it takes the
//! matrix, the prolongations of a refinement hierarchy and the block functions through the
//! [`BlockNonlinearity`](rsf_nonsmooth::BlockNonlinearity) trait of `rsf-nonsmooth`, the
//! problem's interface, which this crate shares with `rsf-direct`.
//!
//! Solvers, both behind [`NonsmoothSolver`](rsf_nonsmooth::NonsmoothSolver) (and, through
//! [`FullStep`](rsf_nonsmooth::FullStep), [`StepSolver`](rsf_nonsmooth::StepSolver)):
//! - [`Tnnmg`]: truncated nonsmooth Newton multigrid (Gräser, Kornhuber, Sander); mesh
//!   independent iteration counts, the method of the paper (§6.2, tolerance 1e-10). Its
//!   linear correction runs block Gauss–Seidel multigrid cycles, by default as the
//!   preconditioner of conjugate gradients ([`LinearCorrection`]).
//! - [`NonlinearGaussSeidel`]: the block smoother alone (baseline).
//!
//! The third solver of the same problem, exact condensation onto the nonsmooth blocks plus
//! globalised Newton on the Schur complement (reference and small-problem fast path), is
//! `rsf-direct`'s `DirectSolver`.
//!
//! Internally the iterative solvers keep matrices in node-block storage (`D × D` blocks,
//! 32-bit node indices, the upper and the lower triangle in separate arrays so that each
//! Gauss–Seidel sweep streams half the matrix); results are deterministic (fixed
//! summation order). TNNMG's nonlinear smoother runs node by node (the default), colour
//! by colour ([`SmootherOrder::MultiColour`], [`Colouring`](rsf_ranks::Colouring)) or by red–black chunks of
//! breadth-first levels ([`SmootherOrder::RedBlackChunks`], also the linear multigrid's
//! fine-level smoother); the parallel orders run on several threads with bit-identical
//! iterates for every thread count.
//!
//! On ranks with distributed memory (docs/scaling.md, "Past one machine"), the
//! [`distributed`] module holds the linear V-cycle of one rank and TNNMG on ranks
//! ([`distributed::DistributedTnnmg`]: the same bits at every rank count, its global sums
//! exact; each rank computes its own rows of the coarse operators), built on the
//! distributed linear algebra of `rsf-ranks` (the multi-colour block Gauss–Seidel sweep of
//! one rank with a halo exchange per colour, exact sums, conjugate gradients), named by its
//! paths there (this crate re-exports none of them). The node-block storage, its kernels
//! and [`Colouring`](rsf_ranks::Colouring) are `rsf-ranks`' too.
//!
//! No solver returns an unconverged iterate as success: exhausting the budget is
//! [`Error::NotConverged`] with the iteration count and the last correction. The failures of
//! the input that every solver shares (dimensions, the matrix, non-finite values, options)
//! are [`Error::Problem`], holding the workspace's one vocabulary
//! [`ProblemError`](rsf_nonsmooth::ProblemError) (defined in `rsf-linalg`).
//!
//! ```
//! use faer::sparse::{SparseColMat, Triplet};
//! use rsf_nonsmooth::{NoNonlinearity, NonsmoothSolver};
//! use rsf_tnnmg::{Tnnmg, TnnmgOptions};
//!
//! // 1-D Laplacian (block size 1) with both ends fixed at 0: a linear problem.
//! let n = 5;
//! let mut t = Vec::new();
//! for i in 0..n {
//!     t.push(Triplet::new(i, i, 2.0));
//!     if i + 1 < n {
//!         t.push(Triplet::new(i, i + 1, -1.0));
//!         t.push(Triplet::new(i + 1, i, -1.0));
//!     }
//! }
//! let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
//! let fixed = [true, false, false, false, true];
//! let mut solver = Tnnmg::<1>::new(a.as_ref(), &fixed, &[], None, TnnmgOptions::default()).unwrap();
//! let b = [0.0, 1.0, 1.0, 1.0, 0.0];
//! let mut v = vec![0.0; n];
//! let report = solver.solve(&b, &NoNonlinearity, &mut v).unwrap();
//! assert!((v[2] - 2.0).abs() < 1e-12 && report.iterations <= 2);
//! ```
#![warn(missing_docs)]

mod chunks;
mod coarse;
pub mod distributed;
mod error;
mod galerkin;
mod gauss_seidel;
mod line_search;
mod linear_correction;
mod multigrid;
mod norm;
mod problem;
mod report;
mod smoother_order;
mod tnnmg;

pub use error::{Error, Result};
pub use gauss_seidel::NonlinearGaussSeidel;
pub use linear_correction::LinearCorrection;
use rsf_linalg::Parallelism;
pub use smoother_order::SmootherOrder;
pub use tnnmg::{Tnnmg, TnnmgOptions};
