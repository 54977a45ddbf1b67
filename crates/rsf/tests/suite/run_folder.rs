//! The run-folder procedure of the library (`rsf::run_folder`, docs/reliability.md): a
//! folder of another run or program refused and left byte-identical, resumes checked
//! before anything is cut (checkpoint, fingerprint, every file's continuation), output
//! bounds and step caps; resumes of the 3-D slider byte-identical to uninterrupted runs
//! (the SEAS output's: the crate rsf-seas's tests).

use std::path::{Path, PathBuf};

use crate::common::{slider, snapshot, within};
use rsf::observe::{FileMode, PointSeries};
use rsf::run_folder::RunFolder;
use rsf::run_folder::{check_output_size, check_window, read_checkpoint};
use rsf::Error;
use rsf_scenes::SliderScene;

const OUTPUTS: [&str; 3] = ["timeseries.csv", "checkpoint.bin", "summary.json"];

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rsf-run-folder-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn a_folder_of_another_run_is_refused_unless_overwritten() {
    let dir = temp_dir("occupied");
    let folder = RunFolder::new(&dir, "test_program", &OUTPUTS);
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
    let e = RunFolder::new(&dir, "test_program", &OUTPUTS)
        .prepare(false, true)
        .unwrap_err();
    assert!(e.to_string().contains("summary.json"), "{e}");
    assert!(dir.join("summary.json").is_dir());
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let e = RunFolder::new(&file, "test_program", &OUTPUTS)
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
        end_time_s: 0.01,
        ..slider(1, 10)
    };
    let mut sim = scene.build().unwrap();
    let x0 = sim
        .model()
        .nearest_node(&rsf_scenes::SLIDER_CENTRE)
        .unwrap();
    let series = dir.join("timeseries.csv");
    let mut obs = PointSeries::new(&series, sim.model(), x0, FileMode::Create).unwrap();
    sim.run(4, &mut [&mut obs]).unwrap();
    drop(obs);
    let mut c = sim.checkpoint();
    c.fingerprint = scene.fingerprint();
    let path = dir.join("checkpoint.bin");
    c.write(&path).unwrap();
    let before = snapshot(&dir);
    let c = read_checkpoint(&path, &scene.fingerprint(), &[]).unwrap();
    PointSeries::<2>::check_checkpoint_row(&series, &c, x0).unwrap();
    // Another node's values (as a checkpoint of another run would have) are refused.
    let e = PointSeries::<2>::check_checkpoint_row(&series, &c, x0 + 1).unwrap_err();
    assert!(e.to_string().contains("another run"), "{e}");
    let mut later = c.clone();
    later.state.step = 9;
    assert!(PointSeries::<2>::check_checkpoint_row(&series, &later, x0).is_err());
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
    use rsf_scenes::{AdaptiveTimeStep, TimeStep};
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
        let bound = rsf_scenes::steps_bound(&scene, (0.0, scene.end_time_s));
        let mut sim = scene.build().unwrap();
        let run = sim.run_until(within(scene.end_time_s), &mut []);
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
    assert_eq!(
        rsf_scenes::steps_bound(&fixed, (0.0, fixed.end_time_s)),
        1001.0
    );
    // The paper's default adaptive run: T / tau_min = 1.5e10 rows would be refused;
    // instead it gets a cap that fits in the budget, and explicit caps are checked.
    let scene = SliderScene {
        time_step: TimeStep::Adaptive(AdaptiveTimeStep::new(1e-3)),
        ..SliderScene::default()
    };
    let window = (0.6725 * 15.0, 0.6775 * 15.0);
    // The output plan of `scene` over `window` (81 nodes, 600 map samples) in a budget of
    // 10 GB with the step cap `max_steps`.
    let plan = |scene: &SliderScene, max_steps| {
        let limits = rsf_scenes::OutputLimits {
            max_steps,
            max_gb: 10.0,
        };
        rsf_scenes::plan_output(scene, window, 81, 600, limits)
    };
    let output = plan(&scene, None).unwrap();
    let cap = output.step_cap.expect("a cap");
    assert!(output.bytes <= 10e9, "{output:?}");
    assert!(cap > 1_000_000, "{cap}");
    let e = plan(&scene, Some(1e9 as u64)).unwrap_err();
    assert!(e.to_string().contains("`max_steps`"), "{e}");
    let ok = plan(&scene, Some(100_000)).unwrap();
    assert_eq!(ok.step_cap, Some(100_000));
    // Fixed steps above the budget are refused naming `steps`.
    let huge = SliderScene {
        steps: 1_000_000_000,
        ..SliderScene::default()
    };
    let e = plan(&huge, None).unwrap_err();
    assert!(e.to_string().contains("`steps`"), "{e}");
}

