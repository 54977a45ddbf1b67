//! The run folder of an example: refused before anything is written if it holds another
//! run's files (unless `--overwrite`), checked writable before the first step, and on
//! `--resume` checked to belong to the checkpoint and the scene before any file is cut
//! (docs/reliability.md).

use std::path::{Path, PathBuf};

use rsf::{
    Checkpoint, Checkpointer, Error, FileMode, Fingerprint, Flow, Observer, SliderScene, StepView,
    TimeStep,
};

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
    /// Refuse to start a run whose output is estimated above this many gigabytes (for
    /// adaptive steps without `--max-steps`: stop the run at the step count whose output
    /// fits, with a checkpoint to resume from).
    #[arg(long, default_value_t = 10.0, value_name = "GB")]
    pub max_output_gb: f64,
    /// Stop the run after this many steps in total (across resumes), writing a checkpoint
    /// to continue from with a larger value; bounds the output of adaptive runs.
    #[arg(long, value_name = "N")]
    pub max_steps: Option<u64>,
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
/// [`Error::InvalidParameter`] named `name` (e.g. `steps`) with the estimate and how to
/// override it.
pub fn check_output_size(estimate_bytes: f64, max_gb: f64, name: &str) -> rsf::Result<()> {
    if estimate_bytes <= max_gb * 1e9 {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name: name.into(),
            reason: format!(
                "the output of this run is estimated at {:.3} GB, above the limit of {max_gb} \
                 GB: use fewer steps, or raise --max-output-gb if the disk holds it",
                estimate_bytes / 1e9
            ),
        })
    }
}

/// Bytes of one row of a [`PointSeries`](rsf::PointSeries) file (2-D: 15 columns, ≈ 190
/// bytes; rounded up).
pub const SERIES_ROW_BYTES: f64 = 200.0;

/// Bytes of one node's row of a [`FrictionalProfile`](rsf::FrictionalProfile) file (≈ 90
/// bytes; rounded up).
pub const PROFILE_ROW_BYTES: f64 = 100.0;

/// An upper bound on the number of steps of a run of `scene` that end in `(t0, t1]` (s):
/// fixed steps `⌈N (t1 − t0) / T⌉ + 1`; adaptive steps `⌈(t1 − t0) / tau_min_s⌉ + 2` — every
/// step the controller chooses is at least `tau_min_s`, and only a step shortened to land
/// on the end of the loading ramp or on `T` is shorter (one each).
pub fn steps_bound(scene: &SliderScene, (t0, t1): (f64, f64)) -> f64 {
    let span = (t1 - t0).max(0.0);
    match scene.time_step {
        TimeStep::Fixed {} => (span / scene.tau()).ceil() + 1.0,
        TimeStep::Adaptive(a) => (span / (a.tau_min_s * (1.0 - 1e-12))).ceil() + 2.0,
    }
}

/// The step cap of a run of `scene` writing or holding `bytes_per_step` bytes per accepted
/// step (docs/reliability.md): `max_steps` if given (refused if even that does not fit in
/// `max_gb` gigabytes), none if [`steps_bound`] steps fit, else for adaptive steps the
/// count that fits.
///
/// # Errors
/// [`Error::InvalidParameter`] named `max_output_gb` (not positive and finite),
/// `max_steps` (0, or its output above `max_gb`) or `steps` (fixed steps above `max_gb`).
pub fn step_cap(
    scene: &SliderScene,
    bytes_per_step: f64,
    max_steps: Option<u64>,
    max_gb: f64,
) -> rsf::Result<Option<u64>> {
    if !(max_gb.is_finite() && max_gb > 0.0) {
        return Err(Error::InvalidParameter {
            name: "max_output_gb".into(),
            reason: format!("{max_gb} GB: must be positive and finite"),
        });
    }
    let bound = steps_bound(scene, (0.0, scene.end_time_s));
    match max_steps {
        Some(0) => Err(Error::InvalidParameter {
            name: "max_steps".into(),
            reason: "0 steps: must be at least 1".into(),
        }),
        Some(m) => check_output_size(bound.min(m as f64) * bytes_per_step, max_gb, "max_steps")
            .map(|()| Some(m)),
        None if bound * bytes_per_step <= max_gb * 1e9 => Ok(None),
        None if matches!(scene.time_step, TimeStep::Adaptive(_)) => Ok(Some(
            ((max_gb * 1e9 / bytes_per_step).floor() as u64).max(1),
        )),
        None => check_output_size(bound * bytes_per_step, max_gb, "steps").map(|()| None),
    }
}

/// The output plan of a slider run: the bound on its output and the step cap to enforce.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputPlan {
    /// Upper bound on the bytes the run writes (time series, profile window, map).
    pub bytes: f64,
    /// Stop after this many steps in total ([`StepCap`]), if any.
    pub step_cap: Option<u64>,
}

