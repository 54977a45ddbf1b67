//! SEAS BP5-QD as a fault alone (docs/seas-bp5.md): the description's check values at
//! t = 0, the off-fault displacement against one big Okada rectangle, the volume model.
//! (A coarse run's ruptures and files, and a stopped and continued run: the crate
//! rsf-seas's tests.)

use crate::{bp5_grid, bp5_zone_grid, within};
use rsf::halfspace::okada::{dc3d, Rectangle};
use rsf::Until;
use rsf_scenes::{SeasBp5, SeasBp5Run, SEAS_BP5_BODY_STATIONS};
use rsf_seas::{SeasSetup, SECONDS_PER_YEAR};

/// The prestress of the description, written out here from its formula (not the scene's
/// code): τ⁰ = σ̄_n a asinh(V/(2V₀) exp((f₀ + b ln(V₀/V_p))/a)) + η V (Pa).
fn published_tau0(a: f64, v: f64) -> f64 {
    let (sigma, f0, b, v0, v_p) = (25e6, 0.6, 0.03, 1e-6, 1e-9);
    let eta = 2670.0 * 3464.0 * 3464.0 / (2.0 * 3464.0);
    sigma * a * (v / (2.0 * v0) * ((f0 + b * (v0 / v_p).ln()) / a).exp()).asinh() + eta * v
}

/// The files' headers of a BP5 run at Δx = `dx` (m), the run's own (modeler `test`, date
/// 2026-11-26).
fn setup(dx: f64) -> SeasSetup {
    let run = SeasBp5Run {
        dx,
        ..SeasBp5Run::default()
    };
    run.seas_setup(&SeasBp5::default(), "test".into(), "2026-11-26".into())
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
    let grid = bp5_grid(5e3);
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
        // The region's rim (|x₂| = l_f/2 or x₃ = W_f; a = a_max around it) too: half of
        // a rim node's faces lie outside the region, and its prestress must be whole
        // there as well (with τ⁰ on the region's faces only, the corner node at
        // x₂ = −50 km, x₃ = 40 km started at V = 1.4e-13 m/s, locked).
        let mut rim = 0;
        for &p in &fb.nodes {
            let x = m.vertices[p];
            let (x2, x3) = (x[1], -x[2]);
            if (x2.abs() - 50e3).abs() < 1.0 || (x3 - 40e3).abs() < 1.0 {
                let v = &ode.state().kinematics.v[3 * p..3 * p + 3];
                assert!(
                    (v[0] / 1e-9 - 1.0).abs() < 1e-6,
                    "rim node at {x:?}: V = {v:?}"
                );
                rim += 1;
            }
        }
        assert_eq!(rim, 21 + 2 * 8);
    };
    check(&ode);
    // The creeping pairs slip at (V_p, 0) in their frame (t₁ along +y): u⁺ − u⁻ = V_p t e_y.
    ode.run_until(within(10.0 * SECONDS_PER_YEAR), &mut [])
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
    let grid = bp5_grid(10e3);
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

/// A fault zone without contrast (rigidity ratio 1) is the homogeneous scene on the same
/// mesh, bit for bit: its matrices, its damping and a run of 60 steps through the
/// nucleation patch's first event.
#[test]
fn a_fault_zone_without_contrast_gives_the_homogeneous_scenes_bits() {
    let homogeneous = SeasBp5::default();
    let zone = SeasBp5 {
        fault_zone: Some(rsf_scenes::FaultZone {
            half_width: 10e3,
            rigidity_ratio: 1.0,
        }),
        ..SeasBp5::default()
    };
    assert_eq!(
        zone.radiation_damping().to_bits(),
        homogeneous.radiation_damping().to_bits()
    );
    let run = |bp5: &SeasBp5| {
        let model = bp5.fe_model(&bp5_zone_grid()).unwrap();
        let k = model.stiffness.val().to_vec();
        let mut ode = bp5
            .fe_fault_ode(model, bp5.fault_ode_options(1e-6).unwrap())
            .unwrap();
        ode.run_until(Until::Steps(60), &mut []).unwrap();
        (
            k,
            ode.state().kinematics.u.clone(),
            ode.state().alpha.clone(),
        )
    };
    let (a, b) = (run(&homogeneous), run(&zone));
    assert!(a
        .0
        .iter()
        .zip(&b.0)
        .all(|(x, y)| x.to_bits() == y.to_bits()));
    let same = |x: &[f64], y: &[f64]| {
        x.len() == y.len()
            && x.iter()
                .zip(y)
                .all(|(p, q)| p.to_bits() == q.to_bits() || (p.is_nan() && q.is_nan()))
    };
    assert!(same(&a.1, &b.1) && same(&a.2, &b.2));
}

