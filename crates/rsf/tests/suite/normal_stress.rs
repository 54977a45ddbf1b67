//! Normal stress that changes with slip on a fault inside the body
//! (`SimulationBuilder::normal_stress(NormalStress::FromSlip)`, docs/faults-inside.md):
//! the fault ODE's normal stress against a full static solve at the same slip, zero change
//! on a fault that is a plane of mirror symmetry, the implicit scheme converging to the
//! fault ODE, and typed refusals.
use crate::common::{assert_first_order_with_normal_stress, quasi_dynamic_of, within};
use rsf::direct::{DirectOptions, DirectSolver};
use rsf::fault_ode::FaultOdeOptions;
use rsf::fem::{rectangle, Diagonal, SimplexMesh, SparseMatrix};
use rsf::friction::{AsinhLaw, RateStateParams};
use rsf::nonsmooth::{NoNonlinearity, NonsmoothSolver};
use rsf::normal_stress::NormalStress;
use rsf::state::Aging;
use rsf::time::Quasistatic;
use rsf::{Flow, Material, Model, ModelBuilder, Observer, Part, SimulationBuilder, StepView};

/// The laws' normal stress σ̄_n⁰ (Pa) of these tests (and of `normal_stress_3d`).
pub(crate) const SIGMA_N: f64 = 5e6;

/// The regularised law's parameters of these tests (and of `normal_stress_3d`).
pub(crate) fn params() -> RateStateParams {
    RateStateParams {
        mu0: 0.1,
        a: 0.015,
        b: 0.01,
        v0: 1e-6,
        l: 1e-4,
        sigma_n: SIGMA_N,
    }
}

/// The quasi-dynamic problem on `model` (regularised law, aging law, steady state at
/// 1e-4 m/s, radiation damping μ/(2c_s)) with the normal stress found as `normal_stress`
/// (also `normal_stress_3d`'s, in 3-D).
pub(crate) fn quasi_dynamic<const D: usize>(
    model: Model<D>,
    normal_stress: NormalStress,
) -> SimulationBuilder<D, AsinhLaw, Aging, Quasistatic, D> {
    quasi_dynamic_of(model, params(), 1e-4, 1e10 / 2.5).normal_stress(normal_stress)
}

/// The fault ODE of [`quasi_dynamic`] at tolerance 1e-9.
pub(crate) fn fault_ode(
    model: Model<2>,
    normal_stress: NormalStress,
) -> rsf::Result<rsf::FaultOde<2, AsinhLaw, Aging>> {
    quasi_dynamic(model, normal_stress)
        .time_step(1e-3)
        .build_fault_ode(FaultOdeOptions {
            tolerance: 1e-9,
            ..Default::default()
        })
}

/// The rows ([`Record`]) of the fault ODE `ode` run to `t_end` (s).
fn record_to(ode: &mut rsf::FaultOde<2, AsinhLaw, Aging>, t_end: f64) -> Record {
    let mut record = Record::default();
    rsf::run_until(ode, within(t_end), &mut [&mut record]).unwrap();
    record
}

/// Per step: time, the model's displacement (fixed dofs and the fault's unknowns), and the
/// normal stress of every frictional node.
#[derive(Default)]
struct Record {
    rows: Vec<(f64, Vec<f64>, Vec<f64>)>,
}

impl Observer<2> for Record {
    fn observe(&mut self, s: &StepView<'_, 2, 2>) -> rsf::Result<Flow> {
        let sigma = (0..s.model.frictional_boundary.len())
            .map(|k| s.normal_traction(k).unwrap())
            .collect();
        self.rows
            .push((s.state.time, s.state.kinematics.u.clone(), sigma));
        Ok(Flow::Continue(()))
    }
}

