//! One run session: the resume sequence every front end shares (the programs and the
//! Python package; docs/reliability.md, "One guard for every program"), written once.
//!
//! 1. [`Session::start`]: the checkpoint to resume from is read, its checksum and
//!    fingerprint checked against the run's (a deliberate change named in
//!    [`SessionFlags::allow_change`]), and the method restored from it — no file is
//!    touched yet;
//! 2. the front end checks and opens its own files in [`Session::mode`] (created, or
//!    continued at the checkpoint's step), writing the initial state of a fresh run
//!    (`rsf_seas::SeasOutput::for_session` for the along-dip SEAS files);
//! 3. [`Session::run`]: the steps with the files first, then the progress bar, then the
//!    checkpointer (every [`SessionFlags::checkpoint_every`] steps and where the step cap
//!    stops the run: a checkpoint never runs ahead of the files); a run that fails returns
//!    [`Error::RunFailed`] (how far it got, the cause as its source), a stop at the step
//!    cap [`Error::StepCapReached`] naming the checkpoint to resume from.
//!
//! The folder itself is prepared before (by [`RunFolder::prepare`](super::RunFolder::prepare)
//! or, on resume, [`RunFolder::prepare_resume`](super::RunFolder::prepare_resume)), so that
//! a checkpoint of another run is refused before any file is read or cut.
//!
//! The processes of an MPI job other than rank 0 start the same session (every rank
//! restores the same state) and [`follow`](Session::follow) the same steps without
//! checkpoints or progress.

use std::path::{Path, PathBuf};

use crate::checkpoint::{Checkpoint, Fingerprint};
use crate::error::{Error, Result};
use crate::observe::{Checkpointer, Every, FileMode, Interval, Observer, Progress};
use crate::run::{run_until, RunSummary, Stepping, Until};

use super::{adopt_run_id, read_checkpoint, step_cap_error, until};

/// The settings of a session: the checkpoint to resume from, the fingerprint fields a
/// resume may change, the checkpoint interval and the step cap (the command line's
/// `--resume FILE`, `--allow-change FIELD,…`, `--checkpoint-every N`, `--max-steps N`;
/// Python's `resume=`, `allow_change=`, `checkpoint_every=`).
#[derive(Debug, Clone, Copy, Default)]
pub struct SessionFlags<'a> {
    /// The checkpoint to continue from.
    pub resume: Option<&'a Path>,
    /// Fingerprint fields a resume may change.
    pub allow_change: &'a [String],
    /// Steps between checkpoints (0: only where the step cap stops the run).
    pub checkpoint_every: usize,
    /// The total number of steps (across resumes) after which the run stops.
    pub step_cap: Option<u64>,
}

/// A run between its set-up and its summary: what a checkpoint continues (the fingerprint),
/// where the run ends, and the checkpoint it continues from.
#[derive(Debug)]
pub struct Session {
    checkpoint_path: PathBuf,
    fingerprint: Fingerprint,
    checkpoint_every: usize,
    step_cap: Option<u64>,
    end: Until,
    resumed: Option<Checkpoint>,
    checkpoints_anywhere: bool,
}

impl Session {
    /// The session of a run of `method` until `end_time` (s) with `flags`, writing its
    /// checkpoints to `checkpoint_path` with `fingerprint`: on resume, the checkpoint
    /// read, checked and restored into `method`.
    ///
    /// # Errors
    /// The checkpoint's: unreadable, a checksum or fingerprint that differs (beyond
    /// [`SessionFlags::allow_change`]: [`read_checkpoint`]), [`Error::EndBeforeCheckpoint`],
    /// a state of another method or model ([`Stepping::restore`]).
    pub fn start<const D: usize, const C: usize, M: Stepping<D, C> + ?Sized>(
        flags: SessionFlags<'_>,
        checkpoint_path: PathBuf,
        fingerprint: Fingerprint,
        end_time: f64,
        method: &mut M,
    ) -> Result<Self> {
        let resumed = match flags.resume {
            None => None,
            Some(path) => {
                let c = read_checkpoint(path, &fingerprint, flags.allow_change)?;
                if end_time < c.state.time {
                    // Issue 87: `--allow-change end_years` to an end before the checkpoint
                    // exited 0 with "0 steps".
                    return Err(Error::EndBeforeCheckpoint {
                        end_time,
                        time: c.state.time,
                        step: c.state.step,
                    });
                }
                method.restore(&c)?;
                Some(c)
            }
        };
        Ok(Self {
            checkpoint_path,
            fingerprint,
            checkpoint_every: flags.checkpoint_every,
            step_cap: flags.step_cap,
            end: until(end_time, flags.step_cap),
            resumed,
            checkpoints_anywhere: false,
        })
    }

    /// The session of a front end that may write a checkpoint at any step (Python's
    /// `Simulation.checkpoint`, a checkpoint when Ctrl-C stops a run, an interval chosen
    /// per call): its files always keep their resume log ([`Self::keeps_resume_log`]).
    pub fn checkpoints_anywhere(mut self) -> Self {
        self.checkpoints_anywhere = true;
        self
    }

    /// The checkpoint the run continues from (`None` for a fresh run).
    pub fn resumed(&self) -> Option<&Checkpoint> {
        self.resumed.as_ref()
    }

    /// The step the run continues from (`None` for a fresh run).
    pub fn resumed_step(&self) -> Option<usize> {
        self.resumed.as_ref().map(|c| c.state.step)
    }

