//! The regularised rate-and-state law (the SEAS benchmarks' form) and its potential.

use crate::potentials::{finite_ln_vm, linear_solution, sat, LawParams, RateStateParams, LN_2};
use crate::{ConvexPotential, FrictionLaw, Result};
use rsf_numeric::{solve_increasing_from, solve_increasing_from_upper_end, wright_omega_ln};

/// `q = ln(s/(2V_m))` from which the friction solve takes the Dieterich–Ruina equation's
/// closed form (`AsinhPotential::dieterich_ruina_exact`): `asinh(e^q) − q − ln 2 < e^{−2q}/4`.
const DR_EXACT_Q: f64 = 20.0;

/// `asinh(e^q)` without overflow.
fn asinh_exp(q: f64) -> f64 {
    if q <= 0.0 {
        q.exp().asinh()
    } else {
        q + (1.0 + (1.0 + (-2.0 * q).exp()).sqrt()).ln()
    }
}

/// `y/(√(1+y²)+1)` with `y = e^q`, without overflow.
fn half_ratio(q: f64) -> f64 {
    if q <= 0.0 {
        let y = q.exp();
        y / ((1.0 + y * y).sqrt() + 1.0)
    } else {
        1.0 / ((1.0 + (-2.0 * q).exp()).sqrt() + (-q).exp())
    }
}

/// `1/√(1 + e^{−2q})` without overflow.
fn inv_sqrt_one_plus_exp_m2q(q: f64) -> f64 {
    if q >= 0.0 {
        1.0 / (1.0 + (-2.0 * q).exp()).sqrt()
    } else {
        let y = q.exp();
        y / (1.0 + y * y).sqrt()
    }
}

/// Regularised rate-state potential (SEAS benchmarks):
/// `ϕ(V) = κ [V asinh(V/(2V_m)) − √(V² + 4V_m²) + 2V_m]`, `κ = a σ̄_n`,
/// `ϕ'(V) = κ asinh(V/(2V_m))`, `ϕ''(V) = κ/√(V² + 4V_m²)`. Smooth and strictly convex;
/// evaluated in log space (`ln V_m` stored).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AsinhPotential {
    ln_vm: f64,
    kappa: f64,
}

