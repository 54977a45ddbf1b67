//! Slip events: detection with hysteresis on the largest slip rate of Γ_F, a catalogue,
//! and stopping a run at an event.

use crate::error::{invalid, Result};
use crate::model::Model;

use super::{Flow, Observer, StepView};

/// Thresholds of slip-event detection (m/s): an event starts at the first step whose
/// largest slip rate on Γ_F exceeds `onset`, and ends at the first later step where it has
/// fallen below `end` (hysteresis: the ringing of one event around `onset` is not counted
/// twice).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EventThresholds {
    /// Onset slip rate (m/s).
    pub onset: f64,
    /// End slip rate (m/s), `0 < end ≤ onset`.
    pub end: f64,
}

impl Default for EventThresholds {
    /// Onset 1e-3 m/s, end 1e-4 m/s (the examples' definition on the paper's slider,
    /// where interseismic slip rates stay below 1e-5 m/s).
    fn default() -> Self {
        Self {
            onset: 1e-3,
            end: 1e-4,
        }
    }
}

impl EventThresholds {
    /// Checks `0 < end ≤ onset < ∞`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `event thresholds`.
    pub fn validate(&self) -> Result<()> {
        if self.end > 0.0 && self.end <= self.onset && self.onset.is_finite() {
            Ok(())
        } else {
            Err(invalid(
                "event thresholds",
                format!(
                    "need 0 < end ≤ onset < ∞ (m/s), got onset {}, end {}",
                    self.onset, self.end
                ),
            ))
        }
    }
}

/// One slip event of the catalogue.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SlipEvent {
    /// Step of the onset: the first step whose largest slip rate exceeds the onset
    /// threshold.
    pub onset_step: usize,
    /// Time of the onset step (s), `t_n` of [`onset_step`](Self::onset_step): what the
    /// examples' statistics call the "first slip" time of the first event (a step's
    /// time, resolved to τ; [`crossing_s`](Self::crossing_s) is the interpolated crossing).
    pub onset_s: f64,
    /// Time (s) where the largest slip rate crosses the onset threshold, interpolated
    /// linearly in `ln V` between the step before the onset and the onset step (the onset
    /// step's time for an event at the first step).
    pub crossing_s: f64,
    /// Step and time (s) where the event ended; `None` while it lasts.
    pub end: Option<(usize, f64)>,
    /// Largest slip rate on Γ_F during the event (m/s).
    pub peak_slip_rate: f64,
    /// Time of the peak (s).
    pub peak_s: f64,
    /// Slip at the chosen node during the event, `|u_p(last step) − u_p(step before the
    /// onset)|` (m); `None` without a node ([`EventDetector::with_slip_at`]).
    pub slip: Option<f64>,
}

impl SlipEvent {
    /// Duration (s) from the onset to the end; `None` while the event lasts.
    pub fn duration_s(&self) -> Option<f64> {
        self.end.map(|(_, t)| t - self.onset_s)
    }
}

/// What a step did to the event state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Transition {
    /// No change.
    None,
    /// An event started at this step.
    Onset,
    /// The current event ended at this step.
    End,
}

/// The detection state machine, fed one step at a time ([`EventDetector::push`]); usable
/// on a live run ([`SlipEvents`]) or on recorded series (e.g. rows of a
/// [`PointSeries`](crate::observe::PointSeries) file read back).
#[derive(Debug, Clone, PartialEq)]
pub struct EventDetector {
    thresholds: EventThresholds,
    /// Displacement of the slip node at the previous step and at the onset (start value).
    u_prev: Vec<f64>,
    u_start: Vec<f64>,
    events: Vec<SlipEvent>,
    slipping: bool,
    /// Time and rate of the previous step.
    previous: Option<(f64, f64)>,
}

impl EventDetector {
    /// A detector with `thresholds`, starting outside an event.
    ///
    /// # Errors
    /// As [`EventThresholds::validate`].
    pub fn new(thresholds: EventThresholds) -> Result<Self> {
        thresholds.validate()?;
        Ok(Self {
            thresholds,
            u_prev: Vec::new(),
            u_start: Vec::new(),
            events: Vec::new(),
            slipping: false,
            previous: None,
        })
    }

    /// Measures the slip of each event at a node whose displacement before the first
    /// step is `u_initial` (m, all components; then pass the node's displacement to every
    /// [`push`](Self::push)).
    pub fn with_slip_at(mut self, u_initial: &[f64]) -> Self {
        self.u_prev = u_initial.to_vec();
        self
    }

    /// The thresholds.
    pub fn thresholds(&self) -> EventThresholds {
        self.thresholds
    }

