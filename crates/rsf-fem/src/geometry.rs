//! Small dense geometry kernels generic over the dimension `D` (no allocation).

/// Determinant of the `n × n` top-left block of `a` (Gaussian elimination with
/// partial pivoting on a copy). `n ≤ D`.
pub(crate) fn det<const D: usize>(mut a: [[f64; D]; D], n: usize) -> f64 {
    let mut det = 1.0;
    for k in 0..n {
        let mut p = k;
        for i in k + 1..n {
            if a[i][k].abs() > a[p][k].abs() {
                p = i;
            }
        }
        if a[p][k] == 0.0 {
            return 0.0;
        }
        if p != k {
            a.swap(p, k);
            det = -det;
        }
        det *= a[k][k];
        for i in k + 1..n {
            let f = a[i][k] / a[k][k];
            for j in k..n {
                a[i][j] -= f * a[k][j];
            }
        }
    }
    det
}

fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

/// Jacobian `J[r][c] = x_{c+1}[r] − x_0[r]` of the affine map from the reference simplex.
#[inline]
pub(crate) fn jacobian<const D: usize>(x: &[[f64; D]]) -> [[f64; D]; D] {
    let mut j = [[0.0; D]; D];
    for c in 0..D {
        for r in 0..D {
            j[r][c] = x[c + 1][r] - x[0][r];
        }
    }
    j
}

/// Signed measure (area in 2D, volume in 3D) of the simplex with vertices `x` (`D + 1` points).
#[inline]
pub(crate) fn signed_measure<const D: usize>(x: &[[f64; D]]) -> f64 {
    det(jacobian(x), D) / factorial(D)
}

/// Measure of a `(D−1)`-simplex (facet) embedded in `R^D`; `x` has `D` points.
pub(crate) fn facet_measure<const D: usize>(x: &[[f64; D]]) -> f64 {
    let k = D - 1;
    if k == 0 {
        return 1.0;
    }
    // Gram matrix G = Eᵀ E with E the edge vectors from x[0].
    let mut g = [[0.0; D]; D];
    for a in 0..k {
        for b in 0..k {
            let mut s = 0.0;
            for r in 0..D {
                s += (x[a + 1][r] - x[0][r]) * (x[b + 1][r] - x[0][r]);
            }
            g[a][b] = s;
        }
    }
    det(g, k).max(0.0).sqrt() / factorial(k)
}

/// Gradients of the `D + 1` barycentric (P1) basis functions on the simplex `x`,
/// and its signed measure. Returns `None` for a singular simplex.
#[inline]
pub(crate) fn p1_gradients<const D: usize>(x: &[[f64; D]]) -> Option<([[f64; D]; 4], f64)> {
    debug_assert!(D <= 3);
    let j = jacobian::<D>(x);
    let d = det(j, D);
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    // Inverse of J by Gauss–Jordan on a copy.
    let mut a = j;
    let mut inv = [[0.0; D]; D];
    for i in 0..D {
        inv[i][i] = 1.0;
    }
    for k in 0..D {
        let mut p = k;
        for i in k + 1..D {
            if a[i][k].abs() > a[p][k].abs() {
                p = i;
            }
        }
        a.swap(p, k);
        inv.swap(p, k);
        let piv = a[k][k];
        for c in 0..D {
            a[k][c] /= piv;
            inv[k][c] /= piv;
        }
        for i in 0..D {
            if i != k {
                let f = a[i][k];
                if f != 0.0 {
                    for c in 0..D {
                        a[i][c] -= f * a[k][c];
                        inv[i][c] -= f * inv[k][c];
                    }
                }
            }
        }
    }
    // Reference gradients: λ_{i+1} = ξ_i, λ_0 = 1 − Σ ξ_i; ∇λ = J^{-T} ∇_ξ λ,
    // so ∇λ_{i+1} = row i of J^{-1}, ∇λ_0 = −Σ rows.
    let mut g = [[0.0; D]; 4];
    for i in 0..D {
        for r in 0..D {
            g[i + 1][r] = inv[i][r];
            g[0][r] -= inv[i][r];
        }
    }
    Some((g, d / factorial(D)))
}

/// Pads a point of `R^D` (`D ≤ 3`) to `R^3` with zeros.
#[inline]
pub(crate) fn pad3<const D: usize>(x: &[f64; D]) -> [f64; 3] {
    let mut p = [0.0; 3];
    p[..D].copy_from_slice(x);
    p
}

/// Cross product in `R^3`.
#[inline]
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Euclidean norm.
#[inline]
pub(crate) fn norm(v: &[f64]) -> f64 {
    v.iter().map(|c| c * c).sum::<f64>().sqrt()
}

/// Normal of an **oriented** facet (`D` points, `D = 2, 3`) scaled by `(D − 1)!` times its
/// measure: `(b − a)` turned clockwise in 2D (outward when the body lies to the left of
/// `a → b`), `(b − a) × (c − a)` in 3D (outward when the facet is seen counter-clockwise
/// from outside).
pub(crate) fn oriented_facet_normal<const D: usize>(x: &[[f64; D]]) -> [f64; D] {
    let mut n = [0.0; D];
    match D {
        2 => {
            n[0] = x[1][1] - x[0][1];
            n[1] = -(x[1][0] - x[0][0]);
        }
        3 => {
            let (a, b, c) = (pad3(&x[0]), pad3(&x[1]), pad3(&x[2]));
            let m = cross(
                [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
                [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
            );
            n.copy_from_slice(&m[..D]);
        }
        _ => unreachable!("oriented facet normals exist for D = 2, 3"),
    }
    n
}

/// Smallest dihedral angle (radians) of a simplex with barycentric gradients `g`
/// (`D + 1` used): the angle between the facets opposite vertices `i` and `j` is
/// `π − ∠(∇λ_i, ∇λ_j)`. In 2D these are the interior angles of the triangle.
pub(crate) fn min_dihedral_angle<const D: usize>(g: &[[f64; D]; 4]) -> f64 {
    let mut best = f64::INFINITY;
    for i in 0..=D {
        for j in i + 1..=D {
            let dot: f64 = (0..D).map(|r| g[i][r] * g[j][r]).sum();
            let cos = -dot / (norm(&g[i]) * norm(&g[j]));
            best = best.min(cos.clamp(-1.0, 1.0).acos());
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradients_of_reference_triangle() {
        let x = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let (g, m) = p1_gradients::<2>(&x).unwrap();
        assert!((m - 0.5).abs() < 1e-15);
        assert_eq!(g[0], [-1.0, -1.0]);
        assert_eq!(g[1], [1.0, 0.0]);
        assert_eq!(g[2], [0.0, 1.0]);
        assert!((facet_measure::<2>(&[[0.0, 0.0], [3.0, 4.0]]) - 5.0).abs() < 1e-15);
        let t = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        assert!((signed_measure::<3>(&t) - 1.0 / 6.0).abs() < 1e-15);
        assert!((facet_measure::<3>(&t[1..]) - 3f64.sqrt() / 2.0).abs() < 1e-14);
    }
}
