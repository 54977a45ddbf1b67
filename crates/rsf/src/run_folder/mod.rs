//! The run folder of a program: the procedure that keeps a week of compute safe from a
//! mistaken command (docs/reliability.md).
//!
//! - [`RunFolder::prepare`], before anything is computed: creates the folder, probes that
//!   it can be written and that no output path is a folder, and refuses a folder holding
//!   another run's files unless told to overwrite. Every program writes a manifest
//!   [`MANIFEST`] naming itself and its outputs, so that a folder of *any* rsf program is
//!   recognised, not only one holding this program's file names.
//! - On resume, [`read_checkpoint`] checks the checkpoint (checksum, fingerprint; the
//!   fields a user allows to change must exist in the fingerprint,
//!   [`check_allowed_changes`]); each writer then checks that its file can be continued
//!   ([`PointSeries::check_resume`](crate::observe::PointSeries::check_resume),
//!   [`PointSeries::check_checkpoint_row`](crate::observe::PointSeries::check_checkpoint_row),
//!   [`FrictionalProfile::check_resume`](crate::observe::FrictionalProfile::check_resume),
//!   and `rsf_seas::SeasOutput::check_resume` of the SEAS files) before any file is cut.
//! - Output bounds and step caps: the one policy [`output_plan`] (refuse, or cap an adaptive
//!   run at what fits) over [`check_output_size`]; a step cap is where a run ends
//!   ([`until`]: [`Until::TimeOrStepCap`], whose stop a
//!   [`Checkpointer`](crate::observe::Checkpointer) checkpoints), [`step_cap_error`] says
//!   how to continue (the bounds of the slider scenes' runs are in `rsf_scenes::output`);
//!   [`check_window`] for recording windows.

mod front_end;
mod handover;
mod session;

use std::path::{Path, PathBuf};

use crate::checkpoint::{write_atomically, Checkpoint, Fingerprint};
use crate::error::{io_at, show_path, Error, Result};
use crate::observe::files::FileMode;
use crate::run::{RunSummary, Termination, Until};
use crate::simulation_state::SimulationState;

pub use crate::run_manifest::{new_run_id, run_id, MANIFEST};
use crate::run_manifest::{short_id, Manifest};
pub use front_end::FrontEnd;
pub use session::{Session, SessionFlags};

/// The output folder of a run: the program that writes it and the files it writes there.
#[derive(Debug, Clone)]
pub struct RunFolder {
    /// The folder.
    pub dir: PathBuf,
    /// The program (e.g. `pipping_slider`), as the manifest names it.
    pub program: String,
    /// The files (paths inside `dir`) the run writes.
    pub outputs: Vec<String>,
    /// The command line of the run, as its manifest records it (empty: none recorded).
    pub command: String,
    /// How the front end names the folder's settings in its errors (the command line's
    /// flags by default).
    pub front_end: FrontEnd,
    /// The fingerprint the run's checkpoints carry and the fields a resume may change,
    /// when the front end knows them before the work ([`expecting`](Self::expecting)).
    pub expected: Option<(Fingerprint, Vec<String>)>,
}

impl RunFolder {
    /// The folder `dir` of a run of `program` writing `outputs` (paths inside `dir`; the
    /// manifest is added by [`prepare`](Self::prepare)).
    pub fn new(dir: impl Into<PathBuf>, program: &str, outputs: &[&str]) -> Self {
        Self {
            dir: dir.into(),
            program: program.to_owned(),
            outputs: outputs.iter().map(|s| (*s).to_owned()).collect(),
            command: String::new(),
            front_end: FrontEnd::CommandLine,
            expected: None,
        }
    }

    /// The folder of a run whose checkpoints carry `fingerprint`, a resume allowed to
    /// change the fields `allow_change`: [`prepare_resume`](Self::prepare_resume) then
    /// checks the checkpoint against it before anything in the folder changes (issue 87:
    /// with `--overwrite` the folder was given to the checkpoint's run before a checkpoint
    /// of other parameters was refused by the session).
    pub fn expecting(mut self, fingerprint: Fingerprint, allow_change: &[String]) -> Self {
        self.expected = Some((fingerprint, allow_change.to_vec()));
        self
    }

