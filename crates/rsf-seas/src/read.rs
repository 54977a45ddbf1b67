//! The SEAS files read back: a file's header, its columns, a profile's positions and its
//! rows as numbers ([`read_seas_file`]) — for the HDF5 file of a run's series (the crate
//! `rsf-hdf5`) and for anyone who reads the benchmark's files from Rust.

use std::path::Path;

use crate::error::{io_at, show_path, Error, Result};
use crate::text::{FIELD_LINE, PROFILE_FIELD_LINES, PROFILE_NAME_LINES, SEAS_FIRST_LINE};

/// A column of a SEAS file: its field name (the field-list line's, e.g. `slip_rate`) and
/// its description (the header's `# Column #k = …`, e.g. `Slip_rate (log10 m/s)`; empty
/// if the header has none).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SeasColumn {
    /// The field name.
    pub name: String,
    /// The description, with the unit in parentheses as the benchmark writes it.
    pub description: String,
}

/// A SEAS file read back ([`read_seas_file`]): a station's time series, `global.dat`, a
/// profile (`devol.dat`, `slip.dat`, …: a row of positions, then one row per time), or a
/// table such as BP5's `rupture.dat`. The numbers are those of the text, which the
/// benchmark's format writes to 7 significant digits (times to 14).
#[derive(Debug, Clone, PartialEq)]
pub struct SeasFile {
    /// The header's `#` lines, as written (with their `#`).
    pub header: Vec<String>,
    /// The columns, in order. In a profile the last column (e.g. `slip`) spans the
    /// positions: one number per position in every row.
    pub columns: Vec<SeasColumn>,
    /// A profile's positions (m): the coordinate's field name (`z`, `xd`, `x2`, `x3`) and
    /// the positions of its first data row (after the `0 0`); `None` for other files.
    pub positions: Option<(String, Vec<f64>)>,
    /// The numbers of the data rows, row after row, [`width`](Self::width) per row.
    pub values: Vec<f64>,
}

impl SeasFile {
    /// The numbers per row: the columns' count, or in a profile the columns before the last
    /// plus one per position.
    pub fn width(&self) -> usize {
        match &self.positions {
            Some((_, p)) => self.columns.len() - 1 + p.len(),
            None => self.columns.len(),
        }
    }

    /// The data rows (times, in a station's or profile's file).
    pub fn rows(&self) -> usize {
        self.values.len().checked_div(self.width()).unwrap_or(0)
    }

    /// The values of column `j` in every row, as a `rows × n` block, row-major: `n` = 1, or
    /// for a profile's last column its positions.
    ///
    /// # Panics
    /// If `j` is not a column of the file.
    pub fn column(&self, j: usize) -> Vec<f64> {
        assert!(
            j < self.columns.len(),
            "column {j} of {}",
            self.columns.len()
        );
        let (width, start) = (self.width(), j);
        let n = match &self.positions {
            Some((_, p)) if j + 1 == self.columns.len() => p.len(),
            _ => 1,
        };
        self.values
            .chunks_exact(width)
            .flat_map(|row| &row[start..start + n])
            .copied()
            .collect()
    }

    /// The value of the header's `# key=value` line (e.g. `problem`, `location`,
    /// `num_time_steps`), if it has one.
    pub fn header_value(&self, key: &str) -> Option<&str> {
        self.header.iter().find_map(|l| {
            l.strip_prefix("# ")
                .and_then(|l| l.split_once('='))
                .filter(|(k, _)| *k == key)
                .map(|(_, v)| v)
        })
    }
}

/// Whether the file at `path` begins as a SEAS file ([`SEAS_FIRST_LINE`]); `false` for
/// one that cannot be read.
pub fn is_seas_file(path: &Path) -> bool {
    use std::io::Read as _;
    let mut first = [0u8; SEAS_FIRST_LINE.len() + 1];
    std::fs::File::open(path)
        .and_then(|mut f| f.read_exact(&mut first))
        .is_ok_and(|()| first[..SEAS_FIRST_LINE.len()] == *SEAS_FIRST_LINE.as_bytes())
        && first[SEAS_FIRST_LINE.len()] == b'\n'
}

