//! Sampling: show an observer every `n`-th step or one step per interval of time.

use crate::error::{invalid, Result};

use super::{Flow, Observer, StepView};

/// How often [`Every`] shows a step to its observer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Interval {
    /// Steps whose index is a multiple of `n` (`n ≥ 1`).
    Steps(usize),
    /// The first step at or after each multiple of `dt` (s, finite and > 0): the step
    /// crosses (or ends on) a multiple. For runs whose steps vary (adaptive steps); the
    /// decision depends on the step's time and τ only, so a resumed run samples the same
    /// steps.
    Time(f64),
    /// No step: the inner observer sees only a stop at a step cap
    /// ([`Observer::at_step_cap`]) and [`finish`](Observer::finish) — e.g. a
    /// [`Checkpointer`](crate::observe::Checkpointer) that writes only where a capped run
    /// stops.
    Never,
}

impl Interval {
    /// Checks `n ≥ 1`, `dt` finite and > 0.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `every`.
    pub fn validate(&self) -> Result<()> {
        match *self {
            Interval::Steps(0) => Err(invalid("every", "a step interval must be at least 1")),
            Interval::Time(dt) if !(dt.is_finite() && dt > 0.0) => Err(invalid(
                "every",
                format!("a time interval must be finite and > 0 (s), got {dt}"),
            )),
            _ => Ok(()),
        }
    }

    /// Every `n`-th step, or [`Interval::Never`] for `n = 0` (a program's
    /// `--checkpoint-every 0`).
    pub fn steps_or_never(n: usize) -> Self {
        if n == 0 {
            Interval::Never
        } else {
            Interval::Steps(n)
        }
    }

    /// Whether the step `step` ending at `time` (s) after a step of `tau` (s) is sampled.
    pub fn samples(&self, step: usize, time: f64, tau: f64) -> bool {
        match *self {
            Interval::Steps(n) => step % n == 0,
            Interval::Time(dt) => (time / dt).floor() > ((time - tau) / dt).floor(),
            Interval::Never => false,
        }
    }
}

/// Shows the steps of a run to an inner observer at an [`Interval`] only; passes
/// [`finish`](Observer::finish) and [`at_step_cap`](Observer::at_step_cap) on.
///
/// ```
/// use rsf::observe::{Every, Interval, Reports};
/// let every_tenth = Every::new(Interval::Steps(10), Reports::default())?;
/// assert!(Every::new(Interval::Time(0.0), Reports::default()).is_err());
/// # Ok::<(), rsf::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Every<O> {
    interval: Interval,
    /// The observer that sees the sampled steps.
    pub inner: O,
}

impl<O> Every<O> {
    /// `inner` at `interval`.
    ///
    /// # Errors
    /// As [`Interval::validate`].
    pub fn new(interval: Interval, inner: O) -> Result<Self> {
        interval.validate()?;
        Ok(Self { interval, inner })
    }

    /// The interval.
    pub fn interval(&self) -> Interval {
        self.interval
    }
}

impl<const D: usize, const C: usize, O: Observer<D, C>> Observer<D, C> for Every<O> {
    fn observe(&mut self, s: &StepView<'_, D, C>) -> Result<Flow> {
        let r = s.report;
        if self.interval.samples(r.step, r.time, r.tau) {
            self.inner.observe(s)
        } else {
            Ok(Flow::Continue(()))
        }
    }
    /// Always passed on: the stop at a step cap is not a sampled step.
    fn at_step_cap(&mut self, s: &StepView<'_, D, C>) -> Result<()> {
        self.inner.at_step_cap(s)
    }
    fn finish(&mut self) -> Result<()> {
        self.inner.finish()
    }
    fn name(&self) -> String {
        self.inner.name()
    }
    fn reads_volume(&self) -> bool {
        self.inner.reads_volume()
    }
    fn volume_vertices(&self) -> Vec<usize> {
        self.inner.volume_vertices()
    }
}

#[cfg(test)]
mod tests {
    use super::Interval;

    #[test]
    fn sampling_by_time_takes_one_step_per_interval() {
        let e = Interval::Time(0.1);
        // Uneven steps: exactly one step of each interval is sampled.
        let mut t: f64 = 0.0;
        let mut sampled = 0;
        for k in 0..400 {
            let tau = if k % 3 == 0 { 0.013 } else { 0.0041 };
            t += tau;
            sampled += usize::from(e.samples(k + 1, t, tau));
        }
        assert_eq!(sampled, (t / 0.1).floor() as usize);
        // A step longer than the interval is sampled once.
        assert!(e.samples(1, 1.05, 0.5));
    }

    #[test]
    fn sampling_by_steps_takes_the_multiples() {
        let e = Interval::Steps(3);
        let picked: Vec<usize> = (1..=10).filter(|&n| e.samples(n, 0.0, 1.0)).collect();
        assert_eq!(picked, [3, 6, 9]);
        assert!(Interval::Steps(0).validate().is_err());
        assert!(Interval::Time(f64::NAN).validate().is_err());
    }
}