    /// The folder of a run started from `front_end`, whose errors name its settings
    /// (Python's `overwrite=True`, `resume=`, `out` instead of the command line's flags).
    pub fn front_end(mut self, front_end: FrontEnd) -> Self {
        self.front_end = front_end;
        self
    }

    /// The folder with the run's command line `command` recorded in its manifest (one
    /// line: newlines become spaces).
    pub fn command(mut self, command: &str) -> Self {
        self.command = command.replace('\n', " ");
        self
    }

    /// Path of the output `name`.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Prepares the folder before anything is computed:
    ///
    /// 1. creates it and checks that it can be written (a probe file is created and
    ///    removed) and that no output path is a folder;
    /// 2. refuses a folder whose manifest names another program (also on `resume`; with
    ///    `overwrite` a new run replaces it), and — for a new run (`resume` false) — one
    ///    holding any non-empty file this run writes or the earlier run's manifest lists,
    ///    unless `overwrite`: then the earlier checkpoint, summary and the files only the
    ///    earlier run's manifest lists are removed, so that nothing in the folder can be
    ///    mistaken for this run's;
    /// 3. writes this run's manifest [`MANIFEST`] (atomically): a new run gets a new run
    ///    id ([`new_run_id`]), a continued one (`resume`) keeps the folder's.
    ///
    /// Returns the [`FileMode`] of new files ([`FileMode::Create`], or
    /// [`FileMode::Overwrite`] when an earlier run's files are replaced). A resume gets
    /// `Create` and must check the files itself (each writer's `check_resume`) before it
    /// cuts any. A resume from a checkpoint is [`prepare_resume`](Self::prepare_resume),
    /// which also checks that the checkpoint belongs to the folder's run.
    ///
    /// # Errors
    /// [`Error::File`] naming the folder (cannot create, not writable);
    /// [`Error::FileExists`] naming the files and the program of another run. Nothing in
    /// the folder is changed on error.
    pub fn prepare(&self, resume: bool, overwrite: bool) -> Result<FileMode> {
        self.prepare_new(resume, overwrite)
            .map_err(|e| self.front_end.spell(e))
    }

    /// [`prepare`](Self::prepare), its errors in the command line's terms.
    fn prepare_new(&self, resume: bool, overwrite: bool) -> Result<FileMode> {
        let (manifest, present) = self.survey(resume, overwrite)?;
        let mode = if resume || present.is_empty() {
            FileMode::Create
        } else if !overwrite {
            return Err(Error::FileExists {
                path: show_path(&self.dir),
                reason: format!(
                    "it holds the files of another run{} ({}); pass --overwrite to replace \
                     them, --resume CHECKPOINT to continue that run, or another --out",
                    manifest
                        .as_ref()
                        .map_or(String::new(), |m| format!(" of `{}`", m.program)),
                    rsf_numeric::excerpt(&present.join(", "))
                ),
            });
        } else {
            for name in &present {
                let ours = self.outputs.iter().any(|o| o == name);
                if !ours || *name == "checkpoint.bin" || *name == "summary.json" {
                    let path = self.path(name);
                    std::fs::remove_file(&path).map_err(io_at("remove", &path))?;
                }
            }
            FileMode::Overwrite
        };
        let kept = manifest
            .filter(|m| resume && m.program == self.program)
            .map(|m| m.run_id)
            .filter(|id| !id.is_empty());
        self.write_manifest(kept.unwrap_or_else(new_run_id))?;
        Ok(mode)
    }

