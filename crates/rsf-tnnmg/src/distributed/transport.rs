//! What a distributed sweep needs of its transport: one exchange of f64 buffers with the
//! neighbour ranks ([`HaloExchange`]), and an implementation over threads of one process
//! ([`ThreadExchange`]).

use std::sync::mpsc::{channel, Receiver, Sender};

/// One message of a [`HaloExchange::exchange`]: `len` values starting at `start` of the
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

/// The ranks of a distributed sweep as its halo exchanges see them: an MPI communicator
/// (to be implemented in the `rsf-mpi` crate), or threads of one process
/// ([`ThreadExchange`]).
///
/// Every rank calls [`exchange`](Self::exchange) the same number of times; the `k`-th
/// calls of all ranks form one exchange, whose messages were agreed in advance (a halo
/// plan that every rank derives from the same global data): a message from rank `s` to
/// rank `r` in `s`'s `k`-th call is received by `r`'s `k`-th call, whose `recvs` has an
/// entry from `s` of the same length. An implementation only moves numbers.
pub trait HaloExchange {
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
}

/// Threads of one process as ranks: one channel per ordered pair of ranks, each message a
/// copied `Vec<f64>` (the channels keep the messages of one pair in order, so a rank may
/// run ahead by any number of exchanges and none needs a barrier).
///
/// Public (not only in this crate's tests) so that tests of other crates can run the
/// distributed sweep on several ranks without MPI and compare with one process; it
/// allocates one vector per message and is not meant for production runs, which use MPI.
#[derive(Debug)]
pub struct ThreadExchange {
    rank: usize,
    /// `to[r]` sends to rank `r`.
    to: Vec<Sender<Vec<f64>>>,
    /// `from[s]` receives from rank `s`.
    from: Vec<Receiver<Vec<f64>>>,
}

impl ThreadExchange {
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
}

impl HaloExchange for ThreadExchange {
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
        let results: Vec<Vec<f64>> = std::thread::scope(|s| {
            let handles: Vec<_> = ThreadExchange::group(3)
                .into_iter()
                .map(|mut t| {
                    s.spawn(move || {
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
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
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
}