/// The reactions `(K u − F)` at the tied normal jumps of the static solution with the
/// fault's unknowns and the fixed dofs at their values in `u` (a full sparse solve).
fn normal_reactions(model: &Model<2>, u: &[f64]) -> Vec<f64> {
    let k: &SparseMatrix = &model.stiffness;
    let mut fixed = model.fixed.clone();
    for &p in &model.frictional_boundary.nodes {
        fixed[2 * p] = true;
    }
    let mut x: Vec<f64> = u
        .iter()
        .zip(&fixed)
        .map(|(&v, &f)| if f { v } else { 0.0 })
        .collect();
    DirectSolver::<2>::new(k.as_ref(), &fixed, DirectOptions::default())
        .unwrap()
        .solve(&model.load, &NoNonlinearity, &mut x)
        .unwrap();
    let mut r: Vec<f64> = model.load.iter().map(|f| -f).collect();
    rsf::fem::spmv_add(k.as_ref(), 1.0, &x, &mut r);
    model
        .frictional_boundary
        .nodes
        .iter()
        .map(|&p| r[2 * p + 1])
        .collect()
}

/// `[-1, 1] × [-1, 0]` (the top a free surface), a fault dipping 45° from the surface at
/// the origin to a tip at (−0.5, −0.5), the sides pushed together (left +v, right −v):
/// reverse slip, which changes the normal stress.
fn thrust_block() -> Model<2> {
    thrust_block_with(false)
}

/// [`thrust_block`], with a mass matrix if `inertia` (the dynamic phases' model).
fn thrust_block_with(inertia: bool) -> Model<2> {
    let v = 1e-4;
    let mesh = rectangle([-1.0, -1.0], [2.0, 1.0], 9, 5, Diagonal::Forward).unwrap();
    let builder = ModelBuilder::refined(mesh, 1)
        .unwrap()
        .material(Material::new(1e10, 0.25, 2700.0))
        .dirichlet(Part::predicate("left", |x| x[0] < -1.0 + 1e-9), [v, 0.0])
        .dirichlet(Part::predicate("right", |x| x[0] > 1.0 - 1e-9), [-v, 0.0])
        .internal_fault("fault", [-0.5, -0.5], [0.0, 0.0]);
    if inertia {
        builder
    } else {
        builder.without_mass()
    }
    .build()
    .unwrap()
}

/// The fault ODE's normal stress at every step equals `σ̄_n⁰ − Δr_N/w` with the
/// reactions of a full static solve at the same slip and loading (an independent solver:
/// the whole sparse system instead of the condensation), and it changes noticeably.
#[test]
fn the_fault_odes_normal_stress_is_the_reaction_of_the_full_static_solution() {
    let model = thrust_block();
    let weights = model.frictional_boundary.weights.clone();
    let mut ode = fault_ode(model.clone(), NormalStress::FromSlip).unwrap();
    let record = record_to(&mut ode, 3.0);
    let r0 = normal_reactions(&model, &model.initial_displacement);
    let mut largest_change = 0.0f64;
    let mut worst = 0.0f64;
    let stride = (record.rows.len() / 12).max(1);
    for (_, u, sigma) in record.rows.iter().step_by(stride) {
        let r = normal_reactions(&model, u);
        for k in 0..sigma.len() {
            let expected = SIGMA_N - (r[k] - r0[k]) / weights[k];
            worst = worst.max((sigma[k] - expected).abs());
            largest_change = largest_change.max((sigma[k] - SIGMA_N).abs());
        }
    }
    eprintln!(
        "{} steps; largest normal-stress change {largest_change:e} Pa of σ̄_n⁰ = {SIGMA_N:e}; \
         largest difference from the full solve {worst:e} Pa",
        record.rows.len()
    );
    assert!(largest_change > 1e-3 * SIGMA_N, "{largest_change:e}");
    assert!(
        worst < 1e-8 * largest_change,
        "{worst:e} of {largest_change:e}"
    );
    // Squeezing the block clamps the fault: compressive normal stress grows.
    let (_, _, last) = record.rows.last().unwrap();
    let mean = last.iter().sum::<f64>() / last.len() as f64;
    eprintln!("mean normal stress at the end {mean:e} Pa");
    assert!(mean > SIGMA_N, "{mean:e}");
}

