//! Absorbing (Lysmer–Kuhlemeyer) boundaries (issue 36, docs/math.md "Absorbing
//! boundaries", docs/physics-tests.md): pulses leave the domain through them, a
//! reflecting boundary keeps them, the discrete energy balance holds with the dashpots'
//! dissipation, and the builder refuses what it cannot use.
//!
//! Set-up: linear elastodynamics (frictionless fault: Tresca with μ = 0), ρ = 1, μ = 1
//! (c_s = 1 m/s; plane strain with λ = 1: c_p = √3 m/s), `u₀ = 0` and an initial velocity
//! pulse away from the absorbing parts, so that `a₀ = 0` is consistent (`M a₀ = −K u₀ −
//! C v₀ = 0`). The pulse splits into two halves travelling in opposite directions; the one
//! running towards the reflecting side (clamped) comes back and crosses the absorbing
//! part later. Energy `E = ½vᵀMv + ½uᵀKu` from the model's matrices.

mod common;

use common::{apply, dot};
use rsf::fem::{rectangle, Diagonal, SimplexMesh};
use rsf::friction::Tresca;
use rsf::model::AntiplaneMaterial;
use rsf::simulation::NoState;
use rsf::time::{BackwardEuler, Newmark, Quasistatic, VelocityIntegrator};
use rsf::{Error, Material, Model, ModelBuilder, Part, SimulationBuilder, SolverKind};

const EPS: f64 = 1e-9;

/// `½vᵀMv + ½uᵀKu` (J per unit thickness).
fn energy<const C: usize>(model: &Model<2, C>, u: &[f64], v: &[f64]) -> f64 {
    let m = model.mass.as_ref().expect("dynamic model");
    0.5 * dot(v, &apply(m, v)) + 0.5 * dot(u, &apply(&model.stiffness, u))
}

/// A Gaussian velocity pulse of width `sigma` (m) centred at `x0`.
fn pulse(x: f64, x0: f64, sigma: f64) -> f64 {
    (-((x - x0) / sigma).powi(2)).exp()
}

/// Runs `sim` to `t_end` (s) with fixed steps; returns `E(t_end)/E(0)`.
fn energy_fraction<I: VelocityIntegrator, const C: usize>(
    mut sim: rsf::Simulation<2, Tresca, NoState, I, C>,
    t_end: f64,
) -> f64 {
    let k = sim.kinematics();
    let e0 = energy(sim.model(), &k.u, &k.v);
    while sim.time() < t_end - 1e-9 {
        sim.step().unwrap();
    }
    let k = sim.kinematics();
    energy(sim.model(), &k.u, &k.v) / e0
}

/// The strip `[0, 4] × [0, 0.25]` (h = 0.025 m).
fn strip() -> SimplexMesh<2> {
    rectangle([0.0, 0.0], [4.0, 0.25], 160, 10, Diagonal::Forward).unwrap()
}

fn right() -> Part<2> {
    Part::predicate("right", |x| x[0] > 4.0 - EPS)
}

/// Scalar (antiplane) strip: clamped at x = 0, frictionless (free) bottom, free top,
/// `right` absorbing if `absorbing`.
fn scalar_strip(absorbing: bool) -> Model<2, 1> {
    let mut b = ModelBuilder::scalar(strip())
        .material(AntiplaneMaterial::new(1.0, 1.0))
        .dirichlet(Part::predicate("left", |x| x[0] < EPS), [0.0])
        .frictional_boundary(Part::predicate("bottom", |x| x[1] < EPS));
    if absorbing {
        b = b.absorbing_boundary(right());
    }
    b.build().unwrap()
}

fn scalar_sim<I: VelocityIntegrator>(
    model: Model<2, 1>,
    integrator: I,
    tau: f64,
) -> rsf::Simulation<2, Tresca, NoState, I, 1> {
    SimulationBuilder::new(model)
        .friction(Tresca::new(0.0, 1.0).unwrap())
        .initial_state(0.0)
        .integrator(integrator)
        .time_step(tau)
        .solver(SolverKind::Direct)
        .initial_velocity_at(|x| [pulse(x[0], 2.0, 0.15)])
        .build()
        .unwrap()
}

/// Plane strain strip (`E = 2.5`, `ν = 0.25`: λ = μ = 1), clamped at x = 0 (also its
/// frictional part), rollers on top and bottom fixing component `roller` (1 for a P wave
/// along x, 0 for an S wave), `right` absorbing if `absorbing`.
fn vector_strip(absorbing: bool, roller: usize) -> Model<2> {
    let left = |x: &[f64; 2]| x[0] < EPS;
    let mut b = ModelBuilder::new(strip())
        .material(Material::new(2.5, 0.25, 1.0))
        .dirichlet(Part::predicate("left", left), [0.0, 0.0])
        .frictional_boundary(Part::predicate("left", left))
        .dirichlet_components(
            Part::predicate("top and bottom", |x| x[1] < EPS || x[1] > 0.25 - EPS),
            &[roller],
            [0.0, 0.0],
        );
    if absorbing {
        b = b.absorbing_boundary(right());
    }
    b.build().unwrap()
}