/// Plans the output of a slider run with `nodes` frictional nodes, the profile `window`,
/// a map of `map_samples` samples, at most `max_steps` steps (if given) and `max_gb`
/// gigabytes. The bound: [`steps_bound`] rows of the time series (at most `max_steps`),
/// [`steps_bound`] of the window plus the map's samples, each times `nodes` profile rows.
/// A run with a bound above `max_gb` is refused — except an adaptive run without
/// `max_steps`, whose honest bound (`T / tau_min_s` rows) is usually far above any disk:
/// it gets the step cap whose output fits in `max_gb` (the run stops there, resumable).
///
/// # Errors
/// [`Error::InvalidParameter`] named `steps` (fixed steps) or `max_steps` with the
/// estimate and how to override it.
pub fn plan_output(
    scene: &SliderScene,
    window: (f64, f64),
    nodes: usize,
    map_samples: usize,
    max_steps: Option<u64>,
    max_gb: f64,
) -> rsf::Result<OutputPlan> {
    let cap = |rows: f64| max_steps.map_or(rows, |m| rows.min(m as f64));
    let nodes = nodes as f64;
    let map_rows = (map_samples + 1) as f64 * nodes;
    let bytes = cap(steps_bound(scene, (0.0, scene.end_time_s))) * SERIES_ROW_BYTES
        + (cap(steps_bound(scene, window)) * nodes + map_rows) * PROFILE_ROW_BYTES;
    let budget = max_gb * 1e9;
    let adaptive = matches!(scene.time_step, TimeStep::Adaptive(_));
    if bytes > budget && adaptive && max_steps.is_none() {
        // Every step in the window (the worst case): the largest count that fits.
        let per_step = SERIES_ROW_BYTES + nodes * PROFILE_ROW_BYTES;
        let fit = ((budget - map_rows * PROFILE_ROW_BYTES) / per_step).floor();
        if fit >= 1.0 {
            return Ok(OutputPlan {
                bytes: fit * per_step + map_rows * PROFILE_ROW_BYTES,
                step_cap: Some(fit as u64),
            });
        }
    }
    let name = if max_steps.is_some() {
        "max_steps"
    } else {
        "steps"
    };
    check_output_size(bytes, max_gb, name)?;
    Ok(OutputPlan {
        bytes,
        step_cap: max_steps,
    })
}

/// Stops a run after `cap` steps in total (the step index of the state, so across
/// resumes), writing a checkpoint of that step with its [`Checkpointer`] first (if it has
/// one). Put it after the observers that write files. [`reached`](Self::reached) tells
/// whether it stopped the run.
#[derive(Debug, Clone)]
pub struct StepCap {
    cap: u64,
    checkpointer: Option<Checkpointer>,
    reached: Option<(usize, f64)>,
}

impl StepCap {
    /// Stops after step `cap`, checkpointing with `checkpointer`.
    pub fn new(cap: u64, checkpointer: Checkpointer) -> Self {
        Self {
            cap,
            checkpointer: Some(checkpointer),
            reached: None,
        }
    }

    /// Stops after step `cap` without a checkpoint (a run that cannot be resumed, whose
    /// files are written at its end).
    pub fn without_checkpoint(cap: u64) -> Self {
        Self {
            cap,
            checkpointer: None,
            reached: None,
        }
    }

    /// The step and time (s) at which the cap stopped the run, if it did.
    pub fn reached(&self) -> Option<(usize, f64)> {
        self.reached
    }

    /// The error of a run stopped by the cap: names `--max-steps`, the step, time and how
    /// to continue.
    pub fn error(&self, t_end: f64, checkpoint: &Path) -> Option<Error> {
        self.reached.map(|(step, t)| Error::InvalidParameter {
            name: "max_steps".into(),
            reason: format!(
                "the run reached its step cap of {} steps at t = {t:.6e} s (of T = {t_end:e} s): \
                 its files and `{}` are complete up to step {step}; continue with --resume \
                 and a larger --max-steps or --max-output-gb",
                self.cap,
                rsf_numeric::excerpt(&checkpoint.display().to_string())
            ),
        })
    }
}

impl<const D: usize> Observer<D> for StepCap {
    fn observe(&mut self, s: &StepView<'_, D>) -> rsf::Result<Flow> {
        if (s.report.step as u64) < self.cap {
            return Ok(Flow::Continue(()));
        }
        if let Some(c) = self.checkpointer.as_mut() {
            let _: Flow = c.observe(s)?;
        }
        self.reached = Some((s.report.step, s.report.time));
        Ok(Flow::Break(()))
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
        check_output_size(9e9, 10.0, "steps").unwrap();
        let e = check_output_size(2e11, 10.0, "steps").unwrap_err();
        assert!(e.to_string().contains("--max-output-gb"), "{e}");
    }

