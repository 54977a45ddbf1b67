//! The all-gather of a whole vector among the ranks that own its nodes
//! ([`NodeAllGather`]).

use crate::error::{Error, Result};
use crate::halo::{AllGather, HaloCounters};
use crate::transport::RankGroup;

/// The all-gather of a global vector of `D` values per node whose node `p` is computed by
/// rank `owner[p]`: after [`gather`](Self::gather) every rank holds every node's values as
/// their owner computed them (pure data movement: the same bits on every rank). What a
/// run whose ranks share the rows of an operator needs to keep its vectors whole and
/// replicated (e.g. the integrator's right-hand side on ranks, each rank computing its
/// owned rows). A collective object: every rank calls `gather` the same number of times.
pub struct NodeAllGather<const D: usize> {
    halo: Box<dyn RankGroup>,
    gather: AllGather,
    counters: HaloCounters,
}

impl<const D: usize> std::fmt::Debug for NodeAllGather<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NodeAllGather")
            .field("rank", &self.halo.rank())
            .field("size", &self.halo.size())
            .field("counters", &self.counters)
            .finish_non_exhaustive()
    }
}

impl<const D: usize> NodeAllGather<D> {
    /// The gather of rank `halo.rank()` for the owners `owner` (one rank per node, the
    /// same on every rank); it keeps `halo` for its gathers.
    ///
    /// # Errors
    /// [`Error::InvalidPartition`] if an owner is not a rank of `halo`.
    pub fn new(owner: &[usize], halo: Box<dyn RankGroup>) -> Result<Self> {
        let size = halo.size();
        if let Some(p) = owner.iter().position(|&r| r >= size) {
            return Err(Error::InvalidPartition(format!(
                "node {p} is owned by rank {} of {size}",
                owner[p]
            )));
        }
        Ok(Self {
            gather: AllGather::new(owner, halo.rank(), size, D),
            halo,
            counters: HaloCounters::default(),
        })
    }

    /// Fills every node of `x` (`D` values per node, node-major, the owners' length) that
    /// this rank does not own with its owner's values; the owned nodes are sent as they
    /// are. One collective ([`RankGroup::all_gather`]: one `MPI_Allgatherv` on MPI).
    /// Allocates nothing (the transport may).
    ///
    /// # Panics
    /// If `x` is not `D` values per node of the owner vector (an internal invariant of
    /// the caller), or as the transport's [`RankGroup::exchange`].
    pub fn gather(&mut self, x: &mut [f64]) {
        assert_eq!(x.len() % D, 0, "D values per node");
        self.gather.gather(x, &mut *self.halo, &mut self.counters);
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.halo.rank()
    }

    /// What the gathers so far sent from this rank.
    pub fn counters(&self) -> HaloCounters {
        self.counters
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ThreadRanks;

    /// The wrapper of `AllGather` (whose gathers halo.rs tests at 1–4 ranks): at 3 thread
    /// ranks, one owning nothing, every rank ends with every owner's values and counts
    /// one collective; a wrong owner is refused.
    #[test]
    fn every_rank_gets_every_owners_values() {
        let owner: Vec<usize> = (0..11).map(|p| (7 * p) % 2).collect();
        let got = ThreadRanks::run(3, |halo| {
            let rank = halo.rank();
            let mut g = NodeAllGather::<2>::new(&owner, Box::new(halo)).unwrap();
            let mut x: Vec<f64> = (0..22)
                .map(|i| {
                    if owner[i / 2] == rank {
                        i as f64
                    } else {
                        f64::NAN
                    }
                })
                .collect();
            g.gather(&mut x);
            (x, g.counters().collectives)
        });
        let want: Vec<f64> = (0..22).map(|i| i as f64).collect();
        for (r, (x, collectives)) in got.iter().enumerate() {
            assert_eq!(x, &want, "rank {r}");
            assert_eq!(*collectives, 1, "rank {r}");
        }
        let halo = ThreadRanks::group(2).pop().unwrap();
        assert!(matches!(
            NodeAllGather::<2>::new(&[0, 2], Box::new(halo)),
            Err(Error::InvalidPartition(_))
        ));
    }
}
