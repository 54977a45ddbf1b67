//! Exact condensation onto the nonsmooth blocks of the velocity problem, and the direct
//! solver built on it (docs/math.md §8).
//!
//! A velocity problem `J(v) = ½ vᵀAv − bᵀv + Σ_k φ_k(v_{p_k})` (the interface is
//! `rsf-nonsmooth`'s) is smooth away from the blocks `p_k` of the fault. This crate
//! eliminates everything else exactly:
//!
//! - [`Condensation`]: a partial sparse Cholesky of `A` with the interior `R` first and the
//!   free components `F` of the blocks last, so that the dense Schur complement
//!   `S = A_FF − A_FR A_RR⁻¹ A_RF` is the factor's last block; forward and backward sweeps
//!   condense a right-hand side and recover the interior. The interior's fill-reducing
//!   order is AMD after one level of dissection, or METIS's nested dissection
//!   ([`InteriorOrdering`], feature `metis` through `rsf-metis`). The fault ODE of `rsf`
//!   uses it alone; [`SchurEntries`] gives entries of `S` without forming it.
//! - [`SchurOnly`]: the same `S` and condensed right-hand sides by a multifrontal
//!   elimination that keeps no factor column (a fraction of the factor's memory in 3-D),
//!   checkpointed, with a few extra kept dofs whose extension rows it also gives.
//! - [`DirectSolver`]: the condensation plus a globalised nonsmooth Newton iteration on the
//!   dense `|F|` unknowns (nonlinear Gauss–Seidel, truncated Newton with dense Cholesky,
//!   line search) — a [`NonsmoothSolver`](rsf_nonsmooth::NonsmoothSolver) and a
//!   [`StepSolver`](rsf_nonsmooth::StepSolver) like `rsf-tnnmg`'s solvers, the reference
//!   and the fast path of small problems. With an energy norm it measures changes exactly
//!   in that norm through the discrete harmonic extension.
//! - [`DirectMemory`]: what the set-up will hold, estimated from the symbolic analysis
//!   alone.
//!
//! Threads ([`rsf_linalg::Parallelism`]): the two halves of the interior in every sweep
//! from [`INTERIOR_PARALLEL_MIN`] interior unknowns, the dense Newton factorisations from
//! [`DENSE_PARALLEL_MIN`] unknowns; the results do not depend on them.
//!
//! ```
//! use faer::sparse::{SparseColMat, Triplet};
//! use rsf_direct::{DirectOptions, DirectSolver};
//! use rsf_nonsmooth::{NoNonlinearity, NonsmoothSolver};
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
//! let mut solver = DirectSolver::<1>::new(a.as_ref(), &fixed, DirectOptions::default()).unwrap();
//! let b = [0.0, 1.0, 1.0, 1.0, 0.0];
//! let mut v = vec![0.0; n];
//! solver.solve(&b, &NoNonlinearity, &mut v).unwrap();
//! assert!((v[2] - 2.0).abs() < 1e-12);
//! ```
//!
//! Errors are [`Error`]: the failures of the input that every solver shares (dimensions, the
//! matrix, non-finite values, options) are [`Error::Problem`], holding the workspace's one
//! vocabulary [`ProblemError`](rsf_nonsmooth::ProblemError) (defined in `rsf-linalg`); the
//! rest (non-convergence, limits, checkpoints, the factorisation) are this crate's own.
#![warn(missing_docs)]

mod condensation;
mod dense;
mod error;
mod fault_newton;
mod functionals;
mod harmonic;
mod memory;
mod norm_bounds;
mod options;
mod ordering;
mod partial_cholesky;
mod schur_entries;
mod schur_only;
mod solver;

pub use condensation::Condensation;
pub use dense::DENSE_PARALLEL_MIN;
pub use error::{Error, Result};
pub use memory::DirectMemory;
pub use options::DirectOptions;
pub use ordering::InteriorOrdering;
pub use partial_cholesky::INTERIOR_PARALLEL_MIN;
pub use schur_entries::SchurEntries;
pub use schur_only::{
    CheckpointPolicy, ExtraRows, InterfaceSchur, KeptSchur, PackedSymmetric, Progress,
    RightHandSide, SchurOnly, SchurOnlyOptions, SchurOnlyPlan, SchurOnlyReport,
};
pub use solver::DirectSolver;