fn vector_sim(model: Model<2>, component: usize, tau: f64) -> rsf::Simulation<2, Tresca, NoState, Newmark> {
    SimulationBuilder::new(model)
        .friction(Tresca::new(0.0, 1.0).unwrap())
        .initial_state(0.0)
        .integrator(Newmark)
        .time_step(tau)
        .solver(SolverKind::Direct)
        .initial_velocity_at(move |x| {
            let mut v = [0.0; 2];
            v[component] = pulse(x[0], 2.0, 0.15);
            v
        })
        .build()
        .unwrap()
}

/// The dashpot matrix integrates the impedance over the part: its entries sum to
/// `ρc_s · |Γ_A|` (scalar), and for plane strain on a face with normal x to `ρc_p |Γ_A|`
/// (xx) and `ρc_s |Γ_A|` (yy), with no xy coupling. Checked from the definitions, not
/// the code's numbers.
#[test]
fn the_dashpots_integrate_the_impedances_over_the_part() {
    let sum = |m: &rsf::fem::SparseMatrix, pick: &dyn Fn(usize, usize) -> bool| {
        let (cp, ri, val) = (m.symbolic().col_ptr(), m.symbolic().row_idx(), m.val());
        let mut s = 0.0;
        for j in 0..m.ncols() {
            for k in cp[j]..cp[j + 1] {
                if pick(ri[k], j) {
                    s += val[k];
                }
            }
        }
        s
    };
    let scalar = scalar_strip(true);
    let c = &scalar.absorbing.as_ref().unwrap().damping;
    assert!((sum(c, &|_, _| true) - 0.25).abs() < 1e-14, "ρc_s |Γ_A| = 0.25");
    let vector = vector_strip(true, 1);
    let c = &vector.absorbing.as_ref().unwrap().damping;
    let xx = sum(c, &|i, j| i % 2 == 0 && j % 2 == 0);
    let yy = sum(c, &|i, j| i % 2 == 1 && j % 2 == 1);
    let xy = sum(c, &|i, j| i % 2 != j % 2);
    assert!((xx - 0.25 * 3f64.sqrt()).abs() < 1e-14, "ρc_p |Γ_A|: {xx}");
    assert!((yy - 0.25).abs() < 1e-14, "ρc_s |Γ_A|: {yy}");
    assert_eq!(xy, 0.0);
    assert!(scalar_strip(false).absorbing.is_none());
}

/// Normal incidence, antiplane (SH): both halves of the pulse cross x = 4 by t = 7 s;
/// at most 1 % of the energy stays. The same run with a free (reflecting) right side
/// keeps it all (Newmark conserves energy; frictionless fault).
#[test]
fn a_pulse_at_normal_incidence_leaves_through_an_absorbing_boundary_antiplane() {
    let tau = 0.0125;
    let absorbed = energy_fraction(scalar_sim(scalar_strip(true), Newmark, tau), 7.0);
    let reflected = energy_fraction(scalar_sim(scalar_strip(false), Newmark, tau), 7.0);
    eprintln!("antiplane: energy left {absorbed:.3e} (absorbing), {reflected:.6} (free side)");
    assert!(absorbed <= 0.01, "{absorbed}");
    assert!((reflected - 1.0).abs() < 1e-6, "{reflected}");
}

/// Normal incidence, plane strain: a P pulse (v along x, c_p = √3) and an S pulse (v
/// along y, c_s = 1) leave through the dashpots of ρc_p n nᵀ + ρc_s (I − n nᵀ).
#[test]
fn p_and_s_pulses_at_normal_incidence_leave_through_an_absorbing_boundary() {
    let tau = 0.0125;
    // P: both halves crossed by (2 + 4 + 0.6)/√3 ≈ 3.8 s.
    let p = energy_fraction(vector_sim(vector_strip(true, 1), 0, tau), 4.0);
    let p_free = energy_fraction(vector_sim(vector_strip(false, 1), 0, tau), 4.0);
    // S: by 2 + 4 + 0.6 = 6.6 s.
    let s = energy_fraction(vector_sim(vector_strip(true, 0), 1, tau), 7.0);
    let s_free = energy_fraction(vector_sim(vector_strip(false, 0), 1, tau), 7.0);
    eprintln!("plane strain: P left {p:.3e} (free {p_free:.6}), S left {s:.3e} (free {s_free:.6})");
    assert!(p <= 0.01 && s <= 0.01, "P {p}, S {s}");
    assert!((p_free - 1.0).abs() < 1e-6 && (s_free - 1.0).abs() < 1e-6);
}
