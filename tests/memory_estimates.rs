//! Memory estimates that bound the measured peak (issue 74; docs/reliability.md, "Memory
//! estimates"): every program that builds a volume runs at a few small sizes with
//! `RSF_MEMORY_REPORT` set, so that the guard prints the plan's estimate and the measured
//! peak resident memory (`VmHWM`) when the run ends; the test fails where a peak exceeds
//! its estimate. The constants of the estimates (`crates/rsf-programs/src/estimates.rs`) were fitted to the
//! larger sizes of the committed table, which the ignored tests below measure and print.
//!
//! The binaries are the examples `cargo test` builds beside this test.

mod common;
use common::program_binary;
use std::path::Path;
use std::process::Command;

/// One run's estimate and measured peak (bytes).
#[derive(Debug, Clone, Copy)]
struct Reading {
    estimate: f64,
    peak: f64,
}

/// Runs `program` with `args` (and a fresh `--out` in `dir` if `out`) and reads the
/// guard's `rsf-memory:` line; panics if the run fails or prints none.
fn measure(program: &str, args: &[&str], dir: &Path, out: bool) -> Reading {
    let mut c = Command::new(program_binary(program));
    c.args(args).env("RSF_MEMORY_REPORT", "1").current_dir(dir);
    if out {
        let folder = dir.join(format!("{program}-{}", args.join("_").replace('/', "-")));
        let _ = std::fs::remove_dir_all(&folder);
        c.arg("--out").arg(folder);
    }
    let o = c.output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{program} {args:?}:\n{err}");
    let line = err
        .lines()
        .find_map(|l| l.strip_prefix("rsf-memory: "))
        .unwrap_or_else(|| panic!("{program} {args:?}: no rsf-memory line:\n{err}"));
    let field = |key: &str| -> f64 {
        line.split_whitespace()
            .find_map(|w| w.strip_prefix(key))
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{line}: no {key}"))
    };
    Reading {
        estimate: field("estimate_bytes="),
        peak: field("peak_bytes="),
    }
}

/// A case: the program and its flags (separated by spaces), whether it takes `--out`.
type Case = (&'static str, bool);

/// Runs `cases` two at a time, prints a table (program, flags, estimate, peak, ratio) and
/// returns the cases whose peak exceeded the estimate.
fn check(cases: &[Case], name: &str) -> Vec<String> {
    let dir = std::env::temp_dir().join(format!("rsf-memory-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let next = std::sync::Mutex::new(0usize);
    let rows = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| loop {
                let i = {
                    let mut n = next.lock().unwrap();
                    *n += 1;
                    *n - 1
                };
                let Some(&(command, out)) = cases.get(i) else {
                    break;
                };
                let mut words = command.split_whitespace();
                let program = words.next().unwrap();
                let args: Vec<&str> = words.collect();
                let r = measure(program, &args, &dir, out);
                rows.lock().unwrap().push((i, program, args, r));
            });
        }
    });
    let mut rows = rows.into_inner().unwrap();
    rows.sort_by_key(|r| r.0);
    println!("| program | flags | estimate (MB) | peak (MB) | peak / estimate |");
    println!("|---|---|---|---|---|");
    let mut over = Vec::new();
    for (_, program, args, r) in &rows {
        println!(
            "| {program} | `{}` | {:.0} | {:.0} | {:.2} |",
            args.join(" "),
            r.estimate / 1e6,
            r.peak / 1e6,
            r.peak / r.estimate
        );
        if r.peak > r.estimate {
            over.push(format!(
                "{program} {args:?}: peak {:.0} MB above its estimate {:.0} MB",
                r.peak / 1e6,
                r.estimate / 1e6
            ));
        }
    }
    std::fs::remove_dir_all(&dir).ok();
    over
}

