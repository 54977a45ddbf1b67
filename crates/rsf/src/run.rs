//! One run loop for every method: a method steps ([`Stepping`]: the implicit
//! [`Simulation`](crate::Simulation), the [`FaultOde`](crate::FaultOde), the
//! [`SwitchingRun`](crate::SwitchingRun)), [`run_until`] drives it and shows every step to
//! the observers; where a run ends ([`Until`]), why it ended ([`Termination`]), and what it
//! did ([`RunSummary`], also on failure through [`RunError`]).

use std::time::Instant;

use crate::checkpoint::Checkpoint;
use crate::error::{invalid, Error, Result};
use crate::method_state::MethodState;
use crate::model::Model;
use crate::observe::{FaultTractions, Observer, StepView};
pub use crate::report::StepReport;
use crate::simulation_state::SimulationState;

/// A method that advances a problem's state one step at a time: what [`run_until`] drives.
/// The library's three methods implement it — the paper's implicit
/// [`Simulation`](crate::Simulation), the quasi-dynamic [`FaultOde`](crate::FaultOde) and
/// the [`SwitchingRun`](crate::SwitchingRun) between them — and so can a user's own.
///
/// Every method's whole state is the common [`SimulationState`] plus its own
/// [`MethodState`]; a [`Checkpoint`] holds both, and [`restore`](Self::restore) of a
/// checkpoint continues bit-identically.
pub trait Stepping<const D: usize, const C: usize = D> {
    /// Advances one accepted step (an adaptive method may shorten it to end at `t_end`, s).
    /// `reads_volume`: whether the observers read the field off Γ_F (a method condensed
    /// onto the fault computes it only then, [`Observer::reads_volume`]).
    ///
    /// # Errors
    /// The method's step errors (a fixed point or a step size that fails, …); the state is
    /// that of the last successful step.
    fn advance(&mut self, t_end: Option<f64>, reads_volume: bool) -> Result<StepReport>;

    /// Called once before a run's steps with the vertices off Γ_F that the observers read
    /// without reading the whole volume ([`Observer::volume_vertices`]; sorted, without
    /// repeats): a method condensed onto the fault computes their `u` and `v` after every
    /// step. Default: nothing (a method that always has the whole field).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a vertex that is not the model's; the method's
    /// set-up errors.
    fn watch_vertices(&mut self, vertices: &[usize]) -> Result<()> {
        let _ = vertices;
        Ok(())
    }

    /// The model the current state belongs to.
    fn model(&self) -> &Model<D, C>;

    /// The common state after the last step.
    fn state(&self) -> &SimulationState;

    /// The smallest step the method's adaptive control may take now (s): its `tau_min`
    /// or `dt_min`; `None` for fixed steps (default). A run whose accepted steps stay at
    /// this floor has collapsed ([`run_until`], [`Error::StepSizeCollapse`]).
    fn step_floor(&self) -> Option<f64> {
        None
    }

    /// The tractions of the friction laws, as observers see them.
    fn fault_tractions(&self) -> &dyn FaultTractions;

    /// The method's own state beyond [`state`](Self::state) (what a checkpoint saves).
    fn method_state(&self) -> MethodState;

    /// Whether the state has reached the end time `t_end` (s), up to round-off relative to
    /// the next step ([`Until::Time`]).
    fn reached(&self, t_end: f64) -> bool {
        let s = self.state();
        time_reached(s.time, t_end, s.tau)
    }

    /// A checkpoint of the whole state (common and the method's own), for
    /// [`restore`](Self::restore).
    fn checkpoint(&self) -> Checkpoint {
        let mut c = Checkpoint::new(D, self.state().clone());
        c.method = self.method_state();
        c
    }

    /// Continues from a checkpoint of the same method on the same model; the continuation
    /// is bit-identical to an uninterrupted run.
    ///
    /// # Errors
    /// [`Error::CheckpointSize`], [`Error::CheckpointValue`] or
    /// [`Error::CheckpointMismatch`] (a checkpoint of another method) naming what differs;
    /// the method's set-up errors. The method is unchanged on error.
    fn restore(&mut self, checkpoint: &Checkpoint) -> Result<()>;
}

