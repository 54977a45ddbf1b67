//! The supernodal layout of a partial Cholesky factor and its forward and backward
//! sweeps (one right-hand side or several at once).

use std::ops::Range;

/// The supernodal layout of `L`: supernode `s` covers columns `start[s]..start[s + 1]`
/// (width `w`), its rows are the `w` diagonal-block rows followed by
/// `rows[row_ptr[s]..row_ptr[s + 1]]` (increasing), and its values are a dense
/// column-major `(w + p) × w` block at `val_ptr[s]`.
#[derive(Debug, Clone)]
pub(super) struct Supernodes {
    pub(super) start: Vec<usize>,
    pub(super) row_ptr: Vec<usize>,
    pub(super) rows: Vec<u32>,
    pub(super) val_ptr: Vec<usize>,
    pub(super) val: Vec<f64>,
}

impl Supernodes {
    /// The layout without the values.
    pub(super) fn clone_layout(&self) -> Self {
        Self {
            start: self.start.clone(),
            row_ptr: self.row_ptr.clone(),
            rows: self.rows.clone(),
            val_ptr: self.val_ptr.clone(),
            val: Vec::new(),
        }
    }

    pub(super) fn len(&self) -> usize {
        self.start.len() - 1
    }

    /// (first column, width, pattern below the diagonal block, values).
    #[inline]
    pub(super) fn get(&self, s: usize) -> (usize, usize, &[u32], &[f64]) {
        let c0 = self.start[s];
        (
            c0,
            self.start[s + 1] - c0,
            &self.rows[self.row_ptr[s]..self.row_ptr[s + 1]],
            &self.val[self.val_ptr[s]..self.val_ptr[s + 1]],
        )
    }

    /// The supernodes that contain a column of `cols`.
    pub(super) fn covering(&self, cols: &Range<usize>) -> Range<usize> {
        if cols.is_empty() {
            return 0..0;
        }
        let first = self.start.partition_point(|&c| c <= cols.start) - 1;
        let last = self.start.partition_point(|&c| c < cols.end);
        first..last
    }

