//! `S_N`'s rows shared out to the ranks of a fault ODE (docs/scaling.md, "The fault ODE
//! on MPI ranks"): each rank sums its part of the reactions `r = ΔG a + S_N (u_F − u_F⁰)`,
//! one all-gather gives every rank every reaction, and every rank makes them into `σ̄_n`
//! and checks them in node order ([`NormalCoupling::finish`]). Each reaction is summed by
//! the arithmetic of the whole product (a dense row over the columns in order; an
//! ℋ-matrix's row by its fixed-order kernels, the same for every split of its leaf
//! clusters), so `σ̄_n` and its errors have the bits of the whole evaluation on every rank,
//! at every rank count.

use std::ops::Range;

use rsf_hmatrix::HMatrix;

use super::{add_dense_rows, NormalCoupling, SlipToNormal};
use crate::error::Result;

/// `S_N`'s rows split into parts, one per rank ([`NormalCoupling::split_rows`]).
pub(crate) struct NormalRows {
    /// Each part's rows: node indices of a dense `S_N`; positions in the cluster order of
    /// an ℋ-matrix's (`Square`). Fewer than the ranks where the ℋ-matrix has fewer leaf
    /// clusters: the other ranks sum nothing.
    ranges: Vec<Range<usize>>,
    /// An ℋ-matrix's permutation to cluster order (empty for a dense `S_N`): a copy, read
    /// while the matrix is borrowed by its own product.
    perm: Vec<usize>,
}

impl NormalRows {
    /// `sigma ← sigma + S_N x` for an ℋ-matrix `h` split for ranks: its parts in turn on
    /// the calling thread, each row's bits those of `h.apply_add(x, sigma, 1.0, _)` (its
    /// `y += α z`), the split kept (a whole product would split the rows for its threads).
    ///
    /// # Errors
    /// As [`HMatrix::apply_part`] ([`rsf_hmatrix::Error::NonFiniteInput`] for a
    /// non-finite `x`, nothing added).
    pub(super) fn add_every_part(
        &self,
        h: &mut HMatrix,
        x: &[f64],
        sigma: &mut [f64],
    ) -> std::result::Result<(), rsf_hmatrix::Error> {
        for part in 0..self.ranges.len() {
            h.apply_part(x, part, |p| {
                for (q, z) in p.rows.zip(p.z) {
                    sigma[self.perm[q]] += 1.0 * z;
                }
            })?;
        }
        Ok(())
    }
}

/// The ranks' all-gather, `(own, counts, all)` as
/// [`RankGroup::all_gather`](rsf_ranks::RankGroup::all_gather)'s arguments.
pub(crate) type AllGather<'a> = &'a mut dyn FnMut(&[f64], &[usize], &mut [f64]);

/// What the ranks exchange for `σ̄_n` (made by [`NormalGather::new`], then reused): the
/// number of reactions each rank sums, this rank's and everyone's.
pub(crate) struct NormalGather {
    rank: usize,
    counts: Vec<usize>,
    own: Vec<f64>,
    all: Vec<f64>,
}

impl NormalGather {
    /// `S_N`'s rows of `normal` split into one part per rank of `ranks` ranks; `None` where
    /// they cannot be summed apart (a 3-D fault's `S_N` by components: evaluated whole on
    /// every rank).
    pub(crate) fn new(normal: &mut NormalCoupling, ranks: usize, rank: usize) -> Option<Self> {
        let counts = normal.split_rows(ranks)?;
        let own = vec![0.0; counts.get(rank).copied().unwrap_or(0)];
        let all = vec![0.0; counts.iter().sum()];
        Some(Self {
            rank,
            counts,
            own,
            all,
        })
    }

    /// The number of reactions exchanged per evaluation (every rank receives them all).
    pub(crate) fn values(&self) -> usize {
        self.all.len()
    }

    /// The reactions `r_k` (N) at integrated loading `big_g` and finite condensed unknowns
    /// `u_f` (length `m`) into `sigma` (one per frictional node, node order): this
    /// rank's, then one all-gather (`all_gather(own, counts, all)`, the ranks'
    /// [`RankGroup::all_gather`](rsf_ranks::RankGroup::all_gather)). Returns whether it
    /// exchanged: not where `u_F − u_F⁰` is not finite — the same on every rank, each then
    /// writing NaN, which [`NormalCoupling::finish`] refuses as the whole evaluation does.
    ///
    /// # Errors
    /// The ℋ-matrix product's (lengths: none for those set up here).
    pub(crate) fn reactions(
        &mut self,
        normal: &mut NormalCoupling,
        all_gather: AllGather<'_>,
        big_g: f64,
        u_f: &[f64],
        sigma: &mut [f64],
    ) -> Result<bool> {
        if !normal.part_reactions(big_g, u_f, self.rank, &mut self.own)? {
            sigma.fill(f64::NAN);
            return Ok(false);
        }
        all_gather(&self.own, &self.counts, &mut self.all);
        normal.place_reactions(&self.all, sigma);
        Ok(true)
    }
}

