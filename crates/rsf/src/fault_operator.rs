//! The seam between the fault ODE and its elastic operator: slip on the fault → change of
//! the traction force on the fault ([`FaultOperator`]). The finite-element model's exact
//! condensation (dense, or an ℋ-matrix) is one implementation; a boundary-element
//! half-space operator on the same unknowns is another (docs/math.md §12, "The fault
//! operator").

use std::ops::Range;
use std::time::Instant;

use rsf_hmatrix::{ErrorMeasure, HMatrix, HOptions, SetupReport};
use rsf_linalg::Parallelism;

use crate::error::{invalid, Result};

/// The elastic operator `S` of a [`FaultOde`](crate::FaultOde): `m` slip unknowns (the
/// free tangential components of the frictional nodes, node by node in
/// `model.frictional_boundary.nodes` order, components in the node's frame order; m) to
/// the forces on them (N: traction times the node's weight), so that the quasi-static
/// balance of the fault ODE reads `g(t) − S u_F = w (τ(V, α) + η V)` node by node.
///
/// `S` is symmetric and positive semi-definite for any elastic medium (it is the energy's
/// Hessian restricted to the fault). Implementations must be deterministic: the same `x`
/// gives the same bits, whatever `par`.
pub trait FaultOperator: Send {
    /// Number `m` of slip unknowns (rows and columns of `S`).
    fn dim(&self) -> usize;

    /// `r ← r − S x` (`x`, `r` of length [`dim`](Self::dim)) on `par`'s threads (rayon's
    /// current pool), bit-identical for every `par`. A non-finite `x` (a trial stage that
    /// blew up) must give a non-finite `r`, not an error: the step is then rejected.
    ///
    /// # Errors
    /// Errors of the implementation's product (not for non-finite input).
    fn subtract_product(&mut self, x: &[f64], r: &mut [f64], par: Parallelism) -> Result<()>;

    /// The ℋ-matrix, if the operator is one: the fault ODE then sums each thread's rows of
    /// the product and solves their nodes in one task (one parallel region per evaluation).
    /// Default `None`: the product, then the node solves.
    fn hierarchical_mut(&mut self) -> Option<&mut HMatrix> {
        None
    }

    /// What the set-up stored and measured.
    fn report(&self) -> &KernelReport;

    /// Where the operator comes from (what its entries are the Green's functions of,
    /// [`GreensFunctions`](crate::greens::GreensFunctions)). Default
    /// [`OperatorOrigin::Other`].
    fn operator_origin(&self) -> OperatorOrigin {
        OperatorOrigin::Other
    }

    /// The unit slip direction (Cartesian) each unknown measures, one per unknown, where
    /// the operator defines its own components rather than the model's frames — a fault
    /// alone on boundary elements
    /// ([`ElementOperator::fault_alone`](crate::halfspace_operator::ElementOperator::fault_alone):
    /// each element's strike, then up-dip direction) — so that
    /// [`GreensFunctions`](crate::greens::GreensFunctions) describes them without being
    /// told. Default `None`: the unknowns are the model's components (its pair frames or
    /// Cartesian axes).
    fn slip_directions(&self) -> Option<&[[f64; 3]]> {
        None
    }

    /// The diagonal of `S` (N/m, length [`dim`](Self::dim)) into `out`: the cheap part
    /// of the fault ODE's Jacobian that its implicit steps precondition with
    /// (docs/math.md §12, "Implicit steps"). The default takes one product per unknown
    /// (`dim` products, exact); the stored kernels (dense, ℋ, the half-space and element
    /// operators) read their entries instead.
    ///
    /// # Errors
    /// The product's errors; [`Error::InvalidParameter`](crate::Error::InvalidParameter)
    /// named `diagonal` for an `out` of another length.
    fn diagonal(&mut self, out: &mut [f64]) -> Result<()> {
        diagonal_by_products(self, out)
    }

