//! The regularised rate-and-state law (`AsinhLaw`, `AsinhPotential`) against its
//! published formula, written here from the SEAS benchmark descriptions (BP1, BP3;
//! docs/seas-bp1.md): the friction coefficient is
//!
//! ```text
//! f(V, θ) = a asinh( V/(2V₀) · exp((f₀ + b ln(V₀θ/L))/a) )
//! ```
//!
//! and the shear stress σ_n f(V, θ) is the slope of the friction potential at V. Sampled
//! over 20 orders of magnitude of V and 16 of θ, with the benchmark's parameters (BP1's
//! a from 0.010 to 0.025, b = 0.015, L = 8 mm, and others), not against the code's own
//! output: a version of the law that dropped the 2 in V/(2V₀), or used ln for log, fails.
use rsf_friction::*;

/// The published friction coefficient, evaluated as written (its arguments stay within
/// f64 for the sampled values: the exponent (f₀ + b ln(V₀θ/L))/a is at most about 206, for
/// the laboratory set at θ = 1e10 s).
fn published(p: &RateStateParams, v: f64, theta: f64) -> f64 {
    p.a * (v / (2.0 * p.v0) * ((p.mu0 + p.b * (p.v0 * theta / p.l).ln()) / p.a).exp()).asinh()
}

fn parameter_sets() -> Vec<RateStateParams> {
    let bp1 = |a: f64| RateStateParams {
        mu0: 0.6,
        a,
        b: 0.015,
        v0: 1e-6,
        l: 0.008,
        sigma_n: 50e6,
    };
    vec![
        bp1(0.010),
        bp1(0.025),
        bp1(0.0175),
        // BP3's L and a laboratory-scale set (larger V₀, smaller L, b > 2a).
        RateStateParams {
            l: 0.004,
            ..bp1(0.01)
        },
        RateStateParams {
            mu0: 0.7,
            a: 0.005,
            b: 0.012,
            v0: 1e-3,
            l: 1e-5,
            sigma_n: 5e6,
        },
    ]
}

#[test]
fn friction_coefficient_and_potential_slope_follow_the_published_formula() {
    let mut worst = 0.0f64;
    let mut samples = 0;
    for p in parameter_sets() {
        let law = AsinhLaw::new(p).unwrap();
        // V from 1e-20 to 1 m/s, θ from 1e-6 s to 1e10 s (α = ln θ), in steps of a
        // quarter and half an order of magnitude.
        for i in 0..=80 {
            let v = 10f64.powf(-20.0 + 0.25 * f64::from(i));
            for j in 0..=32 {
                let theta = 10f64.powf(-6.0 + 0.5 * f64::from(j));
                let alpha = theta.ln();
                let want = published(&p, v, theta);
                assert!(want.is_finite() && want > 0.0);
                let f = law.friction_coefficient(v, alpha);
                let slope = law.potential(alpha).slope(v) / p.sigma_n;
                for (name, got) in [("friction_coefficient", f), ("slope / σ_n", slope)] {
                    let rel = (got - want).abs() / want;
                    // The formula as written loses a few ulps in exp and asinh of large
                    // arguments (up to e^86): 1e-12 leaves room for them and none for a
                    // changed constant (a missing 2 changes f by a·ln 2 or more).
                    assert!(
                        rel <= 1e-12,
                        "{name}: {got} against {want} at V = {v:e}, θ = {theta:e}, {p:?} ({rel:e})"
                    );
                    worst = worst.max(rel);
                }
                samples += 1;
            }
        }
    }
    assert_eq!(samples, 5 * 81 * 33);
    eprintln!("largest relative difference from the published formula: {worst:e}");
}

/// At steady state (θ = L/V) the published coefficient is
/// a asinh(V/(2V₀) exp((f₀ + b ln(V₀/V))/a)), which for V ≫ V_m tends to the classical
/// f₀ + (a − b) ln(V/V₀): checked in that limit, where asinh(x) = ln(2x) + O(x⁻²).
#[test]
fn steady_state_tends_to_the_classical_law_far_above_the_cutoff() {
    for p in parameter_sets() {
        let law = AsinhLaw::new(p).unwrap();
        for v in [1e-12, 1e-9, 1e-6, 1e-3, 1.0] {
            let alpha = (p.l / v).ln();
            let classical = p.mu0 + (p.a - p.b) * (v / p.v0).ln();
            let f = law.friction_coefficient(v, alpha);
            // x = V/(2V_m) is above e^{f/a} ≥ e^{20} here, so the O(x⁻²) term is < 1e-17.
            assert!(
                (f - classical).abs() <= 1e-12 * classical.abs().max(1.0),
                "V = {v:e}: {f} against the classical {classical}, {p:?}"
            );
        }
    }
}
