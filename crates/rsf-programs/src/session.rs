//! One run session: the resume sequence every long program shares (docs/reliability.md,
//! "One guard for every program"), written once.
//!
//! 1. [`Session::start`]: the checkpoint named by `--resume` is read, its checksum and
//!    fingerprint checked against the run's (a deliberate change named by
//!    `--allow-change`), and the method restored from it — no file is touched yet;
//! 2. the program checks and opens its own files in [`Session::mode`] (created, or
//!    continued at the checkpoint's step), writing the initial state of a fresh run;
//! 3. [`Session::run`]: the steps with the program's files first, then the progress bar,
//!    then the checkpointer (every `--checkpoint-every` steps and where the step cap stops
//!    the run: a checkpoint never runs ahead of the files); a run that fails returns its
//!    [`rsf::RunError`] (how far it got, the cause below it), a stop at the step cap the
//!    typed [`rsf::Error::StepCapReached`] naming the checkpoint to resume from.
//!
//! The processes of an MPI job other than rank 0 start the same session (every rank
//! restores the same state) and [`follow`](Session::follow) the same steps without
//! checkpoints or progress.

use std::path::{Path, PathBuf};

use rsf::checkpoint::{Checkpoint, Fingerprint};
use rsf::observe::{Checkpointer, Every, FileMode, Interval, Progress};
use rsf::run_folder::{read_checkpoint, step_cap_error, until};
use rsf::{Observer, RunSummary, Stepping, Until};

use crate::cli::ResumeArgs;
use crate::guard::AnyError;

/// The flags of a session: `--resume FILE`, `--allow-change FIELD,…`,
/// `--checkpoint-every N` and the step cap (`--max-steps N`, or the cap a program derives
/// from its output bound).
#[derive(Debug, Clone, Copy)]
pub struct SessionFlags<'a> {
    /// The checkpoint to continue from (`--resume`).
    pub resume: Option<&'a Path>,
    /// Fingerprint fields a resume may change (`--allow-change`).
    pub allow_change: &'a [String],
    /// Steps between checkpoints (0: only where the step cap stops the run).
    pub checkpoint_every: usize,
    /// The total number of steps (across resumes) after which the run stops.
    pub step_cap: Option<u64>,
}

impl ResumeArgs {
    /// The flags of a session: these, with the step cap `--max-steps`.
    pub fn session_flags(&self) -> SessionFlags<'_> {
        self.session_flags_with_cap(self.max_steps)
    }

    /// The flags of a session with the step cap `step_cap` (a program that derives its
    /// cap from its output bound when `--max-steps` is not given).
    pub fn session_flags_with_cap(&self, step_cap: Option<u64>) -> SessionFlags<'_> {
        SessionFlags {
            resume: self.resume.as_deref(),
            allow_change: &self.allow_change,
            checkpoint_every: self.checkpoint_every,
            step_cap,
        }
    }
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
}