/// A compliant zone softens the fault: reducing the shear modulus in a region lowers the
/// elastic energy of every displacement, and a Schur complement keeps that order, so
/// `sᵀ S_zone s < sᵀ S s` for every slip `s` (tried on uniform, sheared and alternating
/// slip); the damping is the zone's, `√ratio` times the host's.
#[test]
fn a_compliant_fault_zone_softens_the_condensed_operator() {
    let ratio = 0.5;
    let homogeneous = SeasBp5::default();
    let zone = SeasBp5 {
        fault_zone: Some(rsf_scenes::FaultZone {
            half_width: 10e3,
            rigidity_ratio: ratio,
        }),
        ..SeasBp5::default()
    };
    assert!(
        (zone.radiation_damping() / homogeneous.radiation_damping() - ratio.sqrt()).abs() < 1e-15
    );
    let schur = |bp5: &SeasBp5| {
        let model = bp5.fe_model(&bp5_zone_grid()).unwrap();
        let nodes = model.frictional_boundary.nodes.clone();
        let cond =
            rsf::direct::Condensation::<3>::new(model.stiffness.as_ref(), &model.fixed, &nodes)
                .unwrap();
        (cond.dim(), cond.schur_complement())
    };
    let ((m, s_h), (m_z, s_z)) = (schur(&homogeneous), schur(&zone));
    assert_eq!(m, m_z);
    let energy = |s: &[f64], x: &[f64]| -> f64 {
        (0..m)
            .map(|j| x[j] * (0..m).map(|i| s[j * m + i] * x[i]).sum::<f64>())
            .sum()
    };
    let slips: [Box<dyn Fn(usize) -> f64>; 3] = [
        Box::new(|i| if i % 2 == 0 { 1.0 } else { 0.0 }),
        Box::new(|i| (i as f64 * 0.37).sin()),
        Box::new(|i| if i % 4 < 2 { 1.0 } else { -1.0 }),
    ];
    for slip in &slips {
        let x: Vec<f64> = (0..m).map(slip).collect();
        let (e_h, e_z) = (energy(&s_h, &x), energy(&s_z, &x));
        assert!(e_h > 0.0 && e_z > 0.0 && e_z < e_h, "{e_z} against {e_h}");
    }
}

