//! Scalar (antiplane) P1: `Assembler::<2, 1>` with the stiffness `μ∇u·∇w`
//! (docs/seas-bp1.md). Errors are measured against closed forms with a degree-5
//! quadrature, never against the code's own output.
use rsf_fem::element::triangle_quadrature;
use rsf_fem::*;

use crate::common::cell_geometry;
use std::f64::consts::PI;

/// P1 gradients of the barycentric coordinates of a triangle.
fn grads(x: &[[f64; 2]]) -> [[f64; 2]; 3] {
    let det = (x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) - (x[2][0] - x[0][0]) * (x[1][1] - x[0][1]);
    [
        [(x[1][1] - x[2][1]) / det, (x[2][0] - x[1][0]) / det],
        [(x[2][1] - x[0][1]) / det, (x[0][0] - x[2][0]) / det],
        [(x[0][1] - x[1][1]) / det, (x[1][0] - x[0][0]) / det],
    ]
}

fn point(lam: &[f64; 3], x: &[[f64; 2]]) -> [f64; 2] {
    [
        lam[0] * x[0][0] + lam[1] * x[1][0] + lam[2] * x[2][0],
        lam[0] * x[0][1] + lam[1] * x[1][1] + lam[2] * x[2][1],
    ]
}

/// The load `∫ f φ_i` of the source `f` on the hat functions of `m`, by degree-5
/// quadrature.
fn body_load(m: &TriangleMesh, f: impl Fn(&[f64; 2]) -> f64) -> Vec<f64> {
    let q = triangle_quadrature();
    let mut load = vec![0.0; m.num_vertices()];
    for c in 0..m.num_cells() {
        let (v, x, area) = cell_geometry(m, c);
        for (lam, w) in &q {
            let fp = f(&point(lam, &x));
            for a in 0..3 {
                load[v[a]] += w * area * fp * lam[a];
            }
        }
    }
    load
}

/// Solves `−∇·(μ∇u) = f` with `u = g` on the nodes selected by `dirichlet` (natural,
/// traction-free elsewhere); the load by degree-5 quadrature.
fn solve(
    m: &TriangleMesh,
    mu: f64,
    f: impl Fn(&[f64; 2]) -> f64,
    g: impl Fn(&[f64; 2]) -> f64,
    dirichlet: impl Fn(&[f64; 2]) -> bool,
) -> Vec<f64> {
    let asm = Assembler::scalar(m).unwrap();
    assert_eq!(asm.num_dofs(), m.num_vertices());
    let k = asm.laplace(m, mu).unwrap();
    let load = body_load(m, f);
    let mut cons = Constraints::<1>::new(m.num_vertices());
    let seg = BoundarySegment::from_predicate(m, "dirichlet", &dirichlet).unwrap();
    for &p in seg.nodes() {
        cons.fix(p, 0, g(&m.vertices()[p])).unwrap();
    }
    let mut sys = ConstrainedSystem::new(k.as_ref(), cons.fixed()).unwrap();
    let mut uh = vec![0.0; m.num_vertices()];
    cons.apply(&mut uh);
    sys.solve(&load, &mut uh).unwrap();
    uh
}

/// (L² error, energy error `(∫μ|∇(u − u_h)|²)^½`).
fn errors(
    m: &TriangleMesh,
    uh: &[f64],
    mu: f64,
    u: impl Fn(&[f64; 2]) -> f64,
    grad: impl Fn(&[f64; 2]) -> [f64; 2],
) -> (f64, f64) {
    let q = triangle_quadrature();
    let (mut l2, mut en) = (0.0, 0.0);
    for c in 0..m.num_cells() {
        let (v, x, area) = cell_geometry(m, c);
        let g = grads(&x);
        let mut gh = [0.0; 2];
        for a in 0..3 {
            for d in 0..2 {
                gh[d] += uh[v[a]] * g[a][d];
            }
        }
        for (lam, w) in &q {
            let p = point(lam, &x);
            let uhp: f64 = (0..3).map(|a| lam[a] * uh[v[a]]).sum();
            l2 += w * area * (u(&p) - uhp).powi(2);
            let ge = grad(&p);
            en += w * area * mu * ((ge[0] - gh[0]).powi(2) + (ge[1] - gh[1]).powi(2));
        }
    }
    (l2.sqrt(), en.sqrt())
}

