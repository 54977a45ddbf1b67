//! Dense kernels of the condensed problem: Cholesky factors (small ones sequential, large
//! ones on the threads), norms through a factor, quadratic forms and solves, each with a
//! fixed summation order.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{
    cholesky_in_place, cholesky_in_place_scratch, LltParams,
};
use faer::{Accum, Mat, MatRef, Par};
use rsf_linalg::Parallelism;

/// `½ (M + Mᵀ)` for the `m × m` matrix `M` of entries `entry(i, j)`, dense column-major:
/// a product that is symmetric in exact arithmetic, symmetrised against round-off.
pub(super) fn symmetric_part(m: usize, entry: impl Fn(usize, usize) -> f64) -> Vec<f64> {
    let mut out = vec![0.0; m * m];
    for j in 0..m {
        for i in 0..m {
            out[j * m + i] = 0.5 * (entry(i, j) + entry(j, i));
        }
    }
    out
}

/// [`symmetric_part`] of the dense product `a b` (`m × m`, faer's sequential product).
pub(super) fn symmetric_product(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Vec<f64> {
    let mut p = Mat::<f64>::zeros(a.nrows(), b.ncols());
    faer::linalg::matmul::matmul(p.as_mut(), Accum::Replace, a, b, 1.0, Par::Seq);
    symmetric_part(a.nrows(), |i, j| p[(i, j)])
}

/// The lower Cholesky factor of the SPD `m × m` column-major `a`, stored by rows (row-major,
/// zero above the diagonal), or None if `a` is not numerically positive definite.
pub(super) fn lower_cholesky(a: &[f64], m: usize) -> Option<Vec<f64>> {
    let mut l = Mat::from_fn(m, m, |i, j| if i >= j { a[j * m + i] } else { 0.0 });
    let mut mem = MemBuffer::new(cholesky_in_place_scratch::<f64>(
        m,
        Par::Seq,
        Default::default(),
    ));
    cholesky_in_place(
        l.as_mut(),
        Default::default(),
        Par::Seq,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .ok()?;
    let mut out = vec![0.0; m * m];
    for i in 0..m {
        for j in 0..=i {
            out[i * m + j] = l[(i, j)];
        }
    }
    out.iter().all(|x| x.is_finite()).then_some(out)
}

/// Largest dense system factorised by faer's unblocked SIMD kernel instead of its blocked
/// (gemm-based) path. faer's default switches at 64. Within a time step the blocked path
/// cost far more than a stand-alone benchmark of it suggests (main job, one thread:
/// condensed solves 5.0 s → 3.0 s at j = 4, 17 s → 8–11 s at j = 5 with 256; j = 6,
/// where most systems exceed 200 unknowns, unchanged within the noise), while above a few
/// hundred unknowns the blocked path wins by 3× and more.
pub(super) const SMALL_LLT: usize = 256;

/// Smallest dense Newton system of the direct solver factorised on the threads of its
/// [`Parallelism`] ([`DirectSolver::with_parallelism`](super::DirectSolver::with_parallelism));
/// smaller ones stay on one thread. Measured (faer 0.24, two cores of this machine's Xeon): 700 unknowns 2.7 ms on one thread
/// against 3.2 ms on two, 1 400 unknowns 16.7 against 14.5 ms, 2 754 (the 3-D slider at
/// j = 4) 151 against 88 ms.
pub const DENSE_PARALLEL_MIN: usize = 1000;

/// The parallelism of a dense factorisation of `q` unknowns with `par`: one thread below
/// [`DENSE_PARALLEL_MIN`].
pub(super) fn dense_par(q: usize, par: Parallelism) -> Par {
    if q >= DENSE_PARALLEL_MIN {
        par.faer()
    } else {
        Par::Seq
    }
}

/// Scratch of the dense factorisations of up to `m` unknowns with `par`.
pub(super) fn dense_scratch(m: usize, par: Parallelism) -> StackReq {
    cholesky_in_place_scratch::<f64>(m, Par::Seq, Default::default()).or(
        cholesky_in_place_scratch::<f64>(m, dense_par(m, par), Default::default()),
    )
}

pub(super) fn small_llt_params() -> faer::Spec<LltParams, f64> {
    let mut params: LltParams = faer::Auto::<f64>::auto();
    params.recursion_threshold = SMALL_LLT;
    params.into()
}

/// `‖Lᵀx‖` as the direct solver's stopping norm computes it (tests of its bounds).
#[cfg(test)]
pub(super) fn norm_via_factor(l: &[f64], x: &[f64]) -> f64 {
    factor_norm_sq(l, x).sqrt()
}

/// `‖Lᵀx‖²` for the dense lower-triangular `L` stored by rows (`m × m` row-major, zero
/// above the diagonal, `m = x.len()`): `(Lᵀx)_j = Σ_{i ≥ j} L_ij x_i`, each sum over
/// increasing `i`, then `Σ_j (Lᵀx)_j²` over increasing `j`.
///
/// Sixteen columns at a time, one SIMD lane each: row `i` adds `L_ij x_i` to the sums of
/// the block's columns, contiguous in the row. A column `j` of the block also receives the
/// rows `i < j` of its block, whose entries are zero: `+0 + (±0) = +0`, so its sum is still
/// `+0` when its first real term `L_jj x_j` arrives, exactly as a sum started at row `j`.
/// Every sum thus has the bits of the column-by-column loop, without its chain of
/// dependent additions.
#[inline(always)]
pub(super) fn factor_norm_sq(l: &[f64], x: &[f64]) -> f64 {
    const W: usize = 16;
    let m = x.len();
    let mut q = 0.0;
    let mut j0 = 0;
    while j0 + W <= m {
        let mut s = [0.0; W];
        for (i, &xi) in x.iter().enumerate().skip(j0) {
            let row: &[f64; W] = l[i * m + j0..i * m + j0 + W].try_into().expect("W entries");
            for c in 0..W {
                s[c] += row[c] * xi;
            }
        }
        for sc in s {
            q += sc * sc;
        }
        j0 += W;
    }
    for j in j0..m {
        let mut s = 0.0;
        for (i, &xi) in x.iter().enumerate().skip(j) {
            s += l[i * m + j] * xi;
        }
        q += s * s;
    }
    q
}

/// `xᵀAx` for the dense symmetric `A` (`m × m`, column-major, `m = x.len()`): over the
/// columns `j` with `x_j ≠ 0` in increasing order, `x_j Σ_i A_ij x_i` (each sum over
/// increasing `i`). Four columns run side by side where all four `x_j` are nonzero, with the
/// same operations in the same order, so the same bits.
#[inline(always)]
pub(super) fn quadratic_form(a: &[f64], x: &[f64]) -> f64 {
    let m = x.len();
    let column = |j: usize| {
        let mut s = 0.0;
        for (aij, xi) in a[j * m..(j + 1) * m].iter().zip(x) {
            s += aij * xi;
        }
        s
    };
    let mut q = 0.0;
    let mut j = 0;
    while j + 4 <= m {
        if x[j..j + 4].iter().all(|&v| v != 0.0) {
            let cols: [&[f64]; 4] = [0, 1, 2, 3].map(|c| &a[(j + c) * m..(j + c + 1) * m]);
            let mut s = [0.0; 4];
            for (r, &xr) in x.iter().enumerate() {
                for c in 0..4 {
                    s[c] += cols[c][r] * xr;
                }
            }
            for (c, sc) in s.into_iter().enumerate() {
                q += x[j + c] * sc;
            }
        } else {
            for j in j..j + 4 {
                if x[j] != 0.0 {
                    q += x[j] * column(j);
                }
            }
        }
        j += 4;
    }
    for j in j..m {
        if x[j] != 0.0 {
            q += x[j] * column(j);
        }
    }
    q
}

/// `x ← (L Lᵀ)⁻¹ x` for the Cholesky factor `L` (lower triangle of `l`, as faer's
/// `cholesky_in_place` leaves it) by forward and backward substitution over contiguous
/// columns: for the small dense systems here (tens to a few hundred unknowns, one right-hand
/// side) this is several times cheaper than a general blocked triangular solve.
pub(super) fn cholesky_solve(
    l: faer::MatRef<'_, f64>,
    y: &mut [f64],
    mut x: faer::ColMut<'_, f64>,
) {
    let q = y.len();
    // Columns as slices (faer's `Mat` stores columns contiguously): the loops below then run
    // without bounds checks and the forward update vectorises; same operations, same order.
    let col = |j: usize| -> &[f64] {
        l.col(j)
            .try_as_col_major()
            .expect("columns of a dense faer matrix are contiguous")
            .as_slice()
    };
    for (i, yi) in y.iter_mut().enumerate() {
        *yi = x[i];
    }
    for j in 0..q {
        let c = &col(j)[..q];
        let yj = y[j] / c[j];
        y[j] = yj;
        if yj != 0.0 {
            for (yi, lij) in y[j + 1..].iter_mut().zip(&c[j + 1..]) {
                *yi -= lij * yj;
            }
        }
    }
    for j in (0..q).rev() {
        let c = &col(j)[..q];
        let mut acc = y[j];
        for (lij, yi) in c[j + 1..].iter().zip(&y[j + 1..]) {
            acc -= lij * yi;
        }
        y[j] = acc / c[j];
    }
    for (i, yi) in y.iter().enumerate() {
        x[i] = *yi;
    }
}

#[cfg(test)]
mod tests {
    use super::{factor_norm_sq, quadratic_form};

    /// Deterministic test data with zeros, signs and magnitudes spread over many decades.
    fn data(n: usize, seed: u64) -> Vec<f64> {
        let mut z = seed;
        (0..n)
            .map(|_| {
                z = z
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let u = (z >> 11) as f64 / (1u64 << 53) as f64;
                if z % 7 == 0 {
                    0.0
                } else {
                    (u - 0.5) * 10f64.powi((z % 9) as i32 - 4)
                }
            })
            .collect()
    }

    #[test]
    fn blocked_norms_have_the_bits_of_the_column_by_column_loops() {
        for m in [0, 1, 3, 4, 5, 8, 11, 16, 17, 40, 81] {
            let mut l = data(m * m, 1 + m as u64);
            let x = data(m, 100 + m as u64);
            // By rows, zero above the diagonal.
            for i in 0..m {
                l[i * m + i + 1..(i + 1) * m].fill(0.0);
            }
            let mut q = 0.0;
            for j in 0..m {
                let mut s = 0.0;
                for i in j..m {
                    s += l[i * m + j] * x[i];
                }
                q += s * s;
            }
            assert_eq!(factor_norm_sq(&l, &x).to_bits(), q.to_bits(), "m = {m}");
            let mut q = 0.0;
            for j in 0..m {
                if x[j] != 0.0 {
                    let mut s = 0.0;
                    for i in 0..m {
                        s += l[j * m + i] * x[i];
                    }
                    q += x[j] * s;
                }
            }
            assert_eq!(quadratic_form(&l, &x).to_bits(), q.to_bits(), "m = {m}");
        }
    }
}
