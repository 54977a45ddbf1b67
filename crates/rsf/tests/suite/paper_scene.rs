//! The scene is the paper's (issue 22): `SliderScene::default()` and the scene file
//! `scenes/pipping_slider.toml` against §6.1 and Table 6.1 of Pipping, Sander & Kornhuber
//! (text in the shared paper directory; restated in docs/math.md §6), field by field and
//! through what the code derives from them (τ, the ramp, the loading history, the friction
//! parameters, the material, the assembled model's geometry, mass, load and constraints,
//! the initial state).
//!
//! Every expected value below is a literal copied from the paper, with the table or
//! section it comes from; none is read from the code. The paper's values are decimal
//! literals and the derived quantities a few floating-point operations on them, so each is
//! compared to a relative tolerance of 1e-12 (thousands of ulps; the values are either
//! right to a few ulps or wrong by a visible fraction). Integers and choices are compared
//! exactly.
//!
//! Fields the paper does not fix are not checked against it: the velocity solver (the
//! paper uses TNNMG; the scene's `auto` picks the direct solver on small faults, which
//! solves the same problem), the fixed point scheme (Anderson acceleration by default; the
//! paper's damped iteration is `fixed_point = "paper"`), the fixed point budget and the
//! direction of the coarse grid's diagonals.

use crate::common::{apply, dot};
use rsf::method::StateIntegrator;
use rsf::{Integrator, StateLawKind};
use rsf_scenes::{SliderScene, TimeStep};

/// Relative tolerance of every real-valued comparison (module docs).
const TOL: f64 = 1e-12;

/// The scene file in the repository.
const SCENE_FILE: &str = include_str!("../../../../scenes/pipping_slider.toml");

/// The paper's values, as literals from the paper.
mod paper {
    /// Final time T (s), §6.1: "We select the final time T = 15 s".
    pub const T: f64 = 15.0;
    /// Number of time steps N, §6.1: "τ = T/N with N = 10⁴, if not stated otherwise".
    pub const N: usize = 10_000;
    /// Refinement level of the time series, §6.3 (Figs. 6.2–6.5): "T_j, j = 4".
    pub const LEVEL: usize = 4;
    /// The slider Ω = 5 m × 1 m, §6.1.
    pub const LENGTH: f64 = 5.0;
    pub const HEIGHT: f64 = 1.0;
    /// Vertices of the coarse grid T_0, §6.1: "a regular initial grid T_0 with 2×6 vertices".
    pub const COARSE_VERTICES: usize = 2 * 6;
    /// Table 6.1: mass density ρ = 5×10³ kg/m².
    pub const RHO: f64 = 5e3;
    /// Table 6.1: Poisson's ratio ν = 0.3.
    pub const NU: f64 = 0.3;
    /// Table 6.1: Young's modulus E = 5×10⁷ N/m.
    pub const E: f64 = 5e7;
    /// Table 6.1: gravity g = 9.81 N/kg; §6.1: body force f = −ρ g e₂.
    pub const G: f64 = 9.81;
    /// Table 6.1: prescribed normal stress σ̄_n = 49 050 N/m.
    pub const SIGMA_N: f64 = 49_050.0;
    /// Table 6.1: reference velocity V0 = 1×10⁻⁶ m/s.
    pub const V0: f64 = 1e-6;
    /// Table 6.1: reference friction coefficient μ0 = 0.6.
    pub const MU0: f64 = 0.6;
    /// Table 6.1: rate-effect coefficient a = 0.010.
    pub const A: f64 = 0.010;
    /// Table 6.1: state-effect coefficient b = 0.015.
    pub const B: f64 = 0.015;
    /// Table 6.1: characteristic slip distance L = 1×10⁻⁵ m.
    pub const L: f64 = 1e-5;
    /// §6.1: V_D(t) = 2×10⁻⁴ m/s · 4t/T for t ≤ T/4, 2×10⁻⁴ m/s otherwise.
    pub const V_D: f64 = 2e-4;
    /// §6.1: the ramp ends at T/4.
    pub const RAMP_FRACTION: f64 = 0.25;
    /// §6.1: α(·, 0) = −10 on Γ_F.
    pub const ALPHA0: f64 = -10.0;
    /// §6.2: the fixed point iteration stops at ‖u^{ν+1} − u^ν‖ ≤ 10⁻¹⁰ (energy norm).
    pub const FIXED_POINT_TOL: f64 = 1e-10;
    /// §6.2: TNNMG "with an absolute error tolerance of 10⁻¹⁰" in the energy norm.
    pub const SOLVER_TOL: f64 = 1e-10;

