//! A progress bar on stderr (feature `progress`, through `indicatif`) when stderr is a
//! terminal; when it is not (a log file, a notebook, a batch job's output), a plain line
//! every [`PROGRESS_LINE_SECONDS`] of wall time instead (issue 86: nothing was shown). Without
//! the feature the observer does nothing, so code that adds it compiles either way.

use crate::error::Result;

use super::{Flow, Observer, StepView};

/// Shows the progress of a run: of steps, or of simulated time (for adaptive steps) in the
/// problem's unit (seconds, years).
pub struct Progress {
    #[cfg(feature = "progress")]
    bar: Option<indicatif::ProgressBar>,
    /// The plain lines when stderr is not a terminal.
    #[cfg(feature = "progress")]
    lines: Option<Lines>,
    /// Bar positions per simulated second (time-based bar), or `None` (one position per
    /// step).
    #[cfg_attr(not(feature = "progress"), allow(dead_code))]
    per_second: Option<f64>,
}

/// Positions of a time-based bar from 0 to its end time.
const TIME_POSITIONS: f64 = 1e6;

/// Wall-clock seconds between the plain progress lines a run writes when stderr is not a
/// terminal ([`Progress::line_interval`] sets another).
pub const PROGRESS_LINE_SECONDS: f64 = 30.0;

/// The plain progress lines of a run whose stderr is not a terminal: where it is, written
/// every `interval` of wall time.
#[cfg(feature = "progress")]
struct Lines {
    label: String,
    started: std::time::Instant,
    last: std::time::Instant,
    interval: std::time::Duration,
    /// Steps taken and their count (`None`: a time-based run).
    steps: Option<(u64, u64)>,
    /// The end time (s) and its unit of a time-based run.
    time: (f64, TimeUnit),
}

#[cfg(feature = "progress")]
impl Lines {
    fn new(label: &str, steps: Option<u64>, time: (f64, TimeUnit)) -> Option<Self> {
        use std::io::IsTerminal;
        if std::io::stderr().is_terminal() {
            return None;
        }
        let now = std::time::Instant::now();
        Some(Self {
            label: label.to_owned(),
            started: now,
            last: now,
            interval: std::time::Duration::from_secs_f64(PROGRESS_LINE_SECONDS),
            steps: steps.map(|n| (0, n)),
            time,
        })
    }

    /// Counts a step at time `t` (s) and writes a line if `interval` has passed.
    fn step(&mut self, t: f64) {
        if let Some((done, _)) = &mut self.steps {
            *done += 1;
        }
        let now = std::time::Instant::now();
        if now.duration_since(self.last) >= self.interval {
            self.last = now;
            let elapsed = now.duration_since(self.started).as_secs_f64();
            eprintln!("{}", self.line(t, elapsed));
        }
    }

    /// The line at time `t` (s) after `elapsed` seconds of wall time:
    /// `BP1: 12.50/1800 yr (0.7 %), 30 s` or `slider: 1200/4000 steps (30.0 %), 30 s`.
    fn line(&self, t: f64, elapsed: f64) -> String {
        let (now, end, unit) = match self.steps {
            Some((done, n)) => (done as f64, n as f64, "steps"),
            None => {
                let (t_end, unit) = self.time;
                (t / unit.seconds, t_end / unit.seconds, unit.symbol)
            }
        };
        let percent = if end > 0.0 { 100.0 * now / end } else { 0.0 };
        let decimals = match self.steps {
            Some(_) => 0,
            None => (3.0 - end.abs().max(1e-300).log10().floor()).clamp(0.0, 6.0) as usize,
        };
        format!(
            "{}: {now:.decimals$}/{end:.decimals$} {unit} ({percent:.1} %), {elapsed:.0} s",
            self.label
        )
    }
}

