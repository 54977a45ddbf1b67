//! The mean–jump change of variables at a fault inside the body
//! ([`FaultSides::mean_jump_transform`], docs/math.md §13): it inverts, rigid motions have
//! no jump and no force, a frictionless tied fault has zero opening, equal and opposite
//! tractions and the same slip when the whole problem is turned, and the antiplane
//! dislocation through it equals the one by elimination.
use rsf_fem::*;

pub(crate) fn dense(a: &SparseMatrix) -> Vec<Vec<f64>> {
    let a = a.as_ref();
    let mut d = vec![vec![0.0; a.ncols()]; a.nrows()];
    for j in 0..a.ncols() {
        for (i, v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
            d[i][j] += *v;
        }
    }
    d
}

pub(crate) fn matvec(a: &[Vec<f64>], x: &[f64]) -> Vec<f64> {
    a.iter()
        .map(|r| r.iter().zip(x).map(|(p, q)| p * q).sum())
        .collect()
}

/// Solves `A x = 0` for the free entries (`fixed` entries of `x` hold the data), dense
/// Gaussian elimination with partial pivoting.
pub(crate) fn solve_fixed(a: &[Vec<f64>], fixed: &[bool], x: &mut [f64]) {
    let free: Vec<usize> = (0..x.len()).filter(|&i| !fixed[i]).collect();
    let n = free.len();
    let mut m: Vec<Vec<f64>> = free
        .iter()
        .map(|&i| {
            let mut row: Vec<f64> = free.iter().map(|&j| a[i][j]).collect();
            let rhs: f64 = (0..x.len())
                .filter(|&j| fixed[j])
                .map(|j| -a[i][j] * x[j])
                .sum();
            row.push(rhs);
            row
        })
        .collect();
    for c in 0..n {
        let p = (c..n)
            .max_by(|&i, &j| m[i][c].abs().total_cmp(&m[j][c].abs()))
            .unwrap();
        m.swap(c, p);
        for r in c + 1..n {
            let f = m[r][c] / m[c][c];
            if f != 0.0 {
                for k in c..=n {
                    m[r][k] -= f * m[c][k];
                }
            }
        }
    }
    for c in (0..n).rev() {
        let s: f64 = (c + 1..n).map(|k| m[c][k] * x[free[k]]).sum();
        x[free[c]] = (m[c][n] - s) / m[c][c];
    }
}

/// Asserts `T T⁻¹ = I` of the transform `tr`, to 1e-15 in every entry.
pub(crate) fn assert_inverts<const D: usize>(tr: &MeanJumpTransform<D>) {
    let id = dense(&(&tr.t * &tr.t_inv));
    for (i, r) in id.iter().enumerate() {
        for (j, v) in r.iter().enumerate() {
            assert!(
                (v - f64::from(u8::from(i == j))).abs() < 1e-15,
                "T T⁻¹ at ({i}, {j}): {v}"
            );
        }
    }
}

/// The stiffness `K` of `mat` on the mesh `s`.
pub(crate) fn stiffness<const D: usize>(
    s: &SimplexMesh<D>,
    mat: &LinearElasticity,
) -> SparseMatrix {
    Assembler::new(s).unwrap().stiffness(s, mat).unwrap()
}

/// The largest magnitude of the entries of the dense `a`.
pub(crate) fn largest(a: &[Vec<f64>]) -> f64 {
    a.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// The plane rigid motions `u = (a − w y, b + w x)` at the vertices of `s`: the
/// translations along x and along y, and the rotation by w = 1e-3.
pub(crate) fn plane_rigid_motions(s: &TriangleMesh) -> impl Iterator<Item = Vec<f64>> + '_ {
    [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1e-3)]
        .into_iter()
        .map(|(a, b, w)| {
            s.vertices()
                .iter()
                .flat_map(|x| [a - w * x[1], b + w * x[0]])
                .collect()
        })
}

