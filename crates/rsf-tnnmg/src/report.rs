//! The shared iteration loop of the iterative solvers.

use rsf_nonsmooth::{check_inputs, BlockNonlinearity, SolveReport, Stopping};

use crate::error::Result;

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
