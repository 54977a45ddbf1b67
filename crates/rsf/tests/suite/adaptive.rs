//! Adaptive time steps with error control (issue 10, docs/math.md §9): the controller keeps
//! a steady state steady, meets its tolerance on a problem with a reference solution,
//! rejects and retries failing steps without showing them to observers, stays within its
//! bounds, and checkpoints bit-identically.

use crate::common::{frictionless, resumable_observers, slider, temp_dir, within, StopAt};
use rsf::friction::Tresca;
use rsf::simulation::NoState;
use rsf::time::{Newmark, StepControl};
use rsf::{Checkpoint, Flow, Observer, StepView};
use rsf_scenes::{AdaptiveTimeStep, SceneSimulation, SliderScene, TimeStep};

/// Every accepted step as observed: (t, τ, rejected attempts, max slip rate).
#[derive(Default)]
struct Steps(Vec<(f64, f64, usize, f64)>);

impl Observer<2> for Steps {
    fn observe(&mut self, s: &StepView<'_, 2>) -> rsf::Result<Flow> {
        let r = s.report;
        self.0
            .push((r.time, r.tau, r.rejected_attempts, r.max_slip_rate));
        Ok(Flow::Continue(()))
    }
}

fn control(tol: f64, tau_min: f64, tau_max: f64) -> StepControl {
    StepControl::new(tol, 1e-5, tau_min, tau_max).unwrap()
}

/// The observed times are contiguous: each step starts where the last accepted one ended.
fn assert_contiguous(steps: &[(f64, f64, usize, f64)], t0: f64) {
    let mut t = t0;
    for &(ti, tau, _, _) in steps {
        assert!(
            (ti - (t + tau)).abs() <= 1e-9 * ti.max(1.0),
            "step at {ti} after {t} with τ = {tau}"
        );
        t = ti;
    }
}

/// Frictionless-fault slider (Tresca with μ = 0: the fault slides freely, bilateral
/// contact), no gravity: linear elastodynamics driven by the top boundary.
fn linear_scene() -> SliderScene {
    SliderScene {
        end_time_s: 0.5,
        gravity_m_per_s2: 0.0,
        loading_velocity_m_per_s: 1e-3,
        ramp_fraction: 0.2,
        ..slider(1, 1000)
    }
}

fn linear_sim(tau: f64) -> rsf::Simulation<2, Tresca, NoState, Newmark> {
    linear_sim_of(&linear_scene(), tau)
}

/// [`linear_sim`] for another scene (its mesh and loading).
fn linear_sim_of(scene: &SliderScene, tau: f64) -> rsf::Simulation<2, Tresca, NoState, Newmark> {
    let model = scene.build_model().unwrap();
    frictionless(model, Newmark, tau)
        .fixed_point(rsf::method::FixedPointOptions::default())
        .build()
        .unwrap()
}

/// The scaled displacement error of the controller: RMS over the free dofs of the error
/// over `atol + tol · rms(u − u₀)`.
fn scaled_error(
    sim: &rsf::Simulation<2, Tresca, NoState, Newmark>,
    u: &[f64],
    c: &StepControl,
) -> f64 {
    let m = sim.model();
    let (mut e2, mut d2, mut n) = (0.0, 0.0, 0.0);
    for i in 0..u.len() {
        if m.fixed[i] {
            continue;
        }
        let d = sim.kinematics().u[i] - m.initial_displacement[i];
        e2 += (u[i] - sim.kinematics().u[i]).powi(2);
        d2 += d * d;
        n += 1.0;
    }
    (e2 / n).sqrt() / (c.displacement_atol + c.tolerance * (d2 / n).sqrt())
}