/// The fixed dofs and their values on the outer boundary of `s` (its facets without a
/// tag, a fault's faces have one): `u(y')` at every vertex there, `y'` its y in the frame
/// turned by `theta`; the other entries free and 0.
pub(crate) fn outer_boundary_values(
    s: &TriangleMesh,
    theta: f64,
    u: impl Fn(f64) -> [f64; 2],
) -> (Vec<bool>, Vec<f64>) {
    let (c, sn) = (theta.cos(), theta.sin());
    let n = 2 * s.num_vertices();
    let mut fixed = vec![false; n];
    let mut x = vec![0.0; n];
    for f in 0..s.num_boundary_facets() {
        if s.boundary_facet_tag(f).is_some() {
            continue; // a fault's face
        }
        for &p in s.boundary_facet(f) {
            let y = -sn * s.vertices()[p][0] + c * s.vertices()[p][1]; // y in the turned frame
            let u = u(y);
            fixed[2 * p] = true;
            fixed[2 * p + 1] = true;
            x[2 * p] = u[0];
            x[2 * p + 1] = u[1];
        }
    }
    (fixed, x)
}

fn square(theta: f64) -> TriangleMesh {
    let m = rectangle([-1.0, -1.0], [2.0, 2.0], 9, 9, Diagonal::Forward).unwrap();
    let (c, s) = (theta.cos(), theta.sin());
    let v = m
        .vertices()
        .iter()
        .map(|x| [c * x[0] - s * x[1], s * x[0] + c * x[1]])
        .collect();
    m.with_moved_vertices(v).unwrap()
}

#[test]
fn the_transform_inverts_and_rigid_motions_have_no_jump_and_no_force() {
    let m = square(0.0);
    let (s, sides) = m.split_along_segment("f", [0.0, -1.0], [0.0, 0.5]).unwrap();
    let tr = sides.mean_jump_transform::<2>(&s).unwrap();
    let ti = dense(&tr.t_inv);
    assert_inverts(&tr);
    let k = stiffness(&s, &LinearElasticity::plane_strain(1e10, 0.25).unwrap());
    let kp = dense(&tr.congruence(&k).unwrap());
    let scale = largest(&dense(&k));
    for u in plane_rigid_motions(&s) {
        let up = matvec(&ti, &u);
        for (mi, _) in sides.pairs() {
            assert!(up[2 * mi].abs() < 1e-15 && up[2 * mi + 1].abs() < 1e-15);
        }
        let f = matvec(&kp, &up);
        assert!(f.iter().all(|x| x.abs() < 1e-12 * scale));
    }
    assert!(matches!(
        sides.mean_jump_transform::<3>(&s),
        Err(Error::Unsupported(_))
    ));
    assert!(matches!(
        sides.mean_jump_transform::<2>(&m),
        Err(Error::DimensionMismatch { .. })
    ));
}

/// A frictionless, tied fault from `(0, −0.5)` to `(0, 0.5)` (turned by `theta`) in a square
/// whose boundary carries simple shear `u = γ (y', 0)` in the turned frame. Returns the
/// sides, `u` (Cartesian) and `K u`.
fn mode_ii(
    theta: f64,
) -> (
    TriangleMesh,
    FaultSides,
    MeanJumpTransform,
    Vec<f64>,
    Vec<f64>,
) {
    let (c, sn) = (theta.cos(), theta.sin());
    let rot = |x: [f64; 2]| [c * x[0] - sn * x[1], sn * x[0] + c * x[1]];
    let m = square(theta);
    let (s, sides) = m
        .split_along_segment("f", rot([0.0, -0.5]), rot([0.0, 0.5]))
        .unwrap();
    let tr = sides.mean_jump_transform::<2>(&s).unwrap();
    let t = dense(&tr.t);
    let k = stiffness(&s, &LinearElasticity::plane_strain(1.0, 0.25).unwrap());
    let kp = dense(&tr.congruence(&k).unwrap());
    let k = dense(&k);
    let gamma = 1e-3;
    let (mut fixed, mut x) = outer_boundary_values(&s, theta, |y| rot([gamma * y, 0.0]));
    for (mi, _) in sides.pairs() {
        fixed[2 * mi + 1] = true; // tied: no opening
    }
    solve_fixed(&kp, &fixed, &mut x);
    let u = matvec(&t, &x);
    let r = matvec(&k, &u);
    (s, sides, tr, u, r)
}

