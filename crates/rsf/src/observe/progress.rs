//! A progress bar on stderr (feature `progress`, through `indicatif`; only when stderr is a
//! terminal). Without the feature the observer does nothing, so code that adds it compiles
//! either way.

use crate::error::Result;

use super::{Flow, Observer, StepView};

/// Shows the progress of a run: of steps, or of simulated time (for adaptive steps).
pub struct Progress {
    #[cfg(feature = "progress")]
    bar: Option<indicatif::ProgressBar>,
    /// Bar units per simulated second (time-based bar), or `None` (one unit per step).
    #[cfg_attr(not(feature = "progress"), allow(dead_code))]
    per_second: Option<f64>,
}

impl Progress {
    /// A bar labelled `label` for `steps` steps.
    pub fn steps(steps: usize, label: &str) -> Self {
        #[cfg(not(feature = "progress"))]
        let _ = (steps, label);
        Self {
            #[cfg(feature = "progress")]
            bar: bar(steps as u64, label),
            per_second: None,
        }
    }

    /// A bar labelled `label` of simulated time from `t0` to `t_end` (s), in milliseconds.
    pub fn time(t0: f64, t_end: f64, label: &str) -> Self {
        #[cfg(feature = "progress")]
        let bar = bar((1e3 * t_end).ceil().max(0.0) as u64, label);
        #[cfg(feature = "progress")]
        if let Some(b) = &bar {
            b.set_position((1e3 * t0).max(0.0) as u64);
        }
        #[cfg(not(feature = "progress"))]
        let _ = (t0, t_end, label);
        Self {
            #[cfg(feature = "progress")]
            bar,
            per_second: Some(1e3),
        }
    }
}

/// A progress bar on stderr when it is a terminal, nothing otherwise.
#[cfg(feature = "progress")]
fn bar(len: u64, label: &str) -> Option<indicatif::ProgressBar> {
    use std::io::IsTerminal;
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(len);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} ({eta})")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(label.to_string());
    Some(bar)
}

impl<const D: usize, const C: usize> Observer<D, C> for Progress {
    fn observe(&mut self, _s: &StepView<'_, D, C>) -> Result<Flow> {
        #[cfg(feature = "progress")]
        if let Some(b) = &self.bar {
            match self.per_second {
                Some(k) => b.set_position((k * _s.report.time) as u64),
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
