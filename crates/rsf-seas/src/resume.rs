//! What a resume of SEAS files shares, 2-D and 3-D alike: reading a file of the interrupted
//! run, and how much of a station or profile file to keep — after its `#` lines its
//! field-list lines, then the rows written up to the checkpoint's step, complete and the
//! last at the time the output's resume log says.

use std::path::Path;

use rsf::checkpoint::write_atomically;

use crate::error::{invalid, io_at, show_path, Error, Result};
use crate::text::{c_exp, File};

/// Reads `path` for a resume (a missing file is an [`Error::Resume`]).
pub(crate) fn read_for_resume(path: &Path) -> Result<Vec<u8>> {
    match std::fs::read(path) {
        Ok(t) => Ok(t),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(Error::Resume {
            path: show_path(path),
            reason: "the file is missing: resume into the folder of the interrupted run (with \
                     a SEAS output written with its resume log)"
                .into(),
        }),
        Err(e) => Err(io_at("read", path)(e)),
    }
}

/// The complete lines of `text` with the byte offset after each.
pub(crate) fn complete_lines(text: &[u8]) -> impl Iterator<Item = (&[u8], usize)> {
    let mut at = 0;
    std::iter::from_fn(move || {
        let len = text[at..].iter().position(|&b| b == b'\n')?;
        let line = &text[at..at + len];
        at += len + 1;
        Some((line, at))
    })
}

/// What a resume keeps of a file ([`kept_rows`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Kept {
    /// The file's bytes.
    pub(crate) text: Vec<u8>,
    /// The byte offset after the lines `first`, where the rows begin.
    pub(crate) rows_start: usize,
    /// The bytes kept: the `#` lines, the lines `first`, the rows.
    pub(crate) keep: usize,
}

/// Checks a station or profile file at `path` for a resume keeping `rows` rows (each of
/// `fields` fields, the last at time `last_t`) after its `#` lines and the lines `first`
/// (its field-list lines, and a profile's row of positions).
///
/// # Errors
/// [`Error::Resume`] naming the file: missing, other lines than `first`, fewer complete
/// rows, a row of another number of fields, the last row at another time.
pub(crate) fn kept_rows(
    path: &Path,
    first: &[String],
    fields: usize,
    rows: usize,
    last_t: f64,
) -> Result<Kept> {
    let text = read_for_resume(path)?;
    let fail = |reason: String| Error::Resume {
        path: show_path(path),
        reason,
    };
    let mut lines = complete_lines(&text).skip_while(|(l, _)| l.starts_with(b"#"));
    let mut keep = 0;
    for (i, want) in first.iter().enumerate() {
        keep = match lines.next() {
            Some((l, end)) if l == want.as_bytes() => end,
            Some((l, _)) => {
                return Err(fail(format!(
                    "its line {} after the `#` lines is `{}`, expected `{}` (another layout or \
                     output)",
                    i + 1,
                    rsf_numeric::excerpt(&String::from_utf8_lossy(l)),
                    rsf_numeric::excerpt(want)
                )))
            }
            None => return Err(fail("it has no field-list line".into())),
        };
    }
    let rows_start = keep;
    let mut last = None;
    for read in 0..rows {
        let Some((line, end)) = lines.next() else {
            return Err(fail(format!(
                "it has {read} complete rows, the checkpoint's step needs {rows}: rows are \
                 missing (truncated or damaged file)"
            )));
        };
        let line = String::from_utf8_lossy(line);
        if line.split_whitespace().count() != fields {
            return Err(fail(format!(
                "malformed row `{}` (damaged file?)",
                rsf_numeric::excerpt(&line)
            )));
        }
        last = line.split_whitespace().next().map(str::to_owned);
        keep = end;
    }
    if let Some(t) = last {
        let want = c_exp(last_t, 13, 21);
        match t {
            t if t == want.trim() => {}
            t => {
                return Err(fail(format!(
                    "its row {rows} is at t = {} s, the resume log says {} s: rows are missing \
                     (truncated or damaged) or the file is of another run",
                    rsf_numeric::excerpt(&t),
                    want.trim()
                )))
            }
        }
    }
    drop(lines);
    Ok(Kept {
        text,
        rows_start,
        keep,
    })
}

