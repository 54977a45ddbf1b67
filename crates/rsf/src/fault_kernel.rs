//! The fault ODE's condensed elastic operators: the dense slip → traction matrix `S` from
//! the condensation, or its hierarchical (ℋ-matrix) compression ([`FaultKernel`]), with
//! the product every right-hand side needs and a report of what was stored — the
//! finite-element [`FaultOperator`]. Shared by the shear operator of
//! [`FaultOde`](crate::FaultOde) and the normal-stress operator `S_N`.

use std::time::Instant;

use faer::{Accum, Mat, MatMut, MatRef, Par};
use rayon::prelude::*;
use rsf_direct::Condensation;
use rsf_hmatrix::{HMatrix, HOptions};
use rsf_linalg::Parallelism;

use crate::error::{Error, Result};
use crate::fault_operator::{FaultKernel, FaultOperator, KernelReport, RowSplit};
use crate::model::schur_columns::{components_per_node, interface_points};
use crate::model::Model;

/// The condensed finite-element operator `S` of a fault ODE: its kernel and the report of
/// its set-up.
pub(crate) struct CondensedOperator {
    kernel: Kernel,
    report: KernelReport,
    /// The split of [`FaultOperator::split_rows`], if any.
    rows: Option<KernelRows>,
}

impl FaultOperator for CondensedOperator {
    fn dim(&self) -> usize {
        self.report.dim
    }

    fn subtract_product(&mut self, x: &[f64], r: &mut [f64], par: Parallelism) -> Result<()> {
        self.kernel.subtract_product(x, r, par)
    }

    fn hierarchical_mut(&mut self) -> Option<&mut HMatrix> {
        self.kernel.hierarchical_mut()
    }

    fn report(&self) -> &KernelReport {
        &self.report
    }

    fn operator_origin(&self) -> crate::fault_operator::OperatorOrigin {
        crate::fault_operator::OperatorOrigin::FiniteElement
    }

    fn diagonal(&mut self, out: &mut [f64]) -> Result<()> {
        crate::fault_operator::check_diagonal(self.report.dim, out)?;
        out.copy_from_slice(&self.kernel.diagonal_blocks(1)?);
        Ok(())
    }

    fn split_rows(&mut self, parts: usize, work_per_row: f64) -> Result<RowSplit> {
        let rows = self.kernel.split_rows(parts, work_per_row);
        let split = rows.split.clone();
        self.rows = Some(rows);
        Ok(split)
    }

    fn part_subtract(&mut self, x: &[f64], part: usize, r: &mut [f64]) -> Result<()> {
        let rows = self.rows.as_ref().ok_or_else(no_split)?;
        self.kernel.part_subtract(rows, x, part, r)
    }
}

/// The error of a part's product asked for before any split.
pub(crate) fn no_split() -> Error {
    crate::error::invalid(
        "ranks",
        "a part of the product before the rows were split (FaultOperator::split_rows)",
    )
}

/// A [`Kernel`]'s rows split into parts ([`Kernel::split_rows`]) and what made the split,
/// so that it can be made again should another product have split the ℋ-matrix's rows
/// otherwise since.
pub(crate) struct KernelRows {
    parts: usize,
    work_per_row: f64,
    /// The parts (rows in the kernel's own numbering).
    pub(crate) split: RowSplit,
}

/// Where the entries of a condensed operator `S` come from: the condensation's factor
/// (its interface rows, [`Condensation::schur_entries`], or the dense product
/// [`Condensation::schur_complement`]), or a Schur complement computed without the factor
/// ([`rsf_direct::SchurOnly`]: packed rows of `S`).
pub(crate) enum SchurSource<'a, const C: usize> {
    /// The condensation of the whole factor.
    Factor(&'a Condensation<C>),
    /// `S` itself (packed rows of its lower triangle) on the interface dofs `dofs`.
    Packed {
        /// `S`.
        s: &'a rsf_direct::PackedSymmetric,
        /// The dof of each of its rows.
        dofs: &'a [usize],
    },
}

impl<const C: usize> SchurSource<'_, C> {
    /// Number `m` of condensed unknowns.
    fn dim(&self) -> usize {
        self.interface_dofs().len()
    }

    /// The dof of each condensed unknown.
    pub(crate) fn interface_dofs(&self) -> &[usize] {
        match self {
            Self::Factor(cond) => cond.interface_dofs(),
            Self::Packed { dofs, .. } => dofs,
        }
    }

    /// `S` dense (`m × m`).
    fn dense(&self) -> Mat<f64> {
        let m = self.dim();
        match self {
            Self::Factor(cond) => {
                let s_dense = cond.schur_complement();
                Mat::from_fn(m, m, |i, j| s_dense[j * m + i])
            }
            Self::Packed { s, .. } => Mat::from_fn(m, m, |i, j| s.entry(i, j)),
        }
    }
}

