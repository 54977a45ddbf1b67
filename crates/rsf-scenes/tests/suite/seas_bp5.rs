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

/// The fault alone on cells of `dx` with the off-fault stations' columns.
fn with_stations(bp5: &SeasBp5, dx: f64) -> (rsf_scenes::SeasBp5FaultOde, Vec<Vec<f64>>) {
    bp5.fault_ode_with_stations(
        bp5.model(dx).unwrap(),
        bp5.fault_ode_options(1e-6).unwrap(),
        &bp5.half_space(1e-6).unwrap(),
        &SeasBp5::body_station_points(),
    )
    .unwrap()
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
    let (mut ode, columns) = with_stations(&bp5, dx);
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
    let stations = SeasBp5Output::file_names()
        .into_iter()
        .filter(|n| n.starts_with("fltst") || n.starts_with("blkst") || n == "global.dat");
    // The first rows are the description's check values (τ⁰ in MPa, log10 θ), computed
    // above from its formulas: the core, the patch, and a_max at the surface.
    for (name, tau0, log_theta) in [
        ("fltst_strk+00dp+10", published_tau0(0.004, 1e-9), 8.146),
        ("fltst_strk-24dp+10", published_tau0(0.004, 0.03), 8.114),
        ("fltst_strk+36dp+00", published_tau0(0.04, 1e-9), 8.146),
    ] {
        let rows = parse(&dir.join(name), 8);
        assert!(
            (rows[0][5] - tau0 / 1e6).abs() < 1e-5,
            "{name}: {}",
            rows[0][5]
        );
        assert!(
            (rows[0][7] - log_theta).abs() < 5e-4,
            "{name}: {}",
            rows[0][7]
        );
    }
    for name in stations {
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
    // The profiles: the positions row (0 0 and the grid's rows or columns), then time rows
    // of t, log10 max slip rate and one value per position.
    for (name, points) in [
        ("slip_2_depth.dat", 10),
        ("slip_2_strike.dat", 25),
        ("stress_2_depth.dat", 10),
        ("stress_2_strike.dat", 25),
    ] {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        let rows: Vec<Vec<f64>> = text
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with('x') && !l.starts_with('t'))
            .map(|l| l.split_whitespace().map(|t| t.parse().unwrap()).collect())
            .collect();
        assert!(rows.iter().all(|r| r.len() == 2 + points), "{name}");
        assert_eq!(&rows[0][..2], &[0.0, 0.0], "{name}: the positions row");
        let count: usize = text
            .lines()
            .find_map(|l| l.strip_prefix("# num_time_steps="))
            .unwrap()
            .parse()
            .unwrap();
        assert_eq!(count, rows.len() - 1, "{name}");
        // Profiles every 5 years between events: about 50 in 250 years, more in events.
        assert!(rows.len() > 50, "{name}: {} rows", rows.len());
    }
    // rupture.dat: every cell once; the ruptured ones after the first event, in the
    // second rupture (its start at ~180 years) or the afterslip that follows.
    let text = std::fs::read_to_string(dir.join("rupture.dat")).unwrap();
    let times: Vec<f64> = text
        .lines()
        .filter(|l| l.starts_with(' '))
        .map(|l| l.split_whitespace().nth(2).unwrap().parse().unwrap())
        .collect();
    assert_eq!(times.len(), 250);
    let ruptured: Vec<f64> = times
        .iter()
        .copied()
        .filter(|&t| t < rsf_scenes::NEVER_RUPTURED)
        .collect();
    // The weakening core (60 km × 12 km: 45 cells of 4 km) and some of its rim.
    assert!(
        (45..=250).contains(&ruptured.len()),
        "{} of 250 cells ruptured",
        ruptured.len()
    );
    assert!(ruptured.iter().all(|&t| t >= ruptures[0].t_end.unwrap()));
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
        let (mut ode, columns) = with_stations(&bp5, dx);
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
    assert_eq!(compared, 26);
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
    let dir = std::env::temp_dir().join(format!("rsf_bp5_date_{}", std::process::id()));
    let bad_date = SeasSetup {
        date: "2023-02-31".into(),
        ..setup(10e3)
    };
    let columns = vec![vec![0.0; 3 * 2 * 40]; SEAS_BP5_BODY_STATIONS.len()];
    let err = SeasBp5Output::new(&dir, &bp5, 10e3, columns, bad_date)
        .err()
        .unwrap();
    assert!(err.to_string().contains("date"), "{err}");
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

#[test]
fn the_volume_model_starts_at_the_descriptions_rates_and_creeps_at_the_plate_rate() {
    let bp5 = SeasBp5::default();
    let grid = rsf_scenes::SeasBp5Grid {
        dx: 5e3,
        ..rsf_scenes::SeasBp5Grid::default()
    };
    let model = bp5.fe_model(&grid).unwrap();
    let fault = model.internal_fault.as_ref().unwrap();
    // 21 × 9 frictional nodes on the rate-and-state region; every other pair creeps.
    assert_eq!(model.frictional_boundary.len(), 21 * 9);
    let creeping: Vec<usize> = fault
        .pairs()
        .iter()
        .map(|&(minus, _)| minus)
        .filter(|p| model.frictional_boundary.fault_index(*p).is_none())
        .collect();
    assert!(creeping.len() > 100, "{} creeping pairs", creeping.len());
    let mut ode = bp5
        .fe_fault_ode(model, bp5.fault_ode_options(1e-6).unwrap())
        .unwrap();
    // At t = 0 the slip rate is V_init where the prestress is uniform around the node
    // (the core's interior: a = a0 on every adjacent face — x₃ in [5, 15] km around
    // x₃ = 10 km — outside the patch), along +x₂.
    let check = |ode: &rsf_scenes::SeasBp5FaultOde| {
        let m = ode.model();
        let fb = &m.frictional_boundary;
        let mut checked = 0;
        for &p in &fb.nodes {
            let x = m.vertices[p];
            let (x2, x3) = (x[1], -x[2]);
            if x2.abs() <= 10e3 + 1.0 && (x3 - 10e3).abs() < 1.0 {
                let v = &ode.state().kinematics.v[3 * p..3 * p + 3];
                assert!((v[0] / 1e-9 - 1.0).abs() < 1e-6, "node at {x:?}: V = {v:?}");
                assert!(v[1].abs() < 1e-15, "node at {x:?}: V = {v:?}");
                checked += 1;
            }
        }
        assert_eq!(checked, 5);
    };
    check(&ode);
    // The creeping pairs slip at (V_p, 0) in their frame (t₁ along +y): u⁺ − u⁻ = V_p t e_y.
    ode.run_until(Until::Time(10.0 * SECONDS_PER_YEAR), &mut [])
        .unwrap();
    let t = ode.state().time;
    let m = ode.model();
    let frames = &m.internal_fault.as_ref().unwrap().transform.frames;
    for (i, &(minus, _)) in m
        .internal_fault
        .as_ref()
        .unwrap()
        .pairs()
        .iter()
        .enumerate()
    {
        if creeping.contains(&minus) {
            let j = &ode.state().kinematics.u[3 * minus..3 * minus + 2];
            assert!((j[0] - 1e-9 * t).abs() < 1e-12 * t, "pair {i}: jump {j:?}");
            assert!(j[1].abs() < 1e-15, "pair {i}: jump {j:?}");
            assert!((frames[i][1][0] - 1.0).abs() < 1e-12, "t₁ along +y");
        }
    }
}

#[test]
fn the_fault_alone_operator_refuses_a_body() {
    let bp5 = SeasBp5::default();
    let grid = rsf_scenes::SeasBp5Grid {
        dx: 10e3,
        ..rsf_scenes::SeasBp5Grid::default()
    };
    let body = bp5.fe_model(&grid).unwrap();
    let err = rsf::halfspace_operator::HalfSpaceOperator::fault_alone(
        &body,
        &bp5.half_space(1e-6).unwrap(),
    )
    .unwrap_err();
    assert_eq!(
        err,
        rsf::halfspace_operator::HalfSpaceOperatorError::NotAlone
    );
}
