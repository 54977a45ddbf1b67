//! The programs `seas_bp1` and `seas_bp3` on MPI ranks (this crate's binaries: the root
//! package's programs with their evaluations shared): every file byte-identical to one
//! process's (BP1 at 1, 2 and 4 ranks, BP3 — a normal stress from slip — at 2), a run
//! stopped at a step cap and resumed on 2 ranks byte-identical to an uninterrupted one,
//! and an error on rank 0 ends every rank at once.

use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::{Duration, Instant};

mod common;
use common::mpirun;

const BIN: &str = env!("CARGO_BIN_EXE_seas_bp1");
const BP3: &str = env!("CARGO_BIN_EXE_seas_bp3");

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

/// Every file of `a` but the summary (its times) has the bytes of `b`'s.
fn same_files(a: &Path, b: &Path, what: &str) -> usize {
    let mut n = 0;
    for entry in std::fs::read_dir(a).unwrap() {
        let p = entry.unwrap().path();
        let name = p.file_name().unwrap().to_str().unwrap().to_owned();
        if [
            "summary.json",
            "rsf-run.txt",
            "checkpoint.bin",
            "seas_resume.csv",
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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
    // message), then resumed on 2 ranks to the end.
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
    let out = run(Some(2), &resumed);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    same_files(&one, &dir, "stopped and resumed on 2 ranks");
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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let two = folder("bp3_2_ranks");
    let out = run_program(BP3, Some(2), &args(&two));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let two = folder("bp1_25m_2_ranks");
    let out = run(Some(2), &args(&two));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(same_files(&one, &two, "BP1 at 25 m on 2 ranks") >= 14);
}