/// The condensed operator `S` of `source` as `kind` says: dense; hierarchical from the
/// dense `S` by truncated SVD on a 1-D or 2-D model (a fault line: `m` small, the tighter
/// compression, and the trajectories published with it), from its entries by cross
/// approximation on a 3-D model (from the factor: [`Condensation::schur_entries`], half of
/// one dense copy, no dense product; from a packed `S`: its entries as they are).
pub(crate) fn condensed_operator<const D: usize, const C: usize>(
    model: &Model<D, C>,
    source: &SchurSource<'_, C>,
    kind: FaultKernel,
) -> Result<CondensedOperator> {
    let m = source.dim();
    let (kernel, report) = match kind {
        FaultKernel::Hierarchical { epsilon, leaf_size } if D == 3 => {
            let clock = Instant::now();
            let options = HOptions {
                epsilon,
                leaf_size,
                components: components_per_node(source.interface_dofs(), C),
                ..HOptions::default()
            };
            let points = interface_points(model, source.interface_dofs())?;
            let (h, setup_bytes) = match source {
                SchurSource::Factor(cond) => {
                    let entries = cond.schur_entries();
                    let h = HMatrix::from_entries(|i, j| entries.entry(i, j), &points, &options)?;
                    (h, entries.bytes())
                }
                SchurSource::Packed { s, .. } => (
                    HMatrix::from_entries(|i, j| s.entry(i, j), &points, &options)?,
                    s.bytes(),
                ),
            };
            let report = KernelReport::hierarchical(kind, m, h.report(), setup_bytes, clock);
            (Kernel::Hierarchical(Box::new(h)), report)
        }
        _ => compress(source.dense(), model, source.interface_dofs(), kind)?,
    };
    Ok(CondensedOperator {
        kernel,
        report,
        rows: None,
    })
}

/// The operator of the right-hand side (and the normal-stress operator `S_N`).
pub(crate) enum Kernel {
    Dense(Mat<f64>),
    Hierarchical(Box<HMatrix>),
}

impl Kernel {
    /// Splits the rows into at most `parts` parts for [`part_subtract`](Self::part_subtract):
    /// dense, consecutive blocks of a multiple of 8 rows (each row's dot product then has
    /// the bits of the whole product's, as in its threaded form); ℋ, whole leaf clusters of
    /// about equal work ([`HMatrix::split_rows`]) in the cluster order.
    pub(crate) fn split_rows(&mut self, parts: usize, work_per_row: f64) -> KernelRows {
        let parts = parts.max(1);
        let split = match self {
            Self::Dense(s) => {
                let m = s.nrows();
                let rows = m.div_ceil(parts).next_multiple_of(ROW_BLOCK_ALIGN).max(1);
                RowSplit {
                    order: (0..m).collect(),
                    ranges: (0..m.div_ceil(rows).max(1))
                        .map(|b| b * rows..((b + 1) * rows).min(m))
                        .collect(),
                }
            }
            Self::Hierarchical(h) => RowSplit {
                ranges: h.split_rows(parts, work_per_row),
                order: h.permutation().to_vec(),
            },
        };
        KernelRows {
            parts,
            work_per_row,
            split,
        }
    }

