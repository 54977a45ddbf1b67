//! The pressure diffusing over a fault surface (SEAS BP8; docs/pore-pressure.md): the
//! closed forms at the check values of the benchmark's restatement (computed there
//! independently), the numerical field against them on a sequence of grids, against a
//! generic Crank–Nicolson solve of the same semi-discrete system (the well's storage
//! included), its exact volume balance through no-flux edges, and its typed errors.

use super::exp_integral::exp_integral_e1;
use super::*;

const HOUR: f64 = 3600.0;

/// BP8's fault zone (description Table 1): α = k/(φβη_f) = 0.05 m²/s.
fn zone() -> FaultZone {
    FaultZone {
        thickness: 1.0,
        permeability: 5e-14,
        porosity: 0.1,
        compressibility: 1e-8,
        viscosity: 1e-3,
    }
}

/// BP8's fault plane x₁ = 0 with (u, v) = (x₂, x₃).
fn plane() -> FaultPlane {
    FaultPlane {
        origin: [0.0; 3],
        axis_u: [0.0, 1.0, 0.0],
        axis_v: [0.0, 0.0, 1.0],
    }
}

/// BP8's well: r_well = 5 cm, S_well = 1e-7 m³/Pa (or `storage`).
fn well(storage: f64) -> SurfaceSource {
    SurfaceSource::Well(PeacemanWell {
        radius: 0.05,
        storage,
        equivalent_radius: None,
    })
}

/// Q₀ = 3e-3 m³/s for 100 h at the origin.
fn injection(source: SurfaceSource) -> SurfaceInjection {
    SurfaceInjection {
        injection: Injection {
            rate: 3e-3,
            shut_in: 100.0 * HOUR,
        },
        source,
        position: [0.0, 0.0],
    }
}

const GAUSSIAN: SurfaceSource = SurfaceSource::Gaussian { width: 50.0 };

/// The square `±half` (m) on `cells × cells`.
fn square(half: f64, cells: usize) -> SurfaceGrid {
    SurfaceGrid {
        lower: [-half, -half],
        upper: [half, half],
        cells: [cells, cells],
    }
}

fn diffusion(source: SurfaceSource, grid: SurfaceGrid) -> SurfaceDiffusion {
    SurfaceDiffusion::new(zone(), injection(source), plane(), grid).unwrap()
}

fn closed(source: SurfaceSource) -> SurfaceInjectionPressure {
    SurfaceInjectionPressure::new(zone(), injection(source), plane()).unwrap()
}

#[test]
fn the_exponential_integral_matches_abramowitz_and_stegun() {
    // A&S Table 5.1 (x e^x E₁(x) at x = 2, 10) and 5.1.11 at 0.1, 1 (values to 15 digits).
    for (x, want) in [
        (1e-3, 6.331_539_364_136_149),
        (0.1, 1.822_923_958_419_390_7),
        (1.0, 0.219_383_934_395_520_27),
        (2.0, 0.048_900_510_708_061_12),
        (10.0, 4.156_968_929_685_324e-6),
        (50.0, 3.783_264_029_550_459e-24),
    ] {
        let got = exp_integral_e1(x);
        assert!(
            ((got - want) / want).abs() < 1e-14,
            "E1({x}) = {got}, table {want}"
        );
    }
    // The two branches meet at 1.
    let (below, above) = (exp_integral_e1(1.0 - 1e-12), exp_integral_e1(1.0 + 1e-12));
    assert!((below - above).abs() < 1e-12, "{below} {above}");
    assert_eq!(exp_integral_e1(800.0), 0.0);
    assert!(exp_integral_e1(-1.0).is_nan());
}

