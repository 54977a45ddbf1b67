//! The friction laws and their potentials.

use crate::{ConvexPotential, Error, FrictionLaw, Result};
use rsf_numeric::{solve_increasing, wright_omega_ln, StateVariable};

pub(crate) const LN_2: f64 = std::f64::consts::LN_2;

fn check(name: &'static str, value: f64, ok: bool, requirement: &'static str) -> Result<()> {
    if ok {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            requirement,
        })
    }
}

/// [`check`] that `value` is finite and `> 0`.
fn check_positive(name: &'static str, value: f64) -> Result<()> {
    check(
        name,
        value,
        value.is_finite() && value > 0.0,
        "finite and > 0",
    )
}

/// Saturates `+∞` to `f64::MAX` (keeps results finite).
pub(crate) fn sat(x: f64) -> f64 {
    x.min(f64::MAX)
}

/// `r/a` for the unconstrained quadratic, saturated to stay finite.
pub(crate) fn linear_solution(a: f64, r: f64) -> f64 {
    sat(r / a)
}

// ---------------------------------------------------------------------------------------
// Tresca
// ---------------------------------------------------------------------------------------

/// Tresca potential `ϕ(V) = μ σ̄_n V` (2.8): a threshold `μ σ̄_n` (Pa).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrescaPotential {
    threshold: f64,
}

impl TrescaPotential {
    /// Potential with stick threshold `μ σ̄_n` in Pa. Negative or NaN thresholds are
    /// replaced by 0 and `+∞` by `f64::MAX`, so the potential stays finite.
    pub fn new(threshold: f64) -> Self {
        let t = if threshold >= 0.0 {
            sat(threshold)
        } else {
            0.0
        };
        Self { threshold: t }
    }

    /// The threshold `μ σ̄_n` (Pa).
    pub fn threshold(&self) -> f64 {
        self.threshold
    }
}

impl ConvexPotential for TrescaPotential {
    fn value(&self, v: f64) -> f64 {
        sat(self.threshold * v.max(0.0))
    }
    fn slope(&self, _v: f64) -> f64 {
        self.threshold
    }
    fn curvature(&self, v: f64) -> Option<f64> {
        (v > 0.0).then_some(0.0)
    }
    /// Closed form `s = max(0, r − w μ σ̄_n)/a` (shrinkage); NaN for a NaN `r`.
    fn minimize(&self, a: f64, r: f64, w: f64) -> f64 {
        let excess = r - w * self.threshold;
        if excess > 0.0 {
            linear_solution(a, excess)
        } else if r.is_nan() {
            r
        } else {
            0.0
        }
    }
}

/// Tresca friction (2.8) with a constant coefficient: `ϕ(V) = μ σ̄_n V`, independent of `α`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tresca {
    mu: f64,
    sigma_n: f64,
}

impl Tresca {
    /// `mu ≥ 0` (dimensionless) and `sigma_n > 0` (Pa), both finite.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] otherwise.
    pub fn new(mu: f64, sigma_n: f64) -> Result<Self> {
        check("mu", mu, mu.is_finite() && mu >= 0.0, "finite and >= 0")?;
        check_positive("sigma_n", sigma_n)?;
        Ok(Self { mu, sigma_n })
    }
    /// Friction coefficient μ.
    pub fn mu(&self) -> f64 {
        self.mu
    }
    /// Normal stress σ̄_n (Pa).
    pub fn sigma_n(&self) -> f64 {
        self.sigma_n
    }
}

impl FrictionLaw for Tresca {
    type Potential = TrescaPotential;
    fn potential(&self, _alpha: f64) -> TrescaPotential {
        TrescaPotential::new(self.mu * self.sigma_n)
    }
    /// The threshold `μ σ` (a time-dependent bound: `σ = σ̄_n − p(t)`).
    fn potential_at_normal_stress(&self, _alpha: f64, sigma_n: f64) -> Option<TrescaPotential> {
        Some(TrescaPotential::new(self.mu * sigma_n))
    }
    fn uses_state(&self) -> bool {
        false
    }
    fn friction_coefficient(&self, _v: f64, _alpha: f64) -> f64 {
        self.mu
    }
    fn normal_stress(&self) -> Option<f64> {
        Some(self.sigma_n)
    }
    fn proportional_to_normal_stress(&self) -> bool {
        true
    }
}