/// The compliant zone is exactly what its documentation states: the slab `|x₁| ≤
/// half_width` over the rate-and-state region (`|x₂| ≤ l_f/2`, depth `−x₃ ≤ W_f`) of shear
/// modulus `rigidity_ratio · μ`, the host elsewhere. The slab is written here from that
/// statement, given to the homogeneous scene's builder as its material, and the scene's
/// stiffness must be that model's, bit for bit; a slab of half the width gives another
/// stiffness (cells of 10 km, so the half-width's plane cuts between centroids at 2.5 and
/// 7.5 km), so the comparison can tell.
#[test]
fn the_compliant_zone_is_the_slab_of_its_width_over_the_rate_state_region() {
    use rsf::model::MaterialRegions;
    let (half_width, ratio) = (10e3, 0.5);
    let host = SeasBp5::default();
    let zone = SeasBp5 {
        fault_zone: Some(rsf_scenes::FaultZone {
            half_width,
            rigidity_ratio: ratio,
        }),
        ..host
    };
    let scene = zone.fe_model(&bp5_zone_grid()).unwrap();
    let (l_f, w_f, nu, rho) = (host.l_f, host.w_f, host.nu, host.rho);
    let material = |mu: f64| rsf::Material::from_shear_modulus(mu, nu, rho);
    let mu = host.shear_modulus();
    let with_slab = |width: f64| {
        let slab =
            move |x: &[f64; 3]| x[0].abs() <= width && x[1].abs() <= 0.5 * l_f && -x[2] <= w_f;
        host.fe_model_builder(&bp5_zone_grid())
            .unwrap()
            .material(MaterialRegions::new(material(mu)).region("slab", slab, material(ratio * mu)))
            .build()
            .unwrap()
    };
    let bits =
        |m: &rsf::Model<3>| -> Vec<u64> { m.stiffness.val().iter().map(|x| x.to_bits()).collect() };
    assert_eq!(bits(&scene), bits(&with_slab(half_width)));
    assert_ne!(bits(&scene), bits(&with_slab(0.5 * half_width)));
}

/// The graded mesh (an octree of Kuhn cubes) against the tensor grid at the same fault
/// spacing: at Δx = 2 km its smallest dihedral angle is the octree's bound,
/// arctan(1/(2√2)) = 19.47°, and it has less than half the tensor grid's vertices; its
/// condensed operator `S` on the fault's frictional nodes (matched by position and
/// component) is the tensor grid's within 6 % in the Frobenius norm at Δx = 10 km, and
/// closer at 5 km. The two meshes share the fault's cells and cut the volume around them
/// differently, so they agree as two discretisations of one operator, not to round-off:
/// measured 4.6e-2 at 10 km and 3.4e-2 at 5 km. The 6 % is the stated tolerance (a graded
/// mesh whose far field were cut wrongly, e.g. a missing or doubled cell, moves `S` by far
/// more); the second assertion asks that the difference shrink with the mesh.
#[test]
fn the_graded_mesh_is_sound_small_and_condenses_as_the_tensor_grid() {
    use rsf_scenes::{SeasBp5Grid, SeasBp5Mesh};
    let bp5 = SeasBp5::default();
    let grid = |dx, mesh| SeasBp5Grid {
        dx,
        mesh,
        ..SeasBp5Grid::default()
    };
    let mesh = |dx, kind| {
        bp5.fe_model_builder(&grid(dx, kind))
            .unwrap()
            .mesh()
            .clone()
    };
    let (graded, tensor) = (
        mesh(2e3, SeasBp5Mesh::Graded),
        mesh(2e3, SeasBp5Mesh::Tensor),
    );
    let bound = (1.0 / (2.0 * 2f64.sqrt())).atan();
    let angle = graded.min_dihedral_angle();
    assert!(
        angle >= bound - 1e-12,
        "smallest dihedral angle {}° below the octree's bound {}°",
        angle.to_degrees(),
        bound.to_degrees()
    );
    let (n_g, n_t) = (graded.num_vertices(), tensor.num_vertices());
    // The plans' count, from the octree without the mesh, is the mesh's.
    assert_eq!(
        bp5.fe_mesh_vertices(&grid(2e3, SeasBp5Mesh::Graded))
            .unwrap(),
        n_g
    );
    assert_eq!(
        bp5.fe_mesh_vertices(&grid(2e3, SeasBp5Mesh::Tensor))
            .unwrap(),
        n_t
    );
    assert!(
        (n_g as f64) < 0.5 * n_t as f64,
        "graded {n_g} vertices against the tensor grid's {n_t}"
    );
    let condensed = |dx, kind| {
        let model = bp5.fe_model(&grid(dx, kind)).unwrap();
        let nodes = model.frictional_boundary.nodes.clone();
        let at: Vec<[f64; 3]> = nodes.iter().map(|&n| model.vertices[n]).collect();
        let cond =
            rsf::direct::Condensation::<3>::new(model.stiffness.as_ref(), &model.fixed, &nodes)
                .unwrap();
        // The slip unknowns: the nodes' free components, in order.
        let free: Vec<(usize, usize)> = nodes
            .iter()
            .enumerate()
            .flat_map(|(k, &n)| (0..3).map(move |c| (k, 3 * n + c)))
            .filter(|&(_, dof)| !model.fixed[dof])
            .map(|(k, dof)| (k, dof % 3))
            .collect();
        assert_eq!(free.len(), cond.dim());
        (at, free, cond.schur_complement())
    };
    let relative_difference = |dx: f64| {
        let (at_t, free_t, s_t) = condensed(dx, SeasBp5Mesh::Tensor);
        let (at_g, free_g, s_g) = condensed(dx, SeasBp5Mesh::Graded);
        // The graded operator's unknown of each of the tensor grid's, by position and component.
        assert_eq!(free_t.len(), free_g.len());
        let close = |p: &[f64; 3], q: &[f64; 3]| (0..3).all(|k| (p[k] - q[k]).abs() < 1e-6);
        let perm: Vec<usize> = free_t
            .iter()
            .map(|&(k, c)| {
                free_g
                    .iter()
                    .position(|&(l, d)| d == c && close(&at_t[k], &at_g[l]))
                    .expect("the same fault unknowns")
            })
            .collect();
        let m = free_t.len();
        let (mut diff, mut norm) = (0.0, 0.0);
        for j in 0..m {
            for i in 0..m {
                let (t, g) = (s_t[j * m + i], s_g[perm[j] * m + perm[i]]);
                diff += (t - g) * (t - g);
                norm += t * t;
            }
        }
        (diff / norm).sqrt()
    };
    let (coarse, fine) = (relative_difference(10e3), relative_difference(5e3));
    eprintln!(
        "Δx = 2 km: graded {n_g} / tensor {n_t} vertices; ‖S_g − S_t‖/‖S_t‖ = {coarse:.3e} at \
         Δx = 10 km, {fine:.3e} at 5 km"
    );
    assert!(coarse < 0.06, "‖S_g − S_t‖/‖S_t‖ = {coarse:.3e} at 10 km");
    assert!(
        fine < coarse,
        "{fine:.3e} at 5 km against {coarse:.3e} at 10 km"
    );
}

