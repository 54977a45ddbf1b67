//! Fresh groups of the same thread ranks, handed out in order: the thread-rank
//! [`TransportFactory`].

use std::sync::{Arc, Mutex};

use crate::{ThreadRanks, TransportFactory};

/// Groups of `size` thread ranks made on demand: the `k`-th call of rank `r`
/// ([`take`](Self::take), or its [`factory`](Self::factory)) returns rank `r`'s end of the
/// `k`-th group, so that ranks which make their calls in the same order (every rank builds
/// its solvers, operators and observers alike) meet in one group per call — what MPI's
/// duplicated communicators give, for tests on threads.
#[derive(Debug)]
pub struct ThreadGroups {
    size: usize,
    made: Mutex<Made>,
}

/// The groups made so far and what each rank has taken of them.
#[derive(Debug)]
struct Made {
    /// Per rank, the number of ends it has taken.
    taken: Vec<usize>,
    /// Per group, each rank's end until it is taken.
    groups: Vec<Vec<Option<ThreadRanks>>>,
}

impl ThreadGroups {
    /// Groups of `size` ranks (none made yet).
    ///
    /// # Panics
    /// If `size == 0`.
    pub fn new(size: usize) -> Arc<Self> {
        assert!(size > 0, "a group of ranks has at least one rank");
        Arc::new(Self {
            size,
            made: Mutex::new(Made {
                taken: vec![0; size],
                groups: Vec::new(),
            }),
        })
    }

    /// The number of ranks of every group.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Rank `rank`'s end of its next group.
    ///
    /// # Panics
    /// If `rank ≥ size`.
    pub fn take(&self, rank: usize) -> ThreadRanks {
        assert!(rank < self.size, "rank {rank} of {}", self.size);
        let mut made = self.made.lock().unwrap_or_else(|e| e.into_inner());
        let k = made.taken[rank];
        made.taken[rank] += 1;
        while made.groups.len() <= k {
            let group = ThreadRanks::group(self.size)
                .into_iter()
                .map(Some)
                .collect();
            made.groups.push(group);
        }
        made.groups[k][rank].take().expect("each end is taken once")
    }

    /// Rank `rank`'s transport factory: each call [`take`](Self::take)s its next group.
    pub fn factory(self: &Arc<Self>, rank: usize) -> TransportFactory {
        let groups = Arc::clone(self);
        Arc::new(move || Box::new(groups.take(rank)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two ranks take two groups each in the same order, on their own threads: each
    /// all-gather meets its own group's partner (the values say which group).
    #[test]
    fn the_kth_call_of_every_rank_meets_in_the_kth_group() {
        let groups = ThreadGroups::new(2);
        let results: Vec<Vec<f64>> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..2)
                .map(|rank| {
                    let factory = groups.factory(rank);
                    s.spawn(move || {
                        let mut out = Vec::new();
                        for k in 0..2 {
                            let mut g = factory();
                            assert_eq!((g.rank(), g.size()), (rank, 2));
                            let mut all = [0.0; 2];
                            g.all_gather(&[(10 * k + rank) as f64], &[1, 1], &mut all);
                            out.extend(all);
                        }
                        out
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for r in results {
            assert_eq!(r, [0.0, 1.0, 10.0, 11.0]);
        }
    }
}