    /// Prepares the folder for a resume from the checkpoint `checkpoint`, before anything
    /// is computed: as [`prepare`](Self::prepare) with `resume` (the folder created and
    /// probed, another program's folder refused), and the checkpoint read (its checksum)
    /// and its run compared with the folder's: a checkpoint of **another run** than the
    /// one whose files the folder holds (both run ids known and different:
    /// [`Checkpoint::run_id`], the manifest's `run=`) is refused unless `overwrite`, which
    /// gives the folder to the checkpoint's run **whole**: the folder's run's files are
    /// removed and those of the checkpoint's run copied from the checkpoint's own folder
    /// (whose manifest must name that run; refused otherwise, nothing changed), to be
    /// continued from the checkpoint's step by each writer's own check — never the rows
    /// of one run followed by another's (issue 87). A folder without a manifest, or a
    /// manifest or checkpoint of a version before run ids, cannot be told apart by its
    /// manifest: each writer then proves by its files that they are the checkpoint's run's
    /// (the row or resume-log line of the checkpoint's step at the checkpoint's time and
    /// state), or refuses. The manifest then names the checkpoint's run (or keeps the
    /// folder's).
    ///
    /// Returns [`FileMode::Create`] (each writer checks its files before it cuts any).
    ///
    /// # Errors
    /// Those of [`prepare`](Self::prepare); those of [`Checkpoint::read`]
    /// ([`Error::File`], [`Error::CheckpointCorrupt`]); with [`expecting`](Self::expecting),
    /// those of [`read_checkpoint`] ([`Error::CheckpointMismatch`] naming the field that
    /// differs, [`Error::InvalidParameter`] for an unknown field allowed to change);
    /// [`Error::Resume`] naming the folder,
    /// both runs and how to go on, for a checkpoint of another run without `overwrite`,
    /// for `overwrite` where there is nothing to replace (the folder is the checkpoint's
    /// own run, or cannot be told) and where the checkpoint's run's files are not beside
    /// it. Nothing in the folder is changed on these errors; an [`Error::File`] while
    /// the files are replaced names the file.
    pub fn prepare_resume(&self, checkpoint: &Path, overwrite: bool) -> Result<FileMode> {
        self.prepare_continued(checkpoint, overwrite)
            .map_err(|e| self.front_end.spell(e))
    }

    /// [`prepare_resume`](Self::prepare_resume), its errors in the command line's terms.
    fn prepare_continued(&self, checkpoint: &Path, overwrite: bool) -> Result<FileMode> {
        let (manifest, _) = self.survey(true, overwrite)?;
        let folder_id = manifest.as_ref().map_or("", |m| m.run_id.as_str());
        let shown = show_path(checkpoint);
        let nothing_to_replace = |what: &str| Error::Resume {
            path: show_path(&self.dir),
            reason: format!(
                "--overwrite: the checkpoint `{shown}` continues {what}: a resume continues the \
                 run's own files and cannot replace them; leave out --overwrite to continue \
                 them, or --resume to start anew"
            ),
        };
        if overwrite && folder_id.is_empty() {
            return Err(nothing_to_replace(
                "the files in this folder, which name no other run",
            ));
        }
        let c = match &self.expected {
            Some((fingerprint, allowed)) => read_checkpoint(checkpoint, fingerprint, allowed)?,
            None => Checkpoint::read(checkpoint)?,
        };
        let other = !folder_id.is_empty() && !c.run_id.is_empty() && folder_id != c.run_id;
        if other && !overwrite {
            let m = manifest.as_ref().expect("a run id is a manifest's");
            return Err(Error::Resume {
                path: show_path(&self.dir),
                reason: format!(
                    "the folder holds the files of another run ({}) than the one that wrote \
                     the checkpoint `{shown}` (run {}, at step {}): continuing would cut that \
                     run's files and continue another run in them; resume into the \
                     checkpoint's own folder, or pass --overwrite to give this folder to the \
                     checkpoint's run",
                    m.describe(),
                    short_id(&c.run_id),
                    c.state.step
                ),
            });
        }
        if overwrite && !other {
            return Err(nothing_to_replace(if c.run_id.is_empty() {
                "the files in this folder (its run, of an earlier version, cannot be told apart)"
            } else {
                "this folder's own run"
            }));
        }
        if other {
            let m = manifest.as_ref().expect("a run id is a manifest's");
            self.take_over(checkpoint, &c, m)?;
        }
        let id = if c.run_id.is_empty() {
            Some(folder_id.to_owned()).filter(|id| !id.is_empty())
        } else if folder_id.is_empty() {
            // The folder's files are not yet proven the checkpoint's run's (its writers
            // check them): the manifest names no run until the run adopts the
            // checkpoint's ([`adopt_run_id`]), so that a refused resume leaves no claim.
            Some(String::new())
        } else {
            Some(c.run_id.clone())
        };
        self.write_manifest(id.unwrap_or_else(new_run_id))?;
        Ok(FileMode::Create)
    }