    /// Forward sweep over the columns `cols`: `y_j ← y_j / L_jj`, then `y_i −= L_ij y_j` for
    /// the rows below. Rows below `split` live in `own` (at `row − own_off`), the others in
    /// `tail` (at `row − split`).
    #[expect(
        clippy::too_many_arguments,
        reason = "a hot kernel: the two halves of the right-hand side (own rows, shared tail) are its data, as in `SplitRows`"
    )]
    pub(super) fn forward(
        &self,
        cols: Range<usize>,
        own: &mut [f64],
        own_off: usize,
        tail: &mut [f64],
        split: usize,
        tmp: &mut Vec<f64>,
    ) {
        // Compiled for the SIMD level of the machine, chosen at run time (pulp); plain loops
        // whose floating-point operations keep their order, so the results are the same bits
        // on every machine.
        pulp::Arch::new().dispatch(|| self.forward_kernel(cols, own, own_off, tail, split, tmp));
    }

    #[expect(
        clippy::too_many_arguments,
        reason = "a hot kernel: the two halves of the right-hand side (own rows, shared tail) are its data, as in `SplitRows`"
    )]
    #[inline(always)]
    pub(super) fn forward_kernel(
        &self,
        cols: Range<usize>,
        own: &mut [f64],
        own_off: usize,
        tail: &mut [f64],
        split: usize,
        tmp: &mut Vec<f64>,
    ) {
        for s in self.covering(&cols) {
            let (c0, w, pattern, l) = self.get(s);
            let (j0, j1) = (cols.start.max(c0) - c0, cols.end.min(c0 + w) - c0);
            let ld = w + pattern.len();
            // Diagonal block: its rows below `split` are own rows, the rest tail rows.
            let d_own = split.saturating_sub(c0).min(w);
            for jj in j0..j1 {
                let col = &l[jj * ld..(jj + 1) * ld];
                let yj = own[c0 + jj - own_off] / col[jj];
                own[c0 + jj - own_off] = yj;
                if jj + 1 < d_own {
                    // Rows c0 + jj + 1 .. c0 + d_own (c0 + jj ≥ own_off: the column is own).
                    let (r0, r1) = (c0 + jj + 1 - own_off, c0 + d_own - own_off);
                    for (yi, lij) in own[r0..r1].iter_mut().zip(&col[jj + 1..d_own]) {
                        *yi -= lij * yj;
                    }
                }
                let lo = (jj + 1).max(d_own);
                if lo < w {
                    let t = c0 + lo - split;
                    for (yi, lij) in tail[t..t + w - lo].iter_mut().zip(&col[lo..w]) {
                        *yi -= lij * yj;
                    }
                }
            }
            let p = pattern.len();
            if tmp.len() < p {
                tmp.resize(p, 0.0);
            }
            let t = &mut tmp[..p];
            t.fill(0.0);
            for jj in j0..j1 {
                let yj = own[c0 + jj - own_off];
                if yj != 0.0 {
                    for (ti, lij) in t.iter_mut().zip(&col_below(l, ld, w, jj)[..p]) {
                        *ti += lij * yj;
                    }
                }
            }
            let k_own = pattern.partition_point(|&r| (r as usize) < split);
            for (&i, ti) in pattern[..k_own].iter().zip(&t[..k_own]) {
                own[i as usize - own_off] -= ti;
            }
            for (&i, ti) in pattern[k_own..].iter().zip(&t[k_own..]) {
                tail[i as usize - split] -= ti;
            }
        }
    }

    /// Backward sweep over the columns `cols` (in reverse):
    /// `y_j ← (y_j − Σ_{i>j} L_ij y_i) / L_jj`. Rows below `split` live in `own` (updated),
    /// the others in `tail` (read only).
    #[expect(
        clippy::too_many_arguments,
        reason = "a hot kernel: the two halves of the right-hand side (own rows, shared tail) are its data, as in `SplitRows`"
    )]
    pub(super) fn backward(
        &self,
        cols: Range<usize>,
        own: &mut [f64],
        own_off: usize,
        tail: &[f64],
        split: usize,
        tmp: &mut Vec<f64>,
    ) {
        pulp::Arch::new().dispatch(|| self.backward_kernel(cols, own, own_off, tail, split, tmp));
    }

    #[expect(
        clippy::too_many_arguments,
        reason = "a hot kernel: the two halves of the right-hand side (own rows, shared tail) are its data, as in `SplitRows`"
    )]
    #[inline(always)]
    pub(super) fn backward_kernel(
        &self,
        cols: Range<usize>,
        own: &mut [f64],
        own_off: usize,
        tail: &[f64],
        split: usize,
        tmp: &mut Vec<f64>,
    ) {
        for s in self.covering(&cols).rev() {
            let (c0, w, pattern, l) = self.get(s);
            let (j0, j1) = (cols.start.max(c0) - c0, cols.end.min(c0 + w) - c0);
            let ld = w + pattern.len();
            let p = pattern.len();
            if tmp.len() < p {
                tmp.resize(p, 0.0);
            }
            let t = &mut tmp[..p];
            let k_own = pattern.partition_point(|&r| (r as usize) < split);
            for (ti, &i) in t[..k_own].iter_mut().zip(&pattern[..k_own]) {
                *ti = own[i as usize - own_off];
            }
            for (ti, &i) in t[k_own..].iter_mut().zip(&pattern[k_own..]) {
                *ti = tail[i as usize - split];
            }
            for jj in j0..j1 {
                own[c0 + jj - own_off] -= dot(&col_below(l, ld, w, jj)[..p], t);
            }
            let d_own = split.saturating_sub(c0).min(w);
            for jj in (j0..j1).rev() {
                let col = &l[jj * ld..(jj + 1) * ld];
                let mut acc = own[c0 + jj - own_off];
                if jj + 1 < d_own {
                    let (r0, r1) = (c0 + jj + 1 - own_off, c0 + d_own - own_off);
                    acc -= dot(&col[jj + 1..d_own], &own[r0..r1]);
                }
                let lo = (jj + 1).max(d_own);
                if lo < w {
                    let tt = c0 + lo - split;
                    acc -= dot(&col[lo..w], &tail[tt..tt + w - lo]);
                }
                own[c0 + jj - own_off] = acc / col[jj];
            }
        }
    }
}

/// `r` right-hand sides stored row-major (`r` values per row) in two buffers: rows
/// `own_off..split` in `own`, rows `split..` in `tail`.
pub(super) struct SplitRows<'a> {
    pub(super) own: &'a mut [f64],
    pub(super) own_off: usize,
    pub(super) tail: &'a [f64],
    pub(super) split: usize,
    pub(super) r: usize,
}

impl Supernodes {
    /// [`backward`](Self::backward) for `r` right-hand sides at once ([`SplitRows`]). Every
    /// right-hand side goes through exactly the operations of a single backward sweep, in
    /// the same order ([`dot_rows`]), so each column of the result is bit-identical to a
    /// single sweep's; the factor is read once for all of them instead of once per column. (The per-step sweep keeps its own
    /// one-sided kernel: this one with `r = 1` made the main job 1.04× slower at j = 5,
    /// 3 paired runs.)
    pub(super) fn backward_rows(
        &self,
        cols: Range<usize>,
        rows: SplitRows<'_>,
        tmp: &mut Vec<f64>,
    ) {
        pulp::Arch::new().dispatch(|| self.backward_rows_kernel(cols, rows, tmp));
    }

