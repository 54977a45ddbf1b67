//! The implicit engine on ranks with distributed memory (issue 57, docs/scaling.md "Past
//! one machine"): a linear multigrid cycle and TNNMG ([`DistributedTnnmg`]), whose iterates
//! have the same bits at every rank count, built on the distributed linear algebra of
//! `rsf-ranks` (named by its paths there: this module re-exports none of it).
//!
//! From `rsf-ranks`: every node of the matrix is owned by one rank (an owner vector, e.g.
//! a graph partition of the node graph [`node_graph`](rsf_ranks::node_graph)). A rank holds its owned nodes' block
//! rows and one layer of ghost nodes ([`LocalRows`](rsf_ranks::LocalRows)), and sweeps colour by colour through a
//! global [`Colouring`](rsf_ranks::Colouring) ([`DistributedSweep`](rsf_ranks::DistributedSweep)): its owned nodes of a
//! colour, then one halo exchange of that colour's values with the neighbour ranks through
//! the caller's transport ([`RankGroup`](rsf_ranks::RankGroup): MPI in `rsf-mpi`, threads in [`ThreadRanks`](rsf_ranks::ThreadRanks)).
//! The iterate has the same bits at every rank count as the one-process coloured sweep with
//! the same node updates; [`HaloCounters`](rsf_ranks::halo::HaloCounters) counts the messages, collectives and values
//! sent. [`BlockGaussSeidel`](rsf_ranks::BlockGaussSeidel) is linear block Gauss–Seidel's node update on a rank's rows,
//! and [`ColouredGaussSeidel`](rsf_ranks::ColouredGaussSeidel) its one-process reference (the tests' and measurements'
//! smoother).
//!
//! [`DistributedVCycle`] is one rank's linear V-cycle on a nested hierarchy: per level its
//! rows, sweep and transfers ([`DistributedTransfer`]), the coarsest problem gathered and
//! solved on every rank; built alone ([`DistributedVCycle::new`]) it reads a whole
//! hierarchy ([`VCycleHierarchy`]: the Galerkin coarse operators, masks and colourings,
//! computed on every rank), inside [`DistributedTnnmg`] the rank's own rows of every level
//! (each computed by its owner). [`ColouredVCycle`] is its one-process reference with the
//! same smoother order, and the same bits.
//!
//! [`DistributedTnnmg`] is TNNMG on ranks: the multi-colour nonlinear smoother on the owned
//! nodes, the truncated linearisation on the active blocks gathered from their owners, the
//! rank's rows of the Newton hierarchy computed by their owners and updated incrementally,
//! [`DistributedVCycle`]s on the truncated Newton system (alone, or preconditioning the
//! conjugate gradients of `rsf-ranks`, [`DistributedCg`](rsf_ranks::DistributedCg)), the
//! kink rule and the exact line search; its global sums are exact and rounded once (a
//! reproducible reduction, [`ExactSums`](rsf_ranks::ExactSums)), and [`TnnmgCounters`]
//! counts what each part sends. [`BlockTresca`] is a closed-form nonsmooth nonlinearity for
//! its tests and measurements.

mod active;
mod hierarchy;
mod rank_hierarchy;
mod tnnmg;
mod tnnmg_options;
mod tnnmg_step;
mod transfer;
mod tresca;
mod vcycle;

#[cfg(test)]
mod fixtures;
#[cfg(test)]
mod tnnmg_tests;
#[cfg(test)]
mod transfer_tests;
#[cfg(test)]
mod vcycle_tests;

pub use hierarchy::{ColouredVCycle, VCycleHierarchy, VCycleShape};
pub use tnnmg::DistributedTnnmg;
pub use tnnmg_options::{DistributedTnnmgOptions, TnnmgCounters};
pub use transfer::DistributedTransfer;
pub use tresca::BlockTresca;
pub use vcycle::DistributedVCycle;