impl NormalCoupling {
    /// Splits `S_N`'s rows into `parts` parts (contiguous nodes of a dense `S_N`, whole
    /// leaf clusters of an ℋ-matrix's) and returns how many rows each part sums (length
    /// `parts`); `None` for a 3-D fault's `S_N` by components.
    fn split_rows(&mut self, parts: usize) -> Option<Vec<usize>> {
        let (ranges, perm) = match &mut self.s_n {
            SlipToNormal::Dense(s_n) => {
                let n = s_n.nrows();
                let ranges = (0..parts)
                    .map(|p| p * n / parts..(p + 1) * n / parts)
                    .collect();
                (ranges, Vec::new())
            }
            SlipToNormal::Square(h) => (h.split_rows(parts, 0.0), h.permutation().to_vec()),
            SlipToNormal::ByComponent(_) => return None,
        };
        let counts = (0..parts)
            .map(|p| ranges.get(p).map_or(0, Range::len))
            .collect();
        self.rows = Some(NormalRows { ranges, perm });
        Some(counts)
    }

    /// The reactions of part `part` into `own` (its length the part's rows), in the part's
    /// order. Returns `false` (nothing written) where `u_F − u_F⁰` is not finite.
    ///
    /// # Panics
    /// Before [`split_rows`](Self::split_rows), or for an `own` of another length (internal
    /// invariants of [`NormalGather`]).
    fn part_reactions(
        &mut self,
        big_g: f64,
        u_f: &[f64],
        part: usize,
        own: &mut [f64],
    ) -> Result<bool> {
        let rows = self
            .rows
            .as_ref()
            .expect("split before its parts are summed");
        let dg = big_g - self.g0;
        match &mut self.s_n {
            SlipToNormal::Dense(s_n) => {
                let Some(range) = rows.ranges.get(part) else {
                    return Ok(true);
                };
                // As the whole evaluation: `dg a`, then the columns in order.
                for (o, a) in own.iter_mut().zip(&self.loading[range.clone()]) {
                    *o = dg * a;
                }
                add_dense_rows(s_n, u_f, &self.u_f0, range.start, own);
                Ok(true)
            }
            SlipToNormal::Square(h) => {
                if part >= rows.ranges.len() {
                    // Every rank checks the same `u_F − u_F⁰`; this one sums no rows.
                    let finite = u_f
                        .iter()
                        .zip(&self.u_f0)
                        .all(|(u, u0)| (u - u0).is_finite());
                    return Ok(finite);
                }
                for ((d, u), u0) in self.du.iter_mut().zip(u_f).zip(&self.u_f0) {
                    *d = u - u0;
                }
                // As the whole product: `dg a_k`, then `+= 1.0 z` (its `y += α z`).
                let (loading, perm) = (&self.loading, &rows.perm);
                let summed = h.apply_part(&self.du, part, |p| {
                    for ((o, q), z) in own.iter_mut().zip(p.rows).zip(p.z) {
                        *o = dg * loading[perm[q]];
                        *o += 1.0 * z;
                    }
                });
                match summed {
                    Err(rsf_hmatrix::Error::NonFiniteInput(_)) => return Ok(false),
                    other => other?,
                }
                Ok(true)
            }
            SlipToNormal::ByComponent(_) => unreachable!("not split (split_rows: None)"),
        }
    }

    /// Every part's reactions (`all`: the parts concatenated in order) into `sigma` in node
    /// order.
    fn place_reactions(&self, all: &[f64], sigma: &mut [f64]) {
        let rows = self
            .rows
            .as_ref()
            .expect("split before its parts are placed");
        if rows.perm.is_empty() {
            // A dense `S_N`: contiguous nodes, part after part.
            sigma.copy_from_slice(all);
        } else {
            // An ℋ-matrix's cluster order, part after part.
            for (&k, v) in rows.perm.iter().zip(all) {
                sigma[k] = *v;
            }
        }
    }
}
