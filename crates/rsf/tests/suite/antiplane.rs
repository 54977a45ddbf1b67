//! Scalar (antiplane) models through the whole library: the builder's antisymmetric fault,
//! steady creep at the plate rate (issue 23, docs/seas-bp1.md). A coarse SEAS BP1 run to
//! its first event with the benchmark's files is a test of the crate rsf-seas.

use rsf::fem::{rectangle, Diagonal};
use rsf::model::AntiplaneMaterial;
use rsf::{ModelBuilder, Part};

use rsf::observe::SECONDS_PER_YEAR;

use crate::common::{creeping_bp1, steady_creep_errors, within};

/// The antisymmetric fault scales the model's unknown to s·u: K/s², F/s, w/s, velocities
/// s·v — checked against the same model without it, entry by entry.
#[test]
fn antisymmetric_fault_scales_the_model_to_slip() {
    let build = |s: f64| {
        let mesh = rectangle([0.0, 0.0], [4.0, 2.0], 4, 2, Diagonal::Forward).unwrap();
        ModelBuilder::scalar(mesh)
            .material(AntiplaneMaterial::new(3e9, 2500.0))
            .frictional_boundary(Part::predicate("fault", |x| x[0] < 1e-9))
            .neumann(Part::predicate("fault", |x| x[0] < 1e-9), |_| [2e6])
            .dirichlet(Part::predicate("far", |x| x[0] > 4.0 - 1e-9), [1e-3])
            .antisymmetric_fault(s)
            .build()
            .unwrap()
    };
    let (m1, m2) = (build(1.0), build(2.0));
    assert_eq!(m1.num_dofs(), m1.num_nodes(), "one component per node");
    assert_eq!(m2.frictional_boundary.slip_factor, 2.0);
    for (a, b) in m1.stiffness.val().iter().zip(m2.stiffness.val()) {
        assert!((a / 4.0 - b).abs() <= 1e-15 * a.abs(), "{a} {b}");
    }
    for (a, b) in m1.load.iter().zip(&m2.load) {
        assert!((a / 2.0 - b).abs() <= 1e-15 * a.abs());
    }
    for (a, b) in m1
        .frictional_boundary
        .weights
        .iter()
        .zip(&m2.frictional_boundary.weights)
    {
        assert_eq!(a / 2.0, *b);
    }
    for (a, b) in m1.dirichlet.factors.iter().zip(&m2.dirichlet.factors) {
        assert_eq!(a * 2.0, *b);
    }
    // The field's kernel is the constants (antiplane stiffness, no rigid rotation).
    let ones = vec![1.0; m1.num_dofs()];
    let mut k1 = vec![0.0; m1.num_dofs()];
    rsf::fem::spmv_add(m1.stiffness.as_ref(), 1.0, &ones, &mut k1);
    assert!(k1.iter().all(|x| x.abs() < 1e-6 * 3e9));
    let bad = ModelBuilder::scalar(rectangle([0.0; 2], [1.0; 2], 2, 2, Diagonal::Forward).unwrap())
        .material(AntiplaneMaterial::new(1e9, 1e3))
        .frictional_boundary(Part::predicate("f", |x| x[0] < 1e-9))
        .antisymmetric_fault(0.0)
        .build();
    assert!(bad.unwrap_err().to_string().contains("slip_factor"));
}

/// Velocity strengthening everywhere (a = 0.025 > b = 0.015) and started off steady state
/// (V_init = V_p/10): after the transient the fault creeps at V_p at every node and its
/// shear stress is the steady-state friction at V_p, σ_n F(V_p, D_c/V_p) — both from the
/// law, independent of the model and the solver.
#[test]
fn velocity_strengthening_fault_settles_to_steady_creep_at_the_plate_rate() {
    let (bp1, grid) = creeping_bp1();
    let model = bp1.model(&grid, false).unwrap();
    let mut sim = bp1
        .simulation_builder(model, false, 1e-2, bp1.step_control(1e-4).unwrap())
        .unwrap()
        .build()
        .unwrap();
    sim.run_until(within(3000.0 * SECONDS_PER_YEAR), &mut [])
        .unwrap();
    let mut v = vec![0.0; sim.model().frictional_boundary.len()];
    sim.slip_rates(&mut v);
    let (worst_v, worst_tau) = steady_creep_errors(
        &bp1,
        sim.model(),
        &v,
        sim.alpha(),
        sim.problem().friction_laws(),
    );
    eprintln!("steady creep: max |V/V_p − 1| = {worst_v:e}, max stress error {worst_tau:e}");
    assert!(worst_v < 1e-3, "slip rate {worst_v}");
    assert!(worst_tau < 1e-4, "stress {worst_tau}");
}
