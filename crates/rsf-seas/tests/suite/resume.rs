//! The SEAS output resumed from a checkpoint (docs/reliability.md): the files of a run
//! stopped and continued byte-identical to an uninterrupted run's, a damaged file refused
//! before anything is cut, the resume log read back (a line cut off by a kill ignored, a
//! malformed line named).

use std::path::Path;

use rsf::observe::FileMode;
use rsf::run_folder::read_checkpoint;
use rsf_seas::Error;

use crate::common::{snapshot, temp_dir};

/// The SEAS output of the small BP1 (implicit scheme), thinned: written for 40 steps,
/// against written for 15 steps, checkpointed, "killed" at 22 and resumed from the
/// checkpoint to 40 — every file (stations, `devol.dat`, `events.csv`, the resume log)
/// byte-identical. A station file truncated mid-row is refused first, naming it, with
/// nothing changed.
#[test]
fn seas_output_resumed_from_a_checkpoint_writes_byte_identical_files() {
    use rsf::friction::AsinhLaw;
    use rsf::observe::Checkpointer;
    use rsf::Observer;
    use rsf_scenes::{SeasBp1, SeasBp1Simulation};
    use rsf_seas::{SeasOutput, SeasSampling, SeasSetup};
    let (bp1, grid) = crate::common::small_bp1(&SeasBp1::default());
    let sampling = SeasSampling {
        station_quiet: 200.0,
        profile_quiet: 2000.0,
        ..SeasSampling::default()
    };
    let fingerprint = bp1
        .fingerprint(&grid, false, &sampling)
        .with("scheme", "implicit");
    let setup = |_: ()| {
        let mut setup = SeasSetup {
            problem: "BP1-QD (small test)".into(),
            modeler: "test".into(),
            date: "2026-11-24".into(),
            profile_spacing: 1000.0,
            ..bp1.seas_setup(grid.dz, false, sampling)
        };
        setup.stations.truncate(5);
        setup
    };
    let build = || -> SeasBp1Simulation {
        let model = bp1.model(&grid, false).unwrap();
        bp1.simulation_builder(model, false, 1e-2, bp1.step_control(1e-2).unwrap())
            .unwrap()
            .build()
            .unwrap()
    };
    let output = |dir: &Path, sim: &SeasBp1Simulation, mode: FileMode| {
        SeasOutput::<AsinhLaw>::new(
            dir,
            sim.model(),
            sim.problem().friction_laws(),
            setup(()),
            mode,
        )
    };
    // `steps` steps into `dir`, a checkpoint at `checkpoint_at`.
    let run =
        |dir: &Path, sim: &mut SeasBp1Simulation, out: &mut SeasOutput<AsinhLaw>, steps: usize| {
            let mut c = rsf::observe::Every::new(
                rsf::observe::Interval::Steps(15),
                Checkpointer::new(dir.join("checkpoint.bin")).fingerprint(fingerprint.clone()),
            )
            .unwrap();
            let mut observers: [&mut dyn Observer<2, 1>; 2] = [out, &mut c];
            sim.run(steps, &mut observers).unwrap();
        };
    let (whole, parts) = (temp_dir("seas-whole"), temp_dir("seas-parts"));
    // The whole run, and the part that stops after 22 steps.
    for (dir, steps) in [(&whole, 40), (&parts, 22)] {
        let mut sim = build();
        let mut out = output(dir, &sim, FileMode::Overwrite)
            .unwrap()
            .with_resume_log(FileMode::Overwrite)
            .unwrap();
        run(dir, &mut sim, &mut out, steps);
    }
    let c = read_checkpoint(&parts.join("checkpoint.bin"), &fingerprint, &[]).unwrap();
    assert_eq!(c.state.step, 15);
    // The thinning matters: fewer station rows than steps, more than one.
    let station = parts.join(SeasBp1::station_name(0.0));
    let rows = std::fs::read_to_string(&station)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .count()
        - 1;
    assert!(rows > 1 && rows < 22, "{rows} station rows in 22 steps");

    // A station file truncated mid-row (inside the rows up to the checkpoint) is refused
    // before anything is cut.
    let damaged = parts.join(SeasBp1::station_name(5e3));
    let intact = std::fs::read(&damaged).unwrap();
    let header_end = intact.windows(6).position(|w| w == b"state\n").unwrap() + 6;
    std::fs::write(&damaged, &intact[..header_end + 30]).unwrap();
    let before = snapshot(&parts);
    let sim = build();
    let e = output(&parts, &sim, FileMode::Resume { step: 15 })
        .err()
        .unwrap();
    let msg = e.to_string();
    assert!(matches!(e, Error::Resume { .. }), "{msg}");
    assert!(msg.contains("fltst_dp050"), "{msg}");
    assert_eq!(snapshot(&parts), before, "nothing is cut: {msg}");
    std::fs::write(&damaged, &intact).unwrap();

    // The intact folder resumes byte-identically.
    let mut sim = build();
    SeasOutput::<AsinhLaw>::check_resume(&parts, sim.model(), &setup(()), 15).unwrap();
    sim.restore(&c).unwrap();
    let mut out = output(&parts, &sim, FileMode::Resume { step: 15 }).unwrap();
    run(&parts, &mut sim, &mut out, 25);
    drop(out);
    let (a, b) = (snapshot(&whole), snapshot(&parts));
    assert_eq!(a.len(), b.len());
    for ((pa, ba), (pb, bb)) in a.iter().zip(&b) {
        assert_eq!(pa.file_name(), pb.file_name());
        if pa.ends_with("checkpoint.bin") {
            continue; // wall times differ
        }
        assert!(ba == bb, "{} differs after the resume", pa.display());
    }
}

