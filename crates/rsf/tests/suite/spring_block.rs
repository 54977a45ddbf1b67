//! Spring–block slider (one degree of freedom, no mesh): the transition between steady
//! sliding and stick–slip lies within 10% of the critical stiffness `k_c = σ̄_n (b − a)/L`
//! (Ruina 1983, quasistatic limit). See `docs/spring-block.md` and
//! `examples/spring_block.rs`.
//!
//! Model: block = dof 0 (free, frictional node, weight 1 m²), load point = dof 1 (fixed,
//! prescribed velocity `V_load`), spring `[[k, −k], [−k, k]]`. Started at steady sliding
//! with the state kicked by `Δα = −0.01`; a run is *unstable* when the peaks of
//! `ln(V/V_load)` grow from one oscillation to the next.

use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use rsf::fem::SparseMatrix;
use rsf::friction::{DieterichRuina, RateStateParams};
use rsf::method::FixedPointOptions;
use rsf::model::{DirichletVelocity, FrictionalBoundary};
use rsf::state::Aging;
use rsf::time::{Kinematics, Newmark, Quasistatic, VelocityIntegrator};
use rsf::{
    Checkpoint, Model, Simulation, SimulationBuilder, SimulationState, SolverKind, TimeFunction,
};

const PARAMS: RateStateParams = RateStateParams {
    mu0: 0.6,
    a: 0.010,
    b: 0.015,
    v0: 1e-6,
    l: 1e-5,
    sigma_n: 1e6,
};
const V_LOAD: f64 = 1e-6;
const DALPHA: f64 = -0.01;
/// τ = (L/V_load)/100: backward Euler lowers the threshold by about τ V_load/L = 1%.
const TAU: f64 = 0.1;
/// Radiation damping of the quasistatic runs (≈ G/(2 c_s) for rock); lowers the threshold
/// by η V_load/(σ̄_n (b − a)) = 0.1%.
const ETA: f64 = 5e6;

fn k_crit() -> f64 {
    PARAMS.sigma_n * (PARAMS.b - PARAMS.a) / PARAMS.l
}

/// Period (s) of the linearised oscillation of steady sliding at `k_c`.
fn period() -> f64 {
    2.0 * std::f64::consts::PI * PARAMS.l / V_LOAD / ((PARAMS.b - PARAMS.a) / PARAMS.a).sqrt()
}

fn mat2(d00: f64, d01: f64, d11: f64) -> SparseMatrix {
    let sym = SymbolicSparseColMat::new_checked(2, 2, vec![0, 2, 4], None, vec![0, 1, 0, 1]);
    SparseColMat::new(sym, vec![d00, d01, d01, d11])
}

fn build<I: VelocityIntegrator>(
    k: f64,
    mass: Option<f64>,
    integrator: I,
) -> Simulation<1, DieterichRuina, Aging, I> {
    let f_ss = PARAMS.sigma_n * PARAMS.steady_state_friction(V_LOAD)
        + integrator.radiation_damping() * V_LOAD;
    let model = Model::<1> {
        vertices: vec![[0.0], [1.0]],
        mass: mass.map(|m| mat2(m, 0.0, 1.0)),
        stiffness: mat2(k, -k, k),
        energy_norm: match mass {
            Some(m) => mat2(k + m, -k, k + 1.0),
            None => mat2(k, -k, k),
        },
        load: vec![0.0; 2],
        fixed: vec![false, true],
        dirichlet: DirichletVelocity {
            dofs: vec![1],
            factors: vec![V_LOAD],
            history: TimeFunction::Constant(1.0),
        },
        prolongations: Vec::new(),
        frictional_boundary: FrictionalBoundary::new(&[0], &[1.0]).unwrap(),
        initial_displacement: vec![0.0, f_ss / k],
        cells: Vec::new(),
        frames: Default::default(),
        absorbing: None,
        internal_fault: None,
        columns: None,
    };
    let alpha0 = (PARAMS.l / V_LOAD).ln() + DALPHA;
    let mut sim = SimulationBuilder::new(model)
        .friction(DieterichRuina::new(PARAMS).unwrap())
        .state_law(Aging::new(PARAMS.l).unwrap())
        .initial_state(alpha0)
        .integrator(integrator)
        .time_step(TAU)
        .solver(SolverKind::Direct)
        .fixed_point(FixedPointOptions {
            max_iterations: 1000,
            ..FixedPointOptions::default()
        })
        .build()
        .unwrap();
    // Steady sliding: v = V_load on both dofs (the builder starts the block at rest).
    sim.restore(&Checkpoint::new(
        1,
        SimulationState {
            step: 0,
            time: 0.0,
            time_origin: (0, 0.0),
            tau: TAU,
            kinematics: Kinematics {
                u: vec![0.0, f_ss / k],
                v: vec![V_LOAD; 2],
                a: vec![0.0; 2],
            },
            alpha: vec![alpha0],
            controller: None,
        },
    ))
    .unwrap();
    sim
}

