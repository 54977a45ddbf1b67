//! The options of an elimination: the memory bound and when to write checkpoints.

use std::path::PathBuf;

use crate::error::Result;
use rsf_nonsmooth::ProblemError;

/// When and where the elimination writes its state, to resume a set-up that was killed.
///
/// A checkpoint holds the position in the schedule, the pending contribution blocks, the
/// accumulated `S_KK` and the right-hand sides carried so far (about
/// [`SchurOnlyPlan::result_bytes`] plus the stack's current size): it is written to
/// `path.partial`, synced, and renamed over `path`. A call of
/// [`SchurOnly::eliminate`] with the same inputs (matrix pattern and values, fixed dofs,
/// blocks, extras, right-hand sides, ordering) and an existing `path` continues from it;
/// a checkpoint of other inputs is refused
/// ([`Error::CheckpointMismatch`](crate::Error::CheckpointMismatch)) and left alone.
///
/// With [`keep_result`](Self::keep_result), the disk space of the finished checkpoint
/// ([`SchurOnlyPlan::finished_checkpoint_bytes`]) is held before the first front, as zeros
/// in `path.partial` (the first write truncates them and writes into the space they gave
/// back): a disk too small for it is found before any numeric work. A checkpoint written
/// during the elimination also holds the pending blocks, and the old one stays until the
/// new one replaces it: a disk that holds the finished file may still fill then, named
/// by the error.
///
/// [`SchurOnlyPlan::finished_checkpoint_bytes`]: super::SchurOnlyPlan::finished_checkpoint_bytes
///
/// [`SchurOnlyPlan::result_bytes`]: super::SchurOnlyPlan::result_bytes
/// [`SchurOnly::eliminate`]: super::SchurOnly::eliminate
#[derive(Debug, Clone, PartialEq)]
pub struct CheckpointPolicy {
    /// The checkpoint file.
    pub path: PathBuf,
    /// Write after every this many fronts (`None`: not by count).
    pub every_fronts: Option<usize>,
    /// Write when this many seconds of wall time have passed since the last write or
    /// the start (`None`: not by time).
    pub every_seconds: Option<f64>,
    /// At the end, write the finished state (`true`: a later call with the same inputs
    /// reads the result instead of eliminating again) or remove the file (`false`).
    pub keep_result: bool,
}

impl CheckpointPolicy {
    /// Checkpoints at `path` every 10 minutes of wall time, the finished state kept.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        Self {
            path: path.into(),
            every_fronts: None,
            every_seconds: Some(600.0),
            keep_result: true,
        }
    }

    pub(super) fn validate(&self) -> Result<()> {
        if self.every_fronts == Some(0) {
            return Err(ProblemError::InvalidOption(
                "checkpoint every 0 fronts: give at least 1, or None".into(),
            )
            .into());
        }
        if let Some(s) = self.every_seconds {
            if !(s > 0.0 && s.is_finite()) {
                return Err(ProblemError::InvalidOption(format!(
                    "checkpoint every {s} s: give a positive finite interval, or None"
                ))
                .into());
            }
        }
        Ok(())
    }
}

/// Options of [`SchurOnly::eliminate`].
///
/// [`SchurOnly::eliminate`]: super::SchurOnly::eliminate
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SchurOnlyOptions {
    /// Refuse ([`Error::TooLarge`](crate::Error::TooLarge)) before allocating anything if the
    /// elimination would hold more than this many bytes ([`SchurOnlyPlan::total_bytes`]).
    ///
    /// [`SchurOnlyPlan::total_bytes`]: super::SchurOnlyPlan::total_bytes
    pub max_bytes: Option<usize>,
    /// Checkpoints (none by default).
    pub checkpoint: Option<CheckpointPolicy>,
}
