//! The hierarchical matrix: set-up from a dense matrix, from an entry function
//! (`entries`) or from columns, and the allocation-free product (docs/math.md §13).

use std::ops::Range;
use std::time::Instant;

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par};

use crate::block::partition;
use crate::cluster::ClusterTree;
use crate::columns;
use crate::error::{ColumnsError, Error};
use crate::lowrank::{svd_truncate, LowRank};
use crate::options::{ColumnReport, ErrorMeasure, HOptions, SetupReport};
use crate::points::Points;
use crate::product::{
    panel_index, run_part, run_parts, to_row_panels, Block, Data, Operands, PartRows, Segment,
    Split,
};

mod entries;

/// A hierarchical (ℋ-) matrix approximation `S_H` of a square matrix `S` whose rows and
/// columns belong to points (docs/math.md §13): a cluster tree on the points, a block tree
/// with the standard admissibility condition, dense near-field blocks and low-rank
/// far-field blocks `U Vᵀ` compressed to relative Frobenius accuracy `ε` per block, so
/// that `‖S − S_H‖_F ≤ ε ‖S‖_F`.
///
/// Storage and the cost of a product are `O(k n log n)` for `n` points and block ranks
/// `k` (`k` grows like `log(1/ε)` for asymptotically smooth kernels), against `n²` dense.
///
/// ```
/// use rsf_hmatrix::{HMatrix, HOptions, Points};
/// # fn main() -> Result<(), rsf_hmatrix::Error> {
/// let n = 300;
/// let x: Vec<f64> = (0..n).map(|i| i as f64).collect();
/// let points = Points::new(&x, 1)?;
/// let kernel = |i: usize, j: usize| 1.0 / ((x[i] - x[j]).abs() + 1.0);
/// let mut h = HMatrix::from_entries(kernel, &points, &HOptions::with_epsilon(1e-8))?;
/// assert!(h.stored_entries() < n * n);
/// let v = vec![1.0; n];
/// let mut y = vec![0.0; n];
/// h.apply_add(&v, &mut y, 1.0, faer::Par::Seq)?;
/// let exact: f64 = (0..n).map(|j| kernel(0, j)).sum();
/// assert!((y[0] - exact).abs() < 1e-6 * exact);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone)]
pub struct HMatrix {
    n: usize,
    /// Cluster order → original index.
    perm: Vec<usize>,
    blocks: Vec<Block>,
    segments: Vec<Segment>,
    /// The parts of the product (one for a sequential product).
    split: Split,
    /// Total rank of the low-rank blocks (the length of a part's projection scratch).
    t_len: usize,
    /// Scratch: `x` in cluster order.
    xp: Vec<f64>,
    /// Scratch: `S_H x` in cluster order, from the last product.
    zp: Vec<f64>,
    report: SetupReport,
    /// `(part, parts)` if only the blocks of one part's rows are held
    /// ([`from_entries_part`](Self::from_entries_part)).
    held: Option<(usize, usize)>,
}

impl HMatrix {
    /// Compresses the dense `n × n` matrix `s` whose row and column `i` belong to point `i`:
    /// each admissible block by truncated SVD to relative accuracy `ε`. The error in the
    /// [report](Self::report) is exact (every entry of `S_H` against `s`). Costs the SVDs
    /// of the admissible blocks, `O(n² k)`-ish for kernels with low-rank far fields.
    ///
    /// # Errors
    /// Invalid options ([`HOptions::validate`]); [`Error::Shape`] unless `s` is
    /// `points.len()` square; [`Error::NonFiniteEntry`] for NaN or infinity in `s`;
    /// [`Error::Svd`] if an SVD does not converge.
    pub fn from_dense(
        s: MatRef<'_, f64>,
        points: &Points,
        options: &HOptions,
    ) -> Result<Self, Error> {
        options.validate()?;
        let n = points.len();
        if s.nrows() != n || s.ncols() != n {
            return Err(Error::Shape {
                rows: s.nrows(),
                cols: s.ncols(),
                points: n,
            });
        }
        for j in 0..n {
            for i in 0..n {
                if !s[(i, j)].is_finite() {
                    return Err(Error::NonFiniteEntry { row: i, col: j });
                }
            }
        }
        let tree = ClusterTree::new(points, options.leaf_size);
        let perm = &tree.perm;
        let mut blocks = Vec::new();
        let mut err2 = 0.0;
        for shape in partition(&tree, options.eta) {
            let dense = Mat::from_fn(shape.nrows, shape.ncols, |i, j| {
                s[(perm[shape.row + i], perm[shape.col + j])]
            });
            let lr = if shape.admissible {
                svd_truncate(dense.as_ref(), options.epsilon)?
            } else {
                None
            };
            let data = match lr {
                Some(lr) => {
                    err2 += low_rank_error2(dense.as_ref(), &lr);
                    Data::LowRank(lr)
                }
                None => Data::Dense(to_column_major(dense.as_ref())),
            };
            blocks.push(Block {
                shape,
                data,
                t_offset: 0,
            });
        }
        let norm2: f64 = (0..n)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .map(|(i, j)| s[(i, j)] * s[(i, j)])
            .sum();
        let rel = if norm2 > 0.0 {
            (err2 / norm2).sqrt()
        } else {
            0.0
        };
        Ok(Self::assemble(tree, blocks, rel, ErrorMeasure::Exact))
    }