struct Outcome {
    max_v: f64,
    /// Geometric-mean ratio of successive peaks of ln(V/V_load); > 1 means growth.
    growth: f64,
}

fn run<I: VelocityIntegrator>(
    k_over_kc: f64,
    mass: Option<f64>,
    integrator: I,
    periods: f64,
) -> Outcome {
    let mut sim = build(k_over_kc * k_crit(), mass, integrator);
    let steps = (periods * period() / TAU).ceil() as usize;
    let mut xs = Vec::with_capacity(steps);
    let mut max_v = 0.0f64;
    for _ in 0..steps {
        let r = sim
            .step()
            .unwrap_or_else(|e| panic!("k/k_c = {k_over_kc}: {e}"));
        max_v = max_v.max(r.max_slip_rate);
        xs.push((sim.kinematics().v[0].abs() / V_LOAD).ln());
    }
    // Skip sample 0 (the kick itself); ignore round-off peaks of a decayed oscillation.
    let peaks: Vec<f64> = (2..steps - 1)
        .filter(|&n| xs[n] > xs[n - 1] && xs[n] >= xs[n + 1] && xs[n] > 1e-8)
        .map(|n| xs[n])
        .collect();
    assert!(
        peaks.len() >= 2,
        "k/k_c = {k_over_kc}: too few oscillations"
    );
    let growth = (peaks[peaks.len() - 1] / peaks[0]).powf(1.0 / (peaks.len() - 1) as f64);
    Outcome { max_v, growth }
}

/// Bisection on `k/k_c ∈ [0.5, 1.5]` for the sign change of the growth (7 halvings:
/// ±0.004).
fn transition<I: VelocityIntegrator>(mass: Option<f64>, integrator: I) -> f64 {
    let (mut lo, mut hi) = (0.5, 1.5);
    assert!(run(lo, mass, integrator.clone(), 10.0).growth > 1.0);
    assert!(run(hi, mass, integrator.clone(), 10.0).growth < 1.0);
    for _ in 0..7 {
        let mid = 0.5 * (lo + hi);
        if run(mid, mass, integrator.clone(), 10.0).growth > 1.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn quasistatic_transition_within_ten_percent_of_k_crit() {
    let k_star = transition(None, Quasistatic::with_radiation_damping(ETA).unwrap());
    println!("quasistatic (η = {ETA:e}): k*/k_c = {k_star:.4}");
    assert!((k_star - 1.0).abs() < 0.1, "k*/k_c = {k_star}");
    // Linear stability of the discrete scheme predicts 1 − τV/L − ηV/(σ̄_n(b − a)).
    let predicted =
        1.0 - TAU * V_LOAD / PARAMS.l - ETA * V_LOAD / (PARAMS.sigma_n * (PARAMS.b - PARAMS.a));
    assert!(
        (k_star - predicted).abs() < 0.01,
        "k*/k_c = {k_star}, predicted {predicted}"
    );
}

#[test]
fn small_mass_newmark_transition_within_ten_percent_of_k_crit() {
    // m = 1 kg: inertia raises k_c by m V²/(σ̄_n a L) = 1e-11 (negligible).
    let k_star = transition(Some(1.0), Newmark);
    println!("Newmark, m = 1 kg: k*/k_c = {k_star:.4}");
    assert!((k_star - 1.0).abs() < 0.1, "k*/k_c = {k_star}");
}

#[test]
fn stick_slip_below_and_steady_sliding_above_k_crit() {
    let eta = Quasistatic::with_radiation_damping(ETA).unwrap();
    let soft = run(0.5, None, eta, 30.0);
    assert!(
        soft.max_v > 100.0 * V_LOAD,
        "k = k_c/2 should reach stick–slip, max V = {}",
        soft.max_v
    );
    let stiff = run(2.0, None, eta, 30.0);
    assert!(stiff.growth < 0.5, "k = 2 k_c: growth {}", stiff.growth);
    assert!(
        stiff.max_v < 1.02 * V_LOAD,
        "k = 2 k_c: max V = {}",
        stiff.max_v
    );
}
