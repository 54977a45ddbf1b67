//! The run folder of a scene that writes a program's files (`rsf.seas_bp1`,
//! `rsf.seas_bp6`): its keywords `out`, `overwrite`, `resume`, `allow_change`, driven
//! through the programs' [`Session`] by the programs' rule (docs/reliability.md,
//! "Round 5"): the folder prepared before anything is computed (another run's refused),
//! the checkpoint read, checked and restored, its files proven the checkpoint's run's.

use std::path::PathBuf;

use pyo3::prelude::*;
use rsf::checkpoint::Fingerprint;
use rsf::observe::{FaultTractions, FileMode};
use rsf::run_folder::{FrontEnd, RunFolder, Session, SessionFlags};
use rsf::{Model, Observer, SimulationState, Stepping};

use crate::engine::{Engine, Files, Recording, WithFaultOperator};
use crate::errors::{invalid, OrPy};
use crate::simulation::{End, Simulation};

/// The keywords of a run folder.
#[derive(Debug, Clone)]
pub(crate) struct FolderKeywords {
    /// The folder of the files (`None`: no files).
    pub out: Option<PathBuf>,
    /// Replace another run's files in `out`.
    pub overwrite: bool,
    /// The checkpoint to continue from.
    pub resume: Option<PathBuf>,
    /// Fingerprint fields a resume may change.
    pub allow_change: Vec<String>,
}

impl FolderKeywords {
    /// The keywords `out`, `overwrite`, `resume` and `allow_change` of a run.
    pub fn new(
        out: Option<PathBuf>,
        overwrite: bool,
        resume: Option<PathBuf>,
        allow_change: Vec<String>,
    ) -> Self {
        Self {
            out,
            overwrite,
            resume,
            allow_change,
        }
    }

    /// Checks the keywords together: `allow_change` needs `resume`, `overwrite` needs
    /// `out`.
    ///
    /// # Errors
    /// `InvalidParameterError` naming the keyword.
    pub fn check(&self) -> PyResult<()> {
        if !self.allow_change.is_empty() && self.resume.is_none() {
            return Err(invalid(
                "allow_change",
                "needs `resume` (the fields a resume may change; a new run has nothing to change)",
            ));
        }
        if self.overwrite && self.out.is_none() {
            return Err(invalid("overwrite", "needs `out`"));
        }
        Ok(())
    }

    /// The folder `out` prepared for `program`'s files `names` (and `checkpoint.bin`), as
    /// the program's guard prepares it — first, so that another run's folder is refused
    /// before anything is computed; on resume, proven the checkpoint's run's. The mode of
    /// a fresh run's files ([`FileMode::Create`] without `out`). A checkpoint to resume
    /// is checked against the run's `fingerprint` (and `allow_change`) before anything in
    /// the folder changes ([`RunFolder::expecting`]).
    ///
    /// # Errors
    /// The folder's refusal (`RsfIOError`), the checkpoint's.
    pub fn prepare(
        &self,
        program: &str,
        mut names: Vec<String>,
        fingerprint: &Fingerprint,
    ) -> PyResult<FileMode> {
        self.check()?;
        let Some(out) = &self.out else {
            return Ok(FileMode::Create);
        };
        names.push("checkpoint.bin".into());
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let folder = RunFolder::new(out, program, &names)
            .front_end(FrontEnd::Python)
            .expecting(fingerprint.clone(), &self.allow_change);
        match &self.resume {
            Some(checkpoint) => folder.prepare_resume(checkpoint, self.overwrite).py(),
            None => folder.prepare(false, self.overwrite).py(),
        }
    }

    /// The session of `method` until `end_time` (s) with `fingerprint`: on resume, the
    /// checkpoint read, checked (`allow_change`) and restored; checkpoints into
    /// `out/checkpoint.bin` (or the resumed file without `out`), anywhere the package
    /// writes one ([`Session::checkpoints_anywhere`]).
    ///
    /// # Errors
    /// The checkpoint's ([`Session::start`]).
    pub fn session<const D: usize, const C: usize, M: Stepping<D, C>>(
        &self,
        fingerprint: Fingerprint,
        end_time: f64,
        method: &mut M,
    ) -> PyResult<Session> {
        let checkpoint_path = match (&self.out, &self.resume) {
            (Some(out), _) => out.join("checkpoint.bin"),
            (None, Some(r)) => r.clone(),
            (None, None) => PathBuf::from("checkpoint.bin"),
        };
        let flags = SessionFlags {
            resume: self.resume.as_deref(),
            allow_change: &self.allow_change,
            ..SessionFlags::default()
        };
        Ok(
            Session::start(flags, checkpoint_path, fingerprint, end_time, method)
                .py()?
                .checkpoints_anywhere(),
        )
    }

