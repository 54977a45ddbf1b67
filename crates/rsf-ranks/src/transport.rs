//! What processes that share work need of their transport: one exchange of f64 buffers
//! with the neighbour ranks ([`RankGroup::exchange`]) and an all-gather of every rank's
//! values ([`RankGroup::all_gather`], by default made of one exchange), and an
//! implementation over threads of one process ([`ThreadRanks`]).

use std::sync::mpsc::{channel, Receiver, Sender};

/// One message of a [`RankGroup::exchange`]: `len` values starting at `start` of the
/// send (or receive) buffer, to (or from) rank `rank`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HaloMessage {
    /// The other rank (never the caller's own).
    pub rank: usize,
    /// First value of the message in the buffer.
    pub start: usize,
    /// Number of values (≥ 1: empty messages are never sent).
    pub len: usize,
}

impl HaloMessage {
    /// The message's values in its buffer: `start..start + len`.
    pub fn range(&self) -> std::ops::Range<usize> {
        self.start..self.start + self.len
    }
}

/// A group of processes ("ranks") that share work, as its exchanges see them: an MPI
/// communicator (in the `rsf-mpi` crate), or threads of one process ([`ThreadRanks`]).
/// The one transport of the workspace: the fault ODE's shared evaluations and VTU pieces
/// (all-gathers, crate `rsf`) and TNNMG's distributed solves (halo exchanges, all-gathers
/// and exact sums, crate `rsf-tnnmg`) take it.
///
/// Every rank calls [`exchange`](Self::exchange) the same number of times; the `k`-th
/// calls of all ranks form one exchange, whose messages were agreed in advance (a halo
/// plan that every rank derives from the same global data): a message from rank `s` to
/// rank `r` in `s`'s `k`-th call is received by `r`'s `k`-th call, whose `recvs` has an
/// entry from `s` of the same length. The same holds for [`all_gather`](Self::all_gather):
/// every rank makes its `k`-th all-gather call with the same counts, in the same order
/// relative to its exchanges. An implementation only moves numbers.
pub trait RankGroup {
    /// This process's rank, in `0..size()`.
    fn rank(&self) -> usize;

    /// The number of ranks (≥ 1).
    fn size(&self) -> usize;

    /// Sends, for every `m` of `sends`, `send[m.range()]` to rank `m.rank`, and receives,
    /// for every `m` of `recvs`, rank `m.rank`'s message into `recv[m.range()]`; returns
    /// when every message of `recvs` has arrived and `send` may be reused. Each list names
    /// a rank at most once and never the caller; no message is empty. Collective among
    /// the ranks that exchange messages (see the trait's documentation).
    ///
    /// # Panics
    /// If a range is outside its buffer, or (may panic, or end the job) if the transport
    /// fails or a message does not have the agreed length: a rank that cannot reach its
    /// neighbours has no answer to give.
    fn exchange(
        &mut self,
        sends: &[HaloMessage],
        send: &[f64],
        recvs: &[HaloMessage],
        recv: &mut [f64],
    );

    /// The all-gather of a variable number of values per rank: rank `r` contributes
    /// `counts[r]` values (this rank its `send`), and every rank's `recv` becomes the
    /// concatenation of all contributions in rank order, rank `r`'s at
    /// `counts[..r].iter().sum()`. Collective: every rank calls it with the same `counts`
    /// (see the trait's documentation). A count may be zero.
    ///
    /// The default implementation is one [`exchange`](Self::exchange): the caller's values
    /// to every other rank (if it has any), every other rank's non-empty contribution into
    /// its place of `recv`, the caller's own copied there (`size − 1` messages per rank
    /// that contributes; it allocates the two message lists). A transport with a collective
    /// of its own (MPI's `MPI_Allgatherv`) overrides it; the result is the same values.
    ///
    /// # Panics
    /// If `counts.len() != size()`, `send.len() != counts[rank()]` or
    /// `recv.len() != counts.iter().sum()`; as [`exchange`](Self::exchange) if the
    /// transport fails or the ranks' counts disagree.
    fn all_gather(&mut self, send: &[f64], counts: &[usize], recv: &mut [f64]) {
        let rank = self.rank();
        check_all_gather(rank, self.size(), send, counts, recv);
        let (mut sends, mut recvs) = (Vec::new(), Vec::new());
        let mut start = 0;
        for (r, &len) in counts.iter().enumerate() {
            if r == rank {
                recv[start..start + len].copy_from_slice(send);
            } else {
                if len > 0 {
                    recvs.push(HaloMessage {
                        rank: r,
                        start,
                        len,
                    });
                }
                if !send.is_empty() {
                    sends.push(HaloMessage {
                        rank: r,
                        start: 0,
                        len: send.len(),
                    });
                }
            }
            start += len;
        }
        self.exchange(&sends, send, &recvs, recv);
    }
}

