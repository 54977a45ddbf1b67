//! The product `S_H x` by parts of the rows (docs/math.md §13.5): the blocks' data, the
//! leaf clusters of rows ("segments"), and a split of the segments into contiguous parts
//! that run without synchronising each other — each part projects the low-rank blocks
//! that reach its rows (a block reaching two parts is projected by both, into each part's
//! own scratch) and sums its segments. Every row is summed by the same fixed-order
//! kernels whatever the split, so the product's bits do not depend on it.

use std::ops::Range;

use crate::block::BlockShape;
use crate::lowrank::LowRank;

/// The data of a block. Built column-major; [`HMatrix`](crate::HMatrix)'s assembly lays
/// the row-indexed factors (the dense block, `U`) out by row panels ([`to_row_panels`])
/// before any product.
#[derive(Debug, Clone)]
pub(crate) enum Data {
    /// `nrows × ncols`: column-major while built, by row panels once assembled.
    Dense(Vec<f64>),
    /// `U Vᵀ`: `U` column-major while built, by row panels once assembled; `V`
    /// column-major.
    LowRank(LowRank),
}

/// Rows per strip of a row panel: the product keeps a strip's partial sums in registers
/// (four SSE2 registers) while it runs along the strip's columns.
pub(crate) const STRIP: usize = 8;

/// `nrows × width` numbers `data`, column-major, laid out by row panels: for each leaf
/// cluster of the rows in order (`lens`, summing to `nrows`), its rows, strip by strip of
/// [`STRIP`] rows (the last strip of a leaf shorter), each strip column by column. The
/// panel of the leaf starting at row `o` begins at `o · width` ([`panel_index`] gives an
/// entry's place), so a leaf's product reads each block's panel as one contiguous run and
/// sums a strip's rows in registers (docs/math.md §13.5). The same numbers, moved: the
/// product adds them in the same order, its bits do not change.
pub(crate) fn to_row_panels(data: &[f64], nrows: usize, width: usize, lens: &[usize]) -> Vec<f64> {
    debug_assert_eq!(data.len(), nrows * width);
    debug_assert_eq!(lens.iter().sum::<usize>(), nrows);
    let mut out = Vec::with_capacity(data.len());
    let mut o = 0;
    for &len in lens {
        for s in (0..len).step_by(STRIP) {
            let w = STRIP.min(len - s);
            for j in 0..width {
                let from = j * nrows + o + s;
                out.extend_from_slice(&data[from..from + w]);
            }
        }
        o += len;
    }
    out
}

/// Where entry `(o + i, j)` lies in [`to_row_panels`]' layout of a factor `width` wide,
/// for the leaf of `len` rows starting at row `o` and `i < len`.
#[inline]
pub(crate) fn panel_index(o: usize, len: usize, width: usize, i: usize, j: usize) -> usize {
    let s = i - i % STRIP;
    let w = STRIP.min(len - s);
    o * width + s * width + j * w + (i - s)
}

#[derive(Debug, Clone)]
pub(crate) struct Block {
    pub shape: BlockShape,
    pub data: Data,
    /// Where the block's `t = Vᵀ x` lies in a part's projection scratch (low-rank blocks).
    pub t_offset: usize,
}

/// A leaf cluster of rows, with the blocks that reach it.
#[derive(Debug, Clone)]
pub(crate) struct Segment {
    /// First row (cluster order).
    pub start: usize,
    /// Number of rows.
    pub len: usize,
    /// `(block, first row of the block inside the segment)`, in block order.
    pub parts: Vec<(usize, usize)>,
}

/// One part of a [`Split`]: consecutive segments, the low-rank blocks that reach them and
/// the scratch of their projections.
#[derive(Debug, Clone)]
pub(crate) struct Part {
    segments: Range<usize>,
    rows: Range<usize>,
    low_rank: Vec<usize>,
    /// `t = Vᵀ x` of the blocks in `low_rank`, at their `t_offset`s (the other entries unused).
    t: Vec<f64>,
}

