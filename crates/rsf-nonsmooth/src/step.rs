//! Solving the velocity problems of one time step: the fixed point iteration of the coupled
//! step (docs/math.md §4, §8) solves a sequence of problems with the same matrix `A` and
//! right-hand side `b` and a changing nonlinearity (the friction frozen at the current
//! state iterate).
//!
//! [`StepSolver`] is that sequence as an interface: [`begin_step`](StepSolver::begin_step)
//! once per time step, [`solve_step`](StepSolver::solve_step) once per fixed point
//! iteration, [`finish_step`](StepSolver::finish_step) once at the end. A solver that
//! condenses onto the nonsmooth blocks (`rsf_direct::DirectSolver`) does all of
//! its per-step bulk work in `begin_step`/`finish_step` and the iterations on the
//! frictional unknowns only; [`FullStep`] turns any [`NonsmoothSolver`] into a
//! `StepSolver` that solves the whole problem every iteration (TNNMG, Gauss–Seidel).

use faer::sparse::SparseColMatRef;

use crate::error::ProblemError;
use crate::nonlinearity::BlockNonlinearity;
use crate::solver::{check_inputs, energy_norm_matrix, NonsmoothSolver, SolveReport, Stopping};
use rsf_linalg::{Csc, Parallelism};

/// Block `p` of the node-major vector `v`.
#[inline]
fn load<const D: usize>(v: &[f64], p: usize) -> [f64; D] {
    let mut out = [0.0; D];
    out.copy_from_slice(&v[D * p..D * p + D]);
    out
}

/// A minimiser of `J(v) = ½ vᵀAv − bᵀv + Σ_k φ_k(v_{p_k})` for a sequence of
/// nonlinearities `φ` with the same `A`, `b`, fixed dofs and active blocks.
///
/// Protocol: [`begin_step`](Self::begin_step) (`b` and a predicted `v`), then any number of
/// [`solve_step`](Self::solve_step) calls (each warm-started from the previous result),
/// then [`finish_step`](Self::finish_step) to obtain the full solution. Between solves,
/// [`block`](Self::block) reads the current value of an active block (e.g. to update the
/// friction state from the slip rate).
pub trait StepSolver<const D: usize> {
    /// The solver's error type.
    type Error: std::error::Error;

    /// Short name for reports.
    fn name(&self) -> &'static str;

    /// Number of unknowns `n` of the full problem.
    fn dim(&self) -> usize;

    /// Starts a step: `b` (length `n`) is the right-hand side; `v` (length `n`) holds the
    /// values of the fixed dofs and a prediction of the free ones (the start of the first
    /// solve). The predicted iterate counts as the 0-th iterate for
    /// [`last_change`](Self::last_change).
    ///
    /// `active` are the node indices of the nonsmooth blocks of every nonlinearity of this
    /// step (strictly increasing; a solver may have been set up for one set only).
    ///
    /// # Errors
    /// Dimension mismatches, non-finite input, active blocks that differ from the set-up.
    fn begin_step(&mut self, b: &[f64], v: &[f64], active: &[usize]) -> Result<(), Self::Error>;

    /// Minimises `J` for the nonlinearity `nl` (whose active blocks are those given to
    /// [`begin_step`](Self::begin_step)) from the current iterate, to `stopping`.
    ///
    /// # Errors
    /// Non-convergence within the budget (the solver's "not converged"), non-finite iterates.
    fn solve_step<N: BlockNonlinearity<D>>(
        &mut self,
        nl: &N,
        stopping: Stopping,
    ) -> Result<SolveReport, Self::Error>;

    /// Value of active block `k` (all `D` components) of the current iterate.
    fn block(&self, k: usize) -> [f64; D];

    /// Energy norm of the change of the full iterate made by the last
    /// [`solve_step`](Self::solve_step) (after the first solve of a step: the change from the
    /// predicted iterate; for a condensing solver the predicted iterate is the discrete
    /// harmonic extension of its values on the active blocks).
    fn last_change(&self) -> f64;

    /// Writes the full current iterate into `v` (length `n`), recovering everything the
    /// iterations did not compute. Ends the step.
    ///
    /// # Errors
    /// Non-finite results.
    fn finish_step(&mut self, v: &mut [f64]) -> Result<(), Self::Error>;

    /// Writes the full current iterate into `v` (length `n`; entries of fixed dofs are
    /// left as the caller set them) as [`finish_step`](Self::finish_step) would, without
    /// ending the step: for quantities of the whole field inside an outer iteration (the
    /// normal stress of a fault inside the body). For a condensing solver one backward
    /// sweep.
    ///
    /// # Errors
    /// Outside a step; dimension mismatch; non-finite results.
    fn current_iterate(&mut self, v: &mut [f64]) -> Result<(), Self::Error>;
}

/// Any [`NonsmoothSolver`] as a [`StepSolver`]: every [`solve_step`](StepSolver::solve_step)
/// solves the whole problem (warm-started), and the change between iterates is measured in
/// the energy norm given at construction (`‖x‖² = xᵀEx`).
pub struct FullStep<const D: usize, S: NonsmoothSolver<D>> {
    solver: S,
    norm: Option<Csc>,
    b: Vec<f64>,
    v: Vec<f64>,
    v_before: Vec<f64>,
    active: Vec<usize>,
    change: f64,
    parallelism: Parallelism,
    /// Per-dof terms of the parallel energy norm (empty until used).
    sum_scratch: Vec<Option<[f64; 1]>>,
    /// A solve of one iteration takes its change from the solver's report
    /// ([`with_correction_from_solver`](FullStep::with_correction_from_solver)).
    correction_from_solver: bool,
    /// The change of a solve is measured in the solver's own norm
    /// ([`with_norm_from_solver`](FullStep::with_norm_from_solver)).
    norm_from_solver: bool,
}