    /// The fingerprint the run's checkpoints carry.
    pub fn fingerprint(&self) -> &Fingerprint {
        &self.fingerprint
    }

    /// Where the run's checkpoints are written.
    pub fn checkpoint_path(&self) -> &Path {
        &self.checkpoint_path
    }

    /// The mode of the run's files: `fresh` (the folder's: create, or replace with
    /// overwrite) for a fresh run, continued at the checkpoint's step on resume.
    pub fn mode(&self, fresh: FileMode) -> FileMode {
        match self.resumed_step() {
            None => fresh,
            Some(step) => FileMode::Resume { step },
        }
    }

    /// Whether the run can stop before its end (checkpoints or a step cap), so that its
    /// files keep a resume log of what they hold at each checkpoint.
    pub fn keeps_resume_log(&self) -> bool {
        self.checkpoints_anywhere || self.checkpoint_every > 0 || self.step_cap.is_some()
    }

    /// Where the run stops: its end time, or the step cap first.
    pub fn end(&self) -> Until {
        self.end
    }

    /// Wall time (s) of the invocations before this one (0 for a fresh run).
    pub fn wall_time_before(&self) -> f64 {
        self.resumed.as_ref().map_or(0.0, |c| c.wall_time_s)
    }

    /// Names the folder of the checkpoint's files with the checkpoint's run id where its
    /// manifest names no run ([`adopt_run_id`]): call it once every file is checked (the
    /// files prove the folder the checkpoint's run's). Nothing for a fresh run.
    ///
    /// # Errors
    /// [`Error::File`] naming the manifest.
    pub fn adopt_folder(&self) -> Result<()> {
        match (&self.resumed, self.checkpoint_path.parent()) {
            (Some(c), Some(dir)) => adopt_run_id(dir, &c.run_id),
            _ => Ok(()),
        }
    }

    /// The steps, shown to `files` first, then to `progress`, then to the checkpointer.
    ///
    /// # Errors
    /// [`Error::RunFailed`] (the steps taken, the cause as its source); at the step cap
    /// before the end time, [`Error::StepCapReached`] naming the checkpoint just written;
    /// an invalid checkpoint interval.
    pub fn run<const D: usize, const C: usize, M: Stepping<D, C> + ?Sized>(
        self,
        method: &mut M,
        files: &mut [&mut dyn Observer<D, C>],
        progress: Option<Progress>,
    ) -> Result<RunSummary> {
        // Every file is checked by now: a folder whose manifest named no run is the
        // checkpoint's run's (issue 87).
        self.adopt_folder()?;
        let checkpointer = Checkpointer::new(self.checkpoint_path.clone())
            .fingerprint(self.fingerprint.clone())
            .wall_time_before(self.wall_time_before());
        let mut checkpointer = Every::new(
            Interval::steps_or_never(self.checkpoint_every),
            checkpointer,
        )?;
        let mut progress = progress;
        let summary = {
            let mut observers: Vec<&mut dyn Observer<D, C>> =
                files.iter_mut().map(|o| &mut **o as _).collect();
            if let Some(p) = progress.as_mut() {
                observers.push(p);
            }
            observers.push(&mut checkpointer);
            run_until(method, self.end, &mut observers).map_err(failed)?
        };
        match step_cap_error(&summary, self.end, method.state(), &self.checkpoint_path) {
            Some(e) => Err(e),
            None => Ok(summary),
        }
    }

    /// The steps of a process that writes no checkpoint (the ranks of an MPI job other
    /// than rank 0, which reports a step cap), shown to `files` (its own pieces, if any).
    ///
    /// # Errors
    /// [`Error::RunFailed`].
    pub fn follow<const D: usize, const C: usize, M: Stepping<D, C> + ?Sized>(
        self,
        method: &mut M,
        files: &mut [&mut dyn Observer<D, C>],
    ) -> Result<RunSummary> {
        run_until(method, self.end, files).map_err(failed)
    }
}

/// A run's failure as [`Error::RunFailed`]: how far it got, the cause as its source.
fn failed(e: crate::run::RunError) -> Error {
    Error::RunFailed {
        steps: e.summary.steps,
        source: Box::new(e.error),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh session's files take the folder's mode; a resumed one's continue at the
    /// checkpoint's step (checked on `mode` alone: a resume needs a checkpoint).
    #[test]
    fn a_fresh_session_keeps_the_folders_mode_and_no_log_without_stops() {
        let s = Session {
            checkpoint_path: PathBuf::from("out/checkpoint.bin"),
            fingerprint: Fingerprint::default(),
            checkpoint_every: 0,
            step_cap: None,
            end: until(1.0, None),
            resumed: None,
            checkpoints_anywhere: false,
        };
        assert_eq!(s.mode(FileMode::Overwrite), FileMode::Overwrite);
        assert!(!s.keeps_resume_log());
        assert_eq!(s.end(), Until::Time(1.0));
        assert_eq!(s.wall_time_before(), 0.0);
        let capped = Session {
            step_cap: Some(3),
            end: until(1.0, Some(3)),
            ..s
        };
        assert!(capped.keeps_resume_log());
        let anywhere = Session {
            step_cap: None,
            ..capped
        }
        .checkpoints_anywhere();
        assert!(anywhere.keeps_resume_log());
    }
}
