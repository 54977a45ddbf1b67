//! Energy balance of the coupled problem with friction, per step and summed (issue 13).
//!
//! Notation: free dofs are those not in `model.fixed`; `F` the constant load (gravity);
//! `f_n` the friction force, evaluated **from the friction law at the stored state**,
//! independently of the solver: `f_n = w_p ϕ'(|v_p|; α_p) v_p/|v_p|` at each node p of Γ_F
//! (`rsf::friction`, docs/math.md §1, §3), zero elsewhere. Energy (kinetic + elastic + load
//! potential):
//!
//!     E_n = ½ v_nᵀ M v_n + ½ u_nᵀ K u_n − Fᵀ u_n.
//!
//! The step equation of both integrators is `r_n := M a_n + K u_n − F + f_n = 0` on the free
//! dofs (docs/math.md §2: `A v_n − ℓ_n = M a_n + K u_n − F`); on the fixed dofs `r_n` is
//! the reaction of the constraint, which does work only where the Dirichlet data move
//! (the top edge).
//!
//! **Newmark** (`v_n − v_{n−1} = (τ/2)(a_n + a_{n−1})`, `Δu_n = (τ/2)(v_n + v_{n−1})`):
//! multiplying `½(r_n + r_{n−1})` by `Δu_n` gives the exact identity
//!
//!     E_n − E_{n−1} = W_n − D_n + ½(r_n + r_{n−1})|_free · Δu_n,
//!     W_n = ½(r_n + r_{n−1})|_fixed · Δu_n            (work of the Dirichlet data),
//!     D_n = ½(f_n + f_{n−1}) · Δu_n                    (frictional dissipation),
//!
//! and the last term vanishes for an exact step: Newmark **conserves** energy up to the
//! work of the data and the dissipation.
//!
//! **Backward Euler** (`Δu_n = τ v_n`, `a_n = (v_n − v_{n−1})/τ`): multiplying `r_n` by
//! `Δu_n` gives
//!
//!     E_n − E_{n−1} = W_n − D_n − N_n + r_n|_free · Δu_n,
//!     W_n = r_n|_fixed · Δu_n,   D_n = τ Σ_p w_p ϕ'(V_p) V_p,
//!     N_n = ½ Δv_nᵀ M Δv_n + ½ Δu_nᵀ K Δu_n ≥ 0      (numerical dissipation),
//!
//! hence the inequality `E_n − E_{n−1} ≤ W_n − D_n`: backward Euler **dissipates**.
//!
//! The tests evaluate every term from the stored `(u, v, a, α)` of consecutive steps of the
//! fast-loading slider (level 2, τ = 1e-3 s, 300 steps), which sticks, then slides in a
//! slip event up to ~6e-2 m/s, and assert:
//! - the residual on the free dofs is below 1e-7 of the largest force `|K u − F|`;
//! - the identity holds per step to 1e-7 of the largest term of the step, and summed over
//!   the run (`E_N − E_0` from the end states) to 1e-7 of `Σ W + Σ D`; for backward Euler
//!   also `E_n − E_{n−1} ≤ W_n − D_n`;
//! - `D_n ≥ 0` every step, `w_p ϕ'(V_p) V_p ≥ 0` at every node;
//! - friction matters: `Σ D ≥ ½ Σ W` (measured: 0.84), so a friction force wrong by 1e-6
//!   of itself already breaks the balance.
//!
//! Tolerances: measured defects are ~3e-12 (per step) and residuals ~4e-14 with today's
//! solvers. The fixed point stops at a velocity correction of 1e-10 in the energy norm,
//! i.e. nodal velocity errors ≲ 1e-11 m/s and force errors ≲ 1e-5 N against forces of
//! ~1e3 N: a residual ≲ 1e-8. The bounds (1e-7) leave that room and nothing more.

use crate::common::*;
use rsf::friction::DieterichRuina;
use rsf::time::Kinematics;
use rsf::{Integrator, Model, Observer, StepView};

/// Relative tolerance of the residual and of the balance (see the module docs).
const TOL: f64 = 1e-7;

/// Terms of the balance of one step (J per unit thickness).
#[derive(Debug, Clone, Copy, Default)]
struct Balance {
    /// `E_n − E_{n−1}`.
    de: f64,
    /// Work of the Dirichlet data `W_n`.
    work: f64,
    /// Frictional dissipation `D_n`.
    dissipation: f64,
    /// Numerical dissipation `N_n` (backward Euler; 0 for Newmark).
    numerical: f64,
    /// Largest magnitude of the step's individual energy changes and terms.
    scale: f64,
    /// `max |r_n|` on the free dofs relative to `max |K u_n − F|`.
    residual: f64,
    /// Smallest `w_p ϕ'(V_p) V_p` over Γ_F (W).
    min_power: f64,
}

