//! The halo plan of one rank: which owned nodes each neighbour rank needs, which ghosts
//! come from it, and the messages of each colour's exchange; one exchange of a plan's
//! round; the all-gather of a vector's owned values as one collective ([`AllGather`]);
//! and the counters of what was sent.

use std::collections::BTreeMap;
use std::ops::Range;

use crate::block::{load, store};
use crate::colouring::Colouring;
use crate::local_rows::LocalRows;
use crate::transport::{HaloMessage, RankGroup};

/// What one rank has sent, counted by the sweep (or the transfers, gathers, reductions) as
/// it hands the messages to the transport (the numbers a model of the communication cost
/// is fitted with): its point-to-point exchanges (halo messages to neighbour ranks) and
/// its collectives (all-gathers) apart. Bytes are `8 · values`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HaloCounters {
    /// Sweeps ([`DistributedSweep::sweep`](crate::DistributedSweep::sweep)).
    pub sweeps: u64,
    /// Exchanges (calls of [`RankGroup::exchange`], with or without messages of this
    /// rank: one per colour and sweep, one per ghost update, one per transfer).
    pub exchanges: u64,
    /// Point-to-point messages sent (none is empty).
    pub messages: u64,
    /// f64 values sent in point-to-point messages.
    pub values: u64,
    /// Collectives (calls of [`RankGroup::all_gather`]: the gathers of the active
    /// blocks, of the coarsest level and of the solution, and the exact reductions).
    pub collectives: u64,
    /// f64 values this rank contributed to its collectives (its own count in each; it
    /// receives every other rank's).
    pub collective_values: u64,
}

impl HaloCounters {
    /// Bytes handed to the transport: 8 per value, point-to-point and contributed to
    /// collectives.
    pub fn bytes(&self) -> u64 {
        8 * (self.values + self.collective_values)
    }

    /// Every count times `k` (what `k` repetitions of the counted work send).
    pub fn times(self, k: u64) -> Self {
        Self {
            sweeps: k * self.sweeps,
            exchanges: k * self.exchanges,
            messages: k * self.messages,
            values: k * self.values,
            collectives: k * self.collectives,
            collective_values: k * self.collective_values,
        }
    }
}

/// `sweeps/exchanges/messages/values/collectives/collective_values`, the form the
/// programs' rank lines print.
impl std::fmt::Display for HaloCounters {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}/{}/{}/{}/{}/{}",
            self.sweeps,
            self.exchanges,
            self.messages,
            self.values,
            self.collectives,
            self.collective_values
        )
    }
}

impl std::ops::Add for HaloCounters {
    type Output = Self;

    fn add(self, o: Self) -> Self {
        Self {
            sweeps: self.sweeps + o.sweeps,
            exchanges: self.exchanges + o.exchanges,
            messages: self.messages + o.messages,
            values: self.values + o.values,
            collectives: self.collectives + o.collectives,
            collective_values: self.collective_values + o.collective_values,
        }
    }
}

impl std::ops::AddAssign for HaloCounters {
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

/// What one rank exchanges with one neighbour rank (local node indices).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Peer {
    /// The neighbour rank.
    pub rank: usize,
    /// Owned nodes that are ghosts on `rank`, by (colour, global node).
    pub send: Vec<u32>,
    /// Ghosts owned by `rank`, by (colour, global node).
    pub recv: Vec<u32>,
}

/// The messages of one exchange: per neighbour rank (increasing) the nodes sent and
/// received, their values `D` per node in the buffers in the same order.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Round {
    /// The messages sent (in values of the send buffer).
    pub sends: Vec<HaloMessage>,
    /// Local nodes whose values fill the send buffer, in order.
    pub send_nodes: Vec<u32>,
    /// The messages received (in values of the receive buffer).
    pub recvs: Vec<HaloMessage>,
    /// Local nodes that the receive buffer's values go to, in order.
    pub recv_nodes: Vec<u32>,
}

