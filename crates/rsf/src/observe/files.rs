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

/// [`Error::FileExists`] if `path` exists and is not an empty file.
pub(crate) fn refuse_existing(path: &Path) -> Result<()> {
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

/// The rows of a CSV file with `header`, each parsed by `parse` from its fields.
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
    let mut lines = text.lines();
    if lines.next() != Some(header) {
        return Err(fail(format!("its header is not `{header}`")));
    }
    lines
        .map(|line| {
            let fields: Vec<&str> = line.split(',').collect();
            parse(&fields)
                .ok_or_else(|| fail(format!("malformed row `{}`", rsf_numeric::excerpt(line))))
        })
        .collect()
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
    while keep < text.len() {
        let Some(len) = text[keep..].iter().position(|&b| b == b'\n') else {
            break; // a row cut off by the interruption
        };
        let line = std::str::from_utf8(&text[keep..keep + len]).map_err(|e| e.to_string())?;
        let row_step: usize = line
            .split(',')
            .nth(step_field)
            .and_then(|s| s.parse().ok())
            .ok_or_else(|| format!("malformed row `{}`", rsf_numeric::excerpt(line)))?;
        if row_step > step {
            break;
        }
        if row_step < last {
            return Err(format!("rows out of order at step {row_step}"));
        }
        last = row_step;
        keep += len + 1;
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
    }
}
