//! Scalar (antiplane) models through the whole library: the builder's antisymmetric fault,
//! steady creep at the plate rate, and a coarse SEAS BP1 run to its first event with the
//! benchmark's catalogue, resumed from a checkpoint bit-identically (issue 23,
//! docs/seas-bp1.md).

use rsf::fem::{rectangle, Diagonal};
use rsf::friction::{AsinhLaw, FrictionLaw};
use rsf::model::AntiplaneMaterial;
use rsf::observe::{FileMode, SeasOutput, SeasSampling, SeasSetup, SECONDS_PER_YEAR};
use rsf::{Checkpoint, Flow, ModelBuilder, Observer, Part, StepView};
use rsf_scenes::{SeasBp1, SeasBp1Grid, SeasBp1Simulation};

use crate::common::small_bp1;

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
    let (bp1, grid) = small_bp1(&SeasBp1 {
        a0: 0.025,
        v_init: 1e-10,
        ..SeasBp1::default()
    });
    let model = bp1.model(&grid, false).unwrap();
    let mut sim = bp1
        .simulation_builder(model, false, 1e-2, bp1.step_control(1e-4).unwrap())
        .unwrap()
        .build()
        .unwrap();
    sim.run_until(rsf::Until::Time(3000.0 * SECONDS_PER_YEAR), &mut [])
        .unwrap();
    let mut v = vec![0.0; sim.model().frictional_boundary.len()];
    sim.slip_rates(&mut v);
    let worst_v = v
        .iter()
        .map(|v| (v / bp1.v_p - 1.0).abs())
        .fold(0.0, f64::max);
    let laws = sim.problem().friction_laws();
    let mut worst_tau: f64 = 0.0;
    for (k, &p) in sim.model().frictional_boundary.nodes.iter().enumerate() {
        let z = sim.model().vertices[p][1];
        let law = AsinhLaw::new(bp1.params(z)).unwrap();
        let steady = law.friction_coefficient(bp1.v_p, (bp1.d_c / bp1.v_p).ln());
        let now = laws[k].friction_coefficient(v[k], sim.alpha()[k]);
        worst_tau = worst_tau.max((now / steady - 1.0).abs());
    }
    eprintln!("steady creep: max |V/V_p − 1| = {worst_v:e}, max stress error {worst_tau:e}");
    assert!(worst_v < 1e-3, "slip rate {worst_v}");
    assert!(worst_tau < 1e-4, "stress {worst_tau}");
}

fn coarse_bp1() -> (SeasBp1, SeasBp1Simulation) {
    let bp1 = SeasBp1::default();
    let grid = SeasBp1Grid {
        dz: 500.0,
        domain: 50e3,
        ratio: 1.05,
    };
    let model = bp1.model(&grid, false).unwrap();
    let sim = bp1
        .simulation_builder(model, false, 1e-2, bp1.step_control(1e-2).unwrap())
        .unwrap()
        .build()
        .unwrap();
    (bp1, sim)
}

fn output(dir: &std::path::Path, bp1: &SeasBp1, sim: &SeasBp1Simulation) -> SeasOutput<AsinhLaw> {
    SeasOutput::new(
        dir,
        sim.model(),
        sim.problem().friction_laws(),
        SeasSetup {
            problem: "BP1-QD (coarse test)".into(),
            modeler: "test".into(),
            date: "2026-11-24".into(),
            ..bp1.seas_setup(500.0, false, SeasSampling::default())
        },
        FileMode::Overwrite,
    )
    .unwrap()
}

/// Stops a run at the first step after the first event (max slip rate ≥ 1e-3 m/s, then
/// below again).
#[derive(Default)]
struct UntilFirstEventEnds {
    started: bool,
}

impl Observer<2, 1> for UntilFirstEventEnds {
    fn observe(&mut self, s: &StepView<'_, 2, 1>) -> rsf::Result<Flow> {
        let fast = s.report.max_slip_rate >= 1e-3;
        self.started |= fast;
        Ok(if self.started && !fast {
            Flow::Break(())
        } else {
            Flow::Continue(())
        })
    }
}