    /// The paper's loading velocity V_D(t) (m/s), §6.1.
    pub fn loading_velocity(t: f64) -> f64 {
        if t <= T / 4.0 {
            V_D * 4.0 * t / T
        } else {
            V_D
        }
    }

    /// `ln V_m(α)` of the cutoff velocity, (2.13):
    /// `V_m = V0 exp(−(μ0 + b(α + ln(V0/L)))/a)`.
    pub fn ln_cutoff_velocity(alpha: f64) -> f64 {
        V0.ln() - (MU0 + B * (alpha + (V0 / L).ln())) / A
    }
}

/// Comparisons of one scene with the paper, collecting every mismatch.
struct Against {
    /// Where the scene came from (for messages).
    source: &'static str,
    mismatches: Vec<String>,
    /// Largest `relative error / TOL` of the real-valued comparisons.
    worst: f64,
}

impl Against {
    fn new(source: &'static str) -> Self {
        Self {
            source,
            mismatches: Vec::new(),
            worst: 0.0,
        }
    }

    /// `got` against the paper's `expected` to the relative tolerance [`TOL`] (an absolute
    /// one of [`TOL`] where `expected` is 0).
    fn real(&mut self, name: &str, got: f64, expected: f64) {
        let error = (got - expected).abs() / expected.abs().max(1.0e-300);
        let error = if expected == 0.0 { got.abs() } else { error };
        let ratio = error / TOL;
        // NaN counts as a mismatch.
        if !(ratio <= self.worst) {
            self.worst = ratio;
        }
        if !(ratio <= 1.0) {
            self.mismatches.push(format!(
                "{}: {name} = {got:e}, the paper's {expected:e} (relative error {error:.3e}, \
                 {ratio:.3e} × the tolerance)",
                self.source
            ));
        }
    }

    /// `got == expected` for integers and choices.
    fn exact<T: PartialEq + std::fmt::Debug>(&mut self, name: &str, got: T, expected: T) {
        if got != expected {
            self.mismatches.push(format!(
                "{}: {name} = {got:?}, the paper's {expected:?}",
                self.source
            ));
        }
    }

    /// Panics with every mismatch.
    fn finish(self) {
        eprintln!(
            "{}: worst relative error {:.3e} of the tolerance {TOL:e}",
            self.source, self.worst
        );
        assert!(
            self.mismatches.is_empty(),
            "the scene differs from the paper:\n{}",
            self.mismatches.join("\n")
        );
    }
}

