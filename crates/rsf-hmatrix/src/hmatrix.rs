//! The hierarchical matrix: set-up from a dense matrix or from an entry function, and the
//! allocation-free product (docs/math.md §13).

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};
use rayon::prelude::*;

use crate::block::{partition, BlockShape};
use crate::cluster::ClusterTree;
use crate::error::Error;
use crate::lowrank::{aca, recompress, svd_truncate, LowRank};
use crate::options::{ErrorMeasure, HOptions, SetupReport};
use crate::points::Points;

/// The data of a block.
#[derive(Debug, Clone)]
enum Data {
    /// `nrows × ncols`, column-major.
    Dense(Vec<f64>),
    /// `U Vᵀ` and the scratch `t = Vᵀ x` of the product.
    LowRank(LowRank, Vec<f64>),
}

#[derive(Debug, Clone)]
struct Block {
    shape: BlockShape,
    data: Data,
}

/// A leaf cluster of rows, with the blocks that reach it and its part of the product.
#[derive(Debug, Clone)]
struct Segment {
    start: usize,
    /// `(block, first row of the block inside the segment)`, in block order.
    parts: Vec<(usize, usize)>,
    /// Scratch: the segment's rows of `S_H x` in cluster order.
    z: Vec<f64>,
}

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
    /// Scratch: `x` in cluster order.
    xp: Vec<f64>,
    report: SetupReport,
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
                    let t = vec![0.0; lr.rank];
                    Data::LowRank(lr, t)
                }
                None => Data::Dense(to_column_major(dense.as_ref())),
            };
            blocks.push(Block { shape, data });
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

    /// Builds the matrix from its entries `entry(i, j)` (row `i`, column `j`, original
    /// numbering, one point per row/column), evaluating only the near-field blocks in full
    /// and `O(k (m + n))` entries of each admissible `m × n` block: adaptive cross
    /// approximation with partial pivoting to `ε/10`, then recompression (QR of both
    /// factors, SVD of the small core) to `0.9 ε` (docs/math.md §13.3). The way to matrices
    /// too large to form densely. The ACA stopping test is a heuristic (exact for the
    /// asymptotically smooth kernels it is meant for, not a bound); the error in the
    /// [report](Self::report) is estimated on a random sample of
    /// [`HOptions::error_samples`] entries (all entries if `n²` is not larger).
    ///
    /// # Errors
    /// Invalid options; [`Error::NonFiniteEntry`] if `entry` returns NaN or infinity for
    /// an entry it is asked for (entries ACA never evaluates are not seen);
    /// [`Error::Svd`] if an SVD does not converge.
    pub fn from_entries<F>(mut entry: F, points: &Points, options: &HOptions) -> Result<Self, Error>
    where
        F: FnMut(usize, usize) -> f64,
    {
        options.validate()?;
        let n = points.len();
        let tree = ClusterTree::new(points, options.leaf_size);
        let perm = tree.perm.clone();
        let mut checked = |i: usize, j: usize| -> Result<f64, Error> {
            let v = entry(i, j);
            if v.is_finite() {
                Ok(v)
            } else {
                Err(Error::NonFiniteEntry { row: i, col: j })
            }
        };
        let mut blocks = Vec::new();
        for shape in partition(&tree, options.eta) {
            let mut local = |i: usize, j: usize| checked(perm[shape.row + i], perm[shape.col + j]);
            let lr = if shape.admissible {
                aca(shape.nrows, shape.ncols, &mut local, options.epsilon / 10.0)?
            } else {
                None
            };
            let data = match lr {
                Some(lr) => {
                    let lr = recompress(&lr, shape.nrows, shape.ncols, 0.9 * options.epsilon)?;
                    let t = vec![0.0; lr.rank];
                    Data::LowRank(lr, t)
                }
                None => {
                    let mut d = Vec::with_capacity(shape.nrows * shape.ncols);
                    for j in 0..shape.ncols {
                        for i in 0..shape.nrows {
                            d.push(local(i, j)?);
                        }
                    }
                    Data::Dense(d)
                }
            };
            blocks.push(Block { shape, data });
        }
        let mut h = Self::assemble(tree, blocks, 0.0, ErrorMeasure::Exact);
        // Error estimate on a sample of entries.
        let total = n * n;
        let (mut e2, mut s2) = (0.0, 0.0);
        let mut iperm = vec![0; n];
        for (p, &i) in h.perm.iter().enumerate() {
            iperm[i] = p;
        }
        let mut add = |i: usize, j: usize| -> Result<(), Error> {
            let exact = checked(i, j)?;
            let approx = h.entry_in_cluster_order(iperm[i], iperm[j]);
            e2 += (exact - approx).powi(2);
            s2 += exact * exact;
            Ok(())
        };
        let measure = if total <= options.error_samples {
            for j in 0..n {
                for i in 0..n {
                    add(i, j)?;
                }
            }
            ErrorMeasure::Exact
        } else {
            let mut rng = SplitMix64(options.seed);
            for _ in 0..options.error_samples {
                let k = rng.below(total as u64) as usize;
                add(k % n, k / n)?;
            }
            ErrorMeasure::Sampled {
                samples: options.error_samples,
            }
        };
        h.report.relative_error = if s2 > 0.0 { (e2 / s2).sqrt() } else { 0.0 };
        h.report.error_measure = measure;
        Ok(h)
    }

    fn assemble(
        tree: ClusterTree,
        blocks: Vec<Block>,
        relative_error: f64,
        error_measure: ErrorMeasure,
    ) -> Self {
        let n = tree.perm.len();
        let leaves = tree.leaves();
        let segments = leaves
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
                    parts,
                    z: vec![0.0; c.len()],
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
        };
        let mut rank_sum = 0;
        for b in &blocks {
            match &b.data {
                Data::Dense(d) => {
                    report.dense_blocks += 1;
                    report.stored_entries += d.len();
                }
                Data::LowRank(lr, _) => {
                    report.low_rank_blocks += 1;
                    report.stored_entries += lr.u.len() + lr.v.len();
                    report.max_rank = report.max_rank.max(lr.rank);
                    rank_sum += lr.rank;
                }
            }
        }
        if report.low_rank_blocks > 0 {
            report.mean_rank = rank_sum as f64 / report.low_rank_blocks as f64;
        }
        Self {
            n,
            perm: tree.perm,
            blocks,
            segments,
            xp: vec![0.0; n],
            report,
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
                let (i, j) = (off + p - seg.start, q - sh.col);
                return match &b.data {
                    Data::Dense(d) => d[j * sh.nrows + i],
                    Data::LowRank(lr, _) => (0..lr.rank)
                        .map(|l| lr.u[l * sh.nrows + i] * lr.v[l * sh.ncols + j])
                        .sum(),
                };
            }
        }
        0.0
    }

    /// `y ← y + α S_H x` (original numbering). Allocates nothing; the result is bit-identical
    /// from run to run and for every `par`: low-rank blocks first form `t = Vᵀ x` each,
    /// then every leaf cluster of rows sums its blocks in a fixed order (fixed-order
    /// kernels independent of memory alignment; docs/math.md §13.5). `Par::Rayon(k)` with
    /// `k > 1` runs both phases on rayon's current thread pool.
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
        let n = self.n;
        if x.len() != n {
            return Err(Error::VectorLength {
                name: "x",
                len: x.len(),
                expected: n,
            });
        }
        if y.len() != n {
            return Err(Error::VectorLength {
                name: "y",
                len: y.len(),
                expected: n,
            });
        }
        if !alpha.is_finite() {
            return Err(Error::Option {
                name: "alpha",
                value: alpha,
                expected: "finite",
            });
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(Error::NonFiniteInput(i));
        }
        for (xp, &i) in self.xp.iter_mut().zip(&self.perm) {
            *xp = x[i];
        }
        let parallel = matches!(par, Par::Rayon(k) if k.get() > 1);
        let xp = &self.xp;
        if parallel {
            self.blocks.par_iter_mut().for_each(|b| project(b, xp));
            let blocks = &self.blocks;
            self.segments
                .par_iter_mut()
                .for_each(|s| accumulate(s, blocks, xp));
        } else {
            self.blocks.iter_mut().for_each(|b| project(b, xp));
            let blocks = &self.blocks;
            self.segments
                .iter_mut()
                .for_each(|s| accumulate(s, blocks, xp));
        }
        for s in &self.segments {
            for (k, z) in s.z.iter().enumerate() {
                y[self.perm[s.start + k]] += alpha * z;
            }
        }
        Ok(())
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

    /// `S_H` as a dense matrix (original numbering), for checks; `n²` memory.
    pub fn to_dense(&self) -> Mat<f64> {
        let mut iperm = vec![0; self.n];
        for (p, &i) in self.perm.iter().enumerate() {
            iperm[i] = p;
        }
        Mat::from_fn(self.n, self.n, |i, j| {
            self.entry_in_cluster_order(iperm[i], iperm[j])
        })
    }
}

