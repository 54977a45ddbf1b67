//! The coupled simulation on a shortened paper scene: convergence of every step, the
//! loading phase, determinism, checkpoint/resume, scene validation. (TNNMG and the direct
//! solver are compared through the first slip events in `slip_event.rs`.)

use crate::common::within;
use rsf::{Checkpoint, Error, SolverKind};
use rsf_scenes::{SliderScene, SLIDER_CENTRE};

/// The paper's scene at level 2 with its time step (τ = T/1e4), first `steps` steps.
fn short(solver: SolverKind) -> SliderScene {
    SliderScene {
        level: 2,
        solver,
        ..SliderScene::default()
    }
}

/// Runs `steps` steps; returns (u_x0, v_x0) per step and the final checkpoint.
fn run(scene: &SliderScene, steps: usize) -> (Vec<(f64, f64)>, Checkpoint) {
    let mut sim = scene.build().unwrap();
    let x0 = sim.model().nearest_node(&SLIDER_CENTRE).unwrap();
    let mut out = Vec::new();
    for _ in 0..steps {
        let r = sim
            .step()
            .expect("every step's fixed point iteration converges");
        assert!(r.fixed_point_iterations >= 1 && r.correction <= scene.fixed_point_tolerance);
        out.push((sim.kinematics().u[2 * x0], sim.kinematics().v[2 * x0]));
    }
    (out, sim.checkpoint())
}

#[test]
fn loading_phase_converges_sticks_and_is_deterministic() {
    let scene = short(SolverKind::Tnnmg);
    let (a, ca) = run(&scene, 2000);
    // While the block is loaded (t ≤ 3 s ≪ first slip ≈ 2T/3) the centre sticks.
    let vmax = a.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    assert!(
        vmax < 1e-5,
        "slip rate at x0 reached {vmax:e} during loading"
    );
    assert!(a.iter().all(|p| p.0.is_finite() && p.1.is_finite()));
    // Same scene, same build: bit-identical.
    let (b, cb) = run(&scene, 2000);
    assert!(a
        .iter()
        .zip(&b)
        .all(|(x, y)| x.0.to_bits() == y.0.to_bits() && x.1.to_bits() == y.1.to_bits()));
    assert_eq!(ca, cb);
}

