//! What the end-to-end tests share (a module of each test binary that declares `mod common;`).
// Each test binary uses a part of it.
#![allow(dead_code)]

use std::path::PathBuf;

/// The main job: the package's binary (src/main.rs), not an example.
pub const MAIN_JOB: &str = "pipping_slider";

/// The binary of the program `name`: the main job's (Cargo's `CARGO_BIN_EXE_…`) or the
/// example's, which `cargo test` builds beside the test's executable
/// (`target/<profile>/examples/`).
///
/// # Panics
/// The example is not built (the test was not run by `cargo test`).
pub fn program_binary(name: &str) -> PathBuf {
    if name == MAIN_JOB {
        return PathBuf::from(env!("CARGO_BIN_EXE_pipping_slider"));
    }
    let exe = std::env::current_exe().unwrap();
    let dir = exe.parent().unwrap().parent().unwrap().join("examples");
    let path = dir.join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(
        path.is_file(),
        "{} not built: run the tests with `cargo test` (which builds the examples)",
        path.display()
    );
    path
}

/// A fresh temporary folder `rsf-{prefix}-{name}-{pid}`.
pub fn fresh_dir(prefix: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rsf-{prefix}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The data rows of a SEAS station file, `global.dat` or profile (the lines that start
/// with a number; a profile's first row is its positions).
pub fn seas_rows(path: &std::path::Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .filter(|l| {
            l.trim_start()
                .starts_with(|c: char| c.is_ascii_digit() || c == '-')
        })
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect()
}

/// Asserts `|x − y| ≤ tol · max(|y|, floor)`.
pub fn close(x: f64, y: f64, tol: f64, floor: f64, what: &str) {
    assert!(
        (x - y).abs() <= tol * y.abs().max(floor),
        "{what}: {x} against {y}"
    );
}

/// Asserts that `row` has `expected`'s columns, each within 1e-6 of it (relative, floor
/// 1e-30: the files print 7 digits); `what` names the row in the messages.
pub fn assert_row_close(row: &[f64], expected: &[f64], what: &str) {
    assert_eq!(row.len(), expected.len(), "{what}");
    for (k, (x, y)) in row.iter().zip(expected).enumerate() {
        close(*x, *y, 1e-6, 1e-30, &format!("{what} column {}", k + 1));
    }
}

/// Every file of a run folder `dir` by name, with its bytes, but the checkpoint, the
/// manifest, the summary and `also` (a resume log).
pub fn run_files(dir: &std::path::Path, also: &str) -> std::collections::BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .filter(|n| !["checkpoint.bin", also, "rsf-run.txt", "summary.json"].contains(&n.as_str()))
        .map(|n| {
            let bytes = std::fs::read(dir.join(&n)).unwrap();
            (n, bytes)
        })
        .collect()
}

/// Runs `program` with `args`, `--out out` and `extra`: it must succeed, or, with
/// `--max-steps` in `extra`, stop at its step cap.
pub fn run_to_end_or_cap(program: &str, args: &[&str], out: &std::path::Path, extra: &[&str]) {
    let o = std::process::Command::new(program_binary(program))
        .args(args)
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .unwrap();
    let capped = extra.contains(&"--max-steps");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() != capped && (!capped || stderr.contains("step cap")),
        "{program} {extra:?}: {}{stderr}",
        String::from_utf8_lossy(&o.stdout),
    );
}

/// The flags of a test run of the square programs (`seas_bp7`, `seas_bp8`) at cell size
/// `dx` (m): `--dx DX --date 2026-11-29`.
pub fn square_flags(dx: &str) -> [&str; 4] {
    ["--dx", dx, "--date", "2026-11-29"]
}

/// Runs the square program `program` (`seas_bp7`, `seas_bp8`) with [`square_flags`]`(dx)`
/// into `out` with `extra` flags, as [`run_to_end_or_cap`].
pub fn run_square(program: &str, dx: &str, out: &std::path::Path, extra: &[&str]) {
    run_to_end_or_cap(program, &square_flags(dx), out, extra);
}

/// [`assert_resumed_run_is_identical`] for the square program `program` at
/// [`square_flags`]`("80")` and `extra`, stopped after 130 steps.
pub fn assert_square_run_resumes(
    (program, prefix): (&str, &str),
    extra: &[&str],
    (resume_log, files): (&str, Option<usize>),
) {
    assert_resumed_run_is_identical(
        (program, prefix),
        &[&square_flags("80")[..], extra].concat(),
        "130",
        (resume_log, files),
    );
}

/// Runs `program` with `args` (its flags but `--out` and the run's stops) into a fresh
/// folder `rsf-{prefix}-whole…` to its end, and into `rsf-{prefix}-parts…` stopped after
/// `max_steps` steps (checkpoints every 40) and resumed; asserts that both folders hold
/// the same files with the same bytes (but the checkpoint, the manifest, the summary and
/// the resume log `resume_log`), `files` of them if given.
pub fn assert_resumed_run_is_identical(
    (program, prefix): (&str, &str),
    args: &[&str],
    max_steps: &str,
    (resume_log, files): (&str, Option<usize>),
) {
    let whole = fresh_dir(prefix, "whole");
    run_to_end_or_cap(program, args, &whole, &[]);
    let reference = run_files(&whole, resume_log);
    if let Some(n) = files {
        assert_eq!(reference.len(), n, "{program}'s files");
    }
    let parts = fresh_dir(prefix, "parts");
    let every = ["--checkpoint-every", "40"];
    run_to_end_or_cap(
        program,
        args,
        &parts,
        &[&every[..], &["--max-steps", max_steps]].concat(),
    );
    let resume = parts.join("checkpoint.bin").display().to_string();
    run_to_end_or_cap(
        program,
        args,
        &parts,
        &[&every[..], &["--resume", &resume]].concat(),
    );
    let resumed = run_files(&parts, resume_log);
    assert_eq!(
        resumed.keys().collect::<Vec<_>>(),
        reference.keys().collect::<Vec<_>>()
    );
    for (name, bytes) in &reference {
        assert!(bytes == &resumed[name], "{name} differs after the resume");
    }
    let _ = std::fs::remove_dir_all(&whole);
    let _ = std::fs::remove_dir_all(&parts);
}