    /// Builds the matrix of a symmetric `n × n` matrix `S` from its columns, never forming
    /// anything `n × n` — for `S` too large to form, each column costing a solve (the
    /// fault's Schur complement: one pair of sparse triangular solves with the volume's
    /// factor per column, docs/math.md §12). Every column is asked for exactly once:
    /// the near-field blocks need the columns of every leaf cluster, so no set-up from
    /// columns needs fewer (docs/math.md §13.6).
    ///
    /// `columns(js, out)` must write column `js[k]` of `S` (original numbering) into
    /// column `k` of `out`, an `n × js.len()` matrix whose row `i` is row `i` of `S`
    /// (entries on entry zero), and return `Ok(())`. `js` holds whole leaf clusters of
    /// the cluster tree, at least [`HOptions::column_batch`] columns (fewer only in the
    /// last batch), distinct and in no particular order; every column of `0..n` comes in
    /// exactly one call, the calls in a fixed order. Calls come one at a time (never two
    /// at once) but possibly from a thread of rayon's current pool while the previous
    /// batch is compressed on the others; the oracle may use threads itself (a
    /// multi-right-hand-side solve). `S` is taken symmetric and not checked: the rows of
    /// each block come from the same columns as its columns.
    ///
    /// Each batch fills the near-field blocks it reaches and extends, in every admissible
    /// block it reaches, an orthonormal basis of the block's columns: the new columns are
    /// projected on the basis (Gram–Schmidt, twice), what the basis misses is truncated by
    /// its SVD to `ε/10` of the batch's columns and appended. A block whose columns are all
    /// seen is recompressed to `0.9 ε` (SVD of the coefficients, the basis being
    /// orthonormal) and freed of its basis; a block whose rank reaches the point where it
    /// is cheaper dense is stored dense. Every entry is seen, so the result does not rest
    /// on a sampling heuristic: the discarded singular values give a bound on the error
    /// ([`ColumnReport::error_bound`](crate::ColumnReport::error_bound)), and
    /// [`SetupReport::relative_error`] is estimated on [`HOptions::error_columns`] random
    /// columns kept as they pass ([`ErrorMeasure::SampledColumns`]; exact if every column
    /// is sampled); [`SetupReport::columns`] holds the columns computed, the calls, the
    /// memory peak and the times. Blocks are compressed in parallel on rayon's current
    /// pool, each by sequential kernels, so the result is bit-identical for every thread
    /// count. Memory: two batches (`n × batch` each), the sampled columns (`n` each) and
    /// the blocks (the ℋ-matrix at accuracy `ε/10` while being built). Cost: the `n`
    /// columns, plus `O(k n²)` flops of projections (`k` a block's rank at `ε/10`).
    ///
    /// # Errors
    /// [`ColumnsError::Oracle`] with the oracle's error (the set-up stops);
    /// [`ColumnsError::HMatrix`] with invalid options ([`HOptions::validate`]),
    /// [`Error::NonFiniteEntry`] for NaN or infinity in a column, or [`Error::Svd`] if an
    /// SVD does not converge.
    pub fn from_symmetric_columns<C, E>(
        columns: C,
        points: &Points,
        options: &HOptions,
    ) -> Result<Self, ColumnsError<E>>
    where
        C: Fn(&[usize], MatMut<'_, f64>) -> Result<(), E> + Sync,
        E: Send,
    {
        let clock = Instant::now();
        options.validate()?;
        let n = points.len();
        let tree = ClusterTree::new(points, options.leaf_size);
        let shapes = partition(&tree, options.eta);
        let built = columns::build(&columns, &tree, shapes, options)?;
        let mut h = Self::assemble(tree, built.blocks, 0.0, ErrorMeasure::Exact);
        // The error on the sampled columns, against S_H's columns.
        let mut iperm = vec![0; n];
        for (p, &i) in h.perm.iter().enumerate() {
            iperm[i] = p;
        }
        let mut e2 = 0.0;
        for (j, col) in &built.sampled {
            for (i, s) in col.iter().enumerate() {
                e2 += (s - h.entry_in_cluster_order(iperm[i], iperm[*j])).powi(2);
            }
        }
        let s = built.sampled.len();
        let (measure, err2) = if s == n {
            (ErrorMeasure::Exact, e2)
        } else {
            let err2 = if s > 0 { e2 * n as f64 / s as f64 } else { 0.0 };
            (ErrorMeasure::SampledColumns { columns: s }, err2)
        };
        let rel = |x2: f64| {
            if built.norm2 > 0.0 {
                (x2 / built.norm2).sqrt()
            } else {
                0.0
            }
        };
        h.report.relative_error = rel(err2);
        h.report.error_measure = measure;
        let stored = 8 * h.report.stored_entries;
        h.report.columns = Some(ColumnReport {
            columns_computed: built.columns_computed,
            batches: built.batches,
            largest_batch: built.largest_batch,
            peak_bytes: built.peak_bytes.max(stored),
            oracle_seconds: built.oracle_seconds,
            setup_seconds: clock.elapsed().as_secs_f64(),
            error_bound: rel(built.bound2),
        });
        Ok(h)
    }

    fn assemble(
        tree: ClusterTree,
        mut blocks: Vec<Block>,
        relative_error: f64,
        error_measure: ErrorMeasure,
    ) -> Self {
        let n = tree.perm.len();
        let leaves = tree.leaves();
        let segments: Vec<Segment> = leaves
            .iter()
            .map(|&leaf| {
                let c = &tree.nodes[leaf];
                // Leaves are nested in or disjoint from every block's row cluster.
                let parts = blocks
                    .iter()
                    .enumerate()
                    .filter(|(_, b)| b.shape.row <= c.start && c.end <= b.shape.row + b.shape.nrows)
                    .map(|(k, b)| (k, c.start - b.shape.row))
                    .collect();
                Segment {
                    start: c.start,
                    len: c.len(),
                    parts,
                }
            })
            .collect();
        let mut report = SetupReport {
            relative_error,
            error_measure,
            stored_entries: 0,
            dense_entries: n * n,
            dense_blocks: 0,
            low_rank_blocks: 0,
            max_rank: 0,
            mean_rank: 0.0,
            leaf_clusters: leaves.len(),
            columns: None,
            part: None,
        };
        let mut rank_sum = 0;
        for b in &mut blocks {
            // The block's rows are whole leaf clusters: its row panels, one per leaf.
            let sh = b.shape;
            let first = segments.partition_point(|s| s.start < sh.row);
            let last = segments.partition_point(|s| s.start < sh.row + sh.nrows);
            let lens: Vec<usize> = segments[first..last].iter().map(|s| s.len).collect();
            match &mut b.data {
                Data::Dense(d) => *d = to_row_panels(d, sh.nrows, sh.ncols, &lens),
                Data::LowRank(lr) => lr.u = to_row_panels(&lr.u, sh.nrows, lr.rank, &lens),
            }
            match &b.data {
                Data::Dense(d) => {
                    report.dense_blocks += 1;
                    report.stored_entries += d.len();
                }
                Data::LowRank(lr) => {
                    report.low_rank_blocks += 1;
                    report.stored_entries += lr.u.len() + lr.v.len();
                    report.max_rank = report.max_rank.max(lr.rank);
                    b.t_offset = rank_sum;
                    rank_sum += lr.rank;
                }
            }
        }
        if report.low_rank_blocks > 0 {
            report.mean_rank = rank_sum as f64 / report.low_rank_blocks as f64;
        }
        let split = Split::new(1, 0.0, &segments, &blocks, rank_sum);
        Self {
            n,
            perm: tree.perm,
            blocks,
            segments,
            split,
            t_len: rank_sum,
            xp: vec![0.0; n],
            zp: vec![0.0; n],
            report,
            held: None,
        }
    }

    /// Entry `(p, q)` of `S_H` in cluster order.
    fn entry_in_cluster_order(&self, p: usize, q: usize) -> f64 {
        let seg = self.segments.partition_point(|s| s.start <= p) - 1;
        let seg = &self.segments[seg];
        for &(k, off) in &seg.parts {
            let b = &self.blocks[k];
            let sh = b.shape;
            if sh.col <= q && q < sh.col + sh.ncols {
                // Row panels: the segment's rows of the block start at its row `off`.
                let (i, j, len) = (p - seg.start, q - sh.col, seg.len);
                return match &b.data {
                    Data::Dense(d) => d[panel_index(off, len, sh.ncols, i, j)],
                    Data::LowRank(lr) => (0..lr.rank)
                        .map(|l| {
                            lr.u[panel_index(off, len, lr.rank, i, l)] * lr.v[l * sh.ncols + j]
                        })
                        .sum(),
                };
            }
        }
        0.0
    }

    /// `y ← y + α S_H x` (original numbering). Allocates nothing (but a new split of the
    /// rows when `par`'s thread count changes); the result is bit-identical from run to
    /// run and for every `par`: the rows are summed in parts, each part forming the
    /// projections `t = Vᵀ x` of the low-rank blocks that reach its rows and summing the
    /// blocks of each of its leaf clusters in a fixed order (fixed-order kernels
    /// independent of memory alignment and of the split; docs/math.md §13.5).
    /// `Par::Rayon(k)` with `k > 1` runs `k` parts on rayon's current thread pool.
    ///
    /// # Errors
    /// [`Error::VectorLength`] unless `x` and `y` have length [`dim`](Self::dim);
    /// [`Error::NonFiniteInput`] for NaN or infinity in `x`; [`Error::Option`] for a
    /// non-finite `alpha`.
    pub fn apply_add(
        &mut self,
        x: &[f64],
        y: &mut [f64],
        alpha: f64,
        par: Par,
    ) -> Result<(), Error> {
        if y.len() != self.n {
            return Err(Error::VectorLength {
                name: "y",
                len: y.len(),
                expected: self.n,
            });
        }
        if !alpha.is_finite() {
            return Err(Error::Option {
                name: "alpha",
                value: alpha,
                expected: "finite",
            });
        }
        self.whole()?;
        // Before any new split: a non-finite `x` (a trial stage that blew up) leaves the
        // split of a caller's parts as it was (`apply_part` shares it out to processes).
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(Error::NonFiniteInput(i));
        }
        let threads = match par {
            Par::Rayon(k) => k.get(),
            Par::Seq => 1,
        };
        if self.split.requested() != threads {
            self.split_rows(threads, 0.0);
        }
        // Zero-sized states: no allocation.
        let mut states = vec![(); self.split.len()];
        self.apply_by_parts(x, &mut states, |_, _| {})?;
        for (&i, z) in self.perm.iter().zip(&self.zp) {
            y[i] += alpha * z;
        }
        Ok(())
    }