/// On linear elastodynamics (a frictionless fault), every accepted step's true local error
/// — the step against 64 sub-steps of Newmark from the same state, whose own error is
/// 64⁻² times smaller — stays within twice the tolerance (the estimate is not
/// optimistic), and the global error shrinks when the tolerance does.
#[test]
fn linear_elastodynamics_error_meets_the_tolerance() {
    let c = control(1e-4, 1e-9, 0.01);
    let mut sim = linear_sim(0.3 / 150.0);
    sim.run_until(within(0.1), &mut []).unwrap();
    sim.set_step_control(Some(c)).unwrap();
    let mut worst: f64 = 0.0;
    for _ in 0..12 {
        let start = sim.checkpoint();
        let report = sim.step().unwrap();
        assert!(report.error_estimate <= 1.0);
        let stepped = sim.checkpoint();
        // The same step in 64 sub-steps from the same state.
        let mut fine = linear_sim(report.tau / 64.0);
        let mut from = start.clone();
        from.state.tau = report.tau / 64.0;
        from.state.controller = None;
        fine.restore(&from).unwrap();
        fine.run(64, &mut []).unwrap();
        worst = worst.max(scaled_error(&fine, &stepped.state.kinematics.u, &c));
        // Continue from the adaptive step.
        assert_eq!(sim.checkpoint(), stepped);
    }
    assert!(worst <= 2.0, "true local error {worst} × tolerance");
    // Global error at t = 0.3 s against a fine uniform run shrinks with the tolerance.
    let reference = {
        let mut s = linear_sim(0.3 / 9600.0);
        s.run_until(within(0.3), &mut []).unwrap();
        s.kinematics().u.clone()
    };
    let global = |tol: f64| {
        let mut s = linear_sim(0.3 / 150.0);
        s.set_step_control(Some(control(tol, 1e-9, 0.3 / 75.0)))
            .unwrap();
        s.run_until(within(0.3), &mut []).unwrap();
        assert!((s.time() - 0.3).abs() < 1e-12, "ends at the requested time");
        let u = &s.kinematics().u;
        let num: f64 = u
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b) * (a - b))
            .sum();
        let den: f64 = reference.iter().map(|b| b * b).sum();
        (num / den).sqrt()
    };
    let (e3, e5) = (global(1e-3), global(1e-5));
    assert!(
        e5 < 0.2 * e3,
        "global errors {e3:e} (1e-3) and {e5:e} (1e-5)"
    );
}

#[test]
fn steady_sliding_stays_steady_with_growing_steps() {
    // Velocity strengthening (a > b) loaded long enough to slide steadily: the controller
    // must keep it steady (no events) and grow the step to its maximum.
    let scene = SliderScene {
        end_time_s: 20.0,
        a: 0.02,
        b: 0.01,
        ..slider(1, 2000)
    };
    let mut sim = scene.build().unwrap();
    sim.run_until(within(15.0), &mut []).unwrap();
    let v_d = scene.loading_velocity_m_per_s;
    sim.set_step_control(Some(control(1e-4, 1e-9, 0.5)))
        .unwrap();
    let mut steps = Steps::default();
    let t0 = sim.time();
    sim.run_until(within(20.0), &mut [&mut steps]).unwrap();
    assert_contiguous(&steps.0, t0);
    for &(t, _, _, v) in &steps.0 {
        assert!(
            (v / v_d - 1.0).abs() < 0.05,
            "t = {t}: slip rate {v} vs the loading rate {v_d}"
        );
    }
    let largest = steps.0.iter().map(|s| s.1).fold(0.0, f64::max);
    assert!(
        largest >= 0.25,
        "steady sliding lets the step grow (largest {largest})"
    );
}

/// A step never straddles a kink of the loading: the ramp's end (here off every dyadic
/// multiple of the initial step, so no rung reaches it by chance) is the end of a step,
/// and the steps after it continue on the ladder.
#[test]
fn steps_end_at_the_end_of_the_loading_ramp() {
    let ramp_end = 0.2137 * 0.5;
    let scene = SliderScene {
        ramp_fraction: 0.2137,
        ..linear_scene()
    };
    let tau0 = 5e-4;
    let mut sim = linear_sim_of(&scene, tau0);
    let history = &sim.model().dirichlet.history;
    assert_eq!(history.next_breakpoint(0.0), Some(ramp_end));
    assert_eq!(history.next_breakpoint(ramp_end), None);
    sim.set_step_control(Some(control(1e-3, 1e-9, 0.05)))
        .unwrap();
    let mut steps = Steps::default();
    sim.run_until(within(0.3), &mut [&mut steps]).unwrap();
    assert_contiguous(&steps.0, 0.0);
    assert!(
        steps.0.iter().any(|s| (s.0 - ramp_end).abs() <= 1e-12),
        "a step ends at the ramp's end {ramp_end}"
    );
    for &(t, tau, _, _) in &steps.0 {
        assert!(
            !(t - tau < ramp_end - 1e-12 && t > ramp_end + 1e-12),
            "the step ({}, {t}] straddles the ramp's end",
            t - tau
        );
    }
    // After it the steps are rungs τ0·2^k again (only the step onto the kink, and the
    // last one onto the end time, are off the ladder).
    let after: Vec<f64> = steps
        .0
        .iter()
        .filter(|s| s.0 > ramp_end + 1e-12)
        .map(|s| s.1)
        .collect();
    assert!(after.len() > 2);
    for tau in &after[..after.len() - 1] {
        let k = (tau / tau0).log2();
        assert!((k - k.round()).abs() < 1e-9, "τ = {tau} is on the ladder");
    }
}

