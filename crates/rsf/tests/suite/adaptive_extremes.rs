//! Extreme and invalid options of adaptive time steps in the slider scene. The project's
//! standard: extreme or invalid user input gives a correct finite answer or a typed error,
//! never a panic, NaN/inf in the outputs, or a hang.
//!
//! - invalid options are `Error::InvalidParameter` naming the TOML field
//!   (`time_step.<field>`), from `step_control`, `validate` and `build` alike; among them
//!   (issue 26) a tolerance outside (ε, 1) (≥ 1 accepts any step, ≤ ε is never met),
//!   a `tau_min_s` that is not a normal double (1/τ overflows) or below ε · `end_time_s`
//!   (a step at t ≈ T does not advance time), with the range in the message;
//! - valid extremes are accepted (with `inf` switching off the cap and the slip test);
//!   "accept every step" is the tolerance 0.5 with displacement and state scales of 1e30
//!   and no slip test ([`accept_all`]);
//! - runs with valid extremes either land on their end time, stop at a step budget, or
//!   fail with a typed numerical error, and every observed and final state is finite;
//! - checkpoints taken after such runs (also after a failure) resume bit-identically in a
//!   freshly built simulation.
//!
//! All runs are on level 1 and take at most a couple of thousand steps.

use crate::common::{slider, within};
use rsf::time::Error as TimeError;
use rsf::{Error, Flow, Integrator, Observer, StateLawKind, StepView};
use rsf_scenes::{AdaptiveTimeStep, SceneSimulation, SliderScene, TimeStep};

type Sim = SceneSimulation<2>;

/// Default options with tolerance 1e-3 (the repository's adaptive scene).
fn base() -> AdaptiveTimeStep {
    AdaptiveTimeStep::new(1e-3)
}

/// Options under which every step that the solvers finish is accepted: the error control
/// is in range but cannot reject (tolerance `tol` < 1 with absolute tolerances of
/// `tol · 1e30` m and s, no slip test). Before issue 26 the tolerance 1e300 served for this.
fn accept_all(tol: f64) -> AdaptiveTimeStep {
    AdaptiveTimeStep {
        displacement_scale_m: Some(1e30),
        state_scale_s: Some(1e30),
        slip_rate_floor_mps: f64::INFINITY,
        ..AdaptiveTimeStep::new(tol)
    }
}

/// The paper's scene at level 1 (τ₀ = 15 s / 1000): stuck and healing during the loading
/// ramp, which ends at 3.75 s.
fn healing(a: AdaptiveTimeStep) -> SliderScene {
    SliderScene {
        time_step: TimeStep::Adaptive(a),
        ..slider(1, 1000)
    }
}

/// Fast loading from t = 0 (no ramp, no breakpoint): slip within a fraction of a second.
fn fast(a: AdaptiveTimeStep) -> SliderScene {
    SliderScene {
        end_time_s: 0.6,
        loading_velocity_m_per_s: 1e-2,
        ramp_fraction: 0.0,
        time_step: TimeStep::Adaptive(a),
        ..slider(1, 300)
    }
}

/// The options of a scene with adaptive steps.
fn options(scene: &SliderScene) -> AdaptiveTimeStep {
    match scene.time_step {
        TimeStep::Adaptive(a) => a,
        TimeStep::Fixed {} => panic!("adaptive scene expected"),
    }
}

/// The name of an `InvalidParameter` error.
fn invalid_name(e: &Error) -> Option<&str> {
    match e {
        Error::InvalidParameter { name, .. } => Some(name),
        _ => None,
    }
}

/// Whether `e` is a typed numerical failure of a run (not a set-up or parameter error that
/// should have been caught when the scene was built).
fn is_numerical_failure(e: &Error) -> bool {
    match e {
        // A step so small that the time-step matrix overflows (2/τ for τ < 1e-308).
        Error::InvalidParameter { name, reason } => name == "tau" && reason.contains("non-finite"),
        _ => matches!(
            e,
            Error::Time(TimeError::StepTooSmall { .. })
                // A run whose step stays at its floor (issue 74: it cannot progress, and
                // says so instead of crawling to the end time in 1e-9 s steps).
                | Error::StepSizeCollapse { .. }
                | Error::FixedPointNotConverged { .. }
                | Error::Solver(_)
                | Error::Direct(_)
                | Error::State(_)
        ),
    }
}

fn all_finite(xs: &[f64]) -> bool {
    xs.iter().all(|x| x.is_finite())
}

/// Ends a run after `budget` steps and checks every observed step: finite kinematics and
/// state, finite τ in (0, τ_max], time increasing and not past `t_end`, a finite error
/// estimate of at most 1. Problems are collected (with the case's label) and asserted after
/// the run.
struct Watch {
    label: String,
    budget: usize,
    t_end: f64,
    tau_max: f64,
    steps: usize,
    last_time: f64,
    /// Times of the observed steps.
    times: Vec<f64>,
    problems: Vec<String>,
}