    #[inline(always)]
    pub(super) fn backward_rows_kernel(
        &self,
        cols: Range<usize>,
        rows: SplitRows<'_>,
        tmp: &mut Vec<f64>,
    ) {
        let SplitRows {
            own,
            own_off,
            tail,
            split,
            r,
        } = rows;
        // Scratch: the gathered rows of the pattern (p × r), four partial sums (4 × r), one
        // dot product (r) and one running sum (r) per right-hand side.
        for s in self.covering(&cols).rev() {
            let (c0, w, pattern, l) = self.get(s);
            let (j0, j1) = (cols.start.max(c0) - c0, cols.end.min(c0 + w) - c0);
            let ld = w + pattern.len();
            let p = pattern.len();
            if tmp.len() < (p + 6) * r {
                tmp.resize((p + 6) * r, 0.0);
            }
            let (t, scratch) = tmp.split_at_mut(p * r);
            let (acc, scratch) = scratch.split_at_mut(4 * r);
            let (out, sums) = scratch.split_at_mut(r);
            let sums = &mut sums[..r];
            for (q, &i) in pattern.iter().enumerate() {
                let i = i as usize;
                let src = if i < split {
                    &own[(i - own_off) * r..(i - own_off + 1) * r]
                } else {
                    &tail[(i - split) * r..(i - split + 1) * r]
                };
                t[q * r..(q + 1) * r].copy_from_slice(src);
            }
            let t: &[f64] = t;
            for jj in j0..j1 {
                dot_rows(
                    &col_below(l, ld, w, jj)[..p],
                    |q| &t[q * r..(q + 1) * r],
                    acc,
                    out,
                );
                let row = c0 + jj - own_off;
                for (y, o) in own[row * r..(row + 1) * r].iter_mut().zip(out.iter()) {
                    *y -= o;
                }
            }
            let d_own = split.saturating_sub(c0).min(w);
            for jj in (j0..j1).rev() {
                let col = &l[jj * ld..(jj + 1) * ld];
                let row = c0 + jj - own_off;
                sums.copy_from_slice(&own[row * r..(row + 1) * r]);
                if jj + 1 < d_own {
                    let r0 = c0 + jj + 1 - own_off;
                    let own_ref: &[f64] = own;
                    dot_rows(
                        &col[jj + 1..d_own],
                        |q| &own_ref[(r0 + q) * r..(r0 + q + 1) * r],
                        acc,
                        out,
                    );
                    for (a, o) in sums.iter_mut().zip(out.iter()) {
                        *a -= o;
                    }
                }
                let lo = (jj + 1).max(d_own);
                if lo < w {
                    let tt = c0 + lo - split;
                    dot_rows(
                        &col[lo..w],
                        |q| &tail[(tt + q) * r..(tt + q + 1) * r],
                        acc,
                        out,
                    );
                    for (a, o) in sums.iter_mut().zip(out.iter()) {
                        *a -= o;
                    }
                }
                let diag = col[jj];
                for (y, a) in own[row * r..(row + 1) * r].iter_mut().zip(sums.iter()) {
                    *y = a / diag;
                }
            }
        }
    }
}

/// For each `k < r = out.len()`: `out[k] = Σ_i a_i · row(i)[k]`, summed exactly as [`dot`]
/// sums `Σ a_i b_i` (four partial sums over the blocks of four, then the rest in order), so
/// that each `out[k]` is bit-identical to `dot(a, b)` with `b_i = row(i)[k]`. `acc`: scratch
/// of at least `4 r`.
#[inline(always)]
pub(super) fn dot_rows<'a>(
    a: &[f64],
    row: impl Fn(usize) -> &'a [f64],
    acc: &mut [f64],
    out: &mut [f64],
) {
    let r = out.len();
    let acc = &mut acc[..4 * r];
    acc.fill(0.0);
    let n4 = a.len() - a.len() % 4;
    for c in (0..n4).step_by(4) {
        for q in 0..4 {
            let x = a[c + q];
            for (s, y) in acc[q * r..(q + 1) * r].iter_mut().zip(row(c + q)) {
                *s += x * y;
            }
        }
    }
    for k in 0..r {
        out[k] = (acc[k] + acc[r + k]) + (acc[2 * r + k] + acc[3 * r + k]);
    }
    for (i, &x) in a.iter().enumerate().skip(n4) {
        for (o, y) in out.iter_mut().zip(row(i)) {
            *o += x * y;
        }
    }
}

#[inline(always)]
pub(super) fn col_below(l: &[f64], ld: usize, w: usize, jj: usize) -> &[f64] {
    &l[jj * ld + w..(jj + 1) * ld]
}

/// `Σ a_i b_i` with four independent partial sums (a fixed order: deterministic, and not
/// bound by the latency of one chain of additions).
#[inline(always)]
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (a4, ar) = a.split_at(a.len() - a.len() % 4);
    let (b4, br) = b.split_at(a4.len());
    for (x, y) in a4.chunks_exact(4).zip(b4.chunks_exact(4)) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for (x, y) in ar.iter().zip(br) {
        s += x * y;
    }
    s
}
