//! Resume without loss (issue 11): a run stopped through the API after its last checkpoint
//! and resumed from that checkpoint into the same files leaves CSV files byte-identical to
//! an uninterrupted run's, and its state equal bit for bit.

use std::path::Path;

use crate::common::{resumable_observers, temp_dir, StopAt};
use rsf::observe::{Checkpointer, Every, FileMode, FrictionalProfile, Interval, PointSeries};
use rsf::{Checkpoint, SolverKind};
use rsf_scenes::{SceneSimulation, SliderScene, SLIDER_CENTRE};

const STEPS: usize = 300;
const CHECKPOINT_EVERY: usize = 100;
const STOP_AT: usize = 250;

fn scene(solver: SolverKind) -> SliderScene {
    // Level 1, fast loading from t = 0 so that the profile window has motion in it.
    SliderScene {
        level: 1,
        steps: STEPS,
        end_time_s: 0.3,
        loading_velocity_m_per_s: 1e-2,
        ramp_fraction: 0.0,
        solver,
        ..SliderScene::default()
    }
}

/// Runs to the end (or to `stop`), writing `x0.csv`, `profile.csv` and checkpoints into
/// `dir`; with `resume`, continues from the checkpoint in `dir`.
fn run(scene: &SliderScene, dir: &Path, stop: Option<usize>, resume: bool) -> SceneSimulation<2> {
    let mut sim = scene.build().unwrap();
    let (mut series, mut profile, mut checkpointer) =
        resumable_observers(&mut sim, dir, (0.1, 0.25), CHECKPOINT_EVERY, resume);
    let mut stopper = StopAt(stop.unwrap_or(usize::MAX));
    let remaining = STEPS - sim.step_index();
    sim.run(
        remaining,
        &mut [&mut series, &mut profile, &mut checkpointer, &mut stopper],
    )
    .unwrap();
    sim
}

#[test]
fn stopped_and_resumed_run_writes_the_same_bytes() {
    stop_and_resume(SolverKind::Tnnmg, "tnnmg");
}

/// The direct solver (the default at this size) keeps no state across steps that a
/// checkpoint would not hold.
#[test]
fn stopped_and_resumed_run_writes_the_same_bytes_direct() {
    stop_and_resume(SolverKind::Direct, "direct");
}

fn stop_and_resume(solver: SolverKind, name: &str) {
    let scene = scene(solver);
    let (a, b) = (
        temp_dir(&format!("resume-{name}-straight")),
        temp_dir(&format!("resume-{name}-stopped")),
    );
    let straight = run(&scene, &a, None, false);
    let stopped = run(&scene, &b, Some(STOP_AT), false);
    assert_eq!(stopped.step_index(), STOP_AT);
    // The interrupted files hold rows past the checkpoint (steps 201..=250).
    let rows = |p: &Path| std::fs::read_to_string(p).unwrap().lines().count() - 1;
    assert_eq!(rows(&b.join("x0.csv")), STOP_AT);
    let resumed = run(&scene, &b, None, true);
    assert_eq!(resumed.checkpoint(), straight.checkpoint());
    for file in ["x0.csv", "profile.csv"] {
        let (x, y) = (
            std::fs::read(a.join(file)).unwrap(),
            std::fs::read(b.join(file)).unwrap(),
        );
        assert!(rows(&a.join(file)) > 0);
        assert!(x == y, "{file} differs after resuming");
    }
    // The series reads back with one row per step.
    let series = PointSeries::<2>::read(&b.join("x0.csv")).unwrap();
    assert_eq!(series.len(), STEPS);
    assert!(series.iter().enumerate().all(|(i, r)| r.step == i + 1));
    assert!(series
        .iter()
        .all(|r| r.tau.to_bits() == scene.tau().to_bits()));
    for d in [a, b] {
        std::fs::remove_dir_all(d).ok();
    }
}

#[test]
fn resuming_detects_lost_rows_and_foreign_files() {
    let d = temp_dir("resume-lost");
    let mut sim = scene(SolverKind::Auto).build().unwrap();
    let x0 = sim.model().nearest_node(&SLIDER_CENTRE).unwrap();
    let path = d.join("x0.csv");
    {
        let mut series = PointSeries::new(&path, sim.model(), x0, FileMode::Create).unwrap();
        sim.run(5, &mut [&mut series]).unwrap();
    }
    // Rows end at step 5; a checkpoint at step 7 cannot be continued without a gap.
    let resume = |step| FileMode::Resume { step };
    let e = PointSeries::new(&path, sim.model(), x0, resume(7))
        .err()
        .unwrap();
    assert!(e.to_string().contains("missing"), "{e}");
    assert!(PointSeries::new(&path, sim.model(), x0, resume(3)).is_ok());
    // A profile file is not a series file, a missing file is not resumable.
    FrictionalProfile::<2>::new(&d.join("p.csv"), (0.0, 1.0), FileMode::Create).unwrap();
    assert!(PointSeries::new(&d.join("p.csv"), sim.model(), x0, resume(0)).is_err());
    assert!(PointSeries::new(&d.join("none.csv"), sim.model(), x0, resume(0)).is_err());
    std::fs::remove_dir_all(&d).ok();
}

/// VTU frames: the index of a stopped-and-resumed run lists the same frames with the same
/// times as an uninterrupted run's, and the frame files are the same bytes.
#[cfg(feature = "vtk")]
#[test]
fn vtu_frames_resume_without_loss() {
    use rsf::observe::VtuFrames;
    let scene = SliderScene {
        steps: 40,
        end_time_s: 0.04,
        ..scene(SolverKind::Auto)
    };
    let (a, b) = (
        temp_dir("resume-vtu-straight"),
        temp_dir("resume-vtu-stopped"),
    );
    let mut straight = scene.build().unwrap();
    let every_10 = |frames| Every::new(Interval::Steps(10), frames).unwrap();
    let mut frames = every_10(VtuFrames::new(&a, FileMode::Create).unwrap());
    straight.run(40, &mut [&mut frames]).unwrap();
    let mut stopped = scene.build().unwrap();
    let mut frames = every_10(VtuFrames::new(&b, FileMode::Create).unwrap());
    let mut ckpt = Every::new(Interval::Steps(20), Checkpointer::new(b.join("c.bin"))).unwrap();
    stopped
        .run(40, &mut [&mut frames, &mut ckpt, &mut StopAt(35)])
        .unwrap();
    let mut resumed = scene.build().unwrap();
    let c = Checkpoint::read(&b.join("c.bin")).unwrap();
    resumed.restore(&c).unwrap();
    let step = c.state.step;
    let mut frames = every_10(VtuFrames::new(&b, FileMode::Resume { step }).unwrap());
    resumed.run(40 - step, &mut [&mut frames]).unwrap();
    for file in [
        "frames.pvd",
        "frame_000010.vtu",
        "frame_000030.vtu",
        "frame_000040.vtu",
    ] {
        let (x, y) = (
            std::fs::read(a.join(file)).unwrap(),
            std::fs::read(b.join(file)).unwrap(),
        );
        assert!(x == y, "{file} differs after resuming");
    }
    for d in [a, b] {
        std::fs::remove_dir_all(d).ok();
    }
}
