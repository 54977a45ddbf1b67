//! A parallel order for block Gauss–Seidel sweeps (linear or nonlinear) on a matrix whose
//! off-diagonal blocks do not change: red–black chunks of breadth-first levels
//! ([`SmootherOrder::RedBlackChunks`](crate::SmootherOrder::RedBlackChunks)).
//!
//! The node graph's breadth-first levels (from a pseudo-peripheral node, a function of the
//! pattern alone) have the property that a node couples only to nodes of its own level and
//! of the levels just before and after it. Grouping consecutive levels into chunks of nearly
//! equal node counts (2, 4, 8 or 16 of them, at least [`LEVELS_PER_CHUNK`] levels each where the
//! graph has enough levels) therefore gives chunks that couple only to the chunk before and
//! the chunk after: the even chunks are mutually independent, and so are the odd ones. A
//! forward sweep visits the even chunks (each in increasing node order, one task per
//! chunk), then the odd ones; a backward sweep is its exact reverse. This is sequential
//! Gauss–Seidel in one fixed node order, so every thread count gives the same bits.
//!
//! Unlike a node colouring, which reads every node's full row in every sweep, each chunk is
//! swept like the lexicographic sweep of [`BlockCsr::sweep`](rsf_ranks::bsr::BlockCsr::sweep):
//! the couplings inside the chunk are read once per sweep, from the triangle "ahead" of the
//! sweep (forward) or "behind" it (backward), the already updated nodes' contributions
//! being pushed through the transposed blocks; only couplings to the neighbouring chunks
//! are read as rows. The blocks are copied once into the chunked order (positions), so that
//! a chunk's rows and vectors are contiguous.

use std::sync::Arc;

use rayon::prelude::*;

use crate::Parallelism;
use rsf_linalg::for_node_rows;
use rsf_ranks::block::{load, store, sub_mul_t_vec, sub_mul_vec, Block};
use rsf_ranks::bsr::{BlockCsr, SweepOrder};

/// The most chunks (eight per colour: eight threads).
const CHUNKS_MAX: usize = 16;

/// The fewest breadth-first levels per chunk aimed at: a chunk's couplings to its
/// neighbours (read as rows, both ways) come from its first and last levels, so thin
/// chunks read nearly the whole matrix per sweep.
const LEVELS_PER_CHUNK: usize = 10;

/// Blocks by rows of positions: row `i`'s blocks are `ptr[i]..ptr[i + 1]`, each a column
/// position `pos` and its block: here the block `A_{perm[i] perm[pos]}` of the chunked
/// order; in a distributed grid transfer a position in a buffer of owned values then ghosts.
#[derive(Debug, Clone, Default)]
pub(crate) struct PositionRows<const D: usize> {
    pub(crate) ptr: Vec<usize>,
    pub(crate) pos: Vec<u32>,
    pub(crate) val: Vec<Block<D>>,
}

impl<const D: usize> PositionRows<D> {
    fn new() -> Self {
        Self {
            ptr: vec![0],
            ..Default::default()
        }
    }

    fn end_row(&mut self) {
        self.ptr.push(self.pos.len());
    }

    /// `w_{pos_k − first} −= B_kᵀ y` over row `i` (the transposed couplings of position
    /// `i` pushed into the chunk starting at position `first`).
    #[inline(always)]
    fn push_row(&self, i: usize, first: usize, y: &[f64; D], w: &mut [f64]) {
        for (j, blk) in self.row(i) {
            let m = j - first;
            let mut wm = load::<D>(w, m);
            sub_mul_t_vec(&mut wm, blk, y);
            store(w, m, &wm);
        }
    }

    /// Row `i`'s blocks with their column positions.
    #[inline(always)]
    pub(crate) fn row(&self, i: usize) -> impl Iterator<Item = (usize, &Block<D>)> {
        let r = self.ptr[i]..self.ptr[i + 1];
        self.pos[r.clone()]
            .iter()
            .zip(&self.val[r])
            .map(|(&j, b)| (j as usize, b))
    }
}

