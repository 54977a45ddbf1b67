//! The whole node graph of a matrix of which each rank holds its owned nodes' rows
//! ([`NodeGraph`], gathered from the ranks' rows), and the node pattern the set-up's
//! symbolic steps read ([`NodePattern`]).

use crate::block::Block;
use crate::bsr::NodePattern;
use crate::error::Result;
use crate::halo::{AllGather, HaloCounters};
use crate::local_rows::LocalRows;
use crate::transport::RankGroup;
use rsf_linalg::ProblemError;

/// The node graph of a matrix, whole, without values: node `p`'s neighbours are
/// `col[ptr[p]..ptr[p + 1]]`, increasing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeGraph {
    ptr: Vec<usize>,
    col: Vec<u32>,
}

impl NodePattern for NodeGraph {
    fn nodes(&self) -> usize {
        self.ptr.len() - 1
    }
    fn node_neighbours(&self, p: usize) -> impl Iterator<Item = usize> + '_ {
        self.col[self.ptr[p]..self.ptr[p + 1]]
            .iter()
            .map(|&q| q as usize)
    }
}

impl NodeGraph {
    /// The whole graph and diagonal blocks of the matrix whose owned rows each rank
    /// holds (`rows`, nodes owned by `owner`), gathered from every rank in three
    /// all-gathers (the neighbour counts, the neighbour lists, the diagonal blocks) and
    /// checked symmetric. Collective.
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] if the gathered pattern is not symmetric (the ranks'
    /// columns are not the rows of one symmetric-pattern matrix).
    pub fn gather<const D: usize>(
        rows: &LocalRows<D>,
        owner: &[usize],
        halo: &mut dyn RankGroup,
        counters: &mut HaloCounters,
    ) -> Result<(Self, Vec<Block<D>>)> {
        let (rank, size, nodes) = (halo.rank(), halo.size(), owner.len());
        let global = rows.global_nodes();
        // Neighbour counts, by node.
        let mut counts = vec![0.0; nodes];
        for p in 0..rows.owned() {
            counts[global[p]] = rows.neighbours(p).count() as f64;
        }
        AllGather::new(owner, rank, size, 1).gather(&mut counts, halo, counters);
        let mut ptr = Vec::with_capacity(nodes + 1);
        ptr.push(0);
        for &k in &counts {
            ptr.push(ptr.last().expect("pushed") + k as usize);
        }
        drop(counts);
        // Neighbour lists: rank r's owned nodes in increasing order, the ranks in turn.
        let mut per_rank = vec![0usize; size];
        for (p, &r) in owner.iter().enumerate() {
            per_rank[r] += ptr[p + 1] - ptr[p];
        }
        let send: Vec<f64> = (0..rows.owned())
            .flat_map(|p| rows.neighbours(p).map(|(q, _)| global[q] as f64))
            .collect();
        let mut recv = vec![0.0; ptr[nodes]];
        halo.all_gather(&send, &per_rank, &mut recv);
        counters.collectives += 1;
        counters.collective_values += send.len() as u64;
        drop(send);
        let mut starts: Vec<usize> = per_rank
            .iter()
            .scan(0, |s, &k| {
                let a = *s;
                *s += k;
                Some(a)
            })
            .collect();
        let mut col = vec![0u32; ptr[nodes]];
        for (p, &r) in owner.iter().enumerate() {
            let k = ptr[p + 1] - ptr[p];
            for (c, &q) in col[ptr[p]..ptr[p + 1]]
                .iter_mut()
                .zip(&recv[starts[r]..starts[r] + k])
            {
                *c = q as u32;
            }
            starts[r] += k;
        }
        drop(recv);
        let graph = Self { ptr, col };
        graph.check_symmetric()?;
        // Diagonal blocks, by node.
        let mut diag = vec![0.0; D * D * nodes];
        for p in 0..rows.owned() {
            let d = rows.diag(p);
            for r in 0..D {
                let at = D * D * global[p] + D * r;
                diag[at..at + D].copy_from_slice(&d[r]);
            }
        }
        AllGather::new(owner, rank, size, D * D).gather(&mut diag, halo, counters);
        let diag = diag
            .chunks_exact(D * D)
            .map(|b| std::array::from_fn(|r| std::array::from_fn(|c| b[D * r + c])))
            .collect();
        Ok((graph, diag))
    }

    /// Whether `q` is a neighbour of `p` for every neighbour `p` of `q`.
    fn check_symmetric(&self) -> Result<()> {
        for p in 0..self.nodes() {
            for q in self.node_neighbours(p) {
                let back = |q: usize| {
                    self.col[self.ptr[q]..self.ptr[q + 1]]
                        .binary_search(&(p as u32))
                        .is_ok()
                };
                if q >= self.nodes() || q == p || !back(q) {
                    return Err(ProblemError::InvalidMatrix(format!(
                        "the ranks' columns are not the rows of a symmetric pattern: node {p} \
                         couples node {q}, which does not couple it back"
                    ))
                    .into());
                }
            }
        }
        Ok(())
    }
}
