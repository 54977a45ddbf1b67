//! The workspace's transport ([`RankGroup`]) over MPI: halo exchanges by nonblocking
//! point-to-point messages ([`exchange_on`]) and all-gathers by `MPI_Allgatherv`, on a
//! duplicate of the world communicator ([`MpiExchange`], TNNMG's solves) or on the world
//! itself ([`MpiRanks`](crate::MpiRanks), the fault ODE's evaluations).

use mpi::collective::CommunicatorCollectives;
use mpi::point_to_point::{Destination, Source};
use mpi::request::LocalScope;
use mpi::topology::{Communicator, SimpleCommunicator};
use mpi::traits::Equivalence;
use rsf_ranks::{check_all_gather, HaloMessage, RankGroup};

use crate::Partition;

/// The one tag of every halo message: the exchanges of a pair of ranks are told apart by
/// their order (MPI keeps the messages of one sender, tag and communicator in order).
const TAG: i32 = 57;

/// The processes of `MPI_COMM_WORLD` as the ranks of a distributed sweep
/// (`rsf_ranks::DistributedSweep`).
///
/// Each exchange posts one `MPI_Irecv` per received message and one `MPI_Isend` per sent
/// message, then waits for all of them: every rank posts all its messages before it waits,
/// so no order of the ranks deadlocks. Each all-gather (the gathers of the active blocks,
/// of the coarsest level and of the solution, the exact reductions) is one
/// `MPI_Allgatherv`. The messages go over a duplicate of the world communicator (made by
/// [`world`](Self::world)), so that they never meet another message of the program (the
/// fault ODE's all-gathers, a user's own). An exchange allocates nothing (its requests
/// live on the stack), nor does an all-gather once it has been called (its counts'
/// buffers are kept).
///
/// Drop it before MPI ends (before the `Universe` of [`crate::initialize`]): it frees its
/// communicator.
pub struct MpiExchange {
    comm: SimpleCommunicator,
    rank: usize,
    size: usize,
    partition: Partition,
}

impl std::fmt::Debug for MpiExchange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MpiExchange")
            .field("rank", &self.rank)
            .field("size", &self.size)
            .finish()
    }
}

impl MpiExchange {
    /// The ranks of `MPI_COMM_WORLD` (duplicated: `MPI_Comm_dup`, collective, so every
    /// rank calls it). MPI must be running ([`crate::initialize`]).
    pub fn world() -> Self {
        let comm = SimpleCommunicator::world().duplicate();
        let rank = usize::try_from(comm.rank()).expect("MPI ranks are not negative");
        let size = usize::try_from(comm.size()).expect("MPI sizes are positive");
        Self {
            comm,
            rank,
            size,
            partition: Partition::default(),
        }
    }

    /// The communicator of the halo messages (for a program's own collectives among the
    /// same ranks: barriers, gathers).
    pub fn communicator(&self) -> &SimpleCommunicator {
        &self.comm
    }
}

impl RankGroup for MpiExchange {
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

    /// `MPI_Allgatherv` on the exchange's communicator: the trait's result, in one
    /// collective (MPI's algorithm: a ring, recursive doubling or Bruck's, by the sizes).
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

/// [`RankGroup::exchange`] on `comm`, whose rank and size the caller holds
/// (`rank_size`: read once when it was made, not per exchange): one `MPI_Irecv` per received message and one
/// `MPI_Isend` per sent message, then a wait for all of them (every rank posts all its
/// messages before it waits, so no order of the ranks deadlocks; the requests live on the
/// stack: nothing is allocated).
///
/// # Panics
/// As [`MpiExchange`]'s `exchange`.
pub(crate) fn exchange_on(
    comm: &SimpleCommunicator,
    (rank, size): (usize, usize),
    sends: &[HaloMessage],
    send: &[f64],
    recvs: &[HaloMessage],
    recv: &mut [f64],
) {
    for m in sends.iter().chain(recvs) {
        assert!(
            m.rank < size && m.rank != rank,
            "rank {rank} cannot exchange with rank {} of {size}",
            m.rank
        );
    }
    mpi::request::scope(|scope| {
        receive(scope, comm, recvs, recv, 0, &|| {
            post(scope, comm, sends, send)
        })
    });
}

/// Posts the receives of `recvs` (whose ranges start at or after `offset`, the start of
/// `buf` in the receive buffer), then runs `then` (the sends), then waits for the
/// receives. Recursive so that every request lives on the stack until it is waited for.
fn receive<'a>(
    scope: &LocalScope<'a>,
    comm: &SimpleCommunicator,
    recvs: &[HaloMessage],
    buf: &'a mut [f64],
    offset: usize,
    then: &dyn Fn(),
) {
    let Some((m, rest)) = recvs.split_first() else {
        then();
        return;
    };
    assert!(
        m.start >= offset,
        "receive ranges must be increasing and disjoint"
    );
    let (mine, tail) = buf[m.start - offset..].split_at_mut(m.len);
    let request = comm
        .process_at_rank(m.rank as i32)
        .immediate_receive_into_with_tag(scope, mine, TAG);
    receive(scope, comm, rest, tail, m.start + m.len, then);
    let status = request.wait();
    let count = status.count(f64::equivalent_datatype());
    assert_eq!(
        count as usize,
        m.len,
        "rank {} expected {} values from rank {}",
        comm.rank(),
        m.len,
        m.rank
    );
}

/// Posts the sends of `sends` from `buf`, then waits for them (recursive, as [`receive`]).
fn post<'a>(
    scope: &LocalScope<'a>,
    comm: &SimpleCommunicator,
    sends: &[HaloMessage],
    buf: &'a [f64],
) {
    let Some((m, rest)) = sends.split_first() else {
        return;
    };
    let request =
        comm.process_at_rank(m.rank as i32)
            .immediate_send_with_tag(scope, &buf[m.range()], TAG);
    post(scope, comm, rest, buf);
    request.wait();
}
