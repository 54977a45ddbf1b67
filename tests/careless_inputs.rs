//! Every program against a careless user's inputs (issues 38, 58): the test lists every
//! example binary (`examples/*.rs`) and the main job (the package's binary
//! `pipping_slider`), reads its flags from its `--help`, and runs the same
//! careless inputs against each — another program's finished folder, a folder another run
//! is writing (its lock held), an `--out` that is a file, a huge step count or end time, a
//! huge or tiny size, `nan`, `-1`, `--threads 1000000`, absurd `--max-memory-gb` and
//! `--max-output-gb` — plus the cases of particular programs below. Each must exit non-zero
//! within seconds, print `error: …` naming the flag, key or path the user wrote (never a
//! Debug dump or a panic), and leave every file of the scratch folder byte-identical. A
//! program added later is covered without anyone editing this test: it goes through the
//! guard (`rsf_programs::guard`) or fails here.
//!
//! The binaries are the examples `cargo test` builds beside this test
//! (`target/<profile>/examples/`) and the package's binary (Cargo's `CARGO_BIN_EXE_…`); the
//! cases run two at a time. Two more tests: a second
//! run into a running `seas_bp3`'s folder, and a full disk (a 1 MB tmpfs, where the
//! machine allows mounting one).

mod common;
use common::{program_binary, MAIN_JOB};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The programs: the stems of `examples/*.rs` and the main job.
fn programs() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "rs").then(|| p.file_stem().unwrap().to_string_lossy().into())
        })
        .collect();
    names.push(MAIN_JOB.into());
    names.sort();
    names
}

/// Every file under `dir` (recursively) with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if let Ok(bytes) = std::fs::read(&p) {
                files.insert(p.clone(), bytes);
            }
        }
    }
    files
}

/// What a run of a program gave.
struct Outcome {
    ok: bool,
    stdout: String,
    stderr: String,
    seconds: f64,
}

/// Runs `program` with `args` in `dir`, killed after `limit` (then `ok` is false and the
/// time is the limit).
fn run(program: &str, args: &[String], dir: &Path, limit: Duration) -> Outcome {
    let mut child = Command::new(program_binary(program))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    // Read both pipes on threads so that a chatty program cannot block on a full pipe.
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let out = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut out, &mut s).ok();
        s
    });
    let err = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut err, &mut s).ok();
        s
    });
    let ok = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status.success();
        }
        if start.elapsed() > limit {
            child.kill().ok();
            child.wait().ok();
            break false;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    Outcome {
        ok,
        seconds: start.elapsed().as_secs_f64(),
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    }
}

/// The long flags a program's `--help` lists (the first `--name` of each option line).
fn flags(program: &str, dir: &Path) -> BTreeSet<String> {
    let help = run(program, &["--help".into()], dir, Duration::from_secs(20));
    assert!(help.ok, "{program} --help failed:\n{}", help.stderr);
    help.stdout
        .lines()
        .filter_map(|l| {
            let t = l.trim_start();
            let t = match t.strip_prefix('-') {
                Some(rest) if !rest.starts_with('-') => rest.get(3..)?.trim_start(),
                _ => t,
            };
            let name = t.strip_prefix("--")?;
            let end = name
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
                .unwrap_or(name.len());
            Some(format!("--{}", &name[..end]))
        })
        .collect()
}

/// Careless values of the flags that any program may have: `(flags, values)`, each value
/// given to each flag alone; the error must name the flag.
const CARELESS: &[(&[&str], &[&str])] = &[
    // Counts.
    (
        &[
            "--steps",
            "--coarse",
            "--fine",
            "--rows",
            "--reference-steps",
            "--ref-n",
            "--mesh-steps",
            "--energy-steps",
        ],
        &["1e12"],
    ),
    (&["--steps-per-l", "--periods"], &["1e12", "nan"]),
    (&["--level", "--levels", "--max-level"], &["30"]),
    // Times, lengths and other quantities.
    (&["--end-years", "--end-time"], &["1e12", "-1", "nan"]),
    (&["--dx", "--dz"], &["1e-3", "1e300", "nan", "-1"]),
    (
        &["--domain-km", "--ratio", "--base-e"],
        &["1e300", "nan", "-1"],
    ),
    (&["--width"], &["1e300", "1e-300", "nan"]),
    (
        &["--length-km", "--depth-km", "--far", "--dip"],
        &["1e300", "nan"],
    ),
    (
        &["--tolerance", "--epsilon", "--h0", "--mass", "--eta"],
        &["nan", "-1"],
    ),
    (&["--rk-tolerance"], &["nan", "0"]),
    (&["--kernel-epsilon"], &["nan", "0.5"]),
    (&["--adaptive"], &["nan", "2"]),
    (&["--dynamic-tau"], &["1e8"]),
    (&["--window"], &["nan,1"]),
    (
        &[
            "--compare-until",
            "--snapshot-time",
            "--switch",
            "--angle",
            "--state-change-cap",
            "--fixed-point-tolerance",
            "--dynamic-fixed-point-tolerance",
            "--switch-to-dynamic",
            "--event-quiet-time",
            "--memory-budget-gib",
            "--tolerances",
        ],
        &["nan"],
    ),
    // Words.
    (&["--date"], &["2023-02-31"]),
    (&["--modeler"], &[""]),
];

