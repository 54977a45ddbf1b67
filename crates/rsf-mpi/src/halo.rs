//! The halo exchange of [`MpiRanks`](crate::MpiRanks)' [`RankGroup`] by nonblocking
//! point-to-point messages ([`exchange_on`]).

use mpi::point_to_point::{Destination, Source};
use mpi::request::LocalScope;
use mpi::topology::{Communicator, SimpleCommunicator};
use mpi::traits::Equivalence;
use rsf_ranks::HaloMessage;
#[cfg(doc)]
use rsf_ranks::RankGroup;

/// The one tag of every halo message: the exchanges of a pair of ranks are told apart by
/// their order (MPI keeps the messages of one sender, tag and communicator in order).
const TAG: i32 = 57;

/// [`RankGroup::exchange`] on `comm`, whose rank and size the caller holds
/// (`rank_size`: read once when it was made, not per exchange): one `MPI_Irecv` per received message and one
/// `MPI_Isend` per sent message, then a wait for all of them (every rank posts all its
/// messages before it waits, so no order of the ranks deadlocks; the requests live on the
/// stack: nothing is allocated).
///
/// # Panics
/// As [`MpiRanks`](crate::MpiRanks)' `exchange`.
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
