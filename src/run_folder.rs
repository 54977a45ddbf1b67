//! The run folder of an example: refused before anything is written if it holds another
//! run's files (unless `--overwrite`), checked writable before the first step, and on
//! `--resume` checked to belong to the checkpoint and the scene before any file is cut
//! (docs/reliability.md).

use std::path::{Path, PathBuf};

use rsf::{Checkpoint, Error, FileMode, Fingerprint};

/// The flags of a run folder: how to treat existing files, deliberate changes on resume
/// and the bound on the output size.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct FolderArgs {
    /// Replace the files of an earlier run in the output folder (without it, a folder
    /// holding another run's files is refused and left untouched).
    #[arg(long)]
    pub overwrite: bool,
    /// On `--resume`, accept a checkpoint whose fingerprint differs in these scene fields
    /// (comma separated, e.g. `end_time_s`): a deliberate change of the run.
    #[arg(long, value_delimiter = ',', value_name = "FIELD,…")]
    pub allow_change: Vec<String>,
    /// Refuse to start a run whose output is estimated above this many gigabytes.
    #[arg(long, default_value_t = 10.0, value_name = "GB")]
    pub max_output_gb: f64,
}

/// The output folder of a run and the names of the files a run writes there.
#[derive(Debug, Clone)]
pub struct RunFolder {
    /// The folder.
    pub dir: PathBuf,
    /// The files (names inside `dir`) that belong to a run.
    pub outputs: Vec<&'static str>,
}

/// [`Error::File`] for `action` on `path`.
fn io_error<'a>(action: &'static str, path: &'a Path) -> impl Fn(std::io::Error) -> Error + 'a {
    move |source| Error::File {
        path: rsf_numeric::excerpt(&path.display().to_string()),
        action,
        source,
    }
}

