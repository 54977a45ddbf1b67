//! CSV output files that can be continued after a checkpoint without loss: on resume the
//! rows written after the checkpoint's step are cut off and new rows are appended, so a
//! stopped-and-resumed run writes the same bytes as an uninterrupted one. A new file never
//! replaces an existing one unless told to ([`FileMode::Overwrite`]), and a resumed file is
//! checked completely before it is cut, then cut atomically (docs/reliability.md).

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::Path;

use crate::checkpoint::write_atomically;
use crate::error::{io_at, show_path, Error, Result};

/// Coordinate names of CSV columns.
pub(crate) const AXES: [&str; 3] = ["x", "y", "z"];

impl FileMode {
    /// The start of a file of this mode; `every_step`: whether the file has a row for
    /// every step.
    pub(crate) fn start(self, every_step: bool) -> Start {
        match self {
            FileMode::Create => Start::Fresh { overwrite: false },
            FileMode::Overwrite => Start::Fresh { overwrite: true },
            FileMode::Resume { step } => Start::Resume { step, every_step },
        }
    }
}

/// How an output file of an observer ([`PointSeries`](crate::observe::PointSeries),
/// [`FrictionalProfile`](crate::observe::FrictionalProfile), `VtuFrames` with the `vtk` feature) starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileMode {
    /// A new file, starting with its header. An existing non-empty file is not touched:
    /// [`Error::FileExists`] (so that a mistaken command never destroys results).
    Create,
    /// A new file, starting with its header, replacing an existing one (a deliberate
    /// restart).
    Overwrite,
    /// Continues the file of an interrupted run after a checkpoint of step `step`: rows of
    /// later steps (written before the interruption) are removed, new rows appended;
    /// together with [`Simulation::restore`](crate::Simulation::restore) the file ends up
    /// byte-identical to that of an uninterrupted run.
    Resume {
        /// The checkpoint's step.
        step: usize,
    },
}

/// How an output file starts (with what [`FileMode::Resume`] needs to know of the file).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Start {
    /// Create the file and write the header; replace an existing non-empty file only if
    /// `overwrite`.
    Fresh {
        /// Whether an existing non-empty file is replaced.
        overwrite: bool,
    },
    /// Keep the rows of steps `≤ step` of an existing file and append after them.
    Resume {
        /// The checkpoint's step.
        step: usize,
        /// Whether every step has a row (then the last kept row must be `step`).
        every_step: bool,
    },
}

/// Opens `path` for appending CSV rows with `header`, according to `start`. The step of a
/// row is its field number `step_field` (0-based).
///
/// # Errors
/// [`Error::FileExists`] for a new file where a non-empty one exists (unless
/// `overwrite`); [`Error::Resume`] if the file to resume is missing, has another header, a
/// malformed row before the checkpoint's step, or (with `every_step`) ends before it — the
/// file is then untouched; [`Error::File`] for I/O errors.
pub(crate) fn open(
    path: &Path,
    header: &str,
    step_field: usize,
    start: Start,
) -> Result<BufWriter<File>> {
    let (step, every_step) = match start {
        Start::Fresh { overwrite } => return create_file(path, header, overwrite),
        Start::Resume { step, every_step } => (step, every_step),
    };
    let fail = |reason: String| Error::Resume {
        path: show_path(path),
        reason,
    };
    let text = match std::fs::read(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(fail(
                "the file is missing: resume into the folder of the interrupted run".into(),
            ))
        }
        Err(e) => return Err(io_at("read", path)(e)),
    };
    let keep = kept_length(&text, header, step_field, step, every_step).map_err(fail)?;
    if keep < text.len() {
        // Cut atomically: the kept rows into a new file renamed over the old one.
        write_atomically(path, &text[..keep])?;
    }
    let file = OpenOptions::new()
        .append(true)
        .open(path)
        .map_err(io_at("open for appending", path))?;
    Ok(BufWriter::new(file))
}

/// Checks, without changing it, that `path` can be continued after a checkpoint of step
/// `step` (what [`open`] with [`Start::Resume`] checks before it cuts the file).
///
/// # Errors
/// As [`open`] for [`Start::Resume`].
pub(crate) fn check_resume(
    path: &Path,
    header: &str,
    step_field: usize,
    step: usize,
    every_step: bool,
) -> Result<()> {
    let text = match std::fs::read(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(Error::Resume {
                path: show_path(path),
                reason: "the file is missing: resume into the folder of the interrupted run".into(),
            })
        }
        Err(e) => return Err(io_at("read", path)(e)),
    };
    kept_length(&text, header, step_field, step, every_step)
        .map(|_| ())
        .map_err(|reason| Error::Resume {
            path: show_path(path),
            reason,
        })
}

