//! The shared iteration loop of the iterative solvers.

use rsf_nonsmooth::{
    check_inputs, BlockNonlinearity, SolveProgress, SolveReport, SolveWatch, Stopping, WatchVerdict,
};

use crate::error::Result;

/// One iteration of an iterative solver, so that the loop, the stopping test and the
/// report live in one place: the one-process solvers over a
/// [`NodalProblem`](crate::problem::NodalProblem) ([`NodalIteration`]), and TNNMG on ranks,
/// whose energies and norms are reproducible global sums.
pub(crate) trait Iteration<const D: usize> {
    /// Number of dofs of the caller's vectors.
    fn dim(&self) -> usize;
    /// Prepares a solve from `v` (checked lengths) with the active blocks of `nl`.
    fn begin<N: BlockNonlinearity<D>>(&mut self, b: &[f64], nl: &N, v: &[f64]) -> Result<()>;
    /// `J(v)` of the current iterate.
    fn energy<N: BlockNonlinearity<D>>(&mut self, b: &[f64], nl: &N, v: &[f64]) -> f64;
    /// The energy norm of the current iterate (for the relative stopping test).
    fn norm_of_iterate(&mut self, v: &[f64]) -> f64;
    /// Performs one iteration on `v`; returns the energy norm of the correction.
    fn iterate<N: BlockNonlinearity<D>>(&mut self, b: &[f64], nl: &N, v: &mut [f64])
        -> Result<f64>;
    /// Ends a solve (converged or not): makes `v` the current iterate.
    fn end(&mut self, _v: &mut [f64]) {}
}

/// An [`Iteration`] of a one-process solver: the problem, the norm and the map of active
/// blocks give the loop what it needs.
pub(crate) trait NodalIteration<const D: usize> {
    fn blocked(&self) -> &crate::problem::NodalProblem<D>;
    fn energy_norm(&self) -> &crate::norm::EnergyNorm<D>;
    fn active_of_mut(&mut self) -> &mut Vec<usize>;
    /// Performs one iteration on `v`; returns the energy norm of the correction.
    fn iterate<N: BlockNonlinearity<D>>(&mut self, b: &[f64], nl: &N, v: &mut [f64])
        -> Result<f64>;
}

impl<const D: usize, S: NodalIteration<D>> Iteration<D> for S {
    fn dim(&self) -> usize {
        self.blocked().n()
    }
    fn begin<N: BlockNonlinearity<D>>(&mut self, _: &[f64], nl: &N, _: &[f64]) -> Result<()> {
        let nodes = self.blocked().n() / D;
        crate::problem::active_map(nl, nodes, self.active_of_mut())
    }
    fn energy<N: BlockNonlinearity<D>>(&mut self, b: &[f64], nl: &N, v: &[f64]) -> f64 {
        self.blocked().energy(b, nl, v)
    }
    fn norm_of_iterate(&mut self, v: &[f64]) -> f64 {
        self.energy_norm().norm(&self.blocked().a, v)
    }
    fn iterate<N: BlockNonlinearity<D>>(
        &mut self,
        b: &[f64],
        nl: &N,
        v: &mut [f64],
    ) -> Result<f64> {
        NodalIteration::iterate(self, b, nl, v)
    }
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
/// ([`Error::NotConverged`](crate::Error::NotConverged)); with a `watch`, reports its
/// progress and stops at its time limit ([`Error::TimeLimit`](crate::Error::TimeLimit)).
/// The watch does not change the iterates.
pub(crate) fn iterate_to_tolerance<const D: usize, S: Iteration<D>, N: BlockNonlinearity<D>>(
    solver: &mut S,
    run: IterationRun,
    b: &[f64],
    nl: &N,
    v: &mut [f64],
    mut watch: Option<&mut SolveWatch>,
) -> Result<SolveReport> {
    let IterationRun {
        solver: name,
        stop,
        record_energy,
    } = run;
    let start = std::time::Instant::now();
    check_inputs(solver.dim(), b, v)?;
    solver.begin(b, nl, v)?;
    if let Some(w) = watch.as_deref_mut() {
        w.start();
    }
    let mut energy = record_energy.then(|| vec![solver.energy(b, nl, v)]);
    let mut correction = f64::INFINITY;
    let mut tolerance = stop.absolute;
    let progress = |iteration, correction, tolerance| SolveProgress {
        solver: name,
        iteration,
        max_iterations: stop.max_iterations,
        correction,
        tolerance,
        seconds: 0.0,
    };
    for it in 1..=stop.max_iterations {
        let step = solver.iterate(b, nl, v);
        correction = match step {
            Ok(c) => c,
            Err(e) => {
                solver.end(v);
                return Err(e);
            }
        };
        if let Some(e) = energy.as_mut() {
            e.push(solver.energy(b, nl, v));
        }
        let norm_v = if stop.relative > 0.0 {
            solver.norm_of_iterate(v)
        } else {
            0.0
        };
        tolerance = stop.absolute + stop.relative * norm_v;
        if stop.met(correction, norm_v) {
            solver.end(v);
            if let Some(w) = watch {
                w.finish(progress(it, correction, tolerance));
            }
            return Ok(SolveReport {
                iterations: it,
                correction,
                energy,
                seconds: start.elapsed().as_secs_f64(),
            });
        }
        if let Some(w) = watch.as_deref_mut() {
            if w.after_iteration(progress(it, correction, tolerance)) == WatchVerdict::OutOfTime {
                solver.end(v);
                w.finish(progress(it, correction, tolerance));
                return Err(crate::Error::TimeLimit {
                    solver: name,
                    iterations: it,
                    correction,
                    tolerance,
                    seconds: w.elapsed(),
                    limit: w.limit().unwrap_or(0.0),
                });
            }
        }
    }
    solver.end(v);
    if let Some(w) = watch {
        w.finish(progress(stop.max_iterations, correction, tolerance));
    }
    Err(crate::Error::NotConverged {
        solver: name,
        iterations: stop.max_iterations,
        correction,
        tolerance: stop.absolute,
    })
}