#[test]
fn failing_steps_are_rejected_retried_and_never_observed() {
    // A fixed point budget of 3 iterations fails on large steps through the first slip
    // event; the controller must shrink the step and carry on.
    let scene = SliderScene {
        fixed_point_max_iterations: 3,
        ..slider(1, 2000)
    };
    let mut sim = scene.build().unwrap();
    let (tau_min, tau_max) = (1e-7, 0.05);
    sim.set_step_control(Some(control(1e-2, tau_min, tau_max)))
        .unwrap();
    let mut steps = Steps::default();
    let summary = sim.run_until(within(10.6), &mut [&mut steps]).unwrap();
    assert!(summary.rejected_attempts > 0, "some attempts failed");
    assert_eq!(
        summary.rejected_attempts,
        steps.0.iter().map(|s| s.2).sum::<usize>()
    );
    assert_contiguous(&steps.0, 0.0);
    for &(t, tau, _, _) in &steps.0 {
        assert!(
            tau >= tau_min * (1.0 - 1e-12) && tau <= tau_max * (1.0 + 1e-12),
            "t = {t}: τ = {tau} outside [{tau_min}, {tau_max}]"
        );
    }
    let peak = steps.0.iter().map(|s| s.3).fold(0.0, f64::max);
    assert!(peak > 1e-3, "the run went through the first event");
}

#[test]
fn adaptive_checkpoint_and_resume_is_bit_identical() {
    let scene = slider(1, 1000);
    let c = control(1e-3, 1e-9, 0.1);
    let straight = {
        let mut sim = scene.build().unwrap();
        sim.set_step_control(Some(c)).unwrap();
        sim.run(300, &mut []).unwrap();
        sim.checkpoint()
    };
    let path = std::env::temp_dir().join(format!("rsf-adaptive-{}.bin", std::process::id()));
    {
        let mut sim = scene.build().unwrap();
        sim.set_step_control(Some(c)).unwrap();
        sim.run(170, &mut []).unwrap();
        sim.checkpoint().write(&path).unwrap();
    }
    let mut resumed = scene.build().unwrap();
    resumed.set_step_control(Some(c)).unwrap();
    let cp = Checkpoint::read(&path).unwrap();
    assert!(
        cp.state.controller.is_some(),
        "the controller state is saved"
    );
    resumed.restore(&cp).unwrap();
    resumed.run(130, &mut []).unwrap();
    std::fs::remove_file(&path).ok();
    assert_eq!(resumed.checkpoint(), straight);
}

