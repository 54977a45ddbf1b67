//! [`MpiRanks`]: one MPI communicator as the workspace's transport ([`RankGroup`]) and as
//! the processes of a job ([`Processes`]).

use std::sync::Arc;

use mpi::datatype::PartitionMut;
use mpi::topology::{Communicator, SimpleCommunicator};
use mpi::traits::CommunicatorCollectives;
use rsf_ranks::{check_all_gather, HaloMessage, Processes, RankGroup, TransportFactory};

use crate::halo::exchange_on;
use crate::Error;

/// The processes of one MPI communicator — `MPI_COMM_WORLD` ([`world`](Self::world), what
/// [`crate::initialize`] returns) or a duplicate of one ([`duplicate`](Self::duplicate)) —
/// the one MPI type of the workspace's seams:
///
/// * as a [`RankGroup`], the transport of the fault ODE's shared evaluations, VTU pieces
///   and TNNMG's distributed solves: each exchange posts one `MPI_Irecv` per received
///   message and one `MPI_Isend` per sent message, then waits for all of them (every rank
///   posts all its messages before it waits, so no order of the ranks deadlocks); each
///   all-gather is one `MPI_Allgatherv`. An exchange allocates nothing (its requests live
///   on the stack), nor does an all-gather once it has been called (its counts' buffers
///   are kept);
/// * as the [`Processes`] of a job (what `rsf_programs`' programs run on,
///   [`crate::main_on_ranks`]): each [`group`](Processes::group) and each call of the
///   [`transports`](Processes::transports)' factory is a fresh duplicate of this
///   communicator (`MPI_Comm_dup`, collective), so that the messages of one group never
///   meet another's; [`barrier`](Processes::barrier) is `MPI_Barrier`;
///   [`end_all`](Processes::end_all) is `MPI_Abort` on the world.
///
/// Drop a duplicate before MPI ends (before the `Universe` of [`crate::initialize`]): it
/// frees its communicator.
pub struct MpiRanks {
    comm: SimpleCommunicator,
    rank: usize,
    size: usize,
    /// `MPI_Allgatherv`'s counts and displacements, in buffers kept between calls: no
    /// allocation per evaluation.
    partition: Partition,
}

// SAFETY: a communicator handle is a process-wide MPI object, valid on any thread, and MPI
// runs with `MPI_THREAD_SERIALIZED` ([`crate::initialize`] refuses less): calls may come
// from any thread, one at a time. The transport's calls take `&mut self`, so one value is
// used by one thread at a time; the calls through `&self` (`duplicate`, `barrier`,
// `end_all`, the transports' factory) are collectives, which every rank makes from the
// program's one thread in program order (the contract of [`RankGroup`] and
// [`Processes`]) — as the handle-less world ranks and the factories of duplicates, both
// `Send + Sync`, did before this type held the handle.
unsafe impl Send for MpiRanks {}
// SAFETY: as `Send` above.
unsafe impl Sync for MpiRanks {}

impl std::fmt::Debug for MpiRanks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MpiRanks")
            .field("rank", &self.rank)
            .field("size", &self.size)
            .finish()
    }
}

impl MpiRanks {
    /// The ranks of `MPI_COMM_WORLD`. MPI must be running ([`crate::initialize`]).
    pub fn world() -> Self {
        Self::on(SimpleCommunicator::world())
    }

    /// A new communicator of the same processes (`MPI_Comm_dup`: collective, so every rank
    /// calls it, in the same order), whose messages never meet this one's.
    pub fn duplicate(&self) -> Self {
        Self::on(self.comm.duplicate())
    }

    fn on(comm: SimpleCommunicator) -> Self {
        let rank = usize::try_from(comm.rank()).expect("MPI ranks are not negative");
        let size = usize::try_from(comm.size()).expect("MPI sizes are positive");
        Self {
            comm,
            rank,
            size,
            partition: Partition::default(),
        }
    }

    /// This process's rank, in `0..size()` (the same as [`RankGroup::rank`] and
    /// [`Processes::rank`]).
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// The number of processes (the same as [`RankGroup::size`] and [`Processes::size`]).
    pub fn size(&self) -> usize {
        self.size
    }

