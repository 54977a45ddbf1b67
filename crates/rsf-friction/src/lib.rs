//! Convex friction potentials ϕ(V; α) for rate-and-state friction.
//!
//! This crate implements the friction side of the variational formulation of
//! Pipping, Sander & Kornhuber, *Variational formulation of rate- and state-dependent
//! friction problems* (equation numbers below are the paper's). On the frictional
//! boundary the tangential stress satisfies (2.3) `−σ_t ∈ ∂_v φ(v, α)` with
//! `φ(v, α) = ϕ(|v|, α)` and `ϕ(·, α)` convex and nondecreasing on `[0, ∞)`.
//!
//! * [`ConvexPotential`] — a scalar potential `ϕ(V)` at a fixed state: value, slope,
//!   curvature and the **exact local minimiser** of `½ A s² − r s + w ϕ(s)` (the block solve
//!   of a nonlinear Gauss–Seidel sweep), plus the `D`-vector version
//!   [`ConvexPotential::minimize_vector`].
//! * [`FrictionLaw`] — maps a node's state `α` to its potential.
//! * Laws: [`Tresca`] (2.8), [`StateDependentTresca`] (μ = μ(α)), [`DieterichRuina`]
//!   with the `V_m` cutoff (2.12)–(2.13), and the regularised [`AsinhLaw`] used by SEAS
//!   benchmark codes.
//!
//! # Units (SI, per unit area — per unit length × thickness in 2-D)
//! slip rate `V` in m/s, stresses in Pa, `ϕ` in Pa·m/s, `ϕ''` in Pa·s/m, state
//! `α = ln θ` with `θ` in s, `L` in m, `V0` in m/s, `a`, `b`, `μ0` dimensionless.
//!
//! # Stiffness and log space
//! The cutoff velocity `V_m(α) = V0·exp(−(μ0 + b(α + ln(V0/L)))/a)` (2.13) is routinely
//! below `1e-24` m/s and for large `α` below the smallest `f64` (`ln V_m ≈ −1e4`). The
//! rate-state potentials therefore store `ln V_m` and evaluate everything in log space;
//! `V_m` itself is never needed. All functions return finite numbers for finite,
//! admissible inputs (documented per method).
//!
//! # Example
//! ```
//! use rsf_friction::{ConvexPotential, DieterichRuina, FrictionLaw, RateStateParams};
//!
//! // Paper §6.1 parameters (Table 6.1).
//! let law = DieterichRuina::new(RateStateParams {
//!     mu0: 0.6, a: 0.010, b: 0.015, v0: 1e-6, l: 1e-5, sigma_n: 49_050.0,
//! })?;
//! let alpha = -10.0; // ln θ, θ in s
//! let phi = law.potential(alpha);
//! // Friction stress at 1 μm/s equals σ̄_n μ(V, θ):
//! let v = 1e-6;
//! assert!((phi.slope(v) - 49_050.0 * law.friction_coefficient(v, alpha)).abs() < 1e-9);
//! // Exact local solve: argmin_{s ≥ 0} ½ a s² − r s + w ϕ(s).
//! let s = phi.minimize(1e9, 5e4, 0.1);
//! let residual = 1e9 * s - 5e4 + 0.1 * phi.slope(s);
//! assert!(residual.abs() < 1e-10 * 5e4);
//! # Ok::<(), rsf_friction::Error>(())
//! ```
#![warn(missing_docs)]
// `!(x > 0.0)` is used deliberately: it is also true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod asinh;
mod potentials;

pub use asinh::{AsinhLaw, AsinhPotential};
pub use potentials::{
    DieterichRuina, DieterichRuinaPotential, RateStateParams, SlipScaled, StateDependentTresca,
    Tresca, TrescaPotential,
};
pub use rsf_numeric::{wright_omega_ln, StateVariable};

/// Errors of this crate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A law parameter is outside its admissible range (e.g. `a ≤ 0`, non-finite `L`).
    #[error("invalid friction parameter {name} = {}: {requirement}", short(*.value))]
    InvalidParameter {
        /// Name of the parameter (`"a"`, `"sigma_n"`, …).
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// What the parameter must satisfy.
        requirement: &'static str,
    },
}

