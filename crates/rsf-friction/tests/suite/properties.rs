//! Property tests of the friction potentials: convexity, derivatives, exact local
//! minimiser, extreme inputs, and the friction laws' steady state.

use proptest::prelude::*;
use rsf_friction::{
    AsinhLaw, AsinhPotential, ConvexPotential, DieterichRuina, DieterichRuinaPotential, Error,
    FrictionLaw, RateStateParams, StateDependentTresca, Tresca, TrescaPotential,
};

const EPS: f64 = f64::EPSILON;

fn paper() -> RateStateParams {
    RateStateParams {
        mu0: 0.6,
        a: 0.010,
        b: 0.015,
        v0: 1e-6,
        l: 1e-5,
        sigma_n: 49_050.0,
    }
}

/// `ln V_m` from 1e-4343 m/s (far below f64) up to ~150 m/s; κ = aσ̄_n over 11 decades.
fn ln_vm() -> impl Strategy<Value = f64> {
    prop_oneof![-1e4..-700.0, -700.0..5.0_f64]
}
fn kappa() -> impl Strategy<Value = f64> {
    (-3.0..8.0_f64).prop_map(|e| 10f64.powf(e))
}
/// Slip rates: either absolute (1e-320 … 1e3 m/s) or relative to V_m (V_m e^{±40}).
fn slip_rate(ln_vm: f64) -> impl Strategy<Value = f64> {
    let abs = (-736.0..6.9_f64).prop_map(f64::exp);
    let rel = (-40.0..40.0_f64).prop_map(move |d| (ln_vm + d).min(6.9).exp());
    prop_oneof![abs, rel].prop_filter("positive", |v| *v > 0.0)
}

fn dr() -> impl Strategy<Value = (DieterichRuinaPotential, f64)> {
    (ln_vm(), kappa()).prop_map(|(l, k)| (DieterichRuinaPotential::new(l, k), l))
}
fn asinh() -> impl Strategy<Value = (AsinhPotential, f64)> {
    (ln_vm(), kappa()).prop_map(|(l, k)| (AsinhPotential::new(l, k), l))
}

/// The Dieterich–Ruina and the asinh potential of the same `ln V_m = l` and `κ = k`, and `l`.
fn both(l: f64, k: f64) -> (DieterichRuinaPotential, AsinhPotential, f64) {
    (
        DieterichRuinaPotential::new(l, k),
        AsinhPotential::new(l, k),
        l,
    )
}
fn dr_and_asinh() -> impl Strategy<Value = (DieterichRuinaPotential, AsinhPotential, f64)> {
    (ln_vm(), kappa()).prop_map(|(l, k)| both(l, k))
}

/// Midpoint convexity `ϕ((x+y)/2) ≤ (ϕ(x)+ϕ(y))/2`, up to rounding of the values.
fn check_convex<P: ConvexPotential>(p: &P, x: f64, y: f64) -> Result<(), TestCaseError> {
    let (fx, fy, fm) = (p.value(x), p.value(y), p.value(0.5 * (x + y)));
    prop_assert!(fx.is_finite() && fy.is_finite() && fm.is_finite());
    prop_assert!(fx >= 0.0 && fy >= 0.0 && fm >= 0.0);
    let tol = 1e-12 * (fx + fy) + f64::MIN_POSITIVE;
    prop_assert!(
        fm <= 0.5 * (fx + fy) + tol,
        "ϕ({x})={fx}, ϕ({y})={fy}, mid {fm}"
    );
    Ok(())
}

/// `slope` equals the central difference of `value`. The tolerance is the sum of the
/// truncation error `h·sup ϕ''` (ϕ'' may jump, so only first order is assumed), the
/// cancellation error `ε ϕ/h` and `1e-6` relative.
fn check_slope<P: ConvexPotential>(p: &P, v: f64, kappa: f64) -> Result<(), TestCaseError> {
    let h = 1e-6 * v;
    let (f1, f2) = (p.value(v + h), p.value(v - h));
    let fd = (f1 - f2) / (2.0 * h);
    let s = p.slope(v);
    prop_assert!(s.is_finite() && s >= 0.0);
    let tol = 1e-6 * s + kappa * h / (v - h) + 1e3 * EPS * f1 / h;
    prop_assert!(
        (fd - s).abs() <= tol,
        "v={v}: fd {fd} vs slope {s} (tol {tol})"
    );
    Ok(())
}