impl Watch {
    fn new(label: &str, budget: usize, t_end: f64, tau_max: f64, t0: f64) -> Self {
        Self {
            label: label.to_string(),
            budget,
            t_end,
            tau_max,
            steps: 0,
            last_time: t0,
            times: Vec::new(),
            problems: Vec::new(),
        }
    }

    fn assert_clean(&self) {
        assert!(
            self.problems.is_empty(),
            "{}: {} problems, first: {:?}",
            self.label,
            self.problems.len(),
            &self.problems[..self.problems.len().min(3)]
        );
    }
}

impl Observer<2> for Watch {
    fn observe(&mut self, s: &StepView<'_, 2>) -> rsf::Result<Flow> {
        self.steps += 1;
        let r = s.report;
        let k = &s.state.kinematics;
        let mut bad = |what: String| {
            if self.problems.len() < 10 {
                self.problems
                    .push(format!("step {} (t = {}): {what}", r.step, r.time));
            }
        };
        if !(all_finite(&k.u) && all_finite(&k.v) && all_finite(&k.a)) {
            bad("non-finite kinematics".into());
        }
        if !all_finite(&s.state.alpha) {
            bad("non-finite state".into());
        }
        if !(r.tau.is_finite() && r.tau > 0.0 && r.tau <= self.tau_max * (1.0 + 1e-12)) {
            bad(format!("τ = {} outside (0, {}]", r.tau, self.tau_max));
        }
        if !(r.time.is_finite() && r.time > self.last_time) {
            bad(format!("time {} after {}", r.time, self.last_time));
        }
        if r.time > self.t_end * (1.0 + 1e-12) {
            bad(format!("time {} past the end {}", r.time, self.t_end));
        }
        if !(r.error_estimate.is_finite() && r.error_estimate <= 1.0) {
            bad(format!("accepted with error estimate {}", r.error_estimate));
        }
        if !r.max_slip_rate.is_finite() {
            bad(format!("max slip rate {}", r.max_slip_rate));
        }
        self.last_time = r.time;
        self.times.push(r.time);
        Ok(if self.steps >= self.budget {
            Flow::Break(())
        } else {
            Flow::Continue(())
        })
    }
}

/// Checks the state a simulation holds (after a run, successful or not).
fn assert_state_finite(label: &str, sim: &Sim, t_end: f64) {
    let k = sim.kinematics();
    assert!(all_finite(&k.u), "{label}: non-finite displacement");
    assert!(all_finite(&k.v), "{label}: non-finite velocity");
    assert!(all_finite(&k.a), "{label}: non-finite acceleration");
    assert!(all_finite(sim.alpha()), "{label}: non-finite state α");
    let t = sim.time();
    assert!(
        t.is_finite() && t >= 0.0 && t <= t_end * (1.0 + 1e-12),
        "{label}: time {t} outside [0, {t_end}]"
    );
    let tau = sim.tau();
    assert!(tau.is_finite() && tau > 0.0, "{label}: τ = {tau}");
    let c = sim.state().controller.expect("adaptive steps");
    let o = sim.method().step_control().expect("adaptive steps");
    assert!(
        c.tau().is_finite()
            && c.tau() >= o.tau_min * (1.0 - 1e-12)
            && c.tau() <= o.tau_max * (1.0 + 1e-12),
        "{label}: controller τ = {} outside [{}, {}]",
        c.tau(),
        o.tau_min,
        o.tau_max
    );
}

/// How a run ended.
#[derive(Debug)]
enum Outcome {
    /// Landed on the end time.
    Finished(usize),
    /// Stopped at the step budget.
    Budget,
    /// A typed numerical failure (its message).
    Failed(String),
}

impl Outcome {
    fn describe(&self) -> String {
        match self {
            Outcome::Finished(steps) => format!("finished after {steps} steps"),
            Outcome::Budget => "stopped at the step budget".into(),
            Outcome::Failed(e) => format!("failed: {e}"),
        }
    }
}

/// Builds `scene`, runs it to `t_end` (at most `budget` steps) and checks everything the
/// standard asks: no panic (a panic fails the test here), finite states, the end time hit
/// exactly when the run finishes, errors typed.
fn run_case(label: &str, scene: &SliderScene, t_end: f64, budget: usize) -> (Outcome, Sim) {
    let a = options(scene);
    let mut sim = scene
        .build()
        .unwrap_or_else(|e| panic!("{label}: a valid extreme option fails to build: {e}"));
    let mut watch = Watch::new(label, budget, t_end, a.tau_max_s, 0.0);
    let result = sim
        .run_until(within(t_end), &mut [&mut watch])
        .map_err(Error::from);
    watch.assert_clean();
    assert_state_finite(label, &sim, t_end);
    let outcome = match result {
        Ok(summary) if summary.stopped_by_observer() => {
            assert_eq!(summary.steps, budget, "{label}: stopped by the budget only");
            Outcome::Budget
        }
        Ok(summary) => {
            assert!(
                (sim.time() - t_end).abs() <= 1e-12 * t_end,
                "{label}: the run ends at {} instead of {t_end}",
                sim.time()
            );
            assert_eq!(summary.steps, watch.steps, "{label}");
            Outcome::Finished(summary.steps)
        }
        Err(e) => {
            assert!(
                is_numerical_failure(&e),
                "{label}: unexpected kind of error {e:?}"
            );
            if let Error::Time(TimeError::StepTooSmall { tau_min, .. }) = &e {
                assert_eq!(*tau_min, a.tau_min_s, "{label}: {e}");
            }
            Outcome::Failed(e.to_string())
        }
    };
    // A step never straddles the end of the loading ramp.
    let ramp_end = scene.ramp_end_s();
    if ramp_end > 0.0 && sim.time() > ramp_end {
        assert!(
            watch
                .times
                .iter()
                .any(|&t| (t - ramp_end).abs() <= 1e-12 * ramp_end),
            "{label}: no step ends at the ramp's end {ramp_end}"
        );
    }
    (outcome, sim)
}