/// The per-step bound of a run that keeps a record of every step (`long_run`): the
/// closed forms of the bound (T / tau_min_s + 2 adaptive steps, N + 1 fixed ones).
#[test]
fn per_step_records_are_bounded_before_the_run() {
    let adaptive = SliderScene {
        end_time_s: 200.0,
        time_step: rsf_scenes::TimeStep::Adaptive(rsf_scenes::AdaptiveTimeStep::new(1e-3)),
        ..SliderScene::default()
    };
    let rsf_scenes::TimeStep::Adaptive(a) = adaptive.time_step else {
        unreachable!()
    };
    // 200 s / tau_min_s steps of 150 bytes do not fit in 10 GB: capped at what fits.
    assert!(200.0 / a.tau_min_s * 150.0 > 10e9);
    let cap = rsf_scenes::step_cap(&adaptive, 150.0, None, 10.0).unwrap();
    assert_eq!(cap, Some((10e9 / 150.0) as u64));
    // An explicit cap that fits is kept; one that does not names max_steps.
    assert_eq!(
        rsf_scenes::step_cap(&adaptive, 150.0, Some(1000), 10.0).unwrap(),
        Some(1000)
    );
    for bad in [Some(0), Some(1_000_000_000_000)] {
        let e = rsf_scenes::step_cap(&adaptive, 150.0, bad, 10.0).unwrap_err();
        assert!(e.to_string().contains("max_steps"), "{e}");
    }
    // Fixed steps: N + 1 rows; 1e12 steps refused by name, 1e4 steps need no cap.
    let fixed = |steps| SliderScene {
        steps,
        ..SliderScene::default()
    };
    assert_eq!(
        rsf_scenes::step_cap(&fixed(10_000), 150.0, None, 10.0).unwrap(),
        None
    );
    let e = rsf_scenes::step_cap(&fixed(1_000_000_000_000), 150.0, None, 10.0).unwrap_err();
    assert!(e.to_string().contains("`steps`"), "{e}");
    // 10 GB hold 66 666 666 steps of 150 bytes: 66 666 665 fixed steps (+1) fit, one more does not.
    assert!(rsf_scenes::step_cap(&fixed(66_666_665), 150.0, None, 10.0).is_ok());
    assert!(rsf_scenes::step_cap(&fixed(66_666_667), 150.0, None, 10.0).is_err());
    for gb in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = rsf_scenes::step_cap(&fixed(10), 150.0, None, gb).unwrap_err();
        assert!(e.to_string().contains("max_output_gb"), "{e}");
    }
}