/// Block `l` of `w` plus `r` (in this order, as the lexicographic sweep adds them),
/// leaving zeros behind in `w`.
#[inline(always)]
fn take_plus<const D: usize>(w: &mut [f64], l: usize, r: &[f64; D]) -> [f64; D] {
    let mut s = load::<D>(w, l);
    w[D * l..D * l + D].fill(0.0);
    for c in 0..D {
        s[c] += r[c];
    }
    s
}

/// The breadth-first order of the node graph of `a` from `start`, continued from the
/// smallest unvisited node in every further component; returns the order and the level of
/// every node (levels increase along the order).
fn breadth_first<const D: usize>(a: &BlockCsr<D>, start: usize) -> (Vec<u32>, Vec<u32>) {
    let nodes = a.nodes();
    let mut level = vec![u32::MAX; nodes];
    let mut order: Vec<u32> = Vec::with_capacity(nodes);
    let mut next_root = 0;
    let mut base = 0;
    let mut root = start;
    loop {
        level[root] = base;
        let mut head = order.len();
        order.push(root as u32);
        while head < order.len() {
            let p = order[head] as usize;
            head += 1;
            for (q, _) in a.neighbours(p) {
                if level[q] == u32::MAX {
                    level[q] = level[p] + 1;
                    order.push(q as u32);
                }
            }
        }
        if order.len() == nodes {
            return (order, level);
        }
        // The next component starts a level above the last one (no couplings between them).
        base = level[*order.last().expect("non-empty") as usize] + 1;
        while level[next_root] != u32::MAX {
            next_root += 1;
        }
        root = next_root;
    }
}

/// The red–black chunked order of a node graph and the off-diagonal blocks in that order
/// (see the module documentation); immutable, shared by the sweeps that use it.
#[derive(Debug)]
pub(crate) struct ChunkedOrder<const D: usize> {
    /// Node at every position.
    perm: Vec<u32>,
    /// Position of every node.
    pos_of: Vec<u32>,
    /// Chunk `k` holds the positions `bounds[k]..bounds[k + 1]`.
    bounds: Vec<usize>,
    /// Couplings to later positions of the same chunk.
    ahead: PositionRows<D>,
    /// Couplings to earlier positions of the same chunk.
    behind: PositionRows<D>,
    /// Couplings to positions of the neighbouring chunks.
    outside: PositionRows<D>,
}