/// `[-1, 1] × [-1, 1]` made mirror-symmetric about x = 0 (the right half's cells
/// reflected), refined once.
fn mirrored_square() -> SimplexMesh<2> {
    let half = rectangle([0.0, -1.0], [1.0, 2.0], 5, 9, Diagonal::Forward).unwrap();
    let mut vertices = half.vertices().to_vec();
    let mirror: Vec<usize> = half
        .vertices()
        .iter()
        .enumerate()
        .map(|(i, x)| {
            if x[0].abs() < 1e-12 {
                i
            } else {
                vertices.push([-x[0], x[1]]);
                vertices.len() - 1
            }
        })
        .collect();
    let mut cells = Vec::new();
    for c in 0..half.num_cells() {
        cells.extend_from_slice(half.cell(c));
    }
    for c in 0..half.num_cells() {
        cells.extend(half.cell(c).iter().map(|&v| mirror[v]));
    }
    SimplexMesh::from_ordered_cells(vertices, cells).unwrap()
}

/// A fault on a plane of mirror symmetry (x = 0 in a mirror-symmetric body, the sides
/// sheared oppositely: u_x even, u_y odd in x) is neither clamped nor unclamped by its
/// slip: the normal stress stays σ̄_n⁰ to round-off while the fault slips.
#[test]
fn slip_on_a_plane_of_mirror_symmetry_leaves_the_normal_stress_unchanged() {
    let v = 1e-4;
    let model = ModelBuilder::refined(mirrored_square(), 1)
        .unwrap()
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(Part::predicate("left", |x| x[0] < -1.0 + 1e-9), [0.0, v])
        .dirichlet(Part::predicate("right", |x| x[0] > 1.0 - 1e-9), [0.0, -v])
        .internal_fault("fault", [0.0, -0.5], [0.0, 0.5])
        .build()
        .unwrap();
    let mut ode = fault_ode(model, NormalStress::FromSlip).unwrap();
    let record = record_to(&mut ode, 3.0);
    let (_, u, _) = record.rows.last().unwrap();
    let slip = ode
        .model()
        .frictional_boundary
        .nodes
        .iter()
        .map(|&p| (u[2 * p] - ode.model().initial_displacement[2 * p]).abs())
        .fold(0.0f64, f64::max);
    let change = record
        .rows
        .iter()
        .flat_map(|r| r.2.iter())
        .map(|s| (s - SIGMA_N).abs())
        .fold(0.0f64, f64::max);
    eprintln!("largest slip {slip:e} m; largest normal-stress change {change:e} Pa");
    assert!(slip > 1e-6, "the fault slips: {slip:e} m");
    assert!(change < 1e-9 * SIGMA_N, "{change:e} Pa");
}

/// The thrust block pulled apart, hard: the fault unclamps until σ̄_n would be ≤ 0.
pub(crate) fn pulled_apart_block() -> Model<2> {
    let v = 1e2;
    let mesh = rectangle([-1.0, -1.0], [2.0, 1.0], 9, 5, Diagonal::Forward).unwrap();
    ModelBuilder::refined(mesh, 1)
        .unwrap()
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(Part::predicate("left", |x| x[0] < -1.0 + 1e-9), [-v, 0.0])
        .dirichlet(Part::predicate("right", |x| x[0] > 1.0 - 1e-9), [v, 0.0])
        .internal_fault("fault", [-0.5, -0.5], [0.0, 0.0])
        .build()
        .unwrap()
}

