//! The 2-D closed forms against rsf-hmatrix's antiplane kernel, the classic screw
//! dislocation (Savage & Burford) surface profile, and the 3-D DC3D of a very long fault.
use rsf_halfspace::okada::{dc3d, Rectangle};
use rsf_halfspace::two_d::{
    antiplane_segment, edge_segment_stress, edge_surface_displacement, DipSegment,
};
use rsf_halfspace::Error;
use rsf_hmatrix::kernels::AntiplaneHalfSpace;
use std::f64::consts::PI;

const MU: f64 = 3.2e10;

/// Against rsf-hmatrix's reference kernel `AntiplaneHalfSpace` (the SEAS BP1 geometry):
/// with `F(d) = μ/(2π) [1/(d − h/2) − 1/(d + h/2)]`, our shear traction
/// `(σ n)·e_s = −σ_xy` at the cell centres is `F(z − ζ) + F(z + ζ)` — the real cell and its
/// mirror image with the same slip, which makes the surface traction-free (checked against
/// DC3D below) — while rsf-hmatrix's kernel is `F(z − ζ) − F(z + ζ)`, the image of a
/// clamped surface (`u = 0` on `z = 0`). The full-space parts agree to round-off; the
/// image parts are equal and opposite.
#[test]
fn antiplane_cells_against_rsf_hmatrix_kernel() {
    let (n, h) = (24, 0.4);
    let k = AntiplaneHalfSpace::new(n, h, MU).unwrap();
    let scale = k.entry(0, 0).abs();
    let f = |d: f64| MU / (2.0 * PI) * (1.0 / (d - 0.5 * h) - 1.0 / (d + 0.5 * h));
    for i in 0..n {
        for j in 0..n {
            let (z, zeta) = (k.depth(i), k.depth(j));
            let field =
                antiplane_segment(MU, 1.0, [zeta - 0.5 * h, zeta + 0.5 * h], [0.0, -z]).unwrap();
            let ours = -field.sigma_xy;
            let theirs = k.entry(i, j);
            assert!(
                (0.5 * (ours + theirs) - f(z - zeta)).abs() <= 1e-12 * scale,
                "({i}, {j}) full-space part: ours {ours}, rsf-hmatrix {theirs}"
            );
            assert!(
                (0.5 * (ours - theirs) - f(z + zeta)).abs() <= 1e-12 * scale,
                "({i}, {j}) image part: ours {ours}, rsf-hmatrix {theirs}"
            );
            assert_eq!(field.sigma_xz, 0.0);
        }
    }
}

/// A screw dislocation at depth D with slip below it (d2 = ∞): surface displacement
/// `−(s/π) atan(y/D)` (Savage & Burford 1973 with Okada's sign), and the free surface is
/// traction-free.
#[test]
fn screw_dislocation_surface_profile() {
    let (s, d) = (2.0, 15e3);
    for y in [-5e4, -1e4, -10.0, 3.0, 2e3, 1e5] {
        let f = antiplane_segment(MU, s, [d, f64::INFINITY], [y, 0.0]).unwrap();
        let want = -(s / PI) * (y / d).atan();
        assert!((f.u - want).abs() < 1e-14 * s, "y = {y}: {} vs {want}", f.u);
        assert!(f.sigma_xz.abs() < 1e-12 * MU * s / d);
    }
}

/// The jump of `u_x` across the segment is the slip: `u(y < 0) − u(y > 0) = s`.
#[test]
fn antiplane_jump_is_the_slip() {
    let s = 0.7;
    let a = antiplane_segment(MU, s, [1.0, 3.0], [-1e-9, -2.0]).unwrap();
    let b = antiplane_segment(MU, s, [1.0, 3.0], [1e-9, -2.0]).unwrap();
    assert!((a.u - b.u - s).abs() < 1e-8);
    // Off the segment (below it) no jump.
    let a = antiplane_segment(MU, s, [1.0, 3.0], [-1e-9, -4.0]).unwrap();
    let b = antiplane_segment(MU, s, [1.0, 3.0], [1e-9, -4.0]).unwrap();
    assert!((a.u - b.u).abs() < 1e-8);
}