    /// Splits the rows of `S` into at most `parts` (≥ 1) parts of about equal work — each
    /// row's multiply-adds plus `work_per_row` (what the caller does per row, in
    /// multiply-adds) — for processes that share a fault ODE's evaluations
    /// ([`FaultOde::share_evaluations`](crate::FaultOde::share_evaluations); docs/scaling.md,
    /// "The fault ODE on MPI ranks"): one part per process, each computing its rows with
    /// [`part_subtract`](Self::part_subtract) alone. Deterministic: the same call gives the
    /// same split. The split is kept until the next call.
    ///
    /// # Errors
    /// The default: [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
    /// `ranks` (an operator whose rows cannot be computed apart). Implementations: their
    /// own errors.
    fn split_rows(&mut self, parts: usize, work_per_row: f64) -> Result<RowSplit> {
        let _ = (parts, work_per_row);
        Err(invalid(
            "ranks",
            "this fault operator cannot compute its rows apart (FaultOperator::split_rows)",
        ))
    }

    /// `r ← r − (S x)` at the rows of part `part` of the last
    /// [`split_rows`](Self::split_rows), in the split's order (`r` has the part's length;
    /// `x` finite, of length [`dim`](Self::dim)): every row's bits those
    /// [`subtract_product`](Self::subtract_product) gives it, for every split.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `ranks` before
    /// any split (the default: rows not computed apart) or for a part or a length that
    /// does not fit; the product's errors.
    fn part_subtract(&mut self, x: &[f64], part: usize, r: &mut [f64]) -> Result<()> {
        let _ = (x, part, r);
        Err(invalid(
            "ranks",
            "this fault operator cannot compute its rows apart (FaultOperator::part_subtract)",
        ))
    }
}

/// What a [`FaultOperator`] is the operator of ([`FaultOperator::operator_origin`]): the medium
/// and method whose slip → force map it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OperatorOrigin {
    /// The finite-element body condensed exactly onto the fault (any heterogeneous
    /// volume the model holds; docs/math.md §12).
    FiniteElement,
    /// Okada's rectangles on a planar grid in a half-space
    /// ([`HalfSpaceOperator`](crate::halfspace_operator::HalfSpaceOperator)).
    OkadaGrid,
    /// Boundary elements of any set (rectangles of any orientation, triangles; a
    /// half-space or the whole space;
    /// [`ElementOperator`](crate::halfspace_operator::ElementOperator)).
    BoundaryElements,
    /// A homogeneous whole space in closed form (antiplane, or a planar grid).
    WholeSpace,
    /// An operator that does not say (a user's own).
    Other,
}

impl OperatorOrigin {
    /// Every origin, in the order of [`code`](Self::code).
    pub const ALL: [Self; 5] = [
        Self::FiniteElement,
        Self::OkadaGrid,
        Self::BoundaryElements,
        Self::WholeSpace,
        Self::Other,
    ];

    /// `finite_element`, `okada_grid`, `boundary_elements`, `whole_space` or `other`: the
    /// text files hold.
    pub fn code(&self) -> &'static str {
        match self {
            Self::FiniteElement => "finite_element",
            Self::OkadaGrid => "okada_grid",
            Self::BoundaryElements => "boundary_elements",
            Self::WholeSpace => "whole_space",
            Self::Other => "other",
        }
    }

    /// The origin of a [`code`](Self::code).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `origin` for
    /// another text.
    pub fn from_code(code: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|o| o.code() == code)
            .ok_or_else(|| {
                invalid(
                    "origin",
                    format!(
                        "`{code}` is none of {}",
                        Self::ALL.map(|o| o.code()).join(", ")
                    ),
                )
            })
    }
}

/// The diagonal of `op`'s `S` by one product per unknown (exact; [`FaultOperator::diagonal`]'s
/// default).
///
/// # Errors
/// The product's errors; an `out` of another length.
pub(crate) fn diagonal_by_products<O: FaultOperator + ?Sized>(
    op: &mut O,
    out: &mut [f64],
) -> Result<()> {
    let m = op.dim();
    check_diagonal(m, out)?;
    let mut x = vec![0.0; m];
    let mut r = vec![0.0; m];
    for j in 0..m {
        x[j] = 1.0;
        r.fill(0.0);
        op.subtract_product(&x, &mut r, Parallelism::default())?;
        out[j] = -r[j];
        x[j] = 0.0;
    }
    Ok(())
}

