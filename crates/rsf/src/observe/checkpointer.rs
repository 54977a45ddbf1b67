//! Checkpoints during a run, and the reports of every step kept in memory.

use std::path::PathBuf;
use std::time::Instant;

use crate::checkpoint::{Checkpoint, Fingerprint};

use crate::error::Result;
use crate::report::StepReport;

use super::{Flow, Observer, StepView};

/// Writes a checkpoint of every step it is shown, atomically replacing `path` (wrap it in
/// [`Every`](crate::observe::Every) to checkpoint every `n` steps). Put it after the observers that
/// write files, so that a checkpoint never runs ahead of them.
///
/// Each checkpoint carries the [`fingerprint`](Self::fingerprint) of the run, its wall
/// time so far ([`Checkpoint::wall_time_s`](crate::Checkpoint::wall_time_s): the wall
/// time since this checkpointer was made, plus [`wall_time_before`](Self::wall_time_before))
/// and the run's id ([`Checkpoint::run_id`](crate::Checkpoint::run_id): that of the run
/// folder `path` is in, or [`run_id`](Self::run_id)'s).
#[derive(Debug, Clone)]
pub struct Checkpointer {
    path: PathBuf,
    fingerprint: Fingerprint,
    started: Instant,
    before_s: f64,
    run_id: String,
}

impl Checkpointer {
    /// Checkpoints to `path`, with an empty fingerprint and the run id of the run folder
    /// that holds `path` (the `run=` line of its manifest
    /// [`MANIFEST`](crate::run_manifest::MANIFEST), read here once; empty if there is none):
    /// so every checkpoint a run writes into its folder names the run it belongs to.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        let path = path.into();
        let run_id = path
            .parent()
            .and_then(crate::run_manifest::run_id)
            .unwrap_or_default();
        Self {
            path,
            fingerprint: Fingerprint::default(),
            started: Instant::now(),
            before_s: 0.0,
            run_id,
        }
    }

    /// Writes `id` as the run's id into every checkpoint (instead of the folder's).
    pub fn run_id(mut self, id: &str) -> Self {
        self.run_id = id.to_owned();
        self
    }

    /// Writes `fingerprint` (what the run is: physics and method) into every checkpoint.
    pub fn fingerprint(mut self, fingerprint: Fingerprint) -> Self {
        self.fingerprint = fingerprint;
        self
    }

    /// Adds `seconds` (the wall time of the run before a resume, e.g. the resumed
    /// checkpoint's [`wall_time_s`](crate::Checkpoint::wall_time_s)) to the wall time the
    /// checkpoints carry.
    pub fn wall_time_before(mut self, seconds: f64) -> Self {
        self.before_s = seconds;
        self
    }
}

impl Checkpointer {
    /// Writes the checkpoint `c` (of any state, e.g. one a run starts from) as this
    /// checkpointer writes those of its steps: with its fingerprint, wall time and run id.
    ///
    /// # Errors
    /// [`Error::File`](crate::Error::File) naming the file and the operation.
    pub fn write(&self, mut c: Checkpoint) -> Result<()> {
        c.fingerprint = self.fingerprint.clone();
        c.run_id = self.run_id.clone();
        c.wall_time_s = self.before_s + self.started.elapsed().as_secs_f64();
        c.write(&self.path)
    }
}

impl<const D: usize, const C: usize> Observer<D, C> for Checkpointer {
    fn observe(&mut self, s: &StepView<'_, D, C>) -> Result<Flow> {
        self.write(s.checkpoint())?;
        Ok(Flow::Continue(()))
    }
    /// A run stopped at its step cap is checkpointed where it stopped.
    fn at_step_cap(&mut self, s: &StepView<'_, D, C>) -> Result<()> {
        self.write(s.checkpoint())
    }
    /// A checkpoint of a method condensed onto Γ_F needs only its state on Γ_F (the
    /// volume's `u`, `v` follow from it); the implicit simulation always has the whole
    /// field.
    fn reads_volume(&self) -> bool {
        false
    }
}

/// Keeps every step's report in memory (for summaries and figures).
#[derive(Debug, Default, Clone)]
pub struct Reports(pub Vec<StepReport>);

impl<const D: usize, const C: usize> Observer<D, C> for Reports {
    fn observe(&mut self, s: &StepView<'_, D, C>) -> Result<Flow> {
        self.0.push(*s.report);
        Ok(Flow::Continue(()))
    }
    fn reads_volume(&self) -> bool {
        false
    }
}