/// Checks that the files of an output and a checkpoint of step `step` at time `time` (s)
/// are of the same run: the time `logged` that the output's resume log `log` holds for
/// that step (bit for bit: the log keeps every `f64` exactly) is the checkpoint's. A run of
/// the same scene and method (the checkpoint's fingerprint, checked before) that reached
/// the same step at the same time is the same trajectory; another run's files — a folder
/// whose manifest is missing or of an earlier version — are refused before anything is
/// cut, instead of being cut at the step and continued with the checkpoint's run (issue
/// 87). `None`: a log of a version before issue 87, which holds no time: it proves
/// nothing, so the run folder's manifest must (its run id, which
/// `rsf::run_folder::RunFolder::prepare_resume` has compared with the checkpoint's); a
/// folder whose manifest names no run is refused. A checkpoint at step 0 has nothing to
/// compare.
///
/// # Errors
/// [`Error::Resume`] naming the log if the times differ, or if the log holds no time and
/// the folder's manifest names no run.
pub(crate) fn check_logged_time(
    log: &Path,
    step: usize,
    logged: Option<f64>,
    time: f64,
) -> Result<()> {
    match logged {
        Some(t) if step > 0 && t.to_bits() != time.to_bits() => Err(Error::Resume {
            path: show_path(log),
            reason: format!(
                "its state of the checkpoint's step {step} is at t = {t:e} s, the checkpoint at \
                 t = {time:e} s: the files in this folder are of another run than the \
                 checkpoint's, and continuing would splice the two; resume into the \
                 checkpoint's own folder"
            ),
        }),
        None if step > 0
            && rsf::run_folder::run_id(log.parent().unwrap_or(Path::new("."))).is_none() =>
        {
            Err(Error::Resume {
                path: show_path(log),
                reason: format!(
                    "its mark of step {step} holds no time (a log written before issue 87) \
                     and the folder's manifest `{}` names no run: nothing proves that the \
                     files here are the checkpoint's run's, and continuing another run's \
                     would splice the two; restore the folder's `{}`, or start the run anew \
                     in an empty folder",
                    rsf::run_folder::MANIFEST,
                    rsf::run_folder::MANIFEST
                ),
            })
        }
        _ => Ok(()),
    }
}

/// A mark of an output's resume log (the output's state at a persisted step, JSON): the
/// run's step and its time then.
pub(crate) trait LogMark: Clone + serde::Serialize + serde::de::DeserializeOwned {
    /// The run's step.
    fn step(&self) -> usize;
    /// The run's time after the step (s; `None` in a log of a version before issue 87).
    fn time(&self) -> Option<f64>;
}

/// Appends `mark` to `log` (unless its last mark is of the same step) and writes the log
/// to `path`, atomically.
///
/// # Errors
/// [`Error::InvalidParameter`] named `resume` if the log cannot be written as JSON; the
/// atomic write's.
pub(crate) fn write_log<M: LogMark>(log: &mut Vec<M>, mark: &M, path: &Path) -> Result<()> {
    if log.last().map(M::step) != Some(mark.step()) {
        log.push(mark.clone());
    }
    let text = serde_json::to_string(log)
        .map_err(|e| invalid("resume", format!("the resume log: {e}")))?;
    Ok(write_atomically(path, text.as_bytes())?)
}

/// The resume log at `path` up to its mark of step `step`, and that mark, which must be at
/// the checkpoint's time `time` (s; [`check_logged_time`]). `hint` ends the message of a
/// log without a mark at `step` (after the steps it has marks at).
///
/// # Errors
/// [`Error::Resume`] naming the log: unreadable as a log, no mark at `step`, a mark at
/// another time; the read's errors.
pub(crate) fn read_log<M: LogMark>(
    path: &Path,
    step: usize,
    time: f64,
    hint: &str,
) -> Result<(Vec<M>, M)> {
    let fail = |reason: String| Error::Resume {
        path: show_path(path),
        reason,
    };
    let text = std::fs::read_to_string(path).map_err(io_at("read", path))?;
    let mut log: Vec<M> = serde_json::from_str(&text).map_err(|e| fail(e.to_string()))?;
    let Some(i) = log.iter().position(|m| m.step() == step) else {
        return Err(fail(format!(
            "it has no mark at step {step} (the files were written at steps {:?}){hint}",
            log.iter().map(M::step).collect::<Vec<_>>()
        )));
    };
    log.truncate(i + 1);
    let mark = log[i].clone();
    check_logged_time(path, step, mark.time(), time)?;
    Ok((log, mark))
}

impl File {
    /// Keeps the rows of a mark for a resume, checked in the file on disk ([`kept_rows`]):
    /// `station` (rows, time of the last, s) of a station file, `profile` of a profile
    /// (its row of positions kept before them).
    ///
    /// # Errors
    /// As [`kept_rows`].
    pub(crate) fn resume_rows(
        &mut self,
        station: (usize, f64),
        profile: (usize, f64),
    ) -> Result<()> {
        let mut first = self.layout.field_lines();
        // A profile's row of positions (its rows begin with it); a station's rows.
        let (positions, (rows, last_t)) = match self.layout.profile {
            Some(_) => {
                let row = self
                    .rows
                    .split_inclusive('\n')
                    .next()
                    .unwrap_or("")
                    .to_owned();
                first.push(row.trim_end().to_owned());
                (row, profile)
            }
            None => (String::new(), station),
        };
        let fields = match self.layout.profile {
            Some(_) => first.last().map_or(0, |r| r.split_whitespace().count()),
            None => self.layout.columns.len(),
        };
        let kept = kept_rows(&self.path, &first, fields, rows, last_t)?;
        self.rows = positions + &String::from_utf8_lossy(&kept.text[kept.rows_start..kept.keep]);
        Ok(())
    }
}
