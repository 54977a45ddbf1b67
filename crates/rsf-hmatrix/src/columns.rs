//! Set-up from whole columns of a symmetric matrix (docs/math.md §13.6): the columns are
//! asked for once each, in batches of whole leaf clusters in cluster order; each batch
//! fills the near-field blocks it reaches and extends an orthonormal column basis of
//! every admissible block it reaches (projection, then a truncated SVD of what the basis
//! misses); a block is recompressed once its last column has been seen. Nothing `n × n`
//! is formed; the set-up holds two batches, the blocks and the sampled columns of the
//! error estimate.

use std::ops::Range;
use std::time::Instant;

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, Par};
use rayon::prelude::*;

use crate::block::BlockShape;
use crate::cluster::ClusterTree;
use crate::error::{ColumnsError, Error};
use crate::lowrank::{
    max_useful_rank, thin_svd_seq, truncation_rank, truncation_rank_below, LowRank,
};
use crate::options::HOptions;
use crate::product::{Block, Data};
use crate::rng::SplitMix64;

/// What the streaming set-up leaves for the matrix and its report.
pub(crate) struct Built {
    pub blocks: Vec<Block>,
    /// `‖S‖_F²`, every entry seen.
    pub norm2: f64,
    /// `Σ_B bound_B²`, the blocks' error bounds in squares.
    pub bound2: f64,
    /// The sampled columns: `(column, S e_column)` (original numbering), by column.
    pub sampled: Vec<(usize, Vec<f64>)>,
    pub batches: usize,
    pub largest_batch: usize,
    pub columns_computed: usize,
    pub peak_bytes: usize,
    pub oracle_seconds: f64,
}

/// A block while its columns come in.
enum State {
    /// No column seen yet.
    Empty,
    /// Near field (or an admissible block whose rank grew past the point where dense is
    /// cheaper): `nrows × ncols` column-major, filled column by column; the error bound
    /// carried over from a low-rank phase.
    Dense(Vec<f64>, f64),
    /// An admissible block's basis and coefficients so far.
    Building(Basis),
    /// Every column seen: the data and a bound on `‖B − B_H‖_F`.
    Done(Data, f64),
}

impl State {
    /// Logical size in bytes.
    fn bytes(&self) -> usize {
        8 * match self {
            State::Empty => 0,
            State::Dense(d, _) => d.len(),
            State::Building(b) => b.len(),
            State::Done(Data::Dense(d), _) => d.len(),
            State::Done(Data::LowRank(lr), _) => lr.u.len() + lr.v.len(),
        }
    }
}

/// `B(:, seen) ≈ Q Cᵀ`: `Q` (`nrows × r`) with orthonormal columns, and for each batch of
/// columns `(first column in the block, coefficients r_then × columns)`; a batch's
/// coefficients on directions added later are zero.
struct Basis {
    q: Mat<f64>,
    chunks: Vec<(usize, Mat<f64>)>,
    /// `Σ` over the batches of the squared norms discarded.
    err2: f64,
}

impl Basis {
    fn len(&self) -> usize {
        self.q.nrows() * self.q.ncols()
            + self
                .chunks
                .iter()
                .map(|(_, c)| c.nrows() * c.ncols())
                .sum::<usize>()
    }

