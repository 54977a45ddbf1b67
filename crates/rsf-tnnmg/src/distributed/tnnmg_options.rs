//! The options of [`DistributedTnnmg`](super::DistributedTnnmg) and the counters of what
//! its ranks send.

use rsf_nonsmooth::Stopping;

use super::hierarchy::VCycleShape;
use crate::linear_correction::LinearCorrection;
use rsf_ranks::halo::HaloCounters;

/// Options of [`DistributedTnnmg`](super::DistributedTnnmg): the classical TNNMG iteration (docs/math.md §5) with
/// the multi-colour smoother order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DistributedTnnmgOptions {
    /// Stopping test on the energy norm of the correction.
    pub stopping: Stopping,
    /// Nonlinear multi-colour Gauss–Seidel sweeps before each linear correction (≥ 1).
    pub nonlinear_sweeps: usize,
    /// Linear V-cycles on the truncated Newton system per iteration (≥ 1), from zero; at
    /// most this many with [`linear_reduction`](Self::linear_reduction).
    pub v_cycles: usize,
    /// How the V-cycles solve the truncated Newton system: as a stationary iteration
    /// ([`LinearCorrection::Cycles`], the classical TNNMG) or as the preconditioner of
    /// conjugate gradients ([`LinearCorrection::PreconditionedCg`], one cycle per step; its
    /// inner products exact sums, three reductions per step with `linear_reduction`, two
    /// without).
    pub linear_correction: LinearCorrection,
    /// Inexact Newton: stop the V-cycles (or CG steps) of an iteration once the truncated system's
    /// residual (Euclidean norm on the untruncated dofs, a reproducible sum) is reduced by
    /// this factor, in (0, 1); `None` always runs `v_cycles` cycles. Each check costs one
    /// reduction (and the initial norm one more).
    pub linear_reduction: Option<f64>,
    /// Block Gauss–Seidel sweeps of each V-cycle before and after the coarse correction.
    pub smoothing: VCycleShape,
    /// Record `J(v_k)` in the report (one more reduction per iteration).
    pub record_energy: bool,
}

impl Default for DistributedTnnmgOptions {
    /// One nonlinear sweep and one V(3,3)-cycle per iteration, as
    /// [`TnnmgOptions::classical`](crate::TnnmgOptions::classical).
    fn default() -> Self {
        Self {
            stopping: Stopping::default(),
            nonlinear_sweeps: 1,
            v_cycles: 1,
            linear_correction: LinearCorrection::Cycles,
            linear_reduction: None,
            smoothing: VCycleShape { pre: 3, post: 3 },
            record_energy: false,
        }
    }
}

impl crate::tnnmg::NewtonOptions for DistributedTnnmgOptions {
    fn newton(&self) -> (Stopping, Option<f64>, usize, usize) {
        (
            self.stopping,
            self.linear_reduction,
            self.nonlinear_sweeps,
            self.v_cycles,
        )
    }
}

impl DistributedTnnmgOptions {
    /// The options that correspond to the one-process `tnnmg`: the same stopping test,
    /// sweeps, cycles, linear correction, inexact-Newton factor, smoothing and energy
    /// record (the smoother order is the distributed multi-colour one). `None` unless
    /// `tnnmg.cycle_index` is 1: the distributed linear correction runs V-cycles.
    pub fn from_tnnmg(tnnmg: &crate::TnnmgOptions) -> Option<Self> {
        (tnnmg.cycle_index == 1).then_some(Self {
            stopping: tnnmg.stopping,
            nonlinear_sweeps: tnnmg.nonlinear_sweeps,
            v_cycles: tnnmg.v_cycles,
            linear_correction: tnnmg.linear_correction,
            linear_reduction: tnnmg.linear_reduction,
            smoothing: VCycleShape {
                pre: tnnmg.smoothing.0,
                post: tnnmg.smoothing.1,
            },
            record_energy: tnnmg.record_energy,
        })
    }
}

/// What one rank of [`DistributedTnnmg`](super::DistributedTnnmg) has sent, by part of the iteration (each counted
/// as the messages are handed to the transport). Bytes are `8` per value.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TnnmgCounters {
    /// TNNMG iterations.
    pub iterations: u64,
    /// Full numeric updates of the rank's hierarchy: one per solve with a new set of
    /// active blocks (its first iteration); every other iteration updates the rows the
    /// active blocks reach.
    pub full_updates: u64,
    /// The set-up's collectives: the agreement on the ranks' parts, the gathers of the
    /// fine level's node graph and diagonal blocks (the hierarchy's first update is in
    /// `hierarchy`).
    pub setup: HaloCounters,
    /// The hierarchy's updates: per level below the fine one an exchange of `T` rows
    /// and (above the coarsest) one of the ghosts' masks, and the coarsest level's
    /// all-gather (a collective).
    pub hierarchy: HaloCounters,
    /// The nonlinear smoother: one exchange per colour and sweep.
    pub smoother: HaloCounters,
    /// The linear V-cycles: sweeps, ghost updates and transfers of every level
    /// (exchanges), the coarsest gathers (collectives).
    pub cycles: HaloCounters,
    /// The all-gathers of the active blocks' values (the iterate before the
    /// linearisation, the correction before the line search; one collective each).
    pub gathers: HaloCounters,
    /// The reproducible global sums (`g0` and `h` of the line search; the norms and the
    /// energy; one collective each).
    pub reductions: HaloCounters,
    /// The all-gather of the solution at the end of each solve (one collective).
    pub solution: HaloCounters,
}

impl TnnmgCounters {
    /// Everything sent.
    pub fn total(&self) -> HaloCounters {
        self.smoother
            + self.cycles
            + self.gathers
            + self.reductions
            + self.solution
            + self.hierarchy
    }
}