/// Creates the output file `path` with the line(s) `header` (a newline added), flushed so
/// that the header is on disk before the first row, and returns it for appending rows: the
/// start of every output file of [`FileMode::Create`] (`overwrite` false) and
/// [`FileMode::Overwrite`] (`overwrite` true), here and in the crates above (the SEAS files
/// of `rsf-seas`).
///
/// # Errors
/// [`Error::FileExists`] where a non-empty file exists and not `overwrite`;
/// [`Error::File`] for I/O errors.
pub fn create_file(path: &Path, header: &str, overwrite: bool) -> Result<BufWriter<File>> {
    if !overwrite {
        refuse_existing(path)?;
    }
    let mut out = BufWriter::new(File::create(path).map_err(io_at("create", path))?);
    writeln!(out, "{header}").map_err(io_at("write", path))?;
    out.flush().map_err(io_at("write", path))?;
    Ok(out)
}

/// The check of [`FileMode::Create`] before a file is made: nothing, or an empty file, at
/// `path` (what every writer of a new file checks first, here and in the crates above: the
/// HDF5 files of `rsf-hdf5`).
///
/// # Errors
/// [`Error::FileExists`] if `path` exists and is not an empty file (a folder, or a file
/// with content); [`Error::File`] if it cannot be inspected.
pub fn refuse_existing(path: &Path) -> Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() && m.len() == 0 => Ok(()),
        Ok(m) => Err(Error::FileExists {
            path: show_path(path),
            reason: if m.is_dir() {
                "it is a folder".into()
            } else {
                "FileMode::Create never replaces a file (FileMode::Overwrite does, \
                 FileMode::Resume continues it)"
                    .into()
            },
        }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(io_at("inspect", path)(e)),
    }
}

/// The rows of a CSV file with `header`, each parsed by `parse` from its fields (read by
/// the `csv` crate, a last line without its newline included).
///
/// # Errors
/// [`Error::File`] if the file cannot be read; [`Error::Resume`] naming the file for
/// another header, and naming the line for a row `parse` refuses or a blank line.
pub(crate) fn read_rows<T>(
    path: &Path,
    header: &str,
    parse: impl Fn(&[&str]) -> Option<T>,
) -> Result<Vec<T>> {
    let text = std::fs::read_to_string(path).map_err(io_at("read", path))?;
    let fail = |reason: String| Error::Resume {
        path: show_path(path),
        reason,
    };
    if text.lines().next() != Some(header) {
        return Err(fail(format!("its header is not `{header}`")));
    }
    let start = text.find('\n').map_or(text.len(), |i| i + 1);
    csv_lines(text.as_bytes(), start, 2, false)
        .map(|row| {
            let row = row.map_err(|(line, reason)| fail(format!("line {line}: {reason}")))?;
            let fields: Vec<&str> = row.fields.iter().collect();
            parse(&fields).ok_or_else(|| {
                fail(format!(
                    "line {}: malformed row `{}`",
                    row.line,
                    rsf_numeric::excerpt(&fields.join(","))
                ))
            })
        })
        .collect()
}

/// A line of a CSV file read back ([`csv_lines`]): rsf's own files and the SEAS files of
/// `rsf-seas` (the `csv` crate's record: the workspace pins one `csv` for both).
#[derive(Debug)]
pub struct CsvLine {
    /// Its fields.
    pub fields: csv::StringRecord,
    /// Its number in the file (1-based).
    pub line: u64,
    /// The byte offset after it (after its newline, if it has one).
    pub end: usize,
}

/// The CSV lines of `text` from byte `start` (the start of line `line`), by the `csv`
/// crate: fields as written (no quoting), any number of them; with `complete_only`, up to
/// the last newline (a last line without one, cut off by an interruption, is not read). A
/// blank line, or a line that is not UTF-8, is an error `(line, reason)`, after which the
/// iterator ends.
pub fn csv_lines(
    text: &[u8],
    start: usize,
    line: u64,
    complete_only: bool,
) -> impl Iterator<Item = std::result::Result<CsvLine, (u64, String)>> + '_ {
    let end = if complete_only {
        text.iter()
            .rposition(|&b| b == b'\n')
            .map_or(start, |i| (i + 1).max(start))
    } else {
        text.len().max(start)
    };
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .quoting(false)
        .from_reader(&text[start..end]);
    let mut record = csv::StringRecord::new();
    let (mut done, mut last_end) = (false, 0);
    std::iter::from_fn(move || {
        if done {
            return None;
        }
        // Lines of the slice are 1-based from `line`.
        let at = |p: &csv::Position| line + p.line() - 1;
        let read = reader.read_record(&mut record);
        let after = reader.position().clone();
        let item = match read {
            Ok(true) => {
                let pos = record.position().cloned().unwrap_or_else(|| after.clone());
                // The csv crate skips blank lines: a record after one began at it. (A
                // last line without its newline ends where it began.)
                let ended = after.line() == pos.line() + 1
                    || (after.line() == pos.line() && after.byte() as usize == end - start);
                if ended {
                    last_end = after.byte() as usize;
                    Ok(CsvLine {
                        fields: record.clone(),
                        line: at(&pos),
                        end: start + last_end,
                    })
                } else {
                    Err((at(&pos), "a blank line".to_owned()))
                }
            }
            // Blank lines at the end, skipped.
            Ok(false) if last_end < end - start => {
                let lines = text[start..start + last_end]
                    .iter()
                    .filter(|&&b| b == b'\n')
                    .count() as u64;
                Err((line + lines, "a blank line".to_owned()))
            }
            Ok(false) => return None,
            Err(e) => Err((e.position().map_or(line, at), e.to_string())),
        };
        done = item.is_err();
        Some(item)
    })
}