/// `curvature ≥ 0`, finite, and equal to the difference quotient of `slope` where smooth.
fn check_curvature<P: ConvexPotential>(p: &P, v: f64, ln_vm: f64) -> Result<(), TestCaseError> {
    if let Some(c) = p.curvature(v) {
        prop_assert!(c >= 0.0 && c.is_finite(), "curvature {c}");
        // away from the cutoff kink, compare with the slope's difference quotient
        if (v.ln() - ln_vm).abs() > 1e-3 && v > 1e-300 {
            let h = 1e-7 * v;
            let fd = (p.slope(v + h) - p.slope(v - h)) / (2.0 * h);
            let tol = 1e-5 * c + 1e3 * EPS * p.slope(v + h) / h;
            prop_assert!((fd - c).abs() <= tol, "v={v}: fd {fd} vs curvature {c}");
        }
    }
    Ok(())
}

/// Optimality `0 ∈ a s − r + w ∂ϕ(s)`: for `s > 0`, `|a s − r + w ϕ'(s)|` below `1e-10`
/// relative to the magnitude of its terms, plus the floor `8ε·wκ(|ln s| + |ln V_m|)` at which
/// `ϕ'(s) = κ ln(s/V_m)` can be evaluated at all when `V_m` is not representable (docs/math.md
/// §7) and the rounding of `s` itself (relevant for subnormal `s`); for `s = 0`, `r ≤ w ϕ'(0+)` or the root underflows.
fn check_minimizer<P: ConvexPotential>(
    p: &P,
    a: f64,
    r: f64,
    w: f64,
    kappa: f64,
    ln_vm: f64,
) -> Result<(), TestCaseError> {
    let s = p.minimize(a, r, w);
    prop_assert!(s.is_finite() && s >= 0.0, "s = {s}");
    if s == 0.0 {
        // Either sticking (r ≤ w ϕ'(0+)) or the exact root is below the smallest
        // subnormal, so 0 is its correctly rounded value.
        let t = f64::from_bits(1);
        let stick = r <= w * p.slope(0.0) * (1.0 + 1e-12);
        let underflow = r <= (a * t + w * p.slope(t)) * (1.0 + 1e-10);
        prop_assert!(stick || underflow, "r={r}");
        return Ok(());
    }
    let ws = w * p.slope(s);
    let res = a * s - r + ws;
    let floor = 8.0 * EPS * w * kappa * (s.ln().abs() + ln_vm.abs());
    // s itself is rounded: one ulp of s (huge relative to s when s is subnormal) moves the
    // residual by about a·ulp + w(ϕ'(s⁺) − ϕ'(s⁻)) (s± the neighbouring doubles).
    let (up, down) = (
        f64::from_bits(s.to_bits() + 1),
        f64::from_bits(s.to_bits() - 1),
    );
    let floor = floor + a * (up - down) + w * (p.slope(up) - p.slope(down)).abs();
    let tol = 1e-10 * (a * s + r + ws) + floor;
    prop_assert!(
        res.abs() <= tol,
        "a={a} r={r} w={w}: s={s}, res {res}, tol {tol}"
    );
    Ok(())
}

/// [`check_slope`] (with `kappa`) at `v` where `v` is above 1e-300, and
/// [`check_curvature`] with `ln_vm`.
fn check_derivatives<P: ConvexPotential>(
    p: &P,
    v: f64,
    (kappa, ln_vm): (f64, f64),
) -> Result<(), TestCaseError> {
    if v > 1e-300 {
        check_slope(p, v, kappa)?;
    }
    check_curvature(p, v, ln_vm)
}

/// [`check_minimizer`] at `r = a V_m e^d` (`ln_vm` = ln V_m: from below the cutoff to far
/// above for `d` in −5 … 30), where that `r` is positive and finite.
fn check_minimizer_near_cutoff<P: ConvexPotential>(
    p: &P,
    (kappa, ln_vm): (f64, f64),
    a: f64,
    d: f64,
    w: f64,
) -> Result<(), TestCaseError> {
    let r = a * (ln_vm + d).exp();
    prop_assume!(r > 0.0 && r.is_finite());
    check_minimizer(p, a, r, w, kappa, ln_vm)
}

