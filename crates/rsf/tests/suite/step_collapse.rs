//! A run that cannot progress ends with a typed error naming the time, the step and the
//! last rejected error estimate — as an ODE solver reports a step-size underflow — in every
//! engine (issue 74): its accepted steps at the method's floor for `COLLAPSE_STEPS` steps
//! in a row, or its stated number of steps (`Until::TimeWithin`) spent before its end.

use rsf::observe::SECONDS_PER_YEAR;
use rsf::run::COLLAPSE_STEPS;
use rsf::{Error, Until};

use crate::common::small_bp1;

/// The small BP1's fault ODE with its step held within `[dt_min, 1.5 dt_min]` (its first
/// step, 0.01 s, inside): every accepted step is at the floor.
fn pinned_fault_ode(
    dt_min: f64,
) -> rsf::FaultOde<2, rsf::friction::AsinhLaw, rsf::state::Aging, 1> {
    let (bp1, grid) = small_bp1(&rsf_scenes::SeasBp1::default());
    let model = bp1.model(&grid, false).unwrap();
    let mut options = bp1.fault_ode_options(1e-6).unwrap();
    options.runge_kutta.dt_min = dt_min;
    options.runge_kutta.dt_max = 1.5 * dt_min;
    bp1.fault_ode(model, options).unwrap()
}

/// The fault ODE whose steps stay at their floor ends after `COLLAPSE_STEPS` steps with
/// `StepSizeCollapse` naming the time and the step; a run just above the floor does not.
#[test]
fn a_fault_ode_stuck_at_its_floor_ends_with_a_named_error() {
    let mut ode = pinned_fault_ode(8e-3);
    let e = ode
        .run_until(Until::Time(SECONDS_PER_YEAR), &mut [])
        .unwrap_err();
    assert_eq!(e.summary.steps, COLLAPSE_STEPS, "{e}");
    let Error::StepSizeCollapse {
        time, tau, reason, ..
    } = &e.error
    else {
        panic!("{}", e.error)
    };
    assert!(
        *tau <= 2.0 * 8e-3 && *time > 0.0 && *time < 2.0,
        "{time} {tau}"
    );
    let text = e.error.to_string();
    assert!(
        text.contains("floor") && text.contains("t = ") && text.contains("τ = "),
        "{text}"
    );
    assert!(reason.contains(&COLLAPSE_STEPS.to_string()), "{reason}");
    // The default floor (1e-6 s of the SEAS options) is far below BP1's steps: no error.
    let (bp1, grid) = small_bp1(&rsf_scenes::SeasBp1::default());
    let mut ode = bp1
        .fault_ode(
            bp1.model(&grid, false).unwrap(),
            bp1.fault_ode_options(1e-6).unwrap(),
        )
        .unwrap();
    ode.run_until(
        Until::TimeWithin {
            time: 20.0 * SECONDS_PER_YEAR,
            max_steps: 100_000,
        },
        &mut [],
    )
    .unwrap();
}

/// A stated bound of steps that does not reach the end time ends the run with the error,
/// naming the bound; the same run with room reaches its end.
#[test]
fn a_run_past_its_stated_steps_ends_with_a_named_error() {
    let (bp1, grid) = small_bp1(&rsf_scenes::SeasBp1::default());
    let build = || {
        bp1.fault_ode(
            bp1.model(&grid, false).unwrap(),
            bp1.fault_ode_options(1e-6).unwrap(),
        )
        .unwrap()
    };
    let t_end = 20.0 * SECONDS_PER_YEAR;
    let steps = build()
        .run_until(
            Until::TimeWithin {
                time: t_end,
                max_steps: 1_000_000,
            },
            &mut [],
        )
        .unwrap()
        .steps;
    let e = build()
        .run_until(
            Until::TimeWithin {
                time: t_end,
                max_steps: steps / 2,
            },
            &mut [],
        )
        .unwrap_err();
    assert_eq!(e.summary.steps, steps / 2);
    let text = e.error.to_string();
    assert!(
        matches!(e.error, Error::StepSizeCollapse { .. })
            && text.contains(&format!("{} steps", steps / 2)),
        "{text}"
    );
}

/// The implicit scheme with adaptive steps held at `tau_min` (its `tau_max` there) ends
/// with the same error after `COLLAPSE_STEPS` steps.
#[test]
fn the_implicit_scheme_stuck_at_its_floor_ends_with_a_named_error() {
    use rsf_scenes::{AdaptiveTimeStep, SliderScene, TimeStep};
    let scene = SliderScene {
        level: 1,
        end_time_s: 1.0,
        time_step: TimeStep::Adaptive(AdaptiveTimeStep {
            tau_min_s: 1e-5,
            tau_max_s: 1e-5,
            initial_tau_s: Some(1e-5),
            ..AdaptiveTimeStep::new(1e-3)
        }),
        ..SliderScene::default()
    };
    let mut sim = scene.build().unwrap();
    let e = sim.run_until(Until::Time(1.0), &mut []).unwrap_err();
    assert_eq!(e.summary.steps, COLLAPSE_STEPS, "{e}");
    assert!(
        matches!(e.error, Error::StepSizeCollapse { tau, .. } if tau <= 2e-5),
        "{}",
        e.error
    );
}
