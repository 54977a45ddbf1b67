//! Property tests of the state laws and their backward Euler updates.

use proptest::prelude::*;
use rsf_state::{generic_update, Aging, Discontinuous, Error, Slip, StateLaw, StateVariable};

fn pos(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo..hi).prop_map(|e: f64| 10f64.powf(e))
}
/// Slip rates 0, subnormal, or 1e-30 … 1e3 m/s.
fn slip_rate() -> impl Strategy<Value = f64> {
    prop_oneof![
        1 => Just(0.0),
        1 => Just(1e-310),
        20 => pos(-30.0, 3.0),
    ]
}

/// Residual of the implicit equation `β − α_prev + τ ∂ψ/∂α(β, V) = 0` and the magnitude of
/// its terms. The residual of a correctly rounded `β` is `|F'(β)|·ulp(β)` plus the rounding
/// of the terms, i.e. a few `ε` times `scale = |β| + |α_prev| + τ|∂ψ/∂α|-terms`; so the
/// test is `|F| ≤ 1e-12·max(1, scale)`: absolute `1e-12` for terms of order 1, relative to
/// the largest term otherwise (with `τV/L = 1e8` a single term is 1e8 and its own rounding
/// is 1.5e-8, so an absolute 1e-12 cannot be met by any floating-point β).
fn aging_residual(law: &Aging, b: f64, a0: f64, v: f64, tau: f64) -> (f64, f64) {
    let k = tau * (v / law.l());
    let e = tau * (-b).exp();
    ((b - a0) + k - e, b.abs() + a0.abs() + k + e)
}
fn slip_residual(law: &Slip, b: f64, a0: f64, v: f64, tau: f64) -> (f64, f64) {
    if v == 0.0 {
        return (b - a0, b.abs() + a0.abs());
    }
    let k = tau * (v / law.l());
    let lvl = v.ln() - law.l().ln();
    (
        (b - a0) + k * (b + lvl),
        b.abs() + a0.abs() + k * (b.abs() + lvl.abs()),
    )
}

fn check_close(x: f64, y: f64, tol: f64) -> Result<(), TestCaseError> {
    prop_assert!(
        (x - y).abs() <= tol * x.abs().max(1.0),
        "{x} vs {y} (diff {})",
        (x - y).abs()
    );
    Ok(())
}

/// The update `β` of `law` from `(α_prev, V, τ)`, checked: the `(residual, scale)` of its
/// implicit equation (`residual(law, β, α_prev, V, τ)`) within `1e-12·max(1, scale)`, and
/// the generic solver's update within 1e-10.
fn checked_update<L: StateLaw>(
    law: &L,
    residual: fn(&L, f64, f64, f64, f64) -> (f64, f64),
    (a0, v, tau): (f64, f64, f64),
) -> Result<f64, TestCaseError> {
    let b = law.update(a0, v, tau).unwrap();
    let (res, scale) = residual(law, b, a0, v, tau);
    prop_assert!(
        res.abs() <= 1e-12 * scale.max(1.0),
        "β={b}: res {res}, scale {scale}"
    );
    let g = generic_update(law, a0, v, tau).unwrap();
    check_close(b, g, 1e-10)?;
    Ok(b)
}