impl Progress {
    /// A bar labelled `label` for `steps` steps.
    pub fn steps(steps: usize, label: &str) -> Self {
        #[cfg(not(feature = "progress"))]
        let _ = (steps, label);
        #[cfg(feature = "progress")]
        let bar = bar(steps as u64, label, None);
        Self {
            #[cfg(feature = "progress")]
            lines: match bar {
                None => Lines::new(label, Some(steps as u64), (0.0, TimeUnit::SECOND)),
                Some(_) => None,
            },
            #[cfg(feature = "progress")]
            bar,
            per_second: None,
        }
    }

    /// The progress with its plain lines (when stderr is not a terminal) every `seconds` of
    /// wall time instead of [`PROGRESS_LINE_SECONDS`] (a value that is not a positive number
    /// keeps the default).
    #[cfg_attr(not(feature = "progress"), allow(unused_mut))]
    pub fn line_interval(mut self, seconds: f64) -> Self {
        #[cfg(feature = "progress")]
        if let Some(l) = &mut self.lines {
            if seconds > 0.0 && seconds.is_finite() {
                l.interval = std::time::Duration::from_secs_f64(seconds);
            }
        }
        #[cfg(not(feature = "progress"))]
        let _ = seconds;
        self
    }

    /// A bar labelled `label` of simulated time from `t0` to `t_end` (s), shown in seconds.
    pub fn time(t0: f64, t_end: f64, label: &str) -> Self {
        Self::time_in(t0, t_end, TimeUnit::SECOND, label)
    }

    /// A bar labelled `label` of simulated time from `t0` to `t_end` (s), shown in `unit`
    /// (`12.5/1800 yr`): what a long run's user reads its end time in.
    pub fn time_in(t0: f64, t_end: f64, unit: TimeUnit, label: &str) -> Self {
        let per_second = if t_end > 0.0 && t_end.is_finite() {
            TIME_POSITIONS / t_end
        } else {
            0.0
        };
        #[cfg(feature = "progress")]
        let bar = bar(TIME_POSITIONS as u64, label, Some((t_end, unit)));
        #[cfg(feature = "progress")]
        if let Some(b) = &bar {
            b.set_position(position(per_second, t0));
        }
        #[cfg(not(feature = "progress"))]
        let _ = (t0, unit, label);
        Self {
            #[cfg(feature = "progress")]
            lines: match bar {
                None => Lines::new(label, None, (t_end, unit)),
                Some(_) => None,
            },
            #[cfg(feature = "progress")]
            bar,
            per_second: Some(per_second),
        }
    }
}

/// The unit a time-based [`Progress`] bar shows simulated time in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeUnit {
    /// Seconds per unit.
    pub seconds: f64,
    /// Its symbol (`"s"`, `"yr"`).
    pub symbol: &'static str,
}

impl TimeUnit {
    /// The second.
    pub const SECOND: Self = Self {
        seconds: 1.0,
        symbol: "s",
    };

    /// The year of `seconds_per_year` seconds ([`SECONDS_PER_YEAR`](super::SECONDS_PER_YEAR),
    /// or a scene's own year).
    pub const fn year(seconds_per_year: f64) -> Self {
        Self {
            seconds: seconds_per_year,
            symbol: "yr",
        }
    }
}

/// The bar position of time `t` (s).
#[cfg(feature = "progress")]
fn position(per_second: f64, t: f64) -> u64 {
    (per_second * t).clamp(0.0, TIME_POSITIONS) as u64
}