/// A vertical strike-slip fault of length `2L`: DC3D in its middle tends to the 2-D
/// field as `(H/L)²` (the ends are a dislocation dipole seen from `L`; `H` the largest
/// length of the cross-section). Checked at `L = 10³` and `10⁴` (longer faults lose digits
/// in `R + ξ` at the far corners, as `10⁻¹⁶ (L/H)²`): within `(H/L)²` of the 2-D field,
/// and five times closer at the longer fault (or at the round-off floor).
#[test]
fn antiplane_is_the_long_fault_limit_of_dc3d() {
    let (d1, d2) = (0.5, 3.0);
    let m = rsf_halfspace::Medium::from_shear_poisson(MU, 0.25).unwrap();
    for (y, z) in [
        (0.7, -1.0),
        (-2.0, 0.0),
        (0.0, -1.5),
        (5.0, -6.0),
        (-0.3, -3.5),
    ] {
        let f = antiplane_segment(MU, 1.0, [d1, d2], [y, z]).unwrap();
        let hh = d2.max(y.abs()).max(z.abs());
        let mut last = [f64::INFINITY; 3];
        for l in [1e3, 1e4] {
            let d = dc3d(
                m.alpha(),
                [0.0, y, z],
                Rectangle::new(d2, 90.0, [-l, l], [0.0, d2 - d1]).unwrap(),
                [1.0, 0.0, 0.0],
            )
            .unwrap();
            let s = m.stress(&d.grad);
            let err = [
                (d.u[0] - f.u).abs(),
                (s[0][1] - f.sigma_xy).abs() / (MU / (d2 - d1)),
                (s[0][2] - f.sigma_xz).abs() / (MU / (d2 - d1)),
            ];
            for c in 0..3 {
                assert!(
                    err[c] <= (hh / l).powi(2),
                    "({y}, {z}) L = {l}: quantity {c} off by {:e}; DC3D u {} σ_xy {} σ_xz {}, 2-D {:?}",
                    err[c],
                    d.u[0],
                    s[0][1],
                    s[0][2],
                    f
                );
                // Converging, unless already at the round-off floor 10⁻¹⁶ (L/H)² ≈ 10⁻⁸.
                assert!(
                    err[c] <= last[c] / 5.0 || err[c] <= 1e-8,
                    "({y}, {z}): no convergence {err:?} {last:?}"
                );
            }
            last = err;
        }
    }
}

/// Dip-slip faults against DC3D's long-fault limit, buried and surface-breaking: the
/// `depth`, `dip` (°) and along-dip extent `aw` of DC3D's rectangle.
const SEGMENTS: [(f64, f64, [f64; 2]); 5] = [
    (3.0, 30.0, [-1.0, 1.5]),
    (2.0, 60.0, [-2.0, 0.5]),
    (4.0, 90.0, [-1.0, 1.0]),
    (0.0, 45.0, [-3.0, 0.0]),
    (2.5, 120.0, [-1.0, 1.0]),
];

/// The plane-strain edge-dislocation surface displacement is the limit of DC3D's dip-slip
/// surface displacement for a long fault (length `2L`), for several dips, buried and
/// surface-breaking: the difference is `O(H/L)` (the vertical displacement of dip slip
/// has a `1/L` end correction) — within `H/L` times the slip at `L = 10⁴` and at least
/// five times smaller than at `L = 10³` (or at the round-off floor, `10⁻¹⁶ (L/ℓ)²` for the smallest length ℓ ≥ 0.2 here: `10⁻⁶` of the slip).
#[test]
fn edge_surface_displacement_is_the_long_fault_limit_of_dc3d() {
    let s = 0.8;
    // And a vertical fault breaking the surface.
    for (depth, dip, aw) in SEGMENTS.into_iter().chain([(0.0, 90.0, [-2.0, 0.0])]) {
        for y in [-7.0, -1.3, -0.2, 0.4, 2.2, 9.0] {
            let u2d = edge_surface_displacement(s, depth, dip, aw, y).unwrap();
            let hh = (depth + 3.0f64).max(y.abs());
            let err = |l: f64| {
                let d = dc3d(
                    2.0 / 3.0,
                    [0.0, y, 0.0],
                    Rectangle::new(depth, dip, [-l, l], aw).unwrap(),
                    [0.0, s, 0.0],
                )
                .unwrap();
                ((u2d[0] - d.u[1]).abs().max((u2d[1] - d.u[2]).abs()), d.u)
            };
            let (e3, _) = err(1e3);
            let (e4, u) = err(1e4);
            assert!(
                e4 <= hh / 1e4 * s && (e4 <= e3 / 5.0 || e4 <= 1e-6 * s),
                "depth {depth} dip {dip} y {y}: 2-D {u2d:?} vs DC3D {u:?} (errors {e3:e}, {e4:e})"
            );
        }
    }
}