/// [`checked_update`], and the update finite.
fn checked_finite_update<L: StateLaw>(
    law: &L,
    residual: fn(&L, f64, f64, f64, f64) -> (f64, f64),
    args: (f64, f64, f64),
) -> Result<(), TestCaseError> {
    let b = checked_update(law, residual, args)?;
    prop_assert!(b.is_finite());
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    #[test]
    fn aging_implicit_equation(a0 in -1e3..1e3_f64, v in slip_rate(), tau in pos(-12.0, 3.0), l in pos(-6.0, 0.0)) {
        checked_finite_update(&Aging::new(l).unwrap(), aging_residual, (a0, v, tau))?;
    }

    /// Slip increments τV/L from 1e-12 to 1e8 (and beyond), α_prev over ±1e3.
    #[test]
    fn aging_large_slip_increments(a0 in -1e3..1e3_f64, k in pos(-12.0, 9.0), tau in pos(-12.0, 3.0)) {
        let l: f64 = 1e-5;
        let v = k * l / tau;
        prop_assume!(v <= 1e3 * 1.0000001 || k >= 1e8);
        let law = Aging::new(l).unwrap();
        checked_update(&law, aging_residual, (a0, v, tau))?;
    }

    #[test]
    fn slip_implicit_equation(a0 in -1e3..1e3_f64, v in slip_rate(), tau in pos(-12.0, 3.0), l in pos(-6.0, 0.0)) {
        checked_finite_update(&Slip::new(l).unwrap(), slip_residual, (a0, v, tau))?;
    }

    /// Discontinuous law: β is either a regular root of β − α_prev + τV sign(βV − 1) = 0
    /// or the kink 1/V, reached with a step |β − α_prev| ≤ τV (0 ∈ ∂ψ there).
    #[test]
    fn discontinuous_implicit_inclusion(a0 in -1e3..1e3_f64, v in slip_rate(), tau in pos(-12.0, 3.0)) {
        let law = Discontinuous;
        let b = law.update(a0, v, tau).unwrap();
        prop_assert!(b.is_finite());
        let step = tau * v;
        let at_kink = v > 0.0 && (b - 1.0 / v).abs() <= 4.0 * f64::EPSILON * b.abs();
        if at_kink {
            prop_assert!((b - a0).abs() <= step * (1.0 + 1e-12) + 4.0 * f64::EPSILON * b.abs());
        } else {
            let res = (b - a0) + tau * law.dpsi_dalpha(b, v);
            prop_assert!(res.abs() <= 1e-12 * (b.abs() + a0.abs() + step).max(1.0), "res {res}");
        }
        let g = generic_update(&law, a0, v, tau).unwrap();
        check_close(b, g, 1e-10)?;
    }

    /// Steady state: at constant V the aging and slip laws keep α = ln(L/V).
    #[test]
    fn steady_state_is_fixed(v in pos(-20.0, 3.0), tau in pos(-12.0, 3.0), l in pos(-6.0, 0.0)) {
        let alpha = (l / v).ln();
        for law_alpha in [
            Aging::new(l).unwrap().update(alpha, v, tau).unwrap(),
            Slip::new(l).unwrap().update(alpha, v, tau).unwrap(),
        ] {
            check_close(law_alpha, alpha, 1e-12)?;
        }
        prop_assert_eq!(Aging::new(l).unwrap().steady_state(v), Some(-(v / l).ln()));
        let d = Discontinuous;
        prop_assert_eq!(d.update(1.0 / v, v, tau).unwrap(), 1.0 / v);
    }

    /// Extreme inputs: finite or a typed error, never NaN/inf/panic — also for the generic
    /// solver and for a user law with a singular ∂ψ/∂α.
    #[test]
    fn extreme_inputs(a0 in -1e3..1e3_f64, v in slip_rate(), tau in prop_oneof![Just(0.0), pos(-12.0, 3.0)], l in pos(-300.0, 300.0)) {
        let aging = Aging::new(l).unwrap();
        let slip = Slip::new(l).unwrap();
        for r in [
            aging.update(a0, v, tau), generic_update(&aging, a0, v, tau),
            slip.update(a0, v, tau), generic_update(&slip, a0, v, tau),
            Discontinuous.update(a0, v, tau), generic_update(&Discontinuous, a0, v, tau),
        ] {
            match r {
                Ok(x) => prop_assert!(x.is_finite()),
                Err(e) => prop_assert!(false, "unexpected error {e}"),
            }
        }
    }
}

type Scalar = Box<dyn Fn(f64) -> f64>;

