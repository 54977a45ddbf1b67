//! Resuming a [`SeasOutput`](super::SeasOutput)(super::SeasOutput)'s files after a checkpoint: the resume log's state at the
//! checkpoint's step and how much of every file to keep.

use std::path::{Path, PathBuf};

use super::format::{c_exp, profile_field_lines, station_field_line, surface_field_line};
use super::layout::Layout;
use super::setup::{SeasEvent, SeasSetup};
use crate::error::{io_at, show_path, Error, Result};

/// Name of the resume log of a [`SeasOutput`](super::SeasOutput) in its folder
/// ([`SeasOutput::with_resume_log`](super::SeasOutput::with_resume_log)).
pub const SEAS_RESUME_LOG: &str = "seas_resume.csv";

/// Header of the resume log: the output's state after each step, every `f64` in the
/// shortest text that reads back to the same double (NaN: none).
pub(super) const LOG_HEADER: &str =
    "step,t_s,steps,tau_min_s,tau_max_s,last_station_t_s,last_profile_t_s,\
station_rows,profile_rows,slip_at_start_m,pending_t_s,pending_slip_m,events,t_start_s,t_end_s,\
hypocentre_depth_m,peak_slip_rate_mps,surface_slip_m";

/// The state of a [`SeasOutput`](super::SeasOutput) after a step, as its resume log holds it.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct LogState {
    pub(super) steps: usize,
    pub(super) tau_min: f64,
    pub(super) tau_max: f64,
    pub(super) last_station_t: f64,
    pub(super) last_profile_t: f64,
    pub(super) station_rows: usize,
    pub(super) profile_rows: usize,
    pub(super) slip_at_start: f64,
    pub(super) pending_end: Option<(f64, f64)>,
    pub(super) events: Vec<SeasEvent>,
}

impl Default for LogState {
    fn default() -> Self {
        Self {
            steps: 0,
            tau_min: f64::INFINITY,
            tau_max: 0.0,
            last_station_t: f64::NEG_INFINITY,
            last_profile_t: f64::NEG_INFINITY,
            station_rows: 0,
            profile_rows: 0,
            slip_at_start: 0.0,
            pending_end: None,
            events: Vec::new(),
        }
    }
}

/// What a resume keeps: the state of the checkpoint's step and, per file, the bytes kept.
pub(super) struct ResumePlan {
    pub(super) state: LogState,
    /// `(file, bytes kept, bytes now)`, the resume log included.
    pub(super) cuts: Vec<(PathBuf, usize, usize)>,
}

/// Reads the resume log and the files of a [`SeasOutput`](super::SeasOutput) in `dir` and plans their cut
/// at step `step`; changes nothing.
pub(super) fn plan_resume(
    dir: &Path,
    setup: &SeasSetup,
    layout: &Layout,
    step: usize,
) -> Result<ResumePlan> {
    let log_path = dir.join(SEAS_RESUME_LOG);
    let (state, log_keep, log_len) = read_log(&log_path, step)?;
    let mut cuts = vec![(log_path, log_keep, log_len)];
    for (name, _) in &setup.stations {
        let path = dir.join(name);
        let (keep, len) = kept_rows(
            &path,
            &[station_field_line(&setup.layout)],
            setup.layout.station_columns().len(),
            state.station_rows,
            state.last_station_t,
        )?;
        cuts.push((path, keep, len));
    }
    for st in &setup.surface_stations {
        let path = dir.join(&st.name);
        let (keep, len) = kept_rows(
            &path,
            &[surface_field_line(layout.components, setup.depth_axis)],
            1 + 2 * layout.components,
            state.station_rows,
            state.last_station_t,
        )?;
        cuts.push((path, keep, len));
    }
    let files = setup.layout.profile_files();
    for (&quantity, name) in setup.layout.profiles().iter().zip(files) {
        let path = dir.join(name);
        let first = profile_field_lines(&setup.layout, quantity)
            .into_iter()
            .chain([layout.profile_first_row()])
            .collect::<Vec<_>>();
        let (keep, len) = kept_rows(
            &path,
            &first,
            2 + layout.profile.len(),
            state.profile_rows,
            state.last_profile_t,
        )?;
        cuts.push((path, keep, len));
    }
    Ok(ResumePlan { state, cuts })
}

