//! A coarse SEAS BP3-QD (`SeasBp3`, docs/seas-bp3.md): the thrust reaches its first event
//! in CI time with its normal stress changing, and the two engines (the fault ODE, the
//! implicit scheme with adaptive steps) agree on the slip before it.
use rsf::observe::{StepView, SECONDS_PER_YEAR};
use rsf::{Flow, Observer};
use rsf_scenes::{SeasBp3, SeasBp3Grid};

/// A coarse grid: 2 km along the fault, a 100 km box.
const GRID: SeasBp3Grid = SeasBp3Grid {
    dx: 2000.0,
    domain: 100e3,
    ratio: 1.2,
};

/// The first step with max V ≥ 1e-3 m/s, the slip of every frictional node at the last
/// step, and the extreme normal stresses seen.
#[derive(Default)]
struct Watch {
    first_event: Option<f64>,
    slip: Vec<f64>,
    sigma: (f64, f64),
}

impl Observer<2> for Watch {
    fn observe(&mut self, s: &StepView<'_, 2, 2>) -> rsf::Result<Flow> {
        let n = s.model.frictional_boundary.len();
        let v_max = (0..n).map(|k| s.slip_rate(k)).fold(0.0, f64::max);
        if v_max >= 1e-3 && self.first_event.is_none() {
            self.first_event = Some(s.state.time);
        }
        self.slip = (0..n).map(|k| s.slip(k)[0].hypot(s.slip(k)[1])).collect();
        for k in 0..n {
            let sn = s.normal_traction(k).unwrap();
            self.sigma = (self.sigma.0.min(sn), self.sigma.1.max(sn));
        }
        Ok(Flow::Continue(()))
    }
}

#[test]
fn a_coarse_bp3_thrust_reaches_its_first_event_with_a_changing_normal_stress() {
    let bp3 = SeasBp3::thrust();
    let model = bp3.model(&GRID).unwrap();
    let options = bp3.params.fault_ode_options(1e-7).unwrap();
    let mut ode = bp3.fault_ode(model, options).unwrap();
    let mut watch = Watch {
        sigma: (f64::INFINITY, 0.0),
        ..Watch::default()
    };
    let clock = std::time::Instant::now();
    ode.run_until(
        rsf::Until::Time(400.0 * SECONDS_PER_YEAR),
        &mut [&mut watch],
    )
    .unwrap();
    let first = watch.first_event.expect("an event within 400 years") / SECONDS_PER_YEAR;
    eprintln!(
        "first event at {first:.3} yr; normal stress between {:.3} and {:.3} MPa; {:.1} s",
        watch.sigma.0 / 1e6,
        watch.sigma.1 / 1e6,
        clock.elapsed().as_secs_f64()
    );
    // The fault loads at V_p for about a century before it fails; its normal stress moves.
    assert!(first > 50.0 && first < 400.0, "{first}");
    assert!(watch.sigma.1 - watch.sigma.0 > 1e5, "{:?}", watch.sigma);
}

#[test]
fn the_two_engines_agree_on_a_coarse_bp3_before_its_first_event() {
    let bp3 = SeasBp3::normal();
    let t_end = 50.0 * SECONDS_PER_YEAR;
    let model = bp3.model(&GRID).unwrap();
    let options = bp3.params.fault_ode_options(1e-8).unwrap();
    let mut ode = bp3.fault_ode(model.clone(), options).unwrap();
    let mut a = Watch::default();
    ode.run_until(rsf::Until::Time(t_end), &mut [&mut a])
        .unwrap();
    let mut sim = bp3
        .problem_builder(model)
        .unwrap()
        .solver(rsf::SolverKind::Direct)
        .time_step(1e-2)
        .step_control(bp3.params.step_control(1e-5).unwrap())
        .build()
        .unwrap();
    let mut b = Watch::default();
    sim.run_until(rsf::Until::Time(t_end), &mut [&mut b])
        .unwrap();
    let scale = a.slip.iter().fold(0.0f64, |m, x| m.max(*x));
    let d = a
        .slip
        .iter()
        .zip(&b.slip)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    eprintln!("slip after 50 years: largest {scale:.4} m; engines differ by {d:e} m");
    assert!(scale > 1.0, "the creep below W_f loads the fault: {scale}");
    assert!(d < 1e-3 * scale, "{d:e}");
}