    /// Splits the rows for [`apply_by_parts`](Self::apply_by_parts) into at most `parts`
    /// consecutive ranges of the cluster order (whole leaf clusters, at least one part)
    /// of about equal work: each row's multiply-adds plus `work_per_row` (what the caller
    /// does with each row inside its part, in multiply-adds). Returns the ranges; they
    /// cover `0..dim` in order. Kept until the next call (or an [`apply_add`](Self::apply_add)
    /// with another thread count). Allocates.
    pub fn split_rows(&mut self, parts: usize, work_per_row: f64) -> Vec<Range<usize>> {
        if self.held.is_some() {
            // Built for one part: its split is the only one.
            return self.split.rows().collect();
        }
        let work_per_row = if work_per_row.is_finite() {
            work_per_row.max(0.0)
        } else {
            0.0
        };
        self.split = Split::new(
            parts,
            work_per_row,
            &self.segments,
            &self.blocks,
            self.t_len,
        );
        self.split.rows().collect()
    }

    /// `S_H x` by the parts of the last [`split_rows`](Self::split_rows) (one part unless
    /// split), each part run as a rayon task (the parts do not wait for each other) and,
    /// once its rows are summed, handed to `f` with its state (`states[part]`) in the same
    /// task: the way to do row-wise work on the product without a second parallel region.
    /// Each row's value is bit-identical to [`apply_add`](Self::apply_add)'s for every
    /// split. Afterwards the whole product is [`last_product`](Self::last_product).
    /// Allocates nothing.
    ///
    /// # Errors
    /// [`Error::VectorLength`] unless `x` has length [`dim`](Self::dim) and `states` one
    /// entry per part; [`Error::NonFiniteInput`] for NaN or infinity in `x` (then `f` is
    /// not called).
    pub fn apply_by_parts<S, F>(&mut self, x: &[f64], states: &mut [S], f: F) -> Result<(), Error>
    where
        S: Send,
        F: Fn(PartRows<'_>, &mut S) + Sync,
    {
        self.check_x(x)?;
        self.whole()?;
        if states.len() != self.split.len() {
            return Err(Error::VectorLength {
                name: "states",
                len: states.len(),
                expected: self.split.len(),
            });
        }
        self.load_x(x)?;
        let ops = Operands {
            blocks: &self.blocks,
            segments: &self.segments,
            xp: &self.xp,
        };
        run_parts(0, self.split.parts_mut(), &mut self.zp, states, &ops, &f);
        Ok(())
    }

    /// [`Error::VectorLength`] unless `x` has length [`dim`](Self::dim).
    fn check_x(&self, x: &[f64]) -> Result<(), Error> {
        if x.len() == self.n {
            Ok(())
        } else {
            Err(Error::VectorLength {
                name: "x",
                len: x.len(),
                expected: self.n,
            })
        }
    }

    /// `x` (checked by [`check_x`](Self::check_x)) in cluster order into the products'
    /// operand; [`Error::NonFiniteInput`] for NaN or infinity in it (nothing loaded).
    fn load_x(&mut self, x: &[f64]) -> Result<(), Error> {
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(Error::NonFiniteInput(i));
        }
        for (xp, &i) in self.xp.iter_mut().zip(&self.perm) {
            *xp = x[i];
        }
        Ok(())
    }