/// Tresca friction with a state-dependent coefficient `μ(α)` (docs/math.md §1):
/// `ϕ(V, α) = μ(α) σ̄_n V`.
///
/// `μ(α)` is any user function; values that are negative or NaN are treated as 0 and
/// `+∞` as `f64::MAX/σ̄_n` (see [`TrescaPotential::new`]).
///
/// ```
/// use rsf_friction::{ConvexPotential, FrictionLaw, StateDependentTresca};
/// // μ(α) = μ0 + b ln(V0 θ / L) with θ = e^α, clamped at 0.
/// let (mu0, b, v0, l) = (0.6_f64, 0.015_f64, 1e-6_f64, 1e-5_f64);
/// let law = StateDependentTresca::new(move |alpha: f64| mu0 + b * (alpha + (v0 / l).ln()), 1e5)?;
/// assert!(law.uses_state());
/// let t = law.potential(0.0).stick_threshold();
/// assert!((t - 1e5 * (0.6 + 0.015 * (0.1f64).ln())).abs() < 1e-9);
/// # Ok::<(), rsf_friction::Error>(())
/// ```
#[derive(Clone)]
pub struct StateDependentTresca<F> {
    mu: F,
    sigma_n: f64,
    state_variable: StateVariable,
}

impl<F: Fn(f64) -> f64 + Clone + Send + Sync> StateDependentTresca<F> {
    /// `sigma_n > 0` finite (Pa).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an invalid `sigma_n`.
    pub fn new(mu: F, sigma_n: f64) -> Result<Self> {
        check_positive("sigma_n", sigma_n)?;
        Ok(Self {
            mu,
            sigma_n,
            state_variable: StateVariable::LogTheta,
        })
    }
    /// Declares what `α` means for `μ(α)` (default [`StateVariable::LogTheta`]), for the
    /// consistency check against the state law ([`FrictionLaw::state_variable`]).
    pub fn with_state_variable(mut self, state_variable: StateVariable) -> Self {
        self.state_variable = state_variable;
        self
    }
    fn mu_at(&self, alpha: f64) -> f64 {
        let m = (self.mu)(alpha);
        if m >= 0.0 {
            m
        } else {
            0.0
        }
    }
}

impl<F: Fn(f64) -> f64 + Clone + Send + Sync> FrictionLaw for StateDependentTresca<F> {
    type Potential = TrescaPotential;
    fn potential(&self, alpha: f64) -> TrescaPotential {
        TrescaPotential::new(self.mu_at(alpha) * self.sigma_n)
    }
    fn potential_at_normal_stress(&self, alpha: f64, sigma_n: f64) -> Option<TrescaPotential> {
        Some(TrescaPotential::new(self.mu_at(alpha) * sigma_n))
    }
    fn uses_state(&self) -> bool {
        true
    }
    fn friction_coefficient(&self, _v: f64, alpha: f64) -> f64 {
        sat(self.mu_at(alpha))
    }
    fn state_variable(&self) -> StateVariable {
        self.state_variable
    }
    fn normal_stress(&self) -> Option<f64> {
        Some(self.sigma_n)
    }
    fn proportional_to_normal_stress(&self) -> bool {
        true
    }
}

// ---------------------------------------------------------------------------------------
// Rate-and-state parameters
// ---------------------------------------------------------------------------------------

/// Parameters of the rate-and-state laws (2.9), (2.12)–(2.13); may differ per node.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RateStateParams {
    /// Reference friction coefficient μ0 (dimensionless, finite).
    pub mu0: f64,
    /// Direct-effect parameter `a > 0` (dimensionless).
    pub a: f64,
    /// Evolution-effect parameter `b` (dimensionless, any finite value; `b > a` is velocity
    /// weakening; existence of the coupled fixed point is proved for `b/a < 2`, Thm 5.14).
    pub b: f64,
    /// Reference slip rate `V0 > 0` (m/s).
    pub v0: f64,
    /// Characteristic slip distance `L > 0` (m).
    pub l: f64,
    /// Prescribed normal stress `σ̄_n > 0` (Pa).
    pub sigma_n: f64,
}

impl RateStateParams {
    /// Checks `a, L, V0, σ̄_n > 0` and that all parameters are finite.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first offending parameter.
    pub fn validate(&self) -> Result<()> {
        check("mu0", self.mu0, self.mu0.is_finite(), "finite")?;
        check_positive("a", self.a)?;
        check("b", self.b, self.b.is_finite(), "finite")?;
        check_positive("v0", self.v0)?;
        check_positive("l", self.l)?;
        check_positive("sigma_n", self.sigma_n)
    }

