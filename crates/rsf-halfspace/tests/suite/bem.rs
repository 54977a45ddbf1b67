//! The boundary-element operator of a rectangular fault: entries against Okada's stresses
//! evaluated directly, reciprocity, the ℋ-matrix against the dense matrix, the 2-D limits
//! (antiplane cells, 2-D cracks) and the normal-traction operator's symmetries.
use faer::Mat;
use rsf_halfspace::okada::dc3d;
use rsf_halfspace::two_d::antiplane_segment;
use rsf_halfspace::{Component, Error, Medium, Rectangle, RectangularFault};
use rsf_hmatrix::HOptions;
use std::f64::consts::PI;

const MU: f64 = 3.2e10;
const NU: f64 = 0.25;

fn medium() -> Medium {
    Medium::from_shear_poisson(MU, NU).unwrap()
}

/// `[τ_strike, τ_dip, σ_n]` at `p` for the dislocation `disl` on `rect`, written out from
/// DC3D's free function, Hooke's law and the fault's frame (independently of the
/// operator's code path).
fn tractions_at(rect: &Rectangle, p: [f64; 3], disl: [f64; 3]) -> [f64; 3] {
    let m = medium();
    let d = dc3d(
        m.alpha(),
        p,
        Rectangle::new(
            rect.depth(),
            rect.dip_deg(),
            rect.strike_range(),
            rect.dip_range(),
        )
        .unwrap(),
        disl,
    )
    .unwrap();
    let s = m.stress(&d.grad);
    let dip = rect.dip_deg().to_radians();
    let n = [0.0, -dip.sin(), dip.cos()];
    let es = [1.0, 0.0, 0.0];
    let ed = [0.0, dip.cos(), dip.sin()];
    let t: Vec<f64> = (0..3)
        .map(|i| (0..3).map(|j| s[i][j] * n[j]).sum())
        .collect();
    let dot = |a: [f64; 3]| t[0] * a[0] + t[1] * a[1] + t[2] * a[2];
    [dot(es), dot(ed), dot(n)]
}

/// The fault of DC3D's rectangle `(depth, dip, [al1, al2], [aw1, aw2])` (m, degrees)
/// cut into square cells of `cell` (m), in [`medium`].
fn fault(depth: f64, dip: f64, strike: [f64; 2], width: [f64; 2], cell: f64) -> RectangularFault {
    let rect = Rectangle::new(depth, dip, strike, width).unwrap();
    RectangularFault::new(medium(), rect, cell).unwrap()
}

fn bp5_like() -> RectangularFault {
    // Vertical, surface-breaking, 12 × 5 cells of 2 m.
    fault(0.0, 90.0, [-12.0, 12.0], [-10.0, 0.0], 2.0)
}

fn dipping() -> RectangularFault {
    // 30°, buried (top at 1 m depth), 6 × 4 cells of 1.5 m.
    fault(4.0, 30.0, [-4.5, 4.5], [-3.0, 3.0], 1.5)
}

#[test]
fn layout_and_errors() {
    let f = bp5_like();
    assert_eq!(
        (f.n_strike(), f.n_dip(), f.n_elements(), f.len()),
        (12, 5, 60, 120)
    );
    // Element order: strike fastest, top row first.
    let e = f.element_index(3, 0).unwrap();
    assert_eq!(e, 3);
    let r = f.element(e).unwrap();
    assert_eq!(r.strike_range(), [-6.0, -4.0]);
    assert_eq!(r.dip_range(), [-2.0, 0.0]);
    assert_eq!(
        f.element(f.element_index(0, 4).unwrap())
            .unwrap()
            .dip_range(),
        [-10.0, -8.0]
    );
    assert_eq!(RectangularFault::unknown(7, Component::Dip), 15);
    let pts = f.points();
    assert_eq!(pts.len(), 120);
    assert_eq!(pts.point(14), pts.point(15));
    assert_eq!(pts.point(14), &f.centres()[7]);
    assert!(matches!(f.entry(120, 0), Err(Error::Index { .. })));
    assert!(matches!(f.normal_entry(60, 0), Err(Error::Index { .. })));
    assert!(f.element(60).is_err());
    assert!(RectangularFault::new(
        medium(),
        Rectangle::new(0.0, 90.0, [-12.0, 12.0], [-10.0, 0.0]).unwrap(),
        3.0
    )
    .is_err());
    assert!(RectangularFault::new(
        medium(),
        Rectangle::new(0.0, 90.0, [-12.0, 12.0], [-10.0, 0.0]).unwrap(),
        0.0
    )
    .is_err());
    // A fault reaching above the surface is refused by its rectangle.
    assert!(Rectangle::new(0.0, 90.0, [-12.0, 12.0], [-10.0, 1.0]).is_err());
    let rect = Rectangle::new(1.0, 90.0, [0.0, 1.0], [-1.0, 0.0]).unwrap();
    assert!(RectangularFault::from_rectangle(medium(), rect, 0, 3).is_err());
    assert!(matches!(
        RectangularFault::from_rectangle(medium(), rect, usize::MAX, 3),
        Err(Error::TooManyElements { .. })
    ));
}

