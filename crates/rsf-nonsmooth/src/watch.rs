//! A watch over a long iterative solve: progress reports as it goes and a wall-clock cap
//! (the iteration cap is the stopping test's, [`Stopping::max_iterations`](crate::Stopping)).
//! A solve that is watched never runs silently without bound: it reports every `every`
//! seconds and stops at its time limit with the solver's typed error, which carries the
//! iterations done and the last correction.

use std::fmt;
use std::time::Instant;

/// Where an iterative solve stands: what a [`SolveWatch`] reports.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveProgress {
    /// The solver's name ("tnnmg", …).
    pub solver: &'static str,
    /// Iterations done.
    pub iteration: usize,
    /// The iteration cap ([`Stopping::max_iterations`](crate::Stopping)).
    pub max_iterations: usize,
    /// The energy norm of the last correction.
    pub correction: f64,
    /// What the correction must reach to stop: `absolute + relative · ‖v‖` at the current
    /// iterate (the relative part `0` where the solver does not compute `‖v‖`).
    pub tolerance: f64,
    /// Wall time since the solve started (s).
    pub seconds: f64,
}

impl fmt::Display for SolveProgress {
    /// `tnnmg: iteration 12/500, correction 3.1e-4 (tolerance 1.0e-10), 4.2 s`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: iteration {}/{}, correction {:.3e} (tolerance {:.3e}), {:.1} s",
            self.solver,
            self.iteration,
            self.max_iterations,
            self.correction,
            self.tolerance,
            self.seconds
        )
    }
}

/// What a [`SolveWatch`] tells the solver after an iteration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WatchVerdict {
    /// Go on.
    Continue,
    /// The time limit is reached: stop with the solver's error.
    OutOfTime,
}

/// What a [`SolveWatch`] calls with each progress report.
type Report = Box<dyn FnMut(&SolveProgress) + Send>;

/// A progress report every `every` seconds (and after the first iteration) and a
/// wall-clock limit on one solve, for the solvers that take one (`rsf_tnnmg::Tnnmg::
/// with_watch`, `rsf::model::StaticOptions`). The reports do not change the iterates: a
/// watched solve that converges has the bits of an unwatched one.
///
/// ```
/// use rsf_nonsmooth::SolveWatch;
/// // Print a line every 10 s (stderr), give up after 10 minutes.
/// let watch = SolveWatch::to_stderr(10.0).time_limit(600.0);
/// assert_eq!(watch.limit(), Some(600.0));
/// ```
pub struct SolveWatch {
    every: f64,
    limit: Option<f64>,
    report: Option<Report>,
    start: Option<Instant>,
    last_report: f64,
    /// The iteration of the last report.
    reported: Option<usize>,
}

impl fmt::Debug for SolveWatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("SolveWatch")
            .field("every", &self.every)
            .field("limit", &self.limit)
            .field("reports", &self.report.is_some())
            .finish()
    }
}

impl Default for SolveWatch {
    fn default() -> Self {
        Self::new()
    }
}

impl SolveWatch {
    /// No reports, no time limit (the iteration cap alone).
    pub fn new() -> Self {
        Self {
            every: f64::INFINITY,
            limit: None,
            report: None,
            start: None,
            last_report: 0.0,
            reported: None,
        }
    }

    /// Calls `report` after the first iteration and then at most every `every_seconds`
    /// (s; `0`: after every iteration), and once more when the solve ends (converged, out
    /// of iterations or of time). A negative or NaN interval is read as 0.
    pub fn progress(
        mut self,
        every_seconds: f64,
        report: impl FnMut(&SolveProgress) + Send + 'static,
    ) -> Self {
        self.every = if every_seconds >= 0.0 {
            every_seconds
        } else {
            0.0
        };
        self.report = Some(Box::new(report));
        self
    }

    /// Reports as [`progress`](Self::progress) as lines on the standard error
    /// ([`SolveProgress`]'s `Display`).
    pub fn to_stderr(every_seconds: f64) -> Self {
        Self::new().progress(every_seconds, |p| eprintln!("{p}"))
    }

    /// Stops the solve once it has run `seconds` (wall time, checked after each iteration:
    /// an iteration started before the limit ends first) with the solver's error (e.g.
    /// `rsf_tnnmg::Error::TimeLimit`). A non-positive or NaN limit stops after the first
    /// iteration.
    pub fn time_limit(mut self, seconds: f64) -> Self {
        self.limit = Some(if seconds > 0.0 { seconds } else { 0.0 });
        self
    }

    /// The time limit (s), if any.
    pub fn limit(&self) -> Option<f64> {
        self.limit
    }

    /// Starts the clock of a solve (the solver calls this when a solve begins).
    pub fn start(&mut self) {
        self.start = Some(Instant::now());
        self.last_report = f64::NEG_INFINITY;
        self.reported = None;
    }

    /// Seconds since [`start`](Self::start) (0 before it).
    pub fn elapsed(&self) -> f64 {
        self.start.map_or(0.0, |s| s.elapsed().as_secs_f64())
    }

    /// After an iteration: reports `progress` if it is time to (its `seconds` are set
    /// here), and says whether the solve may go on.
    pub fn after_iteration(&mut self, mut progress: SolveProgress) -> WatchVerdict {
        progress.seconds = self.elapsed();
        let out_of_time = self.limit.is_some_and(|l| progress.seconds >= l);
        let due = progress.seconds - self.last_report >= self.every || out_of_time;
        if let Some(report) = self.report.as_mut() {
            if due || progress.iteration == 1 {
                report(&progress);
                self.last_report = progress.seconds;
                self.reported = Some(progress.iteration);
            }
        }
        if out_of_time {
            WatchVerdict::OutOfTime
        } else {
            WatchVerdict::Continue
        }
    }

    /// When a solve ends (converged or not): one last report, unless the last iteration's
    /// was just made.
    pub fn finish(&mut self, mut progress: SolveProgress) {
        progress.seconds = self.elapsed();
        if let Some(report) = self.report.as_mut() {
            if self.reported != Some(progress.iteration) {
                report(&progress);
                self.last_report = progress.seconds;
                self.reported = Some(progress.iteration);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    fn at(iteration: usize) -> SolveProgress {
        SolveProgress {
            solver: "test",
            iteration,
            max_iterations: 10,
            correction: 1.0,
            tolerance: 1e-3,
            seconds: 0.0,
        }
    }

    #[test]
    fn reports_the_first_iteration_and_the_end_and_stops_at_its_limit() {
        let seen = Arc::new(Mutex::new(Vec::new()));
        let s = seen.clone();
        let mut w = SolveWatch::new()
            .progress(1e9, move |p| s.lock().unwrap().push(p.iteration))
            .time_limit(1e9);
        w.start();
        assert_eq!(w.after_iteration(at(1)), WatchVerdict::Continue);
        assert_eq!(w.after_iteration(at(2)), WatchVerdict::Continue);
        w.finish(at(2));
        assert_eq!(*seen.lock().unwrap(), vec![1, 2]);
        let mut w = SolveWatch::new().time_limit(0.0);
        w.start();
        assert_eq!(w.after_iteration(at(1)), WatchVerdict::OutOfTime);
        assert_eq!(
            format!("{}", at(3)),
            "test: iteration 3/10, correction 1.000e0 (tolerance 1.000e-3), 0.0 s"
        );
    }
}