    /// `ln V_m(α) = ln V0 − (μ0 + b(α + ln(V0/L)))/a` (2.13), computed without forming
    /// `V_m` (which underflows for large `α`). For `|α| → ∞` the result may be `±∞`.
    pub fn ln_cutoff_velocity(&self, alpha: f64) -> f64 {
        ParamLogs::of(self).ln_cutoff_velocity(self, alpha)
    }

    /// Steady-state friction coefficient `μ_ss(V) = μ0 + (a − b) ln(V/V0)`, reached at
    /// `θ = L/V` by the aging and slip laws.
    pub fn steady_state_friction(&self, v: f64) -> f64 {
        self.mu0 + (self.a - self.b) * (v.ln() - self.v0.ln())
    }

    /// `κ = a σ̄_n` (Pa), the scale of the rate-state potentials.
    pub(crate) fn kappa(&self) -> f64 {
        self.a * self.sigma_n
    }
}

/// `ln V0` and `ln L` of a law's parameters, taken once when the law is made: the cutoff
/// `ln V_m(α)` is needed at every friction solve (the same values as computed each time).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ParamLogs {
    ln_v0: f64,
    ln_l: f64,
}

impl ParamLogs {
    pub(crate) fn of(p: &RateStateParams) -> Self {
        Self {
            ln_v0: p.v0.ln(),
            ln_l: p.l.ln(),
        }
    }
    /// [`RateStateParams::ln_cutoff_velocity`] of `p` (whose logs these are).
    pub(crate) fn ln_cutoff_velocity(&self, p: &RateStateParams, alpha: f64) -> f64 {
        let lv0 = self.ln_v0;
        lv0 - (p.mu0 + p.b * (alpha + (lv0 - self.ln_l))) / p.a
    }
}

/// A rate-and-state law's validated parameters with their logarithms (the state of
/// [`DieterichRuina`] and [`AsinhLaw`](crate::AsinhLaw)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LawParams {
    pub(crate) params: RateStateParams,
    pub(crate) logs: ParamLogs,
}

impl LawParams {
    /// # Errors
    /// [`Error::InvalidParameter`] if [`RateStateParams::validate`] fails.
    pub(crate) fn new(params: RateStateParams) -> Result<Self> {
        params.validate()?;
        Ok(Self {
            params,
            logs: ParamLogs::of(&params),
        })
    }
    /// `ln V_m(α)` ([`RateStateParams::ln_cutoff_velocity`], the logarithms taken once).
    pub(crate) fn ln_cutoff_velocity(&self, alpha: f64) -> f64 {
        self.logs.ln_cutoff_velocity(&self.params, alpha)
    }
}

/// Clamps `ln V_m` to a finite range (non-finite `α` would give `±∞`/NaN).
pub(crate) fn finite_ln_vm(l: f64) -> f64 {
    if l.is_nan() {
        // Documented: NaN state means "no cutoff information"; treat as V_m = 1 m/s.
        0.0
    } else {
        l.clamp(-1e300, 1e300)
    }
}

// ---------------------------------------------------------------------------------------
// Dieterich–Ruina with cutoff
// ---------------------------------------------------------------------------------------

/// Potential (2.13): `ϕ(V) = κ [V ln(V/V_m) − V + V_m]` for `V ≥ V_m`, else 0,
/// with `κ = a σ̄_n` (Pa). Stored as `(ln V_m, κ)`; `V_m` may be far below `f64::MIN_POSITIVE`.
///
/// `ϕ'(V) = κ ln(V/V_m)` (= σ̄_n μ(V, θ), (2.12)) for `V ≥ V_m`, `ϕ''(V) = κ/V` above
/// `V_m`, `0` below, undefined at `V_m` (jump from 0 to `κ/V_m`: the stiff part).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DieterichRuinaPotential {
    ln_vm: f64,
    vm: f64,
    kappa: f64,
}

/// `ln(v/V_m)` accurately: near `V_m` through `ln_1p`, elsewhere in log space.
fn log_ratio(v: f64, ln_vm: f64, vm: f64) -> f64 {
    if vm >= f64::MIN_POSITIVE && vm.is_finite() {
        let q = v / vm;
        if q > 0.5 && q < 2.0 {
            return ((v - vm) / vm).ln_1p();
        }
    }
    v.ln() - ln_vm
}