/// `NormalStress::FromSlip` needs a fault inside the body; a slip that would open the
/// fault is a typed error, not a NaN: the fault ODE refuses the stages until its cap of
/// refusals ([`rsf::time::Error::TrialPointRefused`]), the implicit scheme its iterates
/// until it cannot shrink the step ([`rsf::Error::TrialStateRefused`]).
#[test]
fn a_normal_stress_from_slip_is_refused_where_it_cannot_be_and_opening_is_an_error() {
    let mesh = rectangle([0.0, 0.0], [2.0, 0.5], 9, 3, Diagonal::Forward).unwrap();
    let boundary = ModelBuilder::refined(mesh, 1)
        .unwrap()
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(Part::predicate("top", |x| x[1] > 0.5 - 1e-9), [1e-4, 0.0])
        .frictional_boundary(Part::predicate("bottom", |x| x[1] < 1e-9))
        .build()
        .unwrap();
    match fault_ode(boundary, NormalStress::FromSlip) {
        Err(rsf::Error::InvalidParameter { name, .. }) => assert_eq!(name, "normal_stress"),
        other => panic!("{:?}", other.map(|_| ())),
    }
    let model = pulled_apart_block();
    let mut ode = fault_ode(model.clone(), NormalStress::FromSlip).unwrap();
    let e = rsf::run_until(&mut ode, within(10.0), &mut []).unwrap_err();
    let text = format!("{e}: {}", e.error);
    eprintln!("fault ODE: {text}");
    match &e.error {
        rsf::Error::Time(rsf::time::Error::TrialPointRefused {
            refusals, reason, ..
        }) => {
            // Up to the cap, or fewer where the next refusal would pass dt_min.
            let cap = FaultOdeOptions::default().runge_kutta.max_refusals;
            assert!(*refusals >= 1 && *refusals <= cap, "{text}");
            assert!(reason.contains("normal stress"), "{reason}");
        }
        _ => panic!("{text}"),
    }
    // Every refused attempt was counted in the steps before the last.
    assert!(e.summary.rejected_normal_stress <= e.summary.rejected_attempts);
    // The implicit scheme: a fixed step cannot be retried smaller (one refusal); an
    // adaptive one shrinks to tau_min first.
    for adaptive in [false, true] {
        let builder = quasi_dynamic(model.clone(), NormalStress::FromSlip)
            .time_step(1e-3)
            .solver(rsf::SolverKind::Direct);
        let mut sim = if adaptive {
            builder.step_control(rsf::time::StepControl::new(1e-3, 1e-4, 1e-9, 1.0).unwrap())
        } else {
            builder
        }
        .build()
        .unwrap();
        let e = sim.run_until(within(10.0), &mut []).unwrap_err();
        let text = format!("{e}: {}", e.error);
        eprintln!("implicit, adaptive {adaptive}: {text}");
        match &e.error {
            rsf::Error::TrialStateRefused {
                refusals, reason, ..
            } => {
                assert!(
                    matches!(**reason, rsf::Error::NormalStressNotPositive { .. }),
                    "{text}"
                );
                assert!(
                    if adaptive {
                        *refusals > 1
                    } else {
                        *refusals == 1
                    },
                    "{text}"
                );
            }
            _ => panic!("{text}"),
        }
    }
}

/// The two engines with a normal stress from slip on the thrust block: the implicit scheme
/// (backward Euler, σ̄_n iterated with the state in the fixed point, direct solver)
/// converges to the fault ODE at first order in τ — in the slip and in the normal stress;
/// TNNMG gives the direct solver's steps.
#[test]
fn the_implicit_scheme_converges_to_the_fault_ode_with_a_normal_stress_from_slip() {
    let t_end = 3.0;
    let model = thrust_block();
    let mut ode = fault_ode(model.clone(), NormalStress::FromSlip).unwrap();
    let reference = record_to(&mut ode, t_end);
    let nodes = model.frictional_boundary.nodes.clone();
    let slip_of = |u: &[f64]| -> Vec<f64> {
        nodes
            .iter()
            .map(|&p| u[2 * p] - model.initial_displacement[2 * p])
            .collect()
    };
    let (_, u_ref, sigma_ref) = reference.rows.last().unwrap();
    let slip_ref = slip_of(u_ref);
    let slip_scale = slip_ref.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let sigma_change = sigma_ref
        .iter()
        .fold(0.0f64, |m, s| m.max((s - SIGMA_N).abs()));
    let mut errors = Vec::new();
    for steps in [25, 50, 100, 200] {
        let mut sim = quasi_dynamic(model.clone(), NormalStress::FromSlip)
            .time_step(t_end / steps as f64)
            .solver(rsf::SolverKind::Direct)
            .build()
            .unwrap();
        let mut last = Record::default();
        sim.run(steps, &mut [&mut last]).unwrap();
        let (_, u, sigma) = last.rows.last().unwrap();
        let slip = slip_of(u);
        let e_slip = slip
            .iter()
            .zip(&slip_ref)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            / slip_scale;
        let e_sigma = sigma
            .iter()
            .zip(sigma_ref)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            / sigma_change;
        eprintln!(
            "τ = T/{steps}: implicit against the fault ODE: slip {e_slip:.3e} of {slip_scale:.3e} m, \
             normal stress {e_sigma:.3e} of its change {sigma_change:.3e} Pa"
        );
        errors.push((e_slip, e_sigma));
    }
    // The coupling matters: with the laws' fixed σ̄_n the fault ODE slips differently, by
    // far more than the implicit scheme's error.
    let mut fixed = fault_ode(model.clone(), NormalStress::Fixed).unwrap();
    let uncoupled = record_to(&mut fixed, t_end);
    let effect = slip_of(&uncoupled.rows.last().unwrap().1)
        .iter()
        .zip(&slip_ref)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / slip_scale;
    eprintln!("fixed σ̄_n against σ̄_n from slip (fault ODE): slip differs by {effect:.3e}");
    assert!(effect > 100.0 * errors[3].0, "{effect:e}");
    assert_first_order_with_normal_stress(&errors);
    // TNNMG (through its current iterate each fixed point iteration) gives the same steps.
    let run = |solver| {
        let mut sim = quasi_dynamic(model.clone(), NormalStress::FromSlip)
            .time_step(t_end / 25.0)
            .solver(solver)
            .build()
            .unwrap();
        let mut last = Record::default();
        sim.run(25, &mut [&mut last]).unwrap();
        last.rows.last().unwrap().clone()
    };
    let (a, b) = (run(rsf::SolverKind::Direct), run(rsf::SolverKind::Tnnmg));
    let d = slip_of(&a.1)
        .iter()
        .zip(slip_of(&b.1))
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    eprintln!("TNNMG against direct: slip {d:e} m");
    assert!(d < 1e-6 * slip_scale, "{d:e}");
    // Without a state there is no fixed point to iterate σ̄_n in: refused.
    let e = SimulationBuilder::new(model.clone())
        .friction(rsf::friction::Tresca::new(0.5, SIGMA_N).unwrap())
        .integrator(Quasistatic::new())
        .time_step(0.1)
        .normal_stress(NormalStress::FromSlip)
        .build()
        .err()
        .expect("refused");
    assert!(
        matches!(e, rsf::Error::InvalidParameter { ref name, .. } if name == "normal_stress"),
        "{e}"
    );
}

