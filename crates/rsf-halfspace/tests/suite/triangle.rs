//! Nikkhoo & Walter's triangular dislocations (`rsf_halfspace::triangle`): two triangles
//! against the Okada rectangle they tile (full and half space, displacement and gradient),
//! the free surface traction-free, the whole space as the limit of the half-space buried
//! ever deeper (at the rate the image predicts, for triangles and for Okada's rectangles),
//! and the displacement's jump across a triangle equal to its slip.
use rsf_halfspace::okada::{Okada, Rectangle};
use rsf_halfspace::{Deformation, Error, Medium, Space, Triangle};

const NU: f64 = 0.25;

fn medium() -> Medium {
    Medium::from_shear_poisson(1.0, NU).unwrap()
}

/// The rectangle's two triangles (split along a diagonal), vertices in the order that
/// gives them Okada's normal.
fn split(rect: &Rectangle) -> [Triangle; 2] {
    let [a1, a2] = rect.strike_range();
    let [w1, w2] = rect.dip_range();
    let p = |x: f64, e: f64| rect.point(x, e);
    [
        Triangle::new([p(a1, w1), p(a2, w1), p(a2, w2)]).unwrap(),
        Triangle::new([p(a1, w1), p(a2, w2), p(a1, w2)]).unwrap(),
    ]
}

/// A seeded uniform number in [0, 1).
fn uniform(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

/// Largest difference of displacement and gradient, each relative to the larger of the
/// two fields' largest entry at the point.
fn relative(a: &Deformation, b: &Deformation) -> (f64, f64) {
    let max = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0_f64, |m, x| m.max(x.abs()));
    let su = max(&mut a.u.iter().chain(b.u.iter()).copied());
    let sg = max(&mut a.grad.iter().chain(b.grad.iter()).flatten().copied());
    let du = max(&mut (0..3).map(|i| a.u[i] - b.u[i]));
    let dg = max(&mut (0..9).map(|k| a.grad[k / 3][k % 3] - b.grad[k / 3][k % 3]));
    (du / su, dg / sg)
}

/// Two triangles tile a rectangle: their displacements and gradients add up to Okada's
/// (DC3D in the half-space, its part A in the whole space) at random points away from the
/// edges and the diagonal (at least 10 % of the shorter side from the rectangle's plane),
/// for the three unit slips, four dips (a horizontal and a vertical rectangle among
/// them), buried and surface-breaking. Two independent closed forms (Okada 1992 and
/// Nikkhoo & Walter 2015's angular dislocations), so agreement is round-off's: measured
/// 5.3e-13 (displacement) and 2.1e-13 (gradient) at worst, asked 1e-11.
#[test]
fn two_triangles_are_one_okada_rectangle() {
    let alpha = medium().alpha();
    let mut seed = 7u64;
    let (mut worst_u, mut worst_g) = (0.0_f64, 0.0_f64);
    for (depth, dip) in [
        (3.0, 40.0),
        (2.0, 90.0),
        (1.5, 0.0),
        (0.8, 120.0),
        (0.0, 60.0),
    ] {
        let aw2 = if depth == 0.0 { 0.0 } else { 0.7 };
        let rect = Rectangle::new(depth, dip, [-1.0, 1.5], [aw2 - 1.5, aw2]).unwrap();
        let ok = Okada::new(alpha, rect).unwrap();
        let tri = split(&rect);
        let okada_frame = rect.frame();
        let n = okada_frame[2];
        let c = rect.centre();
        for space in [Space::WholeSpace, Space::HalfSpace] {
            let mut taken = 0;
            while taken < 40 {
                let p = [0, 1, 2].map(|i| c[i] + 6.0 * (uniform(&mut seed) - 0.5));
                let off = (0..3).map(|i| (p[i] - c[i]) * n[i]).sum::<f64>().abs();
                if off < 0.15 || (space == Space::HalfSpace && p[2] > 0.0) {
                    continue;
                }
                taken += 1;
                let o = ok.unit_responses_in(p, space).unwrap();
                let t0 = tri[0].unit_responses(NU, p, space).unwrap();
                let t1 = tri[1].unit_responses(NU, p, space).unwrap();
                for k in 0..3 {
                    // Okada's unit slip k in the triangles' frame (the same but for the
                    // horizontal rectangle, whose triangles take e_s = e_y).
                    let mut t = Deformation::default();
                    for (c, tc) in tri[0].frame().iter().enumerate() {
                        let w: f64 = (0..3).map(|i| okada_frame[k][i] * tc[i]).sum();
                        t = t.add_scaled(w, &t0[c].add_scaled(1.0, &t1[c]));
                    }
                    let (du, dg) = relative(&o[k], &t);
                    worst_u = worst_u.max(du);
                    worst_g = worst_g.max(dg);
                }
            }
        }
    }
    eprintln!("two triangles against Okada: displacement {worst_u:.2e}, gradient {worst_g:.2e}");
    assert!(
        worst_u < 1e-11 && worst_g < 1e-11,
        "{worst_u:e} {worst_g:e}"
    );
}