    /// The communicator (for a program's own collectives among the same ranks: barriers,
    /// gathers).
    pub fn communicator(&self) -> &SimpleCommunicator {
        &self.comm
    }
}

impl RankGroup for MpiRanks {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.size
    }

    /// # Panics
    /// Besides the trait's: if the ranges of `recvs` are not increasing and disjoint (as
    /// a halo plan gives them), or a message names the caller or a rank out of range; if a
    /// message arrives shorter than agreed (a longer one is an MPI error, which ends the
    /// job).
    fn exchange(
        &mut self,
        sends: &[HaloMessage],
        send: &[f64],
        recvs: &[HaloMessage],
        recv: &mut [f64],
    ) {
        exchange_on(&self.comm, (self.rank, self.size), sends, send, recvs, recv);
    }

    /// `MPI_Allgatherv` on the communicator: the trait's result, in one collective (MPI's
    /// algorithm: a ring, recursive doubling or Bruck's, by the sizes).
    ///
    /// # Panics
    /// As the trait's shapes; if a count or displacement does not fit MPI's `int` (more
    /// than 2³¹ values). A failing MPI ends the job (MPI's error handler); counts that
    /// disagree between the ranks are erroneous MPI (the job may end).
    fn all_gather(&mut self, send: &[f64], counts: &[usize], recv: &mut [f64]) {
        check_all_gather(self.rank, self.size, send, counts, recv);
        let mut partition = self.partition.of(recv, counts);
        self.comm.all_gather_varcount_into(send, &mut partition);
    }
}

impl Processes for MpiRanks {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.size
    }

    /// A new [`duplicate`](MpiRanks::duplicate) of the communicator per call.
    fn group(&self) -> Box<dyn RankGroup + Send> {
        Box::new(self.duplicate())
    }

    /// A factory of new duplicates of the communicator (itself holding one, made here).
    fn transports(&self) -> TransportFactory {
        let parent = self.duplicate();
        Arc::new(move || -> Box<dyn RankGroup> { Box::new(parent.duplicate()) })
    }

    /// Writes `message` (prefixed with this rank) to standard error and calls `MPI_Abort`
    /// on the world with exit code 1, which ends every process of the job — where
    /// returning would leave the other ranks waiting in their next collective.
    fn end_all(&self, message: &str) -> ! {
        // One write of the whole line: `eprintln!` writes its pieces one by one, and the
        // launcher's abort banner (another process on the same stderr) can land between them.
        let line = format!("rank {} of {}: {message}\n", self.rank, self.size);
        let _ = std::io::Write::write_all(&mut std::io::stderr().lock(), line.as_bytes());
        SimpleCommunicator::world().abort(1)
    }

    /// `MPI_Barrier` on the communicator.
    fn barrier(&self) {
        self.comm.barrier();
    }
}

/// The counts and displacements of an `MPI_Allgatherv` (MPI's `int`) of a rank-ordered
/// concatenation, in buffers kept between calls (no allocation once they hold the rank
/// count).
#[derive(Debug, Clone, Default)]
struct Partition {
    counts: Vec<i32>,
    displs: Vec<i32>,
}

impl Partition {
    /// `recv` partitioned by `counts`: rank `r`'s `counts[r]` values at
    /// `counts[..r].iter().sum()`.
    ///
    /// # Panics
    /// If a count or displacement does not fit MPI's `int` (more than 2³¹ values), or
    /// `recv` is shorter than the counts' sum.
    fn of<'a>(
        &'a mut self,
        recv: &'a mut [f64],
        counts: &[usize],
    ) -> PartitionMut<'a, [f64], &'a [i32], &'a [i32]> {
        let to_int = |c: usize| i32::try_from(c).unwrap_or_else(|_| panic!("{}", Error::Count(c)));
        self.counts.clear();
        self.displs.clear();
        let mut at = 0usize;
        for &c in counts {
            self.counts.push(to_int(c));
            self.displs.push(to_int(at));
            at += c;
        }
        assert!(recv.len() >= at, "all_gather: the sum of the counts");
        PartitionMut::new(recv, &self.counts[..], &self.displs[..])
    }
}
