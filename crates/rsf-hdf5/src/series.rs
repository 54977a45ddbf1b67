//! The time series of a SEAS run in one HDF5 file: every SEAS file of the run's folder
//! (stations, `global.dat`, profiles, BP5's `rupture.dat`) and its event catalogue
//! `events.csv`, one group each, read back from the benchmark's text files
//! ([`rsf_seas::read_seas_file`]) — so the HDF5 file holds exactly what they say, and
//! follows them through checkpoints, resumes and overwrites without a state of its own.

use std::path::{Path, PathBuf};

use hdf5::File;
use rsf::observe::{csv_lines, refuse_existing, FileMode};
use rsf::{Flow, Observer, StepView};
use rsf_seas::{is_seas_file, read_seas_file, SeasFile};

use crate::attributes::text;
use crate::error::{h5_at, show_path, Error, Result};
use crate::frames::view;

/// The name of the series file in a SEAS run's folder (`out/seas_bp1/seas.h5`).
pub const SEAS_SERIES_FILE: &str = "seas.h5";

/// The event catalogue the SEAS outputs write beside their files (rsf's own CSV).
const EVENTS: &str = "events.csv";

/// What [`write_seas_series`] wrote: each group's name (a file's name, `events` for the
/// catalogue) and its rows.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SeriesSummary {
    /// `(group, rows)` in the file's order (the files' names, sorted; `events` last).
    pub groups: Vec<(String, usize)>,
}

/// The SEAS files of the folder `dir` ([`rsf_seas::is_seas_file`]: the files that begin
/// with the benchmark's header), sorted by name.
///
/// # Errors
/// [`rsf::Error::File`] (as [`Error::Rsf`]) if the folder cannot be listed.
pub fn seas_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let list = |e| rsf::Error::File {
        path: show_path(dir),
        action: "list the SEAS files of",
        source: e,
    };
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(list)? {
        let path = entry.map_err(list)?.path();
        if path.is_file() && is_seas_file(&path) {
            files.push(path);
        }
    }
    files.sort();
    Ok(files)
}

/// Writes the time series of the SEAS run in the folder `dir` into one HDF5 file `path`
/// (e.g. `dir/`[`SEAS_SERIES_FILE`]), replacing it atomically (written beside it, then
/// renamed: a reader never sees a half-written file). One group per SEAS file, named as
/// the file (`fltst_dp000`, `devol.dat`, `global.dat`, …), holding
///
/// - one dataset per column, named by the file's field names (`t` in s, `slip`,
///   `slip_rate`, `shear_stress`, `state`, …), over the rows; a profile's last column
///   (`slip`, …) over (rows, positions), its positions (m) a dataset named by the
///   coordinate (`z`, `xd`, `x2`, `x3`);
/// - attributes: `header` (the file's `#` lines), one per `# key=value` line (`problem`,
///   `location`, `num_time_steps`, …), and on each dataset its `description` (the
///   header's `# Column #k` text, with the unit).
///
/// The event catalogue `events.csv`, if present, is the group `events`: a dataset per
/// column, named by its header (units in the names). The numbers are the text's, to the
/// benchmark format's 7 significant digits (times to 14): the files are the record; this
/// is their one-file, sliceable form (h5py, xarray).
///
/// # Errors
/// [`Error::InvalidParameter`] named `dir` if it holds no SEAS file; the errors of
/// [`rsf_seas::read_seas_file`] (as [`Error::Seas`]) naming the file and line that is not
/// one; [`rsf::Error::File`] for a catalogue that cannot be read or a number in it that
/// does not parse; [`Error::Hdf5`] naming the file being written. The file at `path` is
/// unchanged on error.
pub fn write_seas_series(dir: &Path, path: &Path) -> Result<SeriesSummary> {
    let files = seas_files(dir)?;
    if files.is_empty() {
        return Err(Error::InvalidParameter {
            name: "dir".into(),
            reason: format!(
                "`{}` holds no SEAS file (none begins with `{}`)",
                show_path(dir),
                rsf_seas::SEAS_FIRST_LINE
            ),
        });
    }
    replace_atomically(path, |partial| {
        write_file(&files, &dir.join(EVENTS), partial)
    })
}