#[test]
fn manufactured_solution_rates() {
    // u = sin(πx) cos(1.5πy) + x y on [0, 2] × [0, 1], μ = 3: −μΔu = μ(π² + 2.25π²) sin cos.
    let mu = 3.0;
    let (a, b) = (PI, 1.5 * PI);
    let u = |x: &[f64; 2]| (a * x[0]).sin() * (b * x[1]).cos() + x[0] * x[1];
    let grad = |x: &[f64; 2]| {
        [
            a * (a * x[0]).cos() * (b * x[1]).cos() + x[1],
            -b * (a * x[0]).sin() * (b * x[1]).sin() + x[0],
        ]
    };
    let f = |x: &[f64; 2]| mu * (a * a + b * b) * (a * x[0]).sin() * (b * x[1]).cos();
    let mut errs = Vec::new();
    for n in [4usize, 8, 16, 32, 64] {
        let m = rectangle([0.0, 0.0], [2.0, 1.0], 2 * n + 1, n + 1, Diagonal::Forward).unwrap();
        // Dirichlet on x = 0, x = 2 and y = 1; traction-free y = 0 with the matching
        // Neumann datum: μ ∂u/∂n = −μ ∂_y u(x, 0) = −μ x, added below as a boundary load.
        let uh = {
            let asm = Assembler::scalar(&m).unwrap();
            let k = asm.laplace(&m, mu).unwrap();
            let mut load = body_load(&m, f);
            // Neumann on y = 0: g = −μ x, exact for P1 hat functions on each segment
            // (∫ g φ_i with g linear: Simpson is exact).
            let dx = 2.0 / (2 * n) as f64;
            for i in 0..2 * n {
                let (x0, x1) = (i as f64 * dx, (i + 1) as f64 * dx);
                let (g0, g1) = (-mu * x0, -mu * x1);
                load[i] += dx * (2.0 * g0 + g1) / 6.0;
                load[i + 1] += dx * (g0 + 2.0 * g1) / 6.0;
            }
            let mut cons = Constraints::<1>::new(m.num_vertices());
            for (p, x) in m.vertices().iter().enumerate() {
                if x[0] < 1e-12 || x[0] > 2.0 - 1e-12 || x[1] > 1.0 - 1e-12 {
                    cons.fix(p, 0, u(x)).unwrap();
                }
            }
            let mut sys = ConstrainedSystem::new(k.as_ref(), cons.fixed()).unwrap();
            let mut uh = vec![0.0; m.num_vertices()];
            cons.apply(&mut uh);
            sys.solve(&load, &mut uh).unwrap();
            uh
        };
        errs.push(errors(&m, &uh, mu, u, grad));
    }
    let rates: Vec<(f64, f64)> = errs
        .windows(2)
        .map(|w| ((w[0].0 / w[1].0).log2(), (w[0].1 / w[1].1).log2()))
        .collect();
    eprintln!("errors {errs:?}\nrates {rates:?}");
    for &(l2, en) in &rates[rates.len() - 2..] {
        assert!((l2 - 2.0).abs() <= 0.1, "L2 rate {l2}");
        assert!((en - 1.0).abs() <= 0.1, "energy rate {en}");
    }
}

