//! `--hdf5 N` of this crate's binaries on tiny runs: the sliders' fields equal their VTU
//! frames bit for bit (two writers of one state); the SEAS programs' fault fields equal
//! their benchmark station files to the files' printed digits (two writers: the text
//! files round to 7 significant digits); a run stopped at `--max-steps` and resumed ends
//! with the uninterrupted run's datasets bit for bit and the same index; a resume with
//! another interval is refused, naming it, and leaves the file usable.

use std::path::Path;
use std::process::{Command, Output};

mod common;
use common::{bits, temp_dir, vtu_field};

/// Runs `bin` with `args`; its output.
fn run(bin: &str, args: &[&str]) -> Output {
    Command::new(bin)
        .args(args)
        .output()
        .expect("the binary runs")
}

/// Runs `bin` with `args` and asserts that it succeeds.
fn run_ok(bin: &str, args: &[&str]) {
    let out = run(bin, args);
    assert!(
        out.status.success(),
        "{bin} {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `path` as a string argument.
fn arg(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

/// Dataset `name` of `file` as doubles (converted from `u64` where it is stored so).
fn read(file: &hdf5::File, name: &str) -> Vec<f64> {
    let d = file.dataset(name).unwrap_or_else(|e| panic!("{name}: {e}"));
    d.read_raw::<f64>()
        .or_else(|_| {
            d.read_raw::<u64>()
                .map(|v| v.into_iter().map(|x| x as f64).collect())
        })
        .unwrap()
}

/// Every dataset of a fields file, by name.
fn datasets(path: &Path) -> Vec<(String, Vec<u64>, Vec<usize>)> {
    let file = hdf5::File::open(path).unwrap();
    let mut names = vec!["time".to_owned(), "step".to_owned()];
    for g in ["mesh", "fields"] {
        let group = file.group(g).unwrap();
        for n in group.member_names().unwrap() {
            names.push(format!("{g}/{n}"));
        }
    }
    names
        .into_iter()
        .map(|n| {
            let shape = file.dataset(&n).unwrap().shape();
            let values = bits(&read(&file, &n));
            (n, values, shape)
        })
        .collect()
}

/// The frames of the fields file `dir/fields.h5` equal the VTU frames of `dir/frames`
/// (`components` per vertex of each field), bit for bit; the steps of its frames.
fn assert_fields_equal_frames(dir: &Path) -> Vec<u64> {
    let file = hdf5::File::open(dir.join("fields.h5")).unwrap();
    let steps: Vec<u64> = file.dataset("step").unwrap().read_raw().unwrap();
    let n = file.dataset("mesh/points").unwrap().shape()[0];
    for (name, c, _) in rsf::observe::POINT_FIELDS {
        let all = read(&file, &format!("fields/{name}"));
        assert_eq!(all.len(), steps.len() * n * c, "{name}");
        for (i, s) in steps.iter().enumerate() {
            let vtu = vtu_field(&dir.join(format!("frames/frame_{s:06}.vtu")), name);
            let frame = &all[i * n * c..(i + 1) * n * c];
            assert_eq!(bits(frame), bits(&vtu), "{name} at step {s}");
        }
    }
    steps
}

#[test]
fn slider_3d_fields_equal_its_frames_and_a_resumed_run_continues_them() {
    let bin = env!("CARGO_BIN_EXE_slider_3d");
    let dir = temp_dir("slider-3d-hdf5");
    let (whole, parts) = (dir.join("whole"), dir.join("parts"));
    let flags = ["--level", "0", "--steps", "40", "--threads", "1"];
    let fields = ["--hdf5", "5", "--frame-every", "5"];
    run_ok(
        bin,
        &[&flags[..], &fields, &["--out", arg(&whole)]].concat(),
    );
    let steps = assert_fields_equal_frames(&whole);
    assert_eq!(steps, (1..=8).map(|k| 5 * k).collect::<Vec<u64>>());
    // Stopped at step 20 with a checkpoint (an error exit), then resumed to the end.
    let stop = ["--checkpoint-every", "10", "--max-steps", "20"];
    let out = run(
        bin,
        &[&flags[..], &fields, &stop, &["--out", arg(&parts)]].concat(),
    );
    assert!(!out.status.success(), "stopped at --max-steps");
    let checkpoint = parts.join("checkpoint.bin");
    // Another interval is refused, naming it; the file is left as it was.
    let out = run(
        bin,
        &[
            &flags[..],
            &["--hdf5", "10", "--frame-every", "5"],
            &["--resume", arg(&checkpoint), "--out", arg(&parts)],
        ]
        .concat(),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("hdf5_every"),
        "{stderr}"
    );
    run_ok(
        bin,
        &[
            &flags[..],
            &fields,
            &["--resume", arg(&checkpoint), "--out", arg(&parts)],
        ]
        .concat(),
    );
    assert_eq!(
        datasets(&parts.join("fields.h5")),
        datasets(&whole.join("fields.h5"))
    );
    let index = |d: &Path| std::fs::read(d.join("fields.xmf")).unwrap();
    assert_eq!(index(&parts), index(&whole));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn pipping_slider_fields_equal_its_frames() {
    let bin = env!("CARGO_BIN_EXE_pipping_slider");
    let dir = temp_dir("pipping-slider-hdf5");
    let flags = ["--level", "1", "--steps", "60", "--threads", "1"];
    let fields = ["--hdf5", "20", "--frame-every", "20"];
    run_ok(bin, &[&flags[..], &fields, &["--out", arg(&dir)]].concat());
    assert_eq!(assert_fields_equal_frames(&dir), [20, 40, 60]);
    std::fs::remove_dir_all(&dir).ok();
}

/// The rows (time and columns) of a SEAS station file.
fn station_rows(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('t'))
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect()
}

/// The fault node of `file` nearest to `point` (m).
fn node_at(file: &hdf5::File, point: [f64; 3]) -> usize {
    let points = read(file, "mesh/points");
    let distance = |k: usize| -> f64 {
        (0..3)
            .map(|c| (points[3 * k + c] - point[c]).powi(2))
            .sum::<f64>()
    };
    (0..points.len() / 3)
        .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
        .unwrap()
}

/// For every row of the station file `station` after t = 0: the frame of the fields file
/// at its time (every step is a frame: `--hdf5 1`) and the row. At least `least` rows.
fn frames_of_rows(file: &hdf5::File, station: &Path, least: usize) -> Vec<(usize, Vec<f64>)> {
    let times = read(file, "time");
    let rows: Vec<(usize, Vec<f64>)> = station_rows(station)
        .into_iter()
        .filter(|r| r[0] > 0.0)
        .map(|r| {
            // The files print the time with 14 significant digits.
            let i = times
                .iter()
                .position(|t| (t - r[0]).abs() <= 1e-13 * r[0])
                .unwrap_or_else(|| panic!("no frame at t = {} s", r[0]));
            (i, r)
        })
        .collect();
    assert!(rows.len() >= least, "{} rows", rows.len());
    rows
}

/// `a` equals `b` to the 7 significant digits of the station files (the last one rounded).
fn digits7(a: f64, b: f64) -> bool {
    (a - b).abs() <= 5.01e-7 * b.abs().max(1e-300) + 1e-300
}

#[test]
fn seas_bp1_fault_fields_equal_its_station_files_and_a_resumed_run_continues_them() {
    let bin = env!("CARGO_BIN_EXE_seas_bp1");
    let dir = temp_dir("seas-bp1-hdf5");
    let (whole, parts) = (dir.join("whole"), dir.join("parts"));
    let flags = [
        "--dz",
        "400",
        "--end-years",
        "2",
        "--every-step",
        "--threads",
        "1",
        "--date",
        "2026-11-29",
    ];
    run_ok(
        bin,
        &[&flags[..], &["--hdf5", "1", "--out", arg(&whole)]].concat(),
    );
    let file = hdf5::File::open(whole.join("fields.h5")).unwrap();
    let n = file.dataset("mesh/points").unwrap().shape()[0];
    // The fault's segments: consecutive nodes along it.
    let cells = file.dataset("mesh/cells").unwrap();
    assert_eq!(cells.shape(), [n - 1, 2]);
    let topology: hdf5::types::VarLenUnicode =
        cells.attr("topology").unwrap().read_scalar().unwrap();
    assert_eq!(topology.as_str(), "Polyline");
    let (slip, rate) = (read(&file, "fields/slip"), read(&file, "fields/slip_rate"));
    let (tau, alpha) = (
        read(&file, "fields/shear_traction"),
        read(&file, "fields/state_alpha"),
    );
    // Stations at depths 0 and 10 km (nodes of the 400 m grid on the fault x = 0; the
    // model's y is the depth).
    for (name, depth) in [("fltst_dp000", 0.0), ("fltst_dp100", 10e3)] {
        let k = node_at(&file, [0.0, depth, 0.0]);
        for (i, row) in frames_of_rows(&file, &whole.join(name), 10) {
            // Antiplane: the slip is the z component.
            let at = |f: &[f64], c: usize| f[i * n * c + k * c + (c - 1)];
            assert!(digits7(at(&slip, 3), row[1]), "{name} slip {row:?}");
            assert!(
                (rate[i * n + k].log10() - row[2]).abs() <= 5.01e-6 * row[2].abs(),
                "{name} slip rate {row:?}"
            );
            assert!(digits7(at(&tau, 1) / 1e6, row[3]), "{name} shear {row:?}");
            let state = alpha[i * n + k] / std::f64::consts::LN_10;
            assert!(
                (state - row[4]).abs() <= 5.01e-6 * row[4].abs(),
                "{name} state {row:?}"
            );
        }
    }
    drop(file);
    // Stopped at step 20 with a checkpoint, resumed to the end: the same datasets.
    let out = run(
        bin,
        &[
            &flags[..],
            &[
                "--hdf5",
                "1",
                "--checkpoint-every",
                "10",
                "--max-steps",
                "20",
            ],
            &["--out", arg(&parts)],
        ]
        .concat(),
    );
    assert!(!out.status.success(), "stopped at --max-steps");
    let checkpoint = parts.join("checkpoint.bin");
    let resume = ["--resume", arg(&checkpoint), "--out", arg(&parts)];
    // Another interval: refused by the file (it records its interval), nothing cut.
    let out = run(bin, &[&flags[..], &["--hdf5", "2"], &resume].concat());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("--hdf5 1"),
        "{stderr}"
    );
    run_ok(bin, &[&flags[..], &["--hdf5", "1"], &resume].concat());
    assert_eq!(
        datasets(&parts.join("fields.h5")),
        datasets(&whole.join("fields.h5"))
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn seas_bp5_fault_fields_of_the_okada_fault_are_its_cells_and_equal_a_station_file() {
    let bin = env!("CARGO_BIN_EXE_seas_bp5");
    let dir = temp_dir("seas-bp5-hdf5");
    run_ok(
        bin,
        &[
            "--dx",
            "4000",
            "--end-years",
            "1",
            "--threads",
            "1",
            "--date",
            "2026-11-29",
            "--hdf5",
            "1",
            "--out",
            arg(&dir),
        ],
    );
    let file = hdf5::File::open(dir.join("fields.h5")).unwrap();
    // 25 × 10 cells of 4 km, a poly-vertex at each centre (no volume mesh).
    assert_eq!(file.dataset("mesh/points").unwrap().shape()[0], 250);
    assert_eq!(file.dataset("mesh/cells").unwrap().shape(), [250, 1]);
    let topology: hdf5::types::VarLenUnicode = file
        .dataset("mesh/cells")
        .unwrap()
        .attr("topology")
        .unwrap()
        .read_scalar()
        .unwrap();
    assert_eq!(topology.as_str(), "Polyvertex");
    // The station 24 km along strike (−x₂), 10 km down-dip: a cell's centre.
    let station = dir.join("fltst_strk-24dp+10");
    fault_fields_equal_station(&file, &station, [0.0, -24e3, -10e3], 7, 10);
    drop(file);
    std::fs::remove_dir_all(&dir).ok();
}

/// The fault's fields of `file` at the cell centred at `point` equal the strike–dip
/// station file `station` at every frame of its rows (at least `least`): `slip_2` to the
/// files' 7 digits, `log10 θ` (the file's column `state_column`) to 6.
fn fault_fields_equal_station(
    file: &hdf5::File,
    station: &Path,
    point: [f64; 3],
    state_column: usize,
    least: usize,
) {
    let n = file.dataset("mesh/points").unwrap().shape()[0];
    let k = node_at(file, point);
    let (slip, alpha) = (read(file, "fields/slip"), read(file, "fields/state_alpha"));
    for (i, row) in frames_of_rows(file, station, least) {
        assert!(digits7(slip[3 * (i * n + k) + 1], row[1]), "slip_2 {row:?}");
        let state = alpha[i * n + k] / std::f64::consts::LN_10;
        let expected = row[state_column];
        assert!(
            (state - expected).abs() <= 5.01e-6 * expected.abs(),
            "state {row:?}"
        );
    }
}

#[test]
fn seas_bp7_and_bp8_fault_fields_are_the_squares_cells_and_equal_a_station_file() {
    // BP7 on 40 m cells (its stations ±100 m are centres), BP8 on 80 m (±200 m).
    for (bin, dx, end, (station, at)) in [
        (
            env!("CARGO_BIN_EXE_seas_bp7"),
            40.0,
            ["--end-years", "3e-8"],
            ("fltst_strk+100dp-100", 100.0),
        ),
        (
            env!("CARGO_BIN_EXE_seas_bp8"),
            80.0,
            ["--end-days", "2"],
            ("fltst_strk+200dp-200", 200.0),
        ),
    ] {
        let dir = temp_dir("seas-square-hdf5");
        let dx_flag = dx.to_string();
        let mut args = vec!["--dx", &dx_flag, "--date", "2026-11-29", "--hdf5", "1"];
        args.extend(end);
        args.extend(["--out", arg(&dir)]);
        run_ok(bin, &args);
        let file = hdf5::File::open(dir.join("fields.h5")).unwrap();
        // The square of 800 m in cells of dx, a poly-vertex at each centre (the fault
        // alone).
        let cells = (800.0 / dx) as usize;
        assert_eq!(
            file.dataset("mesh/cells").unwrap().shape(),
            [cells * cells, 1]
        );
        // The station `at` along strike (x₂) and at `dp = −at` (x₃ = dp in these
        // benchmarks' names, unlike BP5's depth): a cell's centre.
        let station = dir.join(station);
        let state_column = station_rows(&station)[0].len() - 1;
        fault_fields_equal_station(&file, &station, [0.0, at, -at], state_column, 5);
        drop(file);
        std::fs::remove_dir_all(&dir).ok();
    }
}

#[test]
fn seas_bp8_volume_fault_fields_are_the_square_s_pairs_and_equal_a_station_file() {
    // BP8 with `--kernel fe` at 80 m: the fault's faces between the (800/80 − 1)² split
    // pairs inside the square (the rim a tip), two triangles in each of the 8 × 8 squares
    // of pairs, read off the Schur-only elimination (the writer reads the fault alone);
    // the central station is a node (the well's, the injection's centre).
    let dir = temp_dir("seas-bp8-fe-hdf5");
    let args = [
        "--kernel",
        "fe",
        "--domain-km",
        "1.6",
        "--dx",
        "80",
        "--date",
        "2026-11-29",
        "--hdf5",
        "1",
        "--end-days",
        "2",
        "--out",
        arg(&dir),
    ];
    run_ok(env!("CARGO_BIN_EXE_seas_bp8"), &args);
    let file = hdf5::File::open(dir.join("fields.h5")).unwrap();
    assert_eq!(file.dataset("mesh/cells").unwrap().shape(), [128, 3]);
    let station = dir.join("fltst_strk+000dp+000");
    let state_column = station_rows(&station)[0].len() - 1;
    fault_fields_equal_station(&file, &station, [0.0; 3], state_column, 5);
    drop(file);
    std::fs::remove_dir_all(&dir).ok();
}

/// `a` equals `b` to the 13 significant digits of the network station files (`{:.12e}`).
fn digits13(a: f64, b: f64) -> bool {
    (a - b).abs() <= 5.01e-13 * b.abs().max(1e-300) + 1e-300
}

/// The network program `bin` run into a fresh folder with `args` and `--hdf5 1`: every
/// point of its fields file is a frictional node of one of the two faults (the field
/// `fault` names both), and at the first and the last of `stations` (`near` points, m) the
/// slip's magnitude and the state α of every frame equal the station files' rows of the
/// same step (`{fault}_{label}.csv`: `step,t_s,slip…,slip_rate,traction,state`).
fn network_fields_equal_station_files(
    bin: &str,
    args: &[&str],
    stations: &[(String, String, [f64; 3])],
) {
    let dir = temp_dir("network-hdf5");
    let mut all = args.to_vec();
    all.extend(["--threads", "1", "--hdf5", "1", "--out", arg(&dir)]);
    run_ok(bin, &all);
    let file = hdf5::File::open(dir.join("fields.h5")).unwrap();
    let n = file.dataset("mesh/points").unwrap().shape()[0];
    let steps: Vec<u64> = file.dataset("step").unwrap().read_raw().unwrap();
    let fault = read(&file, "fields/fault");
    let faults: std::collections::BTreeSet<u64> = fault[..n].iter().map(|&f| f as u64).collect();
    assert_eq!(faults, [0, 1].into());
    let (slip, alpha) = (
        read(&file, "fields/slip"),
        read(&file, "fields/state_alpha"),
    );
    for (name, label, near) in [&stations[0], &stations[stations.len() - 1]] {
        let k = node_at(&file, *near);
        let path = dir.join(format!("{name}_{label}.csv"));
        let text = std::fs::read_to_string(&path).unwrap();
        let rows: Vec<Vec<f64>> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect();
        assert!(rows.len() > 10, "{} rows in {path:?}", rows.len());
        for row in &rows {
            let i = steps
                .iter()
                .position(|&st| st as f64 == row[0])
                .unwrap_or_else(|| panic!("no frame of step {}", row[0]));
            let u = &slip[3 * (i * n + k)..3 * (i * n + k) + 3];
            let magnitude = u.iter().map(|x| x * x).sum::<f64>().sqrt();
            // The station's slip components: all but the last three columns after t.
            let components = &row[2..row.len() - 3];
            let expected = components.iter().map(|x| x * x).sum::<f64>().sqrt();
            assert!(digits13(magnitude, expected), "slip {magnitude} {row:?}");
            assert!(
                digits13(alpha[i * n + k], row[row.len() - 1]),
                "state {row:?}"
            );
        }
    }
    drop(file);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn network_fault_fields_are_both_faults_and_equal_the_station_files() {
    // The stepover (2-D, the strands' segments) at 500 m for 5 years, and the pair of BP5
    // strands on Okada's cells (3-D, a poly-vertex at each cell) at 4 km for 5 years.
    let stepover: Vec<(String, String, [f64; 3])> = rsf_scenes::StepoverRun::default()
        .scene()
        .stations()
        .into_iter()
        .map(|s| (s.fault, s.label, [s.near[0], s.near[1], 0.0]))
        .collect();
    network_fields_equal_station_files(
        env!("CARGO_BIN_EXE_stepover"),
        &["--dx", "500", "--end-years", "5"],
        &stepover,
    );
    let pair: Vec<(String, String, [f64; 3])> = rsf_scenes::Bp5PairRun::default()
        .scene()
        .stations()
        .into_iter()
        .map(|s| (s.fault, s.label, s.near))
        .collect();
    network_fields_equal_station_files(
        env!("CARGO_BIN_EXE_bp5_pair"),
        &["--dx", "4000", "--end-years", "5"],
        &pair,
    );
}