#[test]
fn the_closed_forms_match_the_check_values_of_the_restatement() {
    // ../shared/benchmarks/seas-bp8.md "Pressure check values": p (MPa) at r (m) and t (h),
    // eq. 21 (GS) and eq. 25 (PW), superposed after the shut-in; 3 decimals printed.
    let hours = [1.0, 10.0, 50.0, 100.0, 150.0, 200.0, 300.0];
    let gs: [(f64, [f64; 7]); 5] = [
        (0.0, [0.642, 4.259, 10.047, 13.056, 4.841, 3.152, 1.882]),
        (50.0, [0.402, 3.070, 8.214, 11.090, 4.659, 3.078, 1.856]),
        (100.0, [0.099, 1.198, 4.845, 7.357, 4.157, 2.867, 1.781]),
        (200.0, [0.000, 0.044, 1.091, 2.563, 2.663, 2.161, 1.508]),
        (300.0, [0.000, 0.000, 0.179, 0.795, 1.314, 1.357, 1.144]),
    ];
    let pw: [(f64, [f64; 7]); 4] = [
        (50.0, [0.034, 3.819, 10.305, 13.453, 5.029, 3.228, 1.909]),
        (100.0, [0.000, 0.564, 4.600, 7.310, 4.438, 2.995, 1.829]),
        (200.0, [0.000, 0.003, 0.872, 2.376, 2.732, 2.224, 1.541]),
        (300.0, [0.000, 0.000, 0.119, 0.699, 1.278, 1.365, 1.160]),
    ];
    for (field, table) in [(closed(GAUSSIAN), &gs[..]), (closed(well(1e-7)), &pw[..])] {
        for &(r, row) in table {
            for (t, want) in hours.iter().zip(row) {
                // Along x₂, along −x₃ and on the diagonal: the same radius.
                let s = r / 2f64.sqrt();
                for x in [[0.0, r, 0.0], [7.0, 0.0, -r], [0.0, s, s]] {
                    let got = field.pressure(&x, t * HOUR) / 1e6;
                    assert!(
                        (got - want).abs() <= 5.0001e-4,
                        "r = {r} m, t = {t} h: {got} MPa, table {want}"
                    );
                }
            }
        }
    }
    // PW at r_e = 2.08 m (four digits printed): 21.69, 32.66, 40.34, 43.65 MPa.
    let pw_field = closed(well(1e-7));
    for (t, want) in [(1.0, 21.69), (10.0, 32.66), (50.0, 40.34), (100.0, 43.65)] {
        let got = pw_field.at([2.08, 0.0], t * HOUR) / 1e6;
        assert!((got - want).abs() <= 5.0001e-3, "{t} h: {got}");
    }
    // C = Q₀/(4παβφL) = 4.7746 MPa; continuity at the shut-in; the Darcy velocity points
    // away from the source with the point source's flux Q₀/L through every small circle.
    assert!((pw_field.scale() / 1e6 - 4.7746).abs() < 1e-4);
    let t = 100.0 * HOUR;
    let jump =
        closed(GAUSSIAN).at([30.0, 0.0], t * (1.0 + 1e-12)) - closed(GAUSSIAN).at([30.0, 0.0], t);
    assert!(jump.abs() < 1e-2, "{jump}");
    let q = pw_field
        .darcy_velocity_vector(&[0.0, 0.0, 0.5], 10.0 * HOUR)
        .unwrap();
    let flux = 2.0 * std::f64::consts::PI * 0.5 * q[2];
    let want = 3e-3 * (-0.25 / (4.0 * 0.05 * 10.0 * HOUR)).exp();
    assert!(
        q[0] == 0.0 && q[1] == 0.0 && (flux - want).abs() < 1e-15,
        "{q:?}"
    );
}

/// `max |p_h − p| / p(0, t)` over the nodes at multiples of 40 m within `r_min ≤ r ≤ 300 m`
/// at 10, 50 and 100 h, on the square ±800 m (far enough that the edges are not felt).
fn worst_error(source: SurfaceSource, h: f64, r_min: f64) -> f64 {
    let field = diffusion(source, square(800.0, (1600.0 / h) as usize));
    let exact = closed(source);
    let mut worst = 0.0_f64;
    for t in [10.0 * HOUR, 50.0 * HOUR, 100.0 * HOUR] {
        let peak = closed(GAUSSIAN).at([0.0, 0.0], t);
        for a in -7..=7 {
            for b in -7..=7 {
                let uv = [40.0 * a as f64, 40.0 * b as f64];
                let r = uv[0].hypot(uv[1]);
                if r < r_min || r > 300.0 {
                    continue;
                }
                worst = worst.max((field.at(uv, t) - exact.at(uv, t)).abs() / peak);
            }
        }
    }
    worst
}