#[test]
fn checkpoint_then_resume_is_bit_identical() {
    let scene = short(SolverKind::Tnnmg);
    let (_, straight) = run(&scene, 2000);
    let dir = std::env::temp_dir().join(format!("rsf-ckpt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("step1000.bin");
    {
        let mut sim = scene.build().unwrap();
        for _ in 0..1000 {
            sim.step().unwrap();
        }
        sim.checkpoint().write(&path).unwrap();
    }
    let mut resumed = scene.build().unwrap();
    resumed.restore(&Checkpoint::read(&path).unwrap()).unwrap();
    assert_eq!(resumed.step_index(), 1000);
    for _ in 0..1000 {
        resumed.step().unwrap();
    }
    assert_eq!(
        resumed.checkpoint(),
        straight,
        "resumed run differs from the straight run"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_scenes_name_the_problem() {
    let named = |e: Error, what: &str| {
        let msg = e.to_string();
        assert!(msg.contains(what), "error `{msg}` does not name `{what}`");
    };
    let s = SliderScene {
        end_time_s: -15.0,
        ..SliderScene::default()
    };
    named(s.build().err().unwrap(), "end_time_s");
    let s = SliderScene {
        a: 0.0,
        ..SliderScene::default()
    };
    named(s.build().err().unwrap(), "a");
    let s = SliderScene {
        poisson_ratio: 0.5,
        ..SliderScene::default()
    };
    named(s.build().err().unwrap(), "poisson_ratio");
    named(
        rsf::model::FrictionalBoundary::new(&[], &[]).unwrap_err(),
        "frictional_boundary",
    );
    named(
        SliderScene::from_toml("level = 2\nfriction_coeff = 0.6\n").unwrap_err(),
        "friction_coeff",
    );
    named(
        SliderScene::from_toml("state_law = \"regularized\"\n").unwrap_err(),
        "state_law",
    );
}

#[test]
fn scene_file_in_the_repository_parses_to_the_defaults() {
    let text = include_str!("../../../../scenes/pipping_slider.toml");
    assert_eq!(
        SliderScene::from_toml(text).unwrap(),
        SliderScene::default()
    );
}

/// The slider at level 1 with τ = T/1000: τ (s) and its simulation.
fn coarse_slider() -> (f64, crate::common::Sim) {
    let scene = SliderScene {
        level: 1,
        steps: 1000,
        ..SliderScene::default()
    };
    (scene.tau(), scene.build().unwrap())
}

/// Ends after a number of steps (an observer that stops the run).
struct StopAfter(usize);

impl rsf::Observer<2> for StopAfter {
    fn observe(&mut self, s: &rsf::StepView<'_, 2>) -> rsf::Result<rsf::Flow> {
        Ok(if s.report.step >= self.0 {
            rsf::Flow::Break(())
        } else {
            rsf::Flow::Continue(())
        })
    }
}

#[test]
fn run_until_a_time_and_until_an_observer_stops() {
    let (tau, mut sim) = coarse_slider();
    let s = sim.run_until(within(10.0 * tau), &mut []).unwrap();
    assert_eq!(s.steps, 10);
    assert!((sim.time() - 10.0 * tau).abs() < 1e-12);
    assert!(!s.stopped_by_observer());
    let mut stop = StopAfter(13);
    let s = sim.run(100, &mut [&mut stop]).unwrap();
    assert_eq!((s.steps, sim.step_index()), (3, 13));
    assert!(s.stopped_by_observer());
    // A non-finite end time is a typed error, not a hang.
    assert!(sim.run_until(within(f64::INFINITY), &mut []).is_err());
}

/// Changing τ mid-run through the API continues the trajectory: the times add up, and
/// returning to the first τ reuses its solver.
#[test]
fn time_step_can_change_between_steps() {
    let (tau, mut sim) = coarse_slider();
    sim.run(4, &mut []).unwrap();
    sim.set_time_step(tau / 2.0).unwrap();
    sim.run(4, &mut []).unwrap();
    assert!((sim.time() - 6.0 * tau).abs() < 1e-12 * tau);
    sim.set_time_step(tau).unwrap();
    sim.run(2, &mut []).unwrap();
    assert!((sim.time() - 8.0 * tau).abs() < 1e-12 * tau);
    assert_eq!(sim.step_index(), 10);
    assert!(sim.set_time_step(-1.0).is_err());
    assert!(sim.set_time_step(f64::NAN).is_err());
}

/// Coarse time steps on a fine mesh (j = 5, τ = 0.75 s: the quasi-static regime, where the
/// condensed problem on Γ_F is strongly coupled): the direct solver converges at every step
/// and follows the same trajectory as TNNMG, an independent solver. (The direct solver once
/// reused a Cholesky factor of the soft blocks after damped steps and stalled here, 500
/// iterations without convergence, while TNNMG converged.)
#[test]
fn coarse_steps_on_a_fine_mesh_converge_with_both_solvers_and_agree() {
    let scene = |solver| SliderScene {
        level: 5,
        steps: 20,
        solver,
        ..SliderScene::default()
    };
    // (u_x0, v_x0) per step; every step converges (its fixed point error estimate meets
    // the tolerance: with τ this large the iteration contracts fast, and the estimate, not
    // the last correction, decides).
    let run = |s: &SliderScene| {
        let mut sim = s.build().unwrap();
        let x0 = sim.model().nearest_node(&SLIDER_CENTRE).unwrap();
        (0..s.steps)
            .map(|_| {
                let r = sim.step().expect("every step converges");
                assert!(r.fixed_point_error <= s.fixed_point_tolerance);
                (sim.kinematics().u[2 * x0], sim.kinematics().v[2 * x0])
            })
            .collect::<Vec<_>>()
    };
    let direct = run(&scene(SolverKind::Direct));
    let tnnmg = run(&scene(SolverKind::Tnnmg));
    let u_scale = tnnmg.iter().map(|p| p.0.abs()).fold(0.0, f64::max);
    let v_scale = tnnmg.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    assert!(u_scale > 0.0 && v_scale > 0.0);
    let mut worst: f64 = 0.0;
    for (d, t) in direct.iter().zip(&tnnmg) {
        worst = worst
            .max((d.0 - t.0).abs() / u_scale)
            .max((d.1 - t.1).abs() / v_scale);
    }
    eprintln!("largest relative difference direct vs TNNMG: {worst:e}");
    for (k, (d, t)) in direct.iter().zip(&tnnmg).enumerate() {
        assert!(
            (d.0 - t.0).abs() <= 1e-9 * u_scale && (d.1 - t.1).abs() <= 1e-9 * v_scale,
            "step {}: direct (u, v) = {d:?}, TNNMG {t:?}",
            k + 1
        );
    }
}