#[test]
fn kernel_is_the_constants_and_energy_is_exact_for_linear_fields() {
    let xs = geometric_grading(0.1, 0.5, 1.3, 4.0).unwrap();
    let ys = geometric_grading(0.05, 0.0, 1.5, 3.0).unwrap();
    let m = rectangle_from_coordinates(&xs, &ys, Diagonal::Backward).unwrap();
    let mu = 32.038e9;
    let asm = Assembler::scalar(&m).unwrap();
    let k = asm.laplace(&m, mu).unwrap();
    let n = m.num_vertices();
    let apply = |u: &[f64]| {
        let mut out = vec![0.0; n];
        spmv_add(k.as_ref(), 1.0, u, &mut out);
        out
    };
    let ones = vec![1.0; n];
    let k1 = apply(&ones);
    let scale = mu; // entries of K are O(μ)
    assert!(k1.iter().all(|r| r.abs() <= 1e-12 * scale), "K·1 ≠ 0");
    // uᵀKu = ∫ μ |∇u|² exactly for linear u = 2x − 3y on [0,4]×[0,3]: μ·13·12.
    let lin: Vec<f64> = m
        .vertices()
        .iter()
        .map(|x| 2.0 * x[0] - 3.0 * x[1])
        .collect();
    let e: f64 = lin.iter().zip(apply(&lin)).map(|(u, ku)| u * ku).sum();
    let exact = mu * 13.0 * 12.0;
    assert!((e - exact).abs() <= 1e-12 * exact, "{e} vs {exact}");
    // Only the constants: with one node fixed the matrix is positive definite (a
    // Cholesky factorisation exists).
    let mut fixed = vec![false; n];
    fixed[n / 2] = true;
    ConstrainedSystem::new(k.as_ref(), &fixed).expect("K with one node fixed is SPD");
    // Mass: total ρ·area, and the scalar mass equals one component of the vector mass.
    let ms = asm.mass(&m, 2670.0).unwrap();
    let mut m1 = vec![0.0; n];
    spmv_add(ms.as_ref(), 1.0, &ones, &mut m1);
    let total: f64 = m1.iter().sum();
    assert!((total - 2670.0 * 12.0).abs() <= 1e-9 * total);
    let mv = Assembler::new(&m).unwrap().mass(&m, 2670.0).unwrap();
    let mut e0 = vec![0.0; 2 * n];
    for i in 0..n {
        e0[2 * i] = lin[i];
    }
    let mut mve = vec![0.0; 2 * n];
    spmv_add(mv.as_ref(), 1.0, &e0, &mut mve);
    let mut mse = vec![0.0; n];
    spmv_add(ms.as_ref(), 1.0, &lin, &mut mse);
    for i in 0..n {
        assert!((mve[2 * i] - mse[i]).abs() <= 1e-9 * total);
        assert_eq!(mve[2 * i + 1], 0.0);
    }
}

#[test]
fn invalid_shear_modulus_is_an_error() {
    let m = rectangle([0.0, 0.0], [1.0, 1.0], 3, 3, Diagonal::Forward).unwrap();
    let asm = Assembler::scalar(&m).unwrap();
    for mu in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            asm.laplace(&m, mu),
            Err(Error::InvalidShearModulus(_))
        ));
    }
}

/// The antisymmetric fault: slip δ on `0 ≤ z ≤ W` of the plane x = 0 in the half-space
/// z ≥ 0 (free surface z = 0). The closed form (a screw dislocation at depth W and its
/// image) is `u(x, z) = δ/(2π) [atan((z + W)/x) − atan((z − W)/x)]`: `u(0⁺, z) = δ/2`
/// above W (slip = 2 × boundary displacement), 0 below, and at the surface
/// `u(x, 0) = (δ/π) atan(W/x)`. Solved on a graded 400 × 400 km quadrant with u = δ/2 /
/// 0 on x = 0 and the closed form on the far sides.
#[test]
fn antiplane_fault_slip_matches_the_screw_dislocation() {
    let (w, delta, l) = (15e3, 2.0, 400e3);
    let exact = |x: &[f64; 2]| {
        if x[0] <= 0.0 {
            return if x[1] < w { 0.5 * delta } else { 0.0 };
        }
        delta / (2.0 * PI) * (((x[1] + w) / x[0]).atan() - ((x[1] - w) / x[0]).atan())
    };
    let mut errs = Vec::new();
    for h in [1000.0, 500.0, 250.0] {
        let xs = geometric_grading(h, 0.0, 1.08, l).unwrap();
        let zs = geometric_grading(h, 40e3, 1.08, l).unwrap();
        let m = rectangle_from_coordinates(&xs, &zs, Diagonal::Forward).unwrap();
        let uh = solve(
            &m,
            32e9,
            |_| 0.0,
            exact,
            |x| x[0] < 1e-9 || x[0] > l - 1e-6 || x[1] > l - 1e-6,
        );
        // Surface displacement at x = W/2, W, 2W, 4W (nodes on z = 0 nearest to these).
        let mut worst: f64 = 0.0;
        for xq in [0.5 * w, w, 2.0 * w, 4.0 * w] {
            let (p, x) = m
                .vertices()
                .iter()
                .enumerate()
                .filter(|(_, x)| x[1] == 0.0)
                .min_by(|a, b| (a.1[0] - xq).abs().total_cmp(&(b.1[0] - xq).abs()))
                .unwrap();
            let e = (uh[p] - exact(x)).abs() / delta;
            worst = worst.max(e);
        }
        errs.push(worst);
    }
    eprintln!("surface errors / δ for h = 1000, 500, 250 m: {errs:?}");
    assert!(errs[2] < 2e-3, "surface error {} δ", errs[2]);
    assert!(errs[2] < errs[0], "no convergence: {errs:?}");
}