impl Balance {
    /// `E_n − E_{n−1} − W_n + D_n + N_n` (zero for an exact step).
    fn defect(&self) -> f64 {
        self.de - self.work + self.dissipation + self.numerical
    }
}

/// Everything the balance needs from one stored state.
#[derive(Debug, Clone)]
struct Evaluated {
    u: Vec<f64>,
    v: Vec<f64>,
    /// Friction force from the law at the stored state.
    f: Vec<f64>,
    /// `r = M a + K u − F + f`.
    r: Vec<f64>,
    kinetic: f64,
    elastic: f64,
    /// `−Fᵀu`.
    load_potential: f64,
    /// `max |K u − F|` (force scale, N).
    force_scale: f64,
    min_power: f64,
}

impl Evaluated {
    fn new(model: &Model<2>, law: &DieterichRuina, k: &Kinematics, alpha: &[f64]) -> Self {
        let mass = model.mass.as_ref().expect("dynamic integrator");
        let fb = &model.frictional_boundary;
        let n = k.u.len();
        let mut f = vec![0.0; n];
        let mut min_power = f64::INFINITY;
        for (i, &p) in fb.nodes.iter().enumerate() {
            let speed = k.v[2 * p].hypot(k.v[2 * p + 1]);
            let stress = friction_stress(law, alpha[i], speed);
            min_power = min_power.min(fb.weights[i] * stress * speed);
            if speed > 0.0 {
                for c in 0..2 {
                    f[2 * p + c] = fb.weights[i] * stress * k.v[2 * p + c] / speed;
                }
            }
        }
        let ku = apply(&model.stiffness, &k.u);
        let mut r = apply(mass, &k.a);
        let mut force_scale = 0.0f64;
        for i in 0..n {
            force_scale = force_scale.max((ku[i] - model.load[i]).abs());
            r[i] += ku[i] - model.load[i] + f[i];
        }
        Self {
            kinetic: 0.5 * dot(&k.v, &apply(mass, &k.v)),
            elastic: 0.5 * dot(&k.u, &ku),
            load_potential: -dot(&model.load, &k.u),
            u: k.u.clone(),
            v: k.v.clone(),
            f,
            r,
            force_scale,
            min_power,
        }
    }

    fn energy(&self) -> f64 {
        self.kinetic + self.elastic + self.load_potential
    }
}

/// Evaluates the balance of every step against the previous one.
struct EnergyObserver {
    law: DieterichRuina,
    newmark: bool,
    prev: Evaluated,
    steps: Vec<Balance>,
}

impl EnergyObserver {
    fn balance(&self, model: &Model<2>, now: &Evaluated) -> Balance {
        let prev = &self.prev;
        let n = now.u.len();
        let du: Vec<f64> = (0..n).map(|i| now.u[i] - prev.u[i]).collect();
        let (mut work, mut dissipation, mut numerical) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let (r, f) = if self.newmark {
                (0.5 * (now.r[i] + prev.r[i]), 0.5 * (now.f[i] + prev.f[i]))
            } else {
                (now.r[i], now.f[i])
            };
            if model.fixed[i] {
                work += r * du[i];
            }
            dissipation += f * du[i];
        }
        if !self.newmark {
            let dv: Vec<f64> = (0..n).map(|i| now.v[i] - prev.v[i]).collect();
            let mass = model.mass.as_ref().expect("dynamic integrator");
            numerical =
                0.5 * dot(&dv, &apply(mass, &dv)) + 0.5 * dot(&du, &apply(&model.stiffness, &du));
        }
        let scale = [
            now.kinetic - prev.kinetic,
            now.elastic - prev.elastic,
            now.load_potential - prev.load_potential,
            work,
            dissipation,
            numerical,
        ]
        .iter()
        .fold(0.0f64, |acc, x| acc.max(x.abs()));
        let residual = (0..n)
            .filter(|&i| !model.fixed[i])
            .map(|i| now.r[i].abs())
            .fold(0.0f64, f64::max)
            / now.force_scale;
        Balance {
            de: now.energy() - prev.energy(),
            work,
            dissipation,
            numerical,
            scale,
            residual,
            min_power: now.min_power,
        }
    }
}

