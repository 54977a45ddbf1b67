//! Processes that share work, for the rsf crates, at the bottom of the workspace (it
//! depends on none of them):
//!
//! * [`RankGroup`] — the one transport of a group of ranks: its rank and size, a halo
//!   exchange of f64 buffers with neighbour ranks ([`RankGroup::exchange`], messages
//!   [`HaloMessage`] agreed in advance) and an all-gather of every rank's values
//!   ([`RankGroup::all_gather`]). The fault ODE's shared evaluations and VTU pieces (crate
//!   `rsf`) and TNNMG's distributed solves (crate `rsf-tnnmg`) take it; MPI's
//!   implementation is in the `rsf-mpi` crate (outside the default build).
//! * [`ThreadRanks`] — threads of one process as ranks: the test double with which every
//!   crate's tests run work on several ranks without MPI and compare the bits with one
//!   process.
//! * [`TransportFactory`] — fresh groups of the same ranks, one per solver (what a method
//!   on ranks builds its solvers' transports with); [`ThreadGroups`] makes them for thread
//!   ranks.
//!
//! Every operation is collective and deterministic: an implementation only moves numbers,
//! so a computation's bits depend on what the ranks hold, never on the transport.
//!
//! Nothing here returns an error: a transport that fails (a rank that cannot reach its
//! neighbours) has no answer to give and panics, or ends the job (MPI) — the caller's
//! shapes are checked by assertions ([`check_all_gather`]).
#![warn(missing_docs)]

mod groups;
mod transport;

pub use groups::ThreadGroups;
pub use transport::{check_all_gather, HaloMessage, RankGroup, ThreadRanks};

/// Fresh groups of a job's ranks: each call (collective: every rank makes its calls in the
/// same order) returns this rank's end of a new group of the same ranks, whose messages
/// never meet another group's (over MPI: a duplicated communicator; over threads: the
/// next [`ThreadRanks`] group). What a solver on ranks is given, one call per built solver.
pub type TransportFactory = std::sync::Arc<dyn Fn() -> Box<dyn RankGroup> + Send + Sync>;