    /// Takes the step `step` at time `t` (s) with largest slip rate `rate` (m/s) and the
    /// slip node's displacement `u` (ignored without [`with_slip_at`](Self::with_slip_at);
    /// must have the same length).
    pub fn push(&mut self, step: usize, t: f64, rate: f64, u: &[f64]) -> Transition {
        let track = !self.u_prev.is_empty() && u.len() == self.u_prev.len();
        let mut transition = Transition::None;
        if !self.slipping && rate > self.thresholds.onset {
            self.slipping = true;
            if track {
                self.u_start.clone_from(&self.u_prev);
            }
            let on = self.thresholds.onset;
            let crossing_s = match self.previous {
                Some((t0, r0)) if r0 > 0.0 && r0 < on && t0 < t => {
                    let (a, b) = (r0.ln(), rate.ln());
                    t0 + (t - t0) * (on.ln() - a) / (b - a)
                }
                _ => t,
            };
            self.events.push(SlipEvent {
                onset_step: step,
                onset_s: t,
                crossing_s,
                end: None,
                peak_slip_rate: rate,
                peak_s: t,
                slip: track.then_some(0.0),
            });
            transition = Transition::Onset;
        } else if self.slipping && rate < self.thresholds.end {
            self.slipping = false;
            if let Some(e) = self.events.last_mut() {
                e.end = Some((step, t));
            }
            transition = Transition::End;
        }
        if let Some(e) = self
            .events
            .last_mut()
            .filter(|e| e.end.is_none() || transition == Transition::End)
        {
            if rate > e.peak_slip_rate {
                e.peak_slip_rate = rate;
                e.peak_s = t;
            }
            if track {
                let d2: f64 = u
                    .iter()
                    .zip(&self.u_start)
                    .map(|(a, b)| (a - b) * (a - b))
                    .sum();
                e.slip = Some(d2.sqrt());
            }
        }
        if track {
            self.u_prev.copy_from_slice(u);
        }
        self.previous = Some((t, rate));
        transition
    }

    /// The events so far (the last may still last).
    pub fn events(&self) -> &[SlipEvent] {
        &self.events
    }

    /// Whether an event is under way.
    pub fn slipping(&self) -> bool {
        self.slipping
    }

    /// Mean time between successive onsets (s), with at least two events.
    pub fn recurrence_interval_s(&self) -> Option<f64> {
        let e = &self.events;
        (e.len() >= 2).then(|| (e[e.len() - 1].onset_s - e[0].onset_s) / (e.len() - 1) as f64)
    }
}

/// When [`SlipEvents`] ends a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StopAt {
    /// Never.
    #[default]
    Never,
    /// At the onset of the `n`-th event (1-based).
    Onset(usize),
    /// At the end of the `n`-th event (1-based).
    End(usize),
}

/// An observer building the slip-event catalogue of a run ([`EventDetector`] on the
/// largest slip rate of each step), optionally measuring the slip at a node and ending the
/// run at an event ([`StopAt`]).
///
/// ```no_run
/// use rsf::Until;
/// use rsf::observe::{EventThresholds, SlipEvents, StopAt};
/// use rsf_scenes::SliderScene;
/// let scene = SliderScene { level: 2, ..SliderScene::default() };
/// let mut sim = scene.build()?;
/// let x0 = sim.model().nearest_node(&rsf_scenes::SLIDER_CENTRE)?;
/// let mut events = SlipEvents::new(EventThresholds::default())?
///     .slip_at(sim.model(), x0)?
///     .stop(StopAt::End(1));
/// sim.run_until(Until::Time(15.0), &mut [&mut events])?;
/// let first = &events.events()[0];
/// println!("onset {:.3} s, {:.2e} m of slip", first.onset_s, first.slip.unwrap());
/// # Ok::<(), rsf::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct SlipEvents {
    detector: EventDetector,
    node: Option<usize>,
    /// Whether `node` is off Γ_F (its displacement is part of the volume).
    node_in_volume: bool,
    stop: StopAt,
}

impl SlipEvents {
    /// Detects events with `thresholds`; no slip measurement, never stops the run.
    ///
    /// # Errors
    /// As [`EventThresholds::validate`].
    pub fn new(thresholds: EventThresholds) -> Result<Self> {
        Ok(Self {
            detector: EventDetector::new(thresholds)?,
            node: None,
            node_in_volume: false,
            stop: StopAt::Never,
        })
    }

    /// Measures each event's slip at mesh vertex `vertex` of `model` (a vertex id, e.g.
    /// from [`Model::nearest_node`]; not a fault index), starting from the model's initial
    /// displacement.
    ///
    /// # Errors
    /// [`Error::NodeOutOfRange`](crate::Error::NodeOutOfRange).
    pub fn slip_at<const D: usize>(mut self, model: &Model<D>, vertex: usize) -> Result<Self> {
        model.check_node("slip events", vertex)?;
        let u0 = &model.initial_displacement[D * vertex..D * vertex + D];
        self.detector = self.detector.with_slip_at(u0);
        self.node = Some(vertex);
        self.node_in_volume = !model.frictional_boundary.nodes.contains(&vertex);
        Ok(self)
    }

    /// Ends the run at an event.
    pub fn stop(mut self, at: StopAt) -> Self {
        self.stop = at;
        self
    }

    /// The catalogue so far.
    pub fn events(&self) -> &[SlipEvent] {
        self.detector.events()
    }

    /// The detector (recurrence interval, state).
    pub fn detector(&self) -> &EventDetector {
        &self.detector
    }
}

impl<const D: usize> Observer<D> for SlipEvents {
    fn observe(&mut self, s: &StepView<'_, D>) -> Result<Flow> {
        let r = s.report;
        let u = match self.node {
            Some(p) => &s.state.kinematics.u[D * p..D * p + D],
            None => &[],
        };
        let transition = self.detector.push(r.step, r.time, r.max_slip_rate, u);
        let n = self.detector.events().len();
        let stop = match self.stop {
            StopAt::Never => false,
            StopAt::Onset(k) => transition == Transition::Onset && n == k,
            StopAt::End(k) => transition == Transition::End && n == k,
        };
        Ok(if stop {
            Flow::Break(())
        } else {
            Flow::Continue(())
        })
    }
    fn reads_volume(&self) -> bool {
        self.node_in_volume
    }
}