#[test]
fn a_fault_zone_the_mesh_does_not_resolve_or_the_half_space_cannot_hold_is_refused() {
    let zone = |half_width: f64| SeasBp5 {
        fault_zone: Some(rsf_scenes::FaultZone {
            half_width,
            rigidity_ratio: 0.5,
        }),
        ..SeasBp5::default()
    };
    // Not a whole number of cells; wider than the slab of cells dx.
    for (bp5, near) in [(zone(5e3), 10e3), (zone(20e3), 10e3)] {
        let grid = rsf_scenes::SeasBp5Grid {
            near_fault: near,
            ..bp5_zone_grid()
        };
        let e = bp5.fe_model(&grid).unwrap_err();
        assert!(e.to_string().contains("fault_zone.half_width"), "{e}");
    }
    let bad_ratio = SeasBp5 {
        fault_zone: Some(rsf_scenes::FaultZone {
            half_width: 10e3,
            rigidity_ratio: 1.5,
        }),
        ..SeasBp5::default()
    };
    assert!(bad_ratio
        .validate()
        .unwrap_err()
        .to_string()
        .contains("rigidity_ratio"));
    let okada = zone(10e3)
        .fault_ode(
            zone(10e3).model(10e3).unwrap(),
            zone(10e3).fault_ode_options(1e-6).unwrap(),
            &zone(10e3).half_space(1e-6).unwrap(),
        )
        .unwrap_err();
    assert!(okada.to_string().contains("fault_zone"), "{okada}");
}