impl RunFolder {
    /// The folder `dir` of a run writing `outputs`.
    pub fn new(dir: impl Into<PathBuf>, outputs: &[&'static str]) -> Self {
        Self {
            dir: dir.into(),
            outputs: outputs.to_vec(),
        }
    }

    /// Path of the output `name`.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Prepares the folder before anything is computed: creates it, checks that it can be
    /// written (a probe file is created and removed), that no output name is a folder,
    /// and — for a new run (`resume` false) — that it holds none of the outputs unless
    /// `overwrite` (then the earlier checkpoint and summary are removed, so that they
    /// cannot be mistaken for this run's). Returns the [`FileMode`] of new files.
    ///
    /// # Errors
    /// [`Error::File`] naming the folder (cannot create, not writable);
    /// [`Error::FileExists`] naming the files of another run. Nothing in the folder is
    /// changed on error.
    pub fn prepare(&self, resume: bool, overwrite: bool) -> rsf::Result<FileMode> {
        std::fs::create_dir_all(&self.dir)
            .map_err(io_error("create the output folder", &self.dir))?;
        let probe = self.dir.join(".rsf-write-probe");
        std::fs::write(&probe, b"").map_err(io_error("write into the output folder", &self.dir))?;
        std::fs::remove_file(&probe).map_err(io_error("remove the probe file of", &self.dir))?;
        let mut present = Vec::new();
        for name in &self.outputs {
            let path = self.path(name);
            match std::fs::metadata(&path) {
                Ok(m) if m.is_dir() => {
                    return Err(Error::FileExists {
                        path: rsf_numeric::excerpt(&path.display().to_string()),
                        reason: "it is a folder where the run writes a file".into(),
                    })
                }
                Ok(m) if m.len() > 0 => present.push(*name),
                _ => {}
            }
        }
        if resume || present.is_empty() {
            return Ok(FileMode::Create);
        }
        if !overwrite {
            return Err(Error::FileExists {
                path: rsf_numeric::excerpt(&self.dir.display().to_string()),
                reason: format!(
                    "it holds the files of another run ({}); pass --overwrite to replace \
                     them, --resume CHECKPOINT to continue that run, or another --out",
                    present.join(", ")
                ),
            });
        }
        for name in ["checkpoint.bin", "summary.json"] {
            let path = self.path(name);
            if present.contains(&name) {
                std::fs::remove_file(&path).map_err(io_error("remove", &path))?;
            }
        }
        Ok(FileMode::Overwrite)
    }
}

/// Reads the checkpoint `path` and checks that it continues a run of `fingerprint`
/// (fields in `allowed` may differ).
///
/// # Errors
/// [`Error::File`], [`Error::CheckpointCorrupt`] (never resumed),
/// [`Error::CheckpointMismatch`] naming the differing field.
pub fn read_checkpoint(
    path: &Path,
    fingerprint: &Fingerprint,
    allowed: &[String],
) -> rsf::Result<Checkpoint> {
    let c = Checkpoint::read(path)?;
    let allowed: Vec<&str> = allowed.iter().map(String::as_str).collect();
    c.fingerprint.check(fingerprint, &allowed)?;
    Ok(c)
}

/// Checks that the row of the checkpoint's step in the [`PointSeries`](rsf::PointSeries)
/// file `series` (at the node `node` of a `D`-dimensional model) shows the checkpoint's
/// time, displacement and velocity exactly as the series writes them: the folder's rows
/// and the checkpoint are of the same run. A checkpoint at step 0 has no row to compare.
///
/// # Errors
/// [`Error::Resume`] naming the file if the row is missing or differs; [`Error::File`].
pub fn check_series_row<const D: usize>(
    series: &Path,
    c: &Checkpoint,
    node: usize,
) -> rsf::Result<()> {
    let step = c.state.step;
    if step == 0 {
        return Ok(());
    }
    let fail = |reason: String| Error::Resume {
        path: rsf_numeric::excerpt(&series.display().to_string()),
        reason,
    };
    let text = std::fs::read_to_string(series).map_err(io_error("read", series))?;
    let want = step.to_string();
    let Some(row) = text
        .split_inclusive('\n')
        .filter(|l| l.ends_with('\n'))
        .map(|l| l.trim_end().split(',').collect::<Vec<_>>())
        .find(|f| f.get(6) == Some(&want.as_str()))
    else {
        return Err(fail(format!(
            "it has no row of the checkpoint's step {step}: the checkpoint is not of this \
             run folder"
        )));
    };
    let (u, v) = (&c.state.kinematics.u, &c.state.kinematics.v);
    let i = D * node;
    if u.len() < i + D || v.len() < i + D {
        return Err(fail(
            "the checkpoint has fewer nodes than the series' node".into(),
        ));
    }
    let mut expected = vec![
        (0, format!("{:.9e}", c.state.time)),
        (1, format!("{:.12e}", u[i])),
        (2, format!("{:.12e}", v[i])),
    ];
    for k in 1..D {
        expected.push((9 + 2 * (k - 1), format!("{:.12e}", u[i + k])));
        expected.push((10 + 2 * (k - 1), format!("{:.12e}", v[i + k])));
    }
    for (col, value) in expected {
        if row.get(col) != Some(&value.as_str()) {
            return Err(fail(format!(
                "its row of step {step} has `{}` in column {col}, the checkpoint gives \
                 `{value}`: the checkpoint belongs to another run (nothing was changed)",
                rsf_numeric::excerpt(row.get(col).unwrap_or(&"")),
            )));
        }
    }
    Ok(())
}

/// Refuses a run whose output is estimated above `max_gb` gigabytes.
///
/// # Errors
/// [`Error::InvalidParameter`] named `steps` with the estimate and how to override it.
pub fn check_output_size(estimate_bytes: f64, max_gb: f64) -> rsf::Result<()> {
    if estimate_bytes <= max_gb * 1e9 {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name: "steps".into(),
            reason: format!(
                "the output of this run is estimated at {:.3} GB, above the limit of {max_gb} \
                 GB: use fewer steps, or raise --max-output-gb if the disk holds it",
                estimate_bytes / 1e9
            ),
        })
    }
}

/// Checks a window `(t0, t1)` (s) named `name` against `[0, end_time]`.
///
/// # Errors
/// [`Error::InvalidParameter`] named `name` unless `0 ≤ t0 < t1 ≤ end_time`.
pub fn check_window(name: &str, (t0, t1): (f64, f64), end_time: f64) -> rsf::Result<()> {
    if t0 >= 0.0 && t0 < t1 && t1 <= end_time {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name: name.into(),
            reason: format!(
                "[{t0:e}, {t1:e}] s must lie inside [0, T] = [0, {end_time:e}] s with \
                 t0 < t1 (outside, it records nothing)"
            ),
        })
    }
}