#[test]
fn the_gaussian_source_converges_to_eq_21_at_second_order() {
    let errors: Vec<f64> = [40.0, 20.0, 10.0, 5.0]
        .iter()
        .map(|&h| worst_error(GAUSSIAN, h, 0.0))
        .collect();
    eprintln!("GS: max |p_h − p|/p(0, t) at h = 40, 20, 10, 5 m: {errors:?}");
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(order > 1.8 && order < 2.2, "order {order}: {errors:?}");
    }
    assert!(errors[3] < 1e-3, "{errors:?}");
}

#[test]
fn a_well_without_storage_converges_to_eq_25_away_from_it() {
    // The point source at a node: second order at r ≥ 80 m; at the well's node Peaceman's
    // equivalent radius 0.1985 h (e^{−γ}/(2√2) for the five-point Laplacian).
    let errors: Vec<f64> = [40.0, 20.0, 10.0, 5.0]
        .iter()
        .map(|&h| worst_error(well(0.0), h, 80.0))
        .collect();
    eprintln!(
        "PW, no storage: max |p_h − p|/p(0, t) (r ≥ 80 m) at h = 40, 20, 10, 5 m: {errors:?}"
    );
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(order > 1.8 && order < 2.2, "order {order}: {errors:?}");
    }
    let exact = closed(well(0.0));
    for h in [20.0, 10.0] {
        let field = diffusion(well(0.0), square(800.0, (1600.0 / h) as usize));
        let t = 100.0 * HOUR;
        let p_e = field.at([0.0, 0.0], t);
        // The radius where eq. 25 has the node's pressure (bisection on the monotone E₁).
        let (mut lo, mut hi) = (1e-3 * h, h);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if exact.at([mid, 0.0], t) > p_e {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let ratio = lo / h;
        eprintln!("h = {h} m: p_e(100 h) = {p_e} Pa is eq. 25 at r = {ratio} h");
        assert!((ratio - 0.1985).abs() < 1e-3, "{ratio}");
    }
}

