//! The exact update at constant slip rate (`StateLaw::constant_rate_update`): checked
//! against an independent integration of the state equation (classical Runge–Kutta with
//! many substeps), against the flow property that only an exact solution has (two half
//! steps are one step; backward Euler fails it), against the closed forms of its limits,
//! and on extreme inputs.

use proptest::prelude::*;
use rsf_state::{Aging, Discontinuous, Slip, StateLaw};

fn pos(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo..hi).prop_map(|e: f64| 10f64.powf(e))
}

/// `α(τ)` of `α̇ = −∂ψ/∂α(α, V)` by classical RK4 with `m` substeps.
fn rk4<S: StateLaw>(law: &S, alpha: f64, v: f64, tau: f64, m: usize) -> f64 {
    let h = tau / m as f64;
    let f = |a: f64| -law.dpsi_dalpha(a, v);
    let mut a = alpha;
    for _ in 0..m {
        let k1 = f(a);
        let k2 = f(a + 0.5 * h * k1);
        let k3 = f(a + 0.5 * h * k2);
        let k4 = f(a + h * k3);
        a += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    a
}

fn exact<S: StateLaw>(law: &S, a: f64, v: f64, tau: f64) -> f64 {
    law.constant_rate_update(a, v, tau)
        .expect("built-in laws have the exact update")
        .expect("admissible input")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]

    /// Against RK4 where RK4 is accurate: slip increments `k = τV/L ≤ 5` and a healing term
    /// `τ e^{−α} ≤ 5` (aging), 2000 substeps (step error ~ (5/2000)^5 per substep).
    #[test]
    fn aging_matches_runge_kutta(a0 in -5.0..20.0_f64, k in pos(-8.0, 0.7), tau in pos(-6.0, 0.0), l in pos(-6.0, -3.0)) {
        let law = Aging::new(l).unwrap();
        prop_assume!(tau * (-a0).exp() <= 5.0);
        let v = k * l / tau;
        let e = exact(&law, a0, v, tau);
        let r = rk4(&law, a0, v, tau, 2000);
        prop_assert!((e - r).abs() <= 1e-9 * e.abs().max(1.0), "exact {e}, rk4 {r}");
    }

    #[test]
    fn slip_matches_runge_kutta(a0 in -30.0..30.0_f64, k in pos(-8.0, 0.7), tau in pos(-6.0, 0.0), l in pos(-6.0, -3.0)) {
        let law = Slip::new(l).unwrap();
        let v = k * l / tau;
        let e = exact(&law, a0, v, tau);
        let r = rk4(&law, a0, v, tau, 2000);
        prop_assert!((e - r).abs() <= 1e-9 * e.abs().max(1.0), "exact {e}, rk4 {r}");
    }

    /// The flow property `S(S(α, τ/2), τ/2) = S(α, τ)`, for any slip increment: an exact
    /// solution has it (backward Euler does not: `backward_euler_is_not_a_flow`).
    #[test]
    fn two_half_steps_are_one_step(a0 in -30.0..30.0_f64, k in pos(-10.0, 8.0), tau in pos(-9.0, 0.0), l in pos(-6.0, 0.0)) {
        let v = k * l / tau;
        let aging = Aging::new(l).unwrap();
        let slip = Slip::new(l).unwrap();
        for (one, two) in [
            (exact(&aging, a0, v, tau), exact(&aging, exact(&aging, a0, v, 0.5 * tau), v, 0.5 * tau)),
            (exact(&slip, a0, v, tau), exact(&slip, exact(&slip, a0, v, 0.5 * tau), v, 0.5 * tau)),
        ] {
            prop_assert!(one.is_finite() && two.is_finite());
            prop_assert!((one - two).abs() <= 1e-11 * one.abs().max(1.0), "{one} vs {two}");
        }
    }

    /// Extreme inputs: finite answers between the start and the steady state.
    #[test]
    fn extreme_inputs_stay_between_start_and_steady_state(
        a0 in -700.0..700.0_f64,
        v in prop_oneof![Just(0.0), Just(1e-310), pos(-30.0, 3.0)],
        tau in prop_oneof![Just(0.0), pos(-12.0, 3.0)],
        l in pos(-12.0, 3.0),
    ) {
        let aging = Aging::new(l).unwrap();
        let slip = Slip::new(l).unwrap();
        for (law_value, ss) in [
            (exact(&aging, a0, v, tau), aging.steady_state(v)),
            (exact(&slip, a0, v, tau), slip.steady_state(v)),
        ] {
            prop_assert!(law_value.is_finite());
            if let Some(ss) = ss.filter(|s| s.is_finite()) {
                let (lo, hi) = if a0 <= ss { (a0, ss) } else { (ss, a0) };
                let slack = 1e-12 * (lo.abs() + hi.abs()).max(1.0);
                // Aging at V = 0 heals without bound; with V > 0 it stays in between.
                prop_assert!(law_value >= lo - slack && law_value <= hi + slack,
                    "{law_value} outside [{lo}, {hi}]");
            }
        }
    }
}

