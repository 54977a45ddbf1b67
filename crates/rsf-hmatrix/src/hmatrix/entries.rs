//! The ℋ-matrix from an entry function by adaptive cross approximation
//! ([`HMatrix::from_entries`]), whole or one part of its rows
//! ([`HMatrix::from_entries_part`]; docs/math.md §13.3).

use std::ops::Range;

use crate::aca::{compress_block, AcaParams};
use crate::block::{partition, BlockShape};
use crate::cluster::ClusterTree;
use crate::error::Error;
use crate::lowrank::recompress;
use crate::options::{ErrorMeasure, HOptions, RowPart};
use crate::points::Points;
use crate::product::{segment_bounds, Block, Data, Split};
use crate::rng::SplitMix64;

use super::HMatrix;

/// The rank an admissible block is taken to have in the work estimate of a split made
/// before the blocks are compressed ([`HMatrix::from_entries_part`]): BP5's half-space
/// operator's ranks at ε = 1e-6 lie between a few and 47 (docs/seas-bp5.md).
const ESTIMATED_RANK: usize = 16;

impl HMatrix {
    /// Builds the matrix from its entries `entry(i, j)` (row `i`, column `j`, original
    /// numbering, one point per row/column), evaluating only the near-field blocks in full
    /// and `O(k (m + n))` entries of each admissible `m × n` block: adaptive cross
    /// approximation ACA+ (Bebendorf & Grzhibovskis 2006: pivots from a reference row and
    /// a reference column kept as residuals) on each of the block's
    /// [`components`](HOptions::components)² component blocks, each stopped when its
    /// newest cross and a seeded random sample of its residual's entries (`m_a + n_b` of
    /// them) both estimate a remainder of at most `ε/(10 c)` of the block's estimated
    /// Frobenius norm; then recompression (QR of both factors, SVD of the small core) to
    /// `0.9 ε` (docs/math.md §13.3). The way to matrices too large to form densely. The
    /// stopping tests are estimates (sharp for the asymptotically smooth kernels ACA is
    /// meant for, not bounds); the error in the [report](Self::report) is estimated on a
    /// random sample of [`HOptions::error_samples`] entries (all entries if `n²` is not
    /// larger). Deterministic: every random choice is seeded by
    /// [`HOptions::seed`] and the block.
    ///
    /// # Errors
    /// Invalid options ([`HOptions::validate_for`]: also unless `n` is a multiple of the
    /// components); [`Error::NonFiniteEntry`] if `entry` returns NaN or infinity for an
    /// entry it is asked for (entries ACA never evaluates are not seen);
    /// [`Error::Svd`] if an SVD does not converge.
    pub fn from_entries<F>(entry: F, points: &Points, options: &HOptions) -> Result<Self, Error>
    where
        F: FnMut(usize, usize) -> f64,
    {
        Self::from_entries_in(entry, points, options, None)
    }

    /// As [`from_entries`](Self::from_entries), but only the blocks that reach the rows of
    /// part `row_part.part` of a split of the rows into `row_part.parts` parts — the share
    /// of one of `parts` processes, each building and holding its own rows (docs/scaling.md,
    /// "The fault ODE on MPI ranks"). The split is made before anything is compressed,
    /// from the block tree alone (whole leaf clusters; each row's work its near-field
    /// columns plus an estimated rank per admissible block), so every process makes the
    /// same split; it is the split of this matrix from then on ([`split_rows`](Self::split_rows)
    /// returns it whatever it is asked). Every block held is the block
    /// [`from_entries`](Self::from_entries) makes (the cross approximation of a block
    /// depends on its entries and its position only), so the part's rows of the product
    /// ([`apply_part`](Self::apply_part)) have the bits of the whole matrix's. The
    /// [report](Self::report) counts the blocks held (`part: Some((part, parts))`) and
    /// estimates the error on the samples that fall in the part's rows. Memory and
    /// set-up: about `1/parts` of the whole.
    ///
    /// # Errors
    /// As [`from_entries`](Self::from_entries); [`Error::Option`] named `part` for
    /// `parts == 0`, `part ≥ parts`, or a part beyond those made (fewer leaf clusters
    /// than parts).
    pub fn from_entries_part<F>(
        entry: F,
        points: &Points,
        options: &HOptions,
        row_part: RowPart,
    ) -> Result<Self, Error>
    where
        F: FnMut(usize, usize) -> f64,
    {
        Self::from_entries_in(entry, points, options, Some(row_part))
    }