/// BP5's volume at 10 km, the off-fault stations' nearest vertices, and the options.
fn schur_case() -> (
    SeasBp5,
    rsf::Model<3, 3>,
    Vec<usize>,
    rsf::fault_ode::FaultOdeOptions,
) {
    let bp5 = SeasBp5::default();
    let grid = bp5_grid(10e3);
    let model = bp5.fe_model(&grid).unwrap();
    let mut vertices: Vec<usize> = SeasBp5::body_station_points()
        .iter()
        .map(|x| model.nearest_node(x).unwrap())
        .collect();
    vertices.sort_unstable();
    vertices.dedup();
    let options = bp5.fault_ode_options(1e-6).unwrap();
    (bp5, model, vertices, options)
}

/// The displacement of the fault's slip unknowns and of the watched vertices after a run.
fn slip_and_stations(ode: &rsf_scenes::SeasBp5FaultOde, vertices: &[usize]) -> Vec<f64> {
    let u = &ode.state().kinematics.u;
    let mut out: Vec<f64> = ode
        .model()
        .frictional_boundary
        .nodes
        .iter()
        .flat_map(|&p| u[3 * p..3 * p + 2].to_vec())
        .collect();
    out.extend(vertices.iter().flat_map(|&v| u[3 * v..3 * v + 3].to_vec()));
    out
}

/// The set-up without the factor gives the factor's trajectory to round-off (another
/// summation order of the same `S`, loads and station rows): slip and the stations'
/// displacements 100 s into the nucleation patch's rupture (slip rates ~1 m/s) agree to
/// 1e-12 of their largest magnitude (measured: 4e-17; `S` differs by 6e-16 of its largest
/// entry).
#[test]
fn the_schur_only_set_up_follows_the_factors_trajectory() {
    let (bp5, model, vertices, options) = schur_case();
    let mut with_factor = bp5.fe_fault_ode(model.clone(), options).unwrap();
    rsf::Stepping::watch_vertices(&mut with_factor, &vertices).unwrap();
    let setup = rsf::fault_ode::SchurOnlySetup {
        watch_vertices: vertices.clone(),
        ..Default::default()
    };
    let mut schur = bp5.fe_fault_ode_schur_only(model, options, setup).unwrap();
    assert_eq!(schur.factor_nnz(), 0);
    let (a, b) = (&mut with_factor, &mut schur);
    a.run_until(
        Until::TimeWithin {
            time: 100.0,
            max_steps: 100_000,
        },
        &mut [&mut Stations(vertices.clone())],
    )
    .unwrap();
    b.run_until(
        Until::TimeWithin {
            time: 100.0,
            max_steps: 100_000,
        },
        &mut [&mut Stations(vertices.clone())],
    )
    .unwrap();
    let (x, y) = (
        slip_and_stations(&with_factor, &vertices),
        slip_and_stations(&schur, &vertices),
    );
    let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = x
        .iter()
        .zip(&y)
        .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
    println!("slip and stations at 100 s: largest difference {worst:e} m of {scale:e} m");
    assert!(scale > 0.0 && worst <= 1e-12 * scale, "{worst} of {scale}");
    assert_eq!(with_factor.state().time, 100.0);
    assert_eq!(schur.state().time, 100.0);
}

/// An observer that reads the given vertices off the fault (so that a run fills them).
struct Stations(Vec<usize>);

impl rsf::Observer<3, 3> for Stations {
    fn observe(&mut self, _: &rsf::StepView<'_, 3, 3>) -> rsf::Result<rsf::Flow> {
        Ok(rsf::Flow::Continue(()))
    }
    fn reads_volume(&self) -> bool {
        false
    }
    fn volume_vertices(&self) -> Vec<usize> {
        self.0.clone()
    }
}

