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

/// The station values of every step as the run's observers see them: time → per station
/// (signed slip m, log10 V, shear stress MPa, normal stress MPa, log10 θ).
#[derive(Default)]
struct StationValues {
    nodes: Vec<usize>,
    rows: std::collections::HashMap<u64, Vec<[f64; 5]>>,
}

impl Observer<2> for StationValues {
    fn observe(&mut self, s: &StepView<'_, 2, 2>) -> rsf::Result<Flow> {
        let row = self
            .nodes
            .iter()
            .map(|&k| {
                let p = s.model.frictional_boundary.nodes[k];
                [
                    s.state.kinematics.u[2 * p] - s.model.initial_displacement[2 * p],
                    s.slip_rate(k).log10(),
                    s.shear_traction(k) / 1e6,
                    s.normal_traction(k).unwrap() / 1e6,
                    s.state.alpha[k] / std::f64::consts::LN_10,
                ]
            })
            .collect();
        self.rows.insert(s.state.time.to_bits(), row);
        Ok(Flow::Continue(()))
    }
}

/// BP3's files read back by the description's rules — header lines, six `# Column #k`
/// lines, the field-list line `t slip slip_rate shear_stress normal_stress state`, rows
/// of six numbers with time increasing from 0, `num_time_steps` the rows in the file —
/// and their numbers against the run's own (slip signed: negative on the normal fault,
/// the normal stress changing).
#[test]
fn the_bp3_files_follow_the_description_and_hold_the_runs_values() {
    use rsf::observe::{FileMode, SeasOutput, SeasSampling};
    let bp3 = SeasBp3::normal();
    let model = bp3.model(&GRID).unwrap();
    let dir = std::env::temp_dir().join(format!("rsf-seas-bp3-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let sampling = SeasSampling {
        station_quiet: SECONDS_PER_YEAR,
        ..SeasSampling::default()
    };
    let setup = rsf::observe::SeasSetup {
        date: "2026-11-25".into(),
        ..bp3.seas_setup(GRID.dx, sampling)
    };
    let stations = setup.stations.clone();
    let options = bp3.params.fault_ode_options(1e-7).unwrap();
    let mut ode = bp3.fault_ode(model, options).unwrap();
    let fb = &ode.model().frictional_boundary;
    let nodes = stations
        .iter()
        .map(|(_, xd)| {
            (0..fb.len())
                .min_by(|&a, &b| {
                    let d = |k: usize| (bp3.x_d(&ode.model().vertices[fb.nodes[k]]) - xd).abs();
                    d(a).total_cmp(&d(b))
                })
                .unwrap()
        })
        .collect();
    let mut values = StationValues {
        nodes,
        ..StationValues::default()
    };
    let mut out = SeasOutput::new(
        &dir,
        ode.model(),
        ode.problem().friction_laws(),
        setup,
        FileMode::Create,
    )
    .unwrap();
    out.write_initial_state(ode.model(), ode.state()).unwrap();
    ode.run_until(
        rsf::Until::Time(150.0 * SECONDS_PER_YEAR),
        &mut [&mut out, &mut values],
    )
    .unwrap();
    assert!(!out.events().is_empty(), "an event within 150 years");
    let mut normal_range = (f64::INFINITY, f64::NEG_INFINITY);
    let mut checked = 0;
    for (i, (name, _)) in stations.iter().enumerate() {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let header: Vec<&str> = lines
            .iter()
            .copied()
            .take_while(|l| l.starts_with('#'))
            .collect();
        for key in [
            "problem=SEAS Benchmark BP3-QD",
            "code=rsf",
            "location=on fault",
        ] {
            assert!(header.iter().any(|l| l.contains(key)), "{name}: {key}");
        }
        for k in 1..=6 {
            assert!(header
                .iter()
                .any(|l| l.starts_with(&format!("# Column #{k} = "))));
        }
        assert_eq!(
            lines[header.len()],
            "t slip slip_rate shear_stress normal_stress state"
        );
        let rows: Vec<Vec<f64>> = lines[header.len() + 1..]
            .iter()
            .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
            .collect();
        let declared: usize = header
            .iter()
            .find_map(|l| l.strip_prefix("# num_time_steps="))
            .unwrap()
            .parse()
            .unwrap();
        assert_eq!(declared, rows.len(), "{name}");
        assert_eq!(rows[0][0], 0.0, "{name}: a first row at t = 0");
        assert!(
            rows.windows(2).all(|w| w[1][0] > w[0][0]),
            "{name}: time increases"
        );
        for r in &rows[1..] {
            assert_eq!(r.len(), 6, "{name}");
            let seen = values.rows.get(&r[0].to_bits()).unwrap_or_else(|| {
                // The file's time is printed with 13 digits: find the step.
                let (_, v) = values
                    .rows
                    .iter()
                    .min_by(|a, b| {
                        (f64::from_bits(*a.0) - r[0])
                            .abs()
                            .total_cmp(&(f64::from_bits(*b.0) - r[0]).abs())
                    })
                    .unwrap();
                v
            })[i];
            for c in 0..5 {
                let tol = 1e-6 * seen[c].abs().max(1e-12);
                assert!(
                    (r[c + 1] - seen[c]).abs() <= tol,
                    "{name} col {}: {} vs {}",
                    c + 2,
                    r[c + 1],
                    seen[c]
                );
            }
            normal_range = (normal_range.0.min(r[4]), normal_range.1.max(r[4]));
            checked += 1;
        }
        if i == 0 {
            // The normal fault slips negatively.
            assert!(
                rows.last().unwrap()[1] < 0.0,
                "{name}: slip {}",
                rows.last().unwrap()[1]
            );
        }
    }
    eprintln!(
        "{checked} station rows checked; normal stress in the files {:.3} … {:.3} MPa",
        normal_range.0, normal_range.1
    );
    assert!(normal_range.1 - normal_range.0 > 0.1);
    std::fs::remove_dir_all(&dir).ok();
}