/// The one output policy: an adaptive run that does not fit is capped at the largest step
/// count whose worst case fits (and one more step would not), a fixed-step run or a given
/// `max_steps` that does not fit is refused by name, a budget below one step is refused, and
/// an unbounded limit (`inf`) never caps.
#[test]
fn the_output_policy_caps_adaptive_runs_and_refuses_the_rest() {
    use rsf::run_folder::{output_plan, OutputEstimate};
    let estimate = |bytes, adaptive| OutputEstimate {
        bytes,
        fixed_bytes: 1e6,
        bytes_per_step: 300.0,
        adaptive,
    };
    // 1 GB: (1e9 − 1e6) / 300 = 3 330 000 steps fit.
    let plan = output_plan(estimate(f64::INFINITY, true), None, 1.0).unwrap();
    let cap = plan.step_cap.unwrap();
    assert_eq!(cap, ((1e9 - 1e6) / 300.0) as u64);
    assert!(1e6 + cap as f64 * 300.0 <= 1e9);
    assert!(1e6 + (cap + 1) as f64 * 300.0 > 1e9);
    assert_eq!(plan.bytes, 1e6 + cap as f64 * 300.0);
    // What fits runs to its end, uncapped (or with the given cap).
    let fits = output_plan(estimate(5e8, true), None, 1.0).unwrap();
    assert_eq!((fits.bytes, fits.step_cap), (5e8, None));
    assert_eq!(
        output_plan(estimate(5e8, true), Some(7), 1.0)
            .unwrap()
            .step_cap,
        Some(7)
    );
    // Refused by name: fixed steps, a given cap that does not fit, a budget below one step.
    let e = output_plan(estimate(2e9, false), None, 1.0).unwrap_err();
    assert!(e.to_string().contains("`steps`"), "{e}");
    let e = output_plan(estimate(2e9, true), Some(10_000_000), 1.0).unwrap_err();
    assert!(e.to_string().contains("`max_steps`"), "{e}");
    let e = output_plan(estimate(f64::INFINITY, true), None, 1e-3).unwrap_err();
    assert!(e.to_string().contains("`steps`"), "{e}");
    // No limit: no cap, even for an unbounded estimate.
    let free = output_plan(estimate(f64::INFINITY, true), None, f64::INFINITY).unwrap();
    assert_eq!(free.step_cap, None);
    for gb in [0.0, -1.0, f64::NAN] {
        let e = output_plan(estimate(1.0, true), None, gb).unwrap_err();
        assert!(e.to_string().contains("max_output_gb"), "{e}");
    }
}

/// A folder written by another program is refused — by its manifest, even where no file
/// name is shared — and left byte-identical; `--overwrite` replaces it.
#[test]
fn a_folder_of_another_program_is_refused_and_left_byte_identical() {
    let dir = temp_dir("other-program");
    let main_job = RunFolder::new(
        &dir,
        "pipping_slider",
        &["timeseries.csv", "checkpoint.bin", "summary.json"],
    );
    assert_eq!(main_job.prepare(false, false).unwrap(), FileMode::Create);
    for name in ["timeseries.csv", "checkpoint.bin", "summary.json"] {
        std::fs::write(dir.join(name), format!("{name} of the main job")).unwrap();
    }
    let before = snapshot(&dir);
    assert!(before.contains_key(&dir.join(rsf::run_folder::MANIFEST)));
    // A program with an overlapping file name (summary.json) and one with none.
    for outputs in [
        &["fltst_dp000", "devol.dat", "summary.json"][..],
        &["sweep.csv"][..],
    ] {
        let other = RunFolder::new(&dir, "seas_bp1", outputs);
        for resume in [false, true] {
            let e = other.prepare(resume, false).unwrap_err();
            let msg = e.to_string();
            assert!(matches!(e, Error::FileExists { .. }), "{msg}");
            assert!(msg.contains("pipping_slider"), "{msg}");
            assert_eq!(snapshot(&dir), before, "{msg}");
        }
        // A resume into another program's folder is refused even with --overwrite.
        assert!(other.prepare(true, true).is_err());
        assert_eq!(snapshot(&dir), before);
    }
    // --overwrite: the earlier run's files are gone, the manifest is the new program's.
    let other = RunFolder::new(&dir, "seas_bp1", &["devol.dat", "summary.json"]);
    assert_eq!(other.prepare(false, true).unwrap(), FileMode::Overwrite);
    for name in ["timeseries.csv", "checkpoint.bin", "summary.json"] {
        assert!(!dir.join(name).exists(), "{name}");
    }
    let manifest = std::fs::read_to_string(dir.join(rsf::run_folder::MANIFEST)).unwrap();
    assert!(manifest.starts_with("program=seas_bp1\n"), "{manifest}");
}