/// A value as a message shows it: as Rust writes it, or in exponent form when that is long
/// (a 1e300 as `1e300`, not 301 digits).
fn short(value: f64) -> String {
    let plain = value.to_string();
    if plain.len() > 20 {
        format!("{value:e}")
    } else {
        plain
    }
}

/// `Result` with this crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

/// A convex, nondecreasing scalar potential `ϕ: [0, ∞) → [0, ∞)` with `ϕ(0) = 0`,
/// per unit area, at a fixed state (paper (2.3), (2.8), (2.13)).
///
/// The vector potential is `φ(v) = ϕ(|v|)` (2.14); its subdifferential at `v = 0` is the
/// closed ball of radius [`slope(0)`](ConvexPotential::slope) = `ϕ'(0+)`.
///
/// All methods expect finite arguments `v ≥ 0`; for `v < 0` they behave as at `v = 0`.
/// They never panic and return finite values for finite admissible inputs.
pub trait ConvexPotential: Clone + Send + Sync {
    /// `ϕ(V)` in Pa·m/s.
    fn value(&self, v: f64) -> f64;

    /// `ϕ'(V)` in Pa (the friction stress magnitude). At `V = 0` the right derivative
    /// `ϕ'(0+)`, i.e. the radius of `∂(ϕ∘|·|)(0)` (the stick threshold).
    fn slope(&self, v: f64) -> f64;

    /// `ϕ''(V)` in Pa·s/m, or `None` where `ϕ` is not twice differentiable
    /// (Tresca at `V = 0`, Dieterich–Ruina exactly at `V = V_m`). Always `≥ 0`.
    fn curvature(&self, v: f64) -> Option<f64>;

    /// `(ϕ'(V), ϕ''(V))` at once (as [`slope`](Self::slope) and
    /// [`curvature`](Self::curvature)); potentials override it when both share work (one
    /// logarithm instead of two for Dieterich–Ruina).
    fn slope_and_curvature(&self, v: f64) -> (f64, Option<f64>) {
        (self.slope(v), self.curvature(v))
    }

    /// Exact minimiser `argmin_{s ≥ 0} ½ a s² − r s + w ϕ(s)`, i.e. the unique
    /// `s ≥ 0` with `0 ∈ a s − r + w ∂ϕ(s)`.
    ///
    /// Expects finite `a > 0` (Pa·s/m, a diagonal entry of `A`), `r ≥ 0` (Pa) and
    /// `w ≥ 0` (the lumped weight, dimensionless or m). For `r ≤ 0` returns 0; for a NaN
    /// `r` returns NaN — never the "stuck" answer 0 for a traction that is not a number,
    /// so that the NaN reaches the caller's checks (a time step's error test or a
    /// solver's non-finite iterate rejects it; docs/reliability.md, "NaN is never
    /// stuck"). Implementations keep this (the built-in potentials do; one comparison on
    /// the branch that returns 0).
    /// The optimality residual is below `1e-10` relative to the magnitude of its terms
    /// (see the crate tests).
    fn minimize(&self, a: f64, r: f64, w: f64) -> f64;

    /// Radius of the subdifferential of `v ↦ ϕ(|v|)` at `v = 0` (Pa): the stick threshold
    /// `ϕ'(0+)`. Equals [`slope(0.0)`](ConvexPotential::slope).
    fn stick_threshold(&self) -> f64 {
        self.slope(0.0)
    }

    /// Exact minimiser of `½ a |v|² − r·v + w ϕ(|v|)` over `v ∈ R^D`.
    ///
    /// The minimiser is collinear with `r`: `v = s r/|r|` with
    /// `s = `[`minimize`](ConvexPotential::minimize)`(a, |r|, w)`. Returns `0` for `r = 0`
    /// and NaN in every component for an `r` with a non-finite component (a NaN or
    /// infinite traction is an error of the caller's state, not stick; docs/reliability.md).
    /// `|r|` is computed overflow-safely.
    fn minimize_vector<const D: usize>(&self, a: f64, r: [f64; D], w: f64) -> [f64; D] {
        let norm = norm(&r);
        if !norm.is_finite() {
            return [f64::NAN; D];
        }
        if norm == 0.0 {
            return [0.0; D];
        }
        let s = self.minimize(a, norm, w);
        let mut out = [0.0; D];
        for i in 0..D {
            out[i] = s * (r[i] / norm);
        }
        out
    }