/// The half-space triangle's stress has no traction on the free surface: `σ_xz`, `σ_yz`,
/// `σ_zz` at points of `z = 0` vanish against the stress's scale there (measured at most
/// 6.5e-14 of it; asked 1e-12), for triangles of several orientations, one reaching the
/// surface; the whole-space triangle's do not (a check that the test can fail).
#[test]
fn the_free_surface_is_traction_free() {
    let m = medium();
    let triangles = [
        [[0.0, 0.0, -1.0], [1.0, 0.2, -2.0], [-0.3, 1.1, -1.6]],
        [[0.0, 0.0, -0.5], [2.0, 0.0, -0.5], [1.0, 1.5, -0.5]],
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.0, -1.0]],
        [[0.0, -1.0, -0.2], [0.3, 1.0, -3.0], [1.5, 0.1, -1.0]],
    ];
    let mut seed = 3u64;
    let (mut worst, mut whole) = (0.0_f64, f64::INFINITY);
    for v in triangles {
        let t = Triangle::new(v).unwrap();
        for _ in 0..30 {
            let p = [
                4.0 * uniform(&mut seed) - 2.0,
                4.0 * uniform(&mut seed) - 2.0,
                0.0,
            ];
            for (space, out) in [
                (Space::HalfSpace, &mut worst),
                (Space::WholeSpace, &mut whole),
            ] {
                let r = match t.unit_responses(NU, p, space) {
                    Ok(r) => r,
                    Err(Error::OnEdge { .. }) => continue,
                    Err(e) => panic!("{e}"),
                };
                for d in &r {
                    let s = m.stress(&d.grad);
                    let scale = s.iter().flatten().fold(0.0_f64, |a, x| a.max(x.abs()));
                    let free = [s[0][2], s[1][2], s[2][2]]
                        .iter()
                        .fold(0.0_f64, |a, x| a.max(x.abs()));
                    if space == Space::HalfSpace {
                        *out = out.max(free / scale);
                    } else {
                        *out = out.min(free / scale).min(1.0);
                    }
                }
            }
        }
    }
    eprintln!(
        "traction on the surface / stress: half-space {worst:.2e}, whole space ≥ {whole:.2e}"
    );
    assert!(worst < 1e-12, "{worst:e}");
    assert!(whole > 1e-3, "{whole:e}");
}

/// The whole-space solution is the half-space one with the surface far away: for a source
/// and a receiver at a fixed offset buried at depth D, the half-space's stress differs
/// from the whole space's by the image's and surface terms, which fall as D⁻³
/// (displacement D⁻²: a dislocation's far field). Measured for a triangle and for
/// Okada's rectangle over D = 8…64 (sizes ~1): the local rates lie within 0.1 of 3 and 2.
#[test]
fn the_whole_space_is_the_half_space_buried_deep() {
    let m = medium();
    let offset = [0.4, 0.9, 0.3];
    let tri = |d: f64| Triangle::new([[0.0, 0.0, -d], [1.0, 0.2, -d - 0.6], [-0.3, 1.0, -d + 0.4]]);
    let rect = |d: f64| {
        Okada::new(
            m.alpha(),
            Rectangle::new(d, 35.0, [-0.6, 0.7], [-0.5, 0.5]).unwrap(),
        )
    };
    let diff = |which: usize, d: f64| -> (f64, f64) {
        let p = [offset[0], offset[1], offset[2] - d];
        let (h, w) = if which == 0 {
            let t = tri(d).unwrap();
            (
                t.unit_responses(NU, p, Space::HalfSpace).unwrap(),
                t.unit_responses(NU, p, Space::WholeSpace).unwrap(),
            )
        } else {
            let o = rect(d).unwrap();
            (
                o.unit_responses_in(p, Space::HalfSpace).unwrap(),
                o.unit_responses_in(p, Space::WholeSpace).unwrap(),
            )
        };
        let (mut du, mut ds) = (0.0_f64, 0.0_f64);
        for k in 0..3 {
            let (sh, sw) = (m.stress(&h[k].grad), m.stress(&w[k].grad));
            for i in 0..3 {
                du = du.hypot(h[k].u[i] - w[k].u[i]);
                for j in 0..3 {
                    ds = ds.hypot(sh[i][j] - sw[i][j]);
                }
            }
        }
        (du, ds)
    };
    for which in 0..2 {
        let depths = [8.0, 16.0, 32.0, 64.0];
        let d: Vec<(f64, f64)> = depths.iter().map(|&z| diff(which, z)).collect();
        for k in 1..d.len() {
            let ru = (d[k - 1].0 / d[k].0).log2();
            let rs = (d[k - 1].1 / d[k].1).log2();
            eprintln!(
                "{} D = {}: displacement {:.3e} (rate {ru:.3}), stress {:.3e} (rate {rs:.3})",
                ["triangle", "rectangle"][which],
                depths[k],
                d[k].0,
                d[k].1
            );
            assert!(
                (ru - 2.0).abs() < 0.1 && (rs - 3.0).abs() < 0.1,
                "{ru} {rs}"
            );
        }
    }
}