    /// Adds the columns `c` (`nrows × b`, block columns `first..first + b`): their
    /// projection on `Q` (classical Gram–Schmidt, twice), the SVD of the rest truncated
    /// where the discarded part's `‖·‖_F² ≤ eps² ‖c‖_F²` (no SVD when the whole rest is
    /// that small), the kept directions appended to `Q`.
    fn extend(&mut self, mut c: Mat<f64>, first: usize, eps: f64) -> Result<(), Error> {
        let (nr, b) = c.shape();
        let norm2 = frob2(&c);
        let r = self.q.ncols();
        let mut coef = Mat::<f64>::zeros(r, b);
        if r > 0 {
            let mut p = Mat::<f64>::zeros(r, b);
            for _ in 0..2 {
                matmul(
                    &mut p,
                    Accum::Replace,
                    self.q.transpose(),
                    &c,
                    1.0,
                    Par::Seq,
                );
                matmul(&mut c, Accum::Add, &self.q, &p, -1.0, Par::Seq);
                coef += &p;
            }
        }
        let bound = eps * eps * norm2;
        let rest = frob2(&c);
        if rest <= bound {
            // The basis holds these columns to the tolerance: no new direction (what the
            // SVD's truncation would find, without the SVD).
            self.err2 += rest;
            self.chunks.push((first, coef));
            return Ok(());
        }
        let (u, sigma, v) = thin_svd_seq(c.as_ref())?;
        let (t, tail) = truncation_rank_below(&sigma, bound);
        self.err2 += tail;
        let mut q = Mat::<f64>::zeros(nr, r + t);
        for l in 0..r {
            q.col_mut(l).copy_from(self.q.col(l));
        }
        for l in 0..t {
            q.col_mut(r + l).copy_from(u.col(l));
        }
        let mut all = Mat::<f64>::zeros(r + t, b);
        for k in 0..b {
            for l in 0..r {
                all[(l, k)] = coef[(l, k)];
            }
            for l in 0..t {
                all[(r + l, k)] = sigma[l] * v[(k, l)];
            }
        }
        self.q = q;
        self.chunks.push((first, all));
        Ok(())
    }

    /// `Q Cᵀ` as a dense block (`nrows × ncols` column-major, columns not seen zero).
    fn to_dense(&self, ncols: usize) -> Vec<f64> {
        let v = self.coefficients(ncols);
        let mut d = Mat::<f64>::zeros(self.q.nrows(), ncols);
        matmul(
            &mut d,
            Accum::Replace,
            &self.q,
            v.transpose(),
            1.0,
            Par::Seq,
        );
        col_major(&d)
    }

    /// `C` (`ncols × r`).
    fn coefficients(&self, ncols: usize) -> Mat<f64> {
        let mut v = Mat::<f64>::zeros(ncols, self.q.ncols());
        for (first, coef) in &self.chunks {
            for k in 0..coef.ncols() {
                for l in 0..coef.nrows() {
                    v[(first + k, l)] = coef[(l, k)];
                }
            }
        }
        v
    }

    /// The block `Q Cᵀ` recompressed to relative accuracy `eps` (SVD of `C`, `Q` being
    /// orthonormal), or dense if its rank would store no fewer numbers; with the bound
    /// on `‖B − B_H‖_F`.
    fn finish(self, ncols: usize, eps: f64) -> Result<(Data, f64), Error> {
        let nr = self.q.nrows();
        let r = self.q.ncols();
        let batch_err = self.err2.sqrt();
        if r == 0 {
            let lr = LowRank {
                u: Vec::new(),
                v: Vec::new(),
                rank: 0,
            };
            return Ok((Data::LowRank(lr), batch_err));
        }
        let c = self.coefficients(ncols);
        let (y, sigma, z) = thin_svd_seq(c.as_ref())?;
        let t = truncation_rank(&sigma, eps);
        if t > max_useful_rank(nr, ncols) {
            return Ok((Data::Dense(self.to_dense(ncols)), batch_err));
        }
        let tail: f64 = sigma[t..].iter().map(|s| s * s).sum();
        // Q C ᵀ = Q Z Σ Yᵀ.
        let w = Mat::<f64>::from_fn(r, t, |i, l| z[(i, l)] * sigma[l]);
        let mut u = Mat::<f64>::zeros(nr, t);
        matmul(&mut u, Accum::Replace, &self.q, &w, 1.0, Par::Seq);
        let mut v = Vec::with_capacity(ncols * t);
        for l in 0..t {
            v.extend((0..ncols).map(|j| y[(j, l)]));
        }
        let lr = LowRank {
            u: col_major(&u),
            v,
            rank: t,
        };
        Ok((Data::LowRank(lr), batch_err + tail.sqrt()))
    }
}

fn frob2(m: &Mat<f64>) -> f64 {
    let mut s = 0.0;
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            s += m[(i, j)] * m[(i, j)];
        }
    }
    s
}