/// Valid extremes of the initial step and of the tolerance scales, on the options `b`
/// (shared by the acceptance and the run tests).
fn start_and_scale_cases(b: AdaptiveTimeStep) -> Vec<(&'static str, AdaptiveTimeStep)> {
    vec![
        (
            "initial_tau_s = 1e-12",
            AdaptiveTimeStep {
                initial_tau_s: Some(1e-12),
                ..b
            },
        ),
        (
            "initial_tau_s = 1e3",
            AdaptiveTimeStep {
                initial_tau_s: Some(1e3),
                ..b
            },
        ),
        (
            "displacement_scale_m = 0",
            AdaptiveTimeStep {
                displacement_scale_m: Some(0.0),
                ..b
            },
        ),
        (
            "displacement_scale_m = 1e30",
            AdaptiveTimeStep {
                displacement_scale_m: Some(1e30),
                ..b
            },
        ),
        (
            "state_scale_s = 0",
            AdaptiveTimeStep {
                state_scale_s: Some(0.0),
                ..b
            },
        ),
        (
            "state_scale_s = 1e30",
            AdaptiveTimeStep {
                state_scale_s: Some(1e30),
                ..b
            },
        ),
    ]
}

/// Valid but extreme options, each with a label naming it.
fn extreme_cases() -> Vec<(&'static str, AdaptiveTimeStep)> {
    let b = base();
    let mut cases = vec![
        ("default (tolerance 1e-3)", b),
        ("tolerance = 1e-12", AdaptiveTimeStep::new(1e-12)),
        ("tolerance = 0.5", AdaptiveTimeStep::new(0.5)),
        ("tolerance = 1e-15", AdaptiveTimeStep::new(1e-15)),
        (
            "tolerance = 1 - ε",
            AdaptiveTimeStep::new(1.0 - f64::EPSILON),
        ),
        ("accept every step (accept_all(0.5))", accept_all(0.5)),
        (
            "tau_min_s = tau_max_s = 1e-3",
            AdaptiveTimeStep {
                tau_min_s: 1e-3,
                tau_max_s: 1e-3,
                ..b
            },
        ),
        (
            "tau_min_s = tau_max_s = 1e-3, accept_all(0.5) (fixed steps)",
            AdaptiveTimeStep {
                tau_min_s: 1e-3,
                tau_max_s: 1e-3,
                ..accept_all(0.5)
            },
        ),
        (
            "tau_min_s = tau_max_s = 1e300",
            AdaptiveTimeStep {
                tau_min_s: 1e300,
                tau_max_s: 1e300,
                ..b
            },
        ),
        (
            "tau_max_s = 1e-6",
            AdaptiveTimeStep {
                tau_max_s: 1e-6,
                ..b
            },
        ),
        (
            "tau_min_s = 1e-14 (ε · T is 3.3e-15 s for T = 15 s)",
            AdaptiveTimeStep {
                tau_min_s: 1e-14,
                ..b
            },
        ),
        (
            "tau_max_s = 1e300",
            AdaptiveTimeStep {
                tau_max_s: 1e300,
                ..b
            },
        ),
        (
            "tau_max_s = f64::MAX",
            AdaptiveTimeStep {
                tau_max_s: f64::MAX,
                ..b
            },
        ),
        (
            "min_factor = 0.99",
            AdaptiveTimeStep {
                min_factor: 0.99,
                ..b
            },
        ),
        (
            "min_factor = 5e-324",
            AdaptiveTimeStep {
                min_factor: 5e-324,
                ..b
            },
        ),
        (
            "max_factor = 1.0001",
            AdaptiveTimeStep {
                max_factor: 1.0001,
                ..b
            },
        ),
        (
            "max_factor = 1e6",
            AdaptiveTimeStep {
                max_factor: 1e6,
                ..b
            },
        ),
        ("safety = 1e-3", AdaptiveTimeStep { safety: 1e-3, ..b }),
        (
            "state_change_cap = 1e-6",
            AdaptiveTimeStep {
                state_change_cap: 1e-6,
                ..b
            },
        ),
        (
            "state_change_cap = inf",
            AdaptiveTimeStep {
                state_change_cap: f64::INFINITY,
                ..b
            },
        ),
        (
            "slip_rate_floor_mps = 1e-300",
            AdaptiveTimeStep {
                slip_rate_floor_mps: 1e-300,
                ..b
            },
        ),
        (
            "slip_rate_floor_mps = inf",
            AdaptiveTimeStep {
                slip_rate_floor_mps: f64::INFINITY,
                ..b
            },
        ),
        (
            "state_extrapolation = false",
            AdaptiveTimeStep {
                state_extrapolation: false,
                ..b
            },
        ),
        (
            "unbounded growth: accept_all(0.5), tau_max 1e300, max_factor 1e6, no cap",
            free_growth(),
        ),
        (
            "tolerance 1e-15 with tau_min_s = 1e-14 (steps shrink to the resolution of t)",
            AdaptiveTimeStep {
                tau_min_s: 1e-14,
                ..AdaptiveTimeStep::new(1e-15)
            },
        ),
    ];
    cases.extend(start_and_scale_cases(b));
    cases
}