/// A set-up stopped part way (its last checkpoint kept) and started again resumes from the
/// checkpoint and gives the uninterrupted set-up's bits; without the factor the volume
/// cannot be read, nor vertices other than the set-up's.
#[test]
fn a_stopped_schur_only_set_up_resumes_with_the_same_bits() {
    let (bp5, model, vertices, options) = schur_case();
    let dir = std::env::temp_dir().join(format!("rsf-bp5-schur-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("setup.bin");
    let _ = std::fs::remove_file(&path);
    let policy = rsf::direct::CheckpointPolicy {
        every_fronts: Some(20),
        every_seconds: None,
        keep_result: false,
        ..rsf::direct::CheckpointPolicy::new(&path)
    };
    let run = |setup: rsf::fault_ode::SchurOnlySetup| {
        bp5.fe_fault_ode_schur_only(model.clone(), options, setup)
            .map(|mut ode| {
                ode.run_until(Until::Steps(40), &mut []).unwrap();
                slip_and_stations(&ode, &vertices)
            })
    };
    let whole = run(rsf::fault_ode::SchurOnlySetup {
        watch_vertices: vertices.clone(),
        ..Default::default()
    })
    .unwrap();
    let stopped = run(rsf::fault_ode::SchurOnlySetup {
        watch_vertices: vertices.clone(),
        checkpoint: Some(policy.clone()),
        progress: Some(Box::new(|p: &rsf::direct::Progress| {
            if p.fronts_done >= 50 {
                std::ops::ControlFlow::Break(())
            } else {
                std::ops::ControlFlow::Continue(())
            }
        })),
        ..Default::default()
    });
    assert!(stopped.is_err() && path.exists(), "{:?}", stopped.err());
    let resumed = run(rsf::fault_ode::SchurOnlySetup {
        watch_vertices: vertices.clone(),
        checkpoint: Some(policy),
        ..Default::default()
    })
    .unwrap();
    assert!(whole
        .iter()
        .zip(&resumed)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
    assert!(
        !path.exists(),
        "keep_result = false removes the finished checkpoint"
    );
    // What the set-up did not keep.
    let mut ode = bp5
        .fe_fault_ode_schur_only(
            model.clone(),
            options,
            rsf::fault_ode::SchurOnlySetup {
                watch_vertices: vertices.clone(),
                ..Default::default()
            },
        )
        .unwrap();
    let other = (0..model.vertices.len())
        .find(|v| {
            vertices.binary_search(v).is_err()
                && model.frictional_boundary.fault_index(*v).is_none()
        })
        .unwrap();
    let e = rsf::Stepping::watch_vertices(&mut ode, &[other]).unwrap_err();
    assert!(e.to_string().contains("volume_vertices"), "{e}");
    let e = rsf::Stepping::advance(&mut ode, None, true).unwrap_err();
    assert!(e.to_string().contains("reads_volume"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Measurement, not a check (ignored; docs/seas-bp5.md, "The volume at 500 m"): the
/// Schur-only elimination's plan for BP5's graded volume — its fronts, the bytes it will
/// hold with the two right-hand sides of a run, its floating-point operations — from the
/// symbolic analysis alone, nothing eliminated. `RSF_BP5_PLAN_DX` lists the spacings (m,
/// default `2000,1000,500`), `RSF_BP5_PLAN_ORDERING=nested-dissection` orders the interior
/// by METIS (feature `metis`) instead of AMD:
/// `RSF_BP5_PLAN_DX=1000,500 cargo test -p rsf-scenes --test suite
/// bp5_elimination_plan -- --ignored --nocapture`.
#[test]
#[ignore = "a measurement: minutes and GBs at 500 m"]
fn bp5_elimination_plan() {
    let list = std::env::var("RSF_BP5_PLAN_DX").unwrap_or_else(|_| "2000,1000,500".into());
    let bp5 = SeasBp5::default();
    for dx in list.split(',').map(|d| d.trim().parse::<f64>().unwrap()) {
        let clock = std::time::Instant::now();
        let grid = bp5_grid(dx);
        let model = bp5.fe_model(&grid).unwrap();
        let built = clock.elapsed().as_secs_f64();
        let ordering = match std::env::var("RSF_BP5_PLAN_ORDERING").as_deref() {
            Ok("nested-dissection") => rsf::direct::InteriorOrdering::NestedDissection,
            _ => bp5.fault_ode_options(1e-6).unwrap().ordering,
        };
        let elimination = rsf::direct::SchurOnly::<3>::new(
            model.stiffness.as_ref(),
            &model.fixed,
            &model.frictional_boundary.nodes,
            &[],
            ordering,
        )
        .unwrap();
        let plan = elimination.plan();
        println!(
            "dx {dx} m, {ordering:?}: {} vertices, {} dofs, K {:.0} MB (model built in {built:.1} s, \
             analysed in {:.1} s): {} fronts, largest order {}, kept {}, holds {:.2} GB \
             (pending {:.2} GB, largest front {:.2} GB, S {:.2} GB), {:.3e} flops",
            model.vertices.len(),
            model.num_dofs(),
            model.stiffness.val().len() as f64 * 16e-6,
            clock.elapsed().as_secs_f64() - built,
            plan.fronts,
            plan.largest_order,
            plan.kept,
            plan.total_bytes(2) as f64 * 1e-9,
            plan.peak_pending_bytes as f64 * 1e-9,
            plan.largest_front_bytes as f64 * 1e-9,
            plan.result_bytes as f64 * 1e-9,
            plan.flops,
        );
    }
}

/// The nucleation patch's weights are exact (issue 84): the sum over the fault's nodes
/// (or cells) of weight × share of the patch equals the patch's area `w × H` = 144 km² to
/// round-off, for the boundary-element cells at 2.5, 2 and 1 km and the finite-element
/// nodes at 10 and 5 km (where the patch's edges at x₂ = −18 km and x₃ = 4, 16 km cut
/// the dual cells), whatever the grid; and each node's L is the share-weighted mean. With
/// closed intervals (a node on the edge taking the patch's L with its whole dual cell),
/// the same sums give the larger areas the issue counted (36 % at 2 km).
#[test]
fn the_nucleation_patchs_weights_sum_to_its_area() {
    let bp5 = SeasBp5::default();
    let area = bp5.w * bp5.h;
    let sums = |model: &rsf::Model<3, 3>| {
        let dx = SeasBp5::grid_spacing(model);
        let fb = &model.frictional_boundary;
        let (mut exact, mut closed) = (0.0, 0.0);
        for (k, &p) in fb.nodes.iter().enumerate() {
            let x = model.vertices[p];
            let (x2, x3) = (x[1], -x[2]);
            exact += fb.weights[k] * bp5.patch_share(x2, x3, dx);
            if bp5.in_nucleation_patch(x2, x3) {
                closed += fb.weights[k];
            }
            let s = bp5.patch_share(x2, x3, dx);
            let l = bp5.l_in_cell(x2, x3, dx);
            assert!((l - (s * bp5.l_nucleation + (1.0 - s) * bp5.l)).abs() <= 1e-15);
        }
        (dx, exact, closed)
    };
    for dx in [2500.0, 2000.0, 1000.0] {
        let (spacing, exact, closed) = sums(&bp5.model(dx).unwrap());
        println!("cells, Δx = {dx}: {exact:e} m² (closed intervals {closed:e})");
        assert_eq!(spacing, dx);
        assert!(
            (exact - area).abs() <= 1e-12 * area,
            "{exact} against {area}"
        );
    }
    for dx in [10e3, 5e3] {
        let grid = bp5_grid(dx);
        let (spacing, exact, closed) = sums(&bp5.fe_model(&grid).unwrap());
        println!("nodes, Δx = {dx}: {exact:e} m² (closed intervals {closed:e})");
        assert_eq!(spacing, dx);
        assert!(
            (exact - area).abs() <= 1e-12 * area,
            "{exact} against {area}"
        );
        assert!(closed > area, "{closed}");
    }
}
