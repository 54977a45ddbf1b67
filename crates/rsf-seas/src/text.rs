//! The SCEC text format the SEAS files share, 2-D and 3-D alike: C-style number formats,
//! the `#` header lines, one `# Column #k` line per column, the field-list line(s), the data
//! rows, the date of a run. A file's [`FileLayout`] says what its header holds; the layouts
//! of the outputs ([`SeasOutput`](crate::SeasOutput)'s along dip,
//! [`SeasBp5Output`](crate::SeasBp5Output)'s on a strike–dip grid) are made of them.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use rsf::checkpoint::write_atomically;

use crate::error::{invalid, io_at, Result};
use crate::setup::SeasSetup;

/// The first line of every SEAS file ([`common_header`]).
pub const SEAS_FIRST_LINE: &str = "# This is the file header:";

/// What the header of one SEAS file says besides the lines every file shares: where the
/// file is (the `location` line), its columns `(field name, description)`, and for a
/// profile, whose first data row holds positions, what they are.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FileLayout {
    /// The header's `location`.
    pub(crate) location: String,
    /// The columns: field name and `# Column #k` description.
    pub(crate) columns: Vec<(String, String)>,
    /// For a profile: its positions.
    pub(crate) profile: Option<Positions>,
}

/// The positions of a profile (its first data row, `0 0` and the positions).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Positions {
    /// How the header names them (`depths z`, `down-dip distances xd`, `positions x3`).
    pub(crate) words: String,
    /// Their field name, the first field-list line (`z`, `xd`, `x2`, `x3`).
    pub(crate) coordinate: String,
    /// Whether each column's field name has a line of its own (SEAS BP7's and BP8's
    /// profiles: `x2`, `t`, `max_slip_rate`, the quantity, four lines) rather than one
    /// line for all of them (BP1, BP3, BP5, BP6).
    pub(crate) name_per_line: bool,
}

impl FileLayout {
    /// A file of `columns` (static names and descriptions) at `location`.
    pub(crate) fn new(location: String, columns: &[(&str, &str)]) -> Self {
        Self {
            location,
            columns: columns
                .iter()
                .map(|&(n, d)| (n.to_owned(), d.to_owned()))
                .collect(),
            profile: None,
        }
    }

    /// The field-list lines: a profile's coordinate, then the columns' names joined by
    /// spaces.
    pub(crate) fn field_lines(&self) -> Vec<String> {
        let names: Vec<String> = self.columns.iter().map(|(n, _)| n.clone()).collect();
        let coordinate = self.profile.iter().map(|p| p.coordinate.clone());
        if self.profile.as_ref().is_some_and(|p| p.name_per_line) {
            coordinate.chain(names).collect()
        } else {
            coordinate.chain([names.join(" ")]).collect()
        }
    }

    /// The header (no newline at its end): the shared lines of `setup` ([`common_header`];
    /// `steps` the smallest and largest time step so far, `rows` the data rows), one
    /// `# Column #k` line per column, a profile's line on its first data row, the
    /// field-list lines.
    pub(crate) fn header(
        &self,
        setup: &SeasSetup,
        steps: Option<(f64, f64)>,
        rows: usize,
    ) -> String {
        let mut h = common_header(setup, &self.location, steps, rows);
        for (i, (_, description)) in self.columns.iter().enumerate() {
            let _ = write!(h, "\n# Column #{} = {description}", i + 1);
        }
        match &self.profile {
            Some(p) => {
                let _ = write!(
                    h,
                    "\n# The first data row is 0 0 followed by the {} (m); every other row is a \
                     time.\n{}",
                    p.words,
                    if p.name_per_line {
                        PROFILE_NAME_LINES
                    } else {
                        PROFILE_FIELD_LINES
                    }
                );
            }
            None => {
                h.push('\n');
                h.push_str(FIELD_LINE);
            }
        }
        for line in self.field_lines() {
            h.push('\n');
            h.push_str(&line);
        }
        h
    }
}

/// Checks the headers' date of `setup` and creates the output folder `dir` (if missing).
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `date` for a date
/// that is not a calendar date `YYYY-MM-DD`; the I/O error creating `dir`.
pub(crate) fn create_output_dir(dir: &Path, setup: &SeasSetup) -> Result<()> {
    if !is_iso_date(&setup.date) {
        return Err(invalid(
            "date",
            format!("{:?} is not a calendar date YYYY-MM-DD", setup.date),
        ));
    }
    std::fs::create_dir_all(dir).map_err(io_at("create", dir))
}

/// A station or profile file of an output that keeps its rows in memory (BP5, BP6, BP7,
/// BP8): its path, its layout and its rows so far (a profile's begin with its row of
/// positions).
pub(crate) struct File {
    /// Where it is written.
    pub(crate) path: PathBuf,
    /// What its header says.
    pub(crate) layout: FileLayout,
    /// Its rows so far, each ending in a newline.
    pub(crate) rows: String,
}

impl File {
    /// The file `path` of `layout`, without rows.
    pub(crate) fn new(path: PathBuf, layout: FileLayout) -> Self {
        Self {
            path,
            layout,
            rows: String::new(),
        }
    }