/// One case: a program, its arguments, what the error must name (and what it must not:
/// a flag the user did not write).
#[derive(Debug, Clone)]
struct Case {
    program: String,
    args: Vec<String>,
    names: String,
    not: Option<String>,
}

fn case(program: &str, args: &[&str], names: &str) -> Case {
    Case {
        program: program.into(),
        args: args.iter().map(|s| (*s).to_owned()).collect(),
        names: names.into(),
        not: None,
    }
}

/// [`case`] of a command: the program and its flags, separated by spaces.
fn command(line: &str, names: &str) -> Case {
    let mut words = line.split_whitespace();
    let program = words.next().unwrap();
    case(program, &words.collect::<Vec<_>>(), names)
}

/// [`case`] whose error must not contain `not`.
fn case_not(program: &str, args: &[&str], names: &str, not: &str) -> Case {
    Case {
        not: Some(not.into()),
        ..case(program, args, names)
    }
}

/// The cases of every program from its flags.
fn generic_cases(program: &str, flags: &BTreeSet<String>) -> Vec<Case> {
    let mut cases = vec![
        case(program, &["--max-memory-gb", "nan"], "--max-memory-gb"),
        case(program, &["--max-memory-gb", "1e-9"], "--max-memory-gb"),
        case(program, &["--max-output-gb", "-1"], "--max-output-gb"),
        case(program, &["--threads", "1000000"], "--threads"),
    ];
    // Another program's finished run (`pipping_slider`'s; `seas_bp1`'s for it).
    let other = if program == "pipping_slider" {
        "bp1_run"
    } else {
        "main_job"
    };
    for folder in ["--out", "--figures"] {
        if flags.contains(folder) {
            cases.push(case(program, &[folder, other], "--overwrite"));
            cases.push(case(program, &[folder, "a_file"], "a_file"));
            cases.push(case(program, &[folder, "busy"], "another run"));
        }
    }
    for &(careless_flags, values) in CARELESS {
        for &flag in careless_flags.iter().filter(|f| flags.contains(**f)) {
            for v in values {
                cases.push(case(program, &[flag, v], flag));
            }
        }
    }
    if flags.contains("--scene") {
        cases.push(case(program, &["--scene", "huge_steps.toml"], "steps"));
        cases.push(case(program, &["--scene", "huge_level.toml"], "level"));
        cases.push(case(program, &["--scene", "missing.toml"], "missing.toml"));
    }
    // A run configuration's file (docs/design.md, "One run configuration"): missing, a
    // key that is no setting, a value of the wrong type, a value out of its range — each
    // named as written.
    if flags.contains("--config") {
        cases.push(case(program, &["--config", "missing.toml"], "missing.toml"));
        cases.push(case(
            program,
            &["--config", "unknown_key.toml"],
            "no_such_setting",
        ));
        // The cell size's key: `dx`, or `dz` where the program's flag is `--dz`.
        let (typed, bad, named) = if flags.contains("--dx") {
            ("typed_dx.toml", "bad_dx.toml", ["`dx`", "key `dx` = -10"])
        } else {
            ("typed_dz.toml", "bad_dz.toml", ["`dz`", "key `dz` = -10"])
        };
        cases.push(case(program, &["--config", typed], named[0]));
        cases.push(case(program, &["--config", bad], named[1]));
    }
    cases
}