    /// Steps 1 and 2 of [`prepare`](Self::prepare): the folder created and probed, an
    /// output path that is a folder refused, another program's folder refused (unless a
    /// new run that overwrites it); the folder's manifest and the non-empty files among
    /// this run's outputs and the other program's.
    fn survey(&self, resume: bool, overwrite: bool) -> Result<(Option<Manifest>, Vec<String>)> {
        std::fs::create_dir_all(&self.dir).map_err(io_at("create the output folder", &self.dir))?;
        let probe = self.dir.join(".rsf-write-probe");
        std::fs::write(&probe, b"").map_err(io_at("write into the output folder", &self.dir))?;
        std::fs::remove_file(&probe).map_err(io_at("remove the probe file of", &self.dir))?;
        let manifest = Manifest::read(&self.dir)?;
        let other = manifest.as_ref().filter(|m| m.program != self.program);
        let mut names: Vec<&str> = self.outputs.iter().map(String::as_str).collect();
        if let Some(m) = other {
            names.extend(m.outputs.iter().map(String::as_str));
        }
        names.sort_unstable();
        names.dedup();
        let mut present = Vec::new();
        for name in &names {
            let path = self.path(name);
            match std::fs::metadata(&path) {
                Ok(m) if m.is_dir() && self.outputs.iter().any(|o| o == name) => {
                    return Err(Error::FileExists {
                        path: show_path(&path),
                        reason: "it is a folder where the run writes a file".into(),
                    })
                }
                Ok(m) if m.is_file() && m.len() > 0 => present.push((*name).to_owned()),
                _ => {}
            }
        }
        if let Some(m) = other {
            if resume || !overwrite {
                return Err(Error::FileExists {
                    path: show_path(&self.dir),
                    reason: format!(
                        "it is the folder of a run of `{}` ({}), not of `{}`; {}",
                        rsf_numeric::excerpt(&m.program),
                        rsf_numeric::excerpt(&present.join(", ")),
                        self.program,
                        match (resume, overwrite) {
                            (true, false) => "resume into the folder of the interrupted run",
                            (true, true) => {
                                "a resume continues a run of its own program (--overwrite \
                                 cannot give it another program's folder): resume into the \
                                 folder of the interrupted run"
                            }
                            _ => "pass --overwrite to replace it, or another --out",
                        }
                    ),
                });
            }
        }
        Ok((manifest, present))
    }

    /// Writes this run's manifest with the run id `run_id` (if it differs from the one
    /// there).
    fn write_manifest(&self, run_id: String) -> Result<()> {
        let mine = Manifest {
            program: self.program.clone(),
            run_id,
            command: self.command.clone(),
            outputs: self.outputs.clone(),
        };
        if Manifest::read(&self.dir)?.as_ref() != Some(&mine) {
            write_atomically(&self.path(MANIFEST), mine.text().as_bytes())?;
        }
        Ok(())
    }
}

/// Gives the run folder `dir` the run id `id` of the checkpoint a run continues, where its
/// manifest names no run (a folder whose manifest was missing or of an earlier version:
/// [`RunFolder::prepare_resume`] leaves the id out until the folder's files are proven to
/// be the checkpoint's run's by their writers' checks). Call it after those checks, before
/// the first checkpoint is written ([`Checkpointer::new`](crate::observe::Checkpointer::new)
/// reads the id). Nothing is done where the manifest is missing, names a run already, or
/// `id` is empty.
///
/// # Errors
/// [`Error::File`] naming the manifest.
pub fn adopt_run_id(dir: &Path, id: &str) -> Result<()> {
    match Manifest::read(dir)? {
        Some(mut m) if m.run_id.is_empty() && !id.is_empty() => {
            m.run_id = id.to_owned();
            write_atomically(&dir.join(MANIFEST), m.text().as_bytes())
        }
        _ => Ok(()),
    }
}