/// The scene's fields and the quantities it derives without assembling anything.
fn check_fields(c: &mut Against, s: &SliderScene) {
    // §6.1: time.
    c.real("end_time_s (T)", s.end_time_s, paper::T);
    c.exact("steps (N)", s.steps, paper::N);
    c.exact("time_step", s.time_step, TimeStep::Fixed {});
    c.real("tau() (τ = T/N)", s.tau(), paper::T / paper::N as f64);
    c.real("tau() (τ = 1.5 ms)", s.tau(), 1.5e-3);
    c.real("initial_tau()", s.initial_tau(), 1.5e-3);
    c.exact("level (j)", s.level, paper::LEVEL);
    // Table 6.1: material and gravity.
    c.real("density_kg_per_m2 (ρ)", s.density_kg_per_m2, paper::RHO);
    c.real("youngs_modulus_pa (E)", s.youngs_modulus_pa, paper::E);
    c.real("poisson_ratio (ν)", s.poisson_ratio, paper::NU);
    c.real("gravity_m_per_s2 (g)", s.gravity_m_per_s2, paper::G);
    let m = s.material();
    c.real("material().density", m.density, paper::RHO);
    c.real("material().youngs_modulus", m.youngs_modulus, paper::E);
    c.real("material().poisson_ratio", m.poisson_ratio, paper::NU);
    // Table 6.1: friction.
    // Each as the scene's field and as the friction parameter it gives.
    let p = s.rate_state_params();
    for (field, got, parameter, got_parameter, expected) in [
        (
            "sigma_n_pa (σ̄_n)",
            s.sigma_n_pa,
            "sigma_n",
            p.sigma_n,
            paper::SIGMA_N,
        ),
        ("mu0", s.mu0, "mu0", p.mu0, paper::MU0),
        ("a", s.a, "a", p.a, paper::A),
        ("b", s.b, "b", p.b, paper::B),
        ("v0_m_per_s (V0)", s.v0_m_per_s, "v0", p.v0, paper::V0),
        ("l_m (L)", s.l_m, "l", p.l, paper::L),
    ] {
        c.real(field, got, expected);
        c.real(
            &format!("rate_state_params().{parameter}"),
            got_parameter,
            expected,
        );
    }
    // The cutoff velocity V_m(α) (2.13) at the initial state and at steady sliding at V_D.
    for alpha in [paper::ALPHA0, (paper::L / paper::V_D).ln()] {
        c.real(
            &format!("ln V_m(α = {alpha:.3})"),
            p.ln_cutoff_velocity(alpha),
            paper::ln_cutoff_velocity(alpha),
        );
    }
    // σ̄_n is the weight of the 1 m high column above Γ_F: ρ g · 1 m.
    c.real(
        "sigma_n_pa against ρ g · height",
        s.sigma_n_pa,
        paper::RHO * paper::G * paper::HEIGHT,
    );
    // §6.1: loading of Γ_D.
    c.real(
        "loading_velocity_m_per_s (V_D after the ramp)",
        s.loading_velocity_m_per_s,
        paper::V_D,
    );
    c.real("ramp_fraction", s.ramp_fraction, paper::RAMP_FRACTION);
    c.real("ramp_end_s (T/4)", s.ramp_end_s(), paper::T / 4.0);
    let g = s.loading();
    for t in [
        0.0,
        paper::T / 40.0,
        paper::T / 8.0,
        0.2 * paper::T,
        paper::T / 4.0,
        0.3 * paper::T,
        2.0 * paper::T / 3.0,
        paper::T,
    ] {
        c.real(
            &format!("V_D(t = {t} s) = loading_velocity · loading().value(t)"),
            s.loading_velocity_m_per_s * g.value(t),
            paper::loading_velocity(t),
        );
    }
    // §6.1: the initial state.
    c.real("alpha0 (α(·, 0))", s.alpha0, paper::ALPHA0);
    // §3, §6.3: Newmark for the velocity, backward Euler (3.5) for the state, Dieterich's
    // (aging) law for the time series.
    c.exact("integrator", s.integrator, Integrator::Newmark);
    c.exact(
        "state_integrator",
        s.state_integrator,
        StateIntegrator::BackwardEuler,
    );
    c.exact("state_law", s.state_law, StateLawKind::Aging);
    // §6.2: tolerances.
    c.real(
        "fixed_point_tolerance",
        s.fixed_point_tolerance,
        paper::FIXED_POINT_TOL,
    );
    c.real("solver_tolerance", s.solver_tolerance, paper::SOLVER_TOL);
}