/// `d − 1 + e^{−d}` for `d ≥ 0` without cancellation.
fn dr_shape(d: f64) -> f64 {
    if d < 0.1 {
        // Taylor series: Σ_{k≥2} (−d)^k / k!, truncation < 1e-16 relative.
        let mut term = d * d / 2.0;
        let mut sum = term;
        for k in 3..=12 {
            term *= -d / k as f64;
            sum += term;
        }
        sum
    } else {
        d + (-d).exp_m1()
    }
}

impl DieterichRuinaPotential {
    /// From `ln V_m` (V_m in m/s) and `κ = a σ̄_n > 0` (Pa). A NaN `ln_vm` is treated as 0,
    /// infinite values are clamped to `±1e300`; `κ` is clamped to `[0, f64::MAX]`.
    pub fn new(ln_vm: f64, kappa: f64) -> Self {
        let ln_vm = finite_ln_vm(ln_vm);
        let kappa = if kappa >= 0.0 { sat(kappa) } else { 0.0 };
        Self {
            ln_vm,
            vm: ln_vm.exp(),
            kappa,
        }
    }
    /// `ln V_m` (V_m in m/s).
    pub fn ln_cutoff_velocity(&self) -> f64 {
        self.ln_vm
    }
    /// `κ = a σ̄_n` (Pa).
    pub fn kappa(&self) -> f64 {
        self.kappa
    }
}

impl ConvexPotential for DieterichRuinaPotential {
    fn value(&self, v: f64) -> f64 {
        if !(v > 0.0) || v.ln() <= self.ln_vm {
            return 0.0;
        }
        let d = log_ratio(v, self.ln_vm, self.vm);
        if d <= 0.0 {
            return 0.0;
        }
        sat(self.kappa * v * dr_shape(d))
    }
    fn slope(&self, v: f64) -> f64 {
        if !(v > 0.0) || v.ln() <= self.ln_vm {
            return 0.0;
        }
        sat(self.kappa * log_ratio(v, self.ln_vm, self.vm).max(0.0))
    }
    fn curvature(&self, v: f64) -> Option<f64> {
        if !(v > 0.0) {
            return Some(0.0);
        }
        let x = v.ln();
        if x < self.ln_vm {
            Some(0.0)
        } else if x > self.ln_vm {
            Some(sat(self.kappa / v))
        } else {
            None
        }
    }
    fn slope_and_curvature(&self, v: f64) -> (f64, Option<f64>) {
        if !(v > 0.0) {
            return (0.0, Some(0.0));
        }
        let x = v.ln();
        if x < self.ln_vm {
            (0.0, Some(0.0))
        } else if x > self.ln_vm {
            let q = v / self.vm;
            let d = if self.vm >= f64::MIN_POSITIVE && self.vm.is_finite() && q > 0.5 && q < 2.0 {
                ((v - self.vm) / self.vm).ln_1p()
            } else {
                x - self.ln_vm
            };
            (sat(self.kappa * d.max(0.0)), Some(sat(self.kappa / v)))
        } else {
            (0.0, None)
        }
    }
    /// For `r ≤ a V_m`: `s = r/a`. Otherwise `s > V_m` solves `a s + wκ ln(s/V_m) = r`;
    /// closed form `s = (wκ/a) ω(r/(wκ) + ln(a V_m/(wκ)))` (Wright omega, evaluated in
    /// log space), polished by safeguarded Newton in `x = ln s` on the bracket
    /// `[ln V_m, ln(r/a)]`.
    fn minimize(&self, a: f64, r: f64, w: f64) -> f64 {
        if !(r > 0.0) {
            // A NaN traction is not "stuck": it propagates (docs/reliability.md).
            return if r.is_nan() { r } else { 0.0 };
        }
        let c = sat(w.max(0.0) * self.kappa);
        let hi = r.ln() - a.ln();
        if c == 0.0 || hi <= self.ln_vm {
            return linear_solution(a, r);
        }
        let l = self.ln_vm;
        let lo = l;
        let lc = c.ln();
        let la = a.ln();
        let z = r / c + l + la - lc;
        let x0 = if z.is_finite() {
            lc - la + wright_omega_ln(z)
        } else {
            hi
        };
        let g = |x: f64| {
            let e = a * x.exp();
            ((e - r) + c * (x - l), e + c)
        };
        let x = solve_increasing(g, lo, hi, x0);
        sat(x.exp())
    }
}