/// Checks that every field in `allowed` (deliberate changes on resume, e.g.
/// `--allow-change end_time_s`) is a field of the run's `fingerprint`.
///
/// # Errors
/// [`Error::InvalidParameter`] named `allow_change` naming the unknown field and listing
/// the fields that exist.
pub fn check_allowed_changes(fingerprint: &Fingerprint, allowed: &[String]) -> Result<()> {
    for a in allowed {
        if a != "format" && fingerprint.get(a).is_none() {
            let known: Vec<&str> = fingerprint.0.iter().map(|(f, _)| f.as_str()).collect();
            return Err(Error::InvalidParameter {
                name: "allow_change".into(),
                reason: format!(
                    "`{}` is not a field of this run's fingerprint; the fields are: {}",
                    rsf_numeric::excerpt(a),
                    known.join(", ")
                ),
            });
        }
    }
    Ok(())
}

/// Reads the checkpoint `path` and checks that it continues a run of `fingerprint`
/// (fields in `allowed` may differ; each must be a field of `fingerprint`).
///
/// # Errors
/// [`Error::InvalidParameter`] for an unknown field in `allowed`
/// ([`check_allowed_changes`]); [`Error::File`], [`Error::CheckpointCorrupt`] (never
/// resumed), [`Error::CheckpointMismatch`] naming the differing field.
pub fn read_checkpoint(
    path: &Path,
    fingerprint: &Fingerprint,
    allowed: &[String],
) -> Result<Checkpoint> {
    check_allowed_changes(fingerprint, allowed)?;
    let c = Checkpoint::read(path)?;
    let allowed: Vec<&str> = allowed.iter().map(String::as_str).collect();
    c.fingerprint.check(fingerprint, &allowed)?;
    Ok(c)
}

/// Refuses a run whose output is estimated above `max_gb` gigabytes.
///
/// # Errors
/// [`Error::InvalidParameter`] named `max_output_gb` unless `max_gb` is a positive number
/// (NaN, ≤ 0); named `name` (e.g. `steps`) with the estimate and how to override it.
pub fn check_output_size(estimate_bytes: f64, max_gb: f64, name: &str) -> Result<()> {
    check_gigabytes("max_output_gb", max_gb)?;
    if estimate_bytes <= max_gb * 1e9 {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name: name.into(),
            reason: format!(
                "the output of this run is estimated at {:.3} GB, above the limit of {} GB: \
                 use fewer steps, or raise --max-output-gb if the disk holds it",
                estimate_bytes / 1e9,
                rsf_numeric::written(max_gb)
            ),
        })
    }
}

/// What a run writes, estimated before it starts: the input of the one output policy,
/// [`output_plan`]. Bytes; any of them may be `+∞` (an adaptive run's honest bound,
/// `T / tau_min` steps, is often far above any disk).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputEstimate {
    /// The bytes the run writes if it runs to its end (within `max_steps`, if given).
    pub bytes: f64,
    /// The bytes written whatever the number of steps (headers, samples at fixed times).
    pub fixed_bytes: f64,
    /// The most bytes one accepted step writes (the worst case: the cap is computed from
    /// it).
    pub bytes_per_step: f64,
    /// Whether the steps are adaptive: a run that does not fit is then capped instead of
    /// refused (a fixed-step run's count is its own, given by the user).
    pub adaptive: bool,
}

/// The output plan of a run: the bound on what it writes and the step cap to enforce
/// ([`until`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputPlan {
    /// Upper bound on the bytes the run writes.
    pub bytes: f64,
    /// Stop after this many steps in total (across resumes), if any.
    pub step_cap: Option<u64>,
}