#[test]
fn geometric_grading_properties_and_errors() {
    let c = geometric_grading(25.0, 40e3, 1.05, 400e3).unwrap();
    assert_eq!(c[0], 0.0);
    assert_eq!(*c.last().unwrap(), 400e3);
    assert!((c[1600] - 40e3).abs() < 1e-6);
    for w in c.windows(2).take(1600) {
        assert!((w[1] - w[0] - 25.0).abs() < 1e-6);
    }
    let d: Vec<f64> = c.windows(2).map(|w| w[1] - w[0]).collect();
    for (i, w) in d.windows(2).enumerate().skip(1600) {
        // Spacing grows by `ratio` except the closing interval.
        if i + 2 < d.len() {
            assert!((w[1] / w[0] - 1.05).abs() < 1e-9, "ratio at {i}");
        }
    }
    let last = d[d.len() - 1];
    let prev = d[d.len() - 2];
    assert!(
        last >= 0.5 * prev && last <= 2.05 * prev * 1.05,
        "{prev} {last}"
    );
    for (h, u, r, l) in [
        (0.0, 0.0, 1.1, 1.0),
        (1.0, 0.0, 0.9, 10.0),
        (2.0, 0.0, 1.1, 1.0),
        (0.1, 2.0, 1.1, 1.0),
        (0.1, 0.0, f64::NAN, 1.0),
        (0.1, 0.0, 1.1, f64::INFINITY),
    ] {
        assert!(matches!(
            geometric_grading(h, u, r, l),
            Err(Error::InvalidGrid(_))
        ));
    }
    assert!(
        geometric_grading(1e-9, 0.0, 1.0, 1.0).is_err(),
        "1e9 coordinates"
    );
    assert!(rectangle_from_coordinates(&[0.0, 1.0, 1.0], &[0.0, 1.0], Diagonal::Forward).is_err());
    assert!(rectangle_from_coordinates(&[0.0], &[0.0, 1.0], Diagonal::Forward).is_err());
    // The equispaced case is `rectangle`.
    let a = rectangle([0.0, 0.0], [2.0, 1.0], 5, 3, Diagonal::Backward).unwrap();
    let b = rectangle_from_coordinates(
        &[0.0, 0.5, 1.0, 1.5, 2.0],
        &[0.0, 0.5, 1.0],
        Diagonal::Backward,
    )
    .unwrap();
    assert_eq!(a.cells(), b.cells());
    assert_eq!(a.vertices(), b.vertices());
}

/// The closed-form count of a grading bounds the coordinates it builds (never below, at
/// most 2 above) over spacings, uniform parts, ratios and lengths; sizes far beyond what
/// can be allocated are refused, not attempted.
#[test]
fn grading_count_bounds_the_grading_without_building_it() {
    for &h in &[1.0, 7.5, 25.0, 100.0] {
        for &uniform in &[0.0, 40.0, 1234.5, 15e3] {
            for &ratio in &[1.0, 1.01, 1.05, 1.3, 2.0, 10.0] {
                for &length in &[20e3, 100e3, 400e3] {
                    let n = geometric_grading(h, uniform, ratio, length).unwrap().len() as f64;
                    let estimate = geometric_grading_len(h, uniform, ratio, length);
                    assert!(
                        estimate >= n && estimate <= n + 2.0,
                        "h {h} uniform {uniform} ratio {ratio} length {length}: {estimate} vs {n}"
                    );
                }
            }
        }
    }
    for (h, uniform, ratio, length) in [
        (1e-300, 40e3, 1.05, 400e3),
        (25.0, 0.0, 1.0, 1e300),
        (1e-3, 40e3, 1.0, 400e3),
    ] {
        assert!(geometric_grading_len(h, uniform, ratio, length) > MAX_GRADED_COORDINATES);
        let e = geometric_grading(h, uniform, ratio, length).unwrap_err();
        assert!(e.to_string().contains("coordinates"), "{e}");
    }
    assert!(geometric_grading_len(0.0, 0.0, 1.05, 1.0).is_infinite());
}