    /// The bound on the steps of adaptive runs is `T / tau_min_s` (not the initial step
    /// count), checked against a run: the steps taken never exceed it, even with a
    /// tolerance that drives τ to `tau_min_s`.
    #[test]
    fn adaptive_output_bounds_are_honest() {
        use rsf::{AdaptiveTimeStep, TimeStep};
        let adaptive = |tol: f64, tau_min_s: f64| SliderScene {
            level: 1,
            steps: 10,
            end_time_s: 0.05,
            loading_velocity_m_per_s: 1e-2,
            ramp_fraction: 0.5,
            time_step: TimeStep::Adaptive(AdaptiveTimeStep {
                tau_min_s,
                ..AdaptiveTimeStep::new(tol)
            }),
            ..SliderScene::default()
        };
        for (tol, tau_min) in [(1e-3, 1e-4), (1e-12, 2e-4), (0.5, 1e-3)] {
            let scene = adaptive(tol, tau_min);
            let bound = super::steps_bound(&scene, (0.0, scene.end_time_s));
            let mut sim = scene.build().unwrap();
            let run = sim.run_until(rsf::Until::Time(scene.end_time_s), &mut []);
            let steps = sim.state().step as f64;
            assert!(
                steps <= bound,
                "tol {tol:e}, tau_min {tau_min:e}: {steps} steps > bound {bound} ({run:?})"
            );
            assert!(
                bound >= scene.end_time_s / tau_min,
                "the bound is T / tau_min, not the initial N"
            );
        }
        // Fixed steps: the bound is N + 1 (and the window's share).
        let fixed = SliderScene {
            steps: 1000,
            ..SliderScene::default()
        };
        assert_eq!(super::steps_bound(&fixed, (0.0, fixed.end_time_s)), 1001.0);
        // The paper's default adaptive run: T / tau_min = 1.5e10 rows would be refused;
        // instead it gets a cap that fits in the budget, and explicit caps are checked.
        let scene = SliderScene {
            time_step: TimeStep::Adaptive(AdaptiveTimeStep::new(1e-3)),
            ..SliderScene::default()
        };
        let window = (0.6725 * 15.0, 0.6775 * 15.0);
        let plan = super::plan_output(&scene, window, 81, 600, None, 10.0).unwrap();
        let cap = plan.step_cap.expect("a cap");
        assert!(plan.bytes <= 10e9, "{plan:?}");
        assert!(cap > 1_000_000, "{cap}");
        let e = super::plan_output(&scene, window, 81, 600, Some(1e9 as u64), 10.0).unwrap_err();
        assert!(e.to_string().contains("`max_steps`"), "{e}");
        let ok = super::plan_output(&scene, window, 81, 600, Some(100_000), 10.0).unwrap();
        assert_eq!(ok.step_cap, Some(100_000));
        // Fixed steps above the budget are refused naming `steps`.
        let huge = SliderScene {
            steps: 1_000_000_000,
            ..SliderScene::default()
        };
        let e = super::plan_output(&huge, window, 81, 600, None, 10.0).unwrap_err();
        assert!(e.to_string().contains("`steps`"), "{e}");
    }

    /// The per-step bound of a run that keeps a record of every step (`long_run`): the
    /// closed forms of the bound (T / tau_min_s + 2 adaptive steps, N + 1 fixed ones).
    #[test]
    fn per_step_records_are_bounded_before_the_run() {
        let adaptive = SliderScene {
            end_time_s: 200.0,
            time_step: rsf::TimeStep::Adaptive(rsf::AdaptiveTimeStep::new(1e-3)),
            ..SliderScene::default()
        };
        let rsf::TimeStep::Adaptive(a) = adaptive.time_step else {
            unreachable!()
        };
        // 200 s / tau_min_s steps of 150 bytes do not fit in 10 GB: capped at what fits.
        assert!(200.0 / a.tau_min_s * 150.0 > 10e9);
        let cap = super::step_cap(&adaptive, 150.0, None, 10.0).unwrap();
        assert_eq!(cap, Some((10e9 / 150.0) as u64));
        // An explicit cap that fits is kept; one that does not names max_steps.
        assert_eq!(
            super::step_cap(&adaptive, 150.0, Some(1000), 10.0).unwrap(),
            Some(1000)
        );
        for bad in [Some(0), Some(1_000_000_000_000)] {
            let e = super::step_cap(&adaptive, 150.0, bad, 10.0).unwrap_err();
            assert!(e.to_string().contains("max_steps"), "{e}");
        }
        // Fixed steps: N + 1 rows; 1e12 steps refused by name, 1e4 steps need no cap.
        let fixed = |steps| SliderScene {
            steps,
            ..SliderScene::default()
        };
        assert_eq!(
            super::step_cap(&fixed(10_000), 150.0, None, 10.0).unwrap(),
            None
        );
        let e = super::step_cap(&fixed(1_000_000_000_000), 150.0, None, 10.0).unwrap_err();
        assert!(e.to_string().contains("`steps`"), "{e}");
        // 10 GB hold 66 666 666 steps of 150 bytes: 66 666 665 fixed steps (+1) fit, one more does not.
        assert!(super::step_cap(&fixed(66_666_665), 150.0, None, 10.0).is_ok());
        assert!(super::step_cap(&fixed(66_666_667), 150.0, None, 10.0).is_err());
        for gb in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = super::step_cap(&fixed(10), 150.0, None, gb).unwrap_err();
            assert!(e.to_string().contains("max_output_gb"), "{e}");
        }
    }
}