impl<const D: usize> ChunkedOrder<D> {
    /// The chunked order of `a`'s node graph and its off-diagonal blocks in that order
    /// (copied: later changes of `a`'s off-diagonal blocks are not seen).
    pub fn new(a: &BlockCsr<D>) -> Self {
        let nodes = a.nodes();
        if nodes == 0 {
            return Self {
                perm: Vec::new(),
                pos_of: Vec::new(),
                bounds: vec![0, 0],
                ahead: PositionRows::new(),
                behind: PositionRows::new(),
                outside: PositionRows::new(),
            };
        }
        // A pseudo-peripheral start: the last node reached from node 0 (more, thinner
        // levels than from an arbitrary node).
        let start = *breadth_first(a, 0).0.last().expect("non-empty") as usize;
        let (mut perm, level) = breadth_first(a, start);
        // 2, 4, 8 or 16 chunks (even counts split evenly between 2, 4, 8 threads), as many
        // as keep LEVELS_PER_CHUNK levels per chunk; chunks of whole levels.
        let levels = level.iter().max().map_or(0, |&l| l as usize + 1);
        let mut chunks = 2;
        while 2 * chunks <= CHUNKS_MAX && 2 * chunks * LEVELS_PER_CHUNK <= levels {
            chunks *= 2;
        }
        // Chunk k + 1 starts at the level start nearest to (k + 1)·nodes/chunks after the
        // start of chunk k: nearly equal node counts, so that every thread of a colour has
        // the same work (closing each chunk once it held nodes/chunks left the last one
        // with the accumulated shortfall: 1 156 nodes against 3 179 at 3-D j = 4).
        let level_starts: Vec<usize> = (1..nodes)
            .filter(|&i| level[perm[i] as usize] != level[perm[i - 1] as usize])
            .collect();
        let mut bounds = vec![0];
        for k in 1..chunks {
            let target = k * nodes / chunks;
            let last = *bounds.last().expect("non-empty");
            let nearest = level_starts
                .iter()
                .copied()
                .filter(|&i| i > last)
                .min_by_key(|&i| i.abs_diff(target));
            match nearest {
                Some(i) => bounds.push(i),
                None => break,
            }
        }
        bounds.push(nodes);
        // Inside a chunk, increasing node order: the per-node data the local solves read
        // (diagonal blocks, smoothers, nonlinearities, all by node) is then visited in
        // increasing address order, not at random.
        for k in 0..bounds.len() - 1 {
            perm[bounds[k]..bounds[k + 1]].sort_unstable();
        }
        let mut chunk_of = vec![0usize; nodes];
        let mut pos_of = vec![0u32; nodes];
        for k in 0..bounds.len() - 1 {
            for i in bounds[k]..bounds[k + 1] {
                chunk_of[i] = k;
                pos_of[perm[i] as usize] = i as u32;
            }
        }
        let (mut ahead, mut behind, mut outside) = (
            PositionRows::new(),
            PositionRows::new(),
            PositionRows::new(),
        );
        for (i, &p) in perm.iter().enumerate() {
            for (q, blk) in a.neighbours(p as usize) {
                let j = pos_of[q] as usize;
                let rows = if chunk_of[j] != chunk_of[i] {
                    // Breadth-first levels couple only to adjacent levels, so a chunk of
                    // whole levels only to the adjacent chunks: the sweep relies on it.
                    assert_eq!(
                        chunk_of[j].abs_diff(chunk_of[i]),
                        1,
                        "breadth-first chunks couple to their neighbours only"
                    );
                    &mut outside
                } else if j > i {
                    &mut ahead
                } else {
                    &mut behind
                };
                rows.pos.push(j as u32);
                rows.val.push(*blk);
            }
            for rows in [&mut ahead, &mut behind, &mut outside] {
                rows.end_row();
            }
        }
        Self {
            perm,
            pos_of,
            bounds,
            ahead,
            behind,
            outside,
        }
    }

    /// Number of chunks.
    pub fn num_chunks(&self) -> usize {
        self.bounds.len() - 1
    }

    /// Scalar length of the vectors (`D` per node).
    fn n(&self) -> usize {
        D * self.perm.len()
    }

    /// Splits `x` and `w` (positions) at the chunk bounds and runs `f(k, x_k, w_k, other)`
    /// for every chunk `k ≡ colour (mod 2)` (every chunk if `colour` is `None`, then
    /// `other` is empty) on at most `par.threads()` threads, where `other[k']` is chunk
    /// `k'`'s part of `x` for the chunks not run (read only). The two short lists of parts
    /// (at most 16 slices each) are allocated per call.
    fn for_chunks<F>(
        &self,
        colour: Option<usize>,
        (x, w): (&mut [f64], &mut [f64]),
        par: Parallelism,
        f: F,
    ) where
        F: Fn(usize, &mut [f64], &mut [f64], &[&[f64]]) + Sync,
    {
        let chunks = self.num_chunks();
        let mut own = Vec::with_capacity(chunks);
        let mut other: Vec<&[f64]> = Vec::new();
        if colour.is_some() {
            other.resize(chunks, &[]);
        }
        let (mut x_rest, mut w_rest) = (x, w);
        for k in 0..chunks {
            let len = D * (self.bounds[k + 1] - self.bounds[k]);
            let (xk, xr) = std::mem::take(&mut x_rest).split_at_mut(len);
            let (wk, wr) = std::mem::take(&mut w_rest).split_at_mut(len);
            (x_rest, w_rest) = (xr, wr);
            match colour {
                Some(c) if k % 2 != c => other[k] = xk,
                _ => own.push((k, xk, wk)),
            }
        }
        let threads = par.threads();
        if threads > 1 && own.len() > 1 {
            let per = own.len().div_ceil(threads);
            own.par_chunks_mut(per).for_each(|group| {
                for (k, xk, wk) in group.iter_mut() {
                    f(*k, xk, wk, &other);
                }
            });
        } else {
            for (k, xk, wk) in own.iter_mut() {
                f(*k, xk, wk, &other);
            }
        }
    }

