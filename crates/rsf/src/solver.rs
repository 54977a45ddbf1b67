//! Choice of the velocity solver.

use rsf_tnnmg::{
    BlockNonlinearity, DirectOptions, DirectSolver, FullStep, NonlinearGaussSeidel,
    NonsmoothSolver, Result, SolveReport, StepSolver, Stopping, Tnnmg, TnnmgOptions,
};

use crate::model::Model;

/// Which solver handles the velocity problems of the fixed point iterations.
#[derive(Debug, Clone, PartialEq)]
pub enum SolverKind {
    /// [`Direct`](Self::Direct) while the condensed problem is small, else
    /// [`Tnnmg`](Self::Tnnmg): see [`SolverKind::resolve`] for the rule.
    Auto {
        /// Options if TNNMG is chosen.
        tnnmg: TnnmgOptions,
        /// Options if the direct solver is chosen.
        direct: DirectOptions,
    },
    /// TNNMG over the model's refinement hierarchy (the paper's choice, §6.2): every fixed
    /// point iteration solves the whole problem.
    Tnnmg(TnnmgOptions),
    /// Exact condensation onto Γ_F (docs/math.md §8): the fixed point iterations work on the
    /// frictional unknowns only; the interior is eliminated once per step.
    Direct(DirectOptions),
    /// Nonlinear block Gauss–Seidel alone (baseline; slow on fine meshes).
    GaussSeidel(Stopping),
}

impl Default for SolverKind {
    fn default() -> Self {
        SolverKind::Auto {
            tnnmg: TnnmgOptions::default(),
            direct: DirectOptions::default(),
        }
    }
}

/// Largest number of condensed unknowns (free components on Γ_F) for which
/// [`SolverKind::Auto`] picks the direct solver. Its set-up stores the discrete harmonic
/// extension of every frictional unknown (`n × |F|` values) and a dense `|F|²` Schur
/// complement; the measurements behind the value are in `docs/performance.md`.
pub const AUTO_DIRECT_MAX_CONDENSED: usize = 1500;

/// Largest `n · |F|` (values of the stored harmonic extension, 8 bytes each) for which
/// [`SolverKind::Auto`] picks the direct solver: 2.5e8 values = 2 GB.
pub const AUTO_DIRECT_MAX_EXTENSION: usize = 250_000_000;

impl SolverKind {
    /// The concrete choice for `model`: [`Auto`](Self::Auto) becomes
    /// [`Direct`](Self::Direct) when the number of free components on Γ_F is at most
    /// [`AUTO_DIRECT_MAX_CONDENSED`] and `n · |F|` at most [`AUTO_DIRECT_MAX_EXTENSION`],
    /// else [`Tnnmg`](Self::Tnnmg) (or Direct if the model has no hierarchy).
    pub fn resolve<const D: usize>(&self, model: &Model<D>) -> SolverKind {
        match self {
            SolverKind::Auto { tnnmg, direct } => {
                let condensed = model
                    .frictional
                    .nodes
                    .iter()
                    .flat_map(|&p| (0..D).map(move |c| D * p + c))
                    .filter(|&i| !model.fixed[i])
                    .count();
                let small = condensed <= AUTO_DIRECT_MAX_CONDENSED
                    && model.num_dofs().saturating_mul(condensed) <= AUTO_DIRECT_MAX_EXTENSION;
                if small || model.prolongations.is_empty() {
                    SolverKind::Direct(direct.clone())
                } else {
                    SolverKind::Tnnmg(tnnmg.clone())
                }
            }
            other => other.clone(),
        }
    }

    /// The inner stopping test of the chosen solver.
    pub fn stopping(&self) -> Stopping {
        match self {
            SolverKind::Auto { tnnmg, .. } => tnnmg.stopping,
            SolverKind::Tnnmg(o) => o.stopping,
            SolverKind::Direct(o) => o.stopping,
            SolverKind::GaussSeidel(s) => *s,
        }
    }
}

/// A velocity solver of any concrete [`SolverKind`], dispatching statically inside each
/// call.
pub enum VelocitySolver<const D: usize> {
    /// See [`SolverKind::Tnnmg`].
    Tnnmg(Box<FullStep<D, Tnnmg<D>>>),
    /// See [`SolverKind::Direct`].
    Direct(Box<DirectSolver<D>>),
    /// See [`SolverKind::GaussSeidel`].
    GaussSeidel(Box<FullStep<D, NonlinearGaussSeidel<D>>>),
}