    /// One part's rows of `S_H x` (part `part` of the last [`split_rows`](Self::split_rows)),
    /// handed to `f`: the share of one process when the parts are shared out between
    /// processes (each then holds its own rows). Each row's value is bit-identical to
    /// [`apply_add`](Self::apply_add)'s and to [`apply_by_parts`](Self::apply_by_parts)'s,
    /// whatever the split. Afterwards [`last_product`](Self::last_product) holds the
    /// part's rows (the others are stale). Runs on the calling thread; allocates nothing.
    ///
    /// # Errors
    /// [`Error::VectorLength`] unless `x` has length [`dim`](Self::dim) and `part` is a
    /// part of the split (`part < ` the number of ranges [`split_rows`](Self::split_rows)
    /// returned); [`Error::NonFiniteInput`] for NaN or infinity anywhere in `x` (then `f`
    /// is not called).
    pub fn apply_part<T>(
        &mut self,
        x: &[f64],
        part: usize,
        f: impl FnOnce(PartRows<'_>) -> T,
    ) -> Result<T, Error> {
        self.check_x(x)?;
        if part >= self.split.len() {
            return Err(Error::VectorLength {
                name: "part",
                len: part,
                expected: self.split.len(),
            });
        }
        if let Some((held, parts)) = self.held {
            if part != held {
                return Err(Error::PartOnly { part: held, parts });
            }
        }
        self.load_x(x)?;
        let ops = Operands {
            blocks: &self.blocks,
            segments: &self.segments,
            xp: &self.xp,
        };
        let p = &mut self.split.parts_mut()[part];
        let rows = p.rows();
        let z = &mut self.zp[rows.clone()];
        run_part(p, z, &ops);
        Ok(f(PartRows { part, rows, z }))
    }

    /// `S_H x` of the last product, in cluster order: entry `p` is row
    /// [`permutation`](Self::permutation)`()[p]` (zeros before the first product).
    pub fn last_product(&self) -> &[f64] {
        &self.zp
    }

    /// The dimension `n` (rows = columns = points).
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Number of f64 stored in the blocks (dense entries plus `k (m + n)` per low-rank
    /// block), against `n²` for the dense matrix.
    pub fn stored_entries(&self) -> usize {
        self.report.stored_entries
    }

    /// What the set-up measured: error, memory, ranks, blocks.
    pub fn report(&self) -> &SetupReport {
        &self.report
    }

    /// The permutation to cluster order: position `p` of the cluster order holds unknown
    /// `permutation()[p]`.
    pub fn permutation(&self) -> &[usize] {
        &self.perm
    }

    /// `(part, parts)` if the matrix holds only the rows of one part
    /// ([`from_entries_part`](Self::from_entries_part)), else `None`.
    pub fn held_part(&self) -> Option<(usize, usize)> {
        self.held
    }

    /// [`Error::PartOnly`] if only one part's rows are held.
    fn whole(&self) -> Result<(), Error> {
        match self.held {
            Some((part, parts)) => Err(Error::PartOnly { part, parts }),
            None => Ok(()),
        }
    }

    /// The `b × b` blocks on the diagonal of `S_H` (original numbering): block `k` holds
    /// the entries `(b k + r, b k + c)`, `r, c < b`, row-major, block after block (length
    /// `n b`); e.g. `b = 1` the diagonal. For preconditioners (docs/math.md §12,
    /// "Implicit steps"); costs `O(n b²)` entry look-ups, each a search of its row's leaf
    /// blocks.
    ///
    /// # Errors
    /// [`Error::PartOnly`] if only one part's rows are held; [`Error::Option`] named
    /// `block` unless `b` divides `n`.
    pub fn diagonal_blocks(&self, b: usize) -> Result<Vec<f64>, Error> {
        self.whole()?;
        if b == 0 || self.n % b != 0 {
            return Err(Error::Option {
                name: "block",
                value: b as f64,
                expected: "a positive divisor of the matrix's dimension",
            });
        }
        let mut iperm = vec![0; self.n];
        for (p, &i) in self.perm.iter().enumerate() {
            iperm[i] = p;
        }
        let mut out = Vec::with_capacity(self.n * b);
        for k in 0..self.n / b {
            for r in 0..b {
                for c in 0..b {
                    out.push(self.entry_in_cluster_order(iperm[b * k + r], iperm[b * k + c]));
                }
            }
        }
        Ok(out)
    }

    /// `S_H` as a dense matrix (original numbering), for checks; `n²` memory.
    ///
    /// # Panics
    /// If the matrix holds only one part's rows ([`from_entries_part`](Self::from_entries_part)).
    pub fn to_dense(&self) -> Mat<f64> {
        assert!(
            self.held.is_none(),
            "to_dense of an ℋ-matrix holding one part's rows"
        );
        let mut iperm = vec![0; self.n];
        for (p, &i) in self.perm.iter().enumerate() {
            iperm[i] = p;
        }
        Mat::from_fn(self.n, self.n, |i, j| {
            self.entry_in_cluster_order(iperm[i], iperm[j])
        })
    }
}

fn to_column_major(m: MatRef<'_, f64>) -> Vec<f64> {
    let mut d = Vec::with_capacity(m.nrows() * m.ncols());
    for j in 0..m.ncols() {
        d.extend((0..m.nrows()).map(|i| m[(i, j)]));
    }
    d
}

/// `‖B − U Vᵀ‖_F²`.
fn low_rank_error2(b: MatRef<'_, f64>, lr: &LowRank) -> f64 {
    let (m, n) = (b.nrows(), b.ncols());
    let mut r = b.to_owned();
    if lr.rank > 0 {
        let u = MatRef::from_column_major_slice(&lr.u, m, lr.rank);
        let v = MatRef::from_column_major_slice(&lr.v, n, lr.rank);
        matmul(&mut r, Accum::Add, u, v.transpose(), -1.0, Par::Seq);
    }
    let mut e = 0.0;
    for j in 0..n {
        for i in 0..m {
            e += r[(i, j)] * r[(i, j)];
        }
    }
    e
}
