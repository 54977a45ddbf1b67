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

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;
    use std::path::{Path, PathBuf};

    use rsf::{Error, FileMode, SliderScene};

    use super::{check_output_size, check_series_row, check_window, read_checkpoint, RunFolder};

    const OUTPUTS: [&str; 3] = ["timeseries.csv", "checkpoint.bin", "summary.json"];

    fn temp_dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("rsf-run-folder-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.is_file())
            .map(|p| (p.clone(), std::fs::read(&p).unwrap()))
            .collect()
    }

    #[test]
    fn a_folder_of_another_run_is_refused_unless_overwritten() {
        let dir = temp_dir("occupied");
        let folder = RunFolder::new(&dir, &OUTPUTS);
        assert_eq!(folder.prepare(false, false).unwrap(), FileMode::Create);
        std::fs::write(dir.join("timeseries.csv"), "rows").unwrap();
        std::fs::write(dir.join("checkpoint.bin"), "state").unwrap();
        let before = snapshot(&dir);
        let e = folder.prepare(false, false).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, Error::FileExists { .. }), "{msg}");
        assert!(
            msg.contains("timeseries.csv") && msg.contains("checkpoint.bin"),
            "{msg}"
        );
        assert_eq!(snapshot(&dir), before);
        // A resume leaves the files to the checks of the resume.
        assert_eq!(folder.prepare(true, false).unwrap(), FileMode::Create);
        assert_eq!(snapshot(&dir), before);
        // --overwrite: the old checkpoint cannot be mistaken for the new run's.
        assert_eq!(folder.prepare(false, true).unwrap(), FileMode::Overwrite);
        assert!(!dir.join("checkpoint.bin").exists());
    }

    #[test]
    fn an_output_that_is_a_folder_or_an_out_that_is_a_file_is_refused_first() {
        let dir = temp_dir("shapes");
        std::fs::create_dir_all(dir.join("summary.json")).unwrap();
        let e = RunFolder::new(&dir, &OUTPUTS)
            .prepare(false, true)
            .unwrap_err();
        assert!(e.to_string().contains("summary.json"), "{e}");
        assert!(dir.join("summary.json").is_dir());
        let file = dir.join("a-file");
        std::fs::write(&file, "x").unwrap();
        let e = RunFolder::new(&file, &OUTPUTS)
            .prepare(false, false)
            .unwrap_err();
        let Error::File { path, action, .. } = &e else {
            panic!("{e}")
        };
        assert!(
            path.ends_with("a-file") && action.contains("output folder"),
            "{e}"
        );
        assert_eq!(std::fs::read(&file).unwrap(), b"x");
    }

    #[test]
    fn a_checkpoint_is_checked_against_the_scene_and_the_rows() {
        let dir = temp_dir("rows");
        let scene = SliderScene {
            level: 1,
            steps: 10,
            end_time_s: 0.01,
            ..SliderScene::default()
        };
        let mut sim = scene.build().unwrap();
        let x0 = sim.model().nearest_node(&rsf::SLIDER_CENTRE).unwrap();
        let series = dir.join("timeseries.csv");
        let mut obs = rsf::PointSeries::new(&series, sim.model(), x0, FileMode::Create).unwrap();
        sim.run(4, &mut [&mut obs]).unwrap();
        drop(obs);
        let mut c = sim.checkpoint();
        c.fingerprint = scene.fingerprint();
        let path = dir.join("checkpoint.bin");
        c.write(&path).unwrap();
        let before = snapshot(&dir);
        let c = read_checkpoint(&path, &scene.fingerprint(), &[]).unwrap();
        check_series_row::<2>(&series, &c, x0).unwrap();
        // Another node's values (as a checkpoint of another run would have) are refused.
        let e = check_series_row::<2>(&series, &c, x0 + 1).unwrap_err();
        assert!(e.to_string().contains("another run"), "{e}");
        let mut later = c.clone();
        later.state.step = 9;
        assert!(check_series_row::<2>(&series, &later, x0).is_err());
        let other = SliderScene { steps: 20, ..scene };
        let e = read_checkpoint(&path, &other.fingerprint(), &[]).unwrap_err();
        assert!(matches!(&e, Error::CheckpointMismatch { field, .. } if field == "steps"));
        read_checkpoint(&path, &other.fingerprint(), &["steps".into()]).unwrap();
        assert_eq!(snapshot(&dir), before);
    }

    #[test]
    fn windows_and_output_sizes_are_bounded() {
        check_window("window", (0.5, 1.0), 1.0).unwrap();
        for w in [(-0.1, 0.5), (0.5, 1.5), (0.5, 0.5), (f64::NAN, 0.5)] {
            let e = check_window("window", w, 1.0).unwrap_err();
            assert!(e.to_string().contains("`window`"), "{e}");
        }
        check_output_size(9e9, 10.0).unwrap();
        let e = check_output_size(2e11, 10.0).unwrap_err();
        assert!(e.to_string().contains("--max-output-gb"), "{e}");
    }
}
