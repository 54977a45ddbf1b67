//! Properties of our DC3D that do not rely on Okada's routine: the displacement jump
//! across the rectangle is the dislocation (our reading of the sign conventions), the
//! free surface is traction-free, the derivatives are those of the displacement (finite
//! differences), the stress is in equilibrium, the vertical fault is the limit of steep
//! dips, and the singular points behave as documented.
use proptest::prelude::*;
use rsf_halfspace::{Error, Medium, Okada, Rectangle};

const ALPHA: f64 = 2.0 / 3.0;

fn okada(depth: f64, dip: f64, al: [f64; 2], aw: [f64; 2]) -> Okada {
    Okada::new(ALPHA, Rectangle::new(depth, dip, al, aw).unwrap()).unwrap()
}

/// `u(hanging wall) − u(footwall) = U1 e_s + U2 e_d + U3 n` just off the middle of the
/// rectangle, for several dips.
#[test]
fn displacement_jump_is_the_dislocation() {
    for dip in [90.0, 60.0, 30.0, 120.0] {
        let ok = okada(5.0, dip, [-2.0, 3.0], [-1.0, 1.5]);
        let rect = ok.rectangle();
        let [es, ed, n] = rect.frame();
        let c = rect.point(0.3, 0.2);
        // Beyond the snapping tolerance (1e-6 × 5) and small against the distance to the
        // edges (≥ 0.8): the jump is then the dislocation to O(h).
        let h = 1e-5;
        let side = |s: f64| [c[0] + s * n[0], c[1] + s * n[1], c[2] + s * n[2]];
        let disl = [0.7, -0.4, 0.25];
        let plus = ok.deformation(side(h), disl).unwrap();
        let minus = ok.deformation(side(-h), disl).unwrap();
        for i in 0..3 {
            let want = disl[0] * es[i] + disl[1] * ed[i] + disl[2] * n[i];
            let got = plus.u[i] - minus.u[i];
            assert!(
                (got - want).abs() < 1e-4,
                "dip {dip}: component {i} jump {got}, dislocation {want}"
            );
        }
    }
}

fn stress_at(ok: &Okada, p: [f64; 3], disl: [f64; 3]) -> [[f64; 3]; 3] {
    let m = Medium::new(1.0, 1.0).unwrap(); // α = 2/3
    m.stress(&ok.deformation(p, disl).unwrap().grad)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// σ·e_z = 0 on z = 0, relative to the stress's scale.
    #[test]
    fn free_surface_is_traction_free(
        x in -8.0..8.0f64, y in -8.0..8.0f64, dip in 1.0..179.0f64, depth in 2.5..6.0f64,
        d1 in -1.0..1.0f64, d2 in -1.0..1.0f64, d3 in -1.0..1.0f64,
    ) {
        let ok = okada(depth, dip, [-2.0, 2.0], [-1.5, 1.0]);
        let s = stress_at(&ok, [x, y, 0.0], [d1, d2, d3]);
        let scale = s.iter().flatten().fold(1e-300f64, |m, v| m.max(v.abs()));
        for i in 0..3 {
            prop_assert!(s[i][2].abs() <= 1e-12 * scale, "sigma_{}z = {} (scale {})", i, s[i][2], scale);
        }
    }

    /// ∇u against central differences of u, and ∇·σ = 0 by central differences of σ:
    /// step 1e-4 (truncation O(h²/ℓ²) ≤ 1e-6 of the scale at ℓ ≥ 0.3 from the rectangle's
    /// edges, where the error of 1e-3 steps reached 2e-4; round-off of the corner sums'
    /// cancellation over 2h below 1e-8).
    #[test]
    fn derivatives_and_equilibrium(
        x in -6.0..6.0f64, y in -6.0..6.0f64, z in -9.0..-0.5f64, dip in 10.0..170.0f64,
        d1 in -1.0..1.0f64, d2 in -1.0..1.0f64, d3 in -1.0..1.0f64,
    ) {
        // Within a few degrees of vertical the general forms lose digits as 1e-16/cos²δ
        // (as DC3D's; see vertical_fault_is_the_limit_of_steep_dips), which the 2h of
        // the differences would magnify.
        prop_assume!((dip - 90.0).abs() > 3.0);
        let ok = okada(4.0, dip, [-2.0, 2.0], [-1.0, 1.0]);
        let p = [x, y, z];
        // Stay away from the rectangle (its plane within 0.3 of it).
        let rect = ok.rectangle();
        let [es, ed, n] = rect.frame();
        let o = rect.point(0.0, 0.0);
        let rel = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
        let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        prop_assume!(dot(&rel, &n).abs() > 0.3 || dot(&rel, &es).abs() > 2.3 || dot(&rel, &ed).abs() > 1.3);
        let disl = [d1, d2, d3];
        let d = ok.deformation(p, disl).unwrap();
        let h = 1e-4;
        let gscale = d.grad.iter().flatten().fold(1e-300f64, |m, v| m.max(v.abs()));
        let mut div = [0.0; 3];
        let s0 = stress_at(&ok, p, disl);
        let sscale = s0.iter().flatten().fold(1e-300f64, |m, v| m.max(v.abs()));
        for j in 0..3 {
            let mut pp = p;
            let mut pm = p;
            pp[j] += h;
            pm[j] -= h;
            let up = ok.deformation(pp, disl).unwrap();
            let um = ok.deformation(pm, disl).unwrap();
            for i in 0..3 {
                let fd = (up.u[i] - um.u[i]) / (2.0 * h);
                prop_assert!((fd - d.grad[i][j]).abs() <= 1e-5 * gscale,
                    "du{}/dx{}: {} vs finite difference {}", i, j, d.grad[i][j], fd);
            }
            let sp = stress_at(&ok, pp, disl);
            let sm = stress_at(&ok, pm, disl);
            for i in 0..3 {
                div[i] += (sp[i][j] - sm[i][j]) / (2.0 * h);
            }
        }
        for i in 0..3 {
            prop_assert!(div[i].abs() <= 1e-4 * sscale, "div sigma_{} = {} (scale {})", i, div[i], sscale);
        }
    }
}