/// What `write` makes of the file `path`, written beside it (`.{name}.partial`) and
/// renamed over it once complete: a reader never sees a half-written file, and `path` is
/// unchanged if `write` fails (the partial file is removed).
///
/// # Errors
/// `write`'s; [`rsf::Error::File`] if the rename fails.
pub(crate) fn replace_atomically<T>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<T>,
) -> Result<T> {
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let partial = path.with_file_name(format!(".{name}.partial"));
    let written = match write(&partial) {
        Ok(w) => w,
        Err(e) => {
            std::fs::remove_file(&partial).ok();
            return Err(e);
        }
    };
    std::fs::rename(&partial, path).map_err(|source| rsf::Error::File {
        path: show_path(path),
        action: "rename the written HDF5 file to",
        source,
    })?;
    Ok(written)
}

/// The HDF5 file `path` of the SEAS `files` and the catalogue `events` (if it exists).
fn write_file(files: &[PathBuf], events: &Path, path: &Path) -> Result<SeriesSummary> {
    let err = h5_at("write the SEAS series into", path);
    let file = File::create(path).map_err(&err)?;
    text(
        &file,
        "source",
        "the SEAS files of a run's folder, one group per file, as written (the benchmark's \
         text format: times to 14 significant digits, other values to 7)",
    )
    .map_err(&err)?;
    let mut groups = Vec::new();
    for f in files {
        let seas = read_seas_file(f)?;
        let name = f
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        write_group(&file, &name, &seas).map_err(&err)?;
        groups.push((name, seas.rows()));
    }
    if events.is_file() {
        let rows = write_events(&file, events, &err)?;
        groups.push(("events".to_owned(), rows));
    }
    file.close().map_err(&err)?;
    Ok(SeriesSummary { groups })
}

/// The group `name` of the SEAS file `seas`.
fn write_group(file: &File, name: &str, seas: &SeasFile) -> hdf5::Result<()> {
    let group = file.create_group(name)?;
    text(&group, "header", &seas.header.join("\n"))?;
    for line in &seas.header {
        if let Some((key, value)) = line.strip_prefix("# ").and_then(|l| l.split_once('=')) {
            if !key.contains(' ') && key != "header" {
                text(&group, key, value)?;
            }
        }
    }
    let rows = seas.rows();
    for (j, column) in seas.columns.iter().enumerate() {
        let values = seas.column(j);
        let shape = match &seas.positions {
            Some((_, p)) if j + 1 == seas.columns.len() => vec![rows, p.len()],
            _ => vec![rows],
        };
        let d = group
            .new_dataset_builder()
            .with_data(view(&values, &shape))
            .create(column.name.as_str())?;
        text(&d, "description", &column.description)?;
    }
    if let Some((coordinate, positions)) = &seas.positions {
        let last = seas.columns.last().map_or("", |c| c.name.as_str());
        let d = group
            .new_dataset_builder()
            .with_data(view(positions, &[positions.len()]))
            .create(coordinate.as_str())?;
        text(
            &d,
            "description",
            &format!("the positions (m) of the profile: the columns of `{last}`"),
        )?;
    }
    Ok(())
}