impl Part {
    /// The part's rows (cluster order).
    pub fn rows(&self) -> Range<usize> {
        self.rows.clone()
    }
}

/// The segments split into consecutive parts of about equal work.
#[derive(Debug, Clone)]
pub(crate) struct Split {
    parts: Vec<Part>,
    /// The number of parts asked for (more than there may be).
    requested: usize,
}

impl Split {
    /// `parts` parts (at least 1, at most one per segment) of about equal work: each
    /// segment's multiply-adds plus `work_per_row` per row (what a caller does with each
    /// row of the product inside the part).
    pub fn new(
        parts_requested: usize,
        work_per_row: f64,
        segments: &[Segment],
        blocks: &[Block],
        t_len: usize,
    ) -> Self {
        let work: Vec<f64> = segments
            .iter()
            .map(|s| {
                let sums: usize = s
                    .parts
                    .iter()
                    .map(|&(k, _)| match &blocks[k].data {
                        Data::Dense(_) => blocks[k].shape.ncols,
                        Data::LowRank(lr) => lr.rank,
                    })
                    .sum();
                (s.len * sums) as f64 + work_per_row * s.len as f64
            })
            .collect();
        let bounds = segment_bounds(&work, parts_requested);
        Self::from_bounds(&bounds, parts_requested, segments, blocks, t_len)
    }

    /// The parts `bounds[p]..bounds[p + 1]` of the segments (as [`segment_bounds`] gives
    /// them).
    pub fn from_bounds(
        bounds: &[usize],
        parts_requested: usize,
        segments: &[Segment],
        blocks: &[Block],
        t_len: usize,
    ) -> Self {
        let parts = bounds
            .windows(2)
            .map(|w| {
                let segs = w[0]..w[1];
                let rows = match (
                    segments.get(w[0]),
                    w[1].checked_sub(1).map(|e| &segments[e]),
                ) {
                    (Some(first), Some(last)) if w[0] < w[1] => first.start..last.start + last.len,
                    _ => 0..0,
                };
                let low_rank = blocks
                    .iter()
                    .enumerate()
                    .filter(|(_, b)| {
                        matches!(b.data, Data::LowRank(_))
                            && b.shape.row < rows.end
                            && rows.start < b.shape.row + b.shape.nrows
                    })
                    .map(|(k, _)| k)
                    .collect();
                Part {
                    segments: segs,
                    rows,
                    low_rank,
                    t: vec![0.0; t_len],
                }
            })
            .collect();
        Self {
            parts,
            requested: parts_requested,
        }
    }

    /// The number of parts the split was asked for.
    pub fn requested(&self) -> usize {
        self.requested
    }

    /// Number of parts.
    pub fn len(&self) -> usize {
        self.parts.len()
    }

    /// The parts, to run.
    pub fn parts_mut(&mut self) -> &mut [Part] {
        &mut self.parts
    }

    /// The rows (cluster order) of each part: consecutive, covering all rows.
    pub fn rows(&self) -> impl Iterator<Item = Range<usize>> + '_ {
        self.parts.iter().map(|p| p.rows.clone())
    }
}

/// Bounds `0 = b₀ < b₁ < … = work.len()` of at most `parts_requested` (at least 1, at
/// most one per segment) consecutive groups of segments of about equal total `work`: a
/// group ends once the work so far reaches its share of the total.
pub(crate) fn segment_bounds(work: &[f64], parts_requested: usize) -> Vec<usize> {
    let count = parts_requested.clamp(1, work.len().max(1));
    let total: f64 = work.iter().sum();
    let mut bounds = vec![0];
    let mut acc = 0.0;
    for (i, w) in work.iter().enumerate() {
        acc += w;
        let next = bounds.len();
        if next < count && acc >= total * next as f64 / count as f64 && i + 1 < work.len() {
            bounds.push(i + 1);
        }
    }
    bounds.push(work.len());
    bounds
}