#[test]
fn a_tied_frictionless_fault_slips_without_opening_and_turns_with_the_problem() {
    let (_, sides, tr, u, r) = mode_ii(0.0);
    let rmax = r.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let mut slip0 = Vec::new();
    for ((mi, pl), q) in sides.pairs().into_iter().zip(&tr.frames) {
        let d = [u[2 * pl] - u[2 * mi], u[2 * pl + 1] - u[2 * mi + 1]];
        let (tn, nn) = ([q[0][0], q[1][0]], [-q[0][1], -q[1][1]]);
        // No opening; the slip is there (a mode II crack in shear).
        assert!((nn[0] * d[0] + nn[1] * d[1]).abs() < 1e-14);
        let slip = tn[0] * d[0] + tn[1] * d[1];
        assert!(slip.abs() > 1e-5);
        slip0.push(slip);
        // Tractions equal and opposite; no shear traction on a frictionless fault.
        assert!((r[2 * mi] + r[2 * pl]).abs() < 1e-10 * rmax);
        assert!((r[2 * mi + 1] + r[2 * pl + 1]).abs() < 1e-10 * rmax);
        assert!((tn[0] * r[2 * mi] + tn[1] * r[2 * mi + 1]).abs() < 1e-10 * rmax);
    }
    // The slip is largest mid-fault and symmetric about it (the crack's profile).
    let k = slip0.len();
    assert_eq!(k, 3);
    assert!(slip0[1].abs() > slip0[0].abs());
    assert!((slip0[0] - slip0[2]).abs() < 1e-10 * slip0[1].abs());
    for theta in [0.3, 1.2, -2.0] {
        let (_, sides_t, tr_t, u_t, _) = mode_ii(theta);
        for (((mi, pl), q), s0) in sides_t.pairs().into_iter().zip(&tr_t.frames).zip(&slip0) {
            let d = [u_t[2 * pl] - u_t[2 * mi], u_t[2 * pl + 1] - u_t[2 * mi + 1]];
            let slip = q[0][0] * d[0] + q[1][0] * d[1];
            assert!(
                (slip - s0).abs() < 1e-9 * s0.abs(),
                "theta {theta}: {slip} vs {s0}"
            );
        }
    }
}

