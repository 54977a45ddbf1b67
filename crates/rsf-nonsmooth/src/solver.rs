//! The stopping test, the report of a solve and the common solver trait.

use faer::sparse::SparseColMatRef;
use rsf_linalg::Csc;

use crate::error::{ProblemError, Result};
use crate::nonlinearity::BlockNonlinearity;

/// When an iterative solver stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stopping {
    /// Stop when the energy norm of the last correction `‖v_{k+1} − v_k‖` is at most
    /// `absolute + relative · ‖v_{k+1}‖` (paper §6.2: absolute 1e-10, relative 0).
    pub absolute: f64,
    /// Relative part of the tolerance (see [`absolute`](Self::absolute)).
    pub relative: f64,
    /// Iteration budget; exceeding it is the solver's error "not converged" (e.g.
    /// `rsf_tnnmg::Error::NotConverged`).
    pub max_iterations: usize,
}

impl Default for Stopping {
    /// The paper's choice: absolute 1e-10 in the energy norm, 200 iterations.
    fn default() -> Self {
        Self {
            absolute: 1e-10,
            relative: 0.0,
            max_iterations: 200,
        }
    }
}

impl Stopping {
    /// Checks the test: finite, non-negative tolerances, not both zero, a positive budget.
    ///
    /// # Errors
    /// [`ProblemError::InvalidOption`] naming what is wrong.
    pub fn validate(&self) -> Result<()> {
        let finite_non_negative = |x: f64| x.is_finite() && x >= 0.0;
        if !finite_non_negative(self.absolute)
            || !finite_non_negative(self.relative)
            || self.absolute + self.relative == 0.0
        {
            return Err(ProblemError::InvalidOption(format!(
                "tolerances must be finite, non-negative and not both zero (absolute {}, relative {})",
                self.absolute, self.relative
            )));
        }
        if self.max_iterations == 0 {
            return Err(ProblemError::InvalidOption(
                "max_iterations must be positive".into(),
            ));
        }
        Ok(())
    }

    /// Whether a correction of energy norm `correction` at an iterate of norm `norm_v`
    /// meets the test.
    pub fn met(&self, correction: f64, norm_v: f64) -> bool {
        correction <= self.absolute + self.relative * norm_v
    }
}

/// What a solve did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SolveReport {
    /// Iterations performed (outer iterations for TNNMG and the direct solver's Newton
    /// phase, sweeps for nonlinear Gauss–Seidel).
    pub iterations: usize,
    /// Energy norm of the last correction.
    pub correction: f64,
    /// `J(v_k)` after every iteration, if requested (first entry: the initial iterate).
    pub energy: Option<Vec<f64>>,
    /// Wall time of the solve in seconds (not part of any numerical output).
    pub seconds: f64,
}

/// A minimiser of `J(v) = ½ vᵀAv − bᵀv + Σ_k φ_k(v_{p_k})` for a matrix and a set of fixed
/// dofs given at construction.
pub trait NonsmoothSolver<const D: usize> {
    /// The solver's error type; it holds the shared checks of this crate ([`ProblemError`]).
    type Error: std::error::Error + From<ProblemError>;

    /// Short name for reports ("tnnmg", "direct", "nonlinear-gauss-seidel").
    fn name(&self) -> &'static str;

    /// Number of unknowns.
    fn dim(&self) -> usize;

    /// The stopping test of [`solve`](Self::solve).
    fn stopping(&self) -> Stopping;

    /// Replaces the stopping test of later solves (e.g. a looser one for an inexact inner
    /// solve of a fixed point iteration).
    ///
    /// # Errors
    /// [`ProblemError::InvalidOption`] (converted) for negative, non-finite or all-zero
    /// tolerances or a zero budget; the old test is kept then.
    fn set_stopping(&mut self, stopping: Stopping) -> std::result::Result<(), Self::Error>;

    /// Minimises `J` starting from `v` (warm start; fixed dofs keep their values in `v`).
    ///
    /// # Errors
    /// Dimension mismatches, non-finite input, non-convergence within the budget (the
    /// solver's "not converged") — never an unconverged success.
    fn solve<N: BlockNonlinearity<D>>(
        &mut self,
        b: &[f64],
        nonlinearity: &N,
        v: &mut [f64],
    ) -> std::result::Result<SolveReport, Self::Error>;

    /// The solver's own energy norm `√(xᵀ E x)` of the vector `x` (length
    /// [`dim`](Self::dim)), if it holds the matrix `E` of its stopping norm; `None` (the
    /// default) if it does not. A solver whose matrices are split among ranks holds only
    /// its rows of `E`: then every rank calls this with the same `x` (collective), and
    /// every rank gets the same bits. [`FullStep::with_norm_from_solver`](crate::FullStep::with_norm_from_solver)
    /// measures its steps' changes with it instead of a copy of `E` of its own.
    fn energy_norm_of(&mut self, _x: &[f64]) -> Option<f64> {
        None
    }
}

/// Checks the inputs of a solve of `n` unknowns: the lengths of the right-hand side `b`
/// and the iterate `v`, and that both are finite.
///
/// # Errors
/// [`ProblemError::DimensionMismatch`], [`ProblemError::NonFinite`].
pub fn check_inputs(n: usize, b: &[f64], v: &[f64]) -> Result<()> {
    ProblemError::check_length("right-hand side", n, b.len())?;
    ProblemError::check_length("iterate", n, v.len())?;
    if b.iter().any(|x| !x.is_finite()) {
        return Err(ProblemError::NonFinite("right-hand side"));
    }
    if v.iter().any(|x| !x.is_finite()) {
        return Err(ProblemError::NonFinite("initial iterate"));
    }
    Ok(())
}

/// The matrix `E` of a solver's energy norm `‖x‖ = √(xᵀ E x)` (`n × n`, symmetric positive
/// semidefinite), copied and checked: `None` (the caller's own norm, e.g. the Euclidean
/// one or `A`'s) stays `None`.
///
/// # Errors
/// [`ProblemError::NonFinite`] for a non-finite entry;
/// [`ProblemError::DimensionMismatch`] (`energy-norm matrix`) if `E` is not `n × n`.
pub fn energy_norm_matrix(
    e: Option<SparseColMatRef<'_, usize, f64>>,
    n: usize,
) -> Result<Option<Csc>> {
    let e = e.map(Csc::from_faer).transpose()?;
    if let Some(e) = &e {
        if e.nrows != n || e.ncols != n {
            return Err(ProblemError::DimensionMismatch {
                what: "energy-norm matrix",
                expected: n,
                got: e.nrows,
            });
        }
    }
    Ok(e)
}