/// What a part's product gives to the caller's function: its rows of `S_H x`.
#[derive(Debug)]
pub struct PartRows<'a> {
    /// The part's index (0-based, in cluster order).
    pub part: usize,
    /// The part's rows in cluster order: `z[i]` is row `rows.start + i` of `S_H x` in
    /// cluster order, i.e. row `permutation[rows.start + i]` in the original numbering.
    pub rows: Range<usize>,
    /// The rows' values of `S_H x`.
    pub z: &'a [f64],
}

/// The read-only data of a product.
pub(crate) struct Operands<'a> {
    pub blocks: &'a [Block],
    pub segments: &'a [Segment],
    /// `x` in cluster order.
    pub xp: &'a [f64],
}

/// Runs `parts` (with `z` their rows of the product, `states` one per part) on rayon's
/// current pool, halving recursively (no allocation), each part calling `f` with its rows
/// once they are summed. One part runs on the calling thread.
pub(crate) fn run_parts<S: Send, F: Fn(PartRows<'_>, &mut S) + Sync>(
    first: usize,
    parts: &mut [Part],
    z: &mut [f64],
    states: &mut [S],
    ops: &Operands<'_>,
    f: &F,
) {
    if parts.len() == 1 {
        let part = &mut parts[0];
        run_part(part, z, ops);
        f(
            PartRows {
                part: first,
                rows: part.rows.clone(),
                z,
            },
            &mut states[0],
        );
        return;
    }
    let half = parts.len() / 2;
    let (p_lo, p_hi) = parts.split_at_mut(half);
    let (z_lo, z_hi) = z.split_at_mut(p_hi[0].rows.start - p_lo[0].rows.start);
    let (s_lo, s_hi) = states.split_at_mut(half);
    rayon::join(
        || run_parts(first, p_lo, z_lo, s_lo, ops, f),
        || run_parts(first + half, p_hi, z_hi, s_hi, ops, f),
    );
}

/// One part: its projections, then its segments' rows into `z` (the part's rows).
pub(crate) fn run_part(part: &mut Part, z: &mut [f64], ops: &Operands<'_>) {
    for &k in &part.low_rank {
        let b = &ops.blocks[k];
        if let Data::LowRank(lr) = &b.data {
            project(b, lr, ops.xp, &mut part.t[b.t_offset..b.t_offset + lr.rank]);
        }
    }
    let base = part.rows.start;
    for s in &ops.segments[part.segments.clone()] {
        let zs = &mut z[s.start - base..s.start - base + s.len];
        accumulate(s, zs, ops.blocks, &part.t, ops.xp);
    }
}

/// `t = Vᵀ x_σ` for a low-rank block.
fn project(b: &Block, lr: &LowRank, xp: &[f64], t: &mut [f64]) {
    let (col, nc) = (b.shape.col, b.shape.ncols);
    let xs = &xp[col..col + nc];
    for (l, tl) in t.iter_mut().enumerate() {
        *tl = dot(&lr.v[l * nc..(l + 1) * nc], xs);
    }
}

/// The segment's rows of `S_H x` into `z`, its blocks summed in order (`t` holds the
/// projections of the low-rank ones).
fn accumulate(s: &Segment, z: &mut [f64], blocks: &[Block], t: &[f64], xp: &[f64]) {
    z.fill(0.0);
    let len = z.len();
    // Each block's panel of the segment's rows is contiguous (row panels): its columns in
    // order, `len` numbers each.
    for &(k, off) in &s.parts {
        let b = &blocks[k];
        let sh = b.shape;
        match &b.data {
            Data::Dense(d) => {
                let xs = &xp[sh.col..sh.col + sh.ncols];
                panel_axpy(z, xs, &d[off * sh.ncols..(off + len) * sh.ncols]);
            }
            Data::LowRank(lr) => {
                let ts = &t[b.t_offset..b.t_offset + lr.rank];
                panel_axpy(z, ts, &lr.u[off * lr.rank..(off + len) * lr.rank]);
            }
        }
    }
}