/// The same semi-discrete system assembled and stepped by Crank–Nicolson (dense LU): the
/// nodes of `grid` (areas halved on edges, quartered at corners), the five-point fluxes,
/// and with a storing well one more unknown coupled to its node by `WI`. Returns the nodes'
/// pressures (and the well's) at `times` (multiples of `dt`, the shut-in one too).
fn crank_nicolson(
    field: &SurfaceDiffusion,
    source_weights: &dyn Fn(usize, usize) -> f64,
    well: Option<([usize; 2], f64, f64)>,
    (dt, times): (f64, &[f64]),
) -> Vec<Vec<f64>> {
    let grid = *field.grid();
    let z = field.zone();
    let [nu, nv] = grid.nodes();
    let h = grid.spacing();
    let n = nu * nv + usize::from(well.is_some());
    let id = |i: usize, j: usize| i + nu * j;
    let edge = |i: usize, m: usize| if i == 0 || i == m - 1 { 0.5 } else { 1.0 };
    let mut s = vec![0.0; n];
    let mut k = faer::Mat::<f64>::zeros(n, n);
    let tr = z.mobility() * z.thickness;
    for j in 0..nv {
        for i in 0..nu {
            s[id(i, j)] = z.storage() * h[0] * h[1] * edge(i, nu) * edge(j, nv);
            // Face to (i+1, j): length h_v (halved on the v-edges); to (i, j+1) likewise.
            let mut couple = |a: usize, b: usize, t: f64| {
                k[(a, a)] += t;
                k[(b, b)] += t;
                k[(a, b)] -= t;
                k[(b, a)] -= t;
            };
            if i + 1 < nu {
                couple(id(i, j), id(i + 1, j), tr * h[1] * edge(j, nv) / h[0]);
            }
            if j + 1 < nv {
                couple(id(i, j), id(i, j + 1), tr * h[0] * edge(i, nu) / h[1]);
            }
        }
    }
    let mut f = vec![0.0; n];
    for j in 0..nv {
        for i in 0..nu {
            f[id(i, j)] = source_weights(i, j);
        }
    }
    if let Some((e, wi, storage)) = well {
        let (a, b) = (id(e[0], e[1]), n - 1);
        s[b] = storage;
        k[(a, a)] += wi;
        k[(b, b)] += wi;
        k[(a, b)] -= wi;
        k[(b, a)] -= wi;
        f = vec![0.0; n];
        f[b] = 1.0;
    }
    let lhs = faer::Mat::from_fn(n, n, |a, b| {
        0.5 * k[(a, b)] + if a == b { s[a] / dt } else { 0.0 }
    });
    let lu = lhs.partial_piv_lu();
    let inj = 3e-3;
    let shut_in = 100.0 * HOUR;
    let mut p = faer::Col::<f64>::zeros(n);
    let (mut t, mut out) = (0.0, Vec::new());
    for &target in times {
        while t < target - 0.5 * dt {
            let q = if t + 0.5 * dt < shut_in { inj } else { 0.0 };
            let kp = &k * &p;
            let rhs = faer::Col::from_fn(n, |a| s[a] / dt * p[a] - 0.5 * kp[a] + q * f[a]);
            p = faer::linalg::solvers::Solve::solve(&lu, &rhs);
            t += dt;
        }
        out.push(p.iter().copied().collect());
    }
    out
}

#[test]
fn the_exact_field_is_the_limit_of_crank_nicolson_steps_well_storage_included() {
    // A coarse square (100 m cells on ±400 m) for 200 h: the exact-in-time field is what
    // Crank–Nicolson converges to at second order in Δt, for the Gaussian and for the
    // storing well (its rank-one coupling solved by the eigendecomposition); the shut-in at
    // 100 h is a step's end.
    let grid = square(400.0, 8);
    let times = [10.0 * HOUR, 100.0 * HOUR, 150.0 * HOUR, 200.0 * HOUR];
    for source in [GAUSSIAN, well(1e-7)] {
        let field = diffusion(source, grid);
        let [nu, _] = grid.nodes();
        if field.well_index().is_some() {
            // The modes even in both indices (5 × 5 but the uniform one) couple, the square
            // pairing (k, l) with (l, k): 14 rates, 12 of them distinct (sin²(π/8) +
            // sin²(3π/8) = 2 sin²(π/4) = 1); ties short of the last bit stay two directions.
            // With the well and the uniform nodes, D is 13 to 15.
            let d = field.well_dimension().unwrap();
            assert!((13..=15).contains(&d), "{d}");
        }
        let exact: Vec<Vec<f64>> = times
            .iter()
            .map(|&t| {
                let mut v = field.nodes(t);
                v.extend(field.well_pressure(t));
                v
            })
            .collect();
        let weights = |i: usize, j: usize| {
            // The Gaussian's node weights, as the field builds them (area × density,
            // scaled to 1): recomputed here.
            let x = grid.node(i, j);
            let edge = |a: usize| if a == 0 || a == nu - 1 { 0.5 } else { 1.0 };
            edge(i) * edge(j) * (-(x[0] * x[0] + x[1] * x[1]) / 5000.0).exp()
        };
        let total: f64 = (0..nu)
            .flat_map(|j| (0..nu).map(move |i| (i, j)))
            .map(|(i, j)| weights(i, j))
            .sum();
        let norm_weights = |i: usize, j: usize| weights(i, j) / total;
        let w = field.well_index().map(|wi| ([4, 4], wi, 1e-7));
        let mut errors = Vec::new();
        for dt in [1800.0, 900.0, 450.0] {
            let steps = crank_nicolson(&field, &norm_weights, w, (dt, &times));
            let mut worst = 0.0_f64;
            for (a, b) in steps.iter().zip(&exact) {
                let scale = b.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
                for (x, y) in a.iter().zip(b) {
                    worst = worst.max((x - y).abs() / scale);
                }
            }
            errors.push(worst);
        }
        eprintln!("{source:?}: max |p_CN − p| / max |p| at Δt = 1800, 900, 450 s: {errors:?}");
        for e in errors.windows(2) {
            let order = (e[0] / e[1]).log2();
            assert!(order > 1.9 && order < 2.1, "order {order}: {errors:?}");
        }
        assert!(errors[2] < 1e-4, "{errors:?}");
    }
}