impl Session {
    /// The session of a run of `method` until `end_time` (s) with `flags`, writing its
    /// checkpoints to `checkpoint_path` with `fingerprint`: on `--resume`, the checkpoint
    /// read, checked and restored into `method`.
    ///
    /// # Errors
    /// The checkpoint's: unreadable, a checksum or fingerprint that differs (beyond
    /// `--allow-change`), an end time before the checkpoint's time, a state of another
    /// method or model
    /// ([`rsf::run_folder::read_checkpoint`], [`Stepping::restore`]).
    pub fn start<const D: usize, const C: usize, M: Stepping<D, C> + ?Sized>(
        flags: SessionFlags<'_>,
        checkpoint_path: PathBuf,
        fingerprint: Fingerprint,
        end_time: f64,
        method: &mut M,
    ) -> Result<Self, AnyError> {
        let resumed = match flags.resume {
            None => None,
            Some(path) => {
                let c = read_checkpoint(path, &fingerprint, flags.allow_change)?;
                if end_time < c.state.time {
                    // Issue 87: `--allow-change end_years` to an end before the checkpoint
                    // exited 0 with "0 steps".
                    return Err(format!(
                        "the run's end, t = {} s, is before the checkpoint's time t = {} s (step \
                         {}): a resume continues a run forward; give an end time after the \
                         checkpoint's",
                        rsf_numeric::number(end_time),
                        rsf_numeric::number(c.state.time),
                        c.state.step
                    )
                    .into());
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
        })
    }

    /// The checkpoint the run continues from (`None` for a fresh run).
    pub fn resumed(&self) -> Option<&Checkpoint> {
        self.resumed.as_ref()
    }

    /// The step the run continues from (`None` for a fresh run).
    pub fn resumed_step(&self) -> Option<usize> {
        self.resumed.as_ref().map(|c| c.state.step)
    }

    /// The mode of the program's files: `fresh` (the guard's: create, or replace with
    /// `--overwrite`) for a fresh run, continued at the checkpoint's step on resume.
    pub fn mode(&self, fresh: FileMode) -> FileMode {
        match self.resumed_step() {
            None => fresh,
            Some(step) => FileMode::Resume { step },
        }
    }

    /// Whether the run can stop before its end (checkpoints or a step cap), so that its
    /// files keep a resume log of what they hold at each checkpoint.
    pub fn keeps_resume_log(&self) -> bool {
        self.checkpoint_every > 0 || self.step_cap.is_some()
    }

    /// The along-dip SEAS files (BP1, BP3: `rsf_seas::SeasOutput`) of the run of `model`
    /// in `out`, `laws` its frictional nodes' laws: opened in [`Self::mode`] of `fresh` (on
    /// resume the resume log's line of the checkpoint's step must show the checkpoint's
    /// time — the files are its run's — and every file's rows are checked up to that step
    /// before any is cut),
    /// with their resume log where the run can stop before its end
    /// ([`Self::keeps_resume_log`]).
    ///
    /// # Errors
    /// `rsf_seas::SeasOutput::new`'s and `with_resume_log`'s (invalid set-up, files that
    /// exist, rows that do not match the checkpoint, I/O naming the file).
    #[cfg(feature = "seas")]
    pub fn along_dip_output<const D: usize, const C: usize, L: rsf::friction::FrictionLaw>(
        &self,
        out: &Path,
        model: &rsf::Model<D, C>,
        laws: &[L],
        setup: rsf_seas::SeasSetup,
        fresh: FileMode,
    ) -> Result<rsf_seas::SeasOutput<L>, AnyError> {
        if let Some(c) = self.resumed() {
            rsf_seas::SeasOutput::<L>::check_checkpoint_time(out, c.state.step, c.state.time)?;
        }
        let mode = self.mode(fresh);
        let output = rsf_seas::SeasOutput::new(out, model, laws, setup, mode)?;
        Ok(if self.keeps_resume_log() {
            output.with_resume_log(mode)?
        } else {
            output
        })
    }

    /// Where the run stops: its end time, or the step cap first.
    pub fn end(&self) -> Until {
        self.end
    }

    /// Wall time (s) of the invocations before this one (0 for a fresh run).
    pub fn wall_time_before(&self) -> f64 {
        self.resumed.as_ref().map_or(0.0, |c| c.wall_time_s)
    }

    /// The steps, shown to `files` first, then to `progress`, then to the checkpointer.
    ///
    /// # Errors
    /// The run's [`rsf::RunError`] (the steps taken, the cause as its source); at the step
    /// cap before the end time, [`rsf::Error::StepCapReached`] naming the checkpoint just
    /// written; an invalid checkpoint interval.
    pub fn run<const D: usize, const C: usize, M: Stepping<D, C> + ?Sized>(
        self,
        method: &mut M,
        files: &mut [&mut dyn Observer<D, C>],
        progress: Option<Progress>,
    ) -> Result<RunSummary, AnyError> {
        if let (Some(c), Some(dir)) = (&self.resumed, self.checkpoint_path.parent()) {
            // Every file is checked by now: a folder whose manifest named no run is the
            // checkpoint's run's (issue 87).
            rsf::run_folder::adopt_run_id(dir, &c.run_id)?;
        }
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
            rsf::run_until(method, self.end, &mut observers).map_err(Box::new)?
        };
        match step_cap_error(&summary, self.end, method.state(), &self.checkpoint_path) {
            Some(e) => Err(e.into()),
            None => Ok(summary),
        }
    }

    /// The steps of a process that writes no checkpoint (the ranks of an MPI job other
    /// than rank 0, which reports a step cap), shown to `files` (its own pieces, if any).
    ///
    /// # Errors
    /// The run's [`rsf::RunError`].
    pub fn follow<const D: usize, const C: usize, M: Stepping<D, C> + ?Sized>(
        self,
        method: &mut M,
        files: &mut [&mut dyn Observer<D, C>],
    ) -> Result<RunSummary, AnyError> {
        Ok(rsf::run_until(method, self.end, files).map_err(Box::new)?)
    }
}