/// What the scene assembles: the coarse grid T_0 of Ω (level 0), its mass, load,
/// boundary parts and Dirichlet data, and the initial state of the simulation.
fn check_assembled(c: &mut Against, s: &SliderScene) {
    let coarse = SliderScene {
        level: 0,
        ..s.clone()
    };
    let mut sim = coarse.build().expect("the scene builds");
    let model = sim.model();
    let n = model.num_dofs();
    // §6.1: Ω = [0, 5] × [0, 1] m, T_0 with 2 × 6 vertices.
    c.exact("vertices of T_0", model.num_nodes(), paper::COARSE_VERTICES);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for x in &model.vertices {
        for d in 0..2 {
            lo[d] = lo[d].min(x[d]);
            hi[d] = hi[d].max(x[d]);
        }
    }
    c.real("x_min", lo[0], 0.0);
    c.real("y_min", lo[1], 0.0);
    c.real("x_max (length)", hi[0], paper::LENGTH);
    c.real("y_max (height)", hi[1], paper::HEIGHT);
    // The mass of the block per unit thickness, ρ · 5 m · 1 m, once per component.
    let area = paper::LENGTH * paper::HEIGHT;
    let mass = model
        .mass
        .as_ref()
        .expect("Newmark assembles the mass matrix");
    let ones = vec![1.0; n];
    c.real(
        "1ᵀ M 1 (2 ρ |Ω|)",
        dot(&ones, &apply(mass, &ones)),
        2.0 * paper::RHO * area,
    );
    // §6.1: body force f = −ρ g e₂: the load sums to (0, −ρ g |Ω|).
    let (fx, fy): (f64, f64) = (
        model.load.iter().step_by(2).sum(),
        model.load.iter().skip(1).step_by(2).sum(),
    );
    c.real("Σ F_x (N)", fx, 0.0);
    c.real("Σ F_y (N)", fy, -paper::RHO * paper::G * area);
    // Γ_F = the bottom edge, bilateral contact (normal velocity fixed, tangential free);
    // its lumped weights add up to its length.
    let fb = &model.frictional_boundary;
    let bottom: Vec<usize> = (0..model.num_nodes())
        .filter(|&p| model.vertices[p][1] == 0.0)
        .collect();
    c.exact("Γ_F nodes", fb.nodes.clone(), bottom.clone());
    c.real(
        "Σ w_p (length of Γ_F)",
        fb.weights.iter().sum(),
        paper::LENGTH,
    );
    c.exact(
        "Γ_F: normal fixed, tangential free",
        bottom
            .iter()
            .map(|&p| (model.fixed[2 * p], model.fixed[2 * p + 1]))
            .collect::<Vec<_>>(),
        vec![(false, true); bottom.len()],
    );
    // Γ_D = the top edge, both components prescribed: velocity (V_D(t), 0). Γ_N = the
    // sides: free.
    for p in 0..model.num_nodes() {
        let [x, y] = model.vertices[p];
        let on_top = y == paper::HEIGHT;
        if on_top {
            c.exact(
                &format!("Γ_D node {p} fixed"),
                (model.fixed[2 * p], model.fixed[2 * p + 1]),
                (true, true),
            );
        } else if y > 0.0 {
            c.exact(
                &format!("node {p} at ({x}, {y}) free"),
                (model.fixed[2 * p], model.fixed[2 * p + 1]),
                (false, false),
            );
        }
    }
    let d = &model.dirichlet;
    for t in [0.0, paper::T / 8.0, paper::T / 4.0, paper::T] {
        let mut v = vec![0.0; n];
        for (&dof, &f) in d.dofs.iter().zip(&d.factors) {
            v[dof] = f * d.speed(t);
        }
        for p in (0..model.num_nodes()).filter(|&p| model.vertices[p][1] == paper::HEIGHT) {
            c.real(
                &format!("v_x on Γ_D at t = {t} s"),
                v[2 * p],
                paper::loading_velocity(t),
            );
            c.real(&format!("v_y on Γ_D at t = {t} s"), v[2 * p + 1], 0.0);
        }
    }
    // §6.1: u_0 solves a(u_0, v) = ℓ(v) (K u_0 = F on the free dofs), v_0 = V_D(0) e₁ = 0,
    // α_0 = −10 on Γ_F.
    let ku = apply(&model.stiffness, &model.initial_displacement);
    let f_scale = model.load.iter().fold(0.0f64, |m, f| m.max(f.abs()));
    let residual = (0..n)
        .filter(|&i| !model.fixed[i])
        .map(|i| (ku[i] - model.load[i]).abs())
        .fold(0.0, f64::max);
    c.real(
        "max |K u_0 − F| / max |F| (free dofs)",
        residual / f_scale,
        0.0,
    );
    let k = sim.kinematics();
    c.exact(
        "u at t = 0",
        k.u.clone(),
        model.initial_displacement.clone(),
    );
    c.exact(
        "v at t = 0",
        k.v.clone(),
        vec![paper::loading_velocity(0.0); n],
    );
    c.exact(
        "α at t = 0",
        sim.alpha().to_vec(),
        vec![paper::ALPHA0; fb.len()],
    );
    // The first step is taken at τ = T/N and ends at t_1 = τ.
    sim.step().expect("the first step succeeds");
    c.real("t_1", sim.time(), paper::T / paper::N as f64);
}

#[test]
fn default_scene_is_the_papers() {
    let mut c = Against::new("SliderScene::default()");
    let scene = SliderScene::default();
    check_fields(&mut c, &scene);
    check_assembled(&mut c, &scene);
    c.finish();
}

#[test]
fn scene_file_is_the_papers() {
    let mut c = Against::new("scenes/pipping_slider.toml");
    let scene = SliderScene::from_toml(SCENE_FILE).expect("the scene file parses");
    check_fields(&mut c, &scene);
    check_assembled(&mut c, &scene);
    c.finish();
}
