//! Block Gauss–Seidel and the linear V-cycle on ranks with distributed memory (issue 57,
//! docs/scaling.md "Past one machine"): the first parts of the implicit engine on ranks, a
//! multi-colour smoother and a linear multigrid cycle; TNNMG's outer loop (the truncated
//! nonlinear smoother, the Krylov method's reductions) is a later part.
//!
//! Every node of the matrix is owned by one rank (an owner vector, e.g. a graph partition
//! of the node graph [`node_graph`]). A rank holds its owned nodes' block rows and one layer
//! of ghost nodes ([`LocalRows`]), and sweeps colour by colour through a global
//! [`Colouring`](crate::Colouring) ([`DistributedSweep`]): its owned nodes of a colour,
//! then one halo exchange of that colour's values with the neighbour ranks through the
//! caller's transport ([`HaloExchange`]: MPI in `rsf-mpi`, threads in [`ThreadExchange`]).
//! The iterate has the same bits at every rank count as the one-process coloured sweep with
//! the same node updates; [`HaloCounters`] counts the messages and values sent.
//! [`BlockGaussSeidel`] is linear block Gauss–Seidel's node update on a rank's rows, and
//! [`ColouredGaussSeidel`] its one-process reference (the tests' and measurements'
//! smoother).
//!
//! [`DistributedVCycle`] is one rank's linear V-cycle on a nested hierarchy: per level its
//! rows, sweep and transfers ([`DistributedTransfer`]), the coarsest problem gathered and
//! solved on every rank; the set-up ([`VCycleHierarchy`]: the Galerkin coarse operators,
//! masks and colourings) is still computed whole on every rank. [`ColouredVCycle`] is its
//! one-process reference with the same smoother order, and the same bits.

mod halo;
mod hierarchy;
mod linear;
mod local_rows;
mod reduce;
mod sweep;
mod transfer;
mod transport;
mod vcycle;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod transfer_tests;
#[cfg(test)]
mod vcycle_tests;

pub use halo::HaloCounters;
pub use hierarchy::{ColouredVCycle, VCycleHierarchy, VCycleShape};
pub use linear::{BlockGaussSeidel, ColouredGaussSeidel};
pub use local_rows::{node_graph, LocalRows};
pub use sweep::DistributedSweep;
pub use transfer::DistributedTransfer;
pub use transport::{HaloExchange, HaloMessage, ThreadExchange};
pub use vcycle::DistributedVCycle;