/// `t = Vᵀ x_σ` for a low-rank block.
fn project(b: &mut Block, xp: &[f64]) {
    if let Data::LowRank(lr, t) = &mut b.data {
        let (col, nc) = (b.shape.col, b.shape.ncols);
        let xs = &xp[col..col + nc];
        for (l, tl) in t.iter_mut().enumerate() {
            *tl = dot(&lr.v[l * nc..(l + 1) * nc], xs);
        }
    }
}

/// The segment's rows of `S_H x`, its blocks summed in order.
fn accumulate(s: &mut Segment, blocks: &[Block], xp: &[f64]) {
    s.z.fill(0.0);
    let len = s.z.len();
    for &(k, off) in &s.parts {
        let b = &blocks[k];
        let sh = b.shape;
        match &b.data {
            Data::Dense(d) => {
                let xs = &xp[sh.col..sh.col + sh.ncols];
                for (j, &xj) in xs.iter().enumerate() {
                    let c = &d[j * sh.nrows + off..j * sh.nrows + off + len];
                    axpy(&mut s.z, xj, c);
                }
            }
            Data::LowRank(lr, t) => {
                for (l, &tl) in t.iter().enumerate() {
                    let c = &lr.u[l * sh.nrows + off..l * sh.nrows + off + len];
                    axpy(&mut s.z, tl, c);
                }
            }
        }
    }
}

/// `z ← z + a c`, element by element (no reordering, vectorisable).
#[inline]
fn axpy(z: &mut [f64], a: f64, c: &[f64]) {
    for (zi, ci) in z.iter_mut().zip(c) {
        *zi += a * ci;
    }
}

/// Dot product with eight fixed partial sums (vectorisable, same bits on every machine
/// with IEEE f64 and no fused multiply-add contraction, which Rust never does implicitly).
#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 8];
    let (ca, cb) = (a.chunks_exact(8), b.chunks_exact(8));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..8 {
            acc[k] += x[k] * y[k];
        }
    }
    let mut tail = 0.0;
    for (x, y) in ra.iter().zip(rb) {
        tail += x * y;
    }
    ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7])) + tail
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

/// SplitMix64 (Steele, Lea, Flood 2014): the sample of the error estimate.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..bound` (`bound > 0`), by rejection.
    fn below(&mut self, bound: u64) -> u64 {
        let zone = u64::MAX - u64::MAX % bound;
        loop {
            let r = self.next();
            if r < zone {
                return r % bound;
            }
        }
    }
}