/// The one output policy of every program (docs/reliability.md, "What every program promises"): with
/// `max_steps` (`--max-steps`) the run is bounded by it and refused if even that does not
/// fit in `max_gb` gigabytes (`--max-output-gb`); without it, a run whose bound fits runs
/// to its end, an adaptive run that does not fit gets the step cap whose output fits (it
/// stops there with a checkpoint, resumable with a larger `--max-steps`), and a fixed-step
/// run that does not fit is refused.
///
/// # Errors
/// [`Error::InvalidParameter`] named `max_output_gb` unless `max_gb` is a positive number;
/// named `max_steps` (given) or `steps` (not given) with the estimate and how to override
/// it ([`check_output_size`]).
pub fn output_plan(
    estimate: OutputEstimate,
    max_steps: Option<u64>,
    max_gb: f64,
) -> Result<OutputPlan> {
    check_gigabytes("max_output_gb", max_gb)?;
    let budget = max_gb * 1e9;
    let OutputEstimate {
        bytes,
        fixed_bytes,
        bytes_per_step,
        adaptive,
    } = estimate;
    if !(bytes <= budget) && adaptive && max_steps.is_none() && bytes_per_step > 0.0 {
        let fit = ((budget - fixed_bytes) / bytes_per_step).floor();
        if fit >= 1.0 {
            return Ok(OutputPlan {
                bytes: fixed_bytes + fit * bytes_per_step,
                step_cap: Some(fit.min(u64::MAX as f64) as u64),
            });
        }
    }
    let name = if max_steps.is_some() {
        "max_steps"
    } else {
        "steps"
    };
    check_output_size(bytes, max_gb, name)?;
    Ok(OutputPlan {
        bytes,
        step_cap: max_steps,
    })
}

/// Checks a size limit in gigabytes named `name`: positive, not NaN (+∞: no limit).
fn check_gigabytes(name: &str, gb: f64) -> Result<()> {
    if gb > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name: name.into(),
            reason: format!("{} GB must be a positive number", rsf_numeric::written(gb)),
        })
    }
}

/// Bytes of one row of a [`PointSeries`](crate::observe::PointSeries) file (2-D: 15 columns, ≈ 190
/// bytes; rounded up).
pub const SERIES_ROW_BYTES: f64 = 200.0;

/// Bytes of one node's row of a [`FrictionalProfile`](crate::observe::FrictionalProfile) file (≈ 90
/// bytes; rounded up).
pub const PROFILE_ROW_BYTES: f64 = 100.0;

/// The end of a run with an optional step cap: [`Until::TimeOrStepCap`] at `t_end` (s) and
/// the cap (steps in total, across resumes), or [`Until::Time`] without one.
pub fn until(t_end: f64, step_cap: Option<u64>) -> Until {
    match step_cap {
        Some(cap) => Until::TimeOrStepCap {
            time: t_end,
            step_cap: usize::try_from(cap).unwrap_or(usize::MAX),
        },
        None => Until::Time(t_end),
    }
}

/// The outcome ([`Error::StepCapReached`]) of a run that ended at the step cap of `until` ([`Termination::StepCap`] of
/// an [`Until::TimeOrStepCap`]) before its end time, at the state `state`: names
/// `--max-steps`, the cap, the step and time, and how to continue (the checkpoint
/// `checkpoint` written there). `None` for a run that ended otherwise.
pub fn step_cap_error(
    summary: &RunSummary,
    until: Until,
    state: &SimulationState,
    checkpoint: &Path,
) -> Option<Error> {
    let Until::TimeOrStepCap { time, step_cap } = until else {
        return None;
    };
    (summary.termination == Termination::StepCap).then(|| Error::StepCapReached {
        step_cap,
        step: state.step,
        time: state.time,
        end_time: time,
        checkpoint: Some(show_path(checkpoint)),
    })
}

/// Checks a window `(t0, t1)` (s) named `name` against `[0, end_time]`.
///
/// # Errors
/// [`Error::InvalidParameter`] named `name` unless `0 ≤ t0 < t1 ≤ end_time`.
pub fn check_window(name: &str, (t0, t1): (f64, f64), end_time: f64) -> Result<()> {
    if t0 >= 0.0 && t0 < t1 && t1 <= end_time {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name: name.into(),
            reason: format!(
                "[{t0:e}, {t1:e}] s must lie inside [0, T] = [0, {end_time:e}] s with \
                 t0 < t1 (outside, it records nothing)"
            ),
        })
    }
}