/// Small sizes of the programs that build a volume, seconds each (test profile).
const SMALL: &[Case] = &[
    (
        "pipping_slider --level 4 --steps 20 --end-time 0.02 --threads 1",
        true,
    ),
    (
        "pipping_slider --level 6 --steps 20 --end-time 0.02 --threads 1",
        true,
    ),
    (
        "slider_3d --level 2 --steps 3 --end-time 0.003 --threads 1",
        true,
    ),
    (
        "slider_3d --level 3 --steps 3 --end-time 0.003 --threads 1",
        true,
    ),
    ("inclined_block --level 4 --steps 5 --end-time 0.005", true),
    ("curved_fault --level 2 --steps 5 --end-time 0.005", true),
    ("long_run --level 4 --steps 10 --end-time 0.01", true),
    ("seas_bp1 --dz 100 --end-years 0.01 --threads 1", true),
    ("seas_bp3 --dx 1000 --end-years 0.01 --threads 1", true),
    ("seas_bp5 --dx 4000 --end-years 0.01 --threads 1", true),
    (
        "seas_bp5 --kernel fe --dx 10000 --end-years 0.001 --threads 1",
        true,
    ),
    (
        "seas_bp5 --kernel fe --mesh tensor --dx 10000 --end-years 0.001 --threads 1",
        true,
    ),
    (
        "seas_bp5 --kernel fe --condensation factor --dx 10000 --end-years 0.001 --threads 1",
        true,
    ),
    ("seas_bp6 --dz 200 --end-years 0.001", true),
    // C on the finite elements peaks in its set-up (the direct solver's dense fault
    // block): 624 MB here, above the 504 MB the estimate gave before it was re-fitted.
    (
        "seas_bp6 --variant c --elastic fe --dz 100 --end-years 0.001",
        true,
    ),
    (
        "seas_bp6 --variant c --dz 500 --domain-km 40 --end-years 0.001",
        true,
    ),
    (
        "seas_bp6 --variant c --elastic bem --dz 100 --end-years 0.001",
        true,
    ),
    ("seas_bp7 --dx 40 --end-years 0.001", true),
    ("seas_bp7 --dx 10 --end-years 1e-7", true),
    ("seas_bp8 --dx 40 --end-days 0.5", true),
    ("seas_bp8 --kernel fe --dx 80 --end-days 0.5", true),
    ("seas_bp7 --kernel fe --dx 80 --end-years 1e-7", true),
    ("seas_bp8 --source pw --dx 10 --end-days 0.1", true),
    ("fault_setup_3d --dx 10 --steps 1", false),
    ("okada_anchor --levels 0,1 --cases buried", false),
    ("fault_kernel_scaling --dz 200,100", false),
    ("solver_memory --levels 3", false),
    ("schur_columns --levels 1,2 --columns 8", false),
];

/// Every program that builds a volume at a few sizes, the small ones fast: a peak above
/// its estimate fails the test (issue 74).
#[test]
fn estimates_bound_the_measured_peaks_at_small_sizes() {
    let over = check(SMALL, "small");
    assert!(over.is_empty(), "{}", over.join("\n"));
}

/// The larger sizes of docs/reliability.md's "Memory estimates" table (minutes each, up to
/// 1.8 GB; build the examples first, e.g. `cargo test --release --test memory_estimates`):
/// `cargo test --release --test memory_estimates -- --ignored --nocapture` prints the table
/// the constants of `crates/rsf-programs/src/estimates.rs` were fitted to, and fails where a peak exceeds its
/// estimate. The 3-D finite-element rows (`seas_bp5 --kernel fe`, `fault_setup_3d`) are
/// those to re-fit after a change of the 3-D build.
#[test]
#[ignore = "a measurement of minutes: the table of docs/reliability.md"]
fn estimates_bound_the_measured_peaks_of_the_table() {
    const TABLE: &[Case] = &[
        (
            "pipping_slider --level 5 --steps 20 --end-time 0.02 --threads 1",
            true,
        ),
        (
            "slider_3d --level 4 --steps 3 --end-time 0.003 --threads 1",
            true,
        ),
        ("inclined_block --level 5 --steps 5 --end-time 0.005", true),
        ("long_run --level 5 --steps 10 --end-time 0.01", true),
        ("seas_bp1 --dz 50 --end-years 0.01 --threads 1", true),
        ("seas_bp3 --dx 250 --end-years 0.01 --threads 1", true),
        ("seas_bp3 --dx 125 --end-years 0.01 --threads 1", true),
        ("seas_bp5 --dx 1000 --end-years 0.01 --threads 1", true),
        (
            "seas_bp5 --kernel fe --dx 5000 --end-years 0.001 --threads 1",
            true,
        ),
        (
            "seas_bp5 --kernel fe --dx 2500 --domain-km 100 --end-years 0.001 --threads 1",
            true,
        ),
        (
            "seas_bp5 --kernel fe --dx 2000 --domain-km 100 --end-years 0.001 --threads 1",
            true,
        ),
        (
            "seas_bp5 --kernel fe --mesh tensor --dx 5000 --end-years 0.001 --threads 1",
            true,
        ),
        (
            "seas_bp5 --kernel fe --condensation factor --dx 4000 --end-years 0.001 --threads 1",
            true,
        ),
        ("seas_bp6 --dz 10 --end-years 0.001", true),
        ("seas_bp6 --elastic fe --dz 50 --end-years 0.001", true),
        (
            "seas_bp6 --variant c --elastic fe --dz 50 --end-years 0.001",
            true,
        ),
        (
            "seas_bp6 --variant c --elastic bem --dz 20 --end-years 0.001",
            true,
        ),
        ("fault_setup_3d --dx 5 --steps 1", false),
        (
            "okada_anchor --levels 0,1,2 --cases buried --method multigrid",
            false,
        ),
        ("fault_kernel_scaling --dz 200,100,50", false),
    ];
    let over = check(TABLE, "table");
    assert!(over.is_empty(), "{}", over.join("\n"));
}