#[test]
fn scene_time_step_parses_defaults_and_rejects_unknown_fields() {
    // Fixed steps stay the default, also for a file that does not name `time_step`.
    assert_eq!(SliderScene::default().time_step, TimeStep::Fixed {});
    let s = SliderScene::from_toml("steps = 500").unwrap();
    assert_eq!((s.steps, s.time_step), (500, TimeStep::Fixed {}));
    assert!(s.step_control().unwrap().is_none());
    let s = SliderScene::from_toml("time_step = { kind = \"fixed\" }").unwrap();
    assert_eq!(s.time_step, TimeStep::Fixed {});

    let s = SliderScene::from_toml(
        "steps = 300\nend_time_s = 3.0\n\
         time_step = { kind = \"adaptive\", tolerance = 1e-4, tau_max_s = 0.05 }",
    )
    .unwrap();
    let TimeStep::Adaptive(a) = s.time_step else {
        panic!("adaptive expected: {:?}", s.time_step)
    };
    assert_eq!(
        a,
        AdaptiveTimeStep {
            tau_max_s: 0.05,
            ..AdaptiveTimeStep::new(1e-4)
        }
    );
    let c = s.step_control().unwrap().unwrap();
    assert_eq!((c.tolerance, c.tau_max), (1e-4, 0.05));
    assert_eq!(c.displacement_atol, 1e-4 * s.l_m, "default scale L");
    assert_eq!(
        c.state_atol,
        1e-4 * (s.l_m / s.loading_velocity_m_per_s),
        "default state scale L/V_load"
    );
    assert_eq!(c.state_change_cap, Some(0.5));
    assert_eq!(
        (c.slip_rate_floor, c.state_extrapolation),
        (Some(1e-9), true)
    );
    assert_eq!(s.initial_tau(), s.tau());
    // The built simulation steps adaptively from the initial step.
    let s = SliderScene { level: 1, ..s };
    let sim = s.build().unwrap();
    let ctrl = sim.state().controller.expect("adaptive steps");
    assert_eq!((ctrl.tau(), sim.tau()), (s.tau(), s.tau()));

    // Every option, ξ = inf for no cap; the scene round-trips through TOML.
    let s = SliderScene::from_toml(
        "[time_step]\nkind = \"adaptive\"\ntolerance = 1e-3\ninitial_tau_s = 1e-4\n\
         tau_min_s = 1e-8\ntau_max_s = 0.2\ndisplacement_scale_m = 1e-4\nsafety = 0.8\n\
         min_factor = 0.25\nmax_factor = 4.0\nstate_change_cap = inf\n\
         slip_rate_floor_mps = inf\nstate_extrapolation = false\nstate_scale_s = 0.0",
    )
    .unwrap();
    let c = s.step_control().unwrap().unwrap();
    assert_eq!(c.state_atol, 0.0, "a purely relative state test");
    assert_eq!(s.initial_tau(), 1e-4);
    assert_eq!(c.state_change_cap, None);
    assert_eq!((c.slip_rate_floor, c.state_extrapolation), (None, false));
    assert_eq!((c.safety, c.min_factor, c.max_factor), (0.8, 0.25, 4.0));
    assert!((c.displacement_atol - 1e-7).abs() < 1e-20);
    let text = toml::to_string(&s).unwrap();
    assert_eq!(SliderScene::from_toml(&text).unwrap(), s);

    // Unknown fields and kinds are named; a tolerance is required; invalid values name
    // their field.
    let e = SliderScene::from_toml(
        "time_step = { kind = \"adaptive\", tolerance = 1e-3, tolerence = 1 }",
    )
    .unwrap_err();
    assert!(e.to_string().contains("tolerence"), "{e}");
    let e = SliderScene::from_toml("time_step = { kind = \"fixed\", steps = 3 }").unwrap_err();
    assert!(e.to_string().contains("steps"), "{e}");
    let e = SliderScene::from_toml("time_step = { kind = \"variable\" }").unwrap_err();
    assert!(e.to_string().contains("variable"), "{e}");
    let e = SliderScene::from_toml("time_step = { kind = \"adaptive\" }").unwrap_err();
    assert!(e.to_string().contains("tolerance"), "{e}");
    for (field, bad) in [
        ("tolerance", "tolerance = -1.0"),
        ("tau_max_s", "tolerance = 1e-3, tau_max_s = 1e-12"),
        ("safety", "tolerance = 1e-3, safety = 2.0"),
        ("initial_tau_s", "tolerance = 1e-3, initial_tau_s = 0.0"),
        (
            "state_change_cap",
            "tolerance = 1e-3, state_change_cap = -1.0",
        ),
        ("state_scale_s", "tolerance = 1e-3, state_scale_s = -1.0"),
        ("state_scale_s", "tolerance = 1e-3, state_scale_s = inf"),
    ] {
        let s = SliderScene::from_toml(&format!("time_step = {{ kind = \"adaptive\", {bad} }}"))
            .unwrap();
        let e = s.validate().unwrap_err();
        assert!(
            e.to_string().contains(&format!("time_step.{field}")),
            "{bad}: {e}"
        );
        assert!(s.build().is_err());
    }
}