/// The resume log read back by the `csv` crate: a last line cut off by a kill is not read
/// (the folder resumes), a malformed or blank line is refused naming the log and its line,
/// with nothing changed.
#[test]
fn the_resume_log_is_read_back_line_by_line() {
    use rsf::friction::AsinhLaw;
    use rsf_scenes::SeasBp1;
    use rsf_seas::{SeasOutput, SeasSampling, SeasSetup, SEAS_RESUME_LOG};
    let (bp1, grid) = crate::common::small_bp1(&SeasBp1::default());
    let mut setup = SeasSetup {
        problem: "BP1-QD (small test)".into(),
        modeler: "test".into(),
        date: "2026-11-24".into(),
        profile_spacing: 1000.0,
        ..bp1.seas_setup(grid.dz, false, SeasSampling::default())
    };
    setup.stations.truncate(3);
    let model = bp1.model(&grid, false).unwrap();
    let mut sim = bp1
        .simulation_builder(model, false, 1e-2, bp1.step_control(1e-2).unwrap())
        .unwrap()
        .build()
        .unwrap();
    let dir = temp_dir("log-lines");
    let laws = sim.problem().friction_laws().to_vec();
    let mut out =
        SeasOutput::<AsinhLaw>::new(&dir, sim.model(), &laws, setup.clone(), FileMode::Create)
            .unwrap()
            .with_resume_log(FileMode::Create)
            .unwrap();
    out.write_initial_state(sim.model(), sim.state()).unwrap();
    sim.run(6, &mut [&mut out]).unwrap();
    drop(out);
    let log = dir.join(SEAS_RESUME_LOG);
    let intact = std::fs::read(&log).unwrap();
    let check = |step| SeasOutput::<AsinhLaw>::check_resume(&dir, sim.model(), &setup, step);
    check(4).unwrap();
    // A line cut off by a kill: not read.
    let mut cut = intact.clone();
    cut.extend_from_slice(b"7,1.2e");
    std::fs::write(&log, &cut).unwrap();
    check(6).unwrap();
    // Line 4 (the log's step 2) malformed, then blank: named, whatever the step.
    let lines: Vec<&[u8]> = intact.split_inclusive(|&b| b == b'\n').collect();
    for (bad, reason) in [(&b"2,x\n"[..], "malformed"), (&b"\n"[..], "blank")] {
        let mut damaged = lines.clone();
        damaged[3] = bad;
        std::fs::write(&log, damaged.concat()).unwrap();
        let before = snapshot(&dir);
        let e = check(5).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, Error::Malformed { line: 4, .. }), "{msg}");
        assert!(
            msg.contains(SEAS_RESUME_LOG) && msg.contains(reason),
            "{msg}"
        );
        assert_eq!(snapshot(&dir), before, "nothing is cut: {msg}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