/// Across the triangle the displacement jumps by the slip: `u(c + h n) − u(c − h n)` at the
/// centroid `c` is `s e_s + d e_d + t n` to within `O(h)` (h = 1e-9 of the size), in
/// either space; the slip's sign convention is Okada's (the side `n` points into moves).
#[test]
fn the_displacement_jumps_by_the_slip() {
    let t = Triangle::new([[0.0, 0.0, -1.0], [1.0, 0.2, -2.0], [-0.3, 1.1, -1.6]]).unwrap();
    let [es, ed, n] = t.frame();
    let c = t.centroid();
    let h = 1e-9;
    for space in [Space::HalfSpace, Space::WholeSpace] {
        for slip in [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.3, -0.7, 0.2],
        ] {
            let at = |s: f64| {
                t.displacement(NU, [0, 1, 2].map(|i| c[i] + s * h * n[i]), slip, space)
                    .unwrap()
            };
            let (plus, minus) = (at(1.0), at(-1.0));
            for i in 0..3 {
                let jump = slip[0] * es[i] + slip[1] * ed[i] + slip[2] * n[i];
                assert!(
                    (plus[i] - minus[i] - jump).abs() < 1e-7,
                    "{space:?} {slip:?} {i}: {} vs {jump}",
                    plus[i] - minus[i]
                );
            }
        }
    }
}

/// What a triangle refuses: vertices on a line, a point on an edge, a point or a vertex
/// above the surface of a half-space (both fine in a whole space), Poisson's ratio out of
/// range.
#[test]
fn careless_inputs_are_refused() {
    assert!(matches!(
        Triangle::new([[0.0; 3], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]]),
        Err(Error::Parameter { .. })
    ));
    assert!(Triangle::new([[0.0; 3], [1.0, 0.0, f64::NAN], [0.0, 1.0, 0.0]]).is_err());
    let t = Triangle::new([[0.0, 0.0, -1.0], [1.0, 0.0, -1.0], [0.0, 0.0, -2.0]]).unwrap();
    assert!(matches!(
        t.unit_responses(NU, [0.5, 0.0, -1.0], Space::HalfSpace),
        Err(Error::OnEdge { .. })
    ));
    assert!(matches!(
        t.unit_responses(NU, [0.5, 0.0, 0.5], Space::HalfSpace),
        Err(Error::AboveSurface { .. })
    ));
    assert!(t
        .unit_responses(NU, [0.5, 0.0, 0.5], Space::WholeSpace)
        .is_ok());
    let high = Triangle::new([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 0.0, -2.0]]).unwrap();
    assert!(matches!(
        high.unit_responses(NU, [0.5, 3.0, -1.0], Space::HalfSpace),
        Err(Error::SourceAboveSurface { .. })
    ));
    assert!(high
        .unit_responses(NU, [0.5, 3.0, -1.0], Space::WholeSpace)
        .is_ok());
    assert!(t
        .unit_responses(0.5, [0.5, 3.0, -1.0], Space::WholeSpace)
        .is_err());
    assert!(t
        .displacement(
            NU,
            [0.5, 3.0, -1.0],
            [f64::INFINITY, 0.0, 0.0],
            Space::WholeSpace
        )
        .is_err());
}