/// A run with adaptive steps from the scene, stopped through the API after a checkpoint
/// and resumed into the same files, writes the same bytes as an uninterrupted run (the
/// rows carry the adaptive τ of each step).
#[test]
fn adaptive_scene_stopped_and_resumed_writes_the_same_bytes() {
    use rsf::observe::PointSeries;
    use rsf_scenes::{AdaptiveTimeStep, TimeStep};
    use std::path::Path;

    // Level 1, fast loading from t = 0; the steps grow from 1e-3 s and shrink again
    // through the slip.
    let scene = SliderScene {
        end_time_s: 0.6,
        loading_velocity_m_per_s: 1e-2,
        ramp_fraction: 0.0,
        time_step: TimeStep::Adaptive(AdaptiveTimeStep::new(1e-3)),
        ..slider(1, 300)
    };
    let (every, stop) = (40, 130);
    let run = |dir: &Path, stop: Option<usize>, resume: bool| {
        let mut sim = scene.build().unwrap();
        let (mut series, mut profile, mut checkpointer) =
            resumable_observers(&mut sim, dir, (0.1, 0.5), every, resume);
        let mut stopper = StopAt(stop.unwrap_or(usize::MAX));
        sim.run_until(
            within(scene.end_time_s),
            &mut [&mut series, &mut profile, &mut checkpointer, &mut stopper],
        )
        .unwrap();
        sim
    };
    let (a, b) = (temp_dir("adaptive-straight"), temp_dir("adaptive-stopped"));
    let straight = run(&a, None, false);
    let stopped = run(&b, Some(stop), false);
    assert_eq!(stopped.step_index(), stop);
    let resumed = run(&b, None, true);
    assert_eq!(resumed.checkpoint(), straight.checkpoint());
    assert_eq!(resumed.time(), scene.end_time_s, "the run lands on T");
    let ctrl = |s: &SceneSimulation<2>| {
        let c = s.state().controller.unwrap();
        (c.accepted(), c.rejected())
    };
    assert_eq!(ctrl(&resumed), ctrl(&straight));
    for file in ["x0.csv", "profile.csv"] {
        let (x, y) = (
            std::fs::read(a.join(file)).unwrap(),
            std::fs::read(b.join(file)).unwrap(),
        );
        assert!(x == y, "{file} differs after resuming");
    }
    let series = PointSeries::<2>::read(&b.join("x0.csv")).unwrap();
    assert!(series.len() > stop, "{} steps", series.len());
    let taus: Vec<f64> = series.iter().map(|r| r.tau).collect();
    let (lo, hi) = taus
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &t| (l.min(t), h.max(t)));
    assert!(hi > 2.0 * lo, "the rows carry varying τ: {lo:e} … {hi:e}");
    let mut t = 0.0;
    for r in &series {
        t += r.tau;
        assert!((r.time - t).abs() < 1e-9, "rows are contiguous in time");
    }
    for d in [a, b] {
        std::fs::remove_dir_all(d).ok();
    }
}

#[test]
fn adaptive_scene_file_in_the_repository_parses() {
    let text = include_str!("../../../../scenes/pipping_slider_adaptive.toml");
    assert_eq!(
        SliderScene::from_toml(text).unwrap(),
        SliderScene {
            time_step: rsf_scenes::TimeStep::Adaptive(rsf_scenes::AdaptiveTimeStep::new(1e-3)),
            ..SliderScene::default()
        }
    );
}

/// Healing of the aging law from θ₀ = e^{−10} s while the fault is stuck (V ≈ 1e-25 m/s):
/// `θ̇ = 1 − Vθ/L`, so `θ(t) = θ₀ + t` to ~1e-20. The state test relative in θ resolves
/// the start of the healing (τ ≲ √(2 tol) θ); with the absolute tolerance `tol · θ_s` the
/// early steps may make errors up to `tol · θ_s`, which healing carries without
/// amplifying: the run takes fewer steps, and θ at the end still has a relative error
/// below the tolerance.
#[test]
fn healing_state_error_with_and_without_the_state_scale() {
    let tol = 1e-3;
    let end = 0.5;
    let run = |state_scale_s: f64| {
        let scene = SliderScene {
            level: 1,
            steps: 50,
            end_time_s: 5.0,
            time_step: TimeStep::Adaptive(AdaptiveTimeStep {
                state_scale_s: Some(state_scale_s),
                ..AdaptiveTimeStep::new(tol)
            }),
            ..SliderScene::default()
        };
        let mut sim = scene.build().unwrap();
        let mut steps = Steps::default();
        sim.run_until(within(end), &mut [&mut steps]).unwrap();
        let v_max = steps.0.iter().map(|s| s.3).fold(0.0_f64, f64::max);
        assert!(v_max < 1e-15, "stuck: largest slip rate {v_max}");
        let exact = scene.alpha0.exp() + sim.time();
        let error = sim
            .alpha()
            .iter()
            .map(|&a| (a.exp() - exact).abs() / exact)
            .fold(0.0_f64, f64::max);
        (steps.0.len(), error)
    };
    let (n_rel, e_rel) = run(0.0);
    let (n_abs, e_abs) = run(0.05);
    println!("relative: {n_rel} steps, θ error {e_rel:e}; θ_s = 0.05 s: {n_abs} steps, {e_abs:e}");
    assert!(e_rel < tol && e_abs < tol, "{e_rel:e}, {e_abs:e}");
    assert!(
        (n_abs as f64) < 0.8 * n_rel as f64,
        "the state scale saves steps: {n_abs} against {n_rel}"
    );
}