impl<const D: usize> VelocitySolver<D> {
    /// Builds the solver for the matrix `a` of the velocity problem of `model`
    /// ([`SolverKind::Auto`] is resolved first). Stopping norms are the model's energy norm.
    ///
    /// # Errors
    /// Set-up errors of the solvers.
    pub fn new(kind: &SolverKind, a: &rsf_fem::SparseMatrix, model: &Model<D>) -> Result<Self> {
        let e = model.energy_norm.as_ref();
        Ok(match kind.resolve(model) {
            SolverKind::Tnnmg(o) => VelocitySolver::Tnnmg(Box::new(FullStep::new(
                Tnnmg::new(a.as_ref(), &model.fixed, &model.prolongations, Some(e), o)?,
                Some(e),
            )?)),
            SolverKind::Direct(o) => {
                let mut d = DirectSolver::new(a.as_ref(), &model.fixed, o)?.with_energy_norm(e)?;
                d.prepare(&model.frictional.nodes)?;
                VelocitySolver::Direct(Box::new(d))
            }
            SolverKind::GaussSeidel(s) => VelocitySolver::GaussSeidel(Box::new(FullStep::new(
                NonlinearGaussSeidel::new(a.as_ref(), &model.fixed, Some(e), s, false)?,
                Some(e),
            )?)),
            SolverKind::Auto { .. } => unreachable!("resolved above"),
        })
    }
}

impl<const D: usize> VelocitySolver<D> {
    /// The solver of the same kind for another matrix `a` of `model` with the same pattern
    /// (the velocity problem at another time step): the direct solver reuses its ordering
    /// and symbolic factorisation ([`DirectSolver::for_matrix`]); the others are set up
    /// as by [`new`](Self::new).
    ///
    /// # Errors
    /// Set-up errors of the solvers.
    pub fn for_matrix(
        &self,
        kind: &SolverKind,
        a: &rsf_fem::SparseMatrix,
        model: &Model<D>,
    ) -> Result<Self> {
        match self {
            VelocitySolver::Direct(d) => {
                Ok(VelocitySolver::Direct(Box::new(d.for_matrix(a.as_ref())?)))
            }
            _ => Self::new(kind, a, model),
        }
    }
}

macro_rules! dispatch {
    ($self:ident, $s:ident => $e:expr) => {
        match $self {
            VelocitySolver::Tnnmg($s) => $e,
            VelocitySolver::Direct($s) => $e,
            VelocitySolver::GaussSeidel($s) => $e,
        }
    };
}

impl<const D: usize> StepSolver<D> for VelocitySolver<D> {
    fn name(&self) -> &'static str {
        dispatch!(self, s => StepSolver::name(s.as_ref()))
    }
    fn dim(&self) -> usize {
        dispatch!(self, s => StepSolver::dim(s.as_ref()))
    }
    fn begin_step(&mut self, b: &[f64], v: &[f64], active: &[usize]) -> Result<()> {
        dispatch!(self, s => s.begin_step(b, v, active))
    }
    fn solve_step<N: BlockNonlinearity<D>>(
        &mut self,
        nl: &N,
        stopping: Stopping,
    ) -> Result<SolveReport> {
        dispatch!(self, s => s.solve_step(nl, stopping))
    }
    fn block(&self, k: usize) -> [f64; D] {
        dispatch!(self, s => s.block(k))
    }
    fn last_change(&self) -> f64 {
        dispatch!(self, s => s.last_change())
    }
    fn finish_step(&mut self, v: &mut [f64]) -> Result<()> {
        dispatch!(self, s => s.finish_step(v))
    }
}

impl<const D: usize> VelocitySolver<D> {
    /// The stopping test of single solves (for [`NonsmoothSolver`] use outside a step).
    pub fn stopping(&self) -> Stopping {
        match self {
            VelocitySolver::Tnnmg(s) => s.inner().stopping(),
            VelocitySolver::Direct(s) => NonsmoothSolver::stopping(s.as_ref()),
            VelocitySolver::GaussSeidel(s) => s.inner().stopping(),
        }
    }
}