#[test]
fn velocity_step_relaxes_over_a_few_l() {
    // V1 → V2 (up and down by 10×), slip per step L/1000.
    let l = 1e-5;
    for (v1, v2) in [(1e-6_f64, 1e-5_f64), (1e-5, 1e-6)] {
        let tau = l / 1000.0 / v2;
        let (ss1, ss2) = ((l / v1).ln(), (l / v2).ln());
        // Slip law: α − α_ss decays like e^{−slip/L}; aging law: θ − θ_ss does.
        let laws: [(&str, Scalar, Scalar); 2] = [
            (
                "slip",
                Box::new(move |a| Slip::new(l).unwrap().update(a, v2, tau).unwrap()),
                Box::new(move |a| (a - ss2).abs() / (ss1 - ss2).abs()),
            ),
            (
                "aging",
                Box::new(move |a| Aging::new(l).unwrap().update(a, v2, tau).unwrap()),
                Box::new(move |a: f64| (a.exp() - ss2.exp()).abs() / (ss1.exp() - ss2.exp()).abs()),
            ),
        ];
        for (name, step, dist) in laws {
            let mut alpha = ss1;
            let mut prev = dist(alpha);
            assert!((prev - 1.0).abs() < 1e-12);
            for n in 1..=5000 {
                alpha = step(alpha);
                let d = dist(alpha);
                assert!(d < prev, "{name}: distance must decrease monotonically");
                prev = d;
                let slip_over_l = n as f64 / 1000.0;
                if n == 1000 {
                    // after one L: still far (e^{-1} ≈ 0.37), i.e. not an instantaneous jump
                    assert!(d > 0.3 && d < 0.45, "{name}: after 1 L distance {d}");
                }
                if n == 5000 {
                    assert!(d < 0.01, "{name}: after {slip_over_l} L distance {d}");
                    // close to the continuous e^{-5}
                    assert!((d / (-5.0f64).exp() - 1.0).abs() < 0.01, "{name}: {d}");
                }
            }
        }
    }
}

#[test]
fn overflowing_slip_increment() {
    // τV/L = 1e3·1e3/1e-310 overflows f64: the closed forms return the limit ln(L/V).
    let l: f64 = 1e-310;
    let a = Aging::new(l).unwrap().update(5.0, 1e3, 1e3).unwrap();
    let s = Slip::new(l).unwrap().update(5.0, 1e3, 1e3).unwrap();
    let ss = l.ln() - 1e3f64.ln();
    assert!((a - ss).abs() < 1e-12 * ss.abs() && (s - ss).abs() < 1e-12 * ss.abs());
}

#[test]
fn typed_errors() {
    assert!(matches!(
        Aging::new(0.0),
        Err(Error::InvalidParameter { name: "l", .. })
    ));
    assert!(matches!(
        Slip::new(f64::NAN),
        Err(Error::InvalidParameter { .. })
    ));
    let law = Aging::new(1e-5).unwrap();
    assert!(matches!(
        law.update(f64::NAN, 1.0, 1.0),
        Err(Error::InvalidInput {
            name: "alpha_prev",
            ..
        })
    ));
    assert!(matches!(
        law.update(0.0, -1.0, 1.0),
        Err(Error::InvalidInput { name: "v", .. })
    ));
    assert!(matches!(
        law.update(0.0, 1.0, f64::INFINITY),
        Err(Error::InvalidInput { name: "tau", .. })
    ));
    assert!(matches!(
        generic_update(&law, 0.0, 1.0, -1.0),
        Err(Error::InvalidInput { .. })
    ));

    // A user law whose ∂ψ/∂α is the same number everywhere: NaN, or −∞ (unbounded).
    #[derive(Clone)]
    struct ConstantDerivative(f64);
    impl StateLaw for ConstantDerivative {
        fn dpsi_dalpha(&self, _: f64, _: f64) -> f64 {
            self.0
        }
    }
    assert!(matches!(
        ConstantDerivative(f64::NAN).update(0.0, 1.0, 1.0),
        Err(Error::NanDerivative { .. })
    ));
    assert!(matches!(
        ConstantDerivative(f64::NEG_INFINITY).update(0.0, 1.0, 1.0),
        Err(Error::NoBracket { .. })
    ));
}

#[test]
fn state_variable_kinds() {
    assert_eq!(
        Aging::new(1.0).unwrap().state_variable(),
        StateVariable::LogTheta
    );
    assert_eq!(
        Slip::new(1.0).unwrap().state_variable(),
        StateVariable::LogTheta
    );
    assert_eq!(Discontinuous.state_variable(), StateVariable::Theta);
}

