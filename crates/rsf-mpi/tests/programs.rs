//! The programs `seas_bp1`, `seas_bp3` and `seas_bp5` on MPI ranks (this crate's binaries:
//! the programs of `rsf-programs` with their evaluations shared): every file byte-identical to
//! one process's — BP1 at 1, 2 and 4 ranks, BP3 (a normal stress from slip) at 2, BP5 (the
//! half-space operator) at 2 and 3, BP5 with the finite-element volume at 2 (its elimination
//! on rank 0 alone, read by the other rank), a run stopped at a step cap on 2 ranks and resumed on
//! 3, and a job killed (`SIGKILL` to every process) and resumed on 2 ranks — and an error
//! on rank 0 ends every rank at once. The program `slider_3d` (TNNMG's velocity solves on
//! the ranks) writes the same bytes on 1, 2 and 4 ranks, also stopped and resumed, but for
//! its frames, which on more than one rank are parallel pieces that join to the one-rank
//! frames bit for bit (also resumed on more and on fewer ranks); an unwritable piece on
//! rank 1 ends every rank.

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
    same_files_but(a, b, what, &[])
}

/// [`same_files`] but for the folders named in `skip`.
fn same_files_but(a: &Path, b: &Path, what: &str, skip: &[&str]) -> usize {
    let mut n = 0;
    for entry in std::fs::read_dir(a).unwrap() {
        let p = entry.unwrap().path();
        let name = p.file_name().unwrap().to_str().unwrap().to_owned();
        if p.is_dir() {
            if !skip.contains(&name.as_str()) {
                n += same_files_but(&p, &b.join(&name), &format!("{what}: {name}"), skip);
            }
            continue;
        }
        if [
            "summary.json",
            "rsf-run.txt",
            "checkpoint.bin",
            "seas_resume.csv",
            "bp5_resume.json",
            // The elimination's kept result: its header holds its wall time.
            "setup.bin",
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

/// Ranks started with different flags — an MPMD launch `mpirun -n 1 P A : -n 1 P B` with
/// another `--end-years` (which hung) or another `--dx` (which crashed with a segmentation
/// fault) on one rank — end, every one, before any work with one error naming the flag on
/// both ranks; nothing is written.
#[test]
fn ranks_started_with_different_flags_end_with_one_named_error() {
    for (name, a, b, shown) in [
        (
            "end_years",
            "--end-years=5",
            "--end-years=50",
            "--end-years 50",
        ),
        ("dx", "--dx=2000", "--dx=4000", "--dx 4000"),
    ] {
        let out = folder(&format!("mpmd_{name}"));
        let common = ["--threads", "1", "--out", out.to_str().unwrap()];
        let t = Instant::now();
        let run = std::process::Command::new("mpirun")
            .args(["--oversubscribe", "-n", "1", BP5, a])
            .args(common)
            .args([":", "-n", "1", BP5, b])
            .args(common)
            .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
            .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
            .output()
            .expect("mpirun");
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success(), "{name}: {err}");
        assert!(
            err.contains("different flags") && err.contains(shown),
            "{name}: {err}"
        );
        assert!(
            t.elapsed() < Duration::from_secs(60),
            "{name}: {:?}",
            t.elapsed()
        );
        assert!(
            !out.exists(),
            "{name}: the folder was made before the ranks agreed"
        );
    }
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

/// BP5's flags: the output folder `out`, `flags`, one thread and the header's date fixed
/// (the files of two runs compared byte by byte).
fn bp5_args(out: &Path, flags: &[&str]) -> Vec<String> {
    let out = out.to_str().unwrap();
    ["--out", out]
        .iter()
        .chain(flags)
        .chain(&["--threads", "1", "--date", "2026-11-26"])
        .map(|s| s.to_string())
        .collect()
}

/// BP5 at Δx = 4 km (500 cells, Okada's operator, dense: its rows in blocks of 8 per
/// rank) for 300 years: every file on 2 and on 3 ranks has one process's bytes.
#[test]
fn bp5_files_are_byte_identical_on_2_and_3_ranks() {
    let args = |out: &Path| bp5_args(out, &["--dx", "4000", "--end-years", "300"]);
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

/// With the feature `hdf5`, `--hdf5 N` on ranks: rank 0 writes the fault's fields, and on
/// 2 ranks `fields.h5` and `fields.xmf` have one process's bytes with every other file —
/// BP1 at 400 m for 300 years, a frame every 20 steps (344 frames), and BP5 on Okada's
/// 4 km cells, a frame every 10 steps.
#[cfg(feature = "hdf5")]
#[test]
fn fault_fields_on_2_ranks_are_one_processs_bytes() {
    let with_fields = |mut args: Vec<String>, n: &str| {
        args.extend(["--hdf5".to_string(), n.to_string()]);
        args
    };
    let bp1 = |out: &Path| with_fields(flags(out), "20");
    let bp5 =
        |out: &Path| with_fields(bp5_args(out, &["--dx", "4000", "--end-years", "300"]), "10");
    for (name, bin, args, files) in [
        ("bp1", BIN, &bp1 as &dyn Fn(&Path) -> Vec<String>, 16),
        ("bp5", BP5, &bp5, 25),
    ] {
        let one = folder(&format!("{name}_fields_one_process"));
        succeeded(&run_program(bin, None, &args(&one)));
        let two = folder(&format!("{name}_fields_2_ranks"));
        succeeded(&run_program(bin, Some(2), &args(&two)));
        for file in ["fields.h5", "fields.xmf"] {
            assert!(two.join(file).is_file(), "{name}: no {file}");
        }
        let same = same_files(&one, &two, &format!("{name} with --hdf5 on 2 ranks"));
        assert!(same >= files, "{name}: {same} files");
    }
}

/// With the feature `hdf5`, `slider_3d --hdf5 N` on ranks: rank 0 writes the body's
/// fields, and on 2 ranks `fields.h5` and `fields.xmf` have the bytes of the run on one rank
/// (the reference of the solver on ranks), as every other file but the frames' pieces.
#[cfg(feature = "hdf5")]
#[test]
fn slider_3d_fields_on_2_ranks_are_one_ranks_bytes() {
    let args = |out: &Path| {
        let mut args = slider_args(out);
        args.extend(["--hdf5".to_string(), "6".to_string()]);
        args
    };
    let one = folder("slider_3d_fields_1_rank");
    succeeded(&run_program(SLIDER_3D, Some(1), &args(&one)));
    let two = folder("slider_3d_fields_2_ranks");
    succeeded(&run_program(SLIDER_3D, Some(2), &args(&two)));
    for file in ["fields.h5", "fields.xmf"] {
        assert!(two.join(file).is_file(), "no {file}");
    }
    let same = same_files_but(&one, &two, "slider_3d with --hdf5 on 2 ranks", &["frames"]);
    // The series, the snapshot, its figure and the two field files.
    assert!(same >= 5, "{same} files");
}

/// Without the feature `hdf5` the programs on ranks refuse `--hdf5 N` before any work,
/// naming the feature.
#[cfg(not(feature = "hdf5"))]
#[test]
fn hdf5_on_ranks_needs_the_feature() {
    let out = folder("bp1_fields_refused");
    let mut args = flags(&out);
    args.extend(["--hdf5".to_string(), "20".to_string()]);
    let run = run(Some(2), &args);
    let text = String::from_utf8_lossy(&run.stderr);
    assert!(
        !run.status.success() && text.contains("--features hdf5"),
        "{text}"
    );
}

/// BP5 at Δx = 1 km (8 000 slip unknowns: Okada's operator an ℋ-matrix) for its first
/// 3 s (15 steps of the initial rupture) on 2 ranks, each building and holding only the blocks of its rows: every file has one
/// process's bytes (the whole operator), and rank 0 says that it holds part 0 of 2.
#[test]
fn bp5_with_the_operator_held_in_parts_is_byte_identical_on_2_ranks() {
    let args = |out: &Path| bp5_args(out, &["--dx", "1000", "--end-years", "1e-7"]);
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

/// BP5 with the finite-element volume (Δx = 5 km, the Schur-only elimination) for 40 years
/// on 2 ranks: rank 0 eliminates and the other rank reads its result from the run folder
/// (each says so), and every file has one process's bytes.
#[test]
fn bp5_with_the_volume_eliminated_on_rank_0_alone_is_byte_identical_on_2_ranks() {
    let args = |out: &Path| {
        bp5_args(
            out,
            &["--kernel", "fe", "--dx", "5000", "--end-years", "40"],
        )
    };
    let one = folder("bp5_fe_one_process");
    let out = run_program(BP5, None, &args(&one));
    succeeded(&out);
    let dir = folder("bp5_fe_2_ranks");
    let out = run_program(BP5, Some(2), &args(&dir));
    succeeded(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        text.contains("eliminated on rank 0 alone, read from")
            && text.contains("by the other ranks (1)"),
        "{text}"
    );
    assert!(
        err.contains("rank 1: the elimination read from rank 0's"),
        "{err}"
    );
    assert!(same_files(&one, &dir, "BP5 with the volume on 2 ranks") >= 20);
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

/// The flags of the 3-D slider runs here: level 2 (525 nodes; Newmark, TNNMG on the
/// ranks) for 48 steps of 0.25 s (`--end-time 12 --steps 48`: through the nucleation of
/// the first event, the largest slip rate rising from 1e-29 to about 1e-3 m/s), a frame
/// every 12 steps, into `out`.
fn slider_args(out: &Path) -> Vec<String> {
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
}

/// The one piece of the unstructured grid in the VTU file `path`.
fn read_vtu(path: &Path) -> vtkio::model::UnstructuredGridPiece {
    let vtk = vtkio::Vtk::import(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let vtkio::model::DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("{}: not an unstructured grid", path.display())
    };
    assert_eq!(pieces.len(), 1, "{}", path.display());
    pieces[0].load_piece_data(None).unwrap()
}

/// The point data `name` of `piece`.
fn point_array<'a>(
    piece: &'a vtkio::model::UnstructuredGridPiece,
    name: &str,
) -> &'a vtkio::model::DataArray {
    piece
        .data
        .point
        .iter()
        .find_map(|a| match a {
            vtkio::model::Attribute::DataArray(a) if a.name == name => Some(a),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no point data `{name}`"))
}

/// The bits of an array of f64.
fn bits(buffer: &vtkio::IOBuffer) -> Vec<u64> {
    let values: Vec<f64> = buffer.clone().cast_into().expect("f64 values");
    values.iter().map(|x| x.to_bits()).collect()
}

/// The cells of `piece` (each its vertices in order), numbered by `global` (a piece's
/// point `i` is mesh vertex `global[i]`).
fn cells(piece: &vtkio::model::UnstructuredGridPiece, global: &[u64]) -> Vec<Vec<u64>> {
    let (connectivity, offsets) = piece.cells.cell_verts.clone().into_xml();
    let mut start = 0;
    offsets
        .iter()
        .map(|&end| {
            let cell = connectivity[start as usize..end as usize]
                .iter()
                .map(|&i| global[i as usize])
                .collect();
            start = end;
            cell
        })
        .collect()
}

/// The point data arrays a `.pvtu` describes (its `PPointData`'s `PDataArray`s): name,
/// type and component count. Read from the text: vtkio 0.7.0-rc2 reads a `PPointData`'s
/// arrays from elements named `data_array` (a missing `rename` in its XML model), not
/// `PDataArray`, so it finds none in a standard file.
fn pvtu_point_arrays(path: &Path) -> Vec<(String, &'static str, u32)> {
    let text = std::fs::read_to_string(path).unwrap();
    let start = text.find("<PPointData>").expect("PPointData");
    let end = text.find("</PPointData>").expect("the end of PPointData");
    text[start..end]
        .split("<PDataArray ")
        .skip(1)
        .map(|element| {
            let attr = |name: &str| {
                let from = element.find(&format!("{name}=\"")).expect(name) + name.len() + 2;
                element[from..from + element[from..].find('"').unwrap()].to_owned()
            };
            let t = match attr("type").as_str() {
                "Float64" => "Float64",
                "UInt64" => "UInt64",
                other => panic!("type {other}"),
            };
            (attr("Name"), t, attr("NumberOfComponents").parse().unwrap())
        })
        .collect()
}

/// The frames of a run on ranks in `dir` against the one-rank frames in `one`: for every
/// one-rank frame `frame_NNNNNN.vtu`, `frame_NNNNNN.pvtu` names exactly the pieces
/// `frame_NNNNNN_rRRRR.vtu` of ranks `0..ranks(NNNNNN)`, no other piece of that step is in
/// the folder, its arrays are the one-rank frame's and `global_node` with their types and
/// component counts, the pieces (loaded through the `.pvtu`) hold every cell exactly once,
/// and every point's coordinates and point data joined by `global_node` have the one-rank
/// bits; `frames.pvd` is the one-rank index with `.pvtu` for `.vtu`. Returns the number
/// of frames.
fn same_frames_in_pieces(one: &Path, dir: &Path, ranks: impl Fn(usize) -> usize) -> usize {
    let (one, dir) = (one.join("frames"), dir.join("frames"));
    let index = std::fs::read_to_string(one.join("frames.pvd")).unwrap();
    assert_eq!(
        std::fs::read_to_string(dir.join("frames.pvd")).unwrap(),
        index.replace(".vtu\"", ".pvtu\""),
        "frames.pvd"
    );
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    let mut frames = 0;
    for entry in std::fs::read_dir(&one).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        let Some(step) = name
            .strip_prefix("frame_")
            .and_then(|n| n.strip_suffix(".vtu"))
        else {
            continue;
        };
        frames += 1;
        let whole = read_vtu(&one.join(&name));
        let n = whole.num_points();
        let expected: Vec<String> = (0..ranks(step.parse().unwrap()))
            .map(|r| format!("frame_{step}_r{r:04}.vtu"))
            .collect();
        let written: Vec<&String> = names
            .iter()
            .filter(|f| f.starts_with(&format!("frame_{step}_r")))
            .collect();
        assert_eq!(written, expected.iter().collect::<Vec<_>>(), "step {step}");
        // The parallel file: its arrays and its pieces.
        let pvtu = dir.join(format!("frame_{step}.pvtu"));
        let vtk = vtkio::Vtk::import(&pvtu).unwrap();
        let vtkio::model::DataSet::UnstructuredGrid { meta, pieces } = vtk.data else {
            panic!("{}: not an unstructured grid", pvtu.display())
        };
        assert!(
            matches!(
                meta.as_deref(),
                Some(vtkio::model::MetaData::UnstructuredGrid { .. })
            ),
            "{}: not a parallel unstructured grid",
            pvtu.display()
        );
        let mut arrays: Vec<(String, &str, u32)> = whole
            .data
            .point
            .iter()
            .map(|a| {
                let vtkio::model::Attribute::DataArray(a) = a else {
                    panic!("not a data array")
                };
                let t = match a.data.scalar_type() {
                    vtkio::model::ScalarType::F64 => "Float64",
                    other => panic!("{}: {other:?}", a.name),
                };
                (a.name.clone(), t, a.elem.num_comp())
            })
            .collect();
        arrays.push(("global_node".to_owned(), "UInt64", 1));
        assert_eq!(pvtu_point_arrays(&pvtu), arrays, "{}", pvtu.display());
        let sources: Vec<String> = pieces
            .iter()
            .map(|p| match p {
                vtkio::model::Piece::Source(s, _) => s.clone(),
                _ => panic!("an inline piece in {}", pvtu.display()),
            })
            .collect();
        assert_eq!(sources, expected, "{}", pvtu.display());
        // The pieces joined.
        let whole_points = bits(&whole.points);
        let mut uncovered = std::collections::HashMap::<Vec<u64>, usize>::new();
        for cell in cells(&whole, &(0..n as u64).collect::<Vec<_>>()) {
            *uncovered.entry(cell).or_default() += 1;
        }
        let mut seen = vec![false; n];
        for p in &pieces {
            let piece = p.load_piece_data(vtk.file_path.as_deref()).unwrap();
            let global: Vec<u64> = point_array(&piece, "global_node")
                .data
                .clone()
                .cast_into()
                .expect("u64 global nodes");
            assert_eq!(global.len(), piece.num_points());
            for cell in cells(&piece, &global) {
                let count = uncovered.get_mut(&cell).expect("a cell of the mesh");
                assert!(*count > 0, "step {step}: cell {cell:?} twice");
                *count -= 1;
            }
            let points = bits(&piece.points);
            for (i, &g) in global.iter().enumerate() {
                let g = g as usize;
                seen[g] = true;
                assert_eq!(points[3 * i..3 * i + 3], whole_points[3 * g..3 * g + 3]);
            }
            for (name, _, c) in &arrays[..arrays.len() - 1] {
                let c = *c as usize;
                let (mine, all) = (
                    bits(&point_array(&piece, name).data),
                    bits(&point_array(&whole, name).data),
                );
                for (i, &g) in global.iter().enumerate() {
                    let g = g as usize;
                    assert_eq!(
                        mine[c * i..c * i + c],
                        all[c * g..c * g + c],
                        "step {step}: {name} at vertex {g}"
                    );
                }
            }
        }
        assert!(
            uncovered.values().all(|&c| c == 0),
            "step {step}: a cell in no piece"
        );
        assert!(seen.iter().all(|&s| s), "step {step}: a vertex in no piece");
    }
    frames
}

/// The 3-D slider ([`slider_args`]) on 1, 2 and 4 MPI ranks: its time series, fault
/// snapshot and figure on 2 and 4 ranks have the bytes of the run on one rank, and so
/// does its frames' index but for the names; the frames on one rank are one file each
/// (those of one process), on 2 and 4 ranks parallel pieces that join to the one-rank
/// frames bit for bit ([`same_frames_in_pieces`]); stopped at step 20 on 2 ranks and
/// resumed on 4, the same again (the frame of step 12 in 2 pieces, the later ones in 4).
#[test]
fn slider_3d_files_are_byte_identical_on_1_2_and_4_ranks_and_after_a_resume() {
    let args = slider_args;
    let one = folder("slider_3d_1_rank");
    let out = run_program(SLIDER_3D, Some(1), &args(&one));
    succeeded(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("tnnmg-ranks solver"), "{text}");
    // One rank writes one file per frame, as one process does.
    let frames: Vec<_> = std::fs::read_dir(one.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert_eq!(frames.len(), 5, "{frames:?}");
    assert!(frames
        .iter()
        .all(|f| f.ends_with(".vtu") || f == "frames.pvd"));
    for n in [2, 4] {
        let dir = folder(&format!("slider_3d_{n}_ranks"));
        let out = run_program(SLIDER_3D, Some(n), &args(&dir));
        succeeded(&out);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(&format!("{n} MPI ranks share every velocity solve")),
            "{err}"
        );
        let files = same_files_but(&one, &dir, &format!("slider_3d on {n} ranks"), &["frames"]);
        // The series, the snapshot and its figure.
        assert!(files >= 3, "{files} files compared");
        assert_eq!(same_frames_in_pieces(&one, &dir, |_| n), 4);
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
    let files = same_files_but(
        &dir,
        &one,
        "slider_3d stopped on 2 ranks and resumed on 4",
        &["frames"],
    );
    assert!(files >= 1, "{files} files compared");
    let frames = same_frames_in_pieces(&one, &dir, |step| if step <= 20 { 2 } else { 4 });
    assert_eq!(frames, 4);
}

/// The piece rank 1 writes of the 3-D slider's first frame cannot be written (a folder
/// has its name): rank 1's error, naming the piece, ends both ranks within seconds, and
/// rank 0 (waiting for every piece) has not written that frame's `.pvtu`.
#[test]
fn an_unwritable_frame_piece_on_rank_1_ends_every_rank() {
    let dir = folder("slider_3d_unwritable_piece");
    std::fs::create_dir_all(dir.join("frames/frame_000012_r0001.vtu")).unwrap();
    let t = Instant::now();
    let out = run_program(SLIDER_3D, Some(2), &slider_args(&dir));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(err.contains("rank 1 of 2: error"), "{err}");
    assert!(err.contains("frame_000012_r0001.vtu"), "{err}");
    assert!(t.elapsed() < Duration::from_secs(60), "{:?}", t.elapsed());
    assert!(!dir.join("frames/frame_000012.pvtu").exists());
    assert!(dir.join("frames/frame_000012_r0000.vtu").exists());
}

/// The 3-D slider ([`slider_args`]) stopped at step 20 on 4 ranks (the checkpoint kept
/// aside), continued on 4 ranks to step 30 (the frame of step 24 in 4 pieces), then
/// resumed from the step-20 checkpoint on 2 ranks to the end: the frame of step 24 is
/// rewritten in 2 pieces, rank 0 removes the 4-rank run's pieces 2 and 3 of that step, and
/// every frame joins to the one-rank frames bit for bit; the series has the one-rank bytes.
#[test]
fn slider_3d_frames_resumed_on_fewer_ranks_keep_no_stale_pieces() {
    let one = folder("slider_3d_1_rank_for_fewer");
    succeeded(&run_program(SLIDER_3D, Some(1), &slider_args(&one)));
    let dir = folder("slider_3d_resumed_on_fewer");
    let checkpoint = dir.join("checkpoint.bin");
    let mut capped = slider_args(&dir);
    capped.extend(["--checkpoint-every", "10", "--max-steps", "20"].map(String::from));
    let out = run_program(SLIDER_3D, Some(4), &capped);
    assert!(
        checkpoint.exists(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let at_20 = dir.join("checkpoint_20.bin");
    std::fs::copy(&checkpoint, &at_20).unwrap();
    let resume = |from: &Path, extra: &[&str]| {
        let mut args = slider_args(&dir);
        args.extend(["--checkpoint-every", "10", "--resume"].map(String::from));
        args.push(from.to_str().unwrap().to_owned());
        args.extend(extra.iter().map(|s| s.to_string()));
        args
    };
    run_program(
        SLIDER_3D,
        Some(4),
        &resume(&checkpoint, &["--max-steps", "30"]),
    );
    assert!(dir.join("frames/frame_000024_r0003.vtu").exists());
    succeeded(&run_program(SLIDER_3D, Some(2), &resume(&at_20, &[])));
    assert!(!dir.join("frames/frame_000024_r0002.vtu").exists());
    assert_eq!(
        same_frames_in_pieces(&one, &dir, |step| if step <= 20 { 4 } else { 2 }),
        4
    );
    assert_eq!(
        std::fs::read(dir.join("timeseries.csv")).unwrap(),
        std::fs::read(one.join("timeseries.csv")).unwrap()
    );
}