/// The physically meaningless inputs of issue 58 and the cases of particular programs.
fn particular_cases(mesh: &str) -> Vec<Case> {
    vec![
        command("seas_bp3 --end-years -1", "--end-years"),
        command("seas_bp3 --dx 1", "--dx"),
        command("seas_bp3 --ratio 1", "--ratio"),
        command("seas_bp3 --dip 90", "--dip"),
        command("seas_bp1 --inertia --dynamic-tau 1e8", "--dynamic-tau"),
        command("seas_bp1 --dynamic-tau 0.01", "--inertia"),
        command("seas_bp1 --switch-to-dynamic 1e-2", "--inertia"),
        command("seas_bp1 --absorbing all", "--inertia"),
        command("seas_bp1 --ratio 1 --end-years 50", "--ratio"),
        command("seas_bp1 --dz 1e-300", "--dz"),
        command("seas_bp1 --date 2023-02-31", "--date"),
        // Issue 87: a flag the default scheme ignores, a device as a checkpoint, a box whose
        // octree's root cubes alone exceed the mesh's limit (refused by arithmetic, before
        // anything is built: it built 62.5 million cubes in 54 s).
        command("seas_bp1 --tolerance 1e-8", "--tolerance"),
        command("seas_bp1 --resume /dev/zero", "--resume"),
        command("seas_bp5 --kernel fe --domain-km 1e4", "--domain-km"),
        command(
            "seas_bp1 --resume main_job/checkpoint.bin --overwrite",
            "--overwrite",
        ),
        command("seas_bp5 --ratio 1.1", "--kernel fe"),
        command("seas_bp5 --dx 100", "--dx"),
        command("slider_elastic_base --base-e 1e300", "--base-e"),
        command("slider_3d --level 6", "--max-memory-gb"),
        command("slider_3d --width 1e-300", "--width"),
        command("inclined_block --level 1 --steps 1e12", "--steps"),
        case(
            "curved_fault",
            &["--level", "0", "--mesh", mesh],
            "coincide",
        ),
        command("pipping_slider --scene huge.toml", "huge.toml"),
        command("spring_block --integrator newmark --mass 0", "--mass"),
        command(
            "fig6_1_fixed_point_iterations --max-level 30",
            "--max-level",
        ),
        // Issue 74: nonsense that ran, lists that printed `m^NaN`, nameless errors.
        command("seas_bp5 --tolerance 1", "--tolerance"),
        command("seas_bp3 --tolerance 1", "--tolerance"),
        command("seas_bp5 --allow-change end_years", "--allow-change"),
        command("seas_bp3 --allow-change nonsense", "--allow-change"),
        command("seas_bp1 --allow-change end_years", "--allow-change"),
        command("pipping_slider --allow-change steps", "--allow-change"),
        command("slider_3d --allow-change steps", "--allow-change"),
        command("seas_bp5 --ordering amd", "--ordering"),
        command("seas_bp5 --dx 2000.0000001", "--dx"),
        command("okada_anchor --modes 3", "--modes"),
        command("seas_bp1 --inertia --dynamic-tau 1e-9", "--dynamic-tau"),
        command("fault_kernel_scaling --dz 1000,1000", "--dz"),
        command("halfspace_scaling --dx 2000,2000", "--dx"),
        command("fault_setup_3d --dx 2,2", "--dx"),
        command("fault_setup_3d --dx 3", "whole cells"),
        command("okada_anchor --levels 1,1", "--levels"),
        command("okada_anchor --far 3,3", "--far"),
        command("solver_memory --levels 4,4", "--levels"),
        // seas_bp6 (issue 71, after issue 74 was filed): the same rules.
        command("seas_bp6 --tolerance 1", "--tolerance"),
        command("seas_bp6 --allow-change end_years", "--allow-change"),
        command("seas_bp6 --dz 3", "--dz"),
        command("seas_bp6 --dz 1e300", "--dz"),
        command("seas_bp6 --variant x", "--variant"),
        // BP6-C runs on the boundary-element kernel (its stiffness formed densely): more
        // than 20 000 cells is refused before anything is built.
        command("seas_bp6 --variant c --elastic bem --dz 1", "--dz"),
        // Settings the chosen kernel would ignore.
        command("seas_bp6 --kernel dense", "--kernel"),
        command("seas_bp6 --elastic fe --bem-product fft", "--bem-product"),
        command("seas_bp6 --diffusion-cells 5", "--diffusion-cells"),
        command(
            "seas_bp6 --pressure diffusion --diffusion-cells 1",
            "--diffusion-cells",
        ),
        command(
            "seas_bp6 --resume main_job/checkpoint.bin --overwrite",
            "--overwrite",
        ),
        // seas_bp8 (issue 85): the same rules.
        command("seas_bp8 --tolerance 1", "--tolerance"),
        command("seas_bp8 --dx 3", "--dx"),
        command("seas_bp8 --dx 30", "--dx"),
        command("seas_bp8 --dx 1e300", "--dx"),
        command("seas_bp8 --source x", "--source"),
        command("seas_bp8 --end-days 0", "--end-days"),
        command("seas_bp8 --sigma-min 20", "--sigma-min"),
        // A setting of the floor that `refuse` would ignore.
        command(
            "seas_bp8 --overpressure refuse --sigma-min 1",
            "--sigma-min",
        ),
        command("seas_bp8 --profile-interval 1", "--profile-interval"),
        command(
            "seas_bp8 --resume main_job/checkpoint.bin --overwrite",
            "--overwrite",
        ),
        // seas_bp7 (issue 85): the same rules, and D_RS.
        command("seas_bp7 --dx 0", "--dx"),
        command("seas_bp7 --dx -10", "--dx"),
        command("seas_bp7 --dx NaN", "--dx"),
        command("seas_bp7 --dx 30", "--dx"),
        command("seas_bp7 --dx 1e300", "--dx"),
        command("seas_bp7 --law x", "--law"),
        command("seas_bp7 --end-years 0", "--end-years"),
        command("seas_bp7 --d-rs 0", "--d-rs"),
        // The finite-element box (issue 85 item 5): its settings without `--kernel fe`,
        // out of range, or a box smaller than 2 l_f.
        command("seas_bp7 --domain-km 3", "--domain-km"),
        command("seas_bp8 --ratio 1.1", "--ratio"),
        command("seas_bp7 --kernel fe --ratio 1", "--ratio"),
        command("seas_bp8 --kernel fe --ratio NaN", "--ratio"),
        command("seas_bp8 --kernel fe --domain-km 0.5", "--domain-km"),
        command("seas_bp7 --kernel x", "--kernel"),
        command("seas_bp7 --tolerance 1", "--tolerance"),
        command(
            "seas_bp7 --resume main_job/checkpoint.bin --overwrite",
            "--overwrite",
        ),
        case_not(
            "pipping_slider",
            &["--scene", "bad_end.toml"],
            "end_time_s",
            "--end-time",
        ),
        case_not(
            "inclined_block",
            &["--scene", "bad_end.toml"],
            "end_time_s",
            "--end-time",
        ),
    ]
}