/// Runs `sim` with `out` until the first event has ended; returns the steps.
fn to_first_event_end(sim: &mut SeasBp1Simulation, out: &mut SeasOutput<AsinhLaw>) -> usize {
    let mut stop = UntilFirstEventEnds::default();
    let summary = sim.run(200_000, &mut [out, &mut stop]).unwrap();
    assert!(summary.steps < 200_000, "no event");
    summary.steps
}

/// A coarse BP1 (Δz = 500 m, 50 km domain, tolerance 1e-2) reaches its first event near
/// the spec's depth and time scale, writes the benchmark's files and catalogue; a
/// checkpoint taken in the interseismic period resumes to the same event and the same
/// final state, bit for bit.
#[test]
fn coarse_bp1_reaches_its_first_event_and_resumes_bit_identically() {
    let dir = std::env::temp_dir().join(format!("rsf_bp1_{}", std::process::id()));
    let (bp1, mut sim) = coarse_bp1();
    let mut out = output(&dir.join("a"), &bp1, &sim);
    let steps = to_first_event_end(&mut sim, &mut out);
    let first = out.events()[0];
    eprintln!("first event after {steps} steps: {first:?}");
    // Nucleation in the velocity-weakening zone, after decades of loading.
    assert!(first.hypocentre_depth > 5e3 && first.hypocentre_depth < 18e3);
    assert!(first.t_start > 50.0 * SECONDS_PER_YEAR && first.t_start < 400.0 * SECONDS_PER_YEAR);
    assert!(first.peak_slip_rate >= 1e-3 && first.t_end > first.t_start);
    let csv = std::fs::read_to_string(dir.join("a/events.csv")).unwrap();
    assert!(csv.starts_with(
        "event,t_start_s,t_end_s,hypocentre_depth_m,peak_slip_rate_mps,surface_slip_m\n1,"
    ));
    let station = std::fs::read_to_string(dir.join("a/fltst_dp075")).unwrap();
    assert!(station.contains("# num_time_steps="));
    assert!(station.contains("\nt slip slip_rate shear_stress state\n"));
    let rows: Vec<&str> = station
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .collect();
    assert!(rows.len() > 10 && rows.iter().all(|r| r.split_whitespace().count() == 5));
    let devol = std::fs::read_to_string(dir.join("a/devol.dat")).unwrap();
    let mut body = devol.lines().skip_while(|l| l.starts_with('#'));
    // The description's two field-list lines, then the row of depths.
    assert_eq!(body.next(), Some("z"));
    assert_eq!(body.next(), Some("t max_slip_rate slip"));
    let depths = body.next().unwrap();
    assert!(depths.starts_with("0 0 "), "{depths}");
    let columns = depths.split_whitespace().count();
    assert_eq!(columns, 2 + 81, "surface to W_f = 40 km every 500 m");
    assert!(body.all(|l| l.split_whitespace().count() == columns));

    // Resume from a checkpoint halfway through the interseismic period.
    let (_, mut sim_b) = coarse_bp1();
    let half = steps / 2;
    sim_b.run(half, &mut []).unwrap();
    let bytes = sim_b.checkpoint().to_bytes();
    let (_, mut sim_c) = coarse_bp1();
    sim_c
        .restore(&Checkpoint::from_bytes(&bytes).unwrap())
        .unwrap();
    let mut out_c = output(&dir.join("c"), &bp1, &sim_c);
    let rest = to_first_event_end(&mut sim_c, &mut out_c);
    assert_eq!(half + rest, steps);
    assert_eq!(out_c.events()[0], first);
    let (a, c) = (&sim.state().kinematics, &sim_c.state().kinematics);
    assert!(a
        .u
        .iter()
        .zip(&c.u)
        .all(|(x, y)| x.to_bits() == y.to_bits()));
    assert!(sim
        .alpha()
        .iter()
        .zip(sim_c.alpha())
        .all(|(x, y)| x.to_bits() == y.to_bits()));
    let _ = std::fs::remove_dir_all(&dir);
}