/// `Σ φβL A_ij p_ij (+ S_well p_w)` (m³) from the nodes, the areas recomputed here.
fn stored(field: &SurfaceDiffusion, t: f64, storage_well: f64) -> f64 {
    let g = *field.grid();
    let [nu, nv] = g.nodes();
    let h = g.spacing();
    let p = field.nodes(t);
    let edge = |i: usize, m: usize| if i == 0 || i == m - 1 { 0.5 } else { 1.0 };
    let mut v = 0.0;
    for j in 0..nv {
        for i in 0..nu {
            v += zone().storage() * h[0] * h[1] * edge(i, nu) * edge(j, nv) * p[i + nu * j];
        }
    }
    v + storage_well * field.well_pressure(t).unwrap_or(0.0)
}

#[test]
fn the_volume_is_kept_to_round_off_and_the_pressure_ends_uniform() {
    // BP8's Ω_f at 10 m (80 × 80 cells), both sources.
    let grid = square(400.0, 80);
    let ends = [1.0, 10.0, 50.0, 100.0, 150.0, 300.0, 720.0, 1e5];
    for (source, storage) in [(GAUSSIAN, 0.0), (well(1e-7), 1e-7), (well(0.0), 0.0)] {
        let field = diffusion(source, grid);
        let mut worst = 0.0_f64;
        for t in ends.map(|h| h * HOUR) {
            let injected = 3e-3 * t.min(100.0 * HOUR);
            worst = worst.max((stored(&field, t, storage) - injected).abs() / injected);
        }
        eprintln!("{source:?}: |stored − injected| / injected ≤ {worst:.1e}");
        // Round-off: 6 561 nodes, each the sum of 81 × 81 modes.
        assert!(worst < 1e-12, "{worst}");
        // After many diffusion times: uniform at Q₀ t_off / (φβL |Ω_f| + S_well), 1.6875 MPa
        // without a storing well.
        let late = field.nodes(1e5 * HOUR);
        let uniform = 1080.0 / (zone().storage() * 0.64e6 + storage);
        for p in late.iter().chain(field.well_pressure(1e5 * HOUR).iter()) {
            assert!(
                (p - uniform).abs() < 1e-10 * uniform,
                "{p} against {uniform}"
            );
        }
        if storage == 0.0 {
            assert!((uniform - 1.6875e6).abs() < 1e-6, "{uniform}");
        }
    }
}