#[test]
fn antiplane_dislocation_through_the_transform_equals_elimination() {
    // Screw dislocation as in tests/suite/split.rs, n = 4, solved twice: with the jump as a fixed
    // new coordinate (the transform) and with the plus unknowns eliminated.
    let mut m = rectangle([-2.0, -2.0], [4.0, 2.0], 17, 9, Diagonal::Forward).unwrap();
    m.tag_boundary("surface", |x| x[1] > -1e-12);
    let (s, sides) = m
        .split_along_segment("fault", [0.0, 0.0], [0.0, -1.0])
        .unwrap();
    let nv = s.num_vertices();
    let k = Assembler::scalar(&s).unwrap().laplace(&s, 1.0).unwrap();
    let tr = sides.mean_jump_transform::<1>(&s).unwrap();
    let t = dense(&tr.t);
    let kp = dense(&tr.congruence(&k).unwrap());
    let k = dense(&k);
    let exact = |x: [f64; 2]| {
        let pi = std::f64::consts::PI;
        ((x[1] + 1.0) / x[0]).atan() / (2.0 * pi) - ((x[1] - 1.0) / x[0]).atan() / (2.0 * pi)
    };
    let far = |x: [f64; 2]| x[0].abs() > 2.0 - 1e-12 || x[1] < -2.0 + 1e-12;
    let mut fixed = vec![false; nv];
    let mut x = vec![0.0; nv];
    for p in 0..nv {
        if far(s.vertices()[p]) {
            fixed[p] = true;
            x[p] = if s.vertices()[p][0] == 0.0 {
                0.0
            } else {
                exact(s.vertices()[p])
            };
        }
    }
    for (mi, _) in sides.pairs() {
        fixed[mi] = true;
        x[mi] = 1.0; // the jump u⁺ − u⁻ (Cartesian for C = 1)
    }
    solve_fixed(&kp, &fixed, &mut x);
    let u = matvec(&t, &x);
    // Elimination: u⁺ = u⁻ + 1 substituted into the energy.
    let mut map: Vec<usize> = (0..nv).collect();
    let mut off = vec![0.0; nv];
    for (mi, pl) in sides.pairs() {
        map[pl] = mi;
        off[pl] = 1.0;
    }
    let mut ke = vec![vec![0.0; nv]; nv];
    let mut b = vec![0.0; nv];
    for i in 0..nv {
        for j in 0..nv {
            ke[map[i]][map[j]] += k[i][j];
            b[map[i]] -= k[i][j] * off[j];
        }
    }
    let mut fixed_e = vec![false; nv];
    let mut y = vec![0.0; nv];
    for p in 0..nv {
        if map[p] != p {
            fixed_e[p] = true;
            ke[p][p] = 1.0;
        } else if far(s.vertices()[p]) {
            fixed_e[p] = true;
            y[p] = x[p];
        }
    }
    // Move b into the system: solve ke y = b by adding b as a fixed unit column.
    let mut aug: Vec<Vec<f64>> = ke
        .iter()
        .zip(&b)
        .map(|(r, bi)| {
            let mut r = r.clone();
            r.push(-bi);
            r
        })
        .collect();
    aug.push({
        let mut r = vec![0.0; nv + 1];
        r[nv] = 1.0;
        r
    });
    fixed_e.push(true);
    y.push(1.0);
    solve_fixed(&aug, &fixed_e, &mut y);
    let ue: Vec<f64> = (0..nv).map(|i| y[map[i]] + off[i]).collect();
    let d = u
        .iter()
        .zip(&ue)
        .fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
    assert!(d < 1e-12, "transform vs elimination: {d:e}");
}

/// The jump shared unequally (`MeanJumpTransform::reshared`): still an inverse pair, the
/// jump block is the same `Rᵀ(u⁺ − u⁻)` whatever the shares, the other block the weighted
/// mean `(1 − β) u⁻ + β u⁺`, and shares outside [0, 1] or of the wrong count are refused.
#[test]
fn a_reshared_transform_keeps_the_jump_and_weights_the_mean() {
    // A kinked fault: the pair frames differ along it.
    let m = square(0.0);
    let (s, sides) = m
        .split_along_polyline("f", &[[-0.5, -1.0], [0.0, -0.5], [0.0, 0.5]])
        .unwrap();
    let mean = sides.mean_jump_transform::<2>(&s).unwrap();
    let pairs = sides.pairs();
    let shares: Vec<f64> = (0..pairs.len())
        .map(|k| (k as f64 + 0.5) / pairs.len() as f64)
        .collect();
    let tr = mean.reshared::<2>(&sides, &shares).unwrap();
    assert_inverts(&tr);
    let u: Vec<f64> = (0..2 * s.num_vertices())
        .map(|i| ((i * 7919) % 101) as f64 / 101.0 - 0.5)
        .collect();
    let (a, b) = (
        matvec(&dense(&mean.t_inv), &u),
        matvec(&dense(&tr.t_inv), &u),
    );
    for (k, &(mi, pl)) in pairs.iter().enumerate() {
        for c in 0..2 {
            assert!((a[2 * mi + c] - b[2 * mi + c]).abs() < 1e-15);
            let w = (1.0 - shares[k]) * u[2 * mi + c] + shares[k] * u[2 * pl + c];
            assert!((b[2 * pl + c] - w).abs() < 1e-15);
        }
    }
    let half = vec![0.5; pairs.len()];
    let again = mean.reshared::<2>(&sides, &half).unwrap();
    assert_eq!(dense(&again.t), dense(&mean.t));
    assert!(matches!(
        mean.reshared::<2>(&sides, &[1.5; 1].repeat(pairs.len())),
        Err(Error::Unsupported(_))
    ));
    assert!(matches!(
        mean.reshared::<2>(&sides, &[0.5]),
        Err(Error::DimensionMismatch { .. })
    ));
}
