//! The [`StateLaw`] trait and the generic algorithms behind its default methods.

use crate::error::Result;
use crate::generic::{backward_euler, LawAtRate};
use crate::probe::first_decrease;
use rsf_numeric::StateVariable;

/// A state law `−α̇ ∈ ∂_α ψ(α, V)` (2.4) with `ψ(·, V)` convex.
///
/// Only [`dpsi_dalpha`](StateLaw::dpsi_dalpha) is required; it must be nondecreasing in
/// `α` (this is the convexity of `ψ`) and may be discontinuous (return any element of the
/// subdifferential at a kink).
///
/// # What a law can see
/// A law sees only its node's state `α` and slip rate `V` (and the constants it holds):
/// **not the tractions**, neither the shear traction `τ` nor the normal traction `σ_n`,
/// nor their rates. Laws whose evolution depends on them cannot be written through this
/// trait today:
/// * Nagata et al. (2012) add `−(c/b) θ τ̇/σ_n` to the aging law: the shear-traction
///   rate is not available (it is not a function of `(α, V)` at one time).
/// * Linker & Dieterich (1992) add `−(α_LD θ / (b σ_n)) σ̇_n`: in this workspace's models
///   `σ_n` is prescribed per node and constant in time (bilateral contact, `σ̄_n` of the
///   friction law), so the term is identically zero and the aging or slip law *is* the
///   Linker–Dieterich law of such a model.
///
/// What a user can do instead: a law that depends on the *level* of the normal stress
/// (or any other per-node constant) holds it as a field, one instance per frictional node
/// (e.g. `SimulationBuilder::state_law_at` in the `rsf` crate, built from the node's
/// position and the `σ̄_n` given to its friction law); the tractions a run produces can be
/// observed (`StepView::shear_traction` / `normal_traction` in `rsf`) but not fed back
/// into the state law.
pub trait StateLaw: Clone + Send + Sync {
    /// `∂ψ/∂α(α, V)` in 1/s, nondecreasing in `α`; `V ≥ 0` in m/s.
    fn dpsi_dalpha(&self, alpha: f64, v: f64) -> f64;

    /// `∂²ψ/∂α²(α, V)` (1/s) if known; used by the Newton steps of [`generic_update`]
    /// (a finite difference is used otherwise).
    fn d2psi_dalpha2(&self, _alpha: f64, _v: f64) -> Option<f64> {
        None
    }

    /// `ψ(α, V)` (1/s) if known (informational; the update does not need it).
    fn psi(&self, _alpha: f64, _v: f64) -> Option<f64> {
        None
    }

    /// Whether `α` is `ln θ` or `θ`. Default [`StateVariable::LogTheta`].
    fn state_variable(&self) -> StateVariable {
        StateVariable::LogTheta
    }

    /// The steady state at constant `V` (where `∂ψ/∂α = 0`), if it exists.
    fn steady_state(&self, _v: f64) -> Option<f64> {
        None
    }

    /// Checks that [`dpsi_dalpha`](StateLaw::dpsi_dalpha) is nondecreasing in `α`, as the
    /// update needs. A simulation calls it once per frictional node at construction. The
    /// default probes a documented grid ([`probe_monotonicity`]); the built-in laws, monotone
    /// by construction, return `Ok(())` at once.
    ///
    /// # Errors
    /// [`Error::NotMonotone`](crate::Error::NotMonotone) or [`Error::NanDerivative`](crate::Error::NanDerivative) (see [`probe_monotonicity`]).
    fn check_monotone(&self) -> Result<()> {
        probe_monotonicity(self)
    }

    /// Backward Euler step (3.5): `α_n = prox_{τψ(·, V)}(α_prev)`, the solution `β` of
    /// `β − α_prev + τ ∂ψ/∂α(β, V) ∋ 0`.
    ///
    /// `alpha_prev` finite, `v ≥ 0` finite (m/s), `tau ≥ 0` finite (s). The default is
    /// [`generic_update`] (safeguarded Newton/bisection to machine precision `4ε·max(1, |β|)`,
    /// i.e. below the paper's absolute `1e-12` whenever `|β| < 1000`).
    ///
    /// # Errors
    /// [`Error::InvalidInput`](crate::Error::InvalidInput) for inadmissible arguments; the errors of
    /// [`generic_update`]; [`Error::NonFinite`](crate::Error::NonFinite) if the result would not be finite.
    /// Never panics.
    fn update(&self, alpha_prev: f64, v: f64, tau: f64) -> Result<f64> {
        generic_update(self, alpha_prev, v, tau)
    }

