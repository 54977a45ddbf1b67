//! The fault ODE's elastic operators: the dense slip → traction matrix `S` from the
//! condensation, or its hierarchical (ℋ-matrix) compression ([`FaultKernel`]), with the
//! product every right-hand side needs and a report of what was stored. Shared by the
//! shear operator of [`FaultOde`](crate::FaultOde)(crate::FaultOde) and the normal-stress operator `S_N`.

use std::time::Instant;

use faer::{Accum, Mat, MatMut, MatRef, Par};
use rayon::prelude::*;
use rsf_hmatrix::{HMatrix, HOptions, Points};
use rsf_linalg::Parallelism;
use rsf_tnnmg::Condensation;

use crate::error::{invalid, Error, Result};
use crate::model::Model;

/// Largest relative accuracy ε of a [`FaultKernel::Hierarchical`]: a coarser operator
/// than 1 % no longer describes the elastic medium.
pub const MAX_KERNEL_EPSILON: f64 = 1e-2;

/// How a [`FaultOde`](crate::FaultOde) stores and applies the Schur complement `S` of its right-hand side.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum FaultKernel {
    /// The dense `m × m` matrix: `m²` f64 and `m²` multiply-adds per evaluation (`m` the
    /// number of free components on Γ_F). The default; exact up to round-off.
    #[default]
    Dense,
    /// An ℋ-matrix `S_H` of `S` (rsf-hmatrix, docs/math.md §13), compressed from the dense
    /// `S` at set-up with one point per condensed unknown (its node's coordinates, m, so
    /// that a node's components are coincident points, never separated by the
    /// admissibility condition): far-field blocks of low rank, near field dense; storage
    /// and product `O(k m log m)`. `‖S − S_H‖_F ≤ ε ‖S‖_F`, measured at set-up
    /// ([`FaultOde::kernel_report`](crate::FaultOde::kernel_report)).
    Hierarchical {
        /// Relative accuracy ε of every admissible block (Frobenius norm), in
        /// `(0, `[`MAX_KERNEL_EPSILON`]`]`. [`FaultKernel::matching`] ties it to the
        /// integrator's tolerance.
        epsilon: f64,
        /// Largest number of unknowns in a leaf cluster (≥ 1; 48 in
        /// [`FaultKernel::hierarchical`]).
        leaf_size: usize,
    },
}

impl FaultKernel {
    /// [`FaultKernel::Hierarchical`] with accuracy `epsilon` and rsf-hmatrix's default
    /// leaf size (48) and admissibility (η = 2).
    pub fn hierarchical(epsilon: f64) -> Self {
        Self::Hierarchical {
            epsilon,
            leaf_size: HOptions::default().leaf_size,
        }
    }

    /// The hierarchical kernel whose accuracy matches a run of Runge–Kutta `tolerance`
    /// ([`FaultOdeOptions::tolerance`](crate::fault_ode::FaultOdeOptions::tolerance)): `ε = tolerance` (capped at
    /// [`MAX_KERNEL_EPSILON`]). The operator's error then perturbs the stress by at most
    /// `ε ‖S‖_F ‖u_F‖`, a relative change of the right-hand side no larger than the
    /// relative local error each step is allowed, and in practice far smaller: ε bounds
    /// each far-field block against its own norm, and the measured `‖S − S_H‖_F/‖S‖_F` is
    /// about three orders of magnitude below ε on BP1 (docs/scaling.md, "Compressed fault
    /// operator"; docs/work-precision.md, "BP1: compressed kernel").
    pub fn matching(tolerance: f64) -> Self {
        Self::hierarchical(tolerance.min(MAX_KERNEL_EPSILON))
    }

    /// `"dense"` or `"hierarchical"`.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Dense => "dense",
            Self::Hierarchical { .. } => "hierarchical",
        }
    }

    /// Checks the kernel's parameters.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `kernel.epsilon` unless ε is in
    /// `(0, `[`MAX_KERNEL_EPSILON`]`]`, named `kernel.leaf_size` for a leaf size of 0.
    pub fn validate(&self) -> Result<()> {
        if let Self::Hierarchical { epsilon, leaf_size } = *self {
            if !(epsilon > 0.0 && epsilon <= MAX_KERNEL_EPSILON) {
                return Err(invalid(
                    "kernel.epsilon",
                    format!("{epsilon} must be in (0, {MAX_KERNEL_EPSILON}]"),
                ));
            }
            if leaf_size == 0 {
                return Err(invalid("kernel.leaf_size", "0 must be at least 1"));
            }
        }
        Ok(())
    }
}

