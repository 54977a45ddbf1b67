//! The resume of a BP5 output: its log of marks (the output's state at each persisted
//! step, `bp5_resume.json`) and each file continued from the mark of the checkpoint's step
//! (the shared check of a station or profile file, [`kept_rows`]).

use super::mark::Mark;
use super::SeasBp5Output;
use crate::error::Result;
use crate::resume::{read_log, write_log};

impl SeasBp5Output {
    /// Keeps the resume log ([`SEAS_BP5_RESUME_LOG`](crate::SEAS_BP5_RESUME_LOG), BP7's
    /// or BP8's): writes every file, the catalogue and
    /// a mark of the log every `steps` steps (0: never) and where a step cap stops the run,
    /// so that a run continued from a checkpoint written at such a step continues its
    /// files ([`resume`](Self::resume)) — checkpoint at multiples of `steps`, with the
    /// checkpointer after this output among the observers.
    pub fn with_resume_log(mut self, steps: usize) -> Self {
        self.resume_log = true;
        self.persist_every = steps;
        self
    }

    /// Keeps the resume log with a mark also where every run ends (its
    /// [`finish`](rsf::Observer::finish): the end time, an observer's break, Ctrl-C), so
    /// that a front end that writes a checkpoint where a run stopped — the Python
    /// package's `Simulation.checkpoint` after `advance` — continues the files from it.
    /// The marks of [`with_resume_log`](Self::with_resume_log) every `steps` steps are
    /// kept.
    pub fn with_marks_where_runs_end(mut self, steps: usize) -> Self {
        self.mark_at_finish = true;
        self.with_resume_log(steps)
    }

    /// Writes the files and a mark of the resume log at the current step.
    pub(super) fn persist(&mut self) -> Result<()> {
        self.write_files()?;
        write_log(&mut self.log, &self.mark, &self.dir.join(self.log_name))
    }

    /// Continues the files of the run in this folder at its persisted step `step` (the
    /// checkpoint's, at time `time`, s): reads the resume log, checks that its mark of the
    /// step is at exactly that time (the files are the checkpoint's run's, not another
    /// run's whose manifest is missing: issue 87), and keeps each file's rows up to that step
    /// (the files are rewritten at the next persisted step or the end of the run call).
    /// Each file is checked as the files along dip are: its field-list lines (and a
    /// profile's positions) after its `#` lines, then the mark's rows, complete, of the
    /// file's number of fields, the last at the mark's time.
    ///
    /// # Errors
    /// [`Error::Resume`](crate::Error::Resume) naming the resume log if it has no mark at
    /// `step`, one at another time, or cannot be read back, or the file that cannot be continued (missing,
    /// another layout, rows missing or damaged); read errors naming the file.
    pub fn resume(&mut self, step: usize, time: f64) -> Result<()> {
        let (log, mark) = read_log::<Mark>(
            &self.dir.join(self.log_name),
            step,
            time,
            ": checkpoint at multiples of the output's persist interval",
        )?;
        let station = (mark.written, mark.last_station_t);
        let profile = (mark.profile_written, mark.last_profile_t);
        let files = self
            .fault
            .iter_mut()
            .map(|s| &mut s.file)
            .chain(self.body.iter_mut().map(|s| &mut s.file))
            .chain(std::iter::once(&mut self.global))
            .chain(self.profiles.iter_mut().map(|p| &mut p.file));
        for f in files {
            f.resume_rows(station, profile)?;
        }
        self.log = log;
        self.mark = mark;
        Ok(())
    }
}
