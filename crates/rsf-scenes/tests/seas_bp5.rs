//! SEAS BP5-QD as a fault alone (docs/seas-bp5.md): the description's check values at
//! t = 0, a coarse run's ruptures and files, the second slip component, a stopped and
//! continued run, and the off-fault displacement against one big Okada rectangle.

use std::path::Path;

use rsf::halfspace::okada::{dc3d, Rectangle};
use rsf::observe::{SeasLayout, SeasSampling, SeasSetup, SECONDS_PER_YEAR};
use rsf::{Observer, Until};
use rsf_scenes::{SeasBp5, SeasBp5Output, SEAS_BP5_BODY_STATIONS};

/// The prestress of the description, written out here from its formula (not the scene's
/// code): τ⁰ = σ̄_n a asinh(V/(2V₀) exp((f₀ + b ln(V₀/V_p))/a)) + η V (Pa).
fn published_tau0(a: f64, v: f64) -> f64 {
    let (sigma, f0, b, v0, v_p) = (25e6, 0.6, 0.03, 1e-6, 1e-9);
    let eta = 2670.0 * 3464.0 * 3464.0 / (2.0 * 3464.0);
    sigma * a * (v / (2.0 * v0) * ((f0 + b * (v0 / v_p).ln()) / a).exp()).asinh() + eta * v
}

fn setup(dx: f64) -> SeasSetup {
    SeasSetup {
        problem: "SEAS Benchmark BP5-QD".into(),
        modeler: "test".into(),
        date: "2026-11-26".into(),
        element_size: dx,
        stations: Vec::new(),
        depth_axis: 2,
        depth_down: false,
        sigma_n: 25e6,
        profile_spacing: dx,
        sampling: SeasSampling::default(),
        layout: SeasLayout::default(),
        surface_stations: Vec::new(),
    }
}

#[test]
fn the_initial_values_are_the_descriptions_check_values() {
    let bp5 = SeasBp5::default();
    // The description's check values (MPa; log10 s), and the published formulas.
    let checks = [
        ((0.0, 10e3), 19.490, 8.146),   // weakening core
        ((45e3, 10e3), 13.273, 8.146),  // a = a_max
        ((-24e3, 10e3), 21.350, 8.114), // nucleation patch
    ];
    for ((x2, x3), tau_mpa, log_theta) in checks {
        let (a, v) = if x2 > 40e3 {
            (0.04, 1e-9)
        } else if x2 < -18e3 {
            (0.004, 0.03)
        } else {
            (0.004, 1e-9)
        };
        assert!(
            (published_tau0(a, v) / 1e6 - tau_mpa).abs() < 5e-4,
            "formula at {x2}"
        );
        assert!(
            (bp5.tau0(x2, x3) / 1e6 - tau_mpa).abs() < 5e-4,
            "scene at {x2}: {}",
            bp5.tau0(x2, x3)
        );
        let theta = bp5.alpha0(x2, x3).exp();
        assert!((theta.log10() - log_theta).abs() < 5e-4, "θ at {x2}");
    }
    // The run starts where the description says: V = V_init, V_i in the patch.
    let dx = 4000.0;
    let model = bp5.model(dx).unwrap();
    let ode = bp5
        .fault_ode(
            model,
            bp5.fault_ode_options(1e-6).unwrap(),
            &bp5.half_space(1e-6).unwrap(),
        )
        .unwrap();
    let cells = bp5.cells(dx).unwrap();
    let v = &ode.state().kinematics.v;
    for (k, c) in cells.iter().enumerate() {
        let expected = bp5.initial_slip_rate(c[0], c[1]);
        let (v2, v3) = (v[3 * k + 1], v[3 * k + 2]);
        assert!(
            (v2 / expected - 1.0).abs() < 1e-9,
            "cell {k}: V₂ = {v2:e}, expected {expected:e}"
        );
        assert!(v3.abs() < 1e-12 * expected, "cell {k}: V₃ = {v3:e}");
    }
}

