//! The shared iteration loop of the iterative solvers.

use rsf_nonsmooth::{
    check_inputs, BlockNonlinearity, SolveProgress, SolveReport, SolveWatch, Stopping, WatchVerdict,
};

use crate::error::Result;

/// What [`iterate_to_tolerance`] asks of an iterative solver besides its iterations
/// ([`Iteration`]): the one-process solvers have it from their
/// [`NodalProblem`](crate::problem::NodalProblem) ([`NodalIteration`]); TNNMG on ranks, whose
/// energies and norms are reproducible global sums, has its own.
pub(crate) trait IterationState<const D: usize> {
    /// Number of dofs of the caller's vectors.
    fn dim(&self) -> usize;
    /// Prepares a solve from `v` (checked lengths) with the active blocks of `nl`.
    fn begin<N: BlockNonlinearity<D>>(&mut self, b: &[f64], nl: &N, v: &[f64]) -> Result<()>;
    /// `J(v)` of the current iterate.
    fn energy<N: BlockNonlinearity<D>>(&mut self, b: &[f64], nl: &N, v: &[f64]) -> f64;
    /// The energy norm of the current iterate (for the relative stopping test).
    fn norm_of_iterate(&mut self, v: &[f64]) -> f64;
    /// Ends a solve (converged or not): makes `v` the current iterate.
    fn end(&mut self, _v: &mut [f64]) {}
}

/// One iteration of an iterative solver, so that the loop, the stopping test and the
/// report live in one place ([`iterate_to_tolerance`]).
pub(crate) trait Iteration<const D: usize>: IterationState<D> {
    /// Performs one iteration on `v`; returns the energy norm of the correction.
    fn iterate<N: BlockNonlinearity<D>>(&mut self, b: &[f64], nl: &N, v: &mut [f64])
        -> Result<f64>;
}

/// The [`IterationState`] of a one-process solver: the problem, the norm and the map of
/// active blocks give the loop what it needs.
pub(crate) trait NodalIteration<const D: usize> {
    fn blocked(&self) -> &crate::problem::NodalProblem<D>;
    fn energy_norm(&self) -> &crate::norm::EnergyNorm<D>;
    fn active_of_mut(&mut self) -> &mut Vec<usize>;
}

impl<const D: usize, S: NodalIteration<D>> IterationState<D> for S {
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
}

/// Ends an iteration that started from `v_old` and left `v`: `v_old` becomes the
/// correction `v − v_old` (whose energy norm the iteration returns).
///
/// # Errors
/// [`ProblemError::NonFinite`](rsf_nonsmooth::ProblemError::NonFinite) naming `what` (the
/// solver's iterate) if `v` holds a non-finite value; `v_old` is left as it was then.
pub(crate) fn correction(v_old: &mut [f64], v: &[f64], what: &'static str) -> Result<()> {
    if v.iter().any(|x| !x.is_finite()) {
        return Err(rsf_nonsmooth::ProblemError::NonFinite(what).into());
    }
    for (o, x) in v_old.iter_mut().zip(v) {
        *o = x - *o;
    }
    Ok(())
}

/// Implements [`NonsmoothSolver`](rsf_nonsmooth::NonsmoothSolver) for an [`Iteration`] of
/// this crate whose `solve` is [`iterate_to_tolerance`]: `$name` its name, `dim` its number
/// of unknowns (what follows `self.`), `options` the fields below `self` that hold
/// `stopping` and `record_energy` (none: `self` itself), `watch` the field of its
/// [`SolveWatch`] if it has one, `reset` a counter of the solve set to zero before it starts
/// if it has one, and `extra` further items of the impl (e.g. `energy_norm_of`).
macro_rules! iterative_solver {
    (
        $solver:ident, $name:literal,
        dim: [$($dim:tt)+],
        options: [$($opts:ident).*],
        watch: [$($watch:ident)?],
        reset: [$($counter:ident)?],
        extra: { $($item:item)* }
    ) => {
        impl<const D: usize> rsf_nonsmooth::NonsmoothSolver<D> for $solver<D> {
            type Error = $crate::error::Error;

            fn name(&self) -> &'static str {
                $name
            }

            fn dim(&self) -> usize {
                self.$($dim)+
            }

            fn stopping(&self) -> rsf_nonsmooth::Stopping {
                self$(.$opts)*.stopping
            }

            fn set_stopping(
                &mut self,
                stopping: rsf_nonsmooth::Stopping,
            ) -> $crate::error::Result<()> {
                stopping.validate()?;
                self$(.$opts)*.stopping = stopping;
                Ok(())
            }

            fn solve<N: rsf_nonsmooth::BlockNonlinearity<D>>(
                &mut self,
                b: &[f64],
                nl: &N,
                v: &mut [f64],
            ) -> $crate::error::Result<rsf_nonsmooth::SolveReport> {
                let run = $crate::report::IterationRun {
                    solver: $name,
                    stop: self$(.$opts)*.stopping,
                    record_energy: self$(.$opts)*.record_energy,
                };
                $(self.$counter = 0;)?
                $crate::report::iterative_solver!(@iterate self, run, b, nl, v $(, $watch)?)
            }

            $($item)*
        }
    };
    (@iterate $solver:ident, $run:ident, $b:ident, $nl:ident, $v:ident) => {
        $crate::report::iterate_to_tolerance($solver, $run, $b, $nl, $v, None)
    };
    // The watch is taken out of the solver while the loop borrows it, then put back.
    (@iterate $solver:ident, $run:ident, $b:ident, $nl:ident, $v:ident, $watch:ident) => {{
        let mut watch = $solver.$watch.take();
        let result =
            $crate::report::iterate_to_tolerance($solver, $run, $b, $nl, $v, watch.as_mut());
        $solver.$watch = watch;
        result
    }};
}
pub(crate) use iterative_solver;

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
