//! The programs `seas_bp1`, `seas_bp3` and `seas_bp5` on MPI ranks (this crate's binaries:
//! the root package's programs with their evaluations shared): every file byte-identical to
//! one process's — BP1 at 1, 2 and 4 ranks, BP3 (a normal stress from slip) at 2, BP5 (the
//! half-space operator) at 2 and 3, a run stopped at a step cap on 2 ranks and resumed on
//! 3, and a job killed (`SIGKILL` to every process) and resumed on 2 ranks — and an error
//! on rank 0 ends every rank at once. The program `slider_3d` (TNNMG's velocity solves on
//! the ranks) writes the same bytes on 1, 2 and 4 ranks, also stopped and resumed.

use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::{Duration, Instant};

mod common;
use common::mpirun;

const BIN: &str = env!("CARGO_BIN_EXE_seas_bp1");
const BP3: &str = env!("CARGO_BIN_EXE_seas_bp3");
const BP5: &str = env!("CARGO_BIN_EXE_seas_bp5");
const SLIDER_3D: &str = env!("CARGO_BIN_EXE_slider_3d");

/// A fresh folder for `name` under the target directory's tmp.
fn folder(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::remove_dir_all(&dir).ok();
    dir
}

/// BP1 at Δz = 400 m for 300 years: 16 events, ~7000 steps.
fn flags(out: &Path) -> Vec<String> {
    ["--out", out.to_str().unwrap()]
        .iter()
        .map(|s| s.to_string())
        .chain(
            ["--dz", "400", "--end-years", "300", "--threads", "1"]
                .iter()
                .map(|s| s.to_string()),
        )
        .collect()
}

fn run(ranks: Option<usize>, args: &[String]) -> Output {
    run_program(BIN, ranks, args)
}

/// `bin` with `args`, on `ranks` MPI ranks or as one process (`None`).
fn run_program(bin: &str, ranks: Option<usize>, args: &[String]) -> Output {
    let mut c = match ranks {
        Some(n) => {
            let mut c = mpirun(n);
            c.arg(bin);
            c
        }
        None => std::process::Command::new(bin),
    };
    c.args(args).output().expect("the program (and mpirun)")
}