/// The rows of a SEAS file: checks its header (problem, `# Column #k` lines, the field
/// line, `num_time_steps`) and every number's `%E` form.
fn parse(path: &Path, columns: usize) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let mut header = Vec::new();
    for line in lines.by_ref() {
        if !line.starts_with('#') {
            assert_eq!(
                line.split(' ').count(),
                columns,
                "{}: field line {line}",
                path.display()
            );
            break;
        }
        header.push(line);
    }
    assert!(
        header.contains(&"# problem=SEAS Benchmark BP5-QD"),
        "{}",
        path.display()
    );
    let described = header
        .iter()
        .filter(|l| l.starts_with("# Column #"))
        .count();
    assert_eq!(described, columns, "{}", path.display());
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            let tokens: Vec<&str> = l.split_whitespace().collect();
            assert_eq!(tokens.len(), columns, "{}: {l}", path.display());
            for (i, t) in tokens.iter().enumerate() {
                let (mantissa, exponent) = t.split_once('E').expect("an %E number");
                let digits = mantissa
                    .trim_start_matches('-')
                    .split_once('.')
                    .unwrap()
                    .1
                    .len();
                assert_eq!(digits, if i == 0 { 13 } else { 6 }, "{t}");
                assert!(
                    exponent.len() == 3 && (exponent.starts_with('+') || exponent.starts_with('-'))
                );
            }
            tokens.iter().map(|t| t.parse().unwrap()).collect()
        })
        .collect();
    let count: usize = header
        .iter()
        .find_map(|l| l.strip_prefix("# num_time_steps="))
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(count, rows.len(), "{}", path.display());
    rows
}

