//! The `stepover` program (a fault network of two strands, docs/fault-networks.md) end to
//! end through its binary: a run stopped at a step cap and resumed, then "killed" — its
//! last checkpoint older than its files — and resumed again, writes every per-fault file
//! byte-identical to an uninterrupted run's (each strand's station files, `catalogue.csv`,
//! `catalogue.png`; `summary.json` up to times), the catalogue's state continued from its
//! resume log; the files are named by their fault and carry the catalogue's columns.
//!
//! Δx = 500 m, 300 years: two events of the network (seconds in a test build).

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use common::{fresh_dir, run_to_end_or_cap};

/// A fresh temporary folder.
fn temp_dir(name: &str) -> PathBuf {
    fresh_dir("stepover", name)
}

/// Runs `stepover` on the test's scene into `out` with `extra` flags (ended at its step cap
/// with `--max-steps`).
fn stepover(out: &Path, extra: &[&str]) {
    let scene = ["--dx", "500", "--end-years", "300", "--threads", "1"];
    run_to_end_or_cap("stepover", &scene, out, extra);
}

/// Every file of `dir` but the checkpoint, the resume log and the manifest, with its bytes.
fn outputs(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .filter(|n| {
            !["checkpoint.bin", "catalogue_resume.csv", "rsf-run.txt"].contains(&n.as_str())
        })
        .map(|n| {
            let bytes = std::fs::read(dir.join(&n)).unwrap();
            (n, bytes)
        })
        .collect()
}

/// `summary.json` without what differs between invocations (times, machine, counts of this
/// invocation).
fn summary(bytes: &[u8]) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_slice(bytes).unwrap();
    v["run"] = serde_json::Value::Null;
    v
}

#[test]
fn a_stopped_killed_and_resumed_network_run_writes_the_uninterrupted_runs_files() {
    let whole = temp_dir("whole");
    stepover(&whole, &[]);
    let reference = outputs(&whole);
    // Per-fault files: six stations per strand, named by their strand.
    for fault in ["south", "north"] {
        let stations = reference
            .keys()
            .filter(|n| n.starts_with(&format!("{fault}_s")))
            .count();
        assert_eq!(stations, 6, "{fault}");
    }
    let catalogue = String::from_utf8(reference["catalogue.csv"].clone()).unwrap();
    let header = catalogue.lines().next().unwrap();
    for column in [
        "nucleation_fault",
        "ruptured",
        "peak_slip_rate_south",
        "moment_north",
        "rupture_s_north",
    ] {
        assert!(header.split(',').any(|c| c == column), "{header}");
    }
    assert!(catalogue.lines().count() >= 2, "an event: {catalogue}");

    let parts = temp_dir("parts");
    let every = ["--checkpoint-every", "600"];
    // Stopped at step 1200, during the first event (onset at step 1142, slip rates above 1e-4 m/s until about 1670), its
    // checkpoint kept aside; continued to a cap at step 3000, during the second …
    stepover(
        &parts,
        &[every.as_slice(), &["--max-steps", "1200"]].concat(),
    );
    let at_1200 = parts.join("checkpoint_1200.bin");
    std::fs::copy(parts.join("checkpoint.bin"), &at_1200).unwrap();
    let resume = parts.join("checkpoint.bin").display().to_string();
    stepover(
        &parts,
        &[
            every.as_slice(),
            &["--max-steps", "3000", "--resume", &resume],
        ]
        .concat(),
    );
    // … then "killed": resumed from step 1200 although the files reach step 3000.
    let killed = at_1200.display().to_string();
    stepover(&parts, &[every.as_slice(), &["--resume", &killed]].concat());
    std::fs::remove_file(&at_1200).unwrap();
    let resumed = outputs(&parts);
    assert_eq!(
        resumed.keys().collect::<Vec<_>>(),
        reference.keys().collect::<Vec<_>>()
    );
    for (name, bytes) in &reference {
        if name == "summary.json" {
            assert_eq!(summary(bytes), summary(&resumed[name]));
        } else {
            assert!(bytes == &resumed[name], "{name} differs after the resumes");
        }
    }
    let _ = std::fs::remove_dir_all(&whole);
    let _ = std::fs::remove_dir_all(&parts);
}