/// `--allow-change` accepts only fields of the run's fingerprint and lists them when
/// given another; the checkpoint is not even read then.
#[test]
fn allow_change_with_an_unknown_field_names_the_known_ones() {
    let scene = SliderScene {
        end_time_s: 0.01,
        ..slider(1, 10)
    };
    let fingerprint = scene.fingerprint().with("window", "0e0,1e-2");
    let missing = temp_dir("allow-change").join("no-checkpoint.bin");
    let e = read_checkpoint(&missing, &fingerprint, &["end_time".into()]).unwrap_err();
    let msg = e.to_string();
    assert!(
        matches!(&e, Error::InvalidParameter { name, .. } if name == "allow_change"),
        "{msg}"
    );
    for known in ["end_time_s", "steps", "window", "level", "format"] {
        assert!(msg.contains(known), "{known}: {msg}");
    }
    // Known fields pass the check (and then the missing file is the error).
    let e = read_checkpoint(
        &missing,
        &fingerprint,
        &["end_time_s".into(), "window".into()],
    )
    .unwrap_err();
    assert!(matches!(e, Error::File { .. }), "{e}");
}

/// The 3-D slider (level 0): checkpointed at step 5, "killed" at step 9, resumed from the
/// checkpoint through the library's procedure to step 12 — the time series and the
/// profile are byte-identical to an uninterrupted run's, and the fingerprint of the
/// 3-D scene refuses a checkpoint of another width.
#[test]
fn a_3d_slider_resumed_from_a_checkpoint_writes_byte_identical_files() {
    use rsf::observe::{Checkpointer, Every, FrictionalProfile, Interval};
    use rsf::Observer;
    use rsf_scenes::Slider3dScene;
    let scene = Slider3dScene {
        slider: SliderScene {
            level: 0,
            steps: 1000,
            end_time_s: 1.5,
            ..Slider3dScene::default().slider
        },
        ..Slider3dScene::default()
    };
    const OUT: [&str; 3] = ["timeseries.csv", "profile.csv", "checkpoint.bin"];
    let fingerprint = scene.fingerprint();
    assert_eq!(fingerprint.get("width_m"), Some("1.0"));
    // Runs `steps` steps into `dir` (from the checkpoint `resume`, if given), checkpointing
    // every 5 steps.
    let run = |dir: &Path, steps: usize, resume: Option<&Path>| -> rsf::Result<()> {
        let folder = RunFolder::new(dir, "slider_3d_test", &OUT);
        let fresh = folder.prepare(resume.is_some(), false)?;
        let mut sim = scene.build()?;
        let x0 = sim.model().nearest_node(&scene.centre())?;
        let (series, profile) = (folder.path("timeseries.csv"), folder.path("profile.csv"));
        let mode = match resume {
            Some(path) => {
                let c = read_checkpoint(path, &fingerprint, &[])?;
                PointSeries::<3>::check_resume(&series, c.state.step)?;
                PointSeries::<3>::check_checkpoint_row(&series, &c, x0)?;
                FrictionalProfile::<3>::check_resume(&profile, c.state.step)?;
                sim.restore(&c)?;
                FileMode::Resume { step: c.state.step }
            }
            None => fresh,
        };
        let mut s = PointSeries::new(&series, sim.model(), x0, mode)?;
        let mut p = FrictionalProfile::new(&profile, (0.0, f64::INFINITY), mode)?;
        let mut c = Every::new(
            Interval::Steps(5),
            Checkpointer::new(folder.path("checkpoint.bin")).fingerprint(fingerprint.clone()),
        )?;
        let left = steps - sim.state().step;
        let mut observers: [&mut dyn Observer<3>; 3] = [&mut s, &mut p, &mut c];
        sim.run(left, &mut observers).map_err(|e| e.error)?;
        Ok(())
    };
    let (whole, parts) = (temp_dir("3d-whole"), temp_dir("3d-parts"));
    run(&whole, 12, None).unwrap();
    run(&parts, 9, None).unwrap();
    let checkpoint = parts.join("checkpoint.bin");
    let saved = temp_dir("3d-saved").join("checkpoint.bin");
    std::fs::copy(&checkpoint, &saved).unwrap();
    assert_eq!(rsf::Checkpoint::read(&saved).unwrap().state.step, 5);
    // Another width is another run.
    let wider = Slider3dScene {
        width_m: 2.0,
        ..scene.clone()
    };
    let e = read_checkpoint(&saved, &wider.fingerprint(), &[]).unwrap_err();
    assert!(
        matches!(&e, Error::CheckpointMismatch { field, .. } if field == "width_m"),
        "{e}"
    );
    run(&parts, 12, Some(&saved)).unwrap();
    for name in ["timeseries.csv", "profile.csv"] {
        let (a, b) = (
            std::fs::read(whole.join(name)).unwrap(),
            std::fs::read(parts.join(name)).unwrap(),
        );
        assert!(a == b, "{name} differs after the resume");
    }
    assert_eq!(
        PointSeries::<3>::read(&parts.join("timeseries.csv"))
            .unwrap()
            .len(),
        12
    );
}