/// The vertical fault (`cos δ = 0`, its own forms of the part-B integrals) is the limit
/// of steep dips: at δ = 90° − 10⁻³ (cos δ = 1.7·10⁻⁵) the fields differ by O(cos δ).
/// (Closer to vertical, the general forms lose digits as 10⁻¹⁶/cos²δ, in DC3D as here.)
#[test]
fn vertical_fault_is_the_limit_of_steep_dips() {
    let vertical = okada(3.0, 90.0, [-2.0, 2.0], [-2.0, 1.0]);
    let steep = okada(3.0, 90.0 - 1e-3, [-2.0, 2.0], [-2.0, 1.0]);
    for p in [
        [0.5, 1.0, -2.0],
        [3.0, -2.0, 0.0],
        [-1.0, 0.4, -4.5],
        [0.0, 5.0, -1.0],
    ] {
        let a = vertical.unit_responses(p).unwrap();
        let b = steep.unit_responses(p).unwrap();
        for c in 0..3 {
            let scale = a[c]
                .grad
                .iter()
                .flatten()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            for i in 0..3 {
                for j in 0..3 {
                    assert!(
                        (a[c].grad[i][j] - b[c].grad[i][j]).abs() < 1e-4 * scale,
                        "point {p:?} component {c}: {} vs {}",
                        a[c].grad[i][j],
                        b[c].grad[i][j]
                    );
                }
                let uscale = a[c].u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                assert!((a[c].u[i] - b[c].u[i]).abs() < 1e-4 * uscale);
            }
        }
    }
}

/// On the extension of an edge beyond the rectangle (`R + ξ → 0` in some corners) the
/// result is finite and continuous with the points nearby.
#[test]
fn negative_extension_of_an_edge_is_regular() {
    let ok = okada(3.0, 60.0, [-1.0, 2.0], [-1.0, 1.0]);
    let rect = *ok.rectangle();
    // On the line of the bottom edge, beyond its ξ = al1 end.
    let on = rect.point(-2.5, -1.0);
    let a = ok.deformation(on, [1.0, 1.0, 1.0]).unwrap();
    let [_, _, n] = rect.frame();
    let h = 1e-5;
    let off = [on[0] + h * n[0], on[1] + h * n[1], on[2] + h * n[2]];
    let b = ok.deformation(off, [1.0, 1.0, 1.0]).unwrap();
    for i in 0..3 {
        assert!((a.u[i] - b.u[i]).abs() < 1e-4, "{:?} vs {:?}", a.u, b.u);
        for j in 0..3 {
            assert!(
                (a.grad[i][j] - b.grad[i][j]).abs() < 1e-3,
                "{:?} vs {:?}",
                a.grad,
                b.grad
            );
        }
    }
}