/// In stick (`V = 0`) the aging law heals as `θ(t) = θ₀ + t` exactly; the update is exact
/// for every step, while backward Euler in `α = ln θ` is not.
#[test]
fn aging_heals_exactly_in_stick() {
    let law = Aging::new(1e-5).unwrap();
    let a0 = -10.0_f64; // θ₀ = 4.5e-5 s, the paper's initial state
    for tau in [1e-9, 1e-6, 1e-3, 1.0, 100.0] {
        let e = exact(&law, a0, 0.0, tau);
        let want = (a0.exp() + tau).ln();
        assert!(
            (e - want).abs() <= 1e-15 * want.abs().max(1.0),
            "τ = {tau}: {e} vs {want}"
        );
    }
    // Backward Euler at τ = 1e-3 (θ grows by a factor 23) is off by more than 0.1 in α.
    let be = law.update(a0, 0.0, 1e-3).unwrap();
    assert!((be - (a0.exp() + 1e-3).ln()).abs() > 0.1);
}

/// The property above fails for backward Euler, so it discriminates: slip law at `k = 1`
/// (`α_n = (α + k ln(L/V))/(1 + k)`: one step contracts by ½, two half steps by 4/9) and
/// aging law with healing and slip (`τ e^{−α} = e³`, `k = 1`).
#[test]
fn backward_euler_is_not_a_flow() {
    let l = 1e-5;
    let (v, tau) = (1e-3, 1e-2); // k = τV/L = 1
    for (one, two) in [
        {
            let s = Slip::new(l).unwrap();
            (
                s.update(2.0, v, tau).unwrap(),
                s.update(s.update(2.0, v, 0.5 * tau).unwrap(), v, 0.5 * tau)
                    .unwrap(),
            )
        },
        {
            let a = Aging::new(l).unwrap();
            let a0 = tau.ln() - 3.0; // θ₀ = τ e^{−3}: far below L/V = τ, strong healing
            (
                a.update(a0, v, tau).unwrap(),
                a.update(a.update(a0, v, 0.5 * tau).unwrap(), v, 0.5 * tau)
                    .unwrap(),
            )
        },
    ] {
        assert!((one - two).abs() > 1e-3, "{one} vs {two}");
    }
}

/// Slip increments far beyond `f64`'s range of `e^{−k}`: the steady state `ln(L/V)`.
#[test]
fn large_slip_increments_reach_the_steady_state() {
    let l = 1e-5;
    for law_ss in [
        (
            exact(&Aging::new(l).unwrap(), 5.0, 1.0, 1e8 * l),
            (l / 1.0_f64).ln(),
        ),
        (
            exact(&Slip::new(l).unwrap(), 5.0, 1.0, 1e8 * l),
            (l / 1.0_f64).ln(),
        ),
        (
            exact(&Aging::new(l).unwrap(), 5.0, 1e300, 1e300),
            (l / 1e300_f64).ln(),
        ),
        (
            exact(&Slip::new(l).unwrap(), 5.0, 1e300, 1e300),
            (l / 1e300_f64).ln(),
        ),
    ] {
        let (got, want) = law_ss;
        assert!((got - want).abs() <= 1e-7 * want.abs(), "{got} vs {want}");
    }
}

/// The discontinuous law's backward Euler step is its exact update; a user law without a
/// closed form has none.
#[test]
fn discontinuous_is_exact_and_user_laws_have_none() {
    let d = Discontinuous;
    assert_eq!(exact(&d, 0.5, 1.0, 0.25), d.update(0.5, 1.0, 0.25).unwrap());
    assert_eq!(exact(&d, 0.5, 1.0, 0.25), 0.75);
    #[derive(Clone)]
    struct NoHealing;
    impl StateLaw for NoHealing {
        fn dpsi_dalpha(&self, _alpha: f64, v: f64) -> f64 {
            v
        }
    }
    assert!(NoHealing.constant_rate_update(0.0, 1.0, 1.0).is_none());
    assert!(Aging::new(1e-5)
        .unwrap()
        .constant_rate_update(f64::NAN, 1.0, 1.0)
        .unwrap()
        .is_err());
}