/// Nothing limits the growth of the step but failing attempts.
fn free_growth() -> AdaptiveTimeStep {
    AdaptiveTimeStep {
        tau_max_s: 1e300,
        max_factor: 1e6,
        state_change_cap: f64::INFINITY,
        ..accept_all(0.5)
    }
}

#[test]
fn invalid_adaptive_options_are_typed_errors_naming_the_field() {
    let b = base();
    let nan = f64::NAN;
    let inf = f64::INFINITY;
    // (label, options, accepted field names after `time_step.`)
    let cases: Vec<(String, AdaptiveTimeStep, &[&str])> = {
        let mut v: Vec<(String, AdaptiveTimeStep, &[&str])> = Vec::new();
        // Outside (ε, 1) (issue 26): ≥ 1 accepts any step, ≤ ε is never met.
        for x in [
            nan,
            -1e-3,
            0.0,
            -0.0,
            inf,
            -inf,
            1.0,
            1e300,
            f64::MAX,
            f64::EPSILON,
            1e-300,
            5e-324,
        ] {
            v.push((
                format!("tolerance = {x}"),
                AdaptiveTimeStep::new(x),
                &["tolerance"],
            ));
        }
        v.push((
            "tau_min_s = 0.2 > tau_max_s = 0.1".into(),
            AdaptiveTimeStep {
                tau_min_s: 0.2,
                tau_max_s: 0.1,
                ..b
            },
            &["tau_min_s", "tau_max_s"],
        ));
        // Not a normal double (1/τ overflows), or below ε · end_time_s = 3.3e-15 s (a
        // step at t ≈ T does not advance time; issue 26).
        for x in [0.0, -1e-9, nan, inf, -inf, 5e-324, 1e-310, 1e-300, 3e-15] {
            v.push((
                format!("tau_min_s = {x}"),
                AdaptiveTimeStep { tau_min_s: x, ..b },
                &["tau_min_s"],
            ));
        }
        for x in [0.0, -0.1, nan, inf] {
            v.push((
                format!("tau_max_s = {x}"),
                AdaptiveTimeStep { tau_max_s: x, ..b },
                &["tau_max_s"],
            ));
        }
        for x in [nan, -1e-5, inf, -inf] {
            v.push((
                format!("displacement_scale_m = {x}"),
                AdaptiveTimeStep {
                    displacement_scale_m: Some(x),
                    ..b
                },
                &["displacement_scale_m"],
            ));
            v.push((
                format!("state_scale_s = {x}"),
                AdaptiveTimeStep {
                    state_scale_s: Some(x),
                    ..b
                },
                &["state_scale_s"],
            ));
        }
        for x in [0.0, -0.5, 1.0 + f64::EPSILON, 2.0, nan, inf] {
            v.push((
                format!("safety = {x}"),
                AdaptiveTimeStep { safety: x, ..b },
                &["safety"],
            ));
        }
        for x in [0.0, 1.0, -0.1, 1.5, nan, inf] {
            v.push((
                format!("min_factor = {x}"),
                AdaptiveTimeStep { min_factor: x, ..b },
                &["min_factor"],
            ));
        }
        for x in [1.0, 0.5, 0.0, inf, nan] {
            v.push((
                format!("max_factor = {x}"),
                AdaptiveTimeStep { max_factor: x, ..b },
                &["max_factor"],
            ));
        }
        for x in [nan, 0.0, -1.0] {
            v.push((
                format!("state_change_cap = {x}"),
                AdaptiveTimeStep {
                    state_change_cap: x,
                    ..b
                },
                &["state_change_cap"],
            ));
            v.push((
                format!("slip_rate_floor_mps = {x}"),
                AdaptiveTimeStep {
                    slip_rate_floor_mps: x,
                    ..b
                },
                &["slip_rate_floor_mps"],
            ));
        }
        for x in [0.0, -0.0, nan, -1e-3, inf, -inf] {
            v.push((
                format!("initial_tau_s = {x}"),
                AdaptiveTimeStep {
                    initial_tau_s: Some(x),
                    ..b
                },
                &["initial_tau_s"],
            ));
        }
        v
    };
    for (label, a, fields) in &cases {
        let scene = healing(*a);
        let names: Vec<String> = fields.iter().map(|f| format!("time_step.{f}")).collect();
        let check = |what: &str, e: Error| {
            let name = invalid_name(&e)
                .unwrap_or_else(|| panic!("{label}: {what} gives an untyped error {e:?}"));
            assert!(
                names.iter().any(|n| n == name),
                "{label}: {what} names `{name}` instead of one of {names:?} ({e})"
            );
            assert!(
                e.to_string().contains(name),
                "{label}: the message names the field: {e}"
            );
            assert!(e.to_string().len() < 400, "{label}: a short message: {e}");
        };
        check(
            "step_control()",
            scene
                .step_control()
                .err()
                .unwrap_or_else(|| panic!("{label}: step_control() accepts it")),
        );
        check(
            "validate()",
            scene
                .validate()
                .err()
                .unwrap_or_else(|| panic!("{label}: validate() accepts it")),
        );
        check(
            "build()",
            scene
                .build()
                .err()
                .unwrap_or_else(|| panic!("{label}: build() accepts it")),
        );
    }
}

