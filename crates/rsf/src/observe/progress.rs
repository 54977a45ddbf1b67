//! A progress bar on stderr (feature `progress`, through `indicatif`; only when stderr is a
//! terminal). Without the feature the observer does nothing, so code that adds it compiles
//! either way.

use crate::error::Result;

use super::{Flow, Observer, StepView};

/// Shows the progress of a run: of steps, or of simulated time (for adaptive steps) in the
/// problem's unit (seconds, years).
pub struct Progress {
    #[cfg(feature = "progress")]
    bar: Option<indicatif::ProgressBar>,
    /// Bar positions per simulated second (time-based bar), or `None` (one position per
    /// step).
    #[cfg_attr(not(feature = "progress"), allow(dead_code))]
    per_second: Option<f64>,
}

/// Positions of a time-based bar from 0 to its end time.
const TIME_POSITIONS: f64 = 1e6;

impl Progress {
    /// A bar labelled `label` for `steps` steps.
    pub fn steps(steps: usize, label: &str) -> Self {
        #[cfg(not(feature = "progress"))]
        let _ = (steps, label);
        Self {
            #[cfg(feature = "progress")]
            bar: bar(steps as u64, label, None),
            per_second: None,
        }
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
