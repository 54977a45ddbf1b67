//! The options of a fault ODE: its Runge–Kutta pair, tolerances, kernel, threads and
//! the volume's fill-reducing ordering.

use std::time::Duration;

use rsf_direct::InteriorOrdering;
use rsf_linalg::Parallelism;
use rsf_time::{
    AutoOptions, OdeIntegrator, RkcOptions, RosenbrockOptions, RungeKuttaOptions, TOLERANCE_RANGE,
};

use crate::checkpoint::Fingerprint;
use crate::error::{invalid, Result};
use crate::fault_operator::FaultKernel;

/// Options of a [`FaultOde`](super::FaultOde).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaultOdeOptions {
    /// The integrator (default [`OdeIntegrator::DormandPrince`], the pair every run used
    /// before issue 84, so that their trajectories keep their bits; the programs default
    /// to [`OdeIntegrator::Auto`]): an explicit embedded pair, the stabilised RKC2, the
    /// linearly implicit ROS34PW2 (`rosenbrock`), or `auto`, the pair while accuracy sets its step and RKC2 while stability would
    /// (docs/math.md §12, "Stiff steps"). A checkpoint of one integrator continues with
    /// another only as a new trajectory (the programs put it in their fingerprint).
    pub integrator: OdeIntegrator,
    /// RKC2's stage limit and spectral radius estimates (used by `rkc` and `auto`).
    pub rkc: RkcOptions,
    /// `auto`'s tests of when to change method.
    pub auto: AutoOptions,
    /// ROS34PW2's linear solves (used by `rosenbrock`).
    pub rosenbrock: RosenbrockOptions,
    /// Error tolerance per step: the local error of every slip component is at most
    /// `tolerance · slip_scale` (m) and of every state `α` at most `tolerance` (absolute:
    /// a relative error of θ). In [`TOLERANCE_RANGE`]; default 1e-6.
    pub tolerance: f64,
    /// The slip that the tolerance is relative to (m), e.g. the characteristic slip
    /// distance `L` (`D_c`). Positive and finite; default 1e-3 m.
    pub slip_scale: f64,
    /// Step limits and controller constants (default: DOPRI5's, steps in [1e-12 s, ∞)).
    pub runge_kutta: RungeKuttaOptions,
    /// How the condensed operator `S` is stored and applied (default
    /// [`FaultKernel::Dense`]). A hierarchical kernel changes the trajectory (by its
    /// accuracy ε); a checkpoint of one kernel continues with the other only as a new
    /// trajectory, so runs that check their checkpoints put the kernel in their
    /// fingerprint (docs/seas-bp1.md, "Compressed kernel").
    pub kernel: FaultKernel,
    /// Threads of every evaluation: the product with `S` and the friction solves (rayon's current pool;
    /// default [`Parallelism::default`], every core, as [`SolverOptions`](crate::method::SolverOptions)'s
    /// since the bits do not depend on it). The results are bit-identical for every value: the
    /// dense product is split over blocks of rows (each row's dot product in the same
    /// order as the sequential product), the hierarchical one into parts of its leaf
    /// clusters of rows, each summed in a fixed order (docs/math.md §13.5), and from 64
    /// frictional nodes on the per-node friction solves are split into one part per
    /// thread (each node's solve is independent of the others) — with the hierarchical
    /// kernel and a fixed normal stress inside the product's parts, one parallel region
    /// per evaluation. Run the simulation on a thread of the pool
    /// (`rayon::ThreadPool::install`): called from outside it, each region hands its work
    /// to the pool and puts the caller to sleep until it is done, which can cost more than
    /// the evaluation (docs/scaling.md, "From inside the pool"). After each evaluation
    /// the pool's other threads poll it for the next (see [`linger`](Self::linger)).
    pub parallelism: Parallelism,
    /// How long, after each evaluation on more than one thread, the pool's other threads
    /// poll it for the next instead of sleeping (timing only, never the bits;
    /// docs/scaling.md, "Idle threads that poll"): `None` (the default) for
    /// [`LINGER`](super::LINGER) = 200 µs, or not at all when rayon's current pool has
    /// more threads than the machine has cores (a polling thread would take a core from
    /// one with work); `Some(t)` for `t` whatever the pool, `Some(Duration::ZERO)` for off.
    pub linger: Option<Duration>,
    /// The fill-reducing ordering of the volume's interior in the condensation onto the
    /// fault (default [`InteriorOrdering::Amd`]). [`InteriorOrdering::NestedDissection`]
    /// (METIS; rsf's feature `metis`) cuts the factor's entries and the set-up time of
    /// 3-D models (docs/three-d.md, "The operator at scale") and changes `S`, so the
    /// trajectory, by round-off only: bit-identical runs keep one ordering.
    pub ordering: InteriorOrdering,
}

/// `fingerprint` with the fault ODE's integrator `integrator` (field `integrator`), unless
/// it is Dormand–Prince — the fingerprint of the runs before the choice existed (issue 84),
/// whose checkpoints keep resuming. One rule for every front end (a program's
/// `--integrator`, the Python package's `integrator=`), so that a checkpoint of either
/// continues in the other.
pub fn integrator_fingerprint(fingerprint: Fingerprint, integrator: OdeIntegrator) -> Fingerprint {
    match integrator {
        OdeIntegrator::DormandPrince => fingerprint,
        i => fingerprint.with("integrator", i),
    }
}

impl Default for FaultOdeOptions {
    fn default() -> Self {
        Self {
            integrator: OdeIntegrator::DormandPrince,
            rkc: RkcOptions::default(),
            auto: AutoOptions::default(),
            rosenbrock: RosenbrockOptions::default(),
            tolerance: 1e-6,
            slip_scale: 1e-3,
            runge_kutta: RungeKuttaOptions::default(),
            kernel: FaultKernel::Dense,
            parallelism: Parallelism::default(),
            linger: None,
            ordering: InteriorOrdering::Amd,
        }
    }
}

impl FaultOdeOptions {
    /// Checks the options.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `tolerance` or `slip_scale`; the Runge–Kutta
    /// options', RKC2's and `auto`'s errors; the kernel's ([`FaultKernel::validate`]).
    pub fn validate(&self) -> Result<()> {
        let (lo, hi) = TOLERANCE_RANGE;
        // The open interval: a relative tolerance of 1 accepts any step (issue 74:
        // `seas_bp5 --tolerance 1` ran).
        if !(self.tolerance > lo && self.tolerance < hi) {
            return Err(invalid(
                "tolerance",
                format!(
                    "{} must be in ({lo:e}, {hi}) (open: a relative tolerance of 1 accepts \
                     any step, one of ε can never be met)",
                    rsf_numeric::written(self.tolerance)
                ),
            ));
        }
        if !(self.slip_scale > 0.0 && self.slip_scale.is_finite()) {
            return Err(invalid(
                "slip_scale",
                format!(
                    "{} m must be positive and finite",
                    rsf_numeric::written(self.slip_scale)
                ),
            ));
        }
        self.runge_kutta.validate()?;
        self.rkc.validate()?;
        self.auto.validate()?;
        self.rosenbrock.validate()?;
        self.kernel.validate()
    }
}