/// Every entry of `K` and `K_N` is minus the traction from DC3D evaluated directly;
/// `entry` and `dense` give the same bits, and `dense` the same bits on one thread and on
/// two.
#[test]
fn dense_entries_are_okada_tractions() {
    for fault in [bp5_like(), dipping()] {
        let k = fault.dense().unwrap();
        let kn = fault.normal_dense().unwrap();
        let n = fault.len();
        assert_eq!(
            (k.nrows(), k.ncols(), kn.nrows(), kn.ncols()),
            (n, n, n / 2, n)
        );
        let scale = (0..n).map(|i| k[(i, i)].abs()).fold(0.0, f64::max);
        for i in 0..n {
            for j in 0..n {
                let (e, f) = (i / 2, j / 2);
                let mut disl = [0.0; 3];
                disl[j % 2] = 1.0;
                let t = tractions_at(fault.element(f).unwrap(), fault.centres()[e], disl);
                assert!(
                    (k[(i, j)] + t[i % 2]).abs() <= 1e-13 * scale,
                    "K ({i}, {j})"
                );
                assert_eq!(k[(i, j)].to_bits(), fault.entry(i, j).unwrap().to_bits());
                if i % 2 == 0 {
                    assert!((kn[(e, j)] + t[2]).abs() <= 1e-13 * scale, "K_N ({e}, {j})");
                    assert_eq!(
                        kn[(e, j)].to_bits(),
                        fault.normal_entry(e, j).unwrap().to_bits()
                    );
                }
            }
        }
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let two = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let k1 = one.install(|| fault.dense().unwrap());
        let k2 = two.install(|| fault.dense().unwrap());
        for i in 0..n {
            for j in 0..n {
                assert_eq!(k1[(i, j)].to_bits(), k2[(i, j)].to_bits());
                assert_eq!(k1[(i, j)].to_bits(), k[(i, j)].to_bits());
            }
        }
    }
}

/// Slip lowers the shear traction on its own element (`K`'s diagonal positive) and the
/// self-stiffness of a small buried square is that of the full space.
#[test]
fn diagonal_is_positive() {
    for fault in [bp5_like(), dipping()] {
        let k = fault.dense().unwrap();
        for i in 0..fault.len() {
            assert!(k[(i, i)] > 0.0, "K[{i}][{i}] = {}", k[(i, i)]);
        }
    }
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton on P_n).
fn gauss(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// `∫_{receiver} τ_c(x; unit slip d on source) dA` by 10 × 10 Gauss points.
fn averaged(receiver: &Rectangle, source: &Rectangle, c: usize, d: usize) -> f64 {
    averaged_n(receiver, source, c, d, 10)
}

fn averaged_n(receiver: &Rectangle, source: &Rectangle, c: usize, d: usize, n: usize) -> f64 {
    let g = gauss(n);
    let [a1, a2] = receiver.strike_range();
    let [w1, w2] = receiver.dip_range();
    let (hs, hd) = (0.5 * (a2 - a1), 0.5 * (w2 - w1));
    let mut disl = [0.0; 3];
    disl[d] = 1.0;
    let mut sum = 0.0;
    for &(u, wu) in &g {
        for &(v, wv) in &g {
            let p = receiver.point(a1 + hs * (1.0 + u), w1 + hd * (1.0 + v));
            sum += wu * wv * hs * hd * tractions_at(source, p, disl)[c];
        }
    }
    sum
}

/// Reciprocity. Betti's theorem makes the Galerkin (element-averaged) operator symmetric:
/// `∫_{E_i} τ_c(slip d on E_j) dA = ∫_{E_j} τ_d(slip c on E_i) dA` for elements that do
/// not touch (touching ones diverge logarithmically) — checked for pairs of elements at
/// least one element apart (the quadrature's error there is below 10⁻¹⁰),
/// buried and surface-breaking, dipping and vertical. Centre collocation keeps this only
/// up to the centre rule's error on the receiver (not exact near the surface); exactly,
/// on a vertical fault the reflection `x → −x` makes `K·diag(A)` symmetric within each
/// depth row (equal areas), which is checked to round-off.
#[test]
fn reciprocity() {
    for fault in [bp5_like(), dipping()] {
        let pairs = [(0usize, 2usize), (1, 9), (4, 18), (7, 23), (13, 3)];
        for &(ei, ej) in &pairs {
            let (ri, rj) = (fault.element(ei).unwrap(), fault.element(ej).unwrap());
            for c in 0..2 {
                for d in 0..2 {
                    let a = averaged(ri, rj, c, d);
                    let b = averaged(rj, ri, d, c);
                    let scale = a.abs().max(b.abs()).max(1e-3 * MU);
                    assert!(
                        (a - b).abs() <= 1e-9 * scale,
                        "elements {ei}, {ej}, components {c}, {d}: {a} vs {b}"
                    );
                }
            }
        }
    }
    let fault = bp5_like();
    let k = fault.dense().unwrap();
    let scale = (0..fault.len()).map(|i| k[(i, i)]).fold(0.0, f64::max);
    let mut asym = 0.0f64;
    for row in 0..fault.n_dip() {
        for a in 0..fault.n_strike() {
            for b in 0..fault.n_strike() {
                let (e, f) = (
                    fault.element_index(a, row).unwrap(),
                    fault.element_index(b, row).unwrap(),
                );
                for c in 0..2 {
                    let (i, j) = (2 * e + c, 2 * f + c);
                    assert!((k[(i, j)] - k[(j, i)]).abs() <= 1e-13 * scale, "({i}, {j})");
                }
            }
        }
    }
    // The collocation asymmetry over the whole matrix, for the record.
    let mut norm = 0.0f64;
    for i in 0..fault.len() {
        for j in 0..fault.len() {
            asym += (k[(i, j)] - k[(j, i)]).powi(2);
            norm += k[(i, j)].powi(2);
        }
    }
    println!(
        "‖K − Kᵀ‖_F / ‖K‖_F = {:.3e} (vertical surface-breaking fault, 12 × 5 cells)",
        (asym / norm).sqrt()
    );
}

fn frobenius(m: &Mat<f64>) -> f64 {
    let mut s = 0.0;
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            s += m[(i, j)] * m[(i, j)];
        }
    }
    s.sqrt()
}