#[test]
fn the_bounded_gaussian_field_matches_the_restatements_own_solve() {
    // ../shared/benchmarks/seas-bp8.md "Bounded Ω_f with no-flux edges, GS" (finite volumes
    // at 5 m, explicit Euler; its 10 m run within 0.02 MPa): p (MPa).
    let field = diffusion(GAUSSIAN, square(400.0, 80));
    let table: [(f64, [f64; 4]); 7] = [
        (10.0, [4.263, 0.044, 0.001, 0.000]),
        (50.0, [10.052, 1.091, 0.250, 0.001]),
        (100.0, [13.062, 2.571, 0.990, 0.060]),
        (150.0, [4.851, 2.716, 1.573, 0.308]),
        (200.0, [3.203, 2.306, 1.675, 0.703]),
        (300.0, [2.125, 1.892, 1.687, 1.305]),
        (720.0, [1.691, 1.689, 1.688, 1.684]),
    ];
    let points = [[0.0, 0.0], [200.0, 0.0], [200.0, 200.0], [400.0, 400.0]];
    let mut worst = 0.0_f64;
    for (t, row) in table {
        for (uv, want) in points.iter().zip(row) {
            worst = worst.max((field.at(*uv, t * HOUR) / 1e6 - want).abs());
        }
    }
    eprintln!("GS at 10 m against the restatement's 5 m table: max difference {worst:.4} MPa");
    assert!(worst < 0.02, "{worst}");
}

#[test]
fn the_darcy_velocity_converges_and_vanishes_across_the_edges() {
    let exact = closed(GAUSSIAN);
    let t = 50.0 * HOUR;
    let points = [[100.0, 0.0], [0.0, -200.0], [120.0, 160.0]];
    let mut errors = Vec::new();
    for h in [20.0, 10.0, 5.0] {
        let field = diffusion(GAUSSIAN, square(800.0, (1600.0 / h) as usize));
        let mut worst = 0.0_f64;
        for uv in points {
            let (a, b) = (field.darcy_at(uv, t), exact.darcy_at(uv, t));
            let size = b[0].hypot(b[1]);
            worst = worst.max((a[0] - b[0]).hypot(a[1] - b[1]) / size);
        }
        errors.push(worst);
    }
    eprintln!("GS Darcy velocity: max relative error at h = 20, 10, 5 m: {errors:?}");
    for e in errors.windows(2) {
        assert!(e[1] < 0.3 * e[0], "{errors:?}");
    }
    // Zero normal flux on the edges of Ω_f, 0 at the symmetric source, and the model's
    // vector along the plane's axes.
    let field = diffusion(GAUSSIAN, square(400.0, 80));
    let t = 200.0 * HOUR;
    assert_eq!(field.darcy_at([400.0, 130.0], t)[0], 0.0);
    assert_eq!(field.darcy_at([-70.0, -400.0], t)[1], 0.0);
    assert_eq!(field.darcy_at([0.0, 0.0], t), [0.0, 0.0]);
    let q = field.darcy_velocity_vector(&[0.0, 60.0, -20.0], t).unwrap();
    let uv = field.darcy_at([60.0, -20.0], t);
    assert_eq!(q, [0.0, uv[0], uv[1]]);
    assert!(uv[0] > 0.0 && uv[1] < 0.0);
}

#[test]
fn a_tilted_plane_maps_the_models_points_to_fault_coordinates() {
    // A plane through (10, 20, −30) with axes rotated about its normal and out of the
    // coordinate planes: a point u e_u + v e_v (+ any normal offset) has the field of (u, v).
    let (c, s) = (0.6, 0.8);
    let tilted = FaultPlane {
        origin: [10.0, 20.0, -30.0],
        axis_u: [c, s, 0.0],
        axis_v: [0.0, 0.0, 1.0],
    };
    let field =
        SurfaceDiffusion::new(zone(), injection(GAUSSIAN), tilted, square(400.0, 40)).unwrap();
    let t = 30.0 * HOUR;
    let (u, v) = (70.0, -45.0);
    let normal = [s, -c, 0.0];
    let x = [0, 1, 2]
        .map(|i| tilted.origin[i] + u * tilted.axis_u[i] + v * tilted.axis_v[i] + 3.0 * normal[i]);
    assert!((field.pressure(&x, t) - field.at([u, v], t)).abs() < 1e-9 * field.at([u, v], t));
    let mut out = [0.0];
    field.pressures(t, &[x], &mut out);
    assert_eq!(out[0], field.pressure(&x, t));
    let q = field.darcy_velocity_vector(&x, t).unwrap();
    let along = field.darcy_at([u, v], t);
    assert!((q[0] - c * along[0]).abs() < 1e-12 * along[0].abs());
    assert!((q[2] - along[1]).abs() < 1e-12 * along[1].abs());
}