/// The scratch folder: another program's finished runs, a file, a folder whose lock is
/// held, careless scene files.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rsf-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for (file, text) in [
        (
            "main_job/rsf-run.txt",
            "program=pipping_slider\noutput=summary.json\noutput=timeseries.csv\n",
        ),
        ("main_job/summary.json", "{\"steps\": 10000}\n"),
        ("main_job/timeseries.csv", "t,max_v\n0,1e-6\n"),
        ("main_job/checkpoint.bin", "not a checkpoint\n"),
        (
            "bp1_run/rsf-run.txt",
            "program=seas_bp1\noutput=devol.dat\noutput=summary.json\n",
        ),
        ("bp1_run/devol.dat", "# BP1\n0 0\n"),
        ("bp1_run/summary.json", "{\"events\": 3}\n"),
        ("busy/timeseries.csv", "t\n0\n"),
        ("a_file", "not a folder\n"),
        ("huge.toml", "level = 1e300\n"),
        ("huge_steps.toml", "steps = 1000000000000\n"),
        ("huge_level.toml", "level = 30\n"),
        ("bad_end.toml", "end_time_s = -1.0\n"),
        ("unknown_key.toml", "no_such_setting = 1\n"),
        ("typed_dx.toml", "dx = \"ten\"\n"),
        ("bad_dx.toml", "dx = -10\n"),
        ("typed_dz.toml", "dz = \"ten\"\n"),
        ("bad_dz.toml", "dz = -10\n"),
    ] {
        let path = dir.join(file);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    dir
}

/// Runs `cases` in `dir` two at a time, each with a fresh `--out` (if the program has
/// one and the case gives none), and returns the failures.
fn check(cases: &[Case], dir: &Path, has_out: &BTreeMap<String, bool>) -> Vec<String> {
    let before = snapshot(dir);
    let next = Mutex::new(0usize);
    let failures = Mutex::new(Vec::new());
    let times = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| loop {
                let i = {
                    let mut n = next.lock().unwrap();
                    *n += 1;
                    *n - 1
                };
                let Some(c) = cases.get(i) else { break };
                let mut args = c.args.clone();
                if has_out[&c.program] && !args.iter().any(|a| a == "--out") {
                    args.extend(["--out".into(), format!("fresh/{i}")]);
                }
                let o = run(&c.program, &args, dir, Duration::from_secs(20));
                let err = &o.stderr;
                let what = format!("{} {args:?}", c.program);
                let fail = if o.ok {
                    Some(format!("{what} succeeded:\n{}", o.stdout))
                } else if o.seconds >= 20.0 {
                    Some(format!("{what}: not refused within 20 s"))
                } else if !(err.contains("error") && err.contains(&c.names)) {
                    Some(format!(
                        "{what}: the error does not name `{}`:\n{err}",
                        c.names
                    ))
                } else if err.contains("panicked") || err.contains("InvalidParameter {") {
                    Some(format!("{what}: a panic or a Debug dump:\n{err}"))
                } else if err.len() > 2500 {
                    Some(format!("{what}: a {}-byte message", err.len()))
                } else if c.not.as_ref().is_some_and(|n| err.contains(n.as_str())) {
                    Some(format!(
                        "{what}: the error names `{}`, which the user did not write:\n{err}",
                        c.not.as_deref().unwrap_or_default()
                    ))
                } else if long_number(err) {
                    Some(format!("{what}: a number of 30 digits or more:\n{err}"))
                } else {
                    None
                };
                times.lock().unwrap().push((o.seconds, what));
                if let Some(f) = fail {
                    failures.lock().unwrap().push(f);
                }
            });
        }
    });
    // A refused run leaves the scratch folder as it was: new (empty or manifest-only)
    // folders may appear, the files that existed are untouched.
    let after = snapshot(dir);
    let mut failures = failures.into_inner().unwrap();
    for (path, bytes) in &before {
        if after.get(path) != Some(bytes) {
            failures.push(format!("{} was changed", path.display()));
        }
    }
    let mut times = times.into_inner().unwrap();
    times.sort_by(|a, b| b.0.total_cmp(&a.0));
    println!(
        "{} cases; slowest: {:?}",
        cases.len(),
        &times[..times.len().min(3)]
    );
    failures
}

/// Whether `text` holds a run of 30 digits or more (a `1e300` printed in full).
fn long_number(text: &str) -> bool {
    let mut run = 0;
    for c in text.chars() {
        run = if c.is_ascii_digit() { run + 1 } else { 0 };
        if run >= 30 {
            return true;
        }
    }
    false
}

/// Holds the exclusive lock of `dir` as a running program does (the guard's lock: the
/// folder's own `flock` on Unix).
fn hold_lock(dir: &Path) -> std::fs::File {
    #[cfg(unix)]
    let file = std::fs::File::open(dir).unwrap();
    #[cfg(not(unix))]
    let file = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(dir.join("rsf-run.lock"))
        .unwrap();
    file.try_lock().unwrap();
    file
}