/// Length in bytes of the header and the complete rows of steps `≤ step`.
fn kept_length(
    text: &[u8],
    header: &str,
    step_field: usize,
    step: usize,
    every_step: bool,
) -> std::result::Result<usize, String> {
    let first = text
        .iter()
        .position(|&b| b == b'\n')
        .ok_or("no complete header line")?;
    if &text[..first] != header.as_bytes() {
        return Err(format!(
            "its header is `{}`, expected `{header}` (another output or version)",
            rsf_numeric::excerpt(&String::from_utf8_lossy(&text[..first]))
        ));
    }
    let mut keep = first + 1;
    let mut last = 0;
    // Complete rows only: a row cut off by the interruption is dropped.
    for row in csv_lines(text, keep, 2, true) {
        let row = row.map_err(|(line, reason)| format!("line {line}: {reason}"))?;
        let row_step: usize = row
            .fields
            .get(step_field)
            .and_then(|s| s.parse().ok())
            .ok_or_else(|| {
                let fields: Vec<&str> = row.fields.iter().collect();
                format!(
                    "line {}: malformed row `{}`",
                    row.line,
                    rsf_numeric::excerpt(&fields.join(","))
                )
            })?;
        if row_step > step {
            break;
        }
        if row_step < last {
            return Err(format!("rows out of order at step {row_step}"));
        }
        last = row_step;
        keep = row.end;
    }
    if every_step && last != step {
        return Err(format!(
            "its rows end at step {last}, the checkpoint is at step {step}: rows are missing \
             (was the file flushed before the checkpoint was written?)"
        ));
    }
    Ok(keep)
}

#[cfg(test)]
mod tests {
    use super::kept_length;

    const H: &str = "t,step";

    #[test]
    fn keeps_rows_up_to_the_step_and_drops_a_cut_off_row() {
        let text = b"t,step\n0.1,1\n0.2,2\n0.3,3\n0.4,4\n0.5";
        assert_eq!(kept_length(text, H, 1, 2, true), Ok(19));
        assert_eq!(kept_length(text, H, 1, 4, true), Ok(31));
        assert_eq!(kept_length(text, H, 1, 0, true), Ok(7));
        assert!(kept_length(text, H, 1, 5, true)
            .unwrap_err()
            .contains("missing"));
        assert_eq!(kept_length(text, H, 1, 5, false), Ok(31));
    }

    #[test]
    fn rejects_another_header_and_malformed_rows() {
        assert!(kept_length(b"x,y\n1,2\n", H, 1, 1, true)
            .unwrap_err()
            .contains("header"));
        assert!(kept_length(b"t,step\n0.1,one\n", H, 1, 1, true)
            .unwrap_err()
            .contains("malformed"));
        assert!(kept_length(b"", H, 1, 1, true).is_err());
        let e = kept_length(b"t,step\n0.1,1\n\n0.3,3\n", H, 1, 3, true).unwrap_err();
        assert!(e.contains("line 3") && e.contains("blank"), "{e}");
        let e = kept_length(b"t,step\n0.1,1\n0.2,x\n", H, 1, 3, true).unwrap_err();
        assert!(e.contains("line 3") && e.contains("malformed"), "{e}");
    }

    #[test]
    fn csv_lines_end_where_their_rows_do() {
        let text = b"a,b\n1,2\n3,4";
        let rows: Vec<_> = super::csv_lines(text, 4, 2, false)
            .map(|r| r.map(|l| (l.line, l.end, l.fields.len())))
            .collect();
        assert_eq!(rows, vec![Ok((2, 8, 2)), Ok((3, 11, 2))]);
        let complete: Vec<_> = super::csv_lines(text, 4, 2, true)
            .map(|r| r.map(|l| l.end))
            .collect();
        assert_eq!(complete, vec![Ok(8)]);
        let blank: Vec<_> = super::csv_lines(b"1\n\n", 0, 1, true)
            .map(|r| r.map(|l| l.line))
            .collect();
        assert_eq!(blank, vec![Ok(1), Err((2, "a blank line".to_owned()))]);
    }
}