#[test]
fn a_coarse_run_reaches_two_ruptures_and_writes_the_benchmarks_files() {
    let bp5 = SeasBp5::default();
    let dx = 4000.0;
    let dir = std::env::temp_dir().join(format!("rsf_bp5_coarse_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let (mut ode, columns) = bp5
        .fault_ode_with_stations(
            bp5.model(dx).unwrap(),
            bp5.fault_ode_options(1e-6).unwrap(),
            &bp5.half_space(1e-6).unwrap(),
            &SeasBp5::body_station_points(),
        )
        .unwrap();
    let mut output = SeasBp5Output::new(&dir, &bp5, dx, columns, setup(dx)).unwrap();
    output.write_initial_state(
        ode.model(),
        ode.state(),
        rsf::Stepping::fault_tractions(&ode),
    );
    ode.run_until(Until::Time(250.0 * SECONDS_PER_YEAR), &mut [&mut output])
        .unwrap();
    let ruptures: Vec<_> = output
        .events()
        .iter()
        .filter(|e| e.peak_slip_rate > 0.1)
        .collect();
    // The patch fails at once; the next rupture a cycle later (~180 years at 4 km cells,
    // 236 at 1 km; a cycle is at least the time to reload the stress drop of a few MPa at
    // V_p over the weakening core, far more than a few years).
    assert!(ruptures.len() >= 2, "{:?}", output.events());
    assert!(
        ruptures[0].t_start < 1000.0,
        "first rupture at {} s",
        ruptures[0].t_start
    );
    let recurrence = (ruptures[1].t_start - ruptures[0].t_start) / SECONDS_PER_YEAR;
    assert!(
        (100.0..300.0).contains(&recurrence),
        "recurrence {recurrence} yr"
    );
    // Peak slip rates of a rupture: ~1 m/s (the description's codes: 1–3 m/s).
    assert!(ruptures
        .iter()
        .all(|e| (0.3..10.0).contains(&e.peak_slip_rate)));
    for name in SeasBp5Output::file_names() {
        let columns = match &name[..5] {
            "fltst" => 8,
            "blkst" => 7,
            _ => 3,
        };
        let rows = parse(&dir.join(&name), columns);
        assert!(rows.len() > 100, "{name}: {} rows", rows.len());
        assert_eq!(rows[0][0], 0.0, "{name}: the first row is t = 0");
        assert!(
            rows.windows(2).all(|w| w[1][0] > w[0][0]),
            "{name}: time increases"
        );
        if name.starts_with("fltst") {
            // Slip along x₃ (the loading is along x₂) stays small: computed, bounded.
            let slip2 = rows.iter().map(|r| r[1].abs()).fold(0.0, f64::max);
            let slip3 = rows.iter().map(|r| r[2].abs()).fold(0.0, f64::max);
            assert!(slip2 > 1.0, "{name}: slip₂ {slip2} m");
            assert!(
                slip3 < 0.05 * slip2,
                "{name}: slip₃ {slip3} m against slip₂ {slip2} m"
            );
            assert!(slip3 > 0.0, "{name}: slip₃ is computed, not assumed 0");
            // V₃ below V₂ whenever V₂ is seismic.
            for r in rows.iter().filter(|r| r[3] > -3.0) {
                assert!(
                    r[4] < r[3] - 0.5,
                    "{name}: log10 V₃ {} against log10 V₂ {}",
                    r[4],
                    r[3]
                );
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_stopped_and_continued_run_writes_the_same_bytes() {
    let bp5 = SeasBp5::default();
    let dx = 4000.0;
    let base = std::env::temp_dir().join(format!("rsf_bp5_resume_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    let end = Until::Time(190.0 * SECONDS_PER_YEAR);
    let every = 200;
    let run = |dir: &Path, stop: Option<usize>, resume: Option<&rsf::Checkpoint>| {
        let (mut ode, columns) = bp5
            .fault_ode_with_stations(
                bp5.model(dx).unwrap(),
                bp5.fault_ode_options(1e-6).unwrap(),
                &bp5.half_space(1e-6).unwrap(),
                &SeasBp5::body_station_points(),
            )
            .unwrap();
        let mut output = SeasBp5Output::new(dir, &bp5, dx, columns, setup(dx))
            .unwrap()
            .with_resume_log(every);
        match resume {
            Some(c) => {
                output.resume(c.state.step).unwrap();
                ode.restore(c).unwrap();
            }
            None => output.write_initial_state(
                ode.model(),
                ode.state(),
                rsf::Stepping::fault_tractions(&ode),
            ),
        }
        let until = match stop {
            Some(step) => Until::TimeOrStepCap {
                time: 190.0 * SECONDS_PER_YEAR,
                step_cap: step,
            },
            None => end,
        };
        let observers: &mut [&mut dyn Observer<3, 3>] = &mut [&mut output];
        ode.run_until(until, observers).unwrap();
        ode.checkpoint()
    };
    let (whole, parts) = (base.join("whole"), base.join("parts"));
    run(&whole, None, None);
    // Stopped in the middle of the first interseismic period and after the files were
    // persisted at step 600 and 800, continued from step 600 (a checkpoint behind the files).
    let stopped = run(&parts, Some(600), None);
    assert_eq!(stopped.state.step, 600);
    run(&parts, Some(900), Some(&stopped));
    let again = run(&parts, None, Some(&stopped));
    assert!(again.state.step > 900);
    let mut compared = 0;
    for name in SeasBp5Output::file_names()
        .into_iter()
        .chain(["events.csv".into()])
    {
        let a = std::fs::read(whole.join(&name)).unwrap();
        let b = std::fs::read(parts.join(&name)).unwrap();
        assert!(a == b, "{name} differs after the resumes");
        compared += 1;
    }
    assert_eq!(compared, 21);
    let _ = std::fs::remove_dir_all(&base);
}

#[test]
fn uniform_slip_of_the_cells_displaces_the_stations_as_one_rectangle() {
    // Linearity and the frames: the cells' displacement columns summed for a uniform
    // strike slip are Okada's displacement of the whole rate-and-state rectangle.
    let bp5 = SeasBp5::default();
    let dx = 10_000.0;
    let model = bp5.model(dx).unwrap();
    let operator = rsf::halfspace_operator::HalfSpaceOperator::fault_alone(
        &model,
        &bp5.half_space(1e-6).unwrap(),
    )
    .unwrap();
    let points = SeasBp5::body_station_points();
    let columns = operator.displacement_columns(&points).unwrap();
    let m = 2 * model.vertices.len();
    // The rectangle in Okada's frame (its origin on the surface above the first cell):
    // along strike between the region's ends, vertical, from the surface to W_f.
    let frame = operator.frame();
    let (a, b) = (
        frame.to_okada([0.0, -50e3, 0.0])[0],
        frame.to_okada([0.0, 50e3, 0.0])[0],
    );
    let rect = Rectangle::new(0.0, 90.0, [a.min(b), a.max(b)], [-40e3, 0.0]).unwrap();
    let alpha = bp5.medium().unwrap().alpha();
    for (p, (x, col)) in points.iter().zip(&columns).enumerate() {
        let uniform: Vec<f64> = (0..3)
            .map(|c| (0..m).step_by(2).map(|j| col[c * m + j]).sum())
            .collect();
        // Okada's point: x along strike (model y); its y normal to the fault. Which side
        // of Okada's frame the model's +x is follows from the operator's frame.
        let okada = operator.frame().to_okada(*x);
        let d = dc3d(alpha, okada, rect, [1.0, 0.0, 0.0]).unwrap();
        let expected = operator.frame().to_model(d.u);
        let sign = operator.frame().plus_is_hanging_wall;
        for c in 0..3 {
            let e = sign * expected[c];
            assert!(
                (uniform[c] - e).abs() <= 1e-9 + 1e-9 * e.abs(),
                "station {:?} component {c}: {} against {e}",
                SEAS_BP5_BODY_STATIONS[p],
                uniform[c]
            );
        }
        // Strike slip on the + side (x > 0) moves it along +y, away from the fault less.
        assert!(
            uniform[1] > 0.0 && uniform[1] < 0.5,
            "station {p}: {uniform:?}"
        );
    }
}

#[test]
fn a_fault_alone_refuses_what_it_cannot_hold() {
    let bp5 = SeasBp5::default();
    assert!(bp5.model(3000.0).is_err(), "3 km does not divide 100 km");
    assert!(bp5.model(-1.0).is_err());
    assert!(bp5.model(f64::NAN).is_err());
    assert!(bp5.model(100.0).is_err(), "above the cell limit");
    assert!(rsf::Model::<3, 3>::fault_only(vec![], &[], 0).is_err());
    assert!(rsf::Model::<3, 3>::fault_only(vec![[0.0; 3]], &[0.0], 0).is_err());
    assert!(rsf::Model::<3, 3>::fault_only(vec![[0.0; 3]], &[1.0], 3).is_err());
    assert!(rsf::Model::<3, 3>::fault_only(vec![[f64::NAN; 3]], &[1.0], 0).is_err());
    // An operator of another size, a plate velocity of another length.
    let model = bp5.model(10_000.0).unwrap();
    let small = bp5.model(20_000.0).unwrap();
    let op = rsf::halfspace_operator::HalfSpaceOperator::fault_alone(
        &small,
        &bp5.half_space(1e-6).unwrap(),
    )
    .unwrap();
    let alone = rsf::fault_alone::FaultAlone {
        operator: Box::new(op),
        plate_velocity: vec![0.0; 2 * small.vertices.len()],
    };
    let err = rsf::SimulationBuilder::new(model)
        .friction_at(|x| rsf_friction::AsinhLaw::new(bp5.params(x[1], -x[2])))
        .state_law_at(|x| rsf_state::Aging::new(bp5.l_at(x[1], -x[2])))
        .initial_state_at(|x| bp5.alpha0(x[1], -x[2]))
        .integrator(rsf::Integrator::Quasistatic(rsf::time::Quasistatic::new()))
        .radiation_damping(bp5.radiation_damping())
        .time_step(1e-3)
        .build_fault_ode_alone(bp5.fault_ode_options(1e-6).unwrap(), alone)
        .unwrap_err();
    assert!(err.to_string().contains("fault_operator"), "{err}");
}