    /// Writes the file whole, atomically: its header ([`FileLayout::header`] of
    /// `written.0` rows for a station file, `written.1` for a profile) and its rows.
    ///
    /// # Errors
    /// The atomic write's, naming the file.
    pub(crate) fn write(
        &self,
        setup: &SeasSetup,
        steps: Option<(f64, f64)>,
        written: (usize, usize),
    ) -> Result<()> {
        let rows = match self.layout.profile {
            Some(_) => written.1,
            None => written.0,
        };
        let text = format!("{}\n{}", self.layout.header(setup, steps, rows), self.rows);
        Ok(write_atomically(&self.path, text.as_bytes())?)
    }
}

/// The header's last line in a file with one field-list line.
pub(crate) const FIELD_LINE: &str = "# The line below lists the names of the data fields:";

/// The header's last line in a profile whose field names have a line each
/// ([`Positions::name_per_line`]).
pub(crate) const PROFILE_NAME_LINES: &str =
    "# The lines below list the names of the data fields, one a line: the positions', then the \
     columns':";

/// The header's last line in a profile with two field-list lines (the coordinate, the
/// columns).
pub(crate) const PROFILE_FIELD_LINES: &str =
    "# The two lines below list the names of the data fields:";

/// Appends a data row to `rows`: the time `t` as `%21.13E`, every value as `%14.6E`,
/// separated by spaces, a newline at the end.
pub(crate) fn write_row(rows: &mut String, t: f64, values: &[f64]) {
    rows.push_str(&c_exp(t, 13, 21));
    for &x in values {
        rows.push(' ');
        rows.push_str(&c_exp(x, 6, 14));
    }
    rows.push('\n');
}

/// A profile's first data row (no newline): `0 0` and the positions (m) as `%14.6E`.
pub(crate) fn positions_row(positions: impl IntoIterator<Item = f64>) -> String {
    let mut row = String::from("0 0");
    for x in positions {
        row.push(' ');
        row.push_str(&c_exp(x, 6, 14));
    }
    row
}

/// Formats `x` as C's `%W.PE` (`1.2345E+03`), right-aligned in `width`: the SEAS
/// files' number format (e.g. `c_exp(t, 13, 21)` for a time column, `c_exp(x, 6, 14)`
/// for the others).
pub fn c_exp(x: f64, precision: usize, width: usize) -> String {
    let s = format!("{x:.precision$E}");
    let (mantissa, exponent) = s.split_once('E').unwrap_or((&s, "0"));
    let e: i32 = exponent.parse().unwrap_or(0);
    let sign = if e < 0 { '-' } else { '+' };
    format!(
        "{:>width$}",
        format!("{mantissa}E{sign}{:02}", e.unsigned_abs())
    )
}

/// The header lines every file shares (`#` lines): problem, author, date, code, version,
/// element size, location, and the run's smallest and largest time step (`steps`,
/// `(τ_min, τ_max)` once a step was taken) and the data rows in the file
/// (`num_time_steps`, the benchmark's name for it). Only `setup`'s `problem`, `modeler`,
/// `date` and `element_size` are read.
pub fn common_header(
    setup: &SeasSetup,
    location: &str,
    steps: Option<(f64, f64)>,
    rows: usize,
) -> String {
    let mut h = format!(
        "{SEAS_FIRST_LINE}\n# problem={}\n# author={}\n# date={}\n# code=rsf\n\
         # code_version={}\n# element_size={} m\n# location={location}",
        setup.problem,
        setup.modeler,
        setup.date,
        env!("CARGO_PKG_VERSION"),
        setup.element_size
    );
    if let Some((lo, hi)) = steps {
        h.push_str(&format!(
            "\n# minimum_time_step={lo:e}\n# maximum_time_step={hi:e}"
        ));
    }
    h.push_str(&format!("\n# num_time_steps={rows}"));
    h
}

/// Today's date in UTC as `YYYY-MM-DD`, for [`SeasSetup::date`] (from the system clock).
pub fn utc_date_today() -> String {
    jiff::tz::Offset::UTC
        .to_datetime(jiff::Timestamp::now())
        .date()
        .to_string()
}

/// Whether `s` is a calendar date `YYYY-MM-DD` of the proleptic Gregorian calendar (a
/// day the month has: `2023-02-31` is not one, `2024-02-29` is).
pub fn is_iso_date(s: &str) -> bool {
    s.len() == 10 && s.parse::<jiff::civil::Date>().is_ok()
}

#[cfg(test)]
mod tests {
    use super::{c_exp, is_iso_date, utc_date_today};

    #[test]
    fn calendar_dates() {
        assert!(is_iso_date(&utc_date_today()));
        for good in ["2024-02-29", "2000-02-29", "2026-11-24", "1970-01-01"] {
            assert!(is_iso_date(good), "{good:?}");
        }
        for bad in [
            "2023-02-31",
            "2023-02-29",
            "1900-02-29",
            "2026-04-31",
            "2026-13-01",
            "2026-1-01",
            "26-11-24",
            "2026-11-24\n",
            "2026/11/24",
            "",
        ] {
            assert!(!is_iso_date(bad), "{bad:?}");
        }
    }

    #[test]
    fn c_style_exponents() {
        assert_eq!(c_exp(1234.5, 3, 10), " 1.234E+03");
        assert_eq!(c_exp(-0.00012, 2, 9), "-1.20E-04");
        assert_eq!(c_exp(0.0, 1, 7), "0.0E+00");
        assert_eq!(c_exp(1e-100, 0, 7), " 1E-100");
    }
}