/// A progress bar on stderr when it is a terminal, nothing otherwise; with `time`
/// (`(t_end, unit)`) its positions are shown as simulated time in `unit`.
#[cfg(feature = "progress")]
fn bar(len: u64, label: &str, time: Option<(f64, TimeUnit)>) -> Option<indicatif::ProgressBar> {
    use std::io::IsTerminal;
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(len);
    let style = match time {
        None => indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} ({eta})"),
        Some(_) => indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {simulated} ({eta})"),
    }
    .expect("valid template")
    .progress_chars("=> ");
    let style = match time {
        None => style,
        Some((t_end, unit)) => {
            let end = t_end / unit.seconds;
            // Decimals so that the end shows about four significant digits.
            let decimals = (3.0 - end.abs().max(1e-300).log10().floor()).clamp(0.0, 6.0) as usize;
            style.with_key(
                "simulated",
                move |state: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                    let now = state.pos() as f64 / TIME_POSITIONS * end;
                    let _ = write!(w, "{now:.decimals$}/{end:.decimals$} {}", unit.symbol);
                },
            )
        }
    };
    bar.set_style(style);
    bar.set_message(label.to_string());
    Some(bar)
}

impl<const D: usize, const C: usize> Observer<D, C> for Progress {
    fn observe(&mut self, _s: &StepView<'_, D, C>) -> Result<Flow> {
        #[cfg(feature = "progress")]
        if let Some(b) = &self.bar {
            match self.per_second {
                Some(k) => b.set_position(position(k, _s.report.time)),
                None => b.inc(1),
            }
        }
        #[cfg(feature = "progress")]
        if let Some(l) = &mut self.lines {
            l.step(_s.report.time);
        }
        Ok(Flow::Continue(()))
    }
    fn finish(&mut self) -> Result<()> {
        #[cfg(feature = "progress")]
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
        Ok(())
    }
    fn reads_volume(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain lines (stderr not a terminal) show the run's progress in its unit, with
    /// the bar's decimals, and in steps for a step-based run.
    #[cfg(feature = "progress")]
    #[test]
    fn plain_lines_show_the_progress_in_the_problems_unit() {
        let year = TimeUnit::year(365.25 * 86_400.0);
        let now = std::time::Instant::now();
        let mut lines = Lines {
            label: "BP1".into(),
            started: now,
            last: now,
            interval: std::time::Duration::from_secs(30),
            steps: None,
            time: (1800.0 * year.seconds, year),
        };
        assert_eq!(
            lines.line(12.6 * year.seconds, 30.2),
            "BP1: 13/1800 yr (0.7 %), 30 s"
        );
        lines.time = (2.0 * year.seconds, year);
        assert_eq!(
            lines.line(0.5 * year.seconds, 5.0),
            "BP1: 0.500/2.000 yr (25.0 %), 5 s"
        );
        lines.steps = Some((1200, 4000));
        lines.label = "slider".into();
        assert_eq!(
            lines.line(0.0, 61.0),
            "slider: 1200/4000 steps (30.0 %), 61 s"
        );
        lines.steps = Some((0, 0));
        assert_eq!(lines.line(0.0, 0.0), "slider: 0/0 steps (0.0 %), 0 s");
    }

    /// A time-based bar maps `[0, t_end]` onto its positions and clamps outside; a zero
    /// or infinite end time gives a bar that stays at 0 instead of a division's NaN.
    #[test]
    fn time_bars_map_the_run_onto_their_positions() {
        let year = TimeUnit::year(365.25 * 86_400.0);
        let p = Progress::time_in(0.0, 1800.0 * year.seconds, year, "test");
        let k = p.per_second.expect("time-based");
        assert_eq!((k * 1800.0 * year.seconds).round(), TIME_POSITIONS);
        assert_eq!((k * 900.0 * year.seconds).round(), TIME_POSITIONS / 2.0);
        for t_end in [0.0, f64::INFINITY, f64::NAN] {
            let p = Progress::time_in(0.0, t_end, TimeUnit::SECOND, "test");
            assert_eq!(p.per_second, Some(0.0), "t_end = {t_end}");
        }
        #[cfg(feature = "progress")]
        {
            assert_eq!(position(k, -1.0), 0);
            assert_eq!(position(k, 1e9 * year.seconds), TIME_POSITIONS as u64);
            assert_eq!(position(f64::NAN, 1.0), 0);
        }
    }
}