/// [`FaultOperator::diagonal`]'s check of its output's length.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `diagonal`.
pub(crate) fn check_diagonal(m: usize, out: &[f64]) -> Result<()> {
    if out.len() == m {
        Ok(())
    } else {
        Err(invalid(
            "diagonal",
            format!("{} entries for an operator of {m} unknowns", out.len()),
        ))
    }
}

/// The rows of a [`FaultOperator`] split into parts ([`FaultOperator::split_rows`]): part
/// `p` computes rows `order[ranges[p]]`, in that order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RowSplit {
    /// Every row (slip unknown, `0..dim`) once, part after part.
    pub order: Vec<usize>,
    /// Each part's positions in `order`: consecutive ranges covering `0..dim`, at least one.
    pub ranges: Vec<Range<usize>>,
}

impl RowSplit {
    /// Checks that `order` is a permutation of `0..dim` and that `ranges` cover it in order.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `row_split`.
    pub fn validate(&self, dim: usize) -> Result<()> {
        let mut seen = vec![false; dim];
        for &i in &self.order {
            if i >= dim || std::mem::replace(&mut seen[i], true) {
                return Err(invalid(
                    "row_split",
                    format!("row {i} is out of 0..{dim} or listed twice"),
                ));
            }
        }
        let mut at = 0;
        for r in &self.ranges {
            if r.start != at || r.end < r.start {
                return Err(invalid(
                    "row_split",
                    format!("the part {r:?} does not start where the last ended ({at})"),
                ));
            }
            at = r.end;
        }
        if at != dim || self.order.len() != dim || self.ranges.is_empty() {
            return Err(invalid(
                "row_split",
                format!("the parts cover {at} of {dim} rows"),
            ));
        }
        Ok(())
    }
}

/// Largest relative accuracy ε of a [`FaultKernel::Hierarchical`]: a coarser operator
/// than 1 % no longer describes the elastic medium.
pub const MAX_KERNEL_EPSILON: f64 = 1e-2;

