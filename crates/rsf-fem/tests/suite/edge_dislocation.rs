//! Plane-strain dip slip on a buried fault inside the body (issue 35): uniform slip on a
//! segment dipping at 45° in a half-space, prescribed as the jump of the mean–jump change
//! of variables ([`FaultSides::mean_jump_transform`]), against the closed form of the
//! surface displacement of two edge dislocations (Freund & Barnett 1976, BSSA 66(3); in
//! the form of Segall 2010, *Earthquake and Volcano Deformation*, §3.3; docs/math.md §15).
//! The surface error converges at first order in h.
use rsf_fem::*;

/// Up-dip end and down-dip end of the fault: from depth 1 m at x = 0 down to depth 2 m at
/// x = 1 m (dip δ = 45°, dipping towards +x; the hanging wall is the side above it).
const UPDIP: [f64; 2] = [0.0, -1.0];
const DOWNDIP: [f64; 2] = [1.0, -2.0];
/// Slip (m), reverse (thrust) positive: the hanging wall moves up-dip.
const SLIP: f64 = 1.0;

/// Surface displacement `(u_x, u_y)` (y up) at `x` of uniform reverse slip `s` on a fault
/// whose up-dip end is at depth `d1 > 0` below `x = 0`, down-dip length `l`, dip `delta`
/// towards +x: the difference of two edge dislocations at the fault's ends (independent
/// of ν). `ζ_k = (x − x_k)/d_k` at the ends `(x_k, −d_k)`.
fn surface_displacement(x: f64, d1: f64, l: f64, delta: f64, s: f64) -> [f64; 2] {
    let (sv, sh) = (s * delta.sin(), s * delta.cos());
    let d2 = d1 + l * delta.sin();
    let z1 = x / d1;
    let z2 = (x - l * delta.cos()) / d2;
    let pi = std::f64::consts::PI;
    let uy = (sv * z1.atan() + (sh + sv * z1) / (1.0 + z1 * z1)
        - sv * z2.atan()
        - (sh + sv * z2) / (1.0 + z2 * z2))
        / pi;
    let ux = -(sh * z1.atan() + (sv - sh * z1) / (1.0 + z1 * z1)
        - sh * z2.atan()
        - (sv - sh * z2) / (1.0 + z2 * z2))
        / pi;
    [ux, uy]
}

/// `0 = c_0 < … ` with spacing `h` to `uniform`, then growing by 1.2 per cell to 1e5 m.
fn graded(h: f64, uniform: f64) -> Vec<f64> {
    geometric_grading(h, uniform, 1.2, 1e5).unwrap()
}