/// Dieterich–Ruina friction with the `V_m` cutoff, (2.9), (2.12)–(2.13):
/// `μ = μ0 + a ln(V/V0) + b ln(V0 θ/L)` for `V ≥ V_m(θ)`, 0 below; `α = ln θ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DieterichRuina {
    law: LawParams,
}

impl DieterichRuina {
    /// Validated law.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] if [`RateStateParams::validate`] fails.
    pub fn new(params: RateStateParams) -> Result<Self> {
        Ok(Self {
            law: LawParams::new(params)?,
        })
    }
    /// The parameters.
    pub fn params(&self) -> &RateStateParams {
        &self.law.params
    }
}

impl FrictionLaw for DieterichRuina {
    type Potential = DieterichRuinaPotential;
    /// `ϕ(·, α)` with `ln V_m(α)` from (2.13).
    fn potential(&self, alpha: f64) -> DieterichRuinaPotential {
        DieterichRuinaPotential::new(self.law.ln_cutoff_velocity(alpha), self.law.params.kappa())
    }
    /// `κ = a σ` with the given `σ` (`V_m` does not depend on it).
    fn potential_at_normal_stress(
        &self,
        alpha: f64,
        sigma_n: f64,
    ) -> Option<DieterichRuinaPotential> {
        Some(DieterichRuinaPotential::new(
            self.law.ln_cutoff_velocity(alpha),
            self.law.params.a * sigma_n,
        ))
    }
    fn uses_state(&self) -> bool {
        true
    }
    /// (2.12): `μ0 + a ln(V/V0) + b(α + ln(V0/L))` for `V ≥ V_m(α)`, else 0.
    fn friction_coefficient(&self, v: f64, alpha: f64) -> f64 {
        let p = &self.law.params;
        if !(v > 0.0) || v.ln() <= self.law.ln_cutoff_velocity(alpha) {
            return 0.0;
        }
        let lv0 = self.law.logs.ln_v0;
        sat(p.mu0 + p.a * (v.ln() - lv0) + p.b * (alpha + (lv0 - self.law.logs.ln_l)))
    }
    fn normal_stress(&self) -> Option<f64> {
        Some(self.law.params.sigma_n)
    }
    fn proportional_to_normal_stress(&self) -> bool {
        true
    }
}

// ---------------------------------------------------------------------------------------
// Slip factor (a fault that is a plane of antisymmetry)
// ---------------------------------------------------------------------------------------

/// A potential seen through a slip factor `s > 0`: when only one side of a fault is
/// modelled (antisymmetry plane, docs/seas-bp1.md) the slip rate is `V = s|v|` (`s = 2`)
/// with `v` the boundary velocity, and the dissipation on the modelled side is
/// `F(V)·v`, so the potential in `v` is `ψ(v) = ϕ(s v)/s`: `ψ'(v) = ϕ'(s v)` (the friction
/// traction at slip rate `V`), `ψ''(v) = s ϕ''(s v)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipScaled<P> {
    inner: P,
    s: f64,
}

impl<P: ConvexPotential> SlipScaled<P> {
    /// `ψ(v) = ϕ(s v)/s`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] (`slip_factor`) unless `s` is finite and `> 0`.
    pub fn new(inner: P, s: f64) -> Result<Self> {
        check_positive("slip_factor", s)?;
        Ok(Self { inner, s })
    }
    /// The slip factor `s`.
    pub fn slip_factor(&self) -> f64 {
        self.s
    }
    /// The potential of the slip rate, `ϕ`.
    pub fn inner(&self) -> &P {
        &self.inner
    }
}

impl<P: ConvexPotential> ConvexPotential for SlipScaled<P> {
    fn value(&self, v: f64) -> f64 {
        self.inner.value(self.s * v) / self.s
    }
    fn slope(&self, v: f64) -> f64 {
        self.inner.slope(self.s * v)
    }
    fn curvature(&self, v: f64) -> Option<f64> {
        self.inner.curvature(self.s * v).map(|c| self.s * c)
    }
    fn slope_and_curvature(&self, v: f64) -> (f64, Option<f64>) {
        let (g, c) = self.inner.slope_and_curvature(self.s * v);
        (g, c.map(|c| self.s * c))
    }
    /// `argmin ½ a x² − r x + w ϕ(s x)/s = y/s` with `y = argmin ½ a y² − (s r) y + (s w) ϕ(y)`
    /// (multiply by `s²`, substitute `y = s x`).
    fn minimize(&self, a: f64, r: f64, w: f64) -> f64 {
        self.inner.minimize(a, self.s * r, self.s * w) / self.s
    }
}
