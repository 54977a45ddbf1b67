//! The SEAS series in one HDF5 file: read back (hdf5-metno) every dataset equals the numbers
//! of its text file, read here by the file's own lines (`#` lines, field lines, rows split
//! at spaces); a run continued by a second run call rewrites the file with the new rows;
//! the program `seas_bp1` of this crate writes the root program's files and `seas.h5`,
//! not on a refused run nor at a step cap, and again when the stopped run is resumed to its
//! end; `seas_hdf5` writes the file of a folder.

use std::path::{Path, PathBuf};
use std::process::Command;

use hdf5::types::VarLenUnicode;
use rsf::observe::FileMode;
use rsf::{Observer, Until};
use rsf_hdf5::{SeasSeries, SEAS_SERIES_FILE};
use rsf_scenes::{SeasBp1, SeasBp1Grid};
use rsf_seas::{SeasOutput, SeasSetup, SECONDS_PER_YEAR};

// rsf-seas's test helpers (a part of them).
#[allow(dead_code, unused_imports)]
#[path = "../../rsf-seas/tests/suite/common.rs"]
mod seas_common;

const SEAS_BP1: &str = env!("CARGO_BIN_EXE_seas_bp1");
const SEAS_HDF5: &str = env!("CARGO_BIN_EXE_seas_hdf5");

/// A fresh path `name` under the target directory's tmp: the folder or file of an earlier
/// run removed.
fn folder(name: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    if path.is_dir() {
        std::fs::remove_dir_all(&path).ok();
    } else {
        std::fs::remove_file(&path).ok();
    }
    path
}

/// A text file read by its lines: the `#` lines' `key=value` pairs, the field lines (those
/// before the first row of numbers) and the rows.
struct Text {
    header: Vec<(String, String)>,
    fields: Vec<Vec<String>>,
    rows: Vec<Vec<f64>>,
}

fn read_text(path: &Path) -> Text {
    let text = std::fs::read_to_string(path).unwrap();
    let mut t = Text {
        header: Vec::new(),
        fields: Vec::new(),
        rows: Vec::new(),
    };
    for line in text.lines() {
        if let Some(h) = line.strip_prefix("# ") {
            if let Some((k, v)) = h.split_once('=').filter(|(k, _)| !k.contains(' ')) {
                t.header.push((k.to_owned(), v.to_owned()));
            }
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        match words[0].parse::<f64>() {
            Ok(_) => t
                .rows
                .push(words.iter().map(|w| w.parse().unwrap()).collect()),
            Err(_) => t.fields.push(words.iter().map(|w| w.to_string()).collect()),
        }
    }
    t
}

/// Bits, so that NaN compares equal to NaN.
fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Every SEAS file of `dir` (and `events.csv`) against its group of `dir/seas.h5`; the
/// number of groups.
fn check_series(dir: &Path) -> usize {
    let file = hdf5::File::open(dir.join(SEAS_SERIES_FILE)).expect("seas.h5");
    let mut groups = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_str().unwrap().to_owned();
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        if !text.starts_with("# This is the file header:\n") {
            continue;
        }
        let t = read_text(&path);
        let g = file
            .group(&name)
            .unwrap_or_else(|_| panic!("no group {name}"));
        for (k, v) in &t.header {
            let a: VarLenUnicode = g.attr(k).unwrap().read_scalar().unwrap();
            assert_eq!(a.as_str(), v, "{name}: attribute {k}");
        }
        let columns = t.fields.last().unwrap();
        let profile = t.fields.len() == 2;
        let rows = if profile { &t.rows[1..] } else { &t.rows[..] };
        for (j, c) in columns.iter().enumerate() {
            let d = g.dataset(c).unwrap();
            let got: Vec<f64> = d.read_raw().unwrap();
            let want: Vec<f64> = if profile && j + 1 == columns.len() {
                assert_eq!(d.shape(), [rows.len(), rows[0].len() - j], "{name}/{c}");
                rows.iter().flat_map(|r| r[j..].to_vec()).collect()
            } else {
                assert_eq!(d.shape(), [rows.len()], "{name}/{c}");
                rows.iter().map(|r| r[j]).collect()
            };
            assert_eq!(bits(&got), bits(&want), "{name}/{c}");
            let description: VarLenUnicode = d.attr("description").unwrap().read_scalar().unwrap();
            assert!(!description.as_str().is_empty(), "{name}/{c}");
        }
        if profile {
            let positions: Vec<f64> = g.dataset(&t.fields[0][0]).unwrap().read_raw().unwrap();
            assert_eq!(positions[..], t.rows[0][columns.len() - 1..], "{name}");
        }
        groups += 1;
    }
    let events = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    let mut lines = events.lines();
    let names: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let g = file.group("events").unwrap();
    for (j, n) in names.iter().enumerate() {
        let got: Vec<f64> = g.dataset(n).unwrap().read_raw().unwrap();
        let want: Vec<f64> = rows.iter().map(|r| r[j]).collect();
        assert_eq!(bits(&got), bits(&want), "events/{n}");
    }
    assert_eq!(file.member_names().unwrap().len(), groups + 1);
    groups
}

