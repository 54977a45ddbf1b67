//! Choice of the velocity solver at the scene level.

use rsf_tnnmg::{
    BlockNonlinearity, DirectOptions, DirectSolver, NonlinearGaussSeidel, NonsmoothSolver, Result,
    SolveReport, Stopping, Tnnmg, TnnmgOptions,
};

use crate::model::Model;

/// Which solver handles the velocity problem of each fixed point iteration.
#[derive(Debug, Clone, PartialEq)]
pub enum SolverKind {
    /// TNNMG over the model's refinement hierarchy (the paper's choice, §6.2).
    Tnnmg(TnnmgOptions),
    /// Direct condensation onto Γ_F plus globalised Newton (reference; fast when Γ_F is small).
    Direct(DirectOptions),
    /// Nonlinear block Gauss–Seidel alone (baseline; slow on fine meshes).
    GaussSeidel(Stopping),
}

impl Default for SolverKind {
    fn default() -> Self {
        SolverKind::Tnnmg(TnnmgOptions::default())
    }
}

/// A velocity solver of any [`SolverKind`], dispatching statically inside each call.
pub enum VelocitySolver<const D: usize> {
    /// See [`SolverKind::Tnnmg`].
    Tnnmg(Box<Tnnmg<D>>),
    /// See [`SolverKind::Direct`].
    Direct(Box<DirectSolver<D>>),
    /// See [`SolverKind::GaussSeidel`].
    GaussSeidel(Box<NonlinearGaussSeidel<D>>),
}

impl<const D: usize> VelocitySolver<D> {
    /// Builds the solver for the matrix `a` of the velocity problem of `model`.
    ///
    /// # Errors
    /// Set-up errors of the solvers.
    pub fn new(kind: &SolverKind, a: &rsf_fem::SparseMatrix, model: &Model<D>) -> Result<Self> {
        Ok(match kind {
            SolverKind::Tnnmg(o) => VelocitySolver::Tnnmg(Box::new(Tnnmg::new(
                a.as_ref(),
                &model.fixed,
                &model.prolongations,
                Some(model.energy_norm.as_ref()),
                o.clone(),
            )?)),
            SolverKind::Direct(o) => VelocitySolver::Direct(Box::new(DirectSolver::new(
                a.as_ref(),
                &model.fixed,
                o.clone(),
            )?)),
            SolverKind::GaussSeidel(s) => {
                VelocitySolver::GaussSeidel(Box::new(NonlinearGaussSeidel::new(
                    a.as_ref(),
                    &model.fixed,
                    Some(model.energy_norm.as_ref()),
                    *s,
                    false,
                )?))
            }
        })
    }
}

impl<const D: usize> NonsmoothSolver<D> for VelocitySolver<D> {
    fn name(&self) -> &'static str {
        match self {
            VelocitySolver::Tnnmg(s) => s.name(),
            VelocitySolver::Direct(s) => s.name(),
            VelocitySolver::GaussSeidel(s) => s.name(),
        }
    }
    fn dim(&self) -> usize {
        match self {
            VelocitySolver::Tnnmg(s) => s.dim(),
            VelocitySolver::Direct(s) => s.dim(),
            VelocitySolver::GaussSeidel(s) => s.dim(),
        }
    }
    fn stopping(&self) -> Stopping {
        match self {
            VelocitySolver::Tnnmg(s) => s.stopping(),
            VelocitySolver::Direct(s) => s.stopping(),
            VelocitySolver::GaussSeidel(s) => s.stopping(),
        }
    }
    fn set_stopping(&mut self, stopping: Stopping) -> Result<()> {
        match self {
            VelocitySolver::Tnnmg(s) => s.set_stopping(stopping),
            VelocitySolver::Direct(s) => s.set_stopping(stopping),
            VelocitySolver::GaussSeidel(s) => s.set_stopping(stopping),
        }
    }
    fn solve<N: BlockNonlinearity<D>>(
        &mut self,
        b: &[f64],
        nl: &N,
        v: &mut [f64],
    ) -> Result<SolveReport> {
        match self {
            VelocitySolver::Tnnmg(s) => s.solve(b, nl, v),
            VelocitySolver::Direct(s) => s.solve(b, nl, v),
            VelocitySolver::GaussSeidel(s) => s.solve(b, nl, v),
        }
    }
}