#[test]
fn errors_on_user_input() {
    let ok = okada(3.0, 60.0, [-1.0, 2.0], [-1.0, 1.0]);
    assert!(matches!(
        ok.deformation([0.0, 0.0, 1e-3], [1.0, 0.0, 0.0]),
        Err(Error::AboveSurface { .. })
    ));
    let corner = ok.rectangle().point(-1.0, 1.0);
    assert!(matches!(
        ok.deformation(corner, [1.0, 0.0, 0.0]),
        Err(Error::OnEdge { .. })
    ));
    let edge = ok.rectangle().point(0.5, -1.0);
    assert!(matches!(ok.unit_responses(edge), Err(Error::OnEdge { .. })));
    assert!(ok
        .deformation([f64::NAN, 0.0, -1.0], [1.0, 0.0, 0.0])
        .is_err());
    assert!(ok
        .deformation([0.0, 0.0, -1.0], [f64::INFINITY, 0.0, 0.0])
        .is_err());
    assert!(Rectangle::new(3.0, 60.0, [2.0, -1.0], [-1.0, 1.0]).is_err());
    assert!(Rectangle::new(3.0, 60.0, [-1.0, 2.0], [-1.0, f64::NAN]).is_err());
    assert!(Rectangle::new(1e308, 90.0, [-1e308, 1e308], [-1.0, 0.0]).is_err());
    assert!(matches!(
        Rectangle::new(0.5, 90.0, [-1.0, 2.0], [-1.0, 1.0]),
        Err(Error::SourceAboveSurface { .. })
    ));
    assert!(Okada::new(1.0, *ok.rectangle()).is_err());
    assert!(Okada::new(f64::NAN, *ok.rectangle()).is_err());
    assert!(Medium::new(1.0, 0.0).is_err());
    assert!(Medium::from_shear_poisson(1.0, 0.5).is_err());
    let m = Medium::from_shear_poisson(3e10, 0.25).unwrap();
    assert!((m.lambda() - 3e10).abs() < 1e-3 && (m.alpha() - 2.0 / 3.0).abs() < 1e-15);
    assert!((m.nu() - 0.25).abs() < 1e-15);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Any finite (or not) input gives a value or an error, never a panic, and a value is
    /// finite.
    #[test]
    fn no_panics_on_any_input(
        alpha in prop::num::f64::ANY, depth in prop::num::f64::ANY, dip in prop::num::f64::ANY,
        a in prop::array::uniform4(prop::num::f64::ANY),
        p in prop::array::uniform3(prop::num::f64::ANY),
        d in prop::array::uniform3(prop::num::f64::ANY),
    ) {
        if let Ok(out) = Rectangle::new(depth, dip, [a[0], a[1]], [a[2], a[3]])
            .and_then(|r| rsf_halfspace::okada::dc3d(alpha, p, r, d)) {
            prop_assert!(out.u.iter().chain(out.grad.iter().flatten()).all(|v| v.is_finite()));
        }
        if let Ok(f) = rsf_halfspace::two_d::antiplane_segment(alpha, depth, [a[0], a[1]], [p[0], p[1]]) {
            prop_assert!(f.u.is_finite() && f.sigma_xy.is_finite() && f.sigma_xz.is_finite());
        }
        if let Ok(u) = rsf_halfspace::two_d::edge_surface_displacement(alpha, depth, dip, [a[0], a[1]], p[0]) {
            prop_assert!(u.iter().all(|v| v.is_finite()));
        }
        if let Ok(m) = Medium::new(d[0], d[1]) {
            if let Ok(t) = rsf_halfspace::two_d::edge_segment_stress(&m, alpha, rsf_halfspace::two_d::DipSegment { depth, dip_deg: dip, aw: [a[0], a[1]] }, [p[0], p[1]]) {
                prop_assert!([t.yy, t.zz, t.yz, t.xx].iter().all(|v| v.is_finite()));
            }
        }
    }
}