/// The largest surface error (m, either component) for |x| ≤ 4 m at h = 1/n m, and the
/// number of split pairs.
fn surface_error(n: usize) -> (f64, usize) {
    let h = 1.0 / n as f64;
    let mut xs: Vec<f64> = graded(h, 4.0).iter().rev().map(|x| -x).collect();
    xs.pop();
    xs.extend(graded(h, 5.0));
    let ys: Vec<f64> = graded(h, 4.0).iter().rev().map(|y| -y).collect();
    let mesh = rectangle_from_coordinates(&xs, &ys, Diagonal::Backward).unwrap();
    let (split, sides) = mesh.split_along_segment("fault", UPDIP, DOWNDIP).unwrap();
    assert_eq!(sides.tips().len(), 2, "both ends are buried tips");
    let nv = split.num_vertices();
    let tr = sides.mean_jump_transform::<2>(&split).unwrap();
    let k = Assembler::new(&split)
        .unwrap()
        .stiffness(&split, &LinearElasticity::plane_strain(1e10, 0.25).unwrap())
        .unwrap();
    let kp = tr.congruence(&k).unwrap();

    // The prescribed jump u(hanging wall) − u(footwall) = s·(−cos δ, sin δ) (up-dip), as
    // new coordinates: T⁻¹ of a field that is 0 except on the side the jump's pair
    // normal (minus → plus) points to.
    let dir = [-(0.5f64.sqrt()), 0.5f64.sqrt()];
    let mut cartesian = vec![0.0; 2 * nv];
    let normals = sides.normals();
    for (k, &(mi, pl)) in sides.nodes().iter().enumerate() {
        if mi == pl {
            continue;
        }
        let n = normals[k.min(normals.len() - 1)];
        // Plus above the fault: u⁺ − u⁻ = s·dir; plus below: −s·dir.
        let sign = if n[1] > 0.0 { 1.0 } else { -1.0 };
        cartesian[2 * pl] = sign * SLIP * dir[0];
        cartesian[2 * pl + 1] = sign * SLIP * dir[1];
    }
    let mut x = vec![0.0; 2 * nv];
    spmv_add(tr.t_inv.as_ref(), 1.0, &cartesian, &mut x);
    let mut fixed = vec![false; 2 * nv];
    for (mi, _) in sides.pairs() {
        fixed[2 * mi] = true;
        fixed[2 * mi + 1] = true; // the opening, 0
        assert!(x[2 * mi + 1].abs() < 1e-15, "the jump is tangential");
    }
    // Far sides and bottom fixed (the half-space truncated at 1e5 m: the field of a
    // dislocation pair decays like 1/r, below 1e-5 m there); the surface is free.
    for (p, v) in split.vertices().iter().enumerate() {
        if v[0].abs() > 1e5 - 1.0 || v[1] < -1e5 + 1.0 {
            fixed[2 * p] = true;
            fixed[2 * p + 1] = true;
            x[2 * p] = 0.0;
            x[2 * p + 1] = 0.0;
        }
    }
    let mut system = ConstrainedSystem::new(kp.as_ref(), &fixed).unwrap();
    system.solve(&vec![0.0; 2 * nv], &mut x).unwrap();
    let mut u = vec![0.0; 2 * nv];
    spmv_add(tr.t.as_ref(), 1.0, &x, &mut u);

    // The jump is the prescribed slip (away from the tips).
    let jumps = sides.jump(&u, 2).unwrap();
    for (k, &(mi, pl)) in sides.nodes().iter().enumerate() {
        if mi != pl {
            let len = (jumps[k][0].powi(2) + jumps[k][1].powi(2)).sqrt();
            assert!((len - SLIP).abs() < 1e-12, "slip {len} at pair {k}");
        }
    }
    let mut err = 0.0f64;
    for (p, v) in split.vertices().iter().enumerate() {
        if v[1] == 0.0 && v[0].abs() <= 4.0 {
            let exact =
                surface_displacement(v[0], 1.0, 2f64.sqrt(), std::f64::consts::FRAC_PI_4, SLIP);
            err = err
                .max((u[2 * p] - exact[0]).abs())
                .max((u[2 * p + 1] - exact[1]).abs());
        }
    }
    (err, sides.pairs().len())
}

/// First-order convergence of the surface displacement: the discrete slip tapers to 0
/// over the last element at each buried tip (a shared node), an O(h) change of the
/// dislocation's moment.
#[test]
fn surface_displacement_of_buried_dip_slip_converges_at_first_order() {
    let mut errors = Vec::new();
    for n in [4, 8, 16, 32] {
        let (e, pairs) = surface_error(n);
        assert_eq!(pairs, n - 1, "interior fault nodes split");
        eprintln!("h = 1/{n} m: max surface error {e:.5e} m");
        errors.push(e);
    }
    for w in errors.windows(2) {
        let rate = (w[0] / w[1]).log2();
        eprintln!("rate {rate:.3}");
        assert!(rate > 0.9, "rate {rate} from {w:?}");
    }
    // Against the displacement itself: its largest surface component for |x| ≤ 4 m.
    let largest = (-400..=400)
        .map(|i| {
            surface_displacement(
                i as f64 / 100.0,
                1.0,
                2f64.sqrt(),
                std::f64::consts::FRAC_PI_4,
                SLIP,
            )
        })
        .fold(0.0f64, |m, u| m.max(u[0].abs()).max(u[1].abs()));
    eprintln!("largest surface displacement {largest:.4} m");
    assert!(errors[3] < 0.05 * largest, "{errors:?} against {largest}");
}