    /// The value of position `j` of a neighbouring chunk of chunk `k`.
    #[inline(always)]
    fn neighbour(&self, k: usize, j: usize, other: &[&[f64]]) -> [f64; D] {
        let kj = if j < self.bounds[k] { k - 1 } else { k + 1 };
        load::<D>(other[kj], j - self.bounds[kj])
    }
}

/// How [`ChunkedSweep::smooth`] sweeps: how many sweeps, in which order, on which
/// threads, and the node update `local(p, b_p, s, x_p)`.
#[derive(Clone, Copy)]
pub(crate) struct Smoothing<F> {
    /// Number of sweeps.
    pub sweeps: usize,
    /// Direction, and whether the first sweep starts from `x = 0`.
    pub order: SweepOrder,
    /// The threads of the chunks of one colour.
    pub par: Parallelism,
    /// The node update.
    pub local: F,
}

/// A sweeper in a [`ChunkedOrder`]: the shared order and the vectors of one user in
/// positions (`x`, the right-hand side, the push accumulator; `D` values per node), and
/// per position the diagonal block of the residual and a block for the local solves.
#[derive(Debug)]
pub(crate) struct ChunkedSweep<const D: usize> {
    order: Arc<ChunkedOrder<D>>,
    x: Vec<f64>,
    rhs: Vec<f64>,
    w: Vec<f64>,
    /// Diagonal block of every position (the residual's).
    diag: Vec<Block<D>>,
    /// A block per position for the local solves (e.g. the smoother's inverse), so that
    /// they read it in the order of the sweep.
    local_block: Vec<Block<D>>,
}

impl<const D: usize> ChunkedSweep<D> {
    /// A sweeper in `order` with the diagonal blocks `diag` (by node) and zero local blocks.
    ///
    /// # Panics
    /// If `diag` does not have one block per node of `order`.
    pub fn new(order: Arc<ChunkedOrder<D>>, diag: &[Block<D>]) -> Self {
        let n = order.n();
        assert_eq!(diag.len(), order.perm.len(), "one diagonal block per node");
        let diag = order.perm.iter().map(|&p| diag[p as usize]).collect();
        Self {
            local_block: vec![[[0.0; D]; D]; order.perm.len()],
            order,
            x: vec![0.0; n],
            rhs: vec![0.0; n],
            w: vec![0.0; n],
            diag,
        }
    }

    /// Sets node `p`'s diagonal block and local block.
    pub fn set_node_blocks(&mut self, p: usize, diag: &Block<D>, local: &Block<D>) {
        let i = self.order.pos_of[p] as usize;
        self.diag[i] = *diag;
        self.local_block[i] = *local;
    }

    /// The shared order.
    #[cfg(test)]
    pub fn order(&self) -> &Arc<ChunkedOrder<D>> {
        &self.order
    }