#[test]
fn a_uniform_initial_pressure_without_injection_stays_exact() {
    let stopped = SurfaceInjection {
        injection: Injection {
            rate: 0.0,
            shut_in: 100.0 * HOUR,
        },
        ..injection(well(1e-7))
    };
    for source in [GAUSSIAN, well(1e-7)] {
        let field = SurfaceDiffusion::new(
            zone(),
            SurfaceInjection { source, ..stopped },
            plane(),
            square(400.0, 16),
        )
        .unwrap()
        .with_initial_pressure(3e6)
        .unwrap();
        for t in [0.0, 1.0, 1e3, 1e6] {
            for x in [[0.0, 13.0, -7.0], [5.0, 400.0, 400.0], [0.0, 1e4, 0.0]] {
                assert_eq!(field.pressure(&x, t), 3e6);
            }
        }
        assert_eq!(field.breakpoints(), vec![100.0 * HOUR]);
    }
}

#[test]
fn invalid_surface_fields_are_typed_errors() {
    let name_of = |r: crate::Result<SurfaceDiffusion>| match r {
        Err(crate::Error::InvalidParameter { name, .. }) => name,
        other => panic!("{other:?}"),
    };
    let grid = square(400.0, 8);
    let z = zone();
    for (bad, name) in [
        (
            FaultZone {
                thickness: 0.0,
                ..z
            },
            "zone.thickness",
        ),
        (
            FaultZone {
                permeability: f64::NAN,
                ..z
            },
            "zone.permeability",
        ),
        (
            FaultZone {
                porosity: -0.1,
                ..z
            },
            "zone.porosity",
        ),
        (
            FaultZone {
                compressibility: f64::INFINITY,
                ..z
            },
            "zone.compressibility",
        ),
        (
            FaultZone {
                viscosity: 0.0,
                ..z
            },
            "zone.viscosity",
        ),
    ] {
        assert_eq!(
            name_of(SurfaceDiffusion::new(
                bad,
                injection(GAUSSIAN),
                plane(),
                grid
            )),
            name
        );
    }
    let inj = injection(GAUSSIAN);
    let with = |source, position| SurfaceInjection {
        source,
        position,
        ..inj
    };
    let w = PeacemanWell {
        radius: 0.05,
        storage: 1e-7,
        equivalent_radius: None,
    };
    for (bad, name) in [
        (
            with(SurfaceSource::Gaussian { width: 0.0 }, [0.0; 2]),
            "source.width",
        ),
        (with(GAUSSIAN, [f64::NAN, 0.0]), "source.position"),
        (with(GAUSSIAN, [500.0, 0.0]), "source.position"),
        (with(well(1e-7), [30.0, 0.0]), "source.position"),
        (with(well(1e-7), [400.0, 0.0]), "source.position"),
        (with(well(-1.0), [0.0; 2]), "well.storage"),
        (
            with(
                SurfaceSource::Well(PeacemanWell { radius: 0.0, ..w }),
                [0.0; 2],
            ),
            "well.radius",
        ),
        (
            with(
                SurfaceSource::Well(PeacemanWell {
                    equivalent_radius: Some(0.01),
                    ..w
                }),
                [0.0; 2],
            ),
            "well.equivalent_radius",
        ),
        (
            with(
                SurfaceSource::Well(PeacemanWell { radius: 30.0, ..w }),
                [0.0; 2],
            ),
            "well.equivalent_radius",
        ),
        (
            SurfaceInjection {
                injection: Injection {
                    rate: f64::NAN,
                    shut_in: 1.0,
                },
                ..inj
            },
            "injection.rate",
        ),
    ] {
        assert_eq!(name_of(SurfaceDiffusion::new(z, bad, plane(), grid)), name);
    }
    let p = plane();
    for (bad, name) in [
        (
            FaultPlane {
                origin: [f64::NAN, 0.0, 0.0],
                ..p
            },
            "plane.origin",
        ),
        (
            FaultPlane {
                axis_u: [0.0, 2.0, 0.0],
                ..p
            },
            "plane.axis_u",
        ),
        (
            FaultPlane {
                axis_v: [0.0, 0.6, 0.8],
                ..p
            },
            "plane.axis_v",
        ),
    ] {
        assert_eq!(name_of(SurfaceDiffusion::new(z, inj, bad, grid)), name);
    }
    for bad in [
        square(400.0, 0),
        square(400.0, MAX_SURFACE_CELLS + 1),
        SurfaceGrid {
            upper: [-500.0, 400.0],
            ..grid
        },
    ] {
        assert_eq!(name_of(SurfaceDiffusion::new(z, inj, p, bad)), "grid");
    }
    // A well off the centre of a fine grid couples more directions than allowed.
    assert_eq!(
        name_of(SurfaceDiffusion::new(
            z,
            with(well(1e-7), [10.0, 30.0]),
            p,
            square(400.0, 160)
        )),
        "grid"
    );
    assert!(matches!(
        SurfaceInjectionPressure::new(z, inj, p).unwrap().with_initial_pressure(f64::NAN),
        Err(crate::Error::InvalidParameter { ref name, .. }) if name == "initial_pressure"
    ));
    assert!(matches!(
        SurfaceInjectionPressure::new(FaultZone { viscosity: -1.0, ..z }, inj, p),
        Err(crate::Error::InvalidParameter { ref name, .. }) if name == "zone.viscosity"
    ));
}