/// The switching run on an internal fault with a normal stress from slip: both phases
/// carry it (low thresholds make the run switch to the dynamic phase and back), the
/// observers see it change in both; engines with different settings are refused.
#[test]
fn the_switching_run_carries_a_normal_stress_from_slip_through_both_phases() {
    let options = rsf::switching::SwitchingOptions {
        to_dynamic: 5e-5,
        to_quasi_dynamic: 2e-5,
        dynamic_tau: 1e-3,
        restart_dt: 1e-3,
    };
    let dynamic = |normal| {
        quasi_dynamic(thrust_block_with(true), normal)
            .integrator(rsf::time::Newmark)
            .time_step(1e-3)
            .solver(rsf::SolverKind::Direct)
            .build()
            .unwrap()
    };
    let ode = fault_ode(thrust_block(), NormalStress::FromSlip).unwrap();
    match rsf::SwitchingRun::new(ode, dynamic(NormalStress::Fixed), options) {
        Err(rsf::Error::InvalidParameter { name, .. }) => assert_eq!(name, "dynamic"),
        other => panic!("{:?}", other.map(|_| ())),
    }
    let ode = fault_ode(thrust_block(), NormalStress::FromSlip).unwrap();
    let mut run = rsf::SwitchingRun::new(ode, dynamic(NormalStress::FromSlip), options).unwrap();
    let mut record = Record::default();
    run.run_until(within(3.0), &mut [&mut record]).unwrap();
    let stats = run.stats();
    let change = record
        .rows
        .iter()
        .flat_map(|r| r.2.iter())
        .fold(0.0f64, |m, s| m.max((s - SIGMA_N).abs()));
    eprintln!(
        "{stats:?}; {} rows; largest normal-stress change {change:e} Pa",
        record.rows.len()
    );
    assert!(
        stats.dynamic_phases > 0 && stats.dynamic_steps > 0,
        "{stats:?}"
    );
    assert!(change > 1e-3 * SIGMA_N, "{change:e}");
    assert!(record
        .rows
        .iter()
        .flat_map(|r| r.2.iter())
        .all(|s| s.is_finite() && *s > 0.0));
}
