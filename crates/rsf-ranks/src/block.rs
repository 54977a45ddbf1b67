//! Small dense kernels of node blocks (`D` values of a node-major vector, `D × D` matrix
//! blocks): the arithmetic that the block matrices, the rows of a rank and the Gauss–Seidel
//! sweeps of this crate and of `rsf-tnnmg` share, each written once so that every caller
//! has the same bits.

/// Solves `A x = r` restricted to the `free` components (Cholesky of the free sub-block),
/// writing the free components of `x`; fixed components of `x` are left unchanged and their
/// coupling `A_{free,fixed} x_fixed` must already be in `r`. Returns `false` when the free
/// sub-block is not positive definite (then `x` is unchanged). A helper for
/// implementations of `rsf_nonsmooth::BlockNonlinearity::minimize_block`.
pub fn solve_spd_masked<const D: usize>(
    a: &[[f64; D]; D],
    r: &[f64; D],
    free: &[bool; D],
    x: &mut [f64; D],
) -> bool {
    let mut idx = [0usize; D];
    let mut m = 0;
    for (c, &f) in free.iter().enumerate() {
        if f {
            idx[m] = c;
            m += 1;
        }
    }
    // Cholesky of the m×m free block.
    let mut l = [[0.0f64; D]; D];
    for i in 0..m {
        for j in 0..=i {
            let mut s = a[idx[i]][idx[j]];
            for k in 0..j {
                s -= l[i][k] * l[j][k];
            }
            if i == j {
                if s <= 0.0 || !s.is_finite() {
                    return false;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    let mut y = [0.0f64; D];
    for i in 0..m {
        y[i] = r[idx[i]];
    }
    cholesky_solve(&l, m, &mut y);
    for i in 0..m {
        x[idx[i]] = y[i];
    }
    true
}

/// `y ← (L Lᵀ)⁻¹ y` on the first `m` components, `L` lower triangular (leading `m × m`).
fn cholesky_solve<const D: usize>(l: &[[f64; D]; D], m: usize, y: &mut [f64; D]) {
    for i in 0..m {
        for k in 0..i {
            y[i] -= l[i][k] * y[k];
        }
        y[i] /= l[i][i];
    }
    for i in (0..m).rev() {
        for k in i + 1..m {
            y[i] -= l[k][i] * y[k];
        }
        y[i] /= l[i][i];
    }
}

/// Block `p` of the node-major vector `v`: `v[D p .. D p + D]`.
///
/// # Panics
/// If `v` is shorter than `D (p + 1)`.
#[inline]
pub fn load<const D: usize>(v: &[f64], p: usize) -> [f64; D] {
    let mut out = [0.0; D];
    out.copy_from_slice(&v[D * p..D * p + D]);
    out
}

/// Writes `x` into block `p` of the node-major vector `v`.
///
/// # Panics
/// If `v` is shorter than `D (p + 1)`.
#[inline]
pub fn store<const D: usize>(v: &mut [f64], p: usize, x: &[f64; D]) {
    v[D * p..D * p + D].copy_from_slice(x);
}

/// A dense `D × D` node block, row-major (`b[r][c]`).
pub type Block<const D: usize> = [[f64; D]; D];

/// `a x`.
#[inline(always)]
pub fn mul_vec<const D: usize>(a: &Block<D>, x: &[f64; D]) -> [f64; D] {
    let mut y = [0.0; D];
    for r in 0..D {
        for c in 0..D {
            y[r] += a[r][c] * x[c];
        }
    }
    y
}

/// `y −= a x`.
#[inline(always)]
pub fn sub_mul_vec<const D: usize>(y: &mut [f64; D], a: &Block<D>, x: &[f64; D]) {
    for r in 0..D {
        for c in 0..D {
            y[r] -= a[r][c] * x[c];
        }
    }
}

/// `y −= aᵀ x`.
#[inline(always)]
pub fn sub_mul_t_vec<const D: usize>(y: &mut [f64; D], a: &Block<D>, x: &[f64; D]) {
    for r in 0..D {
        for c in 0..D {
            y[c] -= a[r][c] * x[r];
        }
    }
}

/// `acc += a b`.
#[inline(always)]
pub fn add_mul<const D: usize>(acc: &mut Block<D>, a: &Block<D>, b: &Block<D>) {
    for r in 0..D {
        for k in 0..D {
            let ark = a[r][k];
            for c in 0..D {
                acc[r][c] += ark * b[k][c];
            }
        }
    }
}

/// `acc += aᵀ b`.
#[inline(always)]
pub fn add_mul_t<const D: usize>(acc: &mut Block<D>, a: &Block<D>, b: &Block<D>) {
    for k in 0..D {
        for r in 0..D {
            let akr = a[k][r];
            for c in 0..D {
                acc[r][c] += akr * b[k][c];
            }
        }
    }
}

/// Pivots of a free sub-block below this multiple of the diagonal entry count as zero
/// (the coarse operators of a rank-deficient truncated prolongation are only semidefinite).
const PIVOT_TOLERANCE: f64 = 1e-12;

/// The block smoother's local solve as a matrix `S`: with `s` the block right-hand side
/// including all off-block couplings, `x = S s` minimises `½ xᵀ a x − sᵀ x` over the free
/// components when the others are 0. `S` is the inverse of the free sub-block of `a`
/// (Cholesky), zero in the rows and columns of the components that are not free. For a
/// semidefinite sub-block, components whose Cholesky pivot vanishes (relative to their
/// diagonal entry, or a non-positive diagonal) are dropped like non-free ones: for a
/// positive semidefinite matrix such a component is decoupled up to round-off, and `S s`
/// is still a minimiser.
pub fn masked_inverse<const D: usize>(a: &Block<D>, free: &[bool; D]) -> Block<D> {
    let mut idx = [0usize; D];
    let mut l = [[0.0f64; D]; D];
    let mut m = 0;
    for c in 0..D {
        if !(free[c] && a[c][c] > 0.0 && a[c][c].is_finite()) {
            continue;
        }
        // Row m of L against the accepted components.
        let mut row = [0.0f64; D];
        for j in 0..m {
            let mut v = a[c][idx[j]];
            for k in 0..j {
                v -= row[k] * l[j][k];
            }
            row[j] = v / l[j][j];
        }
        let pivot = a[c][c] - row[..m].iter().map(|v| v * v).sum::<f64>();
        if pivot > PIVOT_TOLERANCE * a[c][c] {
            row[m] = pivot.sqrt();
            l[m] = row;
            idx[m] = c;
            m += 1;
        }
    }
    let mut out = [[0.0; D]; D];
    // Columns of the inverse: solve L Lᵀ y = e_j.
    for j in 0..m {
        let mut y = [0.0f64; D];
        y[j] = 1.0;
        cholesky_solve(&l, m, &mut y);
        for i in 0..m {
            out[idx[i]][idx[j]] = y[i];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `masked_inverse` inverts the free sub-block, leaves the rest zero, and drops a
    /// degenerate component of a semidefinite block.
    #[test]
    fn masked_inverse_on_free_and_semidefinite_blocks() {
        let a = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]];
        let s = masked_inverse(&a, &[true, false, true]);
        // s restricted to {0, 2} times a restricted to {0, 2} is the identity.
        let ids = [0, 2];
        for &i in &ids {
            for &j in &ids {
                let v: f64 = ids.iter().map(|&k| s[i][k] * a[k][j]).sum();
                assert!((v - if i == j { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
            assert_eq!(s[1][i], 0.0);
            assert_eq!(s[i][1], 0.0);
        }
        // Rank one: [[1, 2], [2, 4]]; the second component is dropped, x = (s0, 0).
        let b = [[1.0, 2.0], [2.0, 4.0]];
        let t = masked_inverse(&b, &[true, true]);
        assert_eq!(t, [[1.0, 0.0], [0.0, 0.0]]);
    }
}
