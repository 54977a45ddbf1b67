//! Every built-in law that says it is proportional to its normal stress
//! (`FrictionLaw::proportional_to_normal_stress`, which a fault inside the body relies on
//! to scale it by a changing σ̄_n) is: with σ̄_n doubled, the potential's value and slope
//! double at sampled slip rates and states over many orders of magnitude.
use rsf_friction::{
    AsinhLaw, ConvexPotential, DieterichRuina, FrictionLaw, RateStateParams, StateDependentTresca,
    Tresca,
};

fn check<L: FrictionLaw>(name: &str, at: impl Fn(f64) -> L) {
    let (one, two) = (at(3e6), at(6e6));
    assert!(one.proportional_to_normal_stress(), "{name}");
    assert_eq!(two.normal_stress(), Some(6e6), "{name}");
    let mut checked = 0;
    for alpha in [-20.0, -3.0, 0.0, 2.5, 11.0] {
        let (p1, p2) = (one.potential(alpha), two.potential(alpha));
        for e in -14..=1 {
            let v = 10f64.powi(e) * 1.7;
            for (a, b) in [(p1.value(v), p2.value(v)), (p1.slope(v), p2.slope(v))] {
                assert!(
                    (b - 2.0 * a).abs() <= 1e-13 * b.abs(),
                    "{name}: α = {alpha}, V = {v:e}: {b:e} vs 2 × {a:e}"
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 160);
}

#[test]
fn the_built_in_laws_scale_with_their_normal_stress() {
    let params = |sigma_n| RateStateParams {
        mu0: 0.6,
        a: 0.01,
        b: 0.015,
        v0: 1e-6,
        l: 1e-5,
        sigma_n,
    };
    check("Dieterich–Ruina", |s| {
        DieterichRuina::new(params(s)).unwrap()
    });
    check("regularised", |s| AsinhLaw::new(params(s)).unwrap());
    check("Tresca", |s| Tresca::new(0.4, s).unwrap());
    check("state-dependent Tresca", |s| {
        StateDependentTresca::new(|alpha: f64| 0.3 + 0.01 * alpha.tanh(), s).unwrap()
    });
}