fn pos(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo..hi).prop_map(|e: f64| 10f64.powf(e))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    /// Both potentials at each `(ln V_m, κ)`: convex.
    #[test]
    fn dr_and_asinh_convex((p, q, l) in dr_and_asinh(), y in -40.0..40.0_f64, z in -40.0..40.0_f64) {
        let (a, b) = ((l + y).min(6.9).exp(), (l + z).min(6.9).exp());
        check_convex(&p, a, b)?;
        check_convex(&p, 0.0, b)?;
        check_convex(&q, a, b)?;
        check_convex(&q, 0.0, b)?;
    }

    /// Both potentials at each `(ln V_m, κ)`: the exact minimiser.
    #[test]
    fn dr_and_asinh_minimizer((p, q, l) in dr_and_asinh(), a in pos(-3.0, 12.0), r in pos(-30.0, 8.0), w in pos(-6.0, 1.0)) {
        check_minimizer(&p, a, r, w, p.kappa(), l)?;
        check_minimizer(&q, a, r, w, q.kappa(), l)?;
    }

    /// Both potentials at each `(ln V_m, κ)`: the minimiser for `r = a V_m e^d`, from below
    /// the cutoff to far above.
    #[test]
    fn dr_and_asinh_minimizer_near_cutoff((p, q, l) in (-700.0..-10.0_f64, kappa()).prop_map(|(l, k)| both(l, k)),
                                          a in pos(-3.0, 12.0), d in -5.0..30.0_f64, w in pos(-6.0, 1.0)) {
        check_minimizer_near_cutoff(&p, (p.kappa(), l), a, d, w)?;
        check_minimizer_near_cutoff(&q, (q.kappa(), l), a, d, w)?;
    }

    #[test]
    fn dr_derivatives((p, l) in dr(), d in -40.0..40.0_f64) {
        let v = (l + d).min(6.9).exp();
        check_derivatives(&p, v, (p.kappa(), l))?;
    }

    #[test]
    fn asinh_derivatives(((p, _), v) in asinh().prop_flat_map(|(p, l)| (Just((p, l)), slip_rate(l)))) {
        check_derivatives(&p, v, (p.kappa(), f64::NEG_INFINITY))?;
    }

    #[test]
    fn asinh_derivatives_rel((p, l) in asinh(), d in -40.0..40.0_f64) {
        let v = (l + d).min(6.9).exp();
        check_derivatives(&p, v, (p.kappa(), f64::NEG_INFINITY))?;
    }

    #[test]
    fn tresca_properties(t in pos(-3.0, 8.0), x in pos(-300.0, 3.0), y in pos(-300.0, 3.0),
                         a in pos(-3.0, 12.0), r in pos(-30.0, 8.0), w in pos(-6.0, 1.0)) {
        let p = TrescaPotential::new(t);
        check_convex(&p, x, y)?;
        check_slope(&p, x, 0.0)?;
        prop_assert_eq!(p.curvature(x), Some(0.0));
        prop_assert_eq!(p.curvature(0.0), None);
        check_minimizer(&p, a, r, w, 0.0, 0.0)?;
    }

    /// Extreme inputs: never NaN/inf/panic.
    #[test]
    fn extreme_inputs_are_finite(alpha in -1e3..1e3_f64, v in pos(-320.0, 3.0), a in pos(-300.0, 300.0),
                                 r in pos(-300.0, 300.0), w in pos(-300.0, 300.0)) {
        let dr = DieterichRuina::new(paper()).unwrap();
        let asl = AsinhLaw::new(paper()).unwrap();
        let p1 = dr.potential(alpha);
        let p2 = asl.potential(alpha);
        for (val, slope, curv, s, mu) in [
            (p1.value(v), p1.slope(v), p1.curvature(v).unwrap_or(0.0), p1.minimize(a, r, w), dr.friction_coefficient(v, alpha)),
            (p2.value(v), p2.slope(v), p2.curvature(v).unwrap_or(0.0), p2.minimize(a, r, w), asl.friction_coefficient(v, alpha)),
        ] {
            prop_assert!(val.is_finite() && slope.is_finite() && curv.is_finite() && s.is_finite() && mu.is_finite());
            prop_assert!(val >= 0.0 && slope >= 0.0 && curv >= 0.0 && s >= 0.0);
        }
    }

    /// The friction coefficient is the slope over σ̄_n, and at steady state θ = L/V it is
    /// μ_ss = μ0 + (a − b) ln(V/V0).
    #[test]
    fn coefficient_and_steady_state(lv in -30.0..0.0_f64, mu0 in 0.1..0.9_f64, a in 0.001..0.05_f64,
                                    b in 0.0..0.05_f64, sigma in pos(3.0, 8.0)) {
        let v = lv.exp();
        let params = RateStateParams { mu0, a, b, v0: 1e-6, l: 1e-5, sigma_n: sigma };
        let law = DieterichRuina::new(params).unwrap();
        let alpha_ss = (params.l / v).ln();
        let mu_ss = mu0 + (a - b) * (v / params.v0).ln();
        let mu = law.friction_coefficient(v, alpha_ss);
        if mu_ss > 0.0 {
            prop_assert!((mu - mu_ss).abs() <= 1e-12 * (1.0 + mu_ss.abs()), "{mu} vs {mu_ss}");
            prop_assert!((params.steady_state_friction(v) - mu_ss).abs() <= 1e-14);
        }
        let p = law.potential(alpha_ss);
        prop_assert!((p.slope(v) - sigma * mu).abs() <= 1e-9 * sigma * mu.abs().max(1e-3));
        // asinh law: asinh(V/2V_m) → ln(V/V_m) for V ≫ V_m
        let asl = AsinhLaw::new(params).unwrap();
        let mu2 = asl.friction_coefficient(v, alpha_ss);
        if mu_ss > 20.0 * a {
            prop_assert!((mu2 - mu_ss).abs() <= 1e-12 + a * 1e-8, "{mu2} vs {mu_ss}");
        }
    }

    /// The D-vector minimiser is collinear with r and solves the vector optimality condition.
    #[test]
    fn vector_minimizer(alpha in -20.0..20.0_f64, r0 in -1e5..1e5_f64, r1 in -1e5..1e5_f64, a in pos(0.0, 12.0)) {
        let law = DieterichRuina::new(paper()).unwrap();
        let p = law.potential(alpha);
        let v = p.minimize_vector(a, [r0, r1], 0.2);
        let s = v[0].hypot(v[1]);
        // v = s r/|r| and a v − r + w ϕ'(s) v/s = 0
        if s > 0.0 {
            let scale = 0.2 * p.slope(s) / s;
            for (vi, ri) in v.iter().zip([r0, r1]) {
                let res = a * vi - ri + scale * vi;
                prop_assert!(res.abs() <= 1e-10 * (ri.abs() + a * vi.abs()) + 1e-9, "{res}");
            }
        }
        let mut out = [0.0; 2];
        p.minimize_block(a, &[r0, r1], 0.2, &mut out);
        prop_assert_eq!(out, v);
    }
}