/// Asserts that the program (or mpirun) ended with success, showing its standard error.
fn succeeded(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Every file of `a` (and of its folders) but the summary (its times) has the bytes of
/// `b`'s.
fn same_files(a: &Path, b: &Path, what: &str) -> usize {
    let mut n = 0;
    for entry in std::fs::read_dir(a).unwrap() {
        let p = entry.unwrap().path();
        let name = p.file_name().unwrap().to_str().unwrap().to_owned();
        if p.is_dir() {
            n += same_files(&p, &b.join(&name), &format!("{what}: {name}"));
            continue;
        }
        if [
            "summary.json",
            "rsf-run.txt",
            "checkpoint.bin",
            "seas_resume.csv",
            "bp5_resume.json",
        ]
        .contains(&name.as_str())
        {
            continue;
        }
        let other = std::fs::read(b.join(&name)).unwrap_or_default();
        assert!(
            std::fs::read(&p).unwrap() == other,
            "{what}: {name} differs"
        );
        n += 1;
    }
    n
}

#[test]
fn files_are_byte_identical_on_1_2_and_4_ranks_and_after_a_resume() {
    let one = folder("bp1_one_process");
    let out = run(None, &flags(&one));
    succeeded(&out);
    for n in [1, 2, 4] {
        let dir = folder(&format!("bp1_{n}_ranks"));
        let out = run(Some(n), &flags(&dir));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{n} ranks: {err}");
        assert!(
            err.contains(&format!("{n} MPI ranks share every evaluation")),
            "{err}"
        );
        let files = same_files(&one, &dir, &format!("{n} ranks"));
        assert!(files >= 14, "{files} files compared");
    }
    // Stopped after 3000 steps with checkpoints (rank 0 ends the job with the step cap's
    // message), then resumed on 3 ranks to the end (a checkpoint holds the whole state:
    // any rank count continues it).
    let dir = folder("bp1_resumed");
    let mut capped = flags(&dir);
    capped.extend(["--checkpoint-every", "500", "--max-steps", "3000"].map(String::from));
    let out = run(Some(2), &capped);
    assert!(
        dir.join("checkpoint.bin").exists(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut resumed = flags(&dir);
    resumed.extend(["--checkpoint-every", "500", "--resume"].map(String::from));
    resumed.push(dir.join("checkpoint.bin").to_str().unwrap().to_owned());
    let out = run(Some(3), &resumed);
    succeeded(&out);
    same_files(&one, &dir, "stopped on 2 ranks and resumed on 3");
}

/// `--out` names a file: rank 0 refuses it while the other ranks have started a long run
/// (Δz = 100 m, 3000 years: minutes); every rank ends within seconds with the message.
#[test]
fn an_error_on_rank_0_ends_every_rank() {
    let file = folder("not_a_folder");
    std::fs::write(&file, b"a file").unwrap();
    let t = Instant::now();
    let out = mpirun(2)
        .arg(BIN)
        .args([
            "--out",
            file.to_str().unwrap(),
            "--dz",
            "100",
            "--threads",
            "1",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("rank 0 of 2: error: --out"), "{err}");
    assert!(t.elapsed() < Duration::from_secs(30), "{:?}", t.elapsed());
    assert_eq!(std::fs::read(&file).unwrap(), b"a file");
}

/// BP3 (thrust, 60°) at Δx = 2 km for 300 years: its 26 files (with the figure) on 2 ranks
/// have one process's bytes.
#[test]
fn bp3_files_are_byte_identical_on_2_ranks() {
    let args = |out: &Path| -> Vec<String> {
        let out = out.to_str().unwrap();
        [
            "--out",
            out,
            "--dx",
            "2000",
            "--end-years",
            "300",
            "--threads",
            "1",
        ]
        .map(String::from)
        .to_vec()
    };
    let one = folder("bp3_one_process");
    let out = run_program(BP3, None, &args(&one));
    succeeded(&out);
    let two = folder("bp3_2_ranks");
    let out = run_program(BP3, Some(2), &args(&two));
    let text = String::from_utf8_lossy(&out.stdout);
    succeeded(&out);
    assert!(
        text.contains("2 MPI ranks share every evaluation"),
        "{text}"
    );
    assert!(same_files(&one, &two, "BP3 on 2 ranks") >= 20);
}

/// BP1 at the benchmark's Δz = 25 m (m = 1 600: ℋ-blocks large enough that a set-up whose
/// bits depended on the cores a process sees — ranks are bound to one core each — would
/// differ) for 30 years: every file on 2 ranks has one process's bytes.
#[test]
fn bp1_at_25_m_is_byte_identical_on_2_ranks() {
    let args = |out: &Path| -> Vec<String> {
        let out = out.to_str().unwrap();
        [
            "--out",
            out,
            "--dz",
            "25",
            "--end-years",
            "30",
            "--threads",
            "1",
        ]
        .map(String::from)
        .to_vec()
    };
    let one = folder("bp1_25m_one_process");
    let out = run(None, &args(&one));
    succeeded(&out);
    let two = folder("bp1_25m_2_ranks");
    let out = run(Some(2), &args(&two));
    succeeded(&out);
    assert!(same_files(&one, &two, "BP1 at 25 m on 2 ranks") >= 14);
}

/// BP5 at Δx = 4 km (500 cells, Okada's operator, dense: its rows in blocks of 8 per
/// rank) for 300 years: every file on 2 and on 3 ranks has one process's bytes.
#[test]
fn bp5_files_are_byte_identical_on_2_and_3_ranks() {
    let args = |out: &Path| -> Vec<String> {
        let out = out.to_str().unwrap();
        [
            "--out",
            out,
            "--dx",
            "4000",
            "--end-years",
            "300",
            "--threads",
            "1",
            "--date",
            "2026-11-26",
        ]
        .map(String::from)
        .to_vec()
    };
    let one = folder("bp5_one_process");
    let out = run_program(BP5, None, &args(&one));
    succeeded(&out);
    for n in [2, 3] {
        let dir = folder(&format!("bp5_{n}_ranks"));
        let out = run_program(BP5, Some(n), &args(&dir));
        let text = String::from_utf8_lossy(&out.stdout);
        succeeded(&out);
        assert!(
            text.contains(&format!("{n} MPI ranks share every evaluation")),
            "{text}"
        );
        assert!(same_files(&one, &dir, &format!("BP5 on {n} ranks")) >= 25);
    }
}

/// BP5 at Δx = 1 km (8 000 slip unknowns: Okada's operator an ℋ-matrix) for its first
/// 3 s (15 steps of the initial rupture) on 2 ranks, each building and holding only the blocks of its rows: every file has one
/// process's bytes (the whole operator), and rank 0 says that it holds part 0 of 2.
#[test]
fn bp5_with_the_operator_held_in_parts_is_byte_identical_on_2_ranks() {
    let args = |out: &Path| -> Vec<String> {
        let out = out.to_str().unwrap();
        [
            "--out",
            out,
            "--dx",
            "1000",
            "--end-years",
            "1e-7",
            "--threads",
            "1",
            "--date",
            "2026-11-27",
        ]
        .map(String::from)
        .to_vec()
    };
    let one = folder("bp5_1km_one_process");
    let out = run_program(BP5, None, &args(&one));
    succeeded(&out);
    let dir = folder("bp5_1km_2_ranks");
    let out = run_program(BP5, Some(2), &args(&dir));
    let text = String::from_utf8_lossy(&out.stdout);
    succeeded(&out);
    assert!(
        text.contains("this rank's rows only (part 0 of 2)"),
        "{text}"
    );
    assert!(same_files(&one, &dir, "BP5 at 1 km on 2 ranks") >= 25);
}

/// The processes whose parent is `pid` (from `/proc`; Open MPI puts each rank in a process
/// group of its own, so a signal to mpirun's group does not reach them).
fn children(pid: u32) -> Vec<u32> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(stat) = std::fs::read_to_string(entry.path().join("stat")) else {
            continue;
        };
        // `pid (comm) state ppid …`: comm may hold spaces, so after the last ')'.
        let after = &stat[stat.rfind(')').map_or(0, |i| i + 1)..];
        let ppid = after.split_whitespace().nth(1).and_then(|p| p.parse().ok());
        if ppid == Some(pid) {
            out.extend(
                entry
                    .file_name()
                    .to_str()
                    .and_then(|p| p.parse::<u32>().ok()),
            );
        }
    }
    out
}

/// BP1 at Δz = 200 m for 600 years (seconds) on 2 ranks with a checkpoint every 500
/// steps, killed (`SIGKILL` to mpirun and both ranks at once) once a checkpoint is on
/// disk, then resumed on 2 ranks: every file has the bytes of an uninterrupted
/// one-process run.
#[test]
fn a_job_killed_and_resumed_on_2_ranks_writes_the_same_bytes() {
    let flags = |out: &Path| -> Vec<String> {
        let out = out.to_str().unwrap();
        [
            "--out",
            out,
            "--dz",
            "200",
            "--end-years",
            "600",
            "--threads",
            "1",
            "--checkpoint-every",
            "500",
        ]
        .map(String::from)
        .to_vec()
    };
    let one = folder("bp1_kill_one_process");
    let out = run(None, &flags(&one));
    succeeded(&out);
    let dir = folder("bp1_killed");
    let checkpointed = flags(&dir);
    let mut job = mpirun(2)
        .arg(BIN)
        .args(&checkpointed)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let checkpoint = dir.join("checkpoint.bin");
    let t = Instant::now();
    while !checkpoint.exists() {
        assert!(t.elapsed() < Duration::from_secs(120), "no checkpoint");
        assert!(job.try_wait().unwrap().is_none(), "the job ended first");
        std::thread::sleep(Duration::from_millis(20));
    }
    let ranks = children(job.id());
    assert_eq!(ranks.len(), 2, "mpirun's children: {ranks:?}");
    let killed = std::process::Command::new("kill")
        .arg("-KILL")
        .arg(job.id().to_string())
        .args(ranks.iter().map(u32::to_string))
        .status()
        .unwrap();
    assert!(killed.success());
    job.wait().unwrap();
    // Killed before its end: rank 0 writes the summary last.
    assert!(!dir.join("summary.json").exists(), "the job had ended");
    let mut resumed = checkpointed.clone();
    resumed.push("--resume".into());
    resumed.push(checkpoint.to_str().unwrap().to_owned());
    // The killed ranks' lock on the folder ends with them.
    let t = Instant::now();
    let out = loop {
        let out = run(Some(2), &resumed);
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        if out.status.success() || !err.contains("holds the folder's lock") {
            break out;
        }
        assert!(t.elapsed() < Duration::from_secs(30), "{err}");
        std::thread::sleep(Duration::from_millis(200));
    };
    succeeded(&out);
    assert!(same_files(&one, &dir, "killed and resumed on 2 ranks") >= 14);
}

/// The 3-D slider at level 2 (525 nodes; Newmark, TNNMG on the ranks) for 48 steps of
/// 0.25 s (`--end-time 12 --steps 48`: through the nucleation of the first event, the
/// largest slip rate rising from 1e-29 to about 1e-3 m/s), a frame every 12 steps: its time
/// series, fault snapshot and figure and every frame on 2 and 4 MPI ranks have the bytes of
/// the run on one rank; stopped at step 20 on 2 ranks and resumed on 4, the same bytes
/// again.
#[test]
fn slider_3d_files_are_byte_identical_on_1_2_and_4_ranks_and_after_a_resume() {
    let args = |out: &Path| -> Vec<String> {
        let out = out.to_str().unwrap();
        [
            "--out",
            out,
            "--level",
            "2",
            "--end-time",
            "12",
            "--steps",
            "48",
            "--frame-every",
            "12",
            "--threads",
            "1",
        ]
        .map(String::from)
        .to_vec()
    };
    let one = folder("slider_3d_1_rank");
    let out = run_program(SLIDER_3D, Some(1), &args(&one));
    succeeded(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("tnnmg-ranks solver"), "{text}");
    for n in [2, 4] {
        let dir = folder(&format!("slider_3d_{n}_ranks"));
        let out = run_program(SLIDER_3D, Some(n), &args(&dir));
        succeeded(&out);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(&format!("{n} MPI ranks share every velocity solve")),
            "{err}"
        );
        let files = same_files(&one, &dir, &format!("slider_3d on {n} ranks"));
        // The series, the snapshot and its figure, four frames and their index.
        assert!(files >= 8, "{files} files compared");
    }
    let dir = folder("slider_3d_resumed");
    let mut capped = args(&dir);
    capped.extend(["--checkpoint-every", "10", "--max-steps", "20"].map(String::from));
    let out = run_program(SLIDER_3D, Some(2), &capped);
    assert!(
        dir.join("checkpoint.bin").exists(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut resumed = args(&dir);
    resumed.extend(["--checkpoint-every", "10", "--resume"].map(String::from));
    resumed.push(dir.join("checkpoint.bin").to_str().unwrap().to_owned());
    let out = run_program(SLIDER_3D, Some(4), &resumed);
    succeeded(&out);
    // The snapshot is of the resumed part only (the program's documentation).
    std::fs::remove_file(dir.join("fault_snapshot.csv")).unwrap();
    std::fs::remove_file(dir.join("fault_slip_rate.png")).unwrap();
    let files = same_files(&dir, &one, "slider_3d stopped on 2 ranks and resumed on 4");
    assert!(files >= 6, "{files} files compared");
}
