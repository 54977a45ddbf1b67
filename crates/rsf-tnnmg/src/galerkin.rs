//! Galerkin coarse operators `C = Pᵀ H P` on fixed sparsity patterns.
//!
//! The patterns of `T = H P` and `C = Pᵀ T` are computed once; every numeric update is an
//! allocation-free pass. Rows of `P` belonging to masked (truncated) fine dofs are skipped,
//! which is the truncated prolongation of TNNMG.

use crate::csc::Csc;

#[derive(Debug, Clone)]
pub(crate) struct Galerkin {
    /// Prolongation, fine × coarse.
    pub p: Csc,
    /// Row-wise view of `p`: for fine row i, entries `prow_ptr[i]..prow_ptr[i+1]` of
    /// `(coarse column, position in p.val)`.
    prow_ptr: Vec<usize>,
    prow: Vec<(usize, usize)>,
    t: Csc,
    /// Coarse matrix (its values are the output).
    pub c: Csc,
    work_f: Vec<f64>,
    work_c: Vec<f64>,
}

fn union_pattern(
    ncols: usize,
    nrows: usize,
    mut rows_of: impl FnMut(usize, &mut Vec<usize>),
) -> Csc {
    let mut col_ptr = vec![0];
    let mut row_idx = Vec::new();
    let mut marker = vec![usize::MAX; nrows];
    let mut buf = Vec::new();
    for j in 0..ncols {
        buf.clear();
        rows_of(j, &mut buf);
        let start = row_idx.len();
        for &i in buf.iter() {
            if marker[i] != j {
                marker[i] = j;
                row_idx.push(i);
            }
        }
        row_idx[start..].sort_unstable();
        col_ptr.push(row_idx.len());
    }
    let nnz = row_idx.len();
    Csc {
        nrows,
        ncols,
        col_ptr,
        row_idx,
        val: vec![0.0; nnz],
    }
}

impl Galerkin {
    /// Symbolic set-up for the fine pattern `h` (n_f × n_f) and prolongation `p` (n_f × n_c).
    pub fn new(h: &Csc, p: Csc) -> Self {
        let (nf, nc) = (p.nrows, p.ncols);
        let mut counts = vec![0usize; nf + 1];
        for &i in &p.row_idx {
            counts[i + 1] += 1;
        }
        for i in 0..nf {
            counts[i + 1] += counts[i];
        }
        let prow_ptr = counts.clone();
        let mut fill = counts;
        let mut prow = vec![(0, 0); p.row_idx.len()];
        for j in 0..nc {
            for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                let i = p.row_idx[k];
                prow[fill[i]] = (j, k);
                fill[i] += 1;
            }
        }
        let t = union_pattern(nc, nf, |jc, out| {
            for k in p.col_ptr[jc]..p.col_ptr[jc + 1] {
                let jf = p.row_idx[k];
                out.extend_from_slice(&h.row_idx[h.col_ptr[jf]..h.col_ptr[jf + 1]]);
            }
        });
        let c = union_pattern(nc, nc, |jc, out| {
            for &i in &t.row_idx[t.col_ptr[jc]..t.col_ptr[jc + 1]] {
                out.extend(prow[prow_ptr[i]..prow_ptr[i + 1]].iter().map(|e| e.0));
            }
        });
        Self {
            work_f: vec![0.0; nf],
            work_c: vec![0.0; nc],
            p,
            prow_ptr,
            prow,
            t,
            c,
        }
    }

    /// Numeric update `C = P_tᵀ H P_t`, with `P_t` = `P` without the rows where `mask` is set.
    pub fn update(&mut self, h: &Csc, mask: &[bool]) {
        for jc in 0..self.p.ncols {
            self.update_t_column(h, mask, jc);
        }
        for jc in 0..self.p.ncols {
            self.update_c_column(mask, jc);
        }
    }

    /// Recomputes only the coarse columns `cols` (they must contain every column whose
    /// fine support meets a fine dof whose row, column or mask changed; see
    /// [`affected_columns`](Self::affected_columns)).
    pub fn update_columns(&mut self, h: &Csc, mask: &[bool], cols: &[usize]) {
        for &jc in cols {
            self.update_t_column(h, mask, jc);
        }
        for &jc in cols {
            self.update_c_column(mask, jc);
        }
    }

    /// Coarse columns of `C` that change when rows/columns/mask of the fine dofs marked in
    /// `changed` change: those whose `T = H P` column has a row in `changed` (this includes
    /// every column whose prolongation support meets `changed`, as `H` has a diagonal).
    pub fn affected_columns(&self, changed: &[bool]) -> Vec<usize> {
        (0..self.t.ncols)
            .filter(|&jc| {
                self.t.row_idx[self.t.col_ptr[jc]..self.t.col_ptr[jc + 1]]
                    .iter()
                    .any(|&i| changed[i])
            })
            .collect()
    }

    /// `T[:, jc] = H P_t[:, jc]`.
    fn update_t_column(&mut self, h: &Csc, mask: &[bool], jc: usize) {
        for k in self.p.col_ptr[jc]..self.p.col_ptr[jc + 1] {
            let jf = self.p.row_idx[k];
            if mask[jf] {
                continue;
            }
            let pv = self.p.val[k];
            let (rows, vals) = h.col(jf);
            for (&i, &hv) in rows.iter().zip(vals) {
                self.work_f[i] += hv * pv;
            }
        }
        for k in self.t.col_ptr[jc]..self.t.col_ptr[jc + 1] {
            let i = self.t.row_idx[k];
            self.t.val[k] = self.work_f[i];
            self.work_f[i] = 0.0;
        }
    }

    /// `C[:, jc] = P_tᵀ T[:, jc]`.
    fn update_c_column(&mut self, mask: &[bool], jc: usize) {
        for k in self.t.col_ptr[jc]..self.t.col_ptr[jc + 1] {
            let i = self.t.row_idx[k];
            if mask[i] {
                continue;
            }
            let tv = self.t.val[k];
            for &(ic, pos) in &self.prow[self.prow_ptr[i]..self.prow_ptr[i + 1]] {
                self.work_c[ic] += self.p.val[pos] * tv;
            }
        }
        for k in self.c.col_ptr[jc]..self.c.col_ptr[jc + 1] {
            let i = self.c.row_idx[k];
            self.c.val[k] = self.work_c[i];
            self.work_c[i] = 0.0;
        }
    }

    /// `coarse = P_tᵀ fine` (restriction; masked fine entries skipped).
    pub fn restrict(&self, fine: &[f64], mask: &[bool], coarse: &mut [f64]) {
        for (jc, out) in coarse.iter_mut().enumerate() {
            let mut s = 0.0;
            for k in self.p.col_ptr[jc]..self.p.col_ptr[jc + 1] {
                let i = self.p.row_idx[k];
                if !mask[i] {
                    s += self.p.val[k] * fine[i];
                }
            }
            *out = s;
        }
    }

    /// `fine += P_t coarse` (prolongation; masked fine entries left unchanged).
    pub fn prolong_add(&self, coarse: &[f64], mask: &[bool], fine: &mut [f64]) {
        for (i, f) in fine.iter_mut().enumerate() {
            if mask[i] {
                continue;
            }
            let mut s = 0.0;
            for &(ic, pos) in &self.prow[self.prow_ptr[i]..self.prow_ptr[i + 1]] {
                s += self.p.val[pos] * coarse[ic];
            }
            *f += s;
        }
    }
}
