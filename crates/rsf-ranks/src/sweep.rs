//! The multi-colour block Gauss–Seidel sweep of one rank with a halo exchange per colour.

use faer::sparse::SparseColMatRef;

use crate::block::store;
use crate::bsr::BlockCsr;
use crate::colouring::Colouring;
use crate::error::{Error, Result};
use crate::halo::{exchange_round, HaloCounters, HaloPlan};
use crate::local_rows::LocalRows;
use crate::transport::RankGroup;
use rsf_linalg::ProblemError;

/// One rank's part of a multi-colour block Gauss–Seidel sweep on distributed memory: its
/// rows ([`LocalRows`]), its owned nodes of each colour, the halo plan and the exchange
/// buffers.
///
/// A sweep runs over the colours of a global [`Colouring`] (computed the same on every
/// rank, from the whole matrix for now; a later phase computes it from the rank's part):
/// per colour it updates the rank's owned nodes of that colour, then exchanges with each
/// neighbour rank the new values of the owned nodes of that colour that are ghosts there.
/// A colour's nodes are not coupled, so each update reads only values of other colours,
/// which are current on every rank (owned, or ghosts refreshed by the exchange after their
/// colour): the iterate is the one-process coloured sweep's
/// ([`Colouring`]'s order), with the same bits at every rank count when each node's update
/// is the same arithmetic on the same numbers (rows summed in global column order, as
/// [`LocalRows::neighbours`] gives them).
///
/// Allocation-free after set-up (the transport may allocate: [`RankGroup`]).
#[derive(Debug, Clone)]
pub struct DistributedSweep<const D: usize> {
    rows: LocalRows<D>,
    /// Colour `c`'s owned local nodes are `colour_nodes[colour_ptr[c]..colour_ptr[c + 1]]`,
    /// increasing.
    colour_ptr: Vec<usize>,
    colour_nodes: Vec<u32>,
    plan: HaloPlan,
    send: Vec<f64>,
    recv: Vec<f64>,
    counters: HaloCounters,
}

