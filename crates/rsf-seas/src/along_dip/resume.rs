//! Resuming a [`SeasOutput`](super::SeasOutput)'s files after a checkpoint: the resume log's
//! state at the checkpoint's step and how much of every file to keep.

use std::path::{Path, PathBuf};

use super::headers;
use super::layout::Layout;
use crate::error::{show_path, Error, Result};
use rsf::observe::csv_lines;

use crate::resume::{check_logged_time, complete_lines, kept_rows, read_for_resume};
use crate::setup::{SeasEvent, SeasSetup};

/// Name of the resume log of a [`SeasOutput`](crate::SeasOutput) in its folder
/// ([`SeasOutput::with_resume_log`](super::SeasOutput::with_resume_log)).
pub const SEAS_RESUME_LOG: &str = "seas_resume.csv";

/// Header of the resume log: the output's state after each step, every `f64` in the
/// shortest text that reads back to the same double (NaN: none).
pub(crate) const LOG_HEADER: &str =
    "step,t_s,steps,tau_min_s,tau_max_s,last_station_t_s,last_profile_t_s,\
station_rows,profile_rows,slip_at_start_m,pending_t_s,pending_slip_m,events,t_start_s,t_end_s,\
hypocentre_depth_m,peak_slip_rate_mps,surface_slip_m";

/// The state of a [`SeasOutput`](super::SeasOutput) after a step, as its resume log holds it.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct LogState {
    /// The time after the step (s; NaN before the first line).
    pub(super) t: f64,
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
            t: f64::NAN,
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
        let kept = kept_rows(
            &path,
            &headers::station(setup, 0.0).field_lines(),
            setup.layout.station_columns().len(),
            state.station_rows,
            state.last_station_t,
        )?;
        cuts.push((path, kept.keep, kept.text.len()));
    }
    for st in &setup.surface_stations {
        let path = dir.join(&st.name);
        let kept = kept_rows(
            &path,
            &headers::surface(setup, &st.position, layout.components).field_lines(),
            1 + 2 * layout.components,
            state.station_rows,
            state.last_station_t,
        )?;
        cuts.push((path, kept.keep, kept.text.len()));
    }
    let files = setup.layout.profile_files();
    for (&quantity, name) in setup.layout.profiles().iter().zip(files) {
        let path = dir.join(name);
        let first = headers::profile(setup, quantity)
            .field_lines()
            .into_iter()
            .chain([layout.profile_first_row()])
            .collect::<Vec<_>>();
        let kept = kept_rows(
            &path,
            &first,
            2 + layout.profile.len(),
            state.profile_rows,
            state.last_profile_t,
        )?;
        cuts.push((path, kept.keep, kept.text.len()));
    }
    Ok(ResumePlan { state, cuts })
}

/// The state of the resume log `path` after step `step` (the default state if the log
/// has no line up to it), the bytes of the log kept and its length. The log is read by the
/// `csv` crate; a last line without its newline (cut off by an interruption) is not read.
///
/// # Errors
/// [`Error::Resume`] for a missing log, another header, lines missing up to `step`;
/// [`Error::Malformed`] naming the line that is not one the output writes.
pub(super) fn read_log(path: &Path, step: usize) -> Result<(LogState, usize, usize)> {
    let text = read_for_resume(path)?;
    let fail = |reason: String| Error::Resume {
        path: show_path(path),
        reason,
    };
    let header_end = match complete_lines(&text).next() {
        Some((h, end)) if h == LOG_HEADER.as_bytes() => end,
        _ => return Err(fail("its first line is not the resume log's header".into())),
    };
    let mut state = LogState::default();
    let (mut keep, mut last) = (header_end, None);
    for read in csv_lines(&text, header_end, 2, true) {
        let row = read.map_err(|(line, reason)| Error::Malformed {
            path: show_path(path),
            line,
            reason,
        })?;
        let f = &row.fields;
        let malformed = || Error::Malformed {
            path: show_path(path),
            line: row.line,
            reason: format!(
                "malformed line `{}`",
                rsf_numeric::excerpt(&f.iter().collect::<Vec<_>>().join(","))
            ),
        };
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
            t: x(1)?,
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
        (keep, last) = (row.end, Some(row_step));
    }
    if let Some(l) = last.filter(|&l| l != step) {
        return Err(fail(format!(
            "its lines end at step {l}, the checkpoint is at step {step}: lines are missing \
             (was the output before the checkpointer?)"
        )));
    }
    Ok((state, keep, text.len()))
}

/// Checks that the resume log `path` and the checkpoint of step `step` at time `time` (s)
/// are of the same run: the log's line of that step shows exactly that time
/// ([`check_logged_time`]). Changes nothing.
///
/// # Errors
/// [`Error::Resume`] naming the log if the times differ; as [`read_log`].
pub(super) fn check_log_time(path: &Path, step: usize, time: f64) -> Result<()> {
    if step == 0 {
        return Ok(());
    }
    let (state, _, _) = read_log(path, step)?;
    check_logged_time(path, step, Some(state.t), time)
}
