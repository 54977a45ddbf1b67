//! Every program against a careless user's inputs (issue 38's probe), table-driven: each
//! case runs the built example binary in a scratch folder holding another program's
//! finished run, and must exit non-zero within seconds, print `error: …` naming the flag,
//! key or path the user wrote (never a Debug dump or a panic), and leave every file of the
//! scratch folder byte-identical.
//!
//! The binaries are the examples `cargo test` builds beside this test
//! (`target/<profile>/examples/`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The example binary `name`, built by `cargo test` beside this test's executable.
fn example(name: &str) -> PathBuf {
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

/// Every file under `dir` (recursively) with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                files.insert(p.clone(), std::fs::read(&p).unwrap());
            }
        }
    }
    files
}

/// Runs `program` with `args` in `dir` (at most 60 s): its exit success and stderr.
fn run(program: &str, args: &[&str], dir: &Path) -> (bool, String) {
    let mut child = Command::new(example(program))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            use std::io::Read;
            child
                .stderr
                .take()
                .unwrap()
                .read_to_string(&mut err)
                .unwrap();
            return (status.success(), err);
        }
        if start.elapsed() > Duration::from_secs(60) {
            child.kill().ok();
            panic!("{program} {args:?} still running after 60 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The plate-like fixture with a duplicated node: a crack nobody declared.
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

#[test]
fn careless_inputs_are_refused_naming_what_the_user_wrote_and_change_nothing() {
    let dir = std::env::temp_dir().join(format!("rsf-hostile-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    // A finished run of the main job (its manifest and summary) and a plain file.
    let main_job = dir.join("main_job");
    std::fs::create_dir_all(&main_job).unwrap();
    std::fs::write(
        main_job.join("rsf-run.txt"),
        "program=pipping_slider\noutput=summary.json\noutput=timeseries.csv\n",
    )
    .unwrap();
    std::fs::write(main_job.join("summary.json"), "{\"steps\": 10000}\n").unwrap();
    std::fs::write(main_job.join("timeseries.csv"), "t,max_v\n0,1e-6\n").unwrap();
    std::fs::write(dir.join("a_file"), "not a folder\n").unwrap();
    std::fs::write(dir.join("huge.toml"), "level = 1e300\n").unwrap();
    let mesh = cracked_arc_mesh(&dir);
    let mesh = mesh.to_str().unwrap();

    // (program, arguments, what the error must name)
    let cases: &[(&str, &[&str], &str)] = &[
        ("seas_bp1", &["--out", "main_job"], "--overwrite"),
        (
            "seas_bp1",
            &["--out", "x", "--ratio", "1", "--end-years", "50"],
            "estimated",
        ),
        ("seas_bp1", &["--out", "x", "--dz", "1e-300"], "estimated"),
        (
            "seas_bp1",
            &["--out", "x", "--domain-km", "1e300"],
            "estimated",
        ),
        (
            "seas_bp1",
            &["--out", "x", "--rk-tolerance", "0"],
            "rk_tolerance",
        ),
        (
            "seas_bp1",
            &["--out", "x", "--state-change-cap", "nan"],
            "state-change-cap",
        ),
        (
            "seas_bp1",
            &["--out", "x", "--max-memory-gb", "nan"],
            "max_memory_gb",
        ),
        (
            "inclined_block",
            &["--level", "1", "--steps", "1e12", "--out", "x"],
            "steps",
        ),
        ("inclined_block", &["--out", "a_file"], "a_file"),
        ("inclined_block", &["--out", "main_job"], "--overwrite"),
        (
            "curved_fault",
            &["--level", "0", "--steps", "1e12", "--out", "x"],
            "steps",
        ),
        ("curved_fault", &["--out", "a_file"], "a_file"),
        (
            "curved_fault",
            &["--level", "0", "--mesh", mesh, "--out", "x"],
            "coincide",
        ),
        ("slider_3d", &["--width", "1e-300", "--out", "x"], "width"),
        (
            "slider_3d",
            &["--level", "6", "--out", "x"],
            "--max-memory-gb",
        ),
        ("slider_3d", &["--out", "main_job"], "--overwrite"),
        (
            "pipping_slider",
            &["--max-output-gb", "nan", "--out", "x"],
            "max_output_gb",
        ),
        (
            "pipping_slider",
            &["--scene", "huge.toml", "--out", "x"],
            "huge.toml",
        ),
        ("long_run", &["--compare-until", "nan"], "compare-until"),
        (
            "spring_block",
            &["--integrator", "newmark", "--mass", "0"],
            "mass",
        ),
        ("spring_block", &["--out", "main_job"], "--overwrite"),
    ];
    let before = snapshot(&dir);
    for (i, &(program, args, name)) in cases.iter().enumerate() {
        // Each case its own new output folder `x<i>`.
        let fresh = format!("x{i}");
        let args: Vec<&str> = args
            .iter()
            .map(|&a| if a == "x" { fresh.as_str() } else { a })
            .collect();
        let args = args.as_slice();
        let start = Instant::now();
        let (ok, err) = run(program, args, &dir);
        let seconds = start.elapsed().as_secs_f64();
        assert!(!ok, "{program} {args:?} succeeded");
        assert!(
            err.contains("error") && err.contains(name),
            "{program} {args:?}: the error does not name `{name}`:\n{err}"
        );
        assert!(
            !err.contains("panicked") && !err.contains("InvalidParameter {"),
            "{program} {args:?}: a panic or a Debug dump:\n{err}"
        );
        assert!(
            err.len() < 2000,
            "{program} {args:?}: a {}-byte message",
            err.len()
        );
        assert!(
            seconds < 30.0,
            "{program} {args:?}: refused after {seconds:.1} s"
        );
        // A refused run leaves the scratch folder as it was (a new `x` may appear empty or
        // with a manifest; the files that existed are untouched).
        let after = snapshot(&dir);
        for (path, bytes) in &before {
            assert_eq!(
                after.get(path),
                Some(bytes),
                "{program} {args:?} changed {}",
                path.display()
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
