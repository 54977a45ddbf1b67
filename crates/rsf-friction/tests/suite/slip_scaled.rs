//! `SlipScaled`: the potential of a boundary velocity v when the slip rate is V = s|v|
//! (antisymmetry plane, docs/seas-bp1.md). Checked against finite differences and the
//! optimality condition, not against the code's own output.
use rsf_friction::*;

fn potentials() -> Vec<AsinhPotential> {
    vec![
        AsinhPotential::new((1e-9f64).ln() - 20.0, 0.01 * 50e6),
        AsinhPotential::new((1e-6f64).ln(), 0.025 * 50e6),
    ]
}

#[test]
fn derivatives_match_finite_differences_and_the_slip_rate_law() {
    for phi in potentials() {
        let s = 2.0;
        let psi = SlipScaled::new(phi, s).unwrap();
        for v in [1e-10, 1e-6, 1e-3, 0.5, 3.0] {
            // ψ'(v) = ϕ'(2v): the traction at slip rate V = 2v.
            assert_eq!(psi.slope(v), phi.slope(s * v));
            let h = 1e-6 * v;
            let fd = (psi.value(v + h) - psi.value(v - h)) / (2.0 * h);
            assert!(
                (fd - psi.slope(v)).abs() <= 1e-6 * psi.slope(v).abs(),
                "v = {v}: {fd} vs {}",
                psi.slope(v)
            );
            let fd2 = (psi.slope(v + h) - psi.slope(v - h)) / (2.0 * h);
            let c = psi.curvature(v).unwrap();
            assert!((fd2 - c).abs() <= 1e-5 * c.abs(), "v = {v}: {fd2} vs {c}");
        }
    }
}

#[test]
fn minimiser_satisfies_the_optimality_condition() {
    for phi in potentials() {
        let psi = SlipScaled::new(phi, 2.0).unwrap();
        for (a, r, w) in [(1e9, 4e7, 25.0), (3e5, 1e6, 1.0), (1.0, 1e3, 1e-3)] {
            let x = psi.minimize(a, r, w);
            assert!(x > 0.0);
            // a x − r + w ψ'(x) = 0.
            let res = a * x - r + w * psi.slope(x);
            let scale = r.abs() + (a * x).abs() + (w * psi.slope(x)).abs();
            assert!(res.abs() <= 1e-9 * scale, "residual {res} of {scale}");
        }
        assert_eq!(psi.minimize(1.0, -1.0, 1.0), 0.0);
    }
}

#[test]
fn factor_one_is_the_inner_potential_and_bad_factors_are_errors() {
    let phi = potentials()[0];
    let psi = SlipScaled::new(phi, 1.0).unwrap();
    for v in [0.0, 1e-9, 1.0] {
        assert_eq!(psi.value(v), phi.value(v));
        assert_eq!(psi.slope(v), phi.slope(v));
    }
    assert_eq!(psi.minimize(2.0, 3.0, 4.0), phi.minimize(2.0, 3.0, 4.0));
    for s in [0.0, -2.0, f64::NAN, f64::INFINITY] {
        let e = SlipScaled::new(phi, s).unwrap_err().to_string();
        assert!(e.contains("slip_factor"), "{e}");
    }
}