impl AsinhPotential {
    /// From `ln V_m` and `κ = a σ̄_n` (Pa); sanitised as in [`DieterichRuinaPotential::new`](crate::DieterichRuinaPotential::new).
    pub fn new(ln_vm: f64, kappa: f64) -> Self {
        Self {
            ln_vm: finite_ln_vm(ln_vm),
            kappa: if kappa >= 0.0 { sat(kappa) } else { 0.0 },
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
    /// `q = ln(V/(2V_m))`.
    fn q(&self, v: f64) -> f64 {
        v.ln() - LN_2 - self.ln_vm
    }
}

impl ConvexPotential for AsinhPotential {
    /// Evaluated as `κ V [asinh(y) − y/(√(1+y²)+1)]`, `y = V/(2V_m)`, which equals the
    /// formula above and never forms `V_m`.
    fn value(&self, v: f64) -> f64 {
        if !(v > 0.0) {
            return 0.0;
        }
        let q = self.q(v);
        sat(self.kappa * v * (asinh_exp(q) - half_ratio(q)))
    }
    fn slope(&self, v: f64) -> f64 {
        if !(v > 0.0) {
            return 0.0;
        }
        sat(self.kappa * asinh_exp(self.q(v)))
    }
    /// Saturated at `f64::MAX` where `κ/(2V_m)` overflows (`V_m` below ~1e-308).
    fn curvature(&self, v: f64) -> Option<f64> {
        // κ/√(V² + 4V_m²) = κ/(2V_m) · 1/√(1+y²)
        let q = if v > 0.0 {
            self.q(v)
        } else {
            f64::NEG_INFINITY
        };
        let c = if q > 0.0 {
            self.kappa / v * inv_sqrt_one_plus_exp_m2q(q)
        } else {
            let y = q.exp();
            // ln(κ/(2 V_m)) − ln √(1+y²)
            (self.kappa.ln() - LN_2 - self.ln_vm - 0.5 * (y * y).ln_1p()).exp()
        };
        Some(sat(c))
    }
    /// Solves `a s + wκ asinh(s/(2V_m)) = r` in `x = ln s` by safeguarded Newton on the
    /// bracket `[ln(r/(a + wκ/(2V_m))), min(ln(r/a), x_DR)]`, where `x_DR` is the
    /// Wright-omega solution of the Dieterich–Ruina equation (an upper bound because
    /// `asinh(y) ≥ ln(2y)`), started at the end where `|g|` is smaller.
    ///
    /// Where the solution slips so far above `V_m` that `asinh(y) = ln(2y)` to round-off
    /// (`y ≥ e^20`), `x_DR` is the root and is returned without iterating
    /// (`dieterich_ruina_exact`). Slipping above `V_m` otherwise, where the solve starts at
    /// `x_DR` and its Newton steps stay far from the lower end, that end (an exponential
    /// and a logarithm) and `g` there are not formed: the same iterates and the same
    /// number as the bracketed solve, bit for bit (`dr_shortcut` says why).
    fn minimize(&self, a: f64, r: f64, w: f64) -> f64 {
        if !(r > 0.0) {
            // A NaN traction is not "stuck": it propagates (docs/reliability.md).
            return if r.is_nan() { r } else { 0.0 };
        }
        let c = sat(w.max(0.0) * self.kappa);
        if c == 0.0 {
            return linear_solution(a, r);
        }
        if let Some(x) = self.dieterich_ruina_exact(a, c, r) {
            return sat(x.exp());
        }
        self.iterated(a, c, r)
    }
}

impl AsinhPotential {
    /// [`minimize`](ConvexPotential::minimize)'s iterated solve for `r > 0` and `c = wκ > 0`.
    fn iterated(&self, a: f64, c: f64, r: f64) -> f64 {
        let l = self.ln_vm;
        let (la, lc, lr) = (a.ln(), c.ln(), r.ln());
        let mut hi = lr - la;
        // ln(a + c/(2 V_m)) = logaddexp(ln a, ln c − ln 2 − l)
        let lb = lc - LN_2 - l;
        let (m, n) = if la > lb { (la, lb) } else { (lb, la) };
        let z = r / c + l + la - lc;
        if z.is_finite() {
            let x_dr = lc - la + wright_omega_ln(z);
            if x_dr < hi {
                hi = x_dr;
                if let Some(x) = self.dr_shortcut(a, c, r, x_dr, lr - m) {
                    return sat(x.exp());
                }
            }
        }
        let lo = lr - (m + (n - m).exp().ln_1p());
        self.bracketed(a, c, r, lo, hi)
    }

    /// `g(x) = a eˣ + c asinh(eˣ/(2V_m)) − r` and `g'(x)`, the friction solve's equation in
    /// `x = ln s`.
    #[inline]
    fn equation(&self, a: f64, c: f64, r: f64, x: f64) -> (f64, f64) {
        let e = a * x.exp();
        let q = x - LN_2 - self.ln_vm;
        (
            (e - r) + c * asinh_exp(q),
            e + c * inv_sqrt_one_plus_exp_m2q(q),
        )
    }

    /// The bracketed solve of [`minimize`](ConvexPotential::minimize) on `[lo, hi]`.
    fn bracketed(&self, a: f64, c: f64, r: f64, lo: f64, hi: f64) -> f64 {
        let g = |x: f64| self.equation(a, c, r, x);
        if !(lo < hi) {
            return sat(lo.min(hi).exp());
        }
        let (glo, ghi) = (g(lo), g(hi));
        let (x0, start) = if glo.0.abs() < ghi.0.abs() {
            (lo, glo)
        } else {
            (hi, ghi)
        };
        sat(solve_increasing_from(g, lo, hi, x0, start).exp())
    }

    /// `ln s` in closed form where the solution slips far above the cutoff: `None` unless
    /// `q = ln(s/(2V_m)) ≥ DR_EXACT_Q` at it.
    ///
    /// There `asinh(e^q) = q + ln 2 + ε` with `0 < ε < e^{−2q}/4 < 1.1·10⁻¹⁸`, so the
    /// equation is the Dieterich–Ruina one with damping, `a s + c (ln s − ln V_m) = r`, to
    /// within `εc` — below the rounding of its terms (`r ≥ c q ≥ 20c`). Its root is `x_DR`,
    /// `ln s = x₀ − ω(z) = ln ω(z) − ln(a/c)` with `x₀ = ln V_m + r/c` (the undamped
    /// solution), `z = x₀ + ln(a/c)` and `ω` the Wright omega function: no iteration on `g`,
    /// one logarithm and two exponentials where the damping is small (plus a Wright-omega
    /// evaluation where it is not) against some fifteen of the iterated solve. The first
    /// form where the damping is small (`z < −9`, `ω` by its series),
    /// the second where it is not (no cancellation of `x₀` against `ω`). Either agrees with
    /// the bracketed solve to the root's conditioning (a proptest below).
    fn dieterich_ruina_exact(&self, a: f64, c: f64, r: f64) -> Option<f64> {
        let rc = r / c;
        if !(rc >= DR_EXACT_Q + LN_2 && a >= 0.0) {
            return None;
        }
        let x0 = self.ln_vm + rc;
        let ln_ac = (a / c).ln();
        let z = x0 + ln_ac;
        let x = if z < -9.0 {
            // W(e^z) = e − e² + (3/2)e³ − (8/3)e⁴ + …, e = e^z < 1.3·10⁻⁴: the next term
            // (125/24)e⁵ is below 2·10⁻¹⁹ (and z = −∞, a = 0, gives 0).
            let e = z.exp();
            x0 - e * (1.0 - e * (1.0 - e * (1.5 - e * (8.0 / 3.0))))
        } else {
            wright_omega_ln(z) - ln_ac
        };
        (x.is_finite() && x - LN_2 - self.ln_vm >= DR_EXACT_Q).then_some(x)
    }

    /// `ln s` from the upper end `x_DR` alone, when the bracketed solve would start there and
    /// its iteration never needs the lower end's value ([`solve_increasing_from_upper_end`]:
    /// the same iterates, bit for bit); `None` otherwise (then the bracket is formed).
    ///
    /// The conditions that the bracketed solve would start at `x_DR`, each checked
    /// (`c = wκ`, `y = s/(2V_m)`):
    /// - the lower end lies below `x_DR`: it is at most `ln r − max(ln a, ln(c/(2V_m)))`
    ///   (`floor`) in floating point, so `x_DR > floor` gives `lo < hi`;
    /// - `|g(x_DR)| ≤ |g(lo)|`: with `|g(x_DR)| ≤ 10⁻³c` and `x_DR ≥ ln(2V_m) + 0.01`, the
    ///   root has `y* ≥ 1` (else `g` would grow by at least `0.01c/√2` between the root and
    ///   `x_DR`, `g` being convex with `g' ≥ c/√(1+y⁻²)`); then
    ///   `y_lo = (2V_m a y* + c asinh y*)/(2V_m a + c) ≥ asinh y* ≥ 0.88` and
    ///   `|g(lo)| = c(y_lo − asinh y_lo) ≥ 0.09c`, whose rounding (with `r ≤ 10⁶c`) is below
    ///   `10⁻⁵c`.
    fn dr_shortcut(&self, a: f64, c: f64, r: f64, x_dr: f64, floor: f64) -> Option<f64> {
        if !(x_dr > floor && x_dr - LN_2 - self.ln_vm >= 0.01 && r <= 1e6 * c) {
            return None;
        }
        let start = self.equation(a, c, r, x_dr);
        if !(start.0.abs() <= 1e-3 * c) {
            return None;
        }
        solve_increasing_from_upper_end(|x| self.equation(a, c, r, x), floor, x_dr, start)
    }
}

/// Regularised rate-and-state law (SEAS benchmark form):
/// `μ(V, θ) = a asinh(V/(2V_m(θ)))` with `V_m` from (2.13), i.e.
/// `μ = a asinh(V/(2V0) exp((μ0 + b ln(V0 θ/L))/a))`; `α = ln θ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AsinhLaw {
    law: LawParams,
}

impl AsinhLaw {
    /// Validated law.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) if [`RateStateParams::validate`] fails.
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

impl FrictionLaw for AsinhLaw {
    type Potential = AsinhPotential;
    fn potential(&self, alpha: f64) -> AsinhPotential {
        AsinhPotential::new(self.law.ln_cutoff_velocity(alpha), self.law.params.kappa())
    }
    /// `κ = a σ` with the given `σ` (`V_m` does not depend on it).
    fn potential_at_normal_stress(&self, alpha: f64, sigma_n: f64) -> Option<AsinhPotential> {
        Some(AsinhPotential::new(
            self.law.ln_cutoff_velocity(alpha),
            self.law.params.a * sigma_n,
        ))
    }
    fn uses_state(&self) -> bool {
        true
    }
    fn friction_coefficient(&self, v: f64, alpha: f64) -> f64 {
        if !(v > 0.0) {
            return 0.0;
        }
        let l = finite_ln_vm(self.law.ln_cutoff_velocity(alpha));
        sat(self.law.params.a * asinh_exp(v.ln() - LN_2 - l))
    }
    fn normal_stress(&self) -> Option<f64> {
        Some(self.law.params.sigma_n)
    }
    fn proportional_to_normal_stress(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The solve as it was before the shortcut: the bracket always formed.
    fn bracketed_always(p: &AsinhPotential, a: f64, r: f64, w: f64) -> f64 {
        let c = sat(w.max(0.0) * p.kappa);
        let l = p.ln_vm;
        let (la, lc, lr) = (a.ln(), c.ln(), r.ln());
        let mut hi = lr - la;
        let lb = lc - LN_2 - l;
        let (m, n) = if la > lb { (la, lb) } else { (lb, la) };
        let lo = lr - (m + (n - m).exp().ln_1p());
        let z = r / c + l + la - lc;
        if z.is_finite() {
            let x_dr = lc - la + wright_omega_ln(z);
            if x_dr < hi {
                hi = x_dr;
            }
        }
        p.bracketed(a, c, r, lo, hi)
    }

    /// `minimize` without the closed form: the iterated solve, whose shortcut keeps the
    /// bracketed solve's bits.
    fn iterated_solve(p: &AsinhPotential, a: f64, r: f64, w: f64) -> f64 {
        let c = sat(w.max(0.0) * p.kappa);
        p.iterated(a, c, r)
    }

    /// Whether `minimize` took the shortcut for these inputs.
    fn shortcut_taken(p: &AsinhPotential, a: f64, r: f64, w: f64) -> bool {
        let c = sat(w.max(0.0) * p.kappa);
        let (la, lc, lr) = (a.ln(), c.ln(), r.ln());
        let lb = lc - LN_2 - p.ln_vm;
        let z = r / c + p.ln_vm + la - lc;
        let x_dr = lc - la + wright_omega_ln(z);
        z.is_finite() && x_dr < lr - la && p.dr_shortcut(a, c, r, x_dr, lr - la.max(lb)).is_some()
    }

    /// The traction of slip rate `s` (the equation's right-hand side).
    fn traction(p: &AsinhPotential, a: f64, w: f64, s: f64) -> f64 {
        a * s + w * p.kappa * asinh_exp(s.ln() - LN_2 - p.ln_vm)
    }

    #[test]
    fn the_shortcut_is_taken_while_slipping_and_gives_the_bracketed_bits() {
        // BP1's scale (a = η = μ/2c_s, κ = aσ_n) and far from it, slip rates from stuck to
        // seismic relative to V_m.
        let mut expected = 0;
        let mut cases = 0;
        for ln_vm in [-60.0, -30.0, -20.0, -5.0, 0.0] {
            for kappa in [1e-2, 5e5, 1.25e6, 1e9] {
                for a in [1e-6, 1.0, 4.6e6, 1e12] {
                    for d in [-30.0, -3.0, -0.5, 0.0, 0.005, 0.02, 1.0, 5.0, 20.0, 45.0] {
                        let p = AsinhPotential::new(ln_vm, kappa);
                        let s = (ln_vm + LN_2 + d).exp();
                        let r = traction(&p, a, 1.0, s);
                        if !(r > 0.0 && r.is_finite()) {
                            continue;
                        }
                        cases += 1;
                        let fast = iterated_solve(&p, a, r, 1.0);
                        let full = bracketed_always(&p, a, r, 1.0);
                        assert_eq!(fast.to_bits(), full.to_bits(), "{ln_vm} {kappa} {a} {d}");
                        let taken = shortcut_taken(&p, a, r, 1.0);
                        // Far above the cutoff (y = e^20: asinh(y) − ln 2y = 1/4y² is below
                        // rounding) with the damping negligible (its rounding in g moves
                        // the first Newton correction above 2ε|x|), the Dieterich–Ruina
                        // solution is the root: the shortcut must be taken.
                        if d >= 20.0 && a * s < 1e-3 * kappa {
                            assert!(taken, "{ln_vm} {kappa} {a} {d}");
                            expected += 1;
                        }
                        // Below 2V_m·e^0.01 it must not be.
                        if d < 0.01 {
                            assert!(!taken, "{ln_vm} {kappa} {a} {d}");
                        }
                    }
                }
            }
        }
        assert!(expected >= 40 && cases >= 400, "{expected} of {cases}");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4000))]
        /// Two solves against the always-bracketed one, over `ln V_m` up to the clamp
        /// `±1e300`, eleven decades of `κ`, 21 of `a`, seven of `w`, tractions of slip rates
        /// from `V_m e⁻⁴⁰` to `V_m e⁶⁰` and absolute ones (passed with
        /// `PROPTEST_CASES=100000` too):
        /// - the iterated solve with its shortcut, bit for bit;
        /// - `minimize` (which takes the closed form far above the cutoff) within the root's
        ///   conditioning, `|Δ ln s| ≤ 16 ε (1 + r/c + |ln V_m| + |ln s|)` (`d ln s = dr/c`
        ///   near the root, and both solves round `r/c`, `ln V_m` and `ln s`).
        #[test]
        fn the_shortcut_never_changes_a_bit_and_the_closed_form_agrees_to_its_conditioning(
            ln_vm in prop_oneof![-1e300..-1e4, -1e4..-700.0, -700.0..5.0_f64, 5.0..1e300_f64],
            kappa in (-3.0..8.0_f64).prop_map(|e| 10f64.powf(e)),
            a in (-8.0..13.0_f64).prop_map(|e| 10f64.powf(e)),
            w in (-6.0..1.0_f64).prop_map(|e| 10f64.powf(e)),
            d in -40.0..60.0_f64,
            r_abs in (-30.0..12.0_f64).prop_map(|e| 10f64.powf(e)),
            by_slip in any::<bool>(),
        ) {
            let p = AsinhPotential::new(ln_vm, kappa);
            let r = if by_slip && ln_vm > -690.0 {
                traction(&p, a, w, (ln_vm + LN_2 + d).min(600.0).exp())
            } else {
                r_abs
            };
            prop_assume!(r > 0.0 && r.is_finite());
            let full = bracketed_always(&p, a, r, w);
            prop_assert_eq!(iterated_solve(&p, a, r, w).to_bits(), full.to_bits());
            let fast = p.minimize(a, r, w);
            prop_assert!(fast.is_finite() && fast >= 0.0);
            if fast == full {
                return Ok(());
            }
            prop_assert!(fast > 0.0 && full > 0.0, "{fast} {full}");
            let (x, y) = (fast.ln(), full.ln());
            let c = w * kappa;
            let bound = 16.0 * f64::EPSILON * (1.0 + r / c + ln_vm.abs() + x.abs());
            prop_assert!((x - y).abs() <= bound, "{fast} {full}: {} > {bound}", (x - y).abs());
        }
    }