/// Smallest relative accuracy ε of a [`FaultKernel::Hierarchical`] (and of the half-space
/// operators' ℋ-matrices): about 50 ulps. The entries themselves carry round-off of that
/// order (Okada's closed forms, the Schur complement's elimination), so a smaller ε cannot
/// be met by the compression's test and takes every admissible block to full rank at full
/// cost — `--kernel-epsilon 1e-300` was accepted and ran as a dense kernel stored in blocks
/// (issue 87's probe).
pub const MIN_KERNEL_EPSILON: f64 = 1e-14;

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
        /// `[`[`MIN_KERNEL_EPSILON`]`, `[`MAX_KERNEL_EPSILON`]`]`. [`FaultKernel::matching`] ties it to the
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
    /// ([`FaultOdeOptions::tolerance`](crate::fault_ode::FaultOdeOptions::tolerance)): `ε = tolerance` (clamped to
    /// [`MIN_KERNEL_EPSILON`], [`MAX_KERNEL_EPSILON`]). The operator's error then perturbs the stress by at most
    /// `ε ‖S‖_F ‖u_F‖`, a relative change of the right-hand side no larger than the
    /// relative local error each step is allowed, and in practice far smaller: ε bounds
    /// each far-field block against its own norm, and the measured `‖S − S_H‖_F/‖S‖_F` is
    /// about three orders of magnitude below ε on BP1 (docs/scaling.md, "Compressed fault
    /// operator"; docs/work-precision.md, "BP1: compressed kernel").
    pub fn matching(tolerance: f64) -> Self {
        Self::hierarchical(tolerance.clamp(MIN_KERNEL_EPSILON, MAX_KERNEL_EPSILON))
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
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `kernel.epsilon` unless ε is in
    /// `[`[`MIN_KERNEL_EPSILON`]`, `[`MAX_KERNEL_EPSILON`]`]`, named `kernel.leaf_size` for a leaf size of 0.
    pub fn validate(&self) -> Result<()> {
        if let Self::Hierarchical { epsilon, leaf_size } = *self {
            if !(MIN_KERNEL_EPSILON..=MAX_KERNEL_EPSILON).contains(&epsilon) {
                return Err(invalid(
                    "kernel.epsilon",
                    format!(
                        "{} must be in [{MIN_KERNEL_EPSILON:e}, {MAX_KERNEL_EPSILON}]",
                        rsf_numeric::written(epsilon)
                    ),
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
    /// `‖S − S_H‖_F / ‖S‖_F` (0 for the dense kernel): over every entry, or estimated on
    /// [`error_samples`](Self::error_samples) sampled entries.
    pub relative_error: f64,
    /// 0 if [`relative_error`](Self::relative_error) is over every entry, else the number
    /// of (seeded, uniformly drawn) entries it was estimated on (rsf-hmatrix's
    /// `ErrorMeasure::Sampled`, docs/math.md §13.4).
    pub error_samples: usize,
    /// Bytes of the set-up's largest transient copy: the dense `S` (`8 m²`) where it is
    /// formed, the factor's interface rows (`4 m (m + 1)`) where the ℋ-matrix is built
    /// from entries (a 3-D fault).
    pub setup_bytes: usize,
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
    /// `(part, parts)` for an operator that holds only one part of its rows (one rank's
    /// share, [`HalfSpaceOperator::fault_alone_on_ranks`](crate::halfspace_operator::HalfSpaceOperator::fault_alone_on_ranks)):
    /// the stored entries, blocks, ranks and error are then that part's. `None`: every
    /// row.
    pub part: Option<(usize, usize)>,
}

impl KernelReport {
    /// The report of a dense `m × m` kernel (nothing compressed, nothing measured).
    pub(crate) fn dense(m: usize) -> Self {
        Self {
            kernel: FaultKernel::Dense,
            dim: m,
            relative_error: 0.0,
            error_samples: 0,
            setup_bytes: 8 * m * m,
            stored_entries: m * m,
            dense_blocks: 1,
            low_rank_blocks: 0,
            max_rank: 0,
            setup_seconds: 0.0,
            part: None,
        }
    }

    /// The report of a hierarchical kernel of `dim` unknowns from its ℋ-matrix's set-up
    /// report `r`: `setup_bytes` as the caller counts them (see
    /// [`setup_bytes`](Self::setup_bytes)), the time since `clock` (the set-up's start) as
    /// `setup_seconds`, every row (`part: None`).
    pub(crate) fn hierarchical(
        kernel: FaultKernel,
        dim: usize,
        r: &SetupReport,
        setup_bytes: usize,
        clock: Instant,
    ) -> Self {
        Self {
            kernel,
            dim,
            relative_error: r.relative_error,
            error_samples: match r.error_measure {
                ErrorMeasure::Sampled { samples } => samples,
                _ => 0,
            },
            setup_bytes,
            stored_entries: r.stored_entries,
            dense_blocks: r.dense_blocks,
            low_rank_blocks: r.low_rank_blocks,
            max_rank: r.max_rank,
            setup_seconds: clock.elapsed().as_secs_f64(),
            part: None,
        }
    }

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
                 blocks {} dense + {} low-rank, max rank {}, compressed in {:.2} s{}{}",
                self.dim,
                self.relative_error,
                self.stored_entries,
                self.bytes() as f64 / 1e6,
                self.compression_ratio(),
                self.dense_blocks,
                self.low_rank_blocks,
                self.max_rank,
                self.setup_seconds,
                if self.error_samples > 0 {
                    format!(
                        " from entries (error on {} sampled entries; set-up copy {:.1} MB)",
                        self.error_samples,
                        self.setup_bytes as f64 / 1e6
                    )
                } else {
                    String::new()
                },
                match self.part {
                    Some((p, n)) => format!(" — this rank's rows only (part {p} of {n})"),
                    None => String::new(),
                }
            ),
        }
    }
}
