//! The halo plan of one rank: which owned nodes each neighbour rank needs, which ghosts
//! come from it, and the messages of each colour's exchange; one exchange of a plan's
//! round, and the counters of what was sent.

use std::collections::BTreeMap;

use super::local_rows::LocalRows;
use super::transport::{HaloExchange, HaloMessage};
use crate::block::{load, store};
use crate::colouring::Colouring;

/// What one rank has sent in its halo exchanges, counted by the sweep (or the transfers) as it hands the
/// messages to the transport (the numbers a model of the communication cost is fitted
/// with). Bytes are `8 · values`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HaloCounters {
    /// Sweeps ([`DistributedSweep::sweep`](super::DistributedSweep::sweep)).
    pub sweeps: u64,
    /// Exchanges (calls of [`HaloExchange::exchange`], with or without messages of this
    /// rank: one per colour and sweep, one per ghost update).
    pub exchanges: u64,
    /// Messages sent (none is empty).
    pub messages: u64,
    /// f64 values sent.
    pub values: u64,
}

impl HaloCounters {
    /// Bytes sent: 8 per value.
    pub fn bytes(&self) -> u64 {
        8 * self.values
    }

    /// Every count times `k` (what `k` repetitions of the counted work send).
    pub fn times(self, k: u64) -> Self {
        Self {
            sweeps: k * self.sweeps,
            exchanges: k * self.exchanges,
            messages: k * self.messages,
            values: k * self.values,
        }
    }
}

/// `sweeps/exchanges/messages/values`, the form the programs' rank lines print.
impl std::fmt::Display for HaloCounters {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}/{}/{}/{}",
            self.sweeps, self.exchanges, self.messages, self.values
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
pub(crate) struct Peer {
    pub rank: usize,
    /// Owned nodes that are ghosts on `rank`, by (colour, global node).
    pub send: Vec<u32>,
    /// Ghosts owned by `rank`, by (colour, global node).
    pub recv: Vec<u32>,
}

/// The messages of one exchange: per neighbour rank (increasing) the nodes sent and
/// received, their values `D` per node in the buffers in the same order.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct Round {
    pub sends: Vec<HaloMessage>,
    /// Local nodes whose values fill the send buffer, in order.
    pub send_nodes: Vec<u32>,
    pub recvs: Vec<HaloMessage>,
    /// Local nodes that the receive buffer's values go to, in order.
    pub recv_nodes: Vec<u32>,
}

impl Round {
    /// What one exchange of this round sends (`D` values per node): one exchange, its
    /// messages and values.
    pub fn counters<const D: usize>(&self) -> HaloCounters {
        HaloCounters {
            sweeps: 0,
            exchanges: 1,
            messages: self.sends.len() as u64,
            values: (D * self.send_nodes.len()) as u64,
        }
    }

    /// The all-gather of a vector whose node `i` is owned by rank `owner[i]`, as one
    /// exchange of rank `rank` of `size` on the global vector (node indices are global):
    /// every rank sends its owned nodes (increasing) to every other rank that receives and
    /// receives each other rank's owned nodes (increasing) into their places. With
    /// `to_owners`, only ranks that own a node receive (a rank that owns none sends no
    /// message and is sent none: it has no value to compute from them); otherwise every
    /// rank receives every value. No message is empty.
    pub fn all_gather(
        owner: &[usize],
        rank: usize,
        size: usize,
        values: usize,
        to_owners: bool,
    ) -> Self {
        let mut round = Self::default();
        let nodes_of = |r: usize| (0..owner.len()).filter(move |&i| owner[i] == r);
        let receives = |r: usize| !to_owners || nodes_of(r).next().is_some();
        let mine: Vec<u32> = nodes_of(rank).map(|i| i as u32).collect();
        for r in (0..size).filter(|&r| r != rank) {
            if receives(r) {
                add(
                    &mut round.sends,
                    &mut round.send_nodes,
                    r,
                    mine.iter(),
                    values,
                );
            }
            if receives(rank) {
                let theirs: Vec<u32> = nodes_of(r).map(|i| i as u32).collect();
                add(
                    &mut round.recvs,
                    &mut round.recv_nodes,
                    r,
                    theirs.iter(),
                    values,
                );
            }
        }
        round
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
pub(crate) struct HaloPlan {
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
    pub fn without_node<const D: usize>(
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
pub(crate) fn exchange_round<const D: usize, H: HaloExchange + ?Sized>(
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
