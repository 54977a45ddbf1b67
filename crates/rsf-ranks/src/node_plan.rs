//! Per-node records sent by their owners to the ranks that need them ([`NodePlan`]): the
//! exchanges of a rank's Newton hierarchy (`T` rows, ghost masks).

use std::collections::BTreeMap;

use crate::halo::HaloCounters;
use crate::transport::{HaloMessage, RankGroup};

/// Per-node records sent from their owners to the ranks that need them: per peer rank
/// (increasing) the nodes, in increasing order on both sides, each record
/// `len(node)` values long. Both sides derive their lists from the same global data.
#[derive(Debug, Clone, Default)]
pub struct NodePlan {
    /// Per peer: `(rank, nodes)`.
    send: Vec<(usize, Vec<usize>)>,
    recv: Vec<(usize, Vec<usize>)>,
    /// The messages in values, and the nodes in buffer order.
    sends: Vec<HaloMessage>,
    send_nodes: Vec<usize>,
    recvs: Vec<HaloMessage>,
    recv_nodes: Vec<usize>,
    send_buf: Vec<f64>,
    recv_buf: Vec<f64>,
}

impl NodePlan {
    /// The plan that sends to each rank of `send` its list of nodes and receives from each
    /// rank of `recv` its list (each list increasing; the peer's matching list is the same
    /// on its side), node `p`'s record `len(p)` values long.
    pub fn new(
        send: BTreeMap<usize, Vec<usize>>,
        recv: BTreeMap<usize, Vec<usize>>,
        len: impl Fn(usize) -> usize,
    ) -> Self {
        let mut plan = Self {
            send: send.into_iter().collect(),
            recv: recv.into_iter().collect(),
            ..Self::default()
        };
        plan.select(|_| true, len);
        plan
    }

    /// Makes the messages carry only the nodes `keep` selects (both sides select with the
    /// same global rule).
    pub fn select(&mut self, keep: impl Fn(usize) -> bool, len: impl Fn(usize) -> usize) {
        fn messages(
            lists: &[(usize, Vec<usize>)],
            keep: &impl Fn(usize) -> bool,
            len: &impl Fn(usize) -> usize,
            msgs: &mut Vec<HaloMessage>,
            nodes: &mut Vec<usize>,
        ) -> usize {
            msgs.clear();
            nodes.clear();
            let mut start = 0;
            for (rank, list) in lists {
                let first = start;
                for &p in list.iter().filter(|&&p| keep(p)) {
                    nodes.push(p);
                    start += len(p);
                }
                if start > first {
                    msgs.push(HaloMessage {
                        rank: *rank,
                        start: first,
                        len: start - first,
                    });
                }
            }
            start
        }
        let n = messages(
            &self.send,
            &keep,
            &len,
            &mut self.sends,
            &mut self.send_nodes,
        );
        self.send_buf.resize(n, 0.0);
        let n = messages(
            &self.recv,
            &keep,
            &len,
            &mut self.recvs,
            &mut self.recv_nodes,
        );
        self.recv_buf.resize(n, 0.0);
    }

    /// Fills each sent record with `pack(node, out)`.
    pub fn pack(&mut self, len: impl Fn(usize) -> usize, mut pack: impl FnMut(usize, &mut [f64])) {
        let mut at = 0;
        for &p in &self.send_nodes {
            let n = len(p);
            pack(p, &mut self.send_buf[at..at + n]);
            at += n;
        }
    }

    /// The exchange of the packed records, counted in `counters`
    /// ([`per_send`](Self::per_send)). Collective among the plan's peers.
    pub fn send(&mut self, halo: &mut dyn RankGroup, counters: &mut HaloCounters) {
        halo.exchange(&self.sends, &self.send_buf, &self.recvs, &mut self.recv_buf);
        *counters += self.per_send();
    }

    /// What one [`send`](Self::send) sends: one exchange, its messages and values.
    pub fn per_send(&self) -> HaloCounters {
        HaloCounters {
            exchanges: 1,
            messages: self.sends.len() as u64,
            values: self.send_buf.len() as u64,
            ..HaloCounters::default()
        }
    }

    /// Hands each received record to `unpack(node, values)`.
    pub fn unpack(&self, len: impl Fn(usize) -> usize, mut unpack: impl FnMut(usize, &[f64])) {
        let mut at = 0;
        for &p in &self.recv_nodes {
            let n = len(p);
            unpack(p, &self.recv_buf[at..at + n]);
            at += n;
        }
    }
}
