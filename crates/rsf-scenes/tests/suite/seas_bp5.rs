//! SEAS BP5-QD as a fault alone (docs/seas-bp5.md): the description's check values at
//! t = 0, the off-fault displacement against one big Okada rectangle, the volume model.
//! (A coarse run's ruptures and files, and a stopped and continued run: the crate
//! rsf-seas's tests.)

use rsf::halfspace::okada::{dc3d, Rectangle};
use rsf::Until;
use rsf_scenes::{SeasBp5, SEAS_BP5_BODY_STATIONS};
use rsf_seas::{SeasLayout, SeasSampling, SeasSetup, SECONDS_PER_YEAR};

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
    let err = bp5.output(&dir, 10e3, columns, bad_date).err().unwrap();
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
    ode.run_until(
        Until::TimeWithin {
            time: 10.0 * SECONDS_PER_YEAR,
            max_steps: 500_000,
        },
        &mut [],
    )
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
