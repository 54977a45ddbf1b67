//! The product with a two-level block-Toeplitz matrix of `2 × 2` blocks through FFTs of
//! its circulant embedding: the operator of a uniform planar grid of cells in a
//! translation-invariant medium, whose entry between two cells depends only on their
//! offset (docs/halfspace.md §11).

use std::sync::Arc;

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

/// `y_c(a) = Σ_{d, b} T_cd(a − b) x_d(b)` for the cells `a, b` of an `n_u × n_v` grid (`u`
/// fastest; two components `c, d` per cell, interleaved as `2 cell + c`), with
/// `T_cd(i, j)` given for `|i| < n_u`, `|j| < n_v`.
///
/// Embedded in a circulant of order `L_u × L_v` (`L = 2n`): `T_cd` written at the offsets
/// modulo `L`, its spectra `T̂_cd` (one 2-D FFT each, at set-up) stored with the inverse
/// transform's `1/(L_u L_v)` folded in. A product packs the two real components of `x`
/// into one complex field `x_u + i x_v`, so that it costs one forward and one inverse
/// complex 2-D FFT: the spectra of the components are `X_u(k) = (Z(k) + Z̄(−k))/2`,
/// `X_v(k) = (Z(k) − Z̄(−k))/(2i)`, and with `Y_c = Σ_d T̂_cd X_d` the transform of
/// `y_u + i y_v` is `Y_u + i Y_v`. Rows of the zero padding are not transformed. Scratch
/// kept: nothing allocated per product; one thread (rustfft), so the same bits every
/// time.
pub(super) struct BlockToeplitz2 {
    n: [usize; 2],
    len: [usize; 2],
    /// `T̂_cd` at `p L_v + q` (the transposed layout the product ends its forward
    /// transform in), for `cd` = uu, uv, vu, vv.
    spectra: [Vec<Complex<f64>>; 4],
    forward: [Arc<dyn Fft<f64>>; 2],
    inverse: [Arc<dyn Fft<f64>>; 2],
    /// `L_v` rows of `L_u` (u fastest) and its transpose, `L_u` rows of `L_v`.
    rows: Vec<Complex<f64>>,
    columns: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl BlockToeplitz2 {
    /// The embedding of `t(c, d, i, j) = T_cd(i, j)` on an `n[0] × n[1]` grid (each at
    /// least 1).
    pub(super) fn new(n: [usize; 2], t: impl Fn(usize, usize, isize, isize) -> f64) -> Self {
        let len = n.map(|k| 2 * k);
        let mut planner = FftPlanner::new();
        let forward = len.map(|l| planner.plan_fft_forward(l));
        let inverse = len.map(|l| planner.plan_fft_inverse(l));
        let scratch_len = forward
            .iter()
            .chain(&inverse)
            .map(|f| f.get_inplace_scratch_len())
            .max()
            .unwrap_or(0);
        let zero = Complex::new(0.0, 0.0);
        let size = len[0] * len[1];
        let mut op = Self {
            n,
            len,
            spectra: std::array::from_fn(|_| Vec::new()),
            forward,
            inverse,
            rows: vec![zero; size],
            columns: vec![zero; size],
            scratch: vec![zero; scratch_len],
        };
        let scale = 1.0 / size as f64;
        // Offset of index p modulo L (the gap between n − 1 and L − n + 1 is zero).
        let offset = |p: usize, a: usize| -> Option<isize> {
            if p < n[a] {
                Some(p as isize)
            } else if p > len[a] - n[a] {
                Some(p as isize - len[a] as isize)
            } else {
                None
            }
        };
        for (cd, spectrum) in op.spectra.iter_mut().enumerate() {
            let (c, d) = (cd / 2, cd % 2);
            let mut rows = vec![zero; size];
            for q in 0..len[1] {
                for p in 0..len[0] {
                    if let (Some(i), Some(j)) = (offset(p, 0), offset(q, 1)) {
                        rows[q * len[0] + p] = Complex::new(t(c, d, i, j), 0.0);
                    }
                }
            }
            let mut columns = vec![zero; size];
            transform_2d(
                (&op.forward, &mut op.scratch),
                len,
                len[1],
                &mut rows,
                &mut columns,
            );
            for s in &mut columns {
                *s *= scale;
            }
            *spectrum = columns;
        }
        op
    }

    /// The grid's cells along `u` and `v`.
    pub(super) fn cells(&self) -> [usize; 2] {
        self.n
    }

    /// Complex numbers stored (the four spectra and the two work arrays).
    pub(super) fn stored(&self) -> usize {
        6 * self.len[0] * self.len[1]
    }

    /// `y ← y + T x` (`x`, `y` of length `2 n_u n_v`). A non-finite `x` gives a non-finite
    /// `y` (NaN spreads through the transforms).
    pub(super) fn add_product(&mut self, x: &[f64], y: &mut [f64]) {
        let [nu, nv] = self.n;
        let [lu, lv] = self.len;
        let zero = Complex::new(0.0, 0.0);
        for q in 0..nv {
            let row = &mut self.rows[q * lu..(q + 1) * lu];
            for (p, z) in row[..nu].iter_mut().enumerate() {
                let k = 2 * (q * nu + p);
                *z = Complex::new(x[k], x[k + 1]);
            }
            row[nu..].fill(zero);
        }
        transform_2d(
            (&self.forward, &mut self.scratch),
            self.len,
            nv,
            &mut self.rows,
            &mut self.columns,
        );
        // Each frequency k with its mirror −k: both read before either is written.
        let [uu, uv, vu, vv] = &self.spectra;
        let half = Complex::new(0.5, 0.0);
        let minus_half_i = Complex::new(0.0, -0.5);
        let i = Complex::new(0.0, 1.0);
        for p in 0..lu {
            let pm = (lu - p) % lu;
            for q in 0..lv {
                let qm = (lv - q) % lv;
                let (a, b) = (p * lv + q, pm * lv + qm);
                if b < a {
                    continue;
                }
                let (za, zb) = (self.columns[a], self.columns[b]);
                let xu_a = half * (za + zb.conj());
                let xv_a = minus_half_i * (za - zb.conj());
                let xu_b = half * (zb + za.conj());
                let xv_b = minus_half_i * (zb - za.conj());
                let w = |k: usize, xu: Complex<f64>, xv: Complex<f64>| {
                    (uu[k] * xu + uv[k] * xv) + i * (vu[k] * xu + vv[k] * xv)
                };
                self.columns[a] = w(a, xu_a, xv_a);
                self.columns[b] = w(b, xu_b, xv_b);
            }
        }
        // Back: the transforms along v of every column, then along u of the grid's rows.
        let [inv_u, inv_v] = &self.inverse;
        inv_v.process_with_scratch(&mut self.columns, &mut self.scratch);
        for q in 0..nv {
            for p in 0..lu {
                self.rows[q * lu + p] = self.columns[p * lv + q];
            }
        }
        inv_u.process_with_scratch(&mut self.rows[..nv * lu], &mut self.scratch);
        for q in 0..nv {
            for (p, z) in self.rows[q * lu..q * lu + nu].iter().enumerate() {
                let k = 2 * (q * nu + p);
                y[k] += z.re;
                y[k + 1] += z.im;
            }
        }
    }
}

/// The two 1-D forward transforms (along `u`, along `v`) and their scratch.
type Forward2d<'a> = (&'a [Arc<dyn Fft<f64>>; 2], &'a mut [Complex<f64>]);

/// The 2-D forward transform of `rows` (`L_v` rows of `L_u`, only the first `filled` rows
/// non-zero) into `columns` (`L_u` rows of `L_v`: the transposed layout).
fn transform_2d(
    (forward, scratch): Forward2d<'_>,
    len: [usize; 2],
    filled: usize,
    rows: &mut [Complex<f64>],
    columns: &mut [Complex<f64>],
) {
    let [lu, lv] = len;
    forward[0].process_with_scratch(&mut rows[..filled * lu], scratch);
    for p in 0..lu {
        for q in 0..lv {
            columns[p * lv + q] = if q < filled {
                rows[q * lu + p]
            } else {
                Complex::new(0.0, 0.0)
            };
        }
    }
    forward[1].process_with_scratch(columns, scratch);
}

#[cfg(test)]
mod tests {
    use super::BlockToeplitz2;

