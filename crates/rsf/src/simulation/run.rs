//! Run control: where a run ends ([`Until`]), why it ended ([`Termination`]), and what it
//! did ([`RunSummary`], also on failure through [`RunError`]).

use std::time::Instant;

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;

use crate::error::{invalid, Error, Result};
use crate::observe::{Observer, StepView};
use crate::problem::Problem;
use crate::report::StepReport;
use crate::simulation_state::SimulationState;

/// Where [`Simulation::run_until`](crate::Simulation::run_until) ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Until {
    /// After this many steps.
    Steps(usize),
    /// At the first step with `t_n ≥ t` (s), up to round-off of `1e-9 min(τ, |t|)`. With a
    /// fixed τ the last step is not shortened to land on `t`; with adaptive steps it is, so
    /// the run ends at `t`.
    Time(f64),
}

/// Why a run ended.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum Termination {
    /// The end time of [`Until::Time`] was reached.
    #[default]
    EndTime,
    /// The step count of [`Until::Steps`] was reached.
    StepCount,
    /// An observer returned [`Flow::Break`](crate::Flow) after a step.
    Observer {
        /// Its position in the observer list (the first one that broke).
        index: usize,
        /// Its [`name`](crate::Observer::name).
        name: String,
    },
    /// A step or an observer failed: see [`RunError::error`].
    Error,
}

/// Summary of a run of several steps.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunSummary {
    /// Steps taken.
    pub steps: usize,
    /// Wall time (s).
    pub seconds: f64,
    /// Mean fixed point iterations per step.
    pub fpi_mean: f64,
    /// Maximum fixed point iterations of a step.
    pub fpi_max: usize,
    /// Total velocity-solver iterations.
    pub solver_iterations: usize,
    /// Steps in which a damped step was taken at least once.
    pub relaxed_steps: usize,
    /// Adaptive steps: rejected attempts over the run.
    pub rejected_attempts: usize,
    /// Why the run ended.
    pub termination: Termination,
}

impl RunSummary {
    /// Whether an observer ended the run.
    pub fn stopped_by_observer(&self) -> bool {
        matches!(self.termination, Termination::Observer { .. })
    }
}

/// A run that failed: the error and the summary of the steps taken before it (the
/// simulation keeps the state of the last successful step; every observer's
/// [`finish`](crate::Observer::finish) has been called). Converts into the [`Error`] with
/// `?`. Its `Display` says how far the run got; the error is its
/// [`source`](std::error::Error::source).
#[derive(Debug)]
pub struct RunError {
    /// What failed.
    pub error: Error,
    /// The run up to the failure (`termination` is [`Termination::Error`]).
    pub summary: Box<RunSummary>,
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "the run failed after {} steps", self.summary.steps)
    }
}

impl std::error::Error for RunError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.error)
    }
}

impl From<RunError> for Error {
    fn from(e: RunError) -> Error {
        e.error
    }
}

/// Whether `time` has reached `t_end` for steps of `tau`, up to [`time_slack`].
pub(crate) fn time_reached(time: f64, t_end: f64, tau: f64) -> bool {
    time >= t_end - time_slack(t_end, tau)
}

/// Round-off allowance of a comparison with the time `t` for steps of `tau` (s):
/// `1e-9 · min(τ, |t|)`. Relative to τ, so that a time that lands next to `t` by round-off
/// is not followed by a sliver of a step; at most `1e-9 |t|`, so that a huge step (τ ≫ |t|)
/// does not swallow `t` itself.
pub(crate) fn time_slack(t: f64, tau: f64) -> f64 {
    1e-9 * tau.min(t.abs())
}

/// Shows the step of `report` (state `state` of `problem`) to every observer: [`notify`]
/// with the view.
///
/// # Errors
/// As [`notify`].
pub(crate) fn notify_step<const D: usize, L: FrictionLaw, S: StateLaw, const C: usize>(
    observers: &mut [&mut dyn Observer<D, C>],
    problem: &Problem<D, L, S, C>,
    state: &SimulationState,
    report: &StepReport,
) -> Result<Option<Termination>> {
    let view = StepView {
        model: problem.model(),
        state,
        report,
        friction: problem.fault_tractions(),
    };
    notify(observers, &view)
}

/// Checks the end time of a run.
///
/// # Errors
/// [`Error::InvalidParameter`] named `until` unless `t_end` is finite.
pub(crate) fn check_end_time(t_end: f64) -> Result<()> {
    if t_end.is_finite() {
        Ok(())
    } else {
        Err(invalid(
            "until",
            format!("end time {t_end} s must be finite"),
        ))
    }
}

/// Shows a step to every observer; the first one that breaks gives the termination (the
/// others still see the step).
///
/// # Errors
/// The first observer error (the observers after it do not see the step).
pub(crate) fn notify<const D: usize, const C: usize>(
    observers: &mut [&mut dyn Observer<D, C>],
    view: &StepView<'_, D, C>,
) -> Result<Option<Termination>> {
    let mut first_break = None;
    for (index, o) in observers.iter_mut().enumerate() {
        let flow = o.observe(view)?;
        if flow.is_break() && first_break.is_none() {
            first_break = Some(Termination::Observer {
                index,
                name: o.name(),
            });
        }
    }
    Ok(first_break)
}

/// A run of `body` (the steps, accumulating into the summary) with its observers: the
/// wall time, every observer's `finish` once at the end ([`finish_run`]), the summary or
/// the error with the summary.
pub(crate) fn observed_run<const D: usize, const C: usize>(
    observers: &mut [&mut dyn Observer<D, C>],
    body: impl FnOnce(&mut [&mut dyn Observer<D, C>], &mut RunSummary) -> Result<()>,
) -> std::result::Result<RunSummary, RunError> {
    let start = Instant::now();
    let mut summary = RunSummary::default();
    let outcome = body(observers, &mut summary);
    finish_run(observers, outcome, summary, start)
}

/// Ends a run: every observer's `finish` (all of them, the first error kept), the wall
/// time since `start`, and the summary or the error with the summary.
pub(crate) fn finish_run<const D: usize, const C: usize>(
    observers: &mut [&mut dyn Observer<D, C>],
    outcome: Result<()>,
    mut summary: RunSummary,
    start: Instant,
) -> std::result::Result<RunSummary, RunError> {
    let mut finished = Ok(());
    for o in observers.iter_mut() {
        let f = o.finish();
        if finished.is_ok() {
            finished = f;
        }
    }
    summary.seconds = start.elapsed().as_secs_f64();
    match outcome.and(finished) {
        Ok(()) => Ok(summary),
        Err(error) => {
            summary.termination = Termination::Error;
            Err(RunError {
                error,
                summary: Box::new(summary),
            })
        }
    }
}
