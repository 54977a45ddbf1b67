//! A [`HalfSpaceOperator`]'s rows split into parts for processes that share a fault ODE's
//! evaluations ([`FaultOperator::split_rows`](crate::fault_operator::FaultOperator::split_rows)):
//! by element, each part's nodes those of its elements of `K`.

use super::{HalfSpaceOperator, HalfSpaceOperatorError};
use crate::error::{invalid, Result};
use crate::fault_kernel::{no_split, KernelRows};
use crate::fault_operator::{FaultOperator, RowSplit};
use rsf_ranks::RankGroup;

/// The ranks of an operator that holds only this rank's part of the rows
/// ([`HalfSpaceOperator::fault_alone_on_ranks`]): the group, the split (one part per
/// rank) and the buffers of the whole product's all-gather.
pub(super) struct OnRanks {
    group: Box<dyn RankGroup + Send>,
    split: RowSplit,
    /// Values per rank (its part's rows).
    counts: Vec<usize>,
    /// This rank's rows of `r`, then of `r − S x`.
    own: Vec<f64>,
    /// Every rank's, in the split's order.
    all: Vec<f64>,
}

impl OnRanks {
    /// The split the ranks hold, for `parts` parts (one per rank).
    ///
    /// # Errors
    /// [`crate::Error::InvalidParameter`] named `ranks` for another number of parts.
    pub(super) fn split_for(&self, parts: usize) -> Result<RowSplit> {
        if parts != self.split.ranges.len() {
            return Err(invalid(
                "ranks",
                format!(
                    "the half-space operator holds the rows of {} ranks, not {parts}",
                    self.split.ranges.len()
                ),
            ));
        }
        Ok(self.split.clone())
    }
}

/// The split of a [`HalfSpaceOperator`]'s rows: `K`'s rows split by its kernel (an
/// element's two rows in one part), each part's nodes those of its elements.
pub(super) struct ElementRows {
    kernel: KernelRows,
    /// Per part, its nodes in the order of the split's rows (two rows per node).
    nodes: Vec<Vec<usize>>,
    /// Position of every row of `K` in the kernel's split order.
    position: Vec<usize>,
    /// `−K s` at a part's rows (scratch of the longest part).
    y: Vec<f64>,
}

impl HalfSpaceOperator {
    /// `K`'s rows split by its kernel; a node's two rows go to the part of its element's
    /// two rows of `K`, which the kernel keeps in one part (dense: blocks of 8 rows; ℋ:
    /// an element's two coincident points in one leaf cluster).
    ///
    /// # Errors
    /// [`crate::Error::InvalidParameter`] named `ranks` should an element's two rows fall in
    /// two parts (a kernel whose leaves separate them).
    pub(super) fn split_element_rows(
        &mut self,
        parts: usize,
        work_per_row: f64,
    ) -> Result<RowSplit> {
        let kernel = self.kernel.split_rows(parts, work_per_row);
        let mut position = vec![0; self.fault.len()];
        for (q, &i) in kernel.split.order.iter().enumerate() {
            position[i] = q;
        }
        let part_of = |q: usize| kernel.split.ranges.partition_point(|r| r.end <= q);
        let mut nodes = vec![Vec::new(); kernel.split.ranges.len()];
        for (k, &e) in self.element.iter().enumerate() {
            let (p, p1) = (part_of(position[2 * e]), part_of(position[2 * e + 1]));
            if p != p1 {
                return Err(crate::error::invalid(
                    "ranks",
                    format!("element {e}'s two rows of K fall in parts {p} and {p1}"),
                ));
            }
            nodes[p].push(k);
        }
        // Each part's nodes in the order of their element's first row in the part.
        for part in &mut nodes {
            part.sort_by_key(|&k| {
                position[2 * self.element[k]].min(position[2 * self.element[k] + 1])
            });
        }
        let mut order = Vec::with_capacity(self.dim());
        let mut ranges = Vec::with_capacity(nodes.len());
        for part in &nodes {
            let start = order.len();
            order.extend(part.iter().flat_map(|&k| [2 * k, 2 * k + 1]));
            ranges.push(start..order.len());
        }
        let longest = kernel
            .split
            .ranges
            .iter()
            .map(|r| r.len())
            .max()
            .unwrap_or(0);
        self.rows = Some(ElementRows {
            kernel,
            nodes,
            position,
            y: vec![0.0; longest],
        });
        Ok(RowSplit { order, ranges })
    }