    /// Against the dense sum, for an unsymmetric `T` on a non-square grid.
    #[test]
    fn product_is_the_dense_sum() {
        let n = [5, 3];
        let t = |c: usize, d: usize, i: isize, j: isize| {
            let x = (i as f64) * 0.37 + (j as f64) * 1.13 + (2 * c + d) as f64 * 0.71;
            x.sin() + 0.1 * (c as f64) - 0.05 * (d as f64)
        };
        let mut op = BlockToeplitz2::new(n, t);
        let m = 2 * n[0] * n[1];
        let x: Vec<f64> = (0..m).map(|k| ((k * 7 + 3) % 11) as f64 - 5.0).collect();
        let mut y = vec![1.0; m];
        op.add_product(&x, &mut y);
        let mut worst = 0.0_f64;
        for a in 0..n[0] * n[1] {
            for c in 0..2 {
                let mut s = 1.0;
                for b in 0..n[0] * n[1] {
                    let i = (a % n[0]) as isize - (b % n[0]) as isize;
                    let j = (a / n[0]) as isize - (b / n[0]) as isize;
                    for d in 0..2 {
                        s += t(c, d, i, j) * x[2 * b + d];
                    }
                }
                worst = worst.max((s - y[2 * a + c]).abs());
            }
        }
        assert!(worst < 1e-12, "{worst:e}");
        // A second product on the same scratch gives the same bits.
        let mut z = vec![1.0; m];
        op.add_product(&x, &mut z);
        assert_eq!(y, z);
    }
}