/// BP1 made small: a 10 km fault on a 500 m grid in a 20 km domain (five stations).
fn small_bp1() -> (SeasBp1, SeasBp1Grid, SeasSetup) {
    let (bp1, grid) = seas_common::small_bp1(&SeasBp1::default());
    let setup = seas_common::five_stations(&bp1, grid.dz, "2026-11-28");
    (bp1, grid, setup)
}

#[test]
fn the_series_file_holds_the_text_files_numbers_and_follows_a_continued_run() {
    let (bp1, grid, setup) = small_bp1();
    let dir = folder("series_observer");
    let model = bp1.model(&grid, false).unwrap();
    let mut ode = bp1
        .fault_ode(model, bp1.fault_ode_options(1e-6).unwrap())
        .unwrap();
    let mut output = SeasOutput::new(
        &dir,
        rsf::Stepping::model(&ode),
        ode.problem().friction_laws(),
        setup,
        FileMode::Create,
    )
    .unwrap();
    output
        .write_initial_state(rsf::Stepping::model(&ode), ode.state())
        .unwrap();
    let mut series = SeasSeries::new(&dir, FileMode::Create).unwrap();
    let rows = |dir: &Path| {
        let f = hdf5::File::open(dir.join(SEAS_SERIES_FILE)).unwrap();
        f.dataset("fltst_dp000/t").unwrap().shape()[0]
    };
    // To 40 years, then on through the first event (about 80 years on the small fault).
    let mut before = 0;
    for years in [40.0, 150.0] {
        let mut observers: [&mut dyn Observer<2, 1>; 2] = [&mut output, &mut series];
        ode.run_until(Until::Time(years * SECONDS_PER_YEAR), &mut observers)
            .unwrap();
        assert_eq!(check_series(&dir), 5 + 1, "five stations and devol.dat");
        assert!(rows(&dir) > before, "the second run call's rows");
        before = rows(&dir);
    }
    let f = hdf5::File::open(dir.join(SEAS_SERIES_FILE)).unwrap();
    assert!(f.dataset("events/t_start_s").unwrap().shape()[0] >= 1);
    // A new series into a folder with one is refused; Overwrite replaces it.
    assert!(SeasSeries::new(&dir, FileMode::Create).is_err());
    assert!(SeasSeries::new(&dir, FileMode::Overwrite).is_ok());
    std::fs::remove_dir_all(&dir).ok();
}

/// `seas_bp1` of this crate with `args` after `--out dir` and coarse flags.
fn seas_bp1(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::new(SEAS_BP1)
        .args(["--out", dir.to_str().unwrap()])
        .args([
            "--dz",
            "400",
            "--end-years",
            "300",
            "--threads",
            "1",
            "--date",
            "2026-11-28",
        ])
        .args(args)
        .output()
        .unwrap()
}

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn the_program_writes_its_series_also_after_a_resume_and_never_on_a_refusal() {
    let dir = folder("seas_bp1_program");
    let h5 = dir.join(SEAS_SERIES_FILE);
    // Stopped at a step cap (an error exit, the files resumable): no series yet.
    let out = seas_bp1(&dir, &["--checkpoint-every", "500", "--max-steps", "1000"]);
    assert!(!out.status.success(), "{}", stderr(&out));
    assert!(
        !h5.exists(),
        "a run stopped at its step cap writes no seas.h5"
    );
    // Resumed to its end: the series of the whole run.
    let checkpoint = dir.join("checkpoint.bin");
    let out = seas_bp1(
        &dir,
        &[
            "--checkpoint-every",
            "500",
            "--resume",
            checkpoint.to_str().unwrap(),
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stderr(&out).contains("seas.h5"), "{}", stderr(&out));
    assert_eq!(check_series(&dir), 12 + 1, "twelve stations and devol.dat");
    // A second run into the folder is refused by the program: seas.h5 is untouched.
    let bytes = std::fs::read(&h5).unwrap();
    let out = seas_bp1(&dir, &[]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("--overwrite"), "{}", stderr(&out));
    assert_eq!(std::fs::read(&h5).unwrap(), bytes);
    // seas_hdf5 writes the same numbers from the folder, to another file on request.
    let other = folder("seas_bp1_program_copy.h5");
    let out = Command::new(SEAS_HDF5)
        .arg(&dir)
        .args(["--output", other.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let (a, b) = (
        hdf5::File::open(&h5).unwrap(),
        hdf5::File::open(&other).unwrap(),
    );
    let x: Vec<f64> = a.dataset("devol.dat/slip").unwrap().read_raw().unwrap();
    let y: Vec<f64> = b.dataset("devol.dat/slip").unwrap().read_raw().unwrap();
    assert_eq!(bits(&x), bits(&y));
    // … and refuses to replace it without --overwrite, or a folder without SEAS files.
    let again = Command::new(SEAS_HDF5)
        .arg(&dir)
        .args(["--output", other.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!again.status.success() && stderr(&again).contains("--overwrite"));
    let empty = folder("no_seas_files");
    std::fs::create_dir_all(&empty).unwrap();
    let none = Command::new(SEAS_HDF5).arg(&empty).output().unwrap();
    assert!(!none.status.success() && stderr(&none).contains("holds no SEAS file"));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::remove_file(&other).ok();
}