    #[test]
    fn the_closed_form_is_taken_far_above_the_cutoff_only() {
        // Slip rates e^d·2V_m at BP1's scale: the closed form exactly where q ≥ 20 at the
        // root, and its answer a root of the full equation to the traction's rounding.
        for ln_vm in [-60.0, -20.0, 0.0] {
            for a in [0.0, 1.0, 4.6e6, 1e12] {
                for d in [5.0, 19.9, 20.1, 45.0] {
                    let (p, kappa) = (AsinhPotential::new(ln_vm, 5e5), 5e5);
                    let s = (ln_vm + LN_2 + d).exp();
                    let r = traction(&p, a, 1.0, s);
                    let x = p.dieterich_ruina_exact(a, kappa, r);
                    assert_eq!(x.is_some(), d > 20.0, "{ln_vm} {a} {d}");
                    if let Some(x) = x {
                        // |Δx| = |residual|/g'(x) with g' ≈ a s + c: a few ulps of x.
                        let residual = traction(&p, a, 1.0, x.exp()) - r;
                        let slope = a * x.exp() + kappa;
                        let bound = 8.0 * f64::EPSILON * (r + slope * x.abs());
                        assert!(residual.abs() <= bound, "{residual} of {r}");
                    }
                }
            }
        }
    }
}