/// `z ← z + P a` for a leaf's panel `P` (`z.len() × a.len()`, by strips as
/// [`to_row_panels`] lays it out): each `z_i` gains `a_j P_ij` for `j = 0, 1, …` in turn,
/// the sums of a whole strip held in registers (no reordering, vectorisable).
#[inline]
fn panel_axpy(z: &mut [f64], a: &[f64], panel: &[f64]) {
    let width = a.len();
    if width == 0 {
        // A low-rank block of rank 0 (a block that is zero to ε): nothing to add.
        return;
    }
    for (zs, ps) in z.chunks_mut(STRIP).zip(panel.chunks(STRIP * width)) {
        if let Ok(zs) = <&mut [f64; STRIP]>::try_from(&mut *zs) {
            let mut acc = *zs;
            for (&aj, c) in a.iter().zip(ps.chunks_exact(STRIP)) {
                for k in 0..STRIP {
                    acc[k] += aj * c[k];
                }
            }
            *zs = acc;
        } else {
            let w = zs.len();
            for (&aj, c) in a.iter().zip(ps.chunks_exact(w)) {
                for (zk, ck) in zs.iter_mut().zip(c) {
                    *zk += aj * ck;
                }
            }
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// Numbers spread over eight decades with both signs: sums of them in another order
    /// round differently.
    fn numbers(len: usize, rng: &mut SplitMix64) -> Vec<f64> {
        (0..len)
            .map(|_| {
                let m = rng.below(1 << 30) as f64 / (1u64 << 30) as f64 - 0.5;
                m * 10f64.powi(rng.below(8) as i32 - 4)
            })
            .collect()
    }

    /// Leaves of 13, 8, 3 and 20 rows: full strips, short last strips, a leaf shorter than
    /// a strip.
    const LENS: [usize; 4] = [13, 8, 3, 20];

    #[test]
    fn row_panels_move_every_entry_to_its_panel_index() {
        let nrows: usize = LENS.iter().sum();
        for width in [0, 1, 5, 17] {
            let data: Vec<f64> = (0..nrows * width).map(|k| k as f64).collect();
            let panels = to_row_panels(&data, nrows, width, &LENS);
            assert_eq!(panels.len(), data.len());
            let mut seen = vec![false; data.len()];
            let mut o = 0;
            for &len in &LENS {
                for i in 0..len {
                    for j in 0..width {
                        let at = panel_index(o, len, width, i, j);
                        assert_eq!(panels[at], data[j * nrows + o + i], "({}, {j})", o + i);
                        seen[at] = true;
                    }
                }
                o += len;
            }
            assert!(
                seen.iter().all(|&s| s),
                "every place of the panels is an entry's"
            );
        }
    }

    /// The strip kernel adds each row's terms in the column order of the plain
    /// column-by-column `axpy` it replaced: the same bits, where summing the columns in
    /// reverse order changes some. Width 0 (a rank-0 block) adds nothing.
    #[test]
    fn the_panel_product_has_the_bits_of_the_column_by_column_sum() {
        let mut rng = SplitMix64::new(7);
        let nrows: usize = LENS.iter().sum();
        for width in [0, 1, 4, 9, 48] {
            let data = numbers(nrows * width, &mut rng);
            let a = numbers(width, &mut rng);
            let z0 = numbers(nrows, &mut rng);
            let panels = to_row_panels(&data, nrows, width, &LENS);
            let (mut forward, mut backward) = (z0.clone(), z0.clone());
            for j in 0..width {
                for i in 0..nrows {
                    forward[i] += a[j] * data[j * nrows + i];
                    let jr = width - 1 - j;
                    backward[i] += a[jr] * data[jr * nrows + i];
                }
            }
            let mut z = z0.clone();
            let mut o = 0;
            for &len in &LENS {
                let panel = &panels[o * width..(o + len) * width];
                panel_axpy(&mut z[o..o + len], &a, panel);
                o += len;
            }
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&z), bits(&forward), "width {width}");
            if width >= 9 {
                assert_ne!(
                    bits(&z),
                    bits(&backward),
                    "width {width}: orders not told apart"
                );
            }
        }
    }
}
