//! The library observers: slip-event detection (hysteresis, catalogue, stopping a run at
//! an event) and the in-memory recorder.

use crate::common::within;
use rsf::observe::{
    EventDetector, EventThresholds, FaultRecorder, Recorder, SlipEvents, StopAt, Transition,
};
use rsf_scenes::{SliderScene, SLIDER_CENTRE};

/// Rates with ringing around the onset threshold inside the first event.
const RATES: [f64; 8] = [1e-6, 2e-3, 5e-4, 3e-3, 1e-3, 5e-5, 4e-3, 1e-6];

#[test]
fn hysteresis_counts_ringing_as_one_event() {
    let mut d = EventDetector::new(EventThresholds::default())
        .unwrap()
        .with_slip_at(&[0.0, 0.0]);
    let mut transitions = Vec::new();
    for (i, &v) in RATES.iter().enumerate() {
        // The node moves by i² m in x, so an event's slip is a difference of squares.
        let u = [(i * i) as f64, 0.0];
        transitions.push(d.push(i + 1, i as f64, v, &u));
    }
    use Transition::*;
    assert_eq!(
        transitions,
        [None, Onset, None, None, None, End, Onset, End]
    );
    let e = d.events();
    assert_eq!(e.len(), 2);
    assert_eq!(
        (e[0].onset_step, e[0].onset_s, e[0].end),
        (2, 1.0, Some((6, 5.0)))
    );
    assert_eq!((e[0].peak_slip_rate, e[0].peak_s), (3e-3, 3.0));
    assert_eq!(e[0].duration_s(), Some(4.0));
    // ln V from ln 1e-6 (t = 0) to ln 2e-3 (t = 1) crosses ln 1e-3 at ln(1e3)/ln(2e3).
    let expected = 1e3f64.ln() / 2e3f64.ln();
    assert!((e[0].crossing_s - expected).abs() < 1e-15);
    assert!((e[1].crossing_s - (5.0 + 20f64.ln() / 80f64.ln())).abs() < 1e-14);
    // From the step before the onset (u = 0²) to the end (u = 5²).
    assert_eq!(e[0].slip, Some(25.0));
    assert_eq!(e[1].slip, Some((49 - 25) as f64));
    assert_eq!(d.recurrence_interval_s(), Some(5.0));
    assert!(!d.slipping());
}

#[test]
fn without_a_node_no_slip_is_measured() {
    let mut d = EventDetector::new(EventThresholds {
        onset: 1e-3,
        end: 1e-3,
    })
    .unwrap();
    for (i, &v) in RATES.iter().enumerate() {
        d.push(i + 1, i as f64, v, &[]);
    }
    // Without hysteresis the ringing makes two events of the first one.
    assert_eq!(d.events().len(), 3);
    assert!(d.events().iter().all(|e| e.slip.is_none()));
}

/// The paper's slider at level 2 loaded fast (2 cm/s from t = 0, τ = 1 ms): its largest
/// slip rate passes 1e-3 m/s within a few hundred steps (measured: onset at step 46, end at
/// step 65); the run stops where this first event ends, and the catalogue agrees with what
/// the recorder saw.
#[test]
fn a_run_stops_at_the_end_of_the_first_event() {
    let scene = SliderScene {
        level: 2,
        steps: 1000,
        end_time_s: 1.0,
        loading_velocity_m_per_s: 2e-2,
        ramp_fraction: 0.0,
        ..SliderScene::default()
    };
    let mut sim = scene.build().unwrap();
    let x0 = sim.model().nearest_node(&SLIDER_CENTRE).unwrap();
    let mut events = SlipEvents::new(EventThresholds::default())
        .unwrap()
        .slip_at(sim.model(), x0)
        .unwrap()
        .stop(StopAt::End(1));
    let mut rec = Recorder::new(sim.model(), &[x0]).unwrap();
    let mut fault = FaultRecorder::new(sim.model());
    let summary = sim
        .run_until(
            within(scene.end_time_s),
            &mut [&mut events, &mut rec, &mut fault],
        )
        .unwrap();
    assert!(summary.stopped_by_observer(), "no slip event within 1 s");
    let e = &events.events()[0];
    let (end_step, end_s) = e.end.unwrap();
    assert_eq!(end_step, sim.step_index());
    assert!(end_s > e.onset_s && e.peak_s >= e.onset_s && e.peak_s < end_s);
    // The recorder's series: onset is the first step above 1e-3 m/s, the peak its maximum.
    let rates: Vec<f64> = rec.reports().iter().map(|r| r.max_slip_rate).collect();
    let first = rates.iter().position(|&v| v > 1e-3).unwrap();
    assert_eq!(rec.reports()[first].step, e.onset_step);
    let peak = rates[first..].iter().copied().fold(0.0, f64::max);
    assert_eq!(peak, e.peak_slip_rate);
    assert!(rates[..rates.len() - 1][first..].iter().all(|&v| v >= 1e-4));
    assert!(rates[rates.len() - 1] < 1e-4);
    // Slip at x0 over the event: the displacement difference from the step before.
    let u: Vec<[f64; 2]> = rec.displacement(0).collect();
    let du = [
        u[end_step - 1][0] - u[first - 1][0],
        u[end_step - 1][1] - u[first - 1][1],
    ];
    assert_eq!(e.slip, Some(du[0].hypot(du[1])));
    assert!(e.slip.unwrap() > 0.0, "x0 moves during the event");
    // Γ_F snapshots every step, ordered along the boundary.
    assert_eq!(fault.snapshots(), rec.len());
    let last = fault.snapshots() - 1;
    assert_eq!(
        fault.slip_rates(last).len(),
        sim.model().frictional_boundary.len()
    );
    assert_eq!(fault.snapshot_time(last), Some((end_step, end_s)));
    let xs: Vec<f64> = fault
        .fault_nodes()
        .iter()
        .map(|&p| sim.model().vertices[p][0])
        .collect();
    assert!(xs.windows(2).all(|w| w[0] < w[1]));
    let peak_profile = fault.slip_rates(last).iter().copied().fold(0.0, f64::max);
    assert_eq!(peak_profile, rates[rates.len() - 1]);
}
