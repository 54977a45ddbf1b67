//! The all-gather of the nonlinear blocks' values: every rank contributes the blocks of its
//! owned active nodes to one collective, so that every rank holds the values of all active
//! blocks (the fault is a surface: few values) in their places of a global vector.

use rsf_ranks::block::{load, store};
use rsf_ranks::halo::{AllGather, HaloCounters};
use rsf_ranks::{LocalRows, RankGroup};

/// One rank's all-gather over the active blocks of a nonlinearity (`D` values per block).
#[derive(Debug, Clone)]
pub(crate) struct ActiveGather<const D: usize> {
    /// The active nodes (global, increasing) this gather was made for.
    active: Vec<usize>,
    /// `(local node, position k)` of the active nodes the rank holds (owned and ghosts).
    local: Vec<(u32, u32)>,
    /// The positions of the active nodes the rank owns, with their local nodes.
    owned: Vec<(u32, u32)>,
    all: AllGather,
    /// The compact vector (`D` per active block) the gather fills.
    compact: Vec<f64>,
}

impl<const D: usize> ActiveGather<D> {
    /// The gather of rank `rows.rank()` of `size` over the nodes `active` (global,
    /// increasing), node `p` owned by `owner[p]`.
    pub fn new(active: &[usize], rows: &LocalRows<D>, owner: &[usize], size: usize) -> Self {
        let rank = rows.rank();
        let mut position = vec![u32::MAX; owner.len()];
        for (k, &p) in active.iter().enumerate() {
            position[p] = k as u32;
        }
        let local: Vec<(u32, u32)> = rows
            .global_nodes()
            .iter()
            .enumerate()
            .filter(|&(_, &g)| position[g] != u32::MAX)
            .map(|(q, &g)| (q as u32, position[g]))
            .collect();
        let owned = local
            .iter()
            .copied()
            .filter(|&(q, _)| (q as usize) < rows.owned())
            .collect();
        let owners: Vec<usize> = active.iter().map(|&p| owner[p]).collect();
        Self {
            active: active.to_vec(),
            local,
            owned,
            compact: vec![0.0; D * active.len()],
            all: AllGather::new(&owners, rank, size, D),
        }
    }

    /// The active nodes this gather was made for.
    pub fn active(&self) -> &[usize] {
        &self.active
    }

    /// Gathers: every active block of the local vector `x` owned by some rank into its
    /// place in the global vector `global` (`D` per node; the other entries are left
    /// alone), on every rank. Collective.
    pub fn gather<H: RankGroup + ?Sized>(
        &mut self,
        x: &[f64],
        global: &mut [f64],
        halo: &mut H,
        counters: &mut HaloCounters,
    ) {
        for &(q, k) in &self.owned {
            store(&mut self.compact, k as usize, &load::<D>(x, q as usize));
        }
        self.all.gather(&mut self.compact, halo, counters);
        for (k, &p) in self.active.iter().enumerate() {
            store(global, p, &load::<D>(&self.compact, k));
        }
    }

    /// Copies the active blocks of the global vector `global` into the local vector `x`,
    /// on every local node (owned and ghost) that is active.
    pub fn scatter(&self, global: &[f64], x: &mut [f64]) {
        for &(q, k) in &self.local {
            let p = self.active[k as usize];
            store(x, q as usize, &load::<D>(global, p));
        }
    }

    /// What one gather sends: one collective, the rank's owned active blocks' values.
    pub fn per_gather(&self) -> HaloCounters {
        self.all.per_gather()
    }
}