/// The plane-strain stress of dip slip on a dipping segment (Segall's edge dislocations)
/// is the limit of DC3D's stress for a long fault: within `(H/L)` of `μ s/W` at
/// `L = 10⁴` and converging from `L = 10³` (or at the round-off floor), for several dips,
/// buried and surface-breaking, at points around and near the segment; `σ_xx` is the
/// plane-strain `ν(σ_yy + σ_zz)`.
#[test]
fn edge_segment_stress_is_the_long_fault_limit_of_dc3d() {
    let m = rsf_halfspace::Medium::from_shear_poisson(MU, 0.3).unwrap();
    let s = 0.8;
    for (depth, dip, aw) in SEGMENTS {
        let w = aw[1] - aw[0];
        let scale = MU * s / w;
        for (y, z) in [
            (0.7, -1.0),
            (-2.0, -4.0),
            (3.0, -0.5),
            (-0.5, -5.5),
            (1.0, 0.0),
        ] {
            let two = edge_segment_stress(
                &m,
                s,
                DipSegment {
                    depth,
                    dip_deg: dip,
                    aw,
                },
                [y, z],
            )
            .unwrap();
            let hh = (depth + 3.0f64).max(y.abs()).max(z.abs());
            let err = |l: f64| {
                let d = dc3d(
                    m.alpha(),
                    [0.0, y, z],
                    Rectangle::new(depth, dip, [-l, l], aw).unwrap(),
                    [0.0, s, 0.0],
                )
                .unwrap();
                let st = m.stress(&d.grad);
                let e = [
                    st[1][1] - two.yy,
                    st[2][2] - two.zz,
                    st[1][2] - two.yz,
                    st[0][0] - two.xx,
                ];
                e.iter().fold(0.0f64, |a, v| a.max(v.abs())) / scale
            };
            let (e3, e4) = (err(1e3), err(1e4));
            assert!(
                e4 <= hh / 1e4 && (e4 <= e3 / 5.0 || e4 <= 1e-8),
                "depth {depth} dip {dip} ({y}, {z}): {two:?}, errors {e3:e} {e4:e}"
            );
        }
    }
}

#[test]
fn two_d_errors() {
    assert!(matches!(
        antiplane_segment(MU, 1.0, [1.0, 2.0], [0.0, 0.5]),
        Err(Error::AboveSurface { .. })
    ));
    assert!(matches!(
        antiplane_segment(MU, 1.0, [1.0, 2.0], [0.0, -2.0]),
        Err(Error::AtDislocation { .. })
    ));
    assert!(antiplane_segment(MU, 1.0, [2.0, 1.0], [0.0, -2.0]).is_err());
    assert!(antiplane_segment(0.0, 1.0, [1.0, 2.0], [0.0, -2.0]).is_err());
    assert!(antiplane_segment(MU, f64::NAN, [1.0, 2.0], [0.0, -2.0]).is_err());
    assert!(matches!(
        edge_surface_displacement(1.0, 0.0, 90.0, [-1.0, 0.0], 0.0),
        Err(Error::AtDislocation { .. })
    ));
    assert!(edge_surface_displacement(1.0, 0.0, 90.0, [-1.0, 1.0], 2.0).is_err());
    assert!(edge_surface_displacement(1.0, 1.0, 0.0, [-1.0, 1.0], 2.0).is_err());
    let m = rsf_halfspace::Medium::from_shear_poisson(MU, 0.25).unwrap();
    // A vertical segment's stress at `at`.
    let vertical = |depth: f64, aw: [f64; 2], at: [f64; 2]| {
        let segment = DipSegment {
            depth,
            dip_deg: 90.0,
            aw,
        };
        edge_segment_stress(&m, 1.0, segment, at)
    };
    assert!(matches!(
        vertical(2.0, [-1.0, 1.0], [0.0, -1.0]),
        Err(Error::AtDislocation { .. })
    ));
    assert!(matches!(
        vertical(0.0, [-1.0, 0.0], [0.0, 0.0]),
        Err(Error::AtDislocation { .. })
    ));
    assert!(vertical(2.0, [-1.0, 1.0], [0.0, 0.1]).is_err());
    assert!(vertical(0.5, [-1.0, 1.0], [0.0, -3.0]).is_err());
}