    /// Slice version of [`minimize_vector`](ConvexPotential::minimize_vector): writes the
    /// minimiser into `out` — NaN in every component for an `r` with a non-finite
    /// component. Allocates nothing (the fault ODE calls it per node and evaluation).
    ///
    /// # Panics
    /// If `r.len() != out.len()`.
    fn minimize_block(&self, a: f64, r: &[f64], w: f64, out: &mut [f64]) {
        assert_eq!(r.len(), out.len(), "minimize_block: length mismatch");
        let norm = norm(r);
        if !norm.is_finite() {
            out.fill(f64::NAN);
            return;
        }
        if norm == 0.0 {
            out.fill(0.0);
            return;
        }
        let s = self.minimize(a, norm, w);
        for (o, ri) in out.iter_mut().zip(r) {
            *o = s * (ri / norm);
        }
    }
}

/// Overflow-safe Euclidean norm.
fn norm(r: &[f64]) -> f64 {
    r.iter().fold(0.0_f64, |acc, &x| acc.hypot(x))
}

/// A friction law: evaluated at a node's state `α` it gives the potential of the slip rate.
///
/// Heterogeneous faults use one law value per frictional node (`Vec<L>`).
pub trait FrictionLaw: Clone + Send + Sync {
    /// The potential at fixed state.
    type Potential: ConvexPotential;

    /// `ϕ(·, α)`; `alpha = ln θ` (θ in s) for the rate-state laws. For non-finite `alpha`
    /// the result is the limit potential (documented per law); never panics.
    fn potential(&self, alpha: f64) -> Self::Potential;

    /// `false` if the potential does not depend on `α` (plain Tresca): no state law needed.
    fn uses_state(&self) -> bool;

    /// Friction coefficient `μ(V, α) = ϕ'(V, α)/σ̄_n` (dimensionless), e.g. (2.12).
    fn friction_coefficient(&self, v: f64, alpha: f64) -> f64;

    /// What the state `α` passed to [`potential`](FrictionLaw::potential) means:
    /// [`StateVariable::LogTheta`] (`α = ln θ`, θ in s) for the rate-and-state laws, the
    /// default. A simulation refuses a state law whose
    /// state law (the `rsf-state` crate's `StateLaw::state_variable`) differs (e.g. the
    /// discontinuous law, `α = θ`, with Dieterich–Ruina friction would give μ ≈ 150).
    /// Irrelevant when [`uses_state`](FrictionLaw::uses_state) is `false`.
    fn state_variable(&self) -> StateVariable {
        StateVariable::LogTheta
    }

    /// The normal stress `σ̄_n` (Pa) the law was given, if it has one: what observers
    /// report as the fault's normal traction (the model prescribes it; bilateral contact
    /// keeps the normal velocity zero). Default `None` (a user law without one).
    fn normal_stress(&self) -> Option<f64> {
        None
    }

    /// Whether the potential is `σ̄_n` ([`normal_stress`](FrictionLaw::normal_stress))
    /// times a function of `(V, α)`, as for every law of the form `τ = σ̄_n μ(V, α)`: then a
    /// normal stress `σ` that changes with slip (a fault inside the body) scales it by
    /// `σ/σ̄_n`. Default `false` (a user law says so if it is).
    fn proportional_to_normal_stress(&self) -> bool {
        false
    }

    /// The potential at state `alpha` with the normal stress `sigma_n` (Pa) in place of
    /// the law's own: a normal stress that changes in time (pore pressure, `σ̄_n − p`).
    /// A law proportional to its normal stress returns the potential with the bits of the
    /// same law built with `sigma_n` (the built-in laws do), so that a constant pressure
    /// `p₀` gives the run of the laws with `σ̄_n − p₀` bit for bit. Default `None`: the
    /// caller scales the potential by `sigma_n/σ̄_n` instead (a law that is
    /// [`proportional_to_normal_stress`](FrictionLaw::proportional_to_normal_stress)) or
    /// refuses a changing normal stress.
    fn potential_at_normal_stress(&self, alpha: f64, sigma_n: f64) -> Option<Self::Potential> {
        let _ = (alpha, sigma_n);
        None
    }
}