/// A number of a data row: C's `%E` (`1.234560E+03`), as [`c_exp`](crate::c_exp) writes
/// it, also for the non-finite values (`NaNE+00`, `-infE+00`).
fn number(s: &str) -> Option<f64> {
    s.parse()
        .ok()
        .or_else(|| s.strip_suffix("E+00").and_then(|m| m.parse().ok()))
}

/// Reads the SEAS file `path` as this crate writes it: the `#` lines, the field-list
/// line(s), a profile's row of positions, the data rows.
///
/// # Errors
/// [`Error::File`] if it cannot be read; [`Error::Format`] naming the line for a file that
/// does not begin with [`SEAS_FIRST_LINE`], a header without its last line (the one
/// announcing the field-list lines), a field-list line of another number of names than
/// the header's `# Column` lines, a number that does not parse, a row of another width
/// than the first, a profile's positions row not starting with zeros, or a last line
/// without its newline (a file being written).
pub fn read_seas_file(path: &Path) -> Result<SeasFile> {
    let text = std::fs::read_to_string(path).map_err(io_at("read", path))?;
    let fail = |line: usize, reason: String| Error::Format {
        path: show_path(path),
        line: line as u64 + 1,
        reason,
    };
    if !text.is_empty() && !text.ends_with('\n') {
        return Err(fail(
            text.lines().count() - 1,
            "the last line has no newline (a file being written, or cut off)".into(),
        ));
    }
    let lines: Vec<&str> = text.lines().collect();
    if lines.first() != Some(&SEAS_FIRST_LINE) {
        return Err(fail(
            0,
            format!("the first line is not `{SEAS_FIRST_LINE}`"),
        ));
    }
    let header: Vec<String> = lines
        .iter()
        .take_while(|l| l.starts_with('#'))
        .map(|l| (*l).to_owned())
        .collect();
    let mut at = header.len();
    // (a profile, one name a line)
    let (profile, name_per_line) = match header.last().map(String::as_str) {
        Some(FIELD_LINE) => (false, false),
        Some(PROFILE_FIELD_LINES) => (true, false),
        Some(PROFILE_NAME_LINES) => (true, true),
        _ => {
            return Err(fail(
                at - 1,
                format!(
                    "the header does not end with `{FIELD_LINE}`, `{PROFILE_FIELD_LINES}` or \
                     `{PROFILE_NAME_LINES}`"
                ),
            ))
        }
    };
    let mut next = |what: &str| {
        let line = lines
            .get(at)
            .ok_or_else(|| fail(at, format!("the file ends before its {what}")));
        at += 1;
        line
    };
    let coordinate = if profile {
        Some(next("coordinate's field line")?.trim().to_owned())
    } else {
        None
    };
    let descriptions: Vec<&str> = header
        .iter()
        .filter_map(|l| l.strip_prefix("# Column #"))
        .filter_map(|l| l.split_once(" = ").map(|(_, d)| d))
        .collect();
    let names: Vec<&str> = if name_per_line {
        // One line per `# Column` line (at least two: the time and the quantity).
        let mut names = Vec::with_capacity(descriptions.len());
        for _ in 0..descriptions.len().max(2) {
            names.push(next("field-list lines")?.trim());
        }
        names
    } else {
        next("field-list line")?.split_whitespace().collect()
    };
    if !descriptions.is_empty() && descriptions.len() != names.len() {
        return Err(fail(
            at - 1,
            format!(
                "{} field names, {} `# Column` lines",
                names.len(),
                descriptions.len()
            ),
        ));
    }
    if names.is_empty() || (profile && names.len() < 2) {
        return Err(fail(at - 1, "too few field names".into()));
    }
    let columns: Vec<SeasColumn> = names
        .iter()
        .enumerate()
        .map(|(j, n)| SeasColumn {
            name: (*n).to_owned(),
            description: descriptions
                .get(j)
                .map_or(String::new(), |d| (*d).to_owned()),
        })
        .collect();
    let parse_row = |i: usize| -> Result<Vec<f64>> {
        lines[i]
            .split_whitespace()
            .map(|s| {
                number(s).ok_or_else(|| {
                    fail(i, format!("`{}` is not a number", rsf_numeric::excerpt(s)))
                })
            })
            .collect()
    };
    let positions = match coordinate {
        Some(c) => {
            if at >= lines.len() {
                return Err(fail(at, "the profile has no row of positions".into()));
            }
            let row = parse_row(at)?;
            let lead = columns.len() - 1;
            if row.len() <= lead || row[..lead].iter().any(|&x| x != 0.0) {
                return Err(fail(
                    at,
                    format!("a profile's first data row is {lead} zeros and the positions"),
                ));
            }
            at += 1;
            Some((c, row[lead..].to_vec()))
        }
        None => None,
    };
    let mut file = SeasFile {
        header,
        columns,
        positions,
        values: Vec::new(),
    };
    let width = file.width();
    for i in at..lines.len() {
        let row = parse_row(i)?;
        if row.len() != width {
            return Err(fail(
                i,
                format!("{} numbers in a row of {width}", row.len()),
            ));
        }
        file.values.extend(row);
    }
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::{is_seas_file, read_seas_file, FIELD_LINE, PROFILE_FIELD_LINES, SEAS_FIRST_LINE};
    use crate::Error;

    /// `text` in a file of its own; its path.
    fn file(name: &str, text: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("rsf-seas-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    fn station(rows: &str) -> String {
        format!(
            "{SEAS_FIRST_LINE}\n# problem=P\n# Column #1 = Time (s)\n# Column #2 = Slip (m)\n\
             {FIELD_LINE}\nt slip\n{rows}"
        )
    }

    #[test]
    fn stations_and_profiles_read_back_with_non_finite_numbers() {
        let path = file(
            "station",
            &station(" 0.0000000000000E+00  1.000000E+00\n 1.0E+00 NaNE+00\n 2.0E+00 -infE+00\n"),
        );
        assert!(is_seas_file(&path));
        let f = read_seas_file(&path).unwrap();
        assert_eq!(f.header_value("problem"), Some("P"));
        assert_eq!(f.columns[1].description, "Slip (m)");
        assert_eq!((f.rows(), f.width()), (3, 2));
        assert_eq!(f.column(0), [0.0, 1.0, 2.0]);
        let slip = f.column(1);
        assert!(slip[0] == 1.0 && slip[1].is_nan() && slip[2] == f64::NEG_INFINITY);
        let profile = format!(
            "{SEAS_FIRST_LINE}\n{PROFILE_FIELD_LINES}\nz\nt max_slip_rate slip\n\
             0 0 1.0E+00 2.0E+00 3.0E+00\n5.0E+00 -9.0E+00 1.0E-01 2.0E-01 3.0E-01\n"
        );
        let f = read_seas_file(&file("devol.dat", &profile)).unwrap();
        assert_eq!(f.positions, Some(("z".to_owned(), vec![1.0, 2.0, 3.0])));
        assert_eq!((f.rows(), f.width()), (1, 5));
        assert_eq!(f.column(1), [-9.0]);
        assert_eq!(f.column(2), [0.1, 0.2, 0.3]);
    }

    #[test]
    fn a_file_that_is_not_one_is_refused_naming_the_line() {
        let line_of = |name: &str, text: &str| match read_seas_file(&file(name, text)) {
            Err(Error::Format { line, .. }) => line,
            other => panic!("{name}: {other:?}"),
        };
        assert!(!is_seas_file(&file("csv", "a,b\n1,2\n")));
        assert_eq!(line_of("csv", "a,b\n1,2\n"), 1);
        assert_eq!(line_of("cut", &station("0.0E+00 1.0E+00\n1.0E+00 2.0")), 8);
        assert_eq!(line_of("width", &station("0.0E+00 1.0E+00\n1.0E+00\n")), 8);
        assert_eq!(line_of("word", &station("0.0E+00 slip\n")), 7);
        assert_eq!(line_of("fields", &station("").replace("t slip", "t")), 6);
        let no_fields = format!("{SEAS_FIRST_LINE}\n# problem=P\n");
        assert_eq!(line_of("header", &no_fields), 2);
        let positions = format!("{SEAS_FIRST_LINE}\n{PROFILE_FIELD_LINES}\nz\nt v s\n1 0 5\n");
        assert_eq!(line_of("positions", &positions), 5);
    }
}