impl Observer<2> for EnergyObserver {
    fn observe(&mut self, s: &StepView<'_, 2>) -> rsf::Result<rsf::Flow> {
        let now = Evaluated::new(s.model, &self.law, &s.state.kinematics, &s.state.alpha);
        let b = self.balance(s.model, &now);
        self.steps.push(b);
        self.prev = now;
        Ok(rsf::Flow::Continue(()))
    }
}

/// Runs the fast-loading slider with `integrator`; returns each step's balance and
/// `E_N − E_0` from the end states.
fn run_balance(integrator: Integrator) -> (Vec<Balance>, f64) {
    let scene = with_integrator(fast_loading(2e-2, 300), integrator);
    let law = friction_law(&scene);
    let mut sim = build(&scene);
    let start = Evaluated::new(sim.model(), &law, sim.kinematics(), sim.alpha());
    let e0 = start.energy();
    let mut obs = EnergyObserver {
        law,
        newmark: integrator == Integrator::Newmark,
        prev: start,
        steps: Vec::new(),
    };
    run_until(&mut sim, 0.3, &mut [&mut obs]);
    assert_eq!(obs.steps.len(), 300);
    (obs.steps, obs.prev.energy() - e0)
}

/// The assertions common to both integrators (module docs); returns `(Σ W, Σ D, Σ N)`.
fn check_balance(name: &str, steps: &[Balance], total_de: f64) -> (f64, f64, f64) {
    for (n, b) in steps.iter().enumerate() {
        let n = n + 1;
        assert!(
            b.residual <= TOL,
            "{name}, step {n}: free-dof residual {:.2e} of the force scale",
            b.residual
        );
        assert!(
            b.defect().abs() <= TOL * b.scale,
            "{name}, step {n}: balance defect {:.3e} J with terms up to {:.3e} J ({b:?})",
            b.defect(),
            b.scale
        );
        assert!(
            b.dissipation >= 0.0,
            "{name}, step {n}: D_n = {:e}",
            b.dissipation
        );
        assert!(
            b.min_power >= 0.0,
            "{name}, step {n}: w ϕ'(V) V = {:e}",
            b.min_power
        );
    }
    let sum = |g: fn(&Balance) -> f64| steps.iter().map(g).sum::<f64>();
    let (work, dissipation, numerical) = (
        sum(|b| b.work),
        sum(|b| b.dissipation),
        sum(|b| b.numerical),
    );
    let defect = total_de - work + dissipation + numerical;
    eprintln!(
        "{name}: E_N − E_0 = {total_de:.6e} J, ΣW = {work:.6e}, ΣD = {dissipation:.6e}, \
         ΣN = {numerical:.6e}, summed defect {defect:.2e}; worst step defect {:.2e}, \
         worst residual {:.2e}",
        steps
            .iter()
            .map(|b| b.defect().abs() / b.scale)
            .fold(0.0, f64::max),
        steps.iter().map(|b| b.residual).fold(0.0, f64::max)
    );
    assert!(
        defect.abs() <= TOL * (work.abs() + dissipation),
        "{name}: summed balance defect {defect:.3e} J (ΣW = {work:.3e}, ΣD = {dissipation:.3e})"
    );
    assert!(
        dissipation >= 0.5 * work,
        "{name}: friction dissipated only {dissipation:.3e} J of the {work:.3e} J of work: \
         the run did not slide as the slip event should"
    );
    (work, dissipation, numerical)
}

/// Newmark conserves: `E_n − E_{n−1} = W_n − D_n` per step and summed.
#[test]
fn newmark_energy_balance_with_friction() {
    let (steps, total) = run_balance(Integrator::Newmark);
    let (.., numerical) = check_balance("Newmark", &steps, total);
    assert_eq!(numerical, 0.0);
}

/// Backward Euler dissipates: `E_n − E_{n−1} = W_n − D_n − N_n` with `N_n ≥ 0`, so
/// `E_n − E_{n−1} ≤ W_n − D_n`.
#[test]
fn backward_euler_energy_inequality_with_friction() {
    let (steps, total) = run_balance(Integrator::BackwardEuler);
    let (work, _, numerical) = check_balance("backward Euler", &steps, total);
    for (n, b) in steps.iter().enumerate() {
        assert!(
            b.numerical >= 0.0,
            "step {}: N_n = {:e}",
            n + 1,
            b.numerical
        );
        assert!(
            b.de <= b.work - b.dissipation + TOL * b.scale,
            "step {}: energy grew beyond the work of the data: {b:?}",
            n + 1
        );
    }
    // The numerical dissipation is real but small against the work at this τ.
    assert!(
        numerical > 0.0 && numerical < 0.1 * work,
        "ΣN = {numerical:e}, ΣW = {work:e}"
    );
}
