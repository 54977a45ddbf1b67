//! A prescribed change of the fault ODE's load in time (`rsf::fault_ode::LoadChange`,
//! `FaultOde::with_load_change`) on BP8's square fault alone (16 cells of 200 m, the whole
//! space's FFT operator, the injection's pressure driving it):
//!
//! - a change held at `h ≡ 1` from the start is the run whose prestress carries the change
//!   from the start (a model built with `τ⁰ + Δτ`, another path to the same load): the same
//!   trajectory to round-off;
//! - a ramp `h(t) = min(t/T, 1)` with a breakpoint at `T`: a step ends exactly at `T`, and
//!   the trajectory differs from the unchanged run's;
//! - refusals: another number of forces, a non-finite force, a non-finite `h`.

use std::sync::Arc;

use rsf::fault_alone::FaultAlone;
use rsf::fault_ode::LoadChange;
use rsf::Until;
use rsf_scenes::square_fault::{square_cells, square_model, square_operator};
use rsf_scenes::{Bp8Overpressure, Bp8Source, SeasBp8, SeasBp8FaultOde};

const DX: f64 = 200.0;

/// The traction change (Pa) along x₂ at `(x₂, x₃)`: 0.5 MPa, a Gaussian of 200 m about
/// (−100, 100) m.
fn delta_tau(x2: f64, x3: f64) -> f64 {
    let r2 = (x2 + 100.0).powi(2) + (x3 - 100.0).powi(2);
    0.5e6 * (-r2 / (2.0 * 200.0 * 200.0)).exp()
}

/// BP8-GS on 16 cells with the prestress `τ⁰ + (extra(x₂, x₃), 0)`.
fn bp8_ode(extra: impl Fn(f64, f64) -> f64) -> SeasBp8FaultOde {
    let bp8 = SeasBp8::default();
    let field = bp8.pressure(Bp8Source::Gaussian, DX).unwrap();
    let pressure = bp8
        .friction_pressure(field, Bp8Overpressure::Refuse)
        .unwrap();
    let tau0 = bp8.tau0();
    let cells = square_cells(bp8.l_f, DX).unwrap();
    let model = square_model(&cells, DX, |x2, x3| [tau0[0] + extra(x2, x3), tau0[1]]).unwrap();
    let operator = square_operator(&model, bp8.medium().unwrap()).unwrap();
    let alone = FaultAlone {
        operator: Box::new(operator),
        plate_velocity: vec![0.0; 2 * model.vertices.len()],
    };
    bp8.problem_builder(model, pressure)
        .unwrap()
        .build_fault_ode_alone(bp8.fault_ode_options(1e-8).unwrap(), alone)
        .unwrap()
}

/// The forces of `delta_tau` on `ode`'s cells: `Δx² Δτ` on each cell's x₂ unknown.
fn forces(ode: &SeasBp8FaultOde) -> Vec<f64> {
    ode.model()
        .vertices
        .iter()
        .flat_map(|x| [DX * DX * delta_tau(x[1], x[2]), 0.0])
        .collect()
}

#[test]
fn a_change_held_from_the_start_is_the_prestress_that_carries_it() {
    let mut carried = bp8_ode(delta_tau);
    let plain = bp8_ode(|_, _| 0.0);
    let f = forces(&plain);
    let mut changed = plain
        .with_load_change(LoadChange {
            forces: f,
            history: Arc::new(|_| 1.0),
            breakpoints: Vec::new(),
        })
        .unwrap();
    // Two days: the injection's transient under way.
    let end = Until::Time(2.0 * 86_400.0);
    carried.run_until(end, &mut []).unwrap();
    changed.run_until(end, &mut []).unwrap();
    let (a, b) = (carried.state(), changed.state());
    assert_eq!(a.time, b.time);
    let scale = a.kinematics.u.iter().fold(0.0_f64, |m, u| m.max(u.abs()));
    // The injection has moved the fault beyond its creep (V_init · 2 days = 1.7e-7 m).
    assert!(scale > 1e-6, "the fault slipped: {scale} m");
    for (x, y) in a.kinematics.u.iter().zip(&b.kinematics.u) {
        assert!((x - y).abs() <= 1e-9 * scale, "slip {x} against {y}");
    }
    for (x, y) in a.alpha.iter().zip(&b.alpha) {
        assert!((x - y).abs() <= 1e-9, "ln θ {x} against {y}");
    }
}

#[test]
fn a_ramp_ends_a_step_at_its_breakpoint_and_changes_the_run() {
    let ramp = 3600.0;
    let plain_run = |change: bool| {
        let ode = bp8_ode(|_, _| 0.0);
        let f = forces(&ode);
        let mut ode = if change {
            ode.with_load_change(LoadChange {
                forces: f,
                history: Arc::new(move |t| (t / ramp).min(1.0)),
                breakpoints: vec![ramp],
            })
            .unwrap()
        } else {
            ode
        };
        let mut times = Vec::new();
        while ode.state().time < 2.0 * ramp {
            ode.run_until(Until::Steps(1), &mut []).unwrap();
            times.push(ode.state().time);
        }
        (times, ode.state().kinematics.u.clone())
    };
    let (times, u) = plain_run(true);
    assert!(times.contains(&ramp), "no step ends at {ramp} s: {times:?}");
    let (_, u0) = plain_run(false);
    let moved = u
        .iter()
        .zip(&u0)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(moved > 0.0, "the change changed nothing");
}

#[test]
fn careless_changes_are_typed_errors() {
    let name = |change: LoadChange| match bp8_ode(|_, _| 0.0).with_load_change(change) {
        Err(rsf::Error::InvalidParameter { name, .. }) => name,
        other => panic!("{other:?}"),
    };
    let n = 2 * 16;
    let ok = |_: f64| 1.0;
    assert_eq!(
        name(LoadChange {
            forces: vec![0.0; n - 1],
            history: Arc::new(ok),
            breakpoints: Vec::new(),
        }),
        "load_change.forces"
    );
    let mut bad = vec![0.0; n];
    bad[3] = f64::NAN;
    assert_eq!(
        name(LoadChange {
            forces: bad,
            history: Arc::new(ok),
            breakpoints: Vec::new(),
        }),
        "load_change.forces"
    );
    assert_eq!(
        name(LoadChange {
            forces: vec![0.0; n],
            history: Arc::new(|_| f64::INFINITY),
            breakpoints: Vec::new(),
        }),
        "load_change.history"
    );
    assert_eq!(
        name(LoadChange {
            forces: vec![0.0; n],
            history: Arc::new(ok),
            breakpoints: vec![f64::NAN],
        }),
        "load_change.breakpoints"
    );
}