/// The group `events` of the catalogue `path` (a header of names, rows of numbers); its
/// rows.
fn write_events(file: &File, path: &Path, err: &impl Fn(hdf5::Error) -> Error) -> Result<usize> {
    let bad = |reason: String| rsf::Error::File {
        path: show_path(path),
        action: "read the event catalogue",
        source: std::io::Error::new(std::io::ErrorKind::InvalidData, reason),
    };
    let read = std::fs::read(path).map_err(|source| rsf::Error::File {
        path: show_path(path),
        action: "read",
        source,
    })?;
    let mut lines = csv_lines(&read, 0, 1, true);
    let names: Vec<String> = match lines.next() {
        Some(Ok(header)) => header.fields.iter().map(str::to_owned).collect(),
        Some(Err((line, reason))) => return Err(bad(format!("line {line}: {reason}")).into()),
        None => return Err(bad("it has no header line".into()).into()),
    };
    let mut columns = vec![Vec::new(); names.len()];
    for row in lines {
        let row = row.map_err(|(line, reason)| bad(format!("line {line}: {reason}")))?;
        if row.fields.len() != names.len() {
            return Err(bad(format!(
                "line {}: {} fields under a header of {}",
                row.line,
                row.fields.len(),
                names.len()
            ))
            .into());
        }
        for (column, field) in columns.iter_mut().zip(row.fields.iter()) {
            let x: f64 = field.parse().map_err(|_| {
                bad(format!(
                    "line {}: `{}` is not a number",
                    row.line,
                    rsf_numeric::excerpt(field)
                ))
            })?;
            column.push(x);
        }
    }
    let group = file.create_group("events").map_err(err)?;
    text(&group, "source", "the run's event catalogue, events.csv").map_err(err)?;
    for (name, values) in names.iter().zip(&columns) {
        group
            .new_dataset_builder()
            .with_data(view(values, &[values.len()]))
            .create(name.as_str())
            .map_err(err)?;
    }
    Ok(columns.first().map_or(0, Vec::len))
}

/// An [`Observer`] that writes the HDF5 file of a SEAS run's series
/// ([`write_seas_series`]) into its folder at the end of every run call
/// ([`Observer::finish`]): put it **after** the SEAS output (`rsf_seas::SeasOutput`,
/// `SeasBp5Output`, `SeasBp6Output`), whose `finish` completes the files it reads. It does
/// nothing per step (and reads nothing of the volume).
///
/// ```no_run
/// # fn run(
/// #     mut ode: rsf_scenes::SeasBp1FaultOde,
/// #     mut output: rsf_seas::SeasOutput<rsf::friction::AsinhLaw>,
/// # ) -> Result<(), Box<dyn std::error::Error>> {
/// use rsf::observe::FileMode;
/// use rsf::{Observer, Until};
/// let mut series = rsf_hdf5::SeasSeries::new("out/bp1", FileMode::Create)?;
/// let mut observers: [&mut dyn Observer<2, 1>; 2] = [&mut output, &mut series];
/// ode.run_until(Until::Time(3.15e9), &mut observers)?; // out/bp1/seas.h5
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone)]
pub struct SeasSeries {
    dir: PathBuf,
    path: PathBuf,
}

impl SeasSeries {
    /// The series of the SEAS run in the folder `dir`, into `dir/`[`SEAS_SERIES_FILE`].
    ///
    /// # Errors
    /// For [`FileMode::Create`], [`rsf::Error::FileExists`] (as [`Error::Rsf`]) if that
    /// file exists and is not empty; [`FileMode::Overwrite`] replaces it and
    /// [`FileMode::Resume`] rewrites it (it is rebuilt from the files at every `finish`).
    pub fn new(dir: impl Into<PathBuf>, mode: FileMode) -> Result<Self> {
        let dir = dir.into();
        let path = dir.join(SEAS_SERIES_FILE);
        if mode == FileMode::Create {
            refuse_existing(&path)?;
        }
        Ok(Self { dir, path })
    }

    /// The HDF5 file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl<const D: usize, const C: usize> Observer<D, C> for SeasSeries {
    fn observe(&mut self, _: &StepView<'_, D, C>) -> rsf::Result<Flow> {
        Ok(Flow::Continue(()))
    }

    fn finish(&mut self) -> rsf::Result<()> {
        write_seas_series(&self.dir, &self.path)?;
        Ok(())
    }

    fn name(&self) -> String {
        format!("SEAS series {}", self.path.display())
    }

    fn reads_volume(&self) -> bool {
        false
    }
}
