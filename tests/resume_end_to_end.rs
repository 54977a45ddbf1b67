//! The `pipping_slider` example end to end, through the function its `main` calls
//! (`rsf_programs::pipping_slider::run` with the flags parsed as from a command line):
//!
//! - a run stopped after N steps (`--max-steps`) and resumed writes files byte-identical
//!   to an uninterrupted run's (every CSV and PNG; `summary.json` up to wall times);
//! - so does a run "killed" between checkpoints: rows written after the last checkpoint
//!   are cut on resume;
//! - a mistaken re-run without `--resume` into the half-finished folder is refused, and so
//!   is a resume with the checkpoint of another run (another scene, or another run's folder):
//!   every file of the folder stays byte-identical.
//!
//! Level 1, 1000 fixed steps over the paper's 15 s (8 slip events): seconds in a debug build.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use clap::Parser;
use rsf_programs::pipping_slider::{run, Cli};

/// A fresh temporary folder.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rsf-e2e-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Every file of `dir` with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect()
}

/// Runs the example with the scene flags and `extra` into `out`.
fn example(out: &Path, extra: &[&str]) -> Result<(), String> {
    let mut args = vec![
        "pipping_slider".to_string(),
        "--level".into(),
        "1".into(),
        "--steps".into(),
        "1000".into(),
        "--out".into(),
        out.display().to_string(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    let cli = Cli::try_parse_from(&args).map_err(|e| e.to_string())?;
    run(cli).map_err(|e| e.to_string())
}

/// `summary.json` without what differs between invocations (wall times, machine).
fn summary_without_times(bytes: &[u8]) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_slice(bytes).unwrap();
    let m = v.as_object_mut().unwrap();
    for key in ["wall_time_s", "setup_time_s", "machine"] {
        assert!(m.remove(key).is_some(), "summary.json has `{key}`");
    }
    v
}

/// Every output of `a` and `b` byte-identical (`summary.json` up to wall times); the
/// checkpoint is not compared (it carries the wall time).
fn assert_same_outputs(a: &Path, b: &Path) {
    let (sa, sb) = (snapshot(a), snapshot(b));
    for name in [
        "timeseries.csv",
        "frictional_profile.csv",
        "slip_rate_map.csv",
        "displacement_x0.png",
        "slip_rate_x0.png",
        "slip_rate_map.png",
    ] {
        let (x, y) = (&sa[name], &sb[name]);
        assert!(
            x == y,
            "{name}: {} bytes against {} bytes",
            x.len(),
            y.len()
        );
    }
    assert_eq!(
        summary_without_times(&sa["summary.json"]),
        summary_without_times(&sb["summary.json"])
    );
    assert!(!sb.keys().any(|k| k.ends_with(".tmp")), "{:?}", sb.keys());
    // VTU frames (`--frame-every`) and their index, where the second run wrote them.
    let (fa, fb) = (a.join("frames"), b.join("frames"));
    if fb.exists() {
        let (fa, fb) = (snapshot(&fa), snapshot(&fb));
        assert!(
            fa.contains_key("frames.pvd") && fa.len() > 1,
            "{:?}",
            fa.keys()
        );
        assert_eq!(
            fa.keys().collect::<Vec<_>>(),
            fb.keys().collect::<Vec<_>>(),
            "frame files"
        );
        for (name, x) in &fa {
            assert!(x == &fb[name], "frames/{name} differs");
        }
    }
}

#[test]
fn stopped_killed_and_resumed_runs_match_and_mistakes_change_nothing() {
    let root = temp_dir("resume");
    let straight = root.join("straight");
    let frames = ["--frame-every", "100"];
    example(
        &straight,
        &["--checkpoint-every", "100", frames[0], frames[1]],
    )
    .unwrap();
    let rows = std::fs::read_to_string(straight.join("timeseries.csv"))
        .unwrap()
        .lines()
        .count();
    assert_eq!(rows, 1001, "a header and 1000 rows");

    // Stopped after 700 steps (t = 10.5 s, in the first slip event; checkpoints every 50),
    // then resumed.
    let stopped = root.join("stopped");
    let e = example(
        &stopped,
        &[
            "--checkpoint-every",
            "50",
            "--max-steps",
            "700",
            frames[0],
            frames[1],
        ],
    )
    .unwrap_err();
    assert!(
        e.contains("max_steps") && e.contains("step cap of 700"),
        "{e}"
    );
    let half = snapshot(&stopped);
    assert!(half.contains_key("checkpoint.bin") && !half.contains_key("summary.json"));

    // Mistakes into the half-finished folder: a new run without --resume, a resume with
    // another scene's fingerprint, a resume with another run's checkpoint. Each refused,
    // every file byte-identical.
    let refused = |args: &[&str], names: &[&str], what: &str| {
        let e = example(&stopped, args).unwrap_err();
        assert!(names.iter().all(|name| e.contains(name)), "{e}");
        assert_eq!(snapshot(&stopped), half, "{what} changes nothing");
    };
    refused(
        &["--checkpoint-every", "50"],
        &["--overwrite", "timeseries.csv"],
        "a refused new run",
    );
    let ckpt = stopped.join("checkpoint.bin").display().to_string();
    let mut other = vec!["--resume", ckpt.as_str(), "--law", "slip"];
    refused(&other, &["state_law"], "another scene");
    other.truncate(2);
    let foreign = straight.join("checkpoint.bin").display().to_string();
    // (The straight run wrote no frames: its `frame_every` differs, allowed here so that
    // the rows refuse it.)
    refused(
        &["--resume", &foreign, "--allow-change", "frame_every"],
        &["cannot resume", "step 1000"],
        "another run's checkpoint",
    );

    // The deliberate resume (VTU frames continued from the checkpoint's step too).
    other.extend(frames);
    example(&stopped, &other).unwrap();
    assert_same_outputs(&straight, &stopped);

    // "Killed" at step 720 with the last checkpoint at 700: the rows 701…720 are cut.
    let killed = root.join("killed");
    example(&killed, &["--checkpoint-every", "50", "--max-steps", "700"]).unwrap_err();
    let at_700 = std::fs::read(killed.join("checkpoint.bin")).unwrap();
    let ckpt = killed.join("checkpoint.bin").display().to_string();
    example(
        &killed,
        &[
            "--resume",
            ckpt.as_str(),
            "--checkpoint-every",
            "50",
            "--max-steps",
            "720",
        ],
    )
    .unwrap_err();
    let lines = |dir: &Path| {
        std::fs::read_to_string(dir.join("timeseries.csv"))
            .unwrap()
            .lines()
            .count()
    };
    assert_eq!(lines(&killed), 721, "rows up to step 720");
    std::fs::write(killed.join("checkpoint.bin"), &at_700).unwrap();
    example(
        &killed,
        &["--resume", ckpt.as_str(), "--checkpoint-every", "50"],
    )
    .unwrap();
    assert_same_outputs(&straight, &killed);

    let _ = std::fs::remove_dir_all(&root);
}