/// Checks the shapes of rank `rank`'s [`all_gather`](RankGroup::all_gather) among
/// `size` ranks (for the trait's default and for transports that override it).
///
/// # Panics
/// If `counts.len() != size`, `send.len() != counts[rank]` or
/// `recv.len() != counts.iter().sum()`.
pub fn check_all_gather(rank: usize, size: usize, send: &[f64], counts: &[usize], recv: &[f64]) {
    assert_eq!(counts.len(), size, "all_gather: one count per rank");
    assert_eq!(send.len(), counts[rank], "all_gather: rank {rank}'s count");
    let total: usize = counts.iter().sum();
    assert_eq!(recv.len(), total, "all_gather: the sum of the counts");
}

/// Threads of one process as ranks: one channel per ordered pair of ranks, each message a
/// copied `Vec<f64>` (the channels keep the messages of one pair in order, so a rank may
/// run ahead by any number of exchanges and none needs a barrier).
///
/// Public (not only in this crate's tests) so that tests of other crates can run the
/// distributed sweep on several ranks without MPI and compare with one process; it
/// allocates one vector per message and is not meant for production runs, which use MPI.
#[derive(Debug)]
pub struct ThreadRanks {
    rank: usize,
    /// `to[r]` sends to rank `r`.
    to: Vec<Sender<Vec<f64>>>,
    /// `from[s]` receives from rank `s`.
    from: Vec<Receiver<Vec<f64>>>,
}

impl ThreadRanks {
    /// The `size` ranks of one group, in rank order: give each to its own thread.
    ///
    /// # Panics
    /// If `size == 0`.
    pub fn group(size: usize) -> Vec<Self> {
        assert!(size > 0, "a group of ranks has at least one rank");
        // channels[s][r] carries the messages from s to r.
        let mut senders: Vec<Vec<Sender<Vec<f64>>>> = Vec::with_capacity(size);
        let mut receivers: Vec<Vec<Option<Receiver<Vec<f64>>>>> = (0..size)
            .map(|_| (0..size).map(|_| None).collect())
            .collect();
        for s in 0..size {
            let mut to = Vec::with_capacity(size);
            for receiving in receivers.iter_mut() {
                let (tx, rx) = channel();
                to.push(tx);
                receiving[s] = Some(rx);
            }
            senders.push(to);
        }
        senders
            .into_iter()
            .zip(receivers)
            .enumerate()
            .map(|(rank, (to, from))| Self {
                rank,
                to,
                from: from
                    .into_iter()
                    .map(|r| r.expect("every pair has a channel"))
                    .collect(),
            })
            .collect()
    }

    /// Runs `run` on every rank of a new group of `size` ([`group`](Self::group)), each
    /// rank on a scoped thread of its own, and returns the results in rank order: how a
    /// test runs a computation on several ranks without MPI.
    ///
    /// # Panics
    /// If `size == 0`; with the panic of a rank whose `run` panicked (the lowest such rank;
    /// the other ranks' threads end when their partner's channels close).
    pub fn run<T: Send>(size: usize, run: impl Fn(Self) -> T + Sync) -> Vec<T> {
        on_threads(Self::group(size), run)
    }
}

/// Runs `run` on every one of `ranks`, each on a scoped thread of its own, and returns the
/// results in the order of `ranks` ([`ThreadRanks::run`],
/// [`ThreadProcess::run`](crate::ThreadProcess::run)).
///
/// # Panics
/// With the panic of a rank whose `run` panicked (the first such rank in order).
pub(crate) fn on_threads<R: Send, T: Send>(ranks: Vec<R>, run: impl Fn(R) -> T + Sync) -> Vec<T> {
    let run = &run;
    std::thread::scope(|s| {
        let handles: Vec<_> = ranks
            .into_iter()
            .map(|rank| s.spawn(move || run(rank)))
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    })
}