    /// `sweeps` block Gauss–Seidel sweeps ([`Smoothing`]) on `A x = rhs` (forward, or backward when
    /// `order.reverse`) in the chunked order, starting from `x = 0` when `order.zero_start`:
    /// for each node `p`, `local(p, b_p, s, x_p)` updates its block `x_p` in place from `s =
    /// rhs_p − Σ_{q≠p} A_pq x_q` (`b_p` is its local block, [`set_node_blocks`](Self::set_node_blocks)),
    /// as in [`BlockCsr::sweep`](rsf_ranks::bsr::BlockCsr::sweep).
    /// The chunks of one colour run on at most `par.threads()` threads. With `residual =
    /// Some(res)`, afterwards `res = rhs − A x` with the sweeper's diagonal blocks (every
    /// chunk on the threads; the couplings inside a chunk pushed as in a sweep).
    pub fn smooth<F>(
        &mut self,
        x: &mut [f64],
        rhs: &[f64],
        residual: Option<&mut [f64]>,
        smoothing: Smoothing<F>,
    ) where
        F: Fn(usize, &Block<D>, &[f64; D], &mut [f64; D]) + Sync,
    {
        let Smoothing {
            sweeps,
            order,
            par,
            local,
        } = smoothing;
        let Self {
            order: chunked,
            x: xs,
            rhs: rs,
            w,
            diag,
            local_block,
        } = self;
        let (diag, local_block): (&[Block<D>], &[Block<D>]) = (diag, local_block);
        let chunked = &**chunked;
        gather::<D>(rs, rhs, &chunked.perm, par);
        if order.zero_start {
            xs.fill(0.0);
        } else {
            gather::<D>(xs, x, &chunked.perm, par);
        }
        for k in 0..sweeps {
            let sweep = SweepOrder {
                reverse: order.reverse,
                zero_start: order.zero_start && k == 0,
            };
            let colours: [usize; 2] = if order.reverse { [1, 0] } else { [0, 1] };
            let inside = if order.reverse {
                &chunked.behind
            } else {
                &chunked.ahead
            };
            for colour in colours {
                let rs: &[f64] = rs;
                chunked.for_chunks(Some(colour), (xs, w), par, |k, x, w, other| {
                    let first = chunked.bounds[k];
                    let len = chunked.bounds[k + 1] - first;
                    for step in 0..len {
                        let l = if sweep.reverse { len - 1 - step } else { step };
                        let i = first + l;
                        let mut s = take_plus(w, l, &load::<D>(rs, i));
                        let mut xi = [0.0; D];
                        if !sweep.zero_start {
                            // (From x = 0 the nodes not yet visited contribute nothing.)
                            for (j, blk) in inside.row(i) {
                                sub_mul_vec(&mut s, blk, &load::<D>(x, j - first));
                            }
                            xi = load::<D>(x, l);
                        }
                        for (j, blk) in chunked.outside.row(i) {
                            sub_mul_vec(&mut s, blk, &chunked.neighbour(k, j, other));
                        }
                        local(chunked.perm[i] as usize, &local_block[i], &s, &mut xi);
                        store(x, l, &xi);
                        inside.push_row(i, first, &xi, w);
                    }
                });
            }
        }
        gather::<D>(x, xs, &chunked.pos_of, par);
        if let Some(res) = residual {
            let xs: &[f64] = xs;
            // rhs − A x in positions, into `rs` (each position reads its own entry only).
            chunked.for_chunks(None, (rs, w), par, |k, r, w, _| {
                let first = chunked.bounds[k];
                for l in 0..chunked.bounds[k + 1] - first {
                    let i = first + l;
                    let xi = load::<D>(xs, i);
                    let mut s = take_plus(w, l, &load::<D>(r, l));
                    sub_mul_vec(&mut s, &diag[i], &xi);
                    for (j, blk) in chunked.ahead.row(i) {
                        sub_mul_vec(&mut s, blk, &load::<D>(xs, j));
                    }
                    for (j, blk) in chunked.outside.row(i) {
                        sub_mul_vec(&mut s, blk, &load::<D>(xs, j));
                    }
                    store(r, l, &s);
                    chunked.ahead.push_row(i, first, &xi, w);
                }
            });
            gather::<D>(res, rs, &chunked.pos_of, par);
        }
    }
}

/// Nodes below which [`gather`] stays on the calling thread.
const GATHER_PARALLEL_MIN: usize = 4096;