#[test]
fn psi_is_consistent_with_its_derivative() {
    let (v, h) = (3e-6, 1e-6);
    let aging = Aging::new(1e-5).unwrap();
    let slip = Slip::new(1e-5).unwrap();
    for alpha in [-20.0_f64, -3.0, 0.0, 4.0, 12.0] {
        let fd = (aging.psi(alpha + h, v).unwrap() - aging.psi(alpha - h, v).unwrap()) / (2.0 * h);
        let d = aging.dpsi_dalpha(alpha, v);
        assert!(
            (fd - d).abs() <= 1e-6 * (d.abs() + (-alpha).exp() + 1.0),
            "{fd} vs {d}"
        );
        let fd = (slip.psi(alpha + h, v).unwrap() - slip.psi(alpha - h, v).unwrap()) / (2.0 * h);
        let d = slip.dpsi_dalpha(alpha, v);
        assert!((fd - d).abs() <= 1e-6 * (d.abs() + 1.0), "{fd} vs {d}");
    }
}

#[test]
fn generic_update_with_finite_difference_derivative() {
    // A user aging law without d2psi: the forward-difference Newton still converges to 1e-10.
    #[derive(Clone)]
    struct UserAging(f64);
    impl StateLaw for UserAging {
        fn dpsi_dalpha(&self, alpha: f64, v: f64) -> f64 {
            v / self.0 - (-alpha).exp()
        }
    }
    let closed = Aging::new(1e-5).unwrap();
    for &(a0, v, tau) in &[
        (-10.0, 2e-4, 1.5e-3),
        (30.0, 1e-9, 1e3),
        (-500.0, 1e3, 1e-12),
        (1e3, 1e3, 1e3),
    ] {
        let g = UserAging(1e-5).update(a0, v, tau).unwrap();
        let c = closed.update(a0, v, tau).unwrap();
        assert!(
            (g - c).abs() <= 1e-10 * c.abs().max(1.0),
            "{a0},{v},{tau}: {g} vs {c}"
        );
    }
}

/// The built-in laws' `∂ψ/∂α` pass the probe on its grid (they skip it in
/// `check_monotone`, so run the probe itself), monotone user laws pass, and a law with
/// `∂ψ/∂α = 100 sin α` (several roots of the update) is caught with the decreasing pair.
#[test]
fn monotonicity_probe() {
    use rsf_state::{probe_monotonicity, PROBE_ALPHA_MAX, PROBE_ALPHA_MIN};
    probe_monotonicity(&Aging::new(1e-5).unwrap()).unwrap();
    probe_monotonicity(&Slip::new(1e-5).unwrap()).unwrap();
    probe_monotonicity(&Discontinuous).unwrap();
    #[derive(Clone)]
    struct Wavy;
    impl StateLaw for Wavy {
        fn dpsi_dalpha(&self, alpha: f64, _v: f64) -> f64 {
            100.0 * alpha.sin()
        }
    }
    match Wavy.check_monotone() {
        Err(Error::NotMonotone {
            alpha_lo,
            alpha_hi,
            dpsi_lo,
            dpsi_hi,
            ..
        }) => {
            assert!(alpha_lo < alpha_hi && dpsi_lo > dpsi_hi);
            assert!((PROBE_ALPHA_MIN..=PROBE_ALPHA_MAX).contains(&alpha_lo));
            assert_eq!(dpsi_lo, 100.0 * alpha_lo.sin());
        }
        other => panic!("expected NotMonotone, got {other:?}"),
    }
    // NaN on the grid is reported, not compared.
    #[derive(Clone)]
    struct NanAbove(f64);
    impl StateLaw for NanAbove {
        fn dpsi_dalpha(&self, alpha: f64, _v: f64) -> f64 {
            if alpha > self.0 {
                f64::NAN
            } else {
                alpha
            }
        }
    }
    assert!(matches!(
        NanAbove(3.0).check_monotone(),
        Err(Error::NanDerivative { .. })
    ));
    // Saturating at ±∞ is monotone.
    #[derive(Clone)]
    struct Steep;
    impl StateLaw for Steep {
        fn dpsi_dalpha(&self, alpha: f64, v: f64) -> f64 {
            (v + 1.0) * alpha.powi(3).exp().min(f64::INFINITY)
        }
    }
    Steep.check_monotone().unwrap();
}