/// The ℋ-matrix from the entries matches the dense operator to its requested accuracy in
/// the Frobenius norm.
#[test]
fn hmatrix_matches_dense() {
    // 32 × 12 cells, 768 unknowns.
    let fault = RectangularFault::new(
        medium(),
        Rectangle::new(0.0, 90.0, [-32.0, 32.0], [-24.0, 0.0]).unwrap(),
        2.0,
    )
    .unwrap();
    let k = fault.dense().unwrap();
    for eps in [1e-4, 1e-7] {
        let options = HOptions {
            leaf_size: 32,
            ..HOptions::with_epsilon(eps)
        };
        let h = fault.hmatrix(&options).unwrap();
        let kh = h.to_dense();
        let mut diff = k.clone();
        for j in 0..k.ncols() {
            for i in 0..k.nrows() {
                diff[(i, j)] -= kh[(i, j)];
            }
        }
        let rel = frobenius(&diff) / frobenius(&k);
        let report = h.report();
        println!(
            "ε = {eps:e}: ‖K − K_H‖_F/‖K‖_F = {rel:.3e}, memory {:.3}, low-rank blocks {}, max rank {}",
            report.memory_ratio(),
            report.low_rank_blocks,
            report.max_rank
        );
        assert!(report.low_rank_blocks > 0);
        assert!(rel <= eps, "ε = {eps}: relative error {rel}");
    }
}

/// A long vertical strike-slip fault: the strike-slip stiffness summed along strike at the
/// middle element tends to the 2-D antiplane cells' (`σ_xy` of `two_d`, per unit slip)
/// as `(H/L)²`.
#[test]
fn long_strike_slip_fault_tends_to_antiplane() {
    let (n_dip, h) = (6, 1.0);
    let depth = n_dip as f64 * h;
    let mut last = f64::INFINITY;
    for half_length in [60.0, 600.0] {
        let rect = Rectangle::new(0.0, 90.0, [-half_length, half_length], [-depth, 0.0]).unwrap();
        let fault = RectangularFault::from_rectangle(medium(), rect, 5, n_dip).unwrap();
        let k = fault.dense().unwrap();
        let mut worst = 0.0f64;
        let scale = MU / h;
        for row in 0..n_dip {
            let e = fault.element_index(2, row).unwrap();
            let z = fault.centres()[e][2];
            for col in 0..n_dip {
                let sum: f64 = (0..5)
                    .map(|s| k[(2 * e, 2 * fault.element_index(s, col).unwrap())])
                    .sum();
                let d1 = col as f64 * h;
                let f = antiplane_segment(MU, 1.0, [d1, d1 + h], [0.0, z]).unwrap();
                worst = worst.max((sum - f.sigma_xy).abs() / scale);
            }
        }
        println!("L = {half_length}: largest difference {worst:.3e} of μ/h");
        assert!(
            worst <= (depth / half_length).powi(2),
            "L = {half_length}: {worst}"
        );
        assert!(worst < last / 10.0);
        last = worst;
    }
}

