//! Processes that share work, for the rsf crates: the transport of a group of ranks and the
//! distributed linear algebra on it that is not one solver's own. It depends on
//! `rsf-linalg` (the CSC matrix, [`Parallelism`](rsf_linalg::Parallelism), the shared
//! [`ProblemError`](rsf_linalg::ProblemError)) and sits below `rsf-tnnmg` and `rsf`.
//!
//! The transport:
//! * [`RankGroup`] — the one transport of a group of ranks: its rank and size, a halo
//!   exchange of f64 buffers with neighbour ranks ([`RankGroup::exchange`], messages
//!   [`HaloMessage`] agreed in advance) and an all-gather of every rank's values
//!   ([`RankGroup::all_gather`]). The fault ODE's shared evaluations and VTU pieces (crate
//!   `rsf`) and TNNMG's distributed solves (crate `rsf-tnnmg`) take it; MPI's
//!   implementation is in the `rsf-mpi` crate (outside the default build).
//! * [`ThreadRanks`] — threads of one process as ranks: the test double with which every
//!   crate's tests run work on several ranks without MPI ([`ThreadRanks::run`]) and compare
//!   the bits with one process.
//! * [`TransportFactory`] — fresh groups of the same ranks, one per solver (what a method
//!   on ranks builds its solvers' transports with); [`ThreadGroups`] makes them for thread
//!   ranks.
//! * [`Processes`] — the processes of a job as a program sees them: its rank, its groups
//!   and transports, a barrier, and how an error ends them all (`end_all`); MPI's job is
//!   the `rsf-mpi` crate's, [`ThreadProcess`] the tests' (threads of one process).
//!
//! The distributed linear algebra (docs/scaling.md, "Past one machine"), on symmetric
//! matrices of `D × D` node blocks (node-major: node `p` owns the dofs `D p .. D p + D`):
//! * [`bsr::BlockCsr`] — one process's node-block sparse matrix (the triangles apart, for
//!   Gauss–Seidel sweeps that stream half of it), with the small dense kernels of
//!   [`block`]; [`Colouring`] — a greedy colouring of its node graph.
//! * [`LocalRows`] — one rank's owned rows and ghost layer in local numbering, the rows of
//!   a one-process row sum in the same order; [`node_graph`] — the node graph a partitioner
//!   splits; [`NodeGraph`] — the whole graph gathered from the ranks' rows.
//! * [`halo`] — the halo plans (which owned nodes each neighbour needs, one round per
//!   colour), their exchanges, the all-gathers, and [`halo::HaloCounters`], what a rank sent;
//!   [`NodeAllGather`] — a whole vector gathered from the nodes' owners; [`NodePlan`] —
//!   per-node records sent to the ranks that need them.
//! * [`ExactSums`] — global sums correctly rounded from exact partial sums: the same bits
//!   at every rank count and partition.
//! * [`DistributedSweep`] — one rank's multi-colour block Gauss–Seidel sweep with a halo
//!   exchange per colour; [`BlockGaussSeidel`] — linear block Gauss–Seidel's node update on
//!   a rank's rows, [`ColouredGaussSeidel`] its one-process reference (the same bits).
//! * [`DistributedCg`] — conjugate gradients on ranks with a [`Preconditioner`] (TNNMG's
//!   distributed V-cycle in `rsf-tnnmg`), its inner products exact sums.
//!
//! Every operation is collective and deterministic: a transport only moves numbers, so a
//! computation's bits depend on what the ranks hold, never on the transport or the rank
//! count.
//!
//! A transport returns no error: one that fails (a rank that cannot reach its neighbours)
//! has no answer to give and panics, or ends the job (MPI) — the caller's shapes are checked
//! by assertions ([`check_all_gather`]). The set-ups of the linear algebra check their
//! input and return [`Error`]: [`Error::Problem`] (the workspace's shared vocabulary) or
//! [`Error::InvalidPartition`].
//!
//! Feature `naive-sums` (off): `ExactSums::use_naive_partial_sums`, a reduction whose bits
//! depend on the partition, for the tests that must detect one.
#![warn(missing_docs)]

pub mod block;
pub mod bsr;
mod cg;
mod colouring;
mod error;
mod gather;
mod groups;
pub mod halo;
mod linear;
mod local_rows;
mod node_graph;
mod node_plan;
mod processes;
mod reduce;
mod sweep;
mod transport;

#[cfg(test)]
mod sweep_tests;

pub use cg::{DistributedCg, Preconditioner};
pub use colouring::{Colouring, COLOUR_PARALLEL_MIN};
pub use error::{Error, Result};
pub use gather::NodeAllGather;
pub use groups::ThreadGroups;
pub use linear::{BlockGaussSeidel, ColouredGaussSeidel};
pub use local_rows::{node_graph, LocalRows};
pub use node_graph::NodeGraph;
pub use node_plan::NodePlan;
pub use processes::{Processes, ThreadProcess};
pub use reduce::ExactSums;
pub use sweep::DistributedSweep;
pub use transport::{check_all_gather, HaloMessage, RankGroup, ThreadRanks};

/// Fresh groups of a job's ranks: each call (collective: every rank makes its calls in the
/// same order) returns this rank's end of a new group of the same ranks, whose messages
/// never meet another group's (over MPI: a duplicated communicator; over threads: the
/// next [`ThreadRanks`] group). What a solver on ranks is given, one call per built solver.
pub type TransportFactory = std::sync::Arc<dyn Fn() -> Box<dyn RankGroup> + Send + Sync>;