impl<const D: usize, S: NonsmoothSolver<D>> FullStep<D, S> {
    /// Wraps `solver`; `energy_norm` is the matrix `E` of the norm of
    /// [`last_change`](StepSolver::last_change) (`n × n`, symmetric positive semidefinite;
    /// `None`: the Euclidean norm).
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] if `E` is not `n × n`; non-finite entries.
    pub fn new(
        solver: S,
        energy_norm: Option<SparseColMatRef<'_, usize, f64>>,
    ) -> Result<Self, S::Error> {
        let n = solver.dim();
        let norm = energy_norm_matrix(energy_norm, n)?;
        Ok(Self {
            solver,
            norm,
            b: vec![0.0; n],
            v: vec![0.0; n],
            v_before: vec![0.0; n],
            active: Vec::new(),
            change: f64::INFINITY,
            parallelism: Parallelism::SEQ,
            sum_scratch: Vec::new(),
            correction_from_solver: false,
            norm_from_solver: false,
        })
    }

    /// Declares that the wrapped solver measures its corrections in this `FullStep`'s
    /// energy norm (the same `E`, e.g. `rsf_tnnmg::Tnnmg` or
    /// `rsf_tnnmg::NonlinearGaussSeidel` built with it): a solve of
    /// one iteration changes the iterate by exactly its last correction, so
    /// [`last_change`](StepSolver::last_change) is the report's
    /// [`correction`](SolveReport::correction) and is not measured a second time (a pass
    /// over `E`: a tenth of a 3-D TNNMG iteration on one thread; docs/scaling.md). The
    /// solver's norm rounds differently (block upper triangle against full columns), so
    /// the value differs from the measured one in round-off; it is only compared with
    /// tolerances. Solves of several iterations are measured as without it. Default off.
    pub fn with_correction_from_solver(mut self) -> Self {
        self.correction_from_solver = true;
        self
    }

    /// Measures [`last_change`](StepSolver::last_change) with the wrapped solver's own norm
    /// ([`NonsmoothSolver::energy_norm_of`]) where a solve's report does not give it, so
    /// that this wrapper holds no copy of the norm's matrix: for a solver whose matrices
    /// are split among ranks (each rank holds its rows of `E`; then the measurement is
    /// collective, and every rank calls the solves alike). Build the wrapper with
    /// `energy_norm = None`; a solver that measures no norm of its own leaves the
    /// Euclidean norm. Default off.
    pub fn with_norm_from_solver(mut self) -> Self {
        self.norm_from_solver = true;
        self
    }

    /// Computes the energy norm of [`last_change`](StepSolver::last_change) on `par`'s
    /// threads (default [`Parallelism::SEQ`]), with the same bits for every thread count;
    /// the wrapped solver's own parallelism is set on the solver.
    pub fn with_parallelism(mut self, par: Parallelism) -> Self {
        self.parallelism = par;
        self
    }

    /// The wrapped solver.
    pub fn inner(&self) -> &S {
        &self.solver
    }

    /// The wrapped solver, mutably.
    pub fn inner_mut(&mut self) -> &mut S {
        &mut self.solver
    }
}

impl<const D: usize, S: NonsmoothSolver<D>> StepSolver<D> for FullStep<D, S> {
    type Error = S::Error;

    fn name(&self) -> &'static str {
        self.solver.name()
    }

    fn dim(&self) -> usize {
        self.solver.dim()
    }

    fn begin_step(&mut self, b: &[f64], v: &[f64], active: &[usize]) -> Result<(), S::Error> {
        check_inputs(self.dim(), b, v).map_err(S::Error::from)?;
        self.b.copy_from_slice(b);
        self.v.copy_from_slice(v);
        self.active.clear();
        self.active.extend_from_slice(active);
        self.change = f64::INFINITY;
        Ok(())
    }

    fn solve_step<N: BlockNonlinearity<D>>(
        &mut self,
        nl: &N,
        stopping: Stopping,
    ) -> Result<SolveReport, S::Error> {
        if nl.active_blocks() != self.active.as_slice() {
            return Err(ProblemError::InvalidOption(
                "the nonlinearity's active blocks differ from those of begin_step".into(),
            )
            .into());
        }
        self.solver.set_stopping(stopping)?;
        self.v_before.copy_from_slice(&self.v);
        let report = self.solver.solve(&self.b, nl, &mut self.v)?;
        if self.correction_from_solver && report.iterations == 1 {
            self.change = report.correction;
            return Ok(report);
        }
        for (d, x) in self.v_before.iter_mut().zip(&self.v) {
            *d = x - *d;
        }
        let own = if self.norm_from_solver {
            self.solver.energy_norm_of(&self.v_before)
        } else {
            None
        };
        self.change = match (own, &self.norm) {
            (Some(norm), _) => norm,
            (None, Some(e)) => e
                .quadratic_form_par(&self.v_before, self.parallelism, &mut self.sum_scratch)
                .max(0.0)
                .sqrt(),
            (None, None) => self.v_before.iter().map(|x| x * x).sum::<f64>().sqrt(),
        };
        Ok(report)
    }

    fn block(&self, k: usize) -> [f64; D] {
        load::<D>(&self.v, self.active[k])
    }

    fn last_change(&self) -> f64 {
        self.change
    }

    fn finish_step(&mut self, v: &mut [f64]) -> Result<(), S::Error> {
        ProblemError::check_length("iterate", self.v.len(), v.len())?;
        v.copy_from_slice(&self.v);
        Ok(())
    }

    fn current_iterate(&mut self, v: &mut [f64]) -> Result<(), S::Error> {
        self.finish_step(v)
    }
}