/// Steps `method` until `until` is reached or an observer returns
/// [`Flow::Break`](crate::Flow) (after every observer has seen that step), then calls
/// every observer's [`finish`](Observer::finish) — also when the run fails. The summary
/// says why the run ended ([`Termination`]). The run loop of every method's `run_until`.
///
/// A run that cannot progress ends with [`Error::StepSizeCollapse`], as an ODE solver
/// reports a step-size underflow, instead of running on: when
/// [`COLLAPSE_STEPS`] accepted steps in a row are at the method's floor
/// ([`Stepping::step_floor`]: within a factor 2 of `tau_min`/`dt_min`), and when
/// [`Until::TimeWithin`]'s stated number of steps is spent before its end time.
///
/// # Errors
/// A [`RunError`] with the first step or observer error (or, after the steps, the first
/// error of a `finish`) and the summary of the steps taken; the method keeps the state of
/// the last successful step. [`Error::InvalidParameter`] named `until` for a non-finite end
/// time; [`Error::StepSizeCollapse`] for a run that cannot progress (above).
pub fn run_until<const D: usize, const C: usize, M: Stepping<D, C> + ?Sized>(
    method: &mut M,
    until: Until,
    observers: &mut [&mut dyn Observer<D, C>],
) -> std::result::Result<RunSummary, RunError> {
    observed_run(observers, |observers, summary| {
        let mut fpi_total = 0;
        let outcome = run_loop(method, until, observers, summary, &mut fpi_total);
        summary.fpi_mean = if summary.steps > 0 {
            fpi_total as f64 / summary.steps as f64
        } else {
            0.0
        };
        outcome
    })
}