/// Issue 26: a tolerance outside (ε, 1) and a `tau_min_s` the run cannot resolve are
/// refused with the admissible range in the message, not run (the tolerance 1e-300 with
/// `tau_min_s = 1e-300` ran forever at τ ≈ 1e-79 s).
#[test]
fn out_of_range_tolerance_and_tau_min_name_the_range() {
    for (a, field, range) in [
        (
            AdaptiveTimeStep::new(1.5),
            "time_step.tolerance",
            "(f64::EPSILON",
        ),
        (
            AdaptiveTimeStep::new(1e-300),
            "time_step.tolerance",
            "(f64::EPSILON",
        ),
        (
            AdaptiveTimeStep {
                tau_min_s: 1e-300,
                ..base()
            },
            "time_step.tau_min_s",
            "ε · end_time_s",
        ),
        (
            AdaptiveTimeStep {
                tau_min_s: 5e-324,
                ..base()
            },
            "time_step.tau_min_s",
            "f64::MIN_POSITIVE",
        ),
    ] {
        let e = healing(a).validate().unwrap_err();
        assert_eq!(invalid_name(&e), Some(field), "{e}");
        assert!(e.to_string().contains(range), "{e}");
    }
}

/// Regression: `state_change_cap = -inf` and `slip_rate_floor_mps = -inf` were accepted and
/// silently meant "off", like `+inf`, although a negative cap or floor is invalid (0 and −1
/// are rejected): `SliderScene::step_control` mapped every non-finite value to `None`.
#[test]
fn negative_infinite_cap_and_slip_floor_are_rejected() {
    let b = base();
    let mut failures = Vec::new();
    for (field, a) in [
        (
            "state_change_cap",
            AdaptiveTimeStep {
                state_change_cap: f64::NEG_INFINITY,
                ..b
            },
        ),
        (
            "slip_rate_floor_mps",
            AdaptiveTimeStep {
                slip_rate_floor_mps: f64::NEG_INFINITY,
                ..b
            },
        ),
    ] {
        match healing(a).step_control() {
            Err(e) if invalid_name(&e) == Some(format!("time_step.{field}").as_str()) => {}
            other => failures.push(format!("{field} = -inf: {other:?}")),
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn valid_extreme_options_are_accepted_as_documented() {
    let b = base();
    let below_one = 1.0 - f64::EPSILON / 2.0;
    let mut cases: Vec<(&str, AdaptiveTimeStep)> = vec![
        (
            "tolerance = 2ε, the smallest admissible (up to rounding)",
            AdaptiveTimeStep::new(2.0 * f64::EPSILON),
        ),
        ("tolerance just below 1", AdaptiveTimeStep::new(below_one)),
        (
            "tau_min_s = tau_max_s",
            AdaptiveTimeStep {
                tau_min_s: 0.01,
                tau_max_s: 0.01,
                ..b
            },
        ),
        (
            "tau_min_s = ε · end_time_s, the smallest admissible",
            AdaptiveTimeStep {
                tau_min_s: f64::EPSILON * 15.0,
                ..b
            },
        ),
        (
            "tau_max_s = f64::MAX",
            AdaptiveTimeStep {
                tau_max_s: f64::MAX,
                ..b
            },
        ),
        ("safety = 1", AdaptiveTimeStep { safety: 1.0, ..b }),
        (
            "safety = 5e-324",
            AdaptiveTimeStep {
                safety: 5e-324,
                ..b
            },
        ),
        (
            "min_factor = 5e-324",
            AdaptiveTimeStep {
                min_factor: 5e-324,
                ..b
            },
        ),
        (
            "min_factor just below 1",
            AdaptiveTimeStep {
                min_factor: below_one,
                ..b
            },
        ),
        (
            "max_factor = 1 + eps",
            AdaptiveTimeStep {
                max_factor: 1.0 + f64::EPSILON,
                ..b
            },
        ),
        (
            "max_factor = f64::MAX",
            AdaptiveTimeStep {
                max_factor: f64::MAX,
                ..b
            },
        ),
        (
            "state_change_cap = 5e-324",
            AdaptiveTimeStep {
                state_change_cap: 5e-324,
                ..b
            },
        ),
        (
            "state_change_cap = f64::MAX",
            AdaptiveTimeStep {
                state_change_cap: f64::MAX,
                ..b
            },
        ),
        (
            "state_change_cap = inf",
            AdaptiveTimeStep {
                state_change_cap: f64::INFINITY,
                ..b
            },
        ),
        (
            "slip_rate_floor_mps = 5e-324",
            AdaptiveTimeStep {
                slip_rate_floor_mps: 5e-324,
                ..b
            },
        ),
        (
            "slip_rate_floor_mps = inf",
            AdaptiveTimeStep {
                slip_rate_floor_mps: f64::INFINITY,
                ..b
            },
        ),
    ];
    cases.extend(start_and_scale_cases(b));
    for (label, a) in &cases {
        let scene = healing(*a);
        let c = scene
            .step_control()
            .unwrap_or_else(|e| panic!("{label}: rejected: {e}"))
            .expect("adaptive steps");
        assert_eq!(c.tolerance, a.tolerance, "{label}");
        assert_eq!(
            (c.tau_min, c.tau_max),
            (a.tau_min_s, a.tau_max_s),
            "{label}"
        );
        assert_eq!(
            (c.safety, c.min_factor, c.max_factor),
            (a.safety, a.min_factor, a.max_factor),
            "{label}"
        );
        // `inf` switches the cap and the slip test off; finite values are kept.
        assert_eq!(
            c.state_change_cap,
            a.state_change_cap.is_finite().then_some(a.state_change_cap),
            "{label}"
        );
        assert_eq!(
            c.slip_rate_floor,
            a.slip_rate_floor_mps
                .is_finite()
                .then_some(a.slip_rate_floor_mps),
            "{label}"
        );
        let scale = a.displacement_scale_m.unwrap_or(scene.l_m);
        assert_eq!(c.displacement_atol, a.tolerance * scale, "{label}");
        let state_scale = a
            .state_scale_s
            .unwrap_or(scene.l_m / scene.loading_velocity_m_per_s);
        assert_eq!(c.state_atol, a.tolerance * state_scale, "{label}");
        scene
            .validate()
            .unwrap_or_else(|e| panic!("{label}: validate() rejects it: {e}"));
        let sim = scene
            .build()
            .unwrap_or_else(|e| panic!("{label}: build() fails: {e}"));
        let ctrl = sim.state().controller.expect("adaptive steps");
        assert_eq!(sim.method().step_control(), Some(&c), "{label}");
        let tau0 = scene.initial_tau().clamp(a.tau_min_s, a.tau_max_s);
        assert_eq!(ctrl.tau(), tau0, "{label}: the initial step, clamped");
    }
    // Without loading, the default state scale is 0: a purely relative state test.
    let scene = SliderScene {
        loading_velocity_m_per_s: 0.0,
        ..healing(b)
    };
    let c = scene.step_control().unwrap().unwrap();
    assert_eq!(c.state_atol, 0.0, "no loading: state scale 0");
}

/// Regression: an initial step below ~1e-308 s (finite and > 0, so `step_control` and
/// `validate` accept it) failed in `build()` with `Solver(NonFinite("matrix entries"))`, an
/// error naming neither `initial_tau_s` nor τ: the simulation was built at the unclamped
/// initial step, where 2/τ of `A = (2/τ) M + (τ/2) K` overflows, while the controller
/// starts at the step clamped to `[tau_min_s, tau_max_s]`. Now the simulation starts at the
/// clamped step too, and a time-step matrix that is not finite is an error naming
/// `time_step.initial_tau_s` (a `tau_min_s` that would let the step stay there, e.g.
/// 5e-324, is refused since issue 26).
#[test]
fn tiny_initial_step_builds_or_is_a_named_error() {
    for x in [1e-310, 5e-324] {
        let scene = healing(AdaptiveTimeStep {
            initial_tau_s: Some(x),
            ..base()
        });
        assert!(scene.validate().is_ok(), "initial_tau_s = {x:e} is valid");
        match scene.build() {
            Ok(mut sim) => {
                let outcome = sim
                    .run_until(within(0.5), &mut [])
                    .map(|s| s.steps)
                    .map_err(Error::from);
                assert!(
                    outcome.is_ok() || outcome.as_ref().is_err_and(is_numerical_failure),
                    "initial_tau_s = {x:e}: {outcome:?}"
                );
                assert_state_finite(&format!("initial_tau_s = {x:e}"), &sim, 0.5);
            }
            Err(e) => assert_eq!(
                invalid_name(&e),
                Some("time_step.initial_tau_s"),
                "initial_tau_s = {x:e}: {e:?}"
            ),
        }
    }
}

/// Regression: `run_until(Until::Time(t))` with adaptive steps returned `Ok` without taking
/// a step when the simulation's τ exceeded `1e9 · (t − time)` (the round-off allowance of
/// time comparisons was `1e-9 τ`): with `initial_tau_s = 1e9` the run ended at t = 0. The
/// same allowance skipped the loading's breakpoint: with `tau_max_s = 1e300`,
/// `initial_tau_s = 1e10` and a tolerance that accepts every step, the first step went from
/// 0 to 1e10 s across the end of the ramp at 3.75 s. The allowance is now
/// `1e-9 · min(τ, |t|)`.
#[test]
fn huge_initial_tau_still_reaches_the_end_time_and_the_breakpoint() {
    let mut failures = Vec::new();
    let scene = healing(AdaptiveTimeStep {
        initial_tau_s: Some(1e9),
        ..base()
    });
    let mut sim = scene.build().unwrap();
    let summary = sim.run_until(within(0.5), &mut []).unwrap();
    if sim.time() != 0.5 {
        failures.push(format!(
            "initial_tau_s = 1e9: run_until(Time(0.5)) ends at t = {} after {} steps",
            sim.time(),
            summary.steps
        ));
    }
    // The ramp's end is a breakpoint also for huge steps.
    let scene = healing(AdaptiveTimeStep {
        initial_tau_s: Some(1e10),
        ..free_growth()
    });
    let mut sim = scene.build().unwrap();
    let r = sim.step().unwrap();
    if r.time > scene.ramp_end_s() {
        failures.push(format!(
            "initial_tau_s = 1e10, tau_max_s = 1e300: the first step ends at {} s, past the \
             ramp's end {} s",
            r.time,
            scene.ramp_end_s()
        ));
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn valid_extreme_options_run_finite_or_fail_typed() {
    let budget = 1500;
    for (label, a) in extreme_cases() {
        for (scene_name, scene, t_end) in [
            ("healing through the ramp's end", healing(a), 4.0),
            ("fast loading", fast(a), 0.6),
        ] {
            let label = format!("{label} [{scene_name}]");
            let start = std::time::Instant::now();
            let (outcome, sim) = run_case(&label, &scene, t_end, budget);
            let c = sim.state().controller.expect("adaptive steps");
            println!(
                "{label}: {} at t = {:e} s, τ = {:e} s, {} accepted, {} rejected \
                 ({:.3} s)",
                outcome.describe(),
                sim.time(),
                c.tau(),
                c.accepted(),
                c.rejected(),
                start.elapsed().as_secs_f64()
            );
        }
    }
}

/// The same extremes with the other state law and integrators (fewer steps).
#[test]
fn extreme_options_with_other_laws_and_integrators() {
    let cases = [
        ("tolerance = 1e-12", AdaptiveTimeStep::new(1e-12)),
        ("unbounded growth", free_growth()),
        (
            "tolerance 1e-15, tau_min_s = 1e-14",
            AdaptiveTimeStep {
                tau_min_s: 1e-14,
                ..AdaptiveTimeStep::new(1e-15)
            },
        ),
        (
            "safety = 1e-3, max_factor = 1e6",
            AdaptiveTimeStep {
                safety: 1e-3,
                max_factor: 1e6,
                ..base()
            },
        ),
    ];
    for (label, a) in cases {
        for law in [StateLawKind::Aging, StateLawKind::Slip] {
            for integrator in [
                Integrator::Newmark,
                Integrator::BackwardEuler,
                Integrator::Quasistatic(rsf::time::Quasistatic::new()),
            ] {
                let scene = SliderScene {
                    state_law: law,
                    integrator,
                    ..fast(a)
                };
                let label = format!("{label} [{law:?}, {integrator:?}]");
                let (outcome, sim) = run_case(&label, &scene, 0.6, 300);
                println!("{label}: {} at t = {:e} s", outcome.describe(), sim.time());
            }
        }
    }
}

/// `tau_min_s = tau_max_s` with options that accept every step ([`accept_all`]) and no
/// extrapolation of the state is the fixed step through the adaptive path: bit-identical
/// to fixed steps.
#[test]
fn equal_step_bounds_reproduce_fixed_steps_bit_identically() {
    let fixed = slider(1, 1000);
    let tau = fixed.tau();
    let adaptive = SliderScene {
        time_step: TimeStep::Adaptive(AdaptiveTimeStep {
            tau_min_s: tau,
            tau_max_s: tau,
            state_extrapolation: false,
            ..accept_all(0.5)
        }),
        ..fixed.clone()
    };
    let n = 60;
    let mut a = fixed.build().unwrap();
    a.run(n, &mut []).unwrap();
    let mut b = adaptive.build().unwrap();
    b.run(n, &mut []).unwrap();
    let (ca, cb) = (a.checkpoint().state, b.checkpoint().state);
    assert_eq!((ca.step, ca.time, ca.tau), (cb.step, cb.time, cb.tau));
    let (ka, kb) = (&ca.kinematics, &cb.kinematics);
    assert!(ka.u == kb.u && ka.v == kb.v && ka.a == kb.a && ca.alpha == cb.alpha);
    let c = b.state().controller.unwrap();
    assert_eq!((c.accepted(), c.rejected()), (n as u64, 0));
    // With the default tolerance the first step of the healing fault (θ₀ = e^{-10} s ≪ τ)
    // is rejected, and τ cannot shrink: a typed error, the state unchanged.
    let strict = SliderScene {
        time_step: TimeStep::Adaptive(AdaptiveTimeStep {
            tau_min_s: tau,
            tau_max_s: tau,
            ..base()
        }),
        ..fixed.clone()
    };
    let mut s = strict.build().unwrap();
    let before = s.checkpoint().state;
    let e = s.run(1, &mut []).map_err(Error::from).unwrap_err();
    assert!(
        matches!(e, Error::Time(TimeError::StepTooSmall { tau_min, .. }) if tau_min == tau),
        "{e:?}"
    );
    let after = s.checkpoint().state;
    let (ka, kb) = (&after.kinematics, &before.kinematics);
    assert!(ka.u == kb.u && ka.v == kb.v && after.alpha == before.alpha);
    assert_eq!((after.step, after.time), (0, 0.0));
}

/// `tau_max_s = 1e-6` over 2 ms: two thousand steps, none longer than 1e-6 s, landing on
/// the end time.
#[test]
fn tiny_tau_max_runs_to_the_end() {
    let t_end = 2e-3;
    for (name, scene) in [
        (
            "healing",
            healing(AdaptiveTimeStep {
                tau_max_s: 1e-6,
                ..base()
            }),
        ),
        (
            "fast",
            fast(AdaptiveTimeStep {
                tau_max_s: 1e-6,
                ..base()
            }),
        ),
    ] {
        let label = format!("tau_max_s = 1e-6 [{name}]");
        let (outcome, sim) = run_case(&label, &scene, t_end, 10_000);
        match outcome {
            Outcome::Finished(steps) => {
                assert!((2000..=2001).contains(&steps), "{label}: {steps} steps")
            }
            other => panic!("{label}: {}", other.describe()),
        }
        assert_eq!(sim.time(), t_end, "{label}");
    }
}

/// Checkpoints after runs with extreme options (finished, stopped or failed) continue
/// bit-identically in a freshly built simulation of the same scene.
#[test]
fn checkpoints_after_extreme_runs_resume_bit_identically() {
    let more = 40;
    let mut cases: Vec<(&str, AdaptiveTimeStep)> = extreme_cases()
        .into_iter()
        .filter(|(label, _)| {
            [
                "tolerance = 1e-12",
                "tolerance = 0.5",
                "tau_min_s = 1e-14",
                "tau_max_s = f64::MAX",
                "min_factor = 0.99",
                "max_factor = 1.0001",
                "max_factor = 1e6",
                "safety = 1e-3",
                "initial_tau_s = 1e-12",
                "initial_tau_s = 1e3",
                "displacement_scale_m = 0",
                "state_scale_s = 1e30",
                "state_change_cap = 1e-6",
                "slip_rate_floor_mps = 1e-300",
                "unbounded growth",
                "tolerance 1e-15 with tau_min_s",
            ]
            .iter()
            .any(|p| label.starts_with(p))
        })
        .collect();
    cases.push(("default (tolerance 1e-3)", base()));
    assert!(cases.len() >= 16, "{} cases", cases.len());
    for (label, a) in cases {
        for (scene_name, scene, t1) in [("healing", healing(a), 3.9), ("fast", fast(a), 0.3)] {
            let label = format!("{label} [{scene_name}]");
            let mut straight = scene.build().unwrap();
            let mut watch = Watch::new(&label, 300, t1, a.tau_max_s, 0.0);
            let first = straight
                .run_until(within(t1), &mut [&mut watch])
                .map_err(Error::from);
            watch.assert_clean();
            if let Err(e) = &first {
                assert!(is_numerical_failure(e), "{label}: {e:?}");
            }
            let cp = straight.checkpoint();
            let mut resumed = scene.build().unwrap();
            resumed
                .restore(&cp)
                .unwrap_or_else(|e| panic!("{label}: restore fails: {e}"));
            assert_eq!(resumed.checkpoint(), cp, "{label}: restored as saved");
            let continue_run = |sim: &mut Sim| {
                let mut watch = Watch::new(&label, more, f64::INFINITY, a.tau_max_s, cp.state.time);
                let r = sim
                    .run(more, &mut [&mut watch])
                    .map(|s| (s.steps, s.rejected_attempts))
                    .map_err(Error::from)
                    .map_err(|e| {
                        assert!(is_numerical_failure(&e), "{label}: {e:?}");
                        e.to_string()
                    });
                watch.assert_clean();
                r
            };
            let r_straight = continue_run(&mut straight);
            let r_resumed = continue_run(&mut resumed);
            assert_eq!(r_straight, r_resumed, "{label}: same continuation");
            assert_eq!(
                straight.checkpoint(),
                resumed.checkpoint(),
                "{label}: bit-identical after {more} more steps ({r_straight:?})"
            );
            let counts = |s: &Sim| {
                let c = s.state().controller.unwrap();
                (c.accepted(), c.rejected(), c.tau().to_bits())
            };
            assert_eq!(counts(&straight), counts(&resumed), "{label}");
            let k = straight.kinematics();
            assert!(
                all_finite(&k.u) && all_finite(&k.v) && all_finite(&k.a),
                "{label}: finite after the continuation"
            );
        }
    }
}
