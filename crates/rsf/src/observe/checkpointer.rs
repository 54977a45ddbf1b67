//! Checkpoints during a run, and the reports of every step kept in memory.

use std::path::PathBuf;

use crate::error::Result;
use crate::report::StepReport;

use super::{Flow, Observer, StepView};

/// Writes a checkpoint of every step it is shown, atomically replacing `path` (wrap it in
/// [`Every`](crate::Every) to checkpoint every `n` steps). Put it after the observers that
/// write files, so that a checkpoint never runs ahead of them.
#[derive(Debug, Clone)]
pub struct Checkpointer {
    path: PathBuf,
}

impl Checkpointer {
    /// Checkpoints to `path`.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        Self { path: path.into() }
    }
}

impl<const D: usize> Observer<D> for Checkpointer {
    fn observe(&mut self, s: &StepView<'_, D>) -> Result<Flow> {
        s.checkpoint().write(&self.path)?;
        Ok(Flow::Continue(()))
    }
}

/// Keeps every step's report in memory (for summaries and figures).
#[derive(Debug, Default, Clone)]
pub struct Reports(pub Vec<StepReport>);

impl<const D: usize> Observer<D> for Reports {
    fn observe(&mut self, s: &StepView<'_, D>) -> Result<Flow> {
        self.0.push(*s.report);
        Ok(Flow::Continue(()))
    }
}