/// Uniform slip on a long, deeply buried fault of width W: the traction drop at its centre
/// is the 2-D crack's, `2μ s/(π W)` for strike slip (antiplane) and `2μ s/(π (1 − ν) W)`
/// for dip slip (plane strain), to `O(W/L)` (and the image's `(W/depth)²`); and no
/// traction in the other direction.
#[test]
fn uniform_slip_on_a_long_buried_fault_is_the_2d_crack() {
    let w = 2.0;
    for dip in [90.0, 30.0] {
        let mut last = [f64::INFINITY; 2];
        for half_length in [20.0, 200.0] {
            let rect =
                Rectangle::new(500.0, dip, [-half_length, half_length], [-1.0, 1.0]).unwrap();
            let fault = RectangularFault::from_rectangle(medium(), rect, 5, 5).unwrap();
            let k = fault.dense().unwrap();
            let centre = fault.element_index(2, 2).unwrap();
            let want = [2.0 * MU / (PI * w), 2.0 * MU / (PI * (1.0 - NU) * w)];
            for c in 0..2 {
                let drop: f64 = (0..fault.n_elements())
                    .map(|f| k[(2 * centre + c, 2 * f + c)])
                    .sum();
                let cross: f64 = (0..fault.n_elements())
                    .map(|f| k[(2 * centre + 1 - c, 2 * f + c)])
                    .sum();
                let rel = (drop - want[c]).abs() / want[c];
                println!("dip {dip} L {half_length} component {c}: drop {drop:.6e}, 2-D {:.6e}, relative {rel:.2e}", want[c]);
                assert!(
                    rel <= w / half_length,
                    "dip {dip}, component {c}: {drop} vs {}",
                    want[c]
                );
                assert!(rel < last[c] / 5.0);
                assert!(cross.abs() <= 1e-9 * want[c], "cross term {cross}");
                last[c] = rel;
            }
        }
    }
}

/// The normal-traction operator. On a vertical fault, reflection `y → −y` maps the
/// half-space to itself and a shear slip to its opposite, so `σ_yy = 0` on the fault
/// plane: `K_N = 0` for strike and dip slip alike (computed, to round-off). On a dipping
/// fault the free surface breaks that symmetry: `K_N ≠ 0` near the surface, and it fades
/// as the fault is buried deeper (the full space has `K_N = 0` for any planar fault).
#[test]
fn normal_traction_operator() {
    let fault = bp5_like();
    let (k, kn) = (fault.dense().unwrap(), fault.normal_dense().unwrap());
    let scale = (0..fault.len()).map(|i| k[(i, i)]).fold(0.0, f64::max);
    let vertical = frobenius(&kn) / scale;
    println!("vertical fault: ‖K_N‖_F / max K_ii = {vertical:.3e}");
    assert!(vertical <= 1e-12);

    let shallow = |depth: f64| {
        let rect = Rectangle::new(depth, 30.0, [-4.0, 4.0], [-2.0, 0.0]).unwrap();
        let fault = RectangularFault::from_rectangle(medium(), rect, 4, 2).unwrap();
        let (k, kn) = (fault.dense().unwrap(), fault.normal_dense().unwrap());
        let scale = (0..fault.len()).map(|i| k[(i, i)]).fold(0.0, f64::max);
        let mut m = 0.0f64;
        for e in 0..kn.nrows() {
            for j in 0..kn.ncols() {
                m = m.max(kn[(e, j)].abs());
            }
        }
        m / scale
    };
    let (at_surface, deep) = (shallow(0.0), shallow(200.0));
    println!(
        "30° fault: max |K_N| / max K_ii = {at_surface:.3e} at the surface, {deep:.3e} at 200 m"
    );
    assert!(at_surface >= 1e-2);
    assert!(deep <= 1e-4);
}

/// Like a finite-element Schur complement, `K`'s symmetric part is positive definite
/// (Cholesky succeeds) for the vertical surface-breaking grid and the buried dipping one.
/// Not a theorem for centre collocation (piecewise-constant slip has infinite elastic
/// energy, so there is no exact energy form to inherit it from); a check that slip on
/// these grids always does work against the tractions it changes.
#[test]
fn symmetric_part_is_positive_definite() {
    for fault in [bp5_like(), dipping()] {
        let k = fault.dense().unwrap();
        let n = k.nrows();
        let sym = Mat::from_fn(n, n, |i, j| 0.5 * (k[(i, j)] + k[(j, i)]));
        assert!(sym.llt(faer::Side::Lower).is_ok());
    }
}