#[test]
fn parameters_are_validated() {
    let good = paper();
    assert!(DieterichRuina::new(good).is_ok());
    for (name, p) in [
        ("a", RateStateParams { a: 0.0, ..good }),
        (
            "a",
            RateStateParams {
                a: f64::NAN,
                ..good
            },
        ),
        ("l", RateStateParams { l: -1.0, ..good }),
        ("v0", RateStateParams { v0: 0.0, ..good }),
        (
            "sigma_n",
            RateStateParams {
                sigma_n: f64::INFINITY,
                ..good
            },
        ),
        (
            "mu0",
            RateStateParams {
                mu0: f64::NAN,
                ..good
            },
        ),
        (
            "b",
            RateStateParams {
                b: f64::INFINITY,
                ..good
            },
        ),
    ] {
        match AsinhLaw::new(p) {
            Err(Error::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{name}: {other:?}"),
        }
        assert!(DieterichRuina::new(p).is_err());
    }
    assert!(Tresca::new(-0.1, 1.0).is_err());
    assert!(Tresca::new(0.5, 0.0).is_err());
}

#[test]
fn tresca_is_stateless_and_sticks() {
    let law = Tresca::new(0.6, 1e5).unwrap();
    assert!(!law.uses_state());
    let p = law.potential(123.0);
    assert_eq!(p.stick_threshold(), 6e4);
    assert_eq!(p.minimize(1.0, 5e4, 1.0), 0.0);
    assert_eq!(p.minimize(2.0, 7e4, 1.0), 5e3);
}

#[test]
fn dieterich_ruina_cutoff_and_underflow() {
    let law = DieterichRuina::new(paper()).unwrap();
    // α = 1e3: ln V_m ≈ −1.5e3, V_m not representable; everything stays finite.
    let p = law.potential(1e3);
    assert!(p.ln_cutoff_velocity() < -1000.0);
    assert_eq!(p.value(0.0), 0.0);
    assert_eq!(p.slope(0.0), 0.0);
    let v: f64 = 1e-300;
    let expected = p.kappa() * (v.ln() - p.ln_cutoff_velocity());
    assert!((p.slope(v) - expected).abs() <= 1e-12 * expected);
    // Below the cutoff the potential vanishes.
    let q = law.potential(-1e3);
    assert_eq!(q.value(1e3), 0.0);
    assert_eq!(q.minimize(2.0, 4.0, 1.0), 2.0);
    // The closed form and the definition agree for a representable V_m.
    let r = law.potential(-10.0);
    let vm = r.ln_cutoff_velocity().exp();
    let v = 3.0 * vm;
    let direct = r.kappa() * (v * (v / vm).ln() - v + vm);
    assert!((r.value(v) - direct).abs() <= 1e-12 * direct);
    assert_eq!(r.curvature(vm * (1.0 - 1e-12)), Some(0.0));
}

/// What each law expects the state to be, for the simulation's consistency check.
#[test]
fn laws_declare_their_state_variable() {
    use rsf_friction::StateVariable;
    assert_eq!(
        DieterichRuina::new(paper()).unwrap().state_variable(),
        StateVariable::LogTheta
    );
    assert_eq!(
        AsinhLaw::new(paper()).unwrap().state_variable(),
        StateVariable::LogTheta
    );
    let mu = StateDependentTresca::new(|a: f64| 0.6 + 0.01 * a, 1e5).unwrap();
    assert_eq!(mu.state_variable(), StateVariable::LogTheta);
    assert_eq!(
        mu.with_state_variable(StateVariable::Theta)
            .state_variable(),
        StateVariable::Theta
    );
}

/// A NaN or infinite traction is never "stuck": every built-in potential's scalar
/// minimiser returns NaN for a NaN `r`, and the vector and block minimisers NaN in every
/// component for a traction with a NaN or infinite component (where they used to return
/// the finite slip rate 0) — in states of stick and of slip, with and without weight.
#[test]
fn a_non_finite_traction_is_never_stuck() {
    fn check<P: ConvexPotential>(name: &str, p: &P) {
        for w in [0.0, 0.2] {
            let s = p.minimize(1e3, f64::NAN, w);
            assert!(s.is_nan(), "{name}: minimize(NaN) = {s}");
            for r in [
                [f64::NAN, 0.0],
                [0.0, f64::NAN],
                [f64::INFINITY, f64::NAN],
                [f64::NEG_INFINITY, 1.0],
                [f64::NAN, f64::NAN],
            ] {
                let v = p.minimize_vector(1e3, r, w);
                assert!(v.iter().all(|x| x.is_nan()), "{name}: {r:?} → {v:?}");
                let mut out = [0.0; 2];
                p.minimize_block(1e3, &r, w, &mut out);
                assert!(out.iter().all(|x| x.is_nan()), "{name}: {r:?} → {out:?}");
            }
            // Finite tractions keep their answers: 0 at r = 0, finite otherwise.
            assert_eq!(p.minimize_vector(1e3, [0.0, 0.0], w), [0.0, 0.0]);
            assert!(p.minimize(1e3, 1.0, w).is_finite());
        }
    }
    let dr = DieterichRuina::new(paper()).unwrap();
    let asinh = AsinhLaw::new(paper()).unwrap();
    for alpha in [-30.0, 0.0, 30.0] {
        check("Dieterich–Ruina", &dr.potential(alpha));
        check("regularised", &asinh.potential(alpha));
        check(
            "slip-scaled",
            &rsf_friction::SlipScaled::new(asinh.potential(alpha), 2.0).unwrap(),
        );
    }
    check("Tresca", &Tresca::new(0.6, 1e5).unwrap().potential(0.0));
    check("Tresca potential", &TrescaPotential::new(6e4));
}