/// `dst_i = src_{idx_i}` for the node blocks `i` of `dst` (between node numbers and
/// positions: `idx` is `perm` or `pos_of`), on `par`'s threads in contiguous ranges of `i`;
/// copies, so the same bits for every thread count.
fn gather<const D: usize>(dst: &mut [f64], src: &[f64], idx: &[u32], par: Parallelism) {
    for_node_rows::<D>(dst, (par, GATHER_PARALLEL_MIN), |i, out| {
        out.copy_from_slice(&src[D * idx[i] as usize..][..D]);
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsf_linalg::Csc;
    use rsf_ranks::block::{masked_inverse, mul_vec};

    /// A symmetric positive definite matrix with the 9-point pattern of an `m × m` grid
    /// and dense `D × D` blocks (nodes numbered row by row after a shuffle, so that the
    /// numbering is not the breadth-first one).
    fn grid<const D: usize>(m: usize) -> BlockCsr<D> {
        let nodes = m * m;
        let shuffle = |p: usize| (p * 37 + 11) % nodes;
        let n = D * nodes;
        let mut dense = vec![vec![0.0; n]; n];
        for j in 0..m {
            for i in 0..m {
                let p = shuffle(j * m + i);
                for (dj, di) in [(0, 1), (1, 0), (1, 1), (1, usize::MAX)] {
                    let (jj, ii) = (j + dj, i.wrapping_add(di));
                    if jj >= m || ii >= m {
                        continue;
                    }
                    let q = shuffle(jj * m + ii);
                    for r in 0..D {
                        for c in 0..D {
                            let v = -0.1 - 0.01 * ((p + q + r + 2 * c) % 7) as f64;
                            dense[D * p + r][D * q + c] = v;
                            dense[D * q + c][D * p + r] = v;
                        }
                    }
                }
            }
        }
        for (k, row) in dense.iter_mut().enumerate() {
            row[k] = 8.0 + (k % 3) as f64;
        }
        BlockCsr::from_csc(&Csc::from_dense(&dense)).unwrap()
    }

    fn smoother<const D: usize>(a: &BlockCsr<D>) -> Vec<Block<D>> {
        a.diag
            .iter()
            .map(|d| masked_inverse(d, &[true; D]))
            .collect()
    }

    /// A sweeper with the smoother's blocks as local blocks.
    fn sweeper<const D: usize>(a: &BlockCsr<D>, s: &[Block<D>]) -> ChunkedSweep<D> {
        let mut c = ChunkedSweep::new(Arc::new(ChunkedOrder::new(a)), &a.diag);
        for (p, sp) in s.iter().enumerate() {
            c.set_node_blocks(p, &a.diag[p], sp);
        }
        c
    }

    /// The linear block Gauss–Seidel step with the local block.
    fn local<const D: usize>(_: usize, b: &Block<D>, r: &[f64; D], x: &mut [f64; D]) {
        *x = mul_vec(b, r);
    }

    /// The positions in sweep order: the even chunks, then the odd ones.
    fn sweep_positions<const D: usize>(c: &ChunkedOrder<D>) -> Vec<usize> {
        let k = c.num_chunks();
        (0..k)
            .step_by(2)
            .chain((1..k).step_by(2))
            .flat_map(|k| c.bounds[k]..c.bounds[k + 1])
            .collect()
    }

    /// The chunks partition the nodes into whole breadth-first levels that couple only to
    /// the adjacent chunks (asserted while building), and there are several of them.
    #[test]
    fn chunks_partition_the_nodes() {
        let a = grid::<2>(24);
        let c = ChunkedOrder::new(&a);
        assert!(c.num_chunks() >= 2, "{} chunks", c.num_chunks());
        let mut seen = c.perm.clone();
        seen.sort_unstable();
        assert!(seen.iter().enumerate().all(|(i, &p)| i == p as usize));
        let blocks = c.ahead.pos.len() + c.behind.pos.len() + c.outside.pos.len();
        let stored = a.lower.col.len() + a.upper.col.len();
        assert_eq!(blocks, stored);
        assert_eq!(c.ahead.pos.len(), c.behind.pos.len());
    }

    /// A forward and a backward chunked sweep equal Gauss–Seidel by full rows in the order
    /// of the positions (even chunks, then odd ones) and its reverse, to round-off (the
    /// chunked sweep accumulates the couplings in another order).
    #[test]
    fn chunked_sweeps_are_gauss_seidel_in_the_chunked_order() {
        let a = grid::<2>(20);
        let s = smoother(&a);
        let mut c = sweeper(&a, &s);
        let n = a.n();
        let rhs: Vec<f64> = (0..n).map(|i| ((i * 13 % 17) as f64 - 8.0) / 3.0).collect();
        let x0: Vec<f64> = (0..n).map(|i| ((i * 7 % 5) as f64 - 2.0) / 4.0).collect();
        let order = sweep_positions(c.order());
        for (reverse, zero_start) in [(false, false), (true, false), (false, true)] {
            let mut x = x0.clone();
            let sweep = SweepOrder {
                reverse,
                zero_start,
            };
            let mut res = vec![0.0; n];
            let smoothing = Smoothing {
                sweeps: 2,
                order: sweep,
                par: Parallelism::SEQ,
                local: local::<D2>,
            };
            c.smooth(&mut x, &rhs, Some(&mut res), smoothing);
            let mut y = if zero_start { vec![0.0; n] } else { x0.clone() };
            for _ in 0..2 {
                let visit: Vec<usize> = if reverse {
                    order.iter().rev().copied().collect()
                } else {
                    order.clone()
                };
                for i in visit {
                    let p = c.order().perm[i] as usize;
                    let mut r = load::<D2>(&rhs, p);
                    for (q, blk) in a.neighbours(p) {
                        sub_mul_vec(&mut r, blk, &load::<D2>(&y, q));
                    }
                    store(&mut y, p, &mul_vec(&s[p], &r));
                }
            }
            let (err, scale) = (max_diff(&x, &y), max_diff(&y, &vec![0.0; n]));
            assert!(err <= 1e-14 * scale, "{reverse} {zero_start}: {err:e}");
            assert!(c.w.iter().all(|&v| v == 0.0));
            // The residual against one by full rows.
            let mut full = vec![0.0; n];
            a.residual_rows(&rhs, &x, &mut full, Parallelism::SEQ);
            let (rerr, rscale) = (max_diff(&res, &full), max_diff(&full, &vec![0.0; n]));
            assert!(rerr <= 1e-13 * rscale, "residual {rerr:e} of {rscale:e}");
        }
    }

    const D2: usize = 2;

    /// `max |u_i − v_i|`.
    fn max_diff(u: &[f64], v: &[f64]) -> f64 {
        u.iter()
            .zip(v)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
    }

    /// The same bits on 1, 2 and 4 threads (in a pool of 4).
    #[test]
    fn chunked_sweeps_are_bit_identical_for_every_thread_count() {
        let a = grid::<3>(40);
        let s = smoother(&a);
        let n = a.n();
        let rhs: Vec<f64> = (0..n).map(|i| ((i * 13 % 17) as f64 - 8.0) / 3.0).collect();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap();
        let run = |threads: usize| {
            let mut c = sweeper(&a, &s);
            let (mut x, mut res) = (vec![0.0; n], vec![0.0; n]);
            pool.install(|| {
                let first = Smoothing {
                    sweeps: 1,
                    order: SweepOrder {
                        reverse: false,
                        zero_start: true,
                    },
                    par: Parallelism::rayon(threads),
                    local: local::<3>,
                };
                c.smooth(&mut x, &rhs, None, first);
                let back = Smoothing {
                    sweeps: 2,
                    order: SweepOrder::from_x(true),
                    ..first
                };
                c.smooth(&mut x, &rhs, Some(&mut res), back);
            });
            let bits = |v: &[f64]| v.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            (bits(&x), bits(&res))
        };
        let one = run(1);
        assert_eq!(run(2), one);
        assert_eq!(run(4), one);
    }
}
