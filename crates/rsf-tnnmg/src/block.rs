//! Small dense helpers for node blocks.

/// Solves `A x = r` restricted to the `free` components (Cholesky of the free sub-block),
/// writing the free components of `x`; fixed components of `x` are left unchanged and their
/// coupling `A_{free,fixed} x_fixed` must already be in `r`. Returns `false` when the free
/// sub-block is not positive definite (then `x` is unchanged). A helper for
/// [`BlockNonlinearity::minimize_block`](crate::BlockNonlinearity::minimize_block)
/// implementations.
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
        let mut s = r[idx[i]];
        for k in 0..i {
            s -= l[i][k] * y[k];
        }
        y[i] = s / l[i][i];
    }
    for i in (0..m).rev() {
        let mut s = y[i];
        for k in i + 1..m {
            s -= l[k][i] * y[k];
        }
        y[i] = s / l[i][i];
    }
    for i in 0..m {
        x[idx[i]] = y[i];
    }
    true
}

#[inline]
pub(crate) fn load<const D: usize>(v: &[f64], p: usize) -> [f64; D] {
    let mut out = [0.0; D];
    out.copy_from_slice(&v[D * p..D * p + D]);
    out
}

#[inline]
pub(crate) fn store<const D: usize>(v: &mut [f64], p: usize, x: &[f64; D]) {
    v[D * p..D * p + D].copy_from_slice(x);
}
