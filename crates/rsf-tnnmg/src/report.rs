//! Solver options, reports and the common solver trait.

use crate::error::Result;
use crate::nonlinearity::BlockNonlinearity;

/// When an iterative solver stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stopping {
    /// Stop when the energy norm of the last correction `‖v_{k+1} − v_k‖` is at most
    /// `absolute + relative · ‖v_{k+1}‖` (paper §6.2: absolute 1e-10, relative 0).
    pub absolute: f64,
    /// Relative part of the tolerance (see [`absolute`](Self::absolute)).
    pub relative: f64,
    /// Iteration budget; exceeding it is [`Error::NotConverged`](crate::Error::NotConverged).
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
    pub(crate) fn validate(&self) -> Result<()> {
        let finite_non_negative = |x: f64| x.is_finite() && x >= 0.0;
        if !finite_non_negative(self.absolute)
            || !finite_non_negative(self.relative)
            || self.absolute + self.relative == 0.0
        {
            return Err(crate::Error::InvalidOption(format!(
                "tolerances must be finite, non-negative and not both zero (absolute {}, relative {})",
                self.absolute, self.relative
            )));
        }
        if self.max_iterations == 0 {
            return Err(crate::Error::InvalidOption(
                "max_iterations must be positive".into(),
            ));
        }
        Ok(())
    }

    pub(crate) fn met(&self, correction: f64, norm_v: f64) -> bool {
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
    /// [`Error::InvalidOption`](crate::Error::InvalidOption) for negative, non-finite or
    /// all-zero tolerances or a zero budget; the old test is kept then.
    fn set_stopping(&mut self, stopping: Stopping) -> Result<()>;

    /// Minimises `J` starting from `v` (warm start; fixed dofs keep their values in `v`).
    ///
    /// # Errors
    /// Dimension mismatches, non-finite input, non-convergence within the budget
    /// ([`Error::NotConverged`](crate::Error::NotConverged)) — never an unconverged success.
    fn solve<N: BlockNonlinearity<D>>(
        &mut self,
        b: &[f64],
        nonlinearity: &N,
        v: &mut [f64],
    ) -> Result<SolveReport>;
}

pub(crate) fn check_inputs(n: usize, b: &[f64], v: &[f64]) -> Result<()> {
    use crate::Error;
    if b.len() != n {
        return Err(Error::DimensionMismatch {
            what: "right-hand side",
            expected: n,
            got: b.len(),
        });
    }
    if v.len() != n {
        return Err(Error::DimensionMismatch {
            what: "iterate",
            expected: n,
            got: v.len(),
        });
    }
    if b.iter().any(|x| !x.is_finite()) {
        return Err(Error::NonFinite("right-hand side"));
    }
    if v.iter().any(|x| !x.is_finite()) {
        return Err(Error::NonFinite("initial iterate"));
    }
    Ok(())
}

/// One iteration of an iterative solver over a [`NodalProblem`](crate::problem::NodalProblem),
/// so that the loop, the stopping test and the report live in one place.
pub(crate) trait Iteration<const D: usize> {
    fn blocked(&self) -> &crate::problem::NodalProblem<D>;
    fn energy_norm(&self) -> &crate::norm::EnergyNorm<D>;
    fn active_of_mut(&mut self) -> &mut Vec<usize>;
    /// Performs one iteration on `v`; returns the energy norm of the correction.
    fn iterate<N: BlockNonlinearity<D>>(&mut self, b: &[f64], nl: &N, v: &mut [f64])
        -> Result<f64>;
}

/// What [`iterate_to_tolerance`] runs: the solver's name (for
/// [`Error::NotConverged`](crate::Error::NotConverged)), its stopping rule and whether the
/// energy history is recorded.
#[derive(Debug, Clone, Copy)]
pub(crate) struct IterationRun {
    pub solver: &'static str,
    pub stop: Stopping,
    pub record_energy: bool,
}

/// Iterates until [`Stopping::met`] or the budget is exhausted
/// ([`Error::NotConverged`](crate::Error::NotConverged)).
pub(crate) fn iterate_to_tolerance<const D: usize, S: Iteration<D>, N: BlockNonlinearity<D>>(
    solver: &mut S,
    run: IterationRun,
    b: &[f64],
    nl: &N,
    v: &mut [f64],
) -> Result<SolveReport> {
    let IterationRun {
        solver: name,
        stop,
        record_energy,
    } = run;
    let start = std::time::Instant::now();
    let n = solver.blocked().n();
    check_inputs(n, b, v)?;
    crate::problem::active_map(nl, n / D, solver.active_of_mut())?;
    let mut energy = record_energy.then(|| vec![solver.blocked().energy(b, nl, v)]);
    let mut correction = f64::INFINITY;
    for it in 1..=stop.max_iterations {
        correction = solver.iterate(b, nl, v)?;
        if let Some(e) = energy.as_mut() {
            e.push(solver.blocked().energy(b, nl, v));
        }
        let norm_v = if stop.relative > 0.0 {
            solver.energy_norm().norm(&solver.blocked().a, v)
        } else {
            0.0
        };
        if stop.met(correction, norm_v) {
            return Ok(SolveReport {
                iterations: it,
                correction,
                energy,
                seconds: start.elapsed().as_secs_f64(),
            });
        }
    }
    Err(crate::Error::NotConverged {
        solver: name,
        iterations: stop.max_iterations,
        correction,
        tolerance: stop.absolute,
    })
}