#[test]
fn every_program_refuses_careless_inputs_naming_them_and_changes_nothing() {
    let dir = scratch("careless");
    let mesh = cracked_arc_mesh(&dir);
    let _busy = hold_lock(&dir.join("busy"));
    let start = Instant::now();
    let programs = programs();
    assert!(programs.len() >= 25, "{programs:?}");
    let mut cases = Vec::new();
    let mut has_out = BTreeMap::new();
    for p in &programs {
        let f = flags(p, &dir);
        has_out.insert(p.clone(), f.contains("--out"));
        cases.extend(generic_cases(p, &f));
    }
    for c in particular_cases(mesh.to_str().unwrap()) {
        assert!(programs.contains(&c.program), "{c:?}: no such program");
        cases.push(c);
    }
    // A build without METIS refuses its ordering at once (it was refused after 5.6 s of
    // set-up); a build with it runs it.
    if !rsf_metis::is_available() {
        cases.push(case(
            "seas_bp5",
            &["--kernel", "fe", "--ordering", "nested-dissection"],
            "--ordering",
        ));
    }
    let failures = check(&cases, &dir, &has_out);
    println!(
        "{} programs, {} cases in {:.1} s",
        programs.len(),
        cases.len(),
        start.elapsed().as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n\n")
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A second run into the folder a run is writing is refused at once, and the first is
/// not disturbed: `seas_bp3` (whose two runs into one folder both used to exit 0, leaving
/// files that matched neither).
#[test]
fn a_second_run_into_a_running_folder_is_refused_at_once() {
    let dir = std::env::temp_dir().join(format!("rsf-concurrent-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let args = ["--out", "run", "--dx", "2000", "--end-years", "1000"];
    let mut first = Command::new(program_binary("seas_bp3"))
        .args(args)
        .arg("--threads=1")
        .current_dir(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // The first run has taken the folder once its manifest is there.
    let start = Instant::now();
    while !dir.join("run/rsf-run.txt").exists() {
        assert!(start.elapsed() < Duration::from_secs(30), "no manifest");
        std::thread::sleep(Duration::from_millis(20));
    }
    let args: Vec<String> = args.iter().map(|s| (*s).to_owned()).collect();
    let second = run("seas_bp3", &args, &dir, Duration::from_secs(20));
    let still_running = first.try_wait().unwrap().is_none();
    first.kill().ok();
    first.wait().ok();
    assert!(!second.ok, "the second run succeeded");
    assert!(
        second.stderr.contains("another run") && second.stderr.contains("run"),
        "{}",
        second.stderr
    );
    assert!(
        second.seconds < 5.0,
        "refused after {:.1} s",
        second.seconds
    );
    assert!(still_running, "the first run ended early");
    std::fs::remove_dir_all(&dir).ok();
}

/// A 1 MB filesystem mounted for the test (`mount -t tmpfs`), unmounted when dropped.
struct SmallDisk(PathBuf);

impl SmallDisk {
    /// Mounts one at `dir`, if the machine allows (root, a kernel with tmpfs).
    fn mount(dir: &Path) -> Option<Self> {
        std::fs::create_dir_all(dir).ok()?;
        let ok = Command::new("mount")
            .args(["-t", "tmpfs", "-o", "size=1m", "tmpfs"])
            .arg(dir)
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        ok.then(|| Self(dir.to_path_buf()))
    }
}

impl Drop for SmallDisk {
    fn drop(&mut self) {
        Command::new("umount").arg(&self.0).status().ok();
    }
}

/// Programs that fill a 1 MB disk within seconds stop with an error naming the file they
/// could not write and the operating system's cause ("No space left on device"), where the
/// machine allows mounting one.
#[test]
fn a_full_disk_is_reported_with_the_path_and_its_cause() {
    let dir = std::env::temp_dir().join(format!("rsf-full-disk-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let Some(disk) = SmallDisk::mount(&dir.join("disk")) else {
        println!("no 1 MB filesystem could be mounted here: skipped");
        return;
    };
    let cases: &[(&str, &[&str])] = &[
        ("seas_bp3", &["--dx", "2000", "--threads", "1"]),
        (
            "seas_bp1",
            &["--dz", "400", "--domain-km", "60", "--threads", "1"],
        ),
        (
            "pipping_slider",
            &["--level", "2", "--steps", "20000", "--threads", "1"],
        ),
        ("inclined_block", &["--level", "2", "--frame-every", "1"]),
        ("spring_block", &["--steps-per-l", "2000"]),
        // Its files are written whole at the end; the space of their rows is held as they
        // grow (issue 74: a full disk was found only after the whole run).
        ("seas_bp5", &["--dx", "4000", "--threads", "1"]),
        ("seas_bp6", &["--dz", "100", "--threads", "1"]),
        // The elimination's setup.bin (2.1 MB at 4 km) does not fit: refused before the
        // elimination, whose disk space is held first (issue 87: it failed after 11 s).
        (
            "seas_bp5",
            &["--kernel", "fe", "--dx", "4000", "--threads", "1"],
        ),
    ];
    let mut failures = Vec::new();
    for (i, (program, args)) in cases.iter().enumerate() {
        let mut args: Vec<String> = args.iter().map(|s| (*s).to_owned()).collect();
        args.extend(["--out".into(), format!("disk/{i}")]);
        let o = run(program, &args, &dir, Duration::from_secs(120));
        let err = &o.stderr;
        let eliminated = err.contains("% of the elimination");
        if o.ok
            || eliminated
            || !(err.contains("No space left on device") && err.contains(&format!("disk/{i}/")))
        {
            failures.push(format!("{program} {args:?} (ok: {}):\n{err}", o.ok));
        }
        // Free the disk for the next case.
        std::fs::remove_dir_all(dir.join(format!("disk/{i}"))).ok();
    }
    drop(disk);
    std::fs::remove_dir_all(&dir).ok();
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// The arc block's Gmsh fixture with a duplicated node: a crack nobody declared.
fn cracked_arc_mesh(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/crates/rsf-fem/tests/fixtures/arc_block.msh"
    ))
    .unwrap();
    // The first node block's first node, repeated under a new tag in its own block.
    let lines: Vec<&str> = text.lines().collect();
    let at = lines.iter().position(|l| *l == "$Nodes").unwrap();
    let header: Vec<u64> = lines[at + 1]
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    let (blocks, nodes, max_tag) = (header[0], header[1], header[3]);
    // First block: "dim entity parametric count", then `count` tags, then coordinates.
    let count: usize = lines[at + 2]
        .split_whitespace()
        .nth(3)
        .unwrap()
        .parse()
        .unwrap();
    let first_tag: u64 = lines[at + 3].trim().parse().unwrap();
    let coords = lines[at + 3 + count];
    let dim_entity: Vec<&str> = lines[at + 2].split_whitespace().take(2).collect();
    let new_tag = max_tag + 1;
    let mut out: Vec<String> = lines[..=at].iter().map(|s| s.to_string()).collect();
    out.push(format!("{} {} 1 {}", blocks + 1, nodes + 1, new_tag));
    out.extend(
        lines[at + 2..]
            .iter()
            .take_while(|l| **l != "$EndNodes")
            .map(|s| s.to_string()),
    );
    out.push(format!("{} {} 0 1", dim_entity[0], dim_entity[1]));
    out.push(new_tag.to_string());
    out.push(coords.to_string());
    let rest = lines.iter().position(|l| *l == "$EndNodes").unwrap();
    // The first triangle using the first node uses its duplicate instead (blocks of
    // `$Elements`: a header `dim entity type count`, then `count` lines `tag nodes…`).
    let first = first_tag.to_string();
    let mut i = rest;
    while lines[i] != "$Elements" {
        out.push(lines[i].to_string());
        i += 1;
    }
    out.push(lines[i].to_string());
    out.push(lines[i + 1].to_string());
    i += 2;
    let mut swapped = false;
    while lines[i] != "$EndElements" {
        let header: Vec<usize> = lines[i]
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        out.push(lines[i].to_string());
        for l in &lines[i + 1..=i + header[3]] {
            let fields: Vec<&str> = l.split_whitespace().collect();
            if header[2] == 2 && !swapped && fields[1..].contains(&first.as_str()) {
                swapped = true;
                let f: Vec<String> = fields
                    .iter()
                    .enumerate()
                    .map(|(k, f)| {
                        if k > 0 && *f == first {
                            new_tag.to_string()
                        } else {
                            f.to_string()
                        }
                    })
                    .collect();
                out.push(f.join(" "));
            } else {
                out.push(l.to_string());
            }
        }
        i += header[3] + 1;
    }
    assert!(swapped, "no triangle uses node {first}");
    out.extend(lines[i..].iter().map(|s| s.to_string()));
    let path = dir.join("cracked.msh");
    std::fs::write(&path, out.join("\n") + "\n").unwrap();
    path
}

/// The files under `dir` by their path inside it, but those that name a run or its time
/// (`rsf-run.txt`, `summary.json`, `checkpoint.bin`: the command line, wall times).
fn run_files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    snapshot(dir)
        .into_iter()
        .map(|(p, b)| (p.strip_prefix(dir).unwrap().to_path_buf(), b))
        .filter(|(p, _)| {
            !["rsf-run.txt", "summary.json", "checkpoint.bin"]
                .iter()
                .any(|n| p == Path::new(n))
        })
        .collect()
}

/// A run's checkpoint resumed into **another** finished run's folder of the same program
/// is refused before anything is cut, that folder byte-identical, while the run's own
/// folder resumes (issue 74: `seas_bp5 --out B --resume A/checkpoint.bin` cut B's finished
/// files to step 500 and continued A's run in them). And two runs are never spliced into
/// one folder (issue 87): the same checkpoint into B **whose `rsf-run.txt` was deleted** is
/// refused by B's own files (the resume log's state of the checkpoint's step is not the
/// checkpoint's), B's files byte-identical and no run id written — or, where B's files up
/// to the step are A's bytes (B diverges later), continued into A's run whole; and
/// `--resume A/checkpoint.bin --overwrite` into a copy of B (its manifest naming B's run)
/// gives that folder to A's run whole — at the end every file byte-identical to A's own
/// folder resumed to the end, none of B's left — while a checkpoint of other parameters
/// (B's tolerance) is refused before that folder changes. Every program with `--resume` but the sliders (whose series row of the step is
/// checked, `crates/rsf/tests/suite/run_folder.rs`): BP1, BP3, BP5 with both kernels, BP6
/// A and C, BP7, BP8 and the two network programs, through the guard; A stops at a step cap
/// with a checkpoint at a step where B (another tolerance, the same checkpoint interval)
/// has its resume log's state too.
#[test]
fn a_checkpoint_resumed_into_another_runs_folder_is_refused_and_changes_nothing() {
    let scratch =
        Scratch(std::env::temp_dir().join(format!("rsf-identity-{}", std::process::id())));
    let dir = scratch.0.clone();
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let every = ["--checkpoint-every", "100"];
    // Program and variant; A's flags; B's other flag (another trajectory from the first
    // steps).
    let table = [
        "seas_bp5 okada; --dx 4000 --end-years 300; --tolerance 1e-7",
        "seas_bp5 fe; --kernel fe --dx 10000 --end-years 20; --tolerance 1e-7",
        "seas_bp3 ; --dx 2000 --end-years 300; --tolerance 1e-6",
        "seas_bp1 ; --dz 1000 --domain-km 60 --end-years 300; --rk-tolerance 1e-7",
        "seas_bp6 a; --dz 200 --end-years 2; --tolerance 1e-8",
        "seas_bp6 c; --variant c --elastic fe --dz 500 --domain-km 40 --end-years 2; --tolerance 1e-8",
        "seas_bp8 ; --dx 80 --end-days 8; --tolerance 1e-8",
        "seas_bp7 ; --dx 80 --end-years 0.002; --tolerance 1e-8",
        "stepover ; --dx 500 --end-years 300; --tolerance 1e-7",
        "bp5_pair ; --dx 4000 --end-years 300; --tolerance 1e-7",
    ];
    let programs: Vec<(&str, &str, Vec<&str>, Vec<&str>)> = table
        .iter()
        .map(|row| {
            let parts: Vec<&str> = row.split("; ").collect();
            let (program, variant) = parts[0].split_once(' ').unwrap();
            let flags = |i: usize| parts[i].split(' ').collect::<Vec<_>>();
            (program, variant, flags(1), flags(2))
        })
        .collect();
    let failures = Mutex::new(Vec::new());
    // Two programs at a time (the machine's cores are shared).
    for pair in programs.chunks(2) {
        std::thread::scope(|scope| {
            for (program, variant, flags, other) in pair {
                let (dir, failures, every) = (&dir, &failures, &every);
                scope.spawn(move || {
                    let args = |extra: &[&str]| -> Vec<String> {
                        flags
                            .iter()
                            .chain(every)
                            .chain(extra)
                            .chain(&["--threads", "1"])
                            .map(|s| (*s).to_owned())
                            .collect()
                    };
                    let name = format!("{program}{variant}");
                    let [a, b, b2] = ["a", "b", "b2"].map(|x| format!("{name}_{x}"));
                    let limit = Duration::from_secs(300);
                    let go = |extra: &[&str]| run(program, &args(extra), dir, limit);
                    let first = go(&["--out", &a, "--max-steps", "200"]);
                    let mut second = args(&["--out", &b]);
                    second.extend(other.iter().map(|s| (*s).to_owned()));
                    let second = run(program, &second, dir, limit);
                    let fail = |m: String| failures.lock().unwrap().push(format!("{name}: {m}"));
                    if first.ok || !first.stderr.contains("step cap") || !second.ok {
                        return fail(format!("the two runs: {}\n{}", first.stderr, second.stderr));
                    }
                    let before = snapshot(&dir.join(&b));
                    let checkpoint = format!("{a}/checkpoint.bin");
                    let into_b = go(&["--out", &b, "--resume", &checkpoint]);
                    if into_b.ok
                        || !(into_b.stderr.contains("another run")
                            && into_b.stderr.contains("--overwrite"))
                    {
                        fail(format!("resumed into B: {}", into_b.stderr));
                    }
                    if snapshot(&dir.join(&b)) != before {
                        fail("B's files were changed".into());
                    }
                    // A copy of B with its manifest; then B without it.
                    copy_folder(&dir.join(&b), &dir.join(&b2));
                    std::fs::remove_file(dir.join(&b).join("rsf-run.txt")).unwrap();
                    let before = run_files(&dir.join(&b));
                    let spliced = go(&["--out", &b, "--resume", &checkpoint]);
                    // Refused by B's files, B unchanged — or, where B's files up to the
                    // step are A's bytes (a run that diverges later), continued into A's
                    // run whole (compared with A's own folder below).
                    if !spliced.ok {
                        if !spliced.stderr.contains("splice") {
                            fail(format!(
                                "resumed into B without its manifest: {}",
                                spliced.stderr
                            ));
                        }
                        if run_files(&dir.join(&b)) != before {
                            fail("B's files were changed by the refused resume".into());
                        }
                        let manifest = std::fs::read_to_string(dir.join(&b).join("rsf-run.txt"))
                            .unwrap_or_default();
                        if manifest.contains("run=") {
                            fail(format!("the refused resume left a run id in B: {manifest}"));
                        }
                    }
                    // With a flag that changes the trajectory (B's, a field of the
                    // fingerprint): refused by that field before B's copy changes (the
                    // plan's fingerprint; the folder was given to A's run first, then
                    // refused, before).
                    let before = snapshot(&dir.join(&b2));
                    let mut changed = args(&["--out", &b2, "--resume", &checkpoint, "--overwrite"]);
                    changed.extend(other.iter().map(|s| (*s).to_owned()));
                    let changed = run(program, &changed, dir, limit);
                    if changed.ok || !changed.stderr.contains("tolerance") {
                        fail(format!(
                            "--overwrite with another tolerance: {}",
                            changed.stderr
                        ));
                    }
                    if snapshot(&dir.join(&b2)) != before {
                        fail("B's copy was changed by a checkpoint of other parameters".into());
                    }
                    let overwrite = go(&["--out", &b2, "--resume", &checkpoint, "--overwrite"]);
                    if !overwrite.ok {
                        fail(format!("--overwrite into B: {}", overwrite.stderr));
                    }
                    let into_a = go(&["--out", &a, "--resume", &checkpoint]);
                    if !into_a.ok {
                        return fail(format!("resumed into its own folder: {}", into_a.stderr));
                    }
                    let whole = run_files(&dir.join(&a));
                    let mut given = vec![("--overwrite", &b2)];
                    if spliced.ok {
                        given.push(("a resume without B's manifest", &b));
                    }
                    for (how, folder) in given {
                        let given = run_files(&dir.join(folder));
                        if whole != given {
                            let differ: Vec<_> = whole
                                .keys()
                                .chain(given.keys())
                                .filter(|k| whole.get(*k) != given.get(*k))
                                .collect();
                            fail(format!(
                                "the folder continued by {how} is not A's run whole: {differ:?}"
                            ));
                        }
                    }
                });
            }
        });
    }
    let failures = failures.into_inner().unwrap();
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// A scratch folder removed when dropped, also when the test fails (its runs' folders
/// hold about 240 MB).
struct Scratch(std::path::PathBuf);

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Copies the folder `from` (files and folders in it) to `to`.
fn copy_folder(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let p = e.unwrap().path();
        let target = to.join(p.file_name().unwrap());
        if p.is_dir() {
            copy_folder(&p, &target);
        } else {
            std::fs::copy(&p, &target).unwrap();
        }
    }
}

/// The programs of the MPI crate (`crates/rsf-mpi/src/bin/`) go through the guard like the
/// examples: each binary is listed in `rsf_programs::on_ranks::programs` (a binary added
/// later and not listed fails here), and the careless inputs of its flags are refused by
/// its guard in this process — no MPI needed — naming the flag, folders untouched.
#[test]
fn the_mpi_programs_refuse_careless_inputs_without_mpi() {
    let bin = Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/rsf-mpi/src/bin");
    let mut binaries: Vec<String> = std::fs::read_dir(bin)
        .unwrap()
        .map(|e| {
            let p = e.unwrap().path();
            let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
            stem
        })
        .collect();
    binaries.sort();
    let listed = rsf_programs::on_ranks::programs();
    for b in &binaries {
        assert!(
            listed.iter().any(|p| p.name == b),
            "the MPI binary `{b}` is not under the guard: list it in rsf_programs::on_ranks"
        );
    }
    assert!(
        binaries.contains(&"distributed_sweep".to_owned()),
        "{binaries:?}"
    );
    let dir = scratch("careless-mpi");
    let _busy = hold_lock(&dir.join("busy"));
    let before = snapshot(&dir);
    let mut failures = Vec::new();
    let mut count = 0;
    for p in &listed {
        let help = (p.command)().render_long_help().to_string();
        let flags: BTreeSet<String> = help
            .lines()
            .filter_map(|l| {
                let name = l.trim_start().strip_prefix("--")?;
                let end = name
                    .find(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
                    .unwrap_or(name.len());
                Some(format!("--{}", &name[..end]))
            })
            .collect();
        let mut cases = generic_cases(p.name, &flags);
        if p.name == "distributed_sweep" {
            cases.extend([
                case(p.name, &["--sweeps", "1e12"], "--sweeps"),
                case(p.name, &["--refinements", "12"], "--max-memory-gb"),
                case(p.name, &["--levels", "2"], "--vcycle"),
                case(p.name, &["--repetitions", "1e9"], "--repetitions"),
                case(p.name, &["--out", "main_job"], "--overwrite"),
            ]);
        }
        for (i, c) in cases.iter().enumerate() {
            count += 1;
            // Paths inside the scratch folder (this process's working folder is not it).
            let mut args = vec![std::ffi::OsString::from(p.name)];
            let mut follows_path = false;
            for a in &c.args {
                let path_flag =
                    matches!(a.as_str(), "--out" | "--figures" | "--scene" | "--config");
                args.push(if follows_path {
                    dir.join(a).into_os_string()
                } else {
                    a.into()
                });
                follows_path = path_flag;
            }
            if flags.contains("--out") && !c.args.iter().any(|a| a == "--out") {
                args.extend([
                    "--out".into(),
                    dir.join(format!("fresh/mpi_{}_{i}", p.name)).into(),
                ]);
            }
            match (p.prepare)(args.clone()) {
                Ok(()) => failures.push(format!("{} {args:?}: accepted", p.name)),
                Err(e) => {
                    let mut text = e.to_string();
                    let mut cause = e.source();
                    while let Some(c) = cause {
                        text.push_str(&format!("\n{c}"));
                        cause = c.source();
                    }
                    if !text.contains(&c.names) {
                        failures.push(format!(
                            "{} {args:?}: the error does not name `{}`:\n{text}",
                            p.name, c.names
                        ));
                    }
                }
            }
        }
    }
    for (path, bytes) in &before {
        if snapshot(&dir).get(path) != Some(bytes) {
            failures.push(format!("{} was changed", path.display()));
        }
    }
    println!("{} MPI programs, {count} cases", listed.len());
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    std::fs::remove_dir_all(&dir).ok();
}