    /// As [`from_entries`](Self::from_entries), the blocks built on rayon's current pool:
    /// `make_entry()` gives each block (and the error's sample) an entry function of its
    /// own, which may keep its own cache (e.g. a kernel that computes several entries at
    /// once). Every block and the report have the bits
    /// [`from_entries`](Self::from_entries) gives with the same entries, on any number of
    /// threads: a block's cross approximation depends on its entries and its position only.
    ///
    /// # Errors
    /// As [`from_entries`](Self::from_entries) (of the failing blocks, one is reported).
    pub fn from_entries_par<M, F>(
        make_entry: M,
        points: &Points,
        options: &HOptions,
    ) -> Result<Self, Error>
    where
        M: Fn() -> F + Sync,
        F: FnMut(usize, usize) -> f64,
    {
        Self::from_entries_par_in(make_entry, points, options, None)
    }

    /// [`from_entries_par`](Self::from_entries_par) of one part's rows, as
    /// [`from_entries_part`](Self::from_entries_part).
    ///
    /// # Errors
    /// As [`from_entries_part`](Self::from_entries_part).
    pub fn from_entries_part_par<M, F>(
        make_entry: M,
        points: &Points,
        options: &HOptions,
        row_part: RowPart,
    ) -> Result<Self, Error>
    where
        M: Fn() -> F + Sync,
        F: FnMut(usize, usize) -> f64,
    {
        Self::from_entries_par_in(make_entry, points, options, Some(row_part))
    }

    /// [`from_entries`](Self::from_entries) of every block, or of those of one part's rows.
    fn from_entries_in<F>(
        mut entry: F,
        points: &Points,
        options: &HOptions,
        row_part: Option<RowPart>,
    ) -> Result<Self, Error>
    where
        F: FnMut(usize, usize) -> f64,
    {
        let plan = Plan::new(points, options, row_part)?;
        let blocks = plan
            .held_shapes()
            .map(|shape| plan.block(shape, &mut entry))
            .collect::<Result<Vec<_>, _>>()?;
        plan.finish(blocks, &mut entry)
    }

    /// [`from_entries_par`](Self::from_entries_par) of every block, or of one part's rows.
    fn from_entries_par_in<M, F>(
        make_entry: M,
        points: &Points,
        options: &HOptions,
        row_part: Option<RowPart>,
    ) -> Result<Self, Error>
    where
        M: Fn() -> F + Sync,
        F: FnMut(usize, usize) -> f64,
    {
        use rayon::prelude::*;
        let plan = Plan::new(points, options, row_part)?;
        let shapes: Vec<BlockShape> = plan.held_shapes().collect();
        let blocks = shapes
            .into_par_iter()
            .map(|shape| plan.block(shape, &mut make_entry()))
            .collect::<Result<Vec<_>, _>>()?;
        plan.finish(blocks, &mut make_entry())
    }
}

/// What the set-up from entries decides before any entry is asked for: the cluster tree,
/// the blocks, and the part's rows if one part is built.
struct Plan<'a> {
    n: usize,
    options: &'a HOptions,
    tree: ClusterTree,
    shapes: Vec<BlockShape>,
    held: Option<(RowPart, PartRows)>,
}

/// A part's split of the leaf clusters ([`part_bounds`]) and its rows (cluster order).
type PartRows = (Vec<usize>, Range<usize>);

/// `entry(i, j)`, a non-finite value as [`Error::NonFiniteEntry`].
fn checked<F: FnMut(usize, usize) -> f64>(entry: &mut F, i: usize, j: usize) -> Result<f64, Error> {
    let v = entry(i, j);
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Error::NonFiniteEntry { row: i, col: j })
    }
}

impl<'a> Plan<'a> {
    fn new(
        points: &Points,
        options: &'a HOptions,
        row_part: Option<RowPart>,
    ) -> Result<Self, Error> {
        let n = points.len();
        options.validate_for(n)?;
        let tree = ClusterTree::new(points, options.leaf_size);
        let shapes = partition(&tree, options.eta);
        let held = match row_part {
            Some(rp) => Some((rp, part_bounds(&tree, &shapes, rp)?)),
            None => None,
        };
        Ok(Self {
            n,
            options,
            tree,
            shapes,
            held,
        })
    }