    /// `r ← r − (S x)` at part `part`'s rows of `rows` (in its order; `x` finite): the bits
    /// of [`subtract_product`](Self::subtract_product) at those rows.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `ranks` for a part or a length that does not
    /// fit `rows`; the ℋ-product's errors (a non-finite `x`).
    pub(crate) fn part_subtract(
        &mut self,
        rows: &KernelRows,
        x: &[f64],
        part: usize,
        r: &mut [f64],
    ) -> Result<()> {
        let range = rows.split.ranges.get(part).cloned().ok_or_else(|| {
            crate::error::invalid(
                "ranks",
                format!("part {part} of {} parts", rows.split.ranges.len()),
            )
        })?;
        if r.len() != range.len() || x.len() != rows.split.order.len() {
            return Err(crate::error::invalid(
                "ranks",
                format!(
                    "a part of {} rows and an x of {} for a part of {} rows of {}",
                    r.len(),
                    x.len(),
                    range.len(),
                    rows.split.order.len()
                ),
            ));
        }
        match self {
            Self::Dense(s) => {
                let xm = MatRef::from_column_major_slice(x, x.len(), 1);
                faer::linalg::matmul::matmul(
                    MatMut::from_column_major_slice_mut(r, range.len(), 1),
                    Accum::Add,
                    s.as_ref().subrows(range.start, range.len()),
                    xm,
                    -1.0,
                    Par::Seq,
                );
                Ok(())
            }
            Self::Hierarchical(h) => {
                // Another product (with another thread count) may have split the rows
                // since: the same call splits them as before.
                for again in [false, true] {
                    let done = h.apply_part(x, part, |p| {
                        if p.rows != range {
                            return false;
                        }
                        // As `apply_add`'s `y[i] += alpha * z` with alpha = −1.
                        for (ri, z) in r.iter_mut().zip(p.z) {
                            *ri += -1.0 * z;
                        }
                        true
                    });
                    match done {
                        Ok(true) => return Ok(()),
                        // Split otherwise (fewer parts, or other rows): split again.
                        Ok(false) | Err(rsf_hmatrix::Error::VectorLength { name: "part", .. })
                            if !again =>
                        {
                            h.split_rows(rows.parts, rows.work_per_row);
                        }
                        Ok(false) => break,
                        Err(e) => return Err(e.into()),
                    }
                }
                Err(crate::error::invalid(
                    "ranks",
                    "the ℋ-matrix's rows split again gave other parts than before",
                ))
            }
        }
    }

    /// The ℋ-matrix of a hierarchical kernel.
    /// The `b × b` blocks on the diagonal (row-major, block after block; `b` divides the
    /// dimension): the dense matrix's entries, or the ℋ-matrix's
    /// ([`HMatrix::diagonal_blocks`]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `block` unless `b` divides the dimension; the
    /// ℋ-matrix's (a matrix holding one part's rows).
    pub(crate) fn diagonal_blocks(&self, b: usize) -> Result<Vec<f64>> {
        match self {
            Self::Dense(s) => {
                let n = s.nrows();
                if b == 0 || n % b != 0 {
                    return Err(crate::error::invalid(
                        "block",
                        format!("{b} does not divide the dimension {n}"),
                    ));
                }
                let mut out = Vec::with_capacity(n * b);
                for k in 0..n / b {
                    for r in 0..b {
                        for c in 0..b {
                            out.push(s[(b * k + r, b * k + c)]);
                        }
                    }
                }
                Ok(out)
            }
            Self::Hierarchical(h) => Ok(h.diagonal_blocks(b)?),
        }
    }

    pub(crate) fn hierarchical_mut(&mut self) -> Option<&mut HMatrix> {
        match self {
            Self::Dense(_) => None,
            Self::Hierarchical(h) => Some(h),
        }
    }

    /// `r ← r − S x` on `par`'s threads, bit-identical for every `par`. A non-finite `x`
    /// (a trial stage that blew up) gives a NaN `r`, as the dense product does, so that
    /// the step is rejected.
    pub(crate) fn subtract_product(
        &mut self,
        x: &[f64],
        r: &mut [f64],
        par: Parallelism,
    ) -> Result<()> {
        match self {
            Self::Dense(s) => {
                dense_subtract_product(s.as_ref(), x, r, par);
                Ok(())
            }
            Self::Hierarchical(h) => match h.apply_add(x, r, -1.0, par.faer()) {
                Err(rsf_hmatrix::Error::NonFiniteInput(_)) => {
                    r.fill(f64::NAN);
                    Ok(())
                }
                other => other.map_err(Error::from),
            },
        }
    }
}

/// Rows per block of the parallel dense product: a multiple of 8 so that every block
/// starts at the same 64-byte alignment within each column as in the whole product.
const ROW_BLOCK_ALIGN: usize = 8;

/// `r ← r − S x` for the dense `S`: one sequential faer product, or with more than one
/// thread one product per block of rows (each row's dot product in the same order, so the
/// same bits).
fn dense_subtract_product(s: MatRef<'_, f64>, x: &[f64], r: &mut [f64], par: Parallelism) {
    let m = r.len();
    let xm = MatRef::from_column_major_slice(x, m, 1);
    if !par.is_parallel() || m < 2 * ROW_BLOCK_ALIGN {
        faer::linalg::matmul::matmul(
            MatMut::from_column_major_slice_mut(r, m, 1),
            Accum::Add,
            s,
            xm,
            -1.0,
            Par::Seq,
        );
        return;
    }
    let rows = m.div_ceil(par.threads()).next_multiple_of(ROW_BLOCK_ALIGN);
    r.par_chunks_mut(rows).enumerate().for_each(|(b, rb)| {
        let len = rb.len();
        faer::linalg::matmul::matmul(
            MatMut::from_column_major_slice_mut(rb, len, 1),
            Accum::Add,
            s.subrows(b * rows, len),
            xm,
            -1.0,
            Par::Seq,
        );
    });
}