fn col_major(m: &Mat<f64>) -> Vec<f64> {
    let mut d = Vec::with_capacity(m.nrows() * m.ncols());
    for j in 0..m.ncols() {
        d.extend((0..m.nrows()).map(|i| m[(i, j)]));
    }
    d
}

/// The batches: consecutive leaf clusters (cluster-order ranges) gathered until a batch
/// holds at least `batch` columns.
fn batches(tree: &ClusterTree, batch: usize) -> Vec<Range<usize>> {
    let mut out: Vec<Range<usize>> = Vec::new();
    for leaf in tree.leaves() {
        let c = &tree.nodes[leaf];
        match out.last_mut() {
            Some(last) if last.len() < batch => last.end = c.end,
            _ => out.push(c.start..c.end),
        }
    }
    out
}

/// `count` distinct columns of `0..n`, seeded (partial Fisher–Yates), sorted.
fn sample_columns(n: usize, count: usize, seed: u64) -> Vec<usize> {
    let count = count.min(n);
    let mut all: Vec<usize> = (0..n).collect();
    let mut rng = SplitMix64::new(seed ^ 0xC01D_C01D_C01D_C01D);
    for k in 0..count {
        let r = k + rng.below((n - k) as u64) as usize;
        all.swap(k, r);
    }
    let mut out = all[..count].to_vec();
    out.sort_unstable();
    out
}