    /// The run's folder once its files are checked (a folder whose manifest named no run
    /// becomes the checkpoint's: [`Session::adopt_folder`]); empty without `out`.
    ///
    /// # Errors
    /// The manifest's I/O errors.
    pub fn files(&self, session: &Session) -> PyResult<Files> {
        match &self.out {
            Some(out) => {
                session.adopt_folder().py()?;
                Ok(Files::of_folder(out))
            }
            None => Ok(Files::default()),
        }
    }
}

/// A program's files that a session continues at a checkpoint's step, or starts with the
/// initial state's rows (BP5's and BP6's, written whole where a run stops).
pub(crate) trait SessionFiles<const D: usize, const C: usize>:
    Observer<D, C> + 'static
{
    /// Continues the files of the run's folder at the checkpoint's `step` and `time`.
    ///
    /// # Errors
    /// The files' (not the checkpoint's run's, rows missing).
    fn resume_at(&mut self, step: usize, time: f64) -> rsf::Result<()>;
    /// The rows of the initial state.
    fn write_initial(
        &mut self,
        model: &Model<D, C>,
        state: &SimulationState,
        f: &dyn FaultTractions,
    );
}

impl SessionFiles<3, 3> for rsf_seas::SeasBp5Output {
    fn resume_at(&mut self, step: usize, time: f64) -> rsf::Result<()> {
        Ok(self.resume(step, time)?)
    }
    fn write_initial(
        &mut self,
        model: &Model<3, 3>,
        state: &SimulationState,
        f: &dyn FaultTractions,
    ) {
        self.write_initial_state(model, state, f)
    }
}

impl<const C: usize> SessionFiles<2, C> for rsf_seas::SeasBp6Output {
    fn resume_at(&mut self, step: usize, time: f64) -> rsf::Result<()> {
        Ok(self.resume(step, time)?)
    }
    fn write_initial(
        &mut self,
        model: &Model<2, C>,
        state: &SimulationState,
        f: &dyn FaultTractions,
    ) {
        self.write_initial_state(model, state, f)
    }
}

/// What a run through a session is: its fingerprint, its end time (s), the fault's
/// recording every `fault_every` steps, the program's name (the simulation's label).
pub(crate) struct SessionRun {
    pub fingerprint: Fingerprint,
    pub end: f64,
    pub fault_every: usize,
    pub program: &'static str,
}

impl FolderKeywords {
    /// The simulation of `sim` through the session of `run`: on resume, the checkpoint
    /// restored and the files `output` makes (of the session's method; `None` without
    /// `out`) continued at its step; else their first rows written.
    ///
    /// # Errors
    /// The checkpoint's, the files'.
    pub fn simulation<const D: usize, const C: usize, M, O>(
        self,
        run: SessionRun,
        mut sim: M,
        output: impl FnOnce(&M) -> PyResult<Option<O>>,
    ) -> PyResult<Simulation>
    where
        M: Stepping<D, C> + WithFaultOperator + 'static,
        O: SessionFiles<D, C>,
    {
        let session = self.session(run.fingerprint.clone(), run.end, &mut sim)?;
        let mut files: Vec<Box<dyn Observer<D, C>>> = Vec::new();
        if let Some(mut output) = output(&sim)? {
            match session.resumed() {
                Some(c) => output.resume_at(c.state.step, c.state.time).py()?,
                None => output.write_initial(sim.model(), sim.state(), sim.fault_tractions()),
            }
            files.push(Box::new(output));
        }
        let engine = Engine::<D, C, M> {
            sim,
            recording: Recording::new(run.fault_every).py()?,
            files,
            fingerprint: run.fingerprint,
            // Every file is checked: a folder whose manifest named no run is the
            // checkpoint's.
            folder: self.files(&session)?,
        };
        Ok(Simulation::new(
            Box::new(engine),
            Some(End::Time(run.end)),
            run.program,
        ))
    }
}