impl Round {
    /// What one exchange of this round sends (`D` values per node): one exchange, its
    /// messages and values.
    pub fn counters<const D: usize>(&self) -> HaloCounters {
        HaloCounters {
            exchanges: 1,
            messages: self.sends.len() as u64,
            values: (D * self.send_nodes.len()) as u64,
            ..HaloCounters::default()
        }
    }
}

/// The halo plan of one rank ([`LocalRows`] with a global [`Colouring`]).
///
/// Per neighbour rank `r` (increasing): the owned nodes that are ghosts on `r` and the
/// ghosts that `r` owns, each list ordered by colour, then by global node. Both sides of a
/// pair derive the same list from the same global data (the pattern, the owners, the
/// colouring), so the messages need no negotiation: rank `s`'s list for `r` is rank `r`'s
/// list for `s`, in the same order. Round `c` (one per colour) sends the owned nodes of
/// colour `c` that are ghosts on each neighbour; the last round sends all of them (a full
/// ghost update). Empty messages are left out.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HaloPlan {
    /// The neighbour ranks, increasing.
    pub peers: Vec<Peer>,
    /// One round per colour, then the full update.
    pub rounds: Vec<Round>,
}

impl HaloPlan {
    /// The plan of `rows` (rank `rows.rank()`, its ghosts' owners) and the global
    /// `colouring`, for `D` values per node.
    pub fn new<const D: usize>(rows: &LocalRows<D>, colouring: &Colouring) -> Self {
        let global = rows.global_nodes();
        let owned = rows.owned();
        let mut peers: BTreeMap<usize, Peer> = BTreeMap::new();
        for (g, &r) in rows.ghost_owners().iter().enumerate() {
            peer(&mut peers, r).recv.push((owned + g) as u32);
        }
        // The ranks an owned node is a ghost on: the owners of its neighbours (the pattern
        // is symmetric), each once.
        let mut ranks = Vec::new();
        for p in 0..owned {
            ranks.clear();
            ranks.extend(
                rows.neighbours(p)
                    .filter(|&(q, _)| q >= owned)
                    .map(|(q, _)| rows.ghost_owners()[q - owned]),
            );
            ranks.sort_unstable();
            ranks.dedup();
            for &r in &ranks {
                peer(&mut peers, r).send.push(p as u32);
            }
        }
        let key = |&l: &u32| (colouring.colour_of(global[l as usize]), global[l as usize]);
        let mut peers: Vec<Peer> = peers.into_values().collect();
        for p in &mut peers {
            p.send.sort_unstable_by_key(key);
            p.recv.sort_unstable_by_key(key);
        }
        let mut plan = Self {
            peers,
            rounds: Vec::new(),
        };
        plan.make_rounds(
            D,
            |l| colouring.colour_of(global[l as usize]),
            colouring.num_colours(),
        );
        plan
    }

    /// The rounds of the peers' lists: one per colour (`colour_of` a local node's colour,
    /// `colours` of them), then the full update, `values` per node.
    pub fn make_rounds(&mut self, values: usize, colour_of: impl Fn(u32) -> usize, colours: usize) {
        let mut rounds = vec![Round::default(); colours + 1];
        for (c, round) in rounds.iter_mut().enumerate() {
            let keep = |l: &&u32| c == colours || colour_of(**l) == c;
            for p in &self.peers {
                add(
                    &mut round.sends,
                    &mut round.send_nodes,
                    p.rank,
                    p.send.iter().filter(keep),
                    values,
                );
                add(
                    &mut round.recvs,
                    &mut round.recv_nodes,
                    p.rank,
                    p.recv.iter().filter(keep),
                    values,
                );
            }
        }
        self.rounds = rounds;
    }

    /// Largest number of nodes sent and received in one round.
    pub fn max_round_nodes(&self) -> (usize, usize) {
        let max = |f: fn(&Round) -> usize| self.rounds.iter().map(f).max().unwrap_or(0);
        (max(|r| r.send_nodes.len()), max(|r| r.recv_nodes.len()))
    }