/// A checkpoint names its run (the run id of the folder it was written into): a resume
/// from a checkpoint of **another** run of the same program into a folder is refused —
/// before anything is cut, the folder byte-identical — unless `--overwrite`, which gives
/// the folder to the checkpoint's run; its own folder, a copy of the checkpoint, a fresh
/// folder and a checkpoint of an earlier format (run unknown) resume as before (issue 74).
#[test]
fn a_resume_into_another_runs_folder_is_refused_unless_overwritten() {
    use rsf::observe::Checkpointer;
    let fingerprint = |dx: f64| {
        rsf::checkpoint::Fingerprint::default()
            .with("format", rsf::checkpoint::CHECKPOINT_FORMAT)
            .with("dx", dx)
    };
    let dir = temp_dir("identity");
    let (a, b) = (dir.join("a"), dir.join("b"));
    let checkpoint = |folder: &Path| {
        let state = rsf::SimulationState {
            step: 7,
            time: 0.7,
            tau: 0.1,
            time_origin: (0, 0.0),
            kinematics: rsf::time::Kinematics {
                u: vec![0.0; 2],
                v: vec![0.0; 2],
                a: vec![0.0; 2],
            },
            alpha: vec![0.0],
            controller: None,
        };
        let c = rsf::Checkpoint::new(2, state);
        Checkpointer::new(folder.join("checkpoint.bin"))
            .fingerprint(fingerprint(1.0))
            .write(c)
            .unwrap();
        folder.join("checkpoint.bin")
    };
    // Two runs of one program, each with its files and checkpoint.
    let run_a = RunFolder::new(&a, "test_program", &OUTPUTS).command("test_program --out a");
    let run_b = RunFolder::new(&b, "test_program", &OUTPUTS).command("test_program --out b");
    for (folder, dir) in [(&run_a, &a), (&run_b, &b)] {
        assert_eq!(folder.prepare(false, false).unwrap(), FileMode::Create);
        std::fs::write(
            dir.join("timeseries.csv"),
            format!("rows of {}", dir.display()),
        )
        .unwrap();
        checkpoint(dir);
    }
    let id_a = rsf::run_folder::run_id(&a).unwrap();
    let id_b = rsf::run_folder::run_id(&b).unwrap();
    assert_ne!(id_a, id_b);
    assert_eq!(id_a.len(), 32);
    let ckpt_a = a.join("checkpoint.bin");
    assert_eq!(rsf::Checkpoint::read(&ckpt_a).unwrap().run_id, id_a);
    // A's checkpoint into B: refused, naming B's run, and B untouched.
    let before = snapshot(&b);
    let e = run_b.prepare_resume(&ckpt_a, false).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, Error::Resume { .. }), "{msg}");
    assert!(
        msg.contains("another run")
            && msg.contains("test_program --out b")
            && msg.contains(&id_b[..12])
            && msg.contains(&id_a[..12])
            && msg.contains("--overwrite"),
        "{msg}"
    );
    assert_eq!(snapshot(&b), before);
    // Into its own folder, and from a copy elsewhere: accepted, the run id kept.
    assert_eq!(
        run_a.prepare_resume(&ckpt_a, false).unwrap(),
        FileMode::Create
    );
    let copy = dir.join("saved.bin");
    std::fs::copy(&ckpt_a, &copy).unwrap();
    assert_eq!(
        run_a.prepare_resume(&copy, false).unwrap(),
        FileMode::Create
    );
    assert_eq!(rsf::run_folder::run_id(&a).unwrap(), id_a);
    // --overwrite where the checkpoint is the folder's own run: nothing to replace.
    let e = run_a.prepare_resume(&ckpt_a, true).unwrap_err();
    assert!(e.to_string().contains("--overwrite"), "{e}");
    // A fresh folder takes the checkpoint's run.
    let fresh = RunFolder::new(dir.join("c"), "test_program", &OUTPUTS);
    assert_eq!(
        fresh.prepare_resume(&ckpt_a, false).unwrap(),
        FileMode::Create
    );
    // It names the run once the run has checked its files (issue 87: a refused resume
    // leaves no claim).
    assert_eq!(rsf::run_folder::run_id(&dir.join("c")), None);
    rsf::run_folder::adopt_run_id(&dir.join("c"), &id_a).unwrap();
    assert_eq!(rsf::run_folder::run_id(&dir.join("c")).unwrap(), id_a);
    // A checkpoint of an earlier format (no run id) cannot be told apart: accepted.
    let mut unknown = rsf::Checkpoint::read(&ckpt_a).unwrap();
    unknown.run_id.clear();
    let old = dir.join("old.bin");
    unknown.write(&old).unwrap();
    assert_eq!(run_b.prepare_resume(&old, false).unwrap(), FileMode::Create);
    assert_eq!(rsf::run_folder::run_id(&b).unwrap(), id_b);
    // --overwrite with a checkpoint away from its run's folder: B cannot be rewritten from
    // A's files, so it is refused, naming why, B untouched (issue 87: never a mix).
    let before = snapshot(&b);
    let e = run_b.prepare_resume(&copy, true).unwrap_err().to_string();
    assert!(
        e.contains("only whole") && e.contains("no run manifest"),
        "{e}"
    );
    assert_eq!(snapshot(&b), before);
    // --overwrite with a checkpoint of other parameters than the run's (a front end that
    // knows its fingerprint before the work): refused by the field that differs before B
    // changes (issue 87: B was given to A's run, then the session refused the checkpoint).
    std::fs::write(b.join("summary.json"), "b's summary").unwrap();
    let before = snapshot(&b);
    let e = run_b
        .clone()
        .expecting(fingerprint(2.0), &[])
        .prepare_resume(&ckpt_a, true)
        .unwrap_err();
    assert!(matches!(e, Error::CheckpointMismatch { .. }), "{e}");
    assert!(e.to_string().contains("dx"), "{e}");
    assert_eq!(snapshot(&b), before);
    // A field allowed to change that the run has not: refused as well, B untouched.
    let unknown = run_b
        .clone()
        .expecting(fingerprint(1.0), &["no_such_field".to_owned()])
        .prepare_resume(&ckpt_a, true)
        .unwrap_err();
    assert!(unknown.to_string().contains("no_such_field"), "{unknown}");
    assert_eq!(snapshot(&b), before);
    // --overwrite gives B to A's run whole: B's files are A's (its checkpoint and summary
    // not copied), none of B's run is left.
    assert_eq!(
        run_b
            .clone()
            .expecting(fingerprint(1.0), &[])
            .prepare_resume(&ckpt_a, true)
            .unwrap(),
        FileMode::Create
    );
    assert_eq!(rsf::run_folder::run_id(&b).unwrap(), id_a);
    assert_eq!(
        std::fs::read(b.join("timeseries.csv")).unwrap(),
        std::fs::read(a.join("timeseries.csv")).unwrap()
    );
    assert!(!b.join("checkpoint.bin").exists() && !b.join("summary.json").exists());
    // A new run into a folder gets a new id.
    std::fs::remove_file(a.join("timeseries.csv")).unwrap();
    std::fs::remove_file(&ckpt_a).unwrap();
    assert_eq!(run_a.prepare(false, false).unwrap(), FileMode::Create);
    assert_ne!(rsf::run_folder::run_id(&a).unwrap(), id_a);
}