/// The cost of BP8's fields (docs/pore-pressure.md, "Cost"): set-up, and an evaluation at
/// a new time at the cell centres of BP8's boundary elements, against the closed form at
/// the same points (the baseline); each the fastest of 5 batches of 40 (the machine is
/// shared); run with
/// `cargo test --release -p rsf --lib surface_diffusion_cost -- --ignored --nocapture`.
#[test]
#[ignore = "a measurement: prints timings"]
fn surface_diffusion_cost() {
    use std::time::Instant;
    let fastest = |f: &mut dyn FnMut(usize)| {
        (0..5)
            .map(|b| {
                let start = Instant::now();
                for e in 0..40 {
                    f(40 * b + e);
                }
                start.elapsed().as_secs_f64() / 40.0
            })
            .fold(f64::INFINITY, f64::min)
    };
    for cells in [20, 40, 80, 160] {
        let h = 800.0 / cells as f64;
        let centres: Vec<[f64; 3]> = (0..cells * cells)
            .map(|c| {
                let (i, j) = (c % cells, c / cells);
                [
                    0.0,
                    -400.0 + (i as f64 + 0.5) * h,
                    -400.0 + (j as f64 + 0.5) * h,
                ]
            })
            .collect();
        let mut out = vec![0.0; centres.len()];
        for (name, source) in [("GS", GAUSSIAN), ("PW", well(1e-7))] {
            let start = Instant::now();
            let field = diffusion(source, square(400.0, cells));
            let setup = start.elapsed().as_secs_f64();
            let new = fastest(&mut |e| field.pressures(3600.0 + e as f64, &centres, &mut out));
            let same = fastest(&mut |_| field.pressures(3600.0, &centres, &mut out));
            let exact = closed(source);
            let baseline = fastest(&mut |e| exact.pressures(3600.0 + e as f64, &centres, &mut out));
            eprintln!(
                "{name} {h} m ({cells}x{cells} cells, {} points, D = {:?}): set-up {setup:.3} s; \
                 an evaluation at a new time {:.3} ms, at the same time {:.3} ms; the closed \
                 form {:.3} ms",
                centres.len(),
                field.well_dimension(),
                new * 1e3,
                same * 1e3,
                baseline * 1e3,
            );
        }
    }
}