/// The inherent `run_until` of a method (a type that is [`Stepping<D, C>`], with its `D`
/// and `C` in scope), with the docs given: [`run_until`] on `self`, so that a user needs
/// no trait in scope to run it.
macro_rules! run_until_method {
    ($(#[$doc:meta])*) => {
        $(#[$doc])*
        pub fn run_until(
            &mut self,
            until: $crate::run::Until,
            observers: &mut [&mut dyn $crate::observe::Observer<D, C>],
        ) -> std::result::Result<$crate::run::RunSummary, $crate::run::RunError> {
            $crate::run::run_until(self, until, observers)
        }
    };
}
pub(crate) use run_until_method;

/// The steps of [`run_until`], accumulating into `summary` and the total of fixed point
/// iterations.
fn run_loop<const D: usize, const C: usize, M: Stepping<D, C> + ?Sized>(
    method: &mut M,
    until: Until,
    observers: &mut [&mut dyn Observer<D, C>],
    summary: &mut RunSummary,
    fpi_total: &mut usize,
) -> Result<()> {
    let t_end = match until {
        Until::Time(t)
        | Until::TimeOrStepCap { time: t, .. }
        | Until::TimeWithin { time: t, .. } => {
            check_end_time(t)?;
            Some(t)
        }
        Until::Steps(_) => None,
    };
    let mut progress = Progress::default();
    let volume = observers.iter().any(|o| o.reads_volume());
    if !volume {
        let mut watched: Vec<usize> = observers.iter().flat_map(|o| o.volume_vertices()).collect();
        watched.sort_unstable();
        watched.dedup();
        method.watch_vertices(&watched)?;
    }
    let mut last: Option<StepReport> = None;
    loop {
        let reached = match until {
            Until::Steps(k) => (summary.steps >= k).then_some(Termination::StepCount),
            Until::Time(t) => method.reached(t).then_some(Termination::EndTime),
            Until::TimeWithin { time, max_steps } => {
                if method.reached(time) {
                    Some(Termination::EndTime)
                } else if summary.steps >= max_steps {
                    let s = method.state();
                    return Err(Error::StepSizeCollapse {
                        time: s.time,
                        tau: last.as_ref().map_or(s.tau, |r| r.tau),
                        rejected_error: progress.rejected_error,
                        reason: format!(
                            "{max_steps} steps (the run's stated bound) did not reach the end \
                             time {time:e} s"
                        ),
                    });
                } else {
                    None
                }
            }
            Until::TimeOrStepCap { time, step_cap } => {
                if method.reached(time) {
                    Some(Termination::EndTime)
                } else if method.state().step >= step_cap {
                    stop_at_cap(method, observers, last.as_ref())?;
                    Some(Termination::StepCap)
                } else {
                    None
                }
            }
        };
        if let Some(reason) = reached {
            summary.termination = reason;
            return Ok(());
        }
        let report = method.advance(t_end, volume)?;
        *fpi_total += report.fixed_point_iterations;
        summary.fpi_max = summary.fpi_max.max(report.fixed_point_iterations);
        summary.solver_iterations += report.solver_iterations;
        summary.evaluations += report.evaluations;
        summary.relaxed_steps += usize::from(report.relaxed_iterations > 0);
        summary.rejected_attempts += report.rejected_attempts;
        summary.rejected_normal_stress += report.rejected_normal_stress;
        summary.steps += 1;
        progress.check(&report, method.step_floor())?;
        let view = StepView {
            model: method.model(),
            state: method.state(),
            report: &report,
            friction: method.fault_tractions(),
            method: &|| method.method_state(),
        };
        if let Some(reason) = notify(observers, &view)? {
            summary.termination = reason;
            return Ok(());
        }
        last = Some(report);
    }
}

/// Accepted steps in a row at the method's floor ([`Stepping::step_floor`]) after which a
/// run has collapsed ([`Error::StepSizeCollapse`]): a step control that cannot leave its
/// floor for a hundred steps will not, and the run would take `T/τ_min` steps.
pub const COLLAPSE_STEPS: usize = 100;

/// What a run's progress check keeps ([`run_until`]): the accepted steps in a row at the
/// floor and the last rejected error estimate.
#[derive(Debug, Default)]
struct Progress {
    at_floor: usize,
    rejected_error: f64,
}

impl Progress {
    /// Counts the accepted step `report` against the method's `floor`.
    ///
    /// # Errors
    /// [`Error::StepSizeCollapse`] after [`COLLAPSE_STEPS`] steps in a row at the floor.
    fn check(&mut self, report: &StepReport, floor: Option<f64>) -> Result<()> {
        if report.rejected_attempts > 0 {
            self.rejected_error = report.rejected_error;
        }
        match floor {
            Some(f) if report.tau <= 2.0 * f => self.at_floor += 1,
            _ => self.at_floor = 0,
        }
        if self.at_floor >= COLLAPSE_STEPS {
            return Err(Error::StepSizeCollapse {
                time: report.time,
                tau: report.tau,
                rejected_error: self.rejected_error,
                reason: format!(
                    "the step size stayed at its floor of {:e} s for {COLLAPSE_STEPS} steps",
                    floor.unwrap_or(0.0)
                ),
            });
        }
        Ok(())
    }
}

/// Shows every observer that the run stops at its step cap
/// ([`Observer::at_step_cap`]), with the last step's report — or, for a state that is at
/// its cap before any step (a resume at the cap, a cap of 0), a report of that state
/// (its step, time and τ; no iterations).
///
/// # Errors
/// The first observer error (the observers after it are not shown the stop).
fn stop_at_cap<const D: usize, const C: usize, M: Stepping<D, C> + ?Sized>(
    method: &M,
    observers: &mut [&mut dyn Observer<D, C>],
    last: Option<&StepReport>,
) -> Result<()> {
    let state = method.state();
    let report = last.copied().unwrap_or(StepReport {
        step: state.step,
        time: state.time,
        tau: state.tau,
        ..StepReport::default()
    });
    let view = StepView {
        model: method.model(),
        state,
        report: &report,
        friction: method.fault_tractions(),
        method: &|| method.method_state(),
    };
    for o in observers.iter_mut() {
        o.at_step_cap(&view)?;
    }
    Ok(())
}

/// Where a run ([`run_until`]) ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Until {
    /// After this many steps.
    Steps(usize),
    /// At the first step with `t_n ≥ t` (s), up to round-off of `1e-9 min(τ, |t|)`. With a
    /// fixed τ the last step is not shortened to land on `t`; with adaptive steps it is, so
    /// the run ends at `t`.
    Time(f64),
    /// At the end time `time` (s, as [`Until::Time`]) or when the state's step index
    /// reaches `step_cap`, whichever comes first. The step index counts from the start of
    /// the run across resumes (a restored checkpoint's `step`), so a run stopped at its cap
    /// and resumed with a larger one continues where it stopped; a state already at or past
    /// the cap computes no step. Stopping at the cap ends with [`Termination::StepCap`]
    /// after every observer's [`at_step_cap`](Observer::at_step_cap): a
    /// [`Checkpointer`](crate::observe::Checkpointer) (also inside
    /// [`Every`](crate::observe::Every)) writes the state there, so the run can be resumed
    /// from exactly where it stopped.
    TimeOrStepCap {
        /// The end time (s).
        time: f64,
        /// The step index to stop at (the state's [`step`](SimulationState::step)).
        step_cap: usize,
    },
    /// At the end time `time` (s, as [`Until::Time`]), which must be reached within
    /// `max_steps` steps of this call: a stated bound, beyond which the run is taken to
    /// have collapsed and ends with [`Error::StepSizeCollapse`] (naming the time, the step
    /// and the last rejected error estimate) instead of running on — the run a test or a
    /// driver that knows its scale should ask for.
    TimeWithin {
        /// The end time (s).
        time: f64,
        /// The most steps the run may take to reach it.
        max_steps: usize,
    },
}

/// Why a run ended.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum Termination {
    /// The end time of [`Until::Time`] was reached.
    #[default]
    EndTime,
    /// The step count of [`Until::Steps`] was reached.
    StepCount,
    /// The step cap of [`Until::TimeOrStepCap`] was reached before its end time (the
    /// state's step and time say where).
    StepCap,
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
    /// Total right-hand-side evaluations of an explicit method (the fault ODE's products
    /// with the condensed operator; 0 for the implicit scheme).
    pub evaluations: usize,
    /// Steps in which a damped step was taken at least once.
    pub relaxed_steps: usize,
    /// Adaptive steps: rejected attempts over the run.
    pub rejected_attempts: usize,
    /// Of `rejected_attempts`, those rejected because a trial state had a normal stress
    /// `σ̄_n ≤ 0` ([`StepReport::rejected_normal_stress`]).
    pub rejected_normal_stress: usize,
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