    /// The part's rows of `−K s` (the kernel's part product on zeros, as
    /// [`subtract_product`](crate::fault_operator::FaultOperator::subtract_product) on the whole), then each of
    /// its nodes' two rows by the same arithmetic.
    pub(super) fn element_part_subtract(
        &mut self,
        x: &[f64],
        part: usize,
        r: &mut [f64],
    ) -> Result<()> {
        let mut s = std::mem::take(&mut self.s);
        self.scatter(x, &mut s);
        let rows = self.rows.as_mut().ok_or_else(no_split);
        let result = rows.and_then(|rows| {
            let (Some(range), Some(nodes)) = (
                rows.kernel.split.ranges.get(part).cloned(),
                rows.nodes.get(part),
            ) else {
                return Err(crate::error::invalid("ranks", format!("no part {part}")));
            };
            if r.len() != 2 * nodes.len() {
                return Err(crate::error::invalid(
                    "ranks",
                    format!("{} rows for a part of {}", r.len(), 2 * nodes.len()),
                ));
            }
            let y = &mut rows.y[..range.len()];
            y.fill(0.0);
            self.kernel.part_subtract(&rows.kernel, &s, part, y)?;
            for (j, &k) in nodes.iter().enumerate() {
                let (e, a, w) = (self.element[k], &self.map[k], self.weights[k]);
                let y = [
                    y[rows.position[2 * e] - range.start],
                    y[rows.position[2 * e + 1] - range.start],
                ];
                r[2 * j] += w * (a[0][0] * y[0] + a[1][0] * y[1]);
                r[2 * j + 1] += w * (a[0][1] * y[0] + a[1][1] * y[1]);
            }
            Ok(())
        });
        self.s = s;
        result
    }

    /// Shares the rows out to `group`, one part per rank (the kernel holds this rank's
    /// part only: [`HalfSpaceOperator::fault_alone_on_ranks`]).
    ///
    /// # Errors
    /// [`HalfSpaceOperatorError::Ranks`] if the kernel's rows give another number of
    /// parts than ranks, or a part cuts an element.
    pub(super) fn share_rows(
        &mut self,
        group: Box<dyn RankGroup + Send>,
    ) -> std::result::Result<(), HalfSpaceOperatorError> {
        let ranks = group.size();
        let refuse = |reason: String| HalfSpaceOperatorError::Ranks { ranks, reason };
        let split = self
            .split_element_rows(ranks, 0.0)
            .map_err(|e| refuse(e.to_string()))?;
        if split.ranges.len() != ranks {
            return Err(refuse(format!(
                "its rows give {} parts",
                split.ranges.len()
            )));
        }
        let counts: Vec<usize> = split.ranges.iter().map(|r| r.len()).collect();
        self.on_ranks = Some(OnRanks {
            own: vec![0.0; counts[group.rank()]],
            all: vec![0.0; self.dim()],
            counts,
            split,
            group,
        });
        Ok(())
    }

    /// `r ← r − S x` of an operator on ranks: this rank's rows
    /// ([`element_part_subtract`](Self::element_part_subtract) on its rows of `r`), then
    /// one all-gather; each row the bits of the whole operator's product. A non-finite
    /// `x` (the same on every rank) gives a NaN `r` on every rank without an exchange, as
    /// the ℋ-kernel's product does.
    pub(super) fn subtract_product_on_ranks(&mut self, x: &[f64], r: &mut [f64]) -> Result<()> {
        if x.iter().any(|v| !v.is_finite()) {
            r.fill(f64::NAN);
            return Ok(());
        }
        let mut on = self.on_ranks.take().expect("on ranks");
        let rank = on.group.rank();
        let range = on.split.ranges[rank].clone();
        for (o, &i) in on.own.iter_mut().zip(&on.split.order[range]) {
            *o = r[i];
        }
        let result = self.element_part_subtract(x, rank, &mut on.own);
        if result.is_ok() {
            on.group.all_gather(&on.own, &on.counts, &mut on.all);
            for (&i, &v) in on.split.order.iter().zip(&on.all) {
                r[i] = v;
            }
        }
        self.on_ranks = Some(on);
        result
    }
}