impl RankGroup for ThreadRanks {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.to.len()
    }

    fn exchange(
        &mut self,
        sends: &[HaloMessage],
        send: &[f64],
        recvs: &[HaloMessage],
        recv: &mut [f64],
    ) {
        for m in sends {
            assert_ne!(m.rank, self.rank, "a rank sends no message to itself");
            self.to[m.rank]
                .send(send[m.range()].to_vec())
                .expect("the receiving rank's thread is running");
        }
        for m in recvs {
            assert_ne!(m.rank, self.rank, "a rank receives no message from itself");
            let message = self.from[m.rank]
                .recv()
                .expect("the sending rank's thread is running");
            assert_eq!(
                message.len(),
                m.len,
                "rank {} expected {} values from rank {}",
                self.rank,
                m.len,
                m.rank
            );
            recv[m.range()].copy_from_slice(&message);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three ranks in a ring, three exchanges of different lengths: each message arrives
    /// at its rank, in order, where its receive entry puts it.
    #[test]
    fn thread_ranks_exchange_in_order() {
        let results: Vec<Vec<f64>> = ThreadRanks::run(3, |mut t| {
            let (r, n) = (t.rank(), t.size());
            let (next, prev) = ((r + 1) % n, (r + n - 1) % n);
            let mut got = Vec::new();
            for round in 0..3 {
                let send = [r as f64, round as f64, 7.0];
                let len = 1 + round;
                let mut recv = [-1.0; 4];
                let to = [HaloMessage {
                    rank: next,
                    start: 0,
                    len,
                }];
                let from = [HaloMessage {
                    rank: prev,
                    start: 1,
                    len,
                }];
                t.exchange(&to, &send, &from, &mut recv);
                got.extend_from_slice(&recv);
            }
            got
        });
        for (r, got) in results.iter().enumerate() {
            let p = ((r + 2) % 3) as f64;
            let want = [
                [-1.0, p, -1.0, -1.0],
                [-1.0, p, 1.0, -1.0],
                [-1.0, p, 2.0, 7.0],
            ];
            assert_eq!(got, &want.concat(), "rank {r}");
        }
    }

    /// The default all-gather on groups of 1–4 thread ranks, with uneven counts (some
    /// zero, the caller's own among them) and three gathers in a row: every rank's result
    /// is the concatenation of the contributions in rank order, bit for bit (negative
    /// zero, a NaN payload and subnormals kept); exchanges in between still pair up.
    #[test]
    fn thread_ranks_all_gather_uneven_counts() {
        let value = |r: usize, round: usize, k: usize| match k % 4 {
            0 => -0.0,
            1 => f64::from_bits(0x7ff8_0000_0000_0000 | (100 * r + 10 * round + k) as u64),
            2 => f64::from_bits(1 + (r + round) as u64),
            _ => (100 * r + 10 * round + k) as f64 + 0.1,
        };
        for size in 1..=4 {
            let patterns: Vec<Vec<usize>> = vec![
                (0..size).map(|r| r + 1).collect(),
                (0..size)
                    .map(|r| if r % 2 == 0 { 0 } else { 3 * r })
                    .collect(),
                (0..size).map(|r| usize::from(r + 1 == size) * 5).collect(),
                vec![0; size],
            ];
            let results: Vec<Vec<Vec<u64>>> = ThreadRanks::run(size, |mut t| {
                let r = t.rank();
                let mut got = Vec::new();
                for (round, counts) in patterns.iter().enumerate() {
                    let send: Vec<f64> = (0..counts[r]).map(|k| value(r, round, k)).collect();
                    let mut recv = vec![7.0; counts.iter().sum()];
                    t.all_gather(&send, counts, &mut recv);
                    got.push(recv.iter().map(|x| x.to_bits()).collect());
                    // An exchange with no messages between the gathers.
                    t.exchange(&[], &[], &[], &mut []);
                }
                got
            });
            for (round, counts) in patterns.iter().enumerate() {
                let want: Vec<u64> = (0..size)
                    .flat_map(|r| (0..counts[r]).map(move |k| value(r, round, k).to_bits()))
                    .collect();
                for (r, got) in results.iter().enumerate() {
                    assert_eq!(got[round], want, "{size} ranks, rank {r}, gather {round}");
                }
            }
        }
    }

    /// A rank whose count disagrees with its values is refused.
    #[test]
    #[should_panic(expected = "rank 0's count")]
    fn all_gather_checks_the_own_count() {
        let mut t = ThreadRanks::group(1).pop().unwrap();
        t.all_gather(&[1.0], &[2], &mut [0.0; 2]);
    }
}