    /// The exact solution at `t + τ` of `α̇ = −∂ψ/∂α(α, V)` from `alpha_prev` at `t`, the
    /// slip rate held at `v` over the step, if the law has one in closed form (the `rsf`
    /// crate's `StateIntegrator::ConstantSlipRate`; docs/friction-state.md). `None` (the
    /// default) if it does not; a law that has it returns `Some` for every input.
    ///
    /// Arguments as for [`update`](StateLaw::update). The built-in laws: [`Aging`](crate::Aging)
    /// (`θ̇ = 1 − Vθ/L` is linear in `θ`), [`Slip`](crate::Slip) (linear in `α`) and [`Discontinuous`](crate::Discontinuous)
    /// (its backward Euler step is already exact at constant `V`).
    ///
    /// # Errors
    /// As [`update`](StateLaw::update) (wrapped in `Some`). Never panics.
    fn constant_rate_update(&self, _alpha_prev: f64, _v: f64, _tau: f64) -> Option<Result<f64>> {
        None
    }
}

/// Backward Euler step for any [`StateLaw`]: the root `β` of the strictly increasing
/// `F(β) = β − α_prev + τ ∂ψ/∂α(β, V)` (paper (3.5); docs/math.md §2).
///
/// **Bracketing.** With `g = ∂ψ/∂α(·, V)` nondecreasing and `g₀ = g(α_prev)`, the root
/// lies between `α_prev` and `α_prev − τ g₀` (one evaluation, no search). If `τ g₀`
/// overflows, a doubling search from `α_prev` finds a sign change (up to `|β| ≤ 1e300`).
///
/// **Iteration.** Newton steps on `F` (derivative `1 + τ ∂²ψ/∂α²` from
/// [`StateLaw::d2psi_dalpha2`] or a forward difference), replaced by bisection whenever
/// a step leaves the bracket or does not halve the previous step. It stops when the step
/// or the bracket is below `4ε·max(1, |β|)`, i.e. at machine precision, which is below the
/// paper's absolute `1e-12` for `|β| < 1000`; for larger `|β|` the absolute tolerance
/// `1e-12` is not representable and the relative one is used. Discontinuous `∂ψ/∂α` (a
/// subdifferential with a jump) converge by bisection onto the jump.
///
/// # Errors
/// [`Error::InvalidInput`](crate::Error::InvalidInput) for inadmissible inputs, [`Error::NanDerivative`](crate::Error::NanDerivative) if
/// `dpsi_dalpha` returns NaN, [`Error::NoBracket`](crate::Error::NoBracket) if no sign change exists in
/// `|β| ≤ 1e300` (non-monotone law), [`Error::NotConverged`](crate::Error::NotConverged) after 2500 iterations,
/// [`Error::NonFinite`](crate::Error::NonFinite) for a non-finite result. Never panics.
pub fn generic_update<S: StateLaw>(law: &S, alpha_prev: f64, v: f64, tau: f64) -> Result<f64> {
    let at_rate = LawAtRate {
        dpsi: |beta| law.dpsi_dalpha(beta, v),
        d2psi: |beta| law.d2psi_dalpha2(beta, v),
        v,
    };
    backward_euler(&at_rate, alpha_prev, tau)
}

/// Checks on a grid that `∂ψ/∂α(·, V)` is nondecreasing, i.e. that `ψ(·, V)` is convex
/// and the backward Euler update `β − α_prev + τ ∂ψ/∂α(β, V) = 0` has a single root.
///
/// **Grid.** `α` at the [`PROBE_ALPHA_POINTS`](crate::PROBE_ALPHA_POINTS) = 161 equally spaced points of
/// [[`PROBE_ALPHA_MIN`](crate::PROBE_ALPHA_MIN), [`PROBE_ALPHA_MAX`](crate::PROBE_ALPHA_MAX)] = [−40, 40] (spacing 0.5; for `α = ln θ` this
/// is θ from 4e-18 s to 2e17 s), for each slip rate of [`PROBE_SLIP_RATES`](crate::PROBE_SLIP_RATES) (0 and
/// 1e-15 … 1e3 m/s): 3220 evaluations. Neighbouring values may decrease by round-off
/// (1e-12 of their magnitude). A probe can only find violations on its grid: a law that
/// is non-monotone on a finer scale than 0.5 or outside the grid passes (the generic
/// update then still fails with [`Error::NoBracket`](crate::Error::NoBracket) when it cannot bracket a root, but
/// may return one of several roots).
///
/// # Errors
/// [`Error::NotMonotone`](crate::Error::NotMonotone) with the first decreasing pair found; [`Error::NanDerivative`](crate::Error::NanDerivative)
/// if the law returns NaN on the grid. Never panics.
pub fn probe_monotonicity<S: StateLaw>(law: &S) -> Result<()> {
    first_decrease(|alpha, v| law.dpsi_dalpha(alpha, v))
}