    /// Drops global node `node` from the plan (neither sent nor received any more): a
    /// wrong plan for the tests that must detect one.
    #[cfg(test)]
    pub(crate) fn without_node<const D: usize>(
        &self,
        rows: &LocalRows<D>,
        colouring: &Colouring,
        node: usize,
    ) -> Self {
        let global = rows.global_nodes();
        let mut plan = self.clone();
        for p in &mut plan.peers {
            p.send.retain(|&l| global[l as usize] != node);
            p.recv.retain(|&l| global[l as usize] != node);
        }
        plan.make_rounds(
            D,
            |l| colouring.colour_of(global[l as usize]),
            colouring.num_colours(),
        );
        plan
    }
}

/// The entry of neighbour rank `rank`, made empty if new.
fn peer(peers: &mut BTreeMap<usize, Peer>, rank: usize) -> &mut Peer {
    peers.entry(rank).or_insert_with(|| Peer {
        rank,
        send: Vec::new(),
        recv: Vec::new(),
    })
}

/// Appends one message to `rank` with `nodes` (if any) to a round's list.
fn add<'a>(
    messages: &mut Vec<HaloMessage>,
    list: &mut Vec<u32>,
    rank: usize,
    nodes: impl Iterator<Item = &'a u32>,
    values: usize,
) {
    let first = list.len();
    list.extend(nodes);
    if list.len() > first {
        messages.push(HaloMessage {
            rank,
            start: values * first,
            len: values * (list.len() - first),
        });
    }
}

/// One exchange of `round` on the local vector `x` (`D` values per local node): packs the
/// values of its send nodes into `send`, exchanges, unpacks `recv` into its receive nodes;
/// counts the exchange, its messages and values in `counters`.
pub fn exchange_round<const D: usize, H: RankGroup + ?Sized>(
    round: &Round,
    x: &mut [f64],
    halo: &mut H,
    send: &mut [f64],
    recv: &mut [f64],
    counters: &mut HaloCounters,
) {
    for (k, &p) in round.send_nodes.iter().enumerate() {
        store(send, k, &load::<D>(x, p as usize));
    }
    halo.exchange(&round.sends, send, &round.recvs, recv);
    for (k, &g) in round.recv_nodes.iter().enumerate() {
        store(x, g as usize, &load::<D>(recv, k));
    }
    counters.exchanges += 1;
    counters.messages += round.sends.len() as u64;
    counters.values += round.sends.iter().map(|m| m.len as u64).sum::<u64>();
}

/// The all-gather of a vector of `values` f64 per node, node `i` owned by rank
/// `owner[i]`, as one collective ([`RankGroup::all_gather`]): each rank contributes
/// its owned nodes' values (increasing nodes), and every rank scatters the rank-ordered
/// concatenation into the nodes' places (a precomputed order). Pure data movement: every
/// rank ends with the owners' bits. Allocation-free per gather (the transport may
/// allocate).
#[derive(Debug, Clone)]
pub struct AllGather {
    values: usize,
    rank: usize,
    /// Values per rank (`values` per owned node).
    counts: Vec<usize>,
    /// The node of each block of the gathered values: rank 0's nodes (increasing), rank
    /// 1's, …
    order: Vec<u32>,
    /// This rank's blocks in `order`.
    mine: Range<usize>,
    send: Vec<f64>,
    recv: Vec<f64>,
}

impl AllGather {
    /// The gather of rank `rank` of `size` for the owners `owner` (one per node),
    /// `values` per node.
    ///
    /// # Panics
    /// If an owner is not below `size`, or `rank` is not, or `values == 0`.
    pub fn new(owner: &[usize], rank: usize, size: usize, values: usize) -> Self {
        assert!(
            rank < size && values > 0,
            "rank {rank} of {size}, {values} values"
        );
        let mut nodes = vec![0usize; size];
        for &r in owner {
            nodes[r] += 1;
        }
        let mut first = vec![0usize; size + 1];
        for r in 0..size {
            first[r + 1] = first[r] + nodes[r];
        }
        let mut next = first.clone();
        let mut order = vec![0u32; owner.len()];
        for (i, &r) in owner.iter().enumerate() {
            order[next[r]] = i as u32;
            next[r] += 1;
        }
        Self {
            values,
            rank,
            counts: nodes.iter().map(|&k| values * k).collect(),
            mine: first[rank]..first[rank + 1],
            order,
            send: vec![0.0; values * nodes[rank]],
            recv: vec![0.0; values * owner.len()],
        }
    }

