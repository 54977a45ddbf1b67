//! The output's own state at a step (what its files hold, the catalogue), as the resume
//! log keeps it.

/// An event of the catalogue.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Bp5Event {
    /// First step with the maximum slip rate at or above the threshold (s).
    pub t_start: f64,
    /// First step below it again (s); `None` while open.
    pub t_end: Option<f64>,
    /// Peak slip rate (m/s).
    pub peak_slip_rate: f64,
    /// `(x₂, x₃)` of the fastest cell at the start (m).
    pub hypocentre: [f64; 2],
}

/// Name of the resume log of [`SeasBp5Output`](crate::SeasBp5Output): the output's state at every persisted
/// step (JSON).
pub const SEAS_BP5_RESUME_LOG: &str = "bp5_resume.json";

/// The output's own state at a step: what its files hold and what comes next.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub(super) struct Mark {
    /// The run's step.
    pub(super) step: usize,
    /// The run's time after the step (s; `None` in a log of a version before issue 87).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) t: Option<f64>,
    /// Rows in every file.
    pub(super) written: usize,
    /// Time of the last row (s).
    pub(super) last_station_t: f64,
    /// Smallest and largest step so far (s).
    pub(super) tau: (f64, f64),
    /// Steps seen.
    pub(super) steps: usize,
    /// The catalogue.
    pub(super) events: Vec<Bp5Event>,
    /// Profile rows written (besides the positions row) and the time of the last.
    pub(super) profile_written: usize,
    pub(super) last_profile_t: f64,
    /// Per fault node: the first time after the first event that its slip rate reached
    /// [`RUPTURE_THRESHOLD`] (s).
    pub(super) rupture: Vec<Option<f64>>,
}

impl crate::resume::LogMark for Mark {
    fn step(&self) -> usize {
        self.step
    }
    fn time(&self) -> Option<f64> {
        self.t
    }
}
