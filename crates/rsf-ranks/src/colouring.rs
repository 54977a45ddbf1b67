//! A multi-colouring of the node graph of a block matrix: the independent sets of the
//! multi-colour block Gauss–Seidel sweeps (of one process, [`Colouring::sweep`], and of
//! ranks, [`DistributedSweep`](crate::DistributedSweep); TNNMG's smoother order
//! `SmootherOrder::MultiColour` in `rsf-tnnmg`).
//!
//! Nodes `p` and `q ≠ p` are adjacent when the matrix has a stored block `A_pq` (explicit
//! zeros count: the colouring depends on the pattern, i.e. on the mesh, never on values).
//! No two adjacent nodes share a colour, so the exact block minimisations of one colour
//! read only values of other colours and can run in any order or in parallel with the
//! same result.

use faer::sparse::SparseColMatRef;
use rayon::prelude::*;

use crate::block::store;
use crate::bsr::{BlockCsr, NodePattern};
use crate::error::Result;
use rsf_linalg::Parallelism;

/// Nodes of one colour below which a coloured sweep stays on one thread (a task costs a
/// few microseconds; a node update a fraction of one).
pub const COLOUR_PARALLEL_MIN: usize = 512;

/// A proper colouring of the node graph: colour `c` is the list of nodes
/// [`colour(c)`](Self::colour), increasing; every node has exactly one colour.
///
/// Greedy (first fit) in increasing node order: node `p` takes the smallest colour that no
/// neighbour `q < p` has. Deterministic (a function of the pattern alone); at most
/// `1 + max degree` colours (P1 on structured triangle/tetrahedron meshes: 7 resp. 15
/// neighbours at most).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Colouring {
    /// Colour `c`'s nodes are `nodes[ptr[c]..ptr[c + 1]]`.
    ptr: Vec<usize>,
    nodes: Vec<u32>,
    colour_of: Vec<u32>,
}

impl Colouring {
    /// The colouring of the node graph of the symmetric-pattern matrix `a` (`D n × D n`,
    /// node-major: node `p` owns the dofs `D p .. D p + D`).
    ///
    /// # Errors
    /// As [`BlockCsr::from_symmetric`]: [`ProblemError::InvalidMatrix`] if `a` is not
    /// square, its pattern is not symmetric, its dimension is not a multiple of `D`, or it
    /// has more than 2³² nodes; [`ProblemError::NonFinite`] for a non-finite entry.
    ///
    /// [`ProblemError::InvalidMatrix`]: rsf_linalg::ProblemError::InvalidMatrix
    /// [`ProblemError::NonFinite`]: rsf_linalg::ProblemError::NonFinite
    pub fn new<const D: usize>(a: SparseColMatRef<'_, usize, f64>) -> Result<Self> {
        Ok(Self::of_blocks(&BlockCsr::<D>::from_symmetric(a)?))
    }

    /// The colouring of a block matrix's node graph.
    pub fn of_blocks<const D: usize>(a: &BlockCsr<D>) -> Self {
        Self::of_pattern(a)
    }

    /// The colouring of a node pattern (greedy in increasing node order).
    pub fn of_pattern(a: &impl NodePattern) -> Self {
        let nodes = a.nodes();
        let mut colour_of = vec![u32::MAX; nodes];
        // forbidden[c] == p: colour c is taken by a neighbour of p.
        let mut forbidden: Vec<usize> = Vec::new();
        let mut count = Vec::new();
        for p in 0..nodes {
            for q in a.node_neighbours(p) {
                let c = colour_of[q];
                if c != u32::MAX {
                    forbidden[c as usize] = p;
                }
            }
            let c = (0..forbidden.len())
                .find(|&c| forbidden[c] != p)
                .unwrap_or(forbidden.len());
            if c == forbidden.len() {
                forbidden.push(usize::MAX);
                count.push(0usize);
            }
            colour_of[p] = c as u32;
            count[c] += 1;
        }
        let mut ptr = vec![0usize; count.len() + 1];
        for (c, &k) in count.iter().enumerate() {
            ptr[c + 1] = ptr[c] + k;
        }
        let mut next = ptr.clone();
        let mut list = vec![0u32; nodes];
        for (p, &c) in colour_of.iter().enumerate() {
            list[next[c as usize]] = p as u32;
            next[c as usize] += 1;
        }
        Self {
            ptr,
            nodes: list,
            colour_of,
        }
    }

    /// Number of colours.
    pub fn num_colours(&self) -> usize {
        self.ptr.len() - 1
    }

    /// Number of nodes coloured.
    pub fn num_nodes(&self) -> usize {
        self.colour_of.len()
    }

    /// The nodes of colour `c` (`c < num_colours()`), increasing.
    ///
    /// # Panics
    /// If `c ≥ num_colours()`.
    pub fn colour(&self, c: usize) -> &[u32] {
        &self.nodes[self.ptr[c]..self.ptr[c + 1]]
    }

    /// The colour of node `p` (`p < num_nodes()`).
    ///
    /// # Panics
    /// If `p ≥ num_nodes()`.
    pub fn colour_of(&self, p: usize) -> usize {
        self.colour_of[p] as usize
    }

    /// One sweep colour by colour over the node blocks of `x` (`D` values per node):
    /// increasing colours, or decreasing when `reverse`. For every node `p` of a colour,
    /// `update(p, x)` returns the new block of `p` from `x`, which then holds the latest
    /// values of all other colours (`p`'s neighbours never share its colour). A colour's
    /// new blocks are computed into `scratch` (at least
    /// [`max_colour_len`](Self::max_colour_len) blocks), in at most `par.threads()`
    /// contiguous chunks when the colour has [`COLOUR_PARALLEL_MIN`] nodes or more, and
    /// then stored into `x`. Each block is computed by the same call whatever the split:
    /// the result is bit-identical for every thread count.
    ///
    /// # Panics
    /// If `x` has fewer than `D` values per coloured node or `scratch` is too short.
    pub fn sweep<const D: usize, F>(
        &self,
        x: &mut [f64],
        reverse: bool,
        scratch: &mut [[f64; D]],
        par: Parallelism,
        update: F,
    ) where
        F: Fn(usize, &[f64]) -> [f64; D] + Sync,
    {
        let colours = self.num_colours();
        for k in 0..colours {
            let list = self.colour(if reverse { colours - 1 - k } else { k });
            let out = &mut scratch[..list.len()];
            {
                let x: &[f64] = x;
                let run = |nodes: &[u32], out: &mut [[f64; D]]| {
                    for (&p, o) in nodes.iter().zip(out.iter_mut()) {
                        *o = update(p as usize, x);
                    }
                };
                let threads = par.threads();
                if threads > 1 && list.len() >= COLOUR_PARALLEL_MIN {
                    let chunk = list.len().div_ceil(threads);
                    out.par_chunks_mut(chunk)
                        .zip(list.par_chunks(chunk))
                        .for_each(|(o, l)| run(l, o));
                } else {
                    run(list, out);
                }
            }
            for (&p, xp) in list.iter().zip(out.iter()) {
                store(x, p as usize, xp);
            }
        }
    }

    /// The largest colour's size (scratch length of a coloured sweep).
    pub fn max_colour_len(&self) -> usize {
        (0..self.num_colours())
            .map(|c| self.ptr[c + 1] - self.ptr[c])
            .max()
            .unwrap_or(0)
    }
}