/// `dense`, or `hierarchical epsilon=ε leaf_size=n` (ε as the shortest text that reads
/// back to it): the text a run's fingerprint holds.
impl std::fmt::Display for FaultKernel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Dense => write!(f, "dense"),
            Self::Hierarchical { epsilon, leaf_size } => {
                write!(f, "hierarchical epsilon={epsilon:e} leaf_size={leaf_size}")
            }
        }
    }
}

/// What the set-up of a [`FaultOde`](crate::FaultOde)'s kernel measured ([`FaultOde::kernel_report`](crate::FaultOde::kernel_report)).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct KernelReport {
    /// The kernel.
    pub kernel: FaultKernel,
    /// Number `m` of condensed unknowns (rows and columns of `S`).
    pub dim: usize,
    /// `‖S − S_H‖_F / ‖S‖_F` over every entry (0 for the dense kernel).
    pub relative_error: f64,
    /// f64 stored for the operator: `m²` dense; dense near-field entries plus
    /// `k (rows + columns)` per low-rank block hierarchical.
    pub stored_entries: usize,
    /// Blocks stored dense (1 for the dense kernel).
    pub dense_blocks: usize,
    /// Blocks stored low-rank (0 for the dense kernel).
    pub low_rank_blocks: usize,
    /// Largest rank of a low-rank block (0 if none).
    pub max_rank: usize,
    /// Time to compress `S` (s; 0 for the dense kernel), after the condensation.
    pub setup_seconds: f64,
}

impl KernelReport {
    /// `m² / stored_entries`: how many times smaller the operator is than dense (1 for
    /// the dense kernel; 0 for `m = 0`).
    pub fn compression_ratio(&self) -> f64 {
        if self.stored_entries == 0 {
            0.0
        } else {
            (self.dim * self.dim) as f64 / self.stored_entries as f64
        }
    }

    /// Bytes of the operator's entries (8 per stored f64).
    pub fn bytes(&self) -> usize {
        8 * self.stored_entries
    }
}

impl std::fmt::Display for KernelReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.kernel {
            FaultKernel::Dense => write!(
                f,
                "dense kernel: m = {}, {} f64 ({:.1} MB)",
                self.dim,
                self.stored_entries,
                self.bytes() as f64 / 1e6
            ),
            FaultKernel::Hierarchical { epsilon, leaf_size } => write!(
                f,
                "hierarchical kernel (ε = {epsilon:e}, leaf size {leaf_size}): m = {}, \
                 ‖S − S_H‖_F/‖S‖_F = {:.2e}, {} f64 ({:.1} MB, {:.1}× smaller than dense), \
                 blocks {} dense + {} low-rank, max rank {}, compressed in {:.2} s",
                self.dim,
                self.relative_error,
                self.stored_entries,
                self.bytes() as f64 / 1e6,
                self.compression_ratio(),
                self.dense_blocks,
                self.low_rank_blocks,
                self.max_rank,
                self.setup_seconds
            ),
        }
    }
}

/// The operator of the right-hand side (and the normal-stress operator `S_N`).
pub(crate) enum Kernel {
    Dense(Mat<f64>),
    Hierarchical(Box<HMatrix>),
}

impl Kernel {
    /// The ℋ-matrix of a hierarchical kernel.
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
    cond: &Condensation<C>,
    kind: FaultKernel,
) -> Result<(Kernel, KernelReport)> {
    let m = s.nrows();
    match kind {
        FaultKernel::Dense => Ok((
            Kernel::Dense(s),
            KernelReport {
                kernel: kind,
                dim: m,
                relative_error: 0.0,
                stored_entries: m * m,
                dense_blocks: 1,
                low_rank_blocks: 0,
                max_rank: 0,
                setup_seconds: 0.0,
            },
        )),
        FaultKernel::Hierarchical { epsilon, leaf_size } => {
            let clock = Instant::now();
            let coords: Vec<[f64; D]> = cond
                .interface_dofs()
                .iter()
                .map(|&dof| model.vertices[dof / C])
                .collect();
            let points = Points::from_array(&coords)?;
            let options = HOptions {
                epsilon,
                leaf_size,
                ..HOptions::default()
            };
            let h = HMatrix::from_dense(s.as_ref(), &points, &options)?;
            let r = h.report();
            let report = KernelReport {
                kernel: kind,
                dim: m,
                relative_error: r.relative_error,
                stored_entries: r.stored_entries,
                dense_blocks: r.dense_blocks,
                low_rank_blocks: r.low_rank_blocks,
                max_rank: r.max_rank,
                setup_seconds: clock.elapsed().as_secs_f64(),
            };
            Ok((Kernel::Hierarchical(Box::new(h)), report))
        }
    }
}