/// Reads `path` for a resume (a missing file is an [`Error::Resume`]).
pub(super) fn read_for_resume(path: &Path) -> Result<Vec<u8>> {
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
pub(super) fn complete_lines(text: &[u8]) -> impl Iterator<Item = (&[u8], usize)> {
    let mut at = 0;
    std::iter::from_fn(move || {
        let len = text[at..].iter().position(|&b| b == b'\n')?;
        let line = &text[at..at + len];
        at += len + 1;
        Some((line, at))
    })
}

/// The state of the resume log `path` after step `step` (the default state if the log
/// has no line up to it), the bytes of the log kept and its length.
pub(super) fn read_log(path: &Path, step: usize) -> Result<(LogState, usize, usize)> {
    let text = read_for_resume(path)?;
    let fail = |reason: String| Error::Resume {
        path: show_path(path),
        reason,
    };
    let mut lines = complete_lines(&text);
    let header_end = match lines.next() {
        Some((h, end)) if h == LOG_HEADER.as_bytes() => end,
        _ => return Err(fail("its first line is not the resume log's header".into())),
    };
    let mut state = LogState::default();
    let (mut keep, mut last) = (header_end, None);
    for (line, end) in lines {
        let line = std::str::from_utf8(line).map_err(|e| fail(e.to_string()))?;
        let malformed = || fail(format!("malformed line `{}`", rsf_numeric::excerpt(line)));
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != 18 {
            return Err(malformed());
        }
        let n = |i: usize| f[i].parse::<usize>().map_err(|_| malformed());
        let x = |i: usize| f[i].parse::<f64>().map_err(|_| malformed());
        let row_step = n(0)?;
        if row_step > step {
            break;
        }
        if last.is_some_and(|l| row_step <= l) {
            return Err(fail(format!("lines out of order at step {row_step}")));
        }
        let events = n(12)?;
        let event = SeasEvent {
            t_start: x(13)?,
            t_end: x(14)?,
            hypocentre_depth: x(15)?,
            peak_slip_rate: x(16)?,
            surface_slip: x(17)?,
        };
        if events == state.events.len() + 1 {
            state.events.push(event);
        } else if events == state.events.len() && events > 0 {
            state.events[events - 1] = event;
        } else if events != state.events.len() {
            return Err(malformed());
        }
        let pending = (x(10)?, x(11)?);
        state = LogState {
            steps: n(2)?,
            tau_min: x(3)?,
            tau_max: x(4)?,
            last_station_t: x(5)?,
            last_profile_t: x(6)?,
            station_rows: n(7)?,
            profile_rows: n(8)?,
            slip_at_start: x(9)?,
            pending_end: (!pending.0.is_nan()).then_some(pending),
            events: state.events,
        };
        (keep, last) = (end, Some(row_step));
    }
    if let Some(l) = last.filter(|&l| l != step) {
        return Err(fail(format!(
            "its lines end at step {l}, the checkpoint is at step {step}: lines are missing \
             (was the output before the checkpointer?)"
        )));
    }
    Ok((state, keep, text.len()))
}

/// Checks a station file or `devol.dat` at `path` for a resume keeping `rows` rows (each
/// of `fields` fields, the last at time `last_t`) after its `#` lines and the lines
/// `first` (its field-list lines, and `devol.dat`'s row of depths); returns the bytes kept
/// and the file's length.
pub(super) fn kept_rows(
    path: &Path,
    first: &[String],
    fields: usize,
    rows: usize,
    last_t: f64,
) -> Result<(usize, usize)> {
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
    Ok((keep, text.len()))
}