/// One call of the oracle: the columns `perm[range]` into an `n × len` panel, checked.
fn compute<C, E>(
    columns: &C,
    perm: &[usize],
    range: Range<usize>,
) -> Result<(Mat<f64>, f64), ColumnsError<E>>
where
    C: Fn(&[usize], MatMut<'_, f64>) -> Result<(), E>,
{
    let n = perm.len();
    let idx = &perm[range];
    let mut panel = Mat::<f64>::zeros(n, idx.len());
    let clock = Instant::now();
    columns(idx, panel.as_mut()).map_err(|source| ColumnsError::Oracle {
        first: idx[0],
        columns: idx.len(),
        source,
    })?;
    let seconds = clock.elapsed().as_secs_f64();
    for (k, &col) in idx.iter().enumerate() {
        for row in 0..n {
            if !panel[(row, k)].is_finite() {
                return Err(Error::NonFiniteEntry { row, col }.into());
            }
        }
    }
    Ok((panel, seconds))
}

/// Streams every column once through the blocks `shapes` of `tree` (docs/math.md §13.6).
pub(crate) fn build<C, E>(
    columns: &C,
    tree: &ClusterTree,
    shapes: Vec<BlockShape>,
    options: &HOptions,
) -> Result<Built, ColumnsError<E>>
where
    C: Fn(&[usize], MatMut<'_, f64>) -> Result<(), E> + Sync,
    E: Send,
{
    let perm = &tree.perm;
    let n = perm.len();
    let ranges = batches(tree, options.column_batch);
    let sampled_cols = sample_columns(n, options.error_columns, options.seed);
    let mut sampled: Vec<(usize, Vec<f64>)> = Vec::with_capacity(sampled_cols.len());
    let mut states: Vec<State> = shapes.iter().map(|_| State::Empty).collect();
    let (eps_batch, eps_final) = (options.epsilon / 10.0, 0.9 * options.epsilon);
    let mut built = Built {
        blocks: Vec::new(),
        norm2: 0.0,
        bound2: 0.0,
        sampled: Vec::new(),
        batches: ranges.len(),
        largest_batch: ranges.iter().map(|r| r.len()).max().unwrap_or(0),
        columns_computed: 0,
        peak_bytes: 0,
        oracle_seconds: 0.0,
    };
    let mut next = match ranges.first() {
        Some(r) => Some(compute(columns, perm, r.clone())?),
        None => None,
    };
    for (b, range) in ranges.iter().enumerate() {
        let Some((panel, seconds)) = next.take() else {
            break;
        };
        built.oracle_seconds += seconds;
        built.columns_computed += range.len();
        // The next batch's columns while this one is compressed.
        let (following, done) = rayon::join(
            || {
                ranges
                    .get(b + 1)
                    .map(|r| compute(columns, perm, r.clone()))
                    .transpose()
            },
            || -> Result<(), Error> {
                states
                    .par_iter_mut()
                    .zip(shapes.par_iter())
                    .try_for_each(|(state, shape)| {
                        update(state, shape, perm, &panel, range, eps_batch, eps_final)
                    })
            },
        );
        next = following?;
        done?;
        for (k, &col) in perm[range.clone()].iter().enumerate() {
            built.norm2 += frob2_col(&panel, k);
            if sampled_cols.binary_search(&col).is_ok() {
                sampled.push((col, (0..n).map(|i| panel[(i, k)]).collect()));
            }
        }
        let held = 8 * n * (range.len() + ranges.get(b + 1).map_or(0, |r| r.len()));
        let samples = 8 * n * sampled.len();
        let blocks: usize = states.iter().map(State::bytes).sum();
        built.peak_bytes = built.peak_bytes.max(held + samples + blocks);
    }
    sampled.sort_by_key(|(c, _)| *c);
    built.sampled = sampled;
    for (state, shape) in states.into_iter().zip(shapes) {
        let (data, err) = match state {
            State::Done(data, err) => (data, err),
            // Only for an empty matrix (every block sees its last column).
            _ => (Data::Dense(vec![0.0; shape.nrows * shape.ncols]), 0.0),
        };
        built.bound2 += err * err;
        built.blocks.push(Block {
            shape,
            data,
            t_offset: 0,
        });
    }
    Ok(built)
}

fn frob2_col(panel: &Mat<f64>, k: usize) -> f64 {
    (0..panel.nrows())
        .map(|i| panel[(i, k)] * panel[(i, k)])
        .sum()
}

/// Feeds the block `shape` the columns of the batch `range` (cluster order) from `panel`
/// (rows in original numbering, column `k` = cluster-order column `range.start + k`).
#[expect(
    clippy::too_many_arguments,
    reason = "one block's state, its shape and the batch it is fed: the loop body of the set-up, called in one place"
)]
fn update(
    state: &mut State,
    shape: &BlockShape,
    perm: &[usize],
    panel: &Mat<f64>,
    range: &Range<usize>,
    eps_batch: f64,
    eps_final: f64,
) -> Result<(), Error> {
    let lo = range.start.max(shape.col);
    let hi = range.end.min(shape.col + shape.ncols);
    if lo >= hi {
        return Ok(());
    }
    let (nr, nc) = (shape.nrows, shape.ncols);
    if matches!(state, State::Empty) {
        *state = if shape.admissible {
            State::Building(Basis {
                q: Mat::zeros(nr, 0),
                chunks: Vec::new(),
                err2: 0.0,
            })
        } else {
            State::Dense(vec![0.0; nr * nc], 0.0)
        };
    }
    let rows = &perm[shape.row..shape.row + nr];
    let mut to_dense = None;
    match state {
        State::Dense(d, _) => {
            for j in lo..hi {
                let (k, jb) = (j - range.start, j - shape.col);
                for (i, &row) in rows.iter().enumerate() {
                    d[jb * nr + i] = panel[(row, k)];
                }
            }
        }
        State::Building(basis) => {
            let c = Mat::<f64>::from_fn(nr, hi - lo, |i, k| panel[(rows[i], lo - range.start + k)]);
            basis.extend(c, lo - shape.col, eps_batch)?;
            if basis.q.ncols() > max_useful_rank(nr, nc) {
                // Cheaper dense: what is seen so far from the basis, the rest exactly.
                to_dense = Some((basis.to_dense(nc), basis.err2.sqrt()));
            }
        }
        State::Empty | State::Done(..) => {}
    }
    if let Some((d, err)) = to_dense {
        *state = State::Dense(d, err);
    }
    if hi == shape.col + nc {
        let old = std::mem::replace(state, State::Empty);
        *state = match old {
            State::Dense(d, err) => State::Done(Data::Dense(d), err),
            State::Building(basis) => {
                let (data, err) = basis.finish(nc, eps_final)?;
                State::Done(data, err)
            }
            other => other,
        };
    }
    Ok(())
}