/// The kernel of `kind` from the dense `s` (moved in, dropped if compressed) and its
/// report. Points: each condensed unknown at its node's coordinates.
pub(crate) fn compress<const D: usize, const C: usize>(
    s: Mat<f64>,
    model: &Model<D, C>,
    interface: &[usize],
    kind: FaultKernel,
) -> Result<(Kernel, KernelReport)> {
    let m = s.nrows();
    match kind {
        FaultKernel::Dense => Ok((Kernel::Dense(s), KernelReport::dense(m))),
        FaultKernel::Hierarchical { epsilon, leaf_size } => {
            let clock = Instant::now();
            let points = interface_points::<D, C>(model, interface)?;
            let options = HOptions {
                epsilon,
                leaf_size,
                ..HOptions::default()
            };
            let h = HMatrix::from_dense(s.as_ref(), &points, &options)?;
            // Measured on every entry: no samples.
            let report = KernelReport::hierarchical(kind, m, h.report(), 8 * m * m, clock);
            Ok((Kernel::Hierarchical(Box::new(h)), report))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fault_operator::MAX_KERNEL_EPSILON;
    use crate::model::{Material, ModelBuilder, Part};

    /// A 3-D fault's ℋ-kernel built from the factor's entries (no dense `S`) applies `S`
    /// to within its ε: against the dense Schur complement on random vectors, with the
    /// sampled error estimate in the report; the two slip components are its interleaved
    /// components.
    #[test]
    fn a_3d_hierarchical_kernel_from_entries_matches_the_dense_operator() {
        let cube = rsf_fem::cuboid([-1.0; 3], [2.0; 3], [5, 33, 17]).unwrap();
        let model = ModelBuilder::new(cube)
            .material(Material::new(1e10, 0.25, 2700.0))
            .without_mass()
            .dirichlet(Part::predicate("minus", |x| x[0] < -1.0 + 1e-9), [0.0; 3])
            .dirichlet(Part::predicate("plus", |x| x[0] > 1.0 - 1e-9), [0.0; 3])
            .internal_fault_polygon(
                "fault",
                &[
                    [0.0, -1.0, -1.0],
                    [0.0, 1.0, -1.0],
                    [0.0, 1.0, 1.0],
                    [0.0, -1.0, 1.0],
                ],
            )
            .build()
            .unwrap();
        let fb = &model.frictional_boundary;
        let cond =
            Condensation::<3>::new(model.stiffness.as_ref(), &model.fixed, &fb.nodes).unwrap();
        let m = cond.dim();
        // The coarsest accuracy a kernel may have: the blocks of this small fault compress
        // only there once each pair of the two slip components is approximated apart.
        let epsilon = MAX_KERNEL_EPSILON;
        let kind = FaultKernel::Hierarchical {
            epsilon,
            leaf_size: 48,
        };
        let mut op = condensed_operator(&model, &SchurSource::Factor(&cond), kind).unwrap();
        let report = op.report().clone();
        eprintln!("{report}");
        assert_eq!(report.dim, m);
        assert!(report.low_rank_blocks > 0, "no block compressed: {report}");
        assert!(report.error_samples > 0);
        assert_eq!(report.setup_bytes, 4 * m * (m + 1));
        assert!(report.relative_error <= epsilon, "{report}");
        let s = cond.schur_complement();
        let mut worst = 0.0f64;
        for seed in 0..4u64 {
            let x: Vec<f64> = (0..m)
                .map(|i| ((i as u64 * 2654435761 + seed * 97) % 1000) as f64 / 500.0 - 1.0)
                .collect();
            let mut exact = vec![0.0; m];
            for j in 0..m {
                for i in 0..m {
                    exact[i] -= s[j * m + i] * x[j];
                }
            }
            let mut approx = vec![0.0; m];
            op.subtract_product(&x, &mut approx, Parallelism::SEQ)
                .unwrap();
            let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
            let diff: Vec<f64> = exact.iter().zip(&approx).map(|(a, b)| a - b).collect();
            worst = worst.max(norm(&diff) / norm(&exact));
        }
        eprintln!("‖(S − S_H) x‖ / ‖S x‖ ≤ {worst:e} (ε = {epsilon:e}, m = {m})");
        assert!(worst <= 10.0 * epsilon, "{worst:e}");
    }
}