    /// Gathers: `x` (`values` per node, global node order) holds this rank's owned nodes'
    /// values on entry and every node's, from its owner, on return, on every rank.
    /// Counts one collective and this rank's values in `counters`. Collective.
    ///
    /// # Panics
    /// If `x` is shorter than the nodes' values, `halo` is another rank's, or as
    /// [`RankGroup::all_gather`].
    pub fn gather<H: RankGroup + ?Sized>(
        &mut self,
        x: &mut [f64],
        halo: &mut H,
        counters: &mut HaloCounters,
    ) {
        assert_eq!(halo.rank(), self.rank, "the transport of another rank");
        let v = self.values;
        for (block, &p) in self
            .send
            .chunks_exact_mut(v)
            .zip(&self.order[self.mine.clone()])
        {
            block.copy_from_slice(&x[v * p as usize..][..v]);
        }
        halo.all_gather(&self.send, &self.counts, &mut self.recv);
        for (block, &p) in self.recv.chunks_exact(v).zip(&self.order) {
            x[v * p as usize..][..v].copy_from_slice(block);
        }
        *counters += self.per_gather();
    }

    /// What one gather sends: one collective, this rank's values.
    pub fn per_gather(&self) -> HaloCounters {
        HaloCounters {
            collectives: 1,
            collective_values: self.send.len() as u64,
            ..HaloCounters::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ThreadRanks;

    /// 11 nodes of 2 values owned out of order by 1–4 thread ranks (the last rank owns
    /// none at 3 and 4 ranks), two gathers in a row: every rank ends with every node's
    /// values from its owner, bit for bit, and counts one collective per gather with its
    /// own nodes' values.
    #[test]
    fn all_gather_fills_every_node_from_its_owner() {
        const V: usize = 2;
        let value = |p: usize, c: usize, round: usize| (100 * round + 10 * p + c) as f64 / 3.0;
        for size in 1..=4usize {
            let owners = size.min(2).max(size.saturating_sub(1));
            let owner: Vec<usize> = (0..11).map(|p| (p * 7 + 3) % owners).collect();
            let owner = &owner;
            let got = ThreadRanks::run(size, |mut halo| {
                let rank = halo.rank();
                let mut gather = AllGather::new(owner, rank, size, V);
                let mut counters = HaloCounters::default();
                let mut out = Vec::new();
                for round in 0..2 {
                    let mut x = vec![f64::NAN; V * owner.len()];
                    for p in (0..owner.len()).filter(|&p| owner[p] == rank) {
                        for c in 0..V {
                            x[V * p + c] = value(p, c, round);
                        }
                    }
                    gather.gather(&mut x, &mut halo, &mut counters);
                    out.push(x);
                }
                let mine = owner.iter().filter(|&&r| r == rank).count();
                (out, counters, gather.per_gather(), mine)
            });
            for (r, (out, counters, per, mine)) in got.into_iter().enumerate() {
                for (round, x) in out.iter().enumerate() {
                    let want: Vec<u64> = (0..V * owner.len())
                        .map(|k| value(k / V, k % V, round).to_bits())
                        .collect();
                    let bits: Vec<u64> = x.iter().map(|v| v.to_bits()).collect();
                    assert_eq!(bits, want, "rank {r} of {size}, gather {round}");
                }
                assert_eq!(
                    (per.collectives, per.collective_values),
                    (1, (V * mine) as u64)
                );
                assert_eq!(counters, per.times(2), "rank {r} of {size}");
            }
        }
    }
}