    /// The blocks that reach the rows held, in the block tree's order.
    fn held_shapes(&self) -> impl Iterator<Item = BlockShape> + '_ {
        self.shapes
            .iter()
            .copied()
            .filter(move |shape| match &self.held {
                Some((_, (_, rows))) => {
                    shape.row < rows.end && rows.start < shape.row + shape.nrows
                }
                None => true,
            })
    }

    /// One block: its cross approximation, recompressed, if admissible and worth it, else
    /// its entries.
    fn block<F: FnMut(usize, usize) -> f64>(
        &self,
        shape: BlockShape,
        entry: &mut F,
    ) -> Result<Block, Error> {
        let perm = &self.tree.perm;
        let options = self.options;
        let c = options.components;
        let mut local =
            |i: usize, j: usize| checked(entry, perm[shape.row + i], perm[shape.col + j]);
        let lr = if shape.admissible {
            let row_comp: Vec<usize> = (0..shape.nrows).map(|i| perm[shape.row + i] % c).collect();
            let col_comp: Vec<usize> = (0..shape.ncols).map(|j| perm[shape.col + j] % c).collect();
            let params = AcaParams {
                eps: options.epsilon / 10.0,
                components: c,
                seed: options.seed ^ ((shape.row as u64) << 32 | shape.col as u64),
            };
            compress_block(
                shape.nrows,
                shape.ncols,
                &row_comp,
                &col_comp,
                &mut local,
                params,
            )?
        } else {
            None
        };
        let data = match lr {
            Some(lr) => {
                let lr = recompress(&lr, shape.nrows, shape.ncols, 0.9 * options.epsilon)?;
                Data::LowRank(lr)
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
        Ok(Block {
            shape,
            data,
            t_offset: 0,
        })
    }

    /// The matrix of `blocks`, its split for a part, and the error estimated on a sample
    /// of `entry`'s entries (of the rows held).
    fn finish<F: FnMut(usize, usize) -> f64>(
        self,
        blocks: Vec<Block>,
        entry: &mut F,
    ) -> Result<HMatrix, Error> {
        let (n, options) = (self.n, self.options);
        let mut h = HMatrix::assemble(self.tree, blocks, 0.0, ErrorMeasure::Exact);
        let rows = match &self.held {
            Some((rp, (bounds, rows))) => {
                h.split = Split::from_bounds(bounds, rp.parts, &h.segments, &h.blocks, h.t_len);
                h.held = Some((rp.part, bounds.len() - 1));
                h.report.part = h.held;
                rows.clone()
            }
            None => 0..n,
        };
        // Error estimate on a sample of entries (of the rows held).
        let total = n * n;
        let (mut e2, mut s2) = (0.0, 0.0);
        let mut iperm = vec![0; n];
        for (p, &i) in h.perm.iter().enumerate() {
            iperm[i] = p;
        }
        let mut used = 0;
        let mut add = |i: usize, j: usize| -> Result<(), Error> {
            if !rows.contains(&iperm[i]) {
                return Ok(());
            }
            used += 1;
            let exact = checked(entry, i, j)?;
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
            let mut rng = SplitMix64::new(options.seed);
            for _ in 0..options.error_samples {
                let k = rng.below(total as u64) as usize;
                add(k % n, k / n)?;
            }
            ErrorMeasure::Sampled { samples: used }
        };
        h.report.relative_error = if s2 > 0.0 { (e2 / s2).sqrt() } else { 0.0 };
        h.report.error_measure = measure;
        Ok(h)
    }
}

/// The split of the leaf clusters of `tree` into `row_part.parts` parts of about equal
/// estimated work (each row: its near-field columns plus [`ESTIMATED_RANK`] per
/// admissible block, at most the block's size) and the rows (cluster order) of part
/// `row_part.part`.
///
/// # Errors
/// [`Error::Option`] named `part` for `parts == 0`, `part ≥ parts` or a part beyond those
/// made.
fn part_bounds(
    tree: &ClusterTree,
    shapes: &[BlockShape],
    row_part: RowPart,
) -> Result<PartRows, Error> {
    let refuse = |expected| Error::Option {
        name: "part",
        value: row_part.part as f64,
        expected,
    };
    if row_part.parts == 0 || row_part.part >= row_part.parts {
        return Err(refuse("a part < parts, parts ≥ 1"));
    }
    let leaves: Vec<(usize, usize)> = tree
        .leaves()
        .iter()
        .map(|&l| (tree.nodes[l].start, tree.nodes[l].end))
        .collect();
    let mut work = vec![0.0; leaves.len()];
    for b in shapes {
        let per_row = if b.admissible {
            ESTIMATED_RANK.min(b.nrows).min(b.ncols)
        } else {
            b.ncols
        };
        let first = leaves.partition_point(|&(start, _)| start < b.row);
        for (k, &(start, end)) in leaves.iter().enumerate().skip(first) {
            if start >= b.row + b.nrows {
                break;
            }
            work[k] += ((end - start) * per_row) as f64;
        }
    }
    let bounds = segment_bounds(&work, row_part.parts);
    if row_part.part + 1 >= bounds.len() {
        return Err(refuse(
            "a part of those made: fewer leaf clusters than parts",
        ));
    }
    let rows = leaves[bounds[row_part.part]].0..leaves[bounds[row_part.part + 1] - 1].1;
    Ok((bounds, rows))
}