impl<const D: usize> DistributedSweep<D> {
    /// The sweep of rank `halo.rank()` of `halo.size()` on the symmetric-pattern matrix `a`
    /// (`D n × D n`, node-major), node `p` owned by rank `owner[p]` (length `n`), in the
    /// order of `colouring` (a colouring of `a`'s node graph, the same on every rank).
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] as [`Colouring::new`]; [`ProblemError::DimensionMismatch`]
    /// if `owner` or `colouring` does not have one entry per node; [`Error::InvalidPartition`] if
    /// an owner is not a rank of `halo` or `colouring` gives two adjacent nodes the same colour (a
    /// colouring of another matrix).
    pub fn new<H: RankGroup + ?Sized>(
        a: SparseColMatRef<'_, usize, f64>,
        owner: &[usize],
        colouring: &Colouring,
        halo: &H,
    ) -> Result<Self> {
        Self::of_blocks(&BlockCsr::<D>::from_symmetric(a)?, owner, colouring, halo)
    }

    /// [`new`](Self::new) of a block matrix.
    pub fn of_blocks<H: RankGroup + ?Sized>(
        a: &BlockCsr<D>,
        owner: &[usize],
        colouring: &Colouring,
        halo: &H,
    ) -> Result<Self> {
        let size = halo.size();
        if let Some(p) = owner.iter().position(|&r| r >= size) {
            return Err(Error::InvalidPartition(format!(
                "node {p} is owned by rank {}, but there are {size} ranks",
                owner[p]
            )));
        }
        ProblemError::check_length(
            "colouring (one colour per node)",
            a.nodes(),
            colouring.num_nodes(),
        )?;
        Self::of_rows(LocalRows::of_blocks(a, owner, halo.rank())?, colouring)
    }

    /// The sweep on a rank's rows `rows` (of a matrix with `colouring.num_nodes()`
    /// nodes) in the order of `colouring`.
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] if `colouring` does not colour the rows' matrix;
    /// [`Error::InvalidPartition`] if it gives two adjacent nodes the same colour.
    pub fn of_rows(rows: LocalRows<D>, colouring: &Colouring) -> Result<Self> {
        if rows
            .global_nodes()
            .iter()
            .any(|&p| p >= colouring.num_nodes())
        {
            return Err(ProblemError::DimensionMismatch {
                what: "colouring (one colour per node)",
                expected: rows.global_nodes().iter().max().map_or(0, |&p| p + 1),
                got: colouring.num_nodes(),
            }
            .into());
        }
        let global = rows.global_nodes();
        for p in 0..rows.owned() {
            let c = colouring.colour_of(global[p]);
            if let Some((q, _)) = rows
                .neighbours(p)
                .find(|&(q, _)| colouring.colour_of(global[q]) == c)
            {
                return Err(Error::InvalidPartition(format!(
                    "adjacent nodes {} and {} have the same colour {c}",
                    global[p], global[q]
                )));
            }
        }
        let colours = colouring.num_colours();
        let mut colour_ptr = vec![0usize; colours + 1];
        for &p in &global[..rows.owned()] {
            colour_ptr[colouring.colour_of(p) + 1] += 1;
        }
        for c in 0..colours {
            colour_ptr[c + 1] += colour_ptr[c];
        }
        let mut next = colour_ptr.clone();
        let mut colour_nodes = vec![0u32; rows.owned()];
        for (l, &p) in global[..rows.owned()].iter().enumerate() {
            let c = colouring.colour_of(p);
            colour_nodes[next[c]] = l as u32;
            next[c] += 1;
        }
        let plan = HaloPlan::new(&rows, colouring);
        Ok(Self::with_plan(rows, colour_ptr, colour_nodes, plan))
    }

    fn with_plan(
        rows: LocalRows<D>,
        colour_ptr: Vec<usize>,
        colour_nodes: Vec<u32>,
        plan: HaloPlan,
    ) -> Self {
        let (send, recv) = plan.max_round_nodes();
        Self {
            rows,
            colour_ptr,
            colour_nodes,
            plan,
            send: vec![0.0; D * send],
            recv: vec![0.0; D * recv],
            counters: HaloCounters::default(),
        }
    }

    /// The rank's rows and local numbering.
    pub fn rows(&self) -> &LocalRows<D> {
        &self.rows
    }

    /// The rank's rows, to change their values (not their pattern).
    pub fn rows_mut(&mut self) -> &mut LocalRows<D> {
        &mut self.rows
    }

    /// Number of colours (exchanges per sweep).
    pub fn num_colours(&self) -> usize {
        self.colour_ptr.len() - 1
    }

    /// The owned local nodes of colour `c`, increasing.
    ///
    /// # Panics
    /// If `c ≥ num_colours()`.
    pub fn colour(&self, c: usize) -> &[u32] {
        &self.colour_nodes[self.colour_ptr[c]..self.colour_ptr[c + 1]]
    }

    /// The neighbour ranks (those this rank exchanges with), increasing.
    pub fn neighbour_ranks(&self) -> impl Iterator<Item = usize> + '_ {
        self.plan.peers.iter().map(|p| p.rank)
    }

    /// What the rank has sent since set-up (or [`reset_counters`](Self::reset_counters)).
    pub fn counters(&self) -> HaloCounters {
        self.counters
    }

    /// Sets the counters to zero.
    pub fn reset_counters(&mut self) {
        self.counters = HaloCounters::default();
    }

    /// What one sweep sends by the plan: one exchange per colour, its messages and values
    /// (`sweeps` = 1).
    pub fn per_sweep(&self) -> HaloCounters {
        let colours = &self.plan.rounds[..self.num_colours()];
        HaloCounters {
            sweeps: 1,
            exchanges: colours.len() as u64,
            messages: colours.iter().map(|r| r.sends.len() as u64).sum(),
            values: colours
                .iter()
                .map(|r| (D * r.send_nodes.len()) as u64)
                .sum(),
            ..HaloCounters::default()
        }
    }

    /// What one ghost update ([`update_ghosts`](Self::update_ghosts)) sends by the plan: one
    /// exchange, its messages and values (`sweeps` = 0).
    pub fn per_ghost_update(&self) -> HaloCounters {
        self.plan.rounds[self.num_colours()].counters::<D>()
    }

    /// Refreshes every ghost of `x` (a local vector, `D · rows().len()` values) from its
    /// owner: one exchange of all the owned values that are ghosts elsewhere (before the
    /// first sweep, or after the owned values changed outside a sweep). Collective.
    ///
    /// # Panics
    /// If `x` has the wrong length or `halo` is another rank's.
    pub fn update_ghosts<H: RankGroup + ?Sized>(&mut self, x: &mut [f64], halo: &mut H) {
        self.check(x, halo);
        let full = self.num_colours();
        self.exchange(x, full, halo);
    }

    /// One sweep over the colours (increasing, or decreasing when `reverse`) of the local
    /// vector `x` (`D · rows().len()` values, its ghosts current): for every owned node `p`
    /// of a colour (a local index, increasing), `update(rows, p, x)` returns its new block
    /// from `x` and it is stored (`rows` = [`rows`](Self::rows), for the update's row sum);
    /// then one exchange sends the colour's new values to the ranks where they are ghosts.
    /// Afterwards every owned and ghost value is current. Collective: every rank sweeps in
    /// the same direction.
    ///
    /// # Panics
    /// If `x` has the wrong length or `halo` is another rank's.
    pub fn sweep<H, F>(&mut self, x: &mut [f64], reverse: bool, halo: &mut H, mut update: F)
    where
        H: RankGroup + ?Sized,
        F: FnMut(&LocalRows<D>, usize, &[f64]) -> [f64; D],
    {
        self.check(x, halo);
        let colours = self.num_colours();
        for k in 0..colours {
            let c = if reverse { colours - 1 - k } else { k };
            for &p in &self.colour_nodes[self.colour_ptr[c]..self.colour_ptr[c + 1]] {
                let xp = update(&self.rows, p as usize, x);
                store(x, p as usize, &xp);
            }
            self.exchange(x, c, halo);
        }
        self.counters.sweeps += 1;
    }

    /// The exchange of the plan's round `round` (a colour's, or the full one of a ghost
    /// update) on the local vector `x`.
    fn exchange<H: RankGroup + ?Sized>(&mut self, x: &mut [f64], round: usize, halo: &mut H) {
        exchange_round::<D, H>(
            &self.plan.rounds[round],
            x,
            halo,
            &mut self.send,
            &mut self.recv,
            &mut self.counters,
        );
    }

    /// Lengths and ranks agree with the set-up.
    fn check<H: RankGroup + ?Sized>(&self, x: &[f64], halo: &H) {
        assert_eq!(x.len(), D * self.rows.len(), "local vector length");
        assert_eq!(
            halo.rank(),
            self.rows.rank(),
            "the transport of another rank"
        );
    }

    /// The same sweep with a wrong plan: `node` (global) dropped from the halo.
    #[cfg(test)]
    pub(crate) fn without_halo_node(&self, colouring: &Colouring, node: usize) -> Self {
        let plan = self.plan.without_node(&self.rows, colouring, node);
        Self::with_plan(
            self.rows.clone(),
            self.colour_ptr.clone(),
            self.colour_nodes.clone(),
            plan,
        )
    }
}
