//! Galerkin coarse operators `C = P_tᵀ H P_t` in node-block form on fixed sparsity patterns.
//!
//! `P_t = F P` is the prolongation without the rows of masked (truncated) fine dofs, `F` the
//! diagonal 0/1 mask of the free fine dofs — the truncated prolongation of TNNMG. The
//! patterns of `T = H F P` (fine node rows) and `C = Pᵀ F T` (coarse node rows) are computed
//! once; every numeric update is an allocation-free pass over rows, and an incremental
//! update recomputes only the rows that a change of a few fine nodes can reach.

use crate::block::{add_mul, add_mul_t, load, mul_vec, Block};
use crate::bsr::BlockCsr;
use crate::csc::Csc;
use crate::error::{Error, Result};

#[derive(Debug, Clone)]
pub(crate) struct Galerkin<const D: usize> {
    /// Prolongation by fine node rows: blocks `p_ptr[i]..p_ptr[i + 1]`, coarse node
    /// `p_col[k]`, value `p_val[k]`.
    p_ptr: Vec<usize>,
    p_col: Vec<u32>,
    p_val: Vec<Block<D>>,
    /// Its transpose by coarse node rows: `(fine node, position in p_val)`.
    pt_ptr: Vec<usize>,
    pt: Vec<(u32, u32)>,
    /// `T = H F P` by fine node rows.
    t_ptr: Vec<usize>,
    t_col: Vec<u32>,
    t_val: Vec<Block<D>>,
    /// Dense accumulator over the coarse nodes (zero between uses).
    acc: Vec<Block<D>>,
}

/// Node index as u32 (the block formats store node indices in 32 bits).
fn node_u32(i: usize) -> Result<u32> {
    u32::try_from(i).map_err(|_| Error::InvalidMatrix("more than 2^32 nodes".into()))
}

impl<const D: usize> Galerkin<D> {
    /// Symbolic set-up for the pattern of the fine matrix `h` and the prolongation `p`
    /// (`D n_f × D n_c`, node-major on both sides). Returns the set-up and the coarse
    /// operator (zero, with its pattern).
    ///
    /// # Errors
    /// [`Error::InvalidMatrix`] if the column count of `p` is not a multiple of `D` or the
    /// row count is not `h`'s dimension.
    pub fn new(h: &BlockCsr<D>, p: &Csc) -> Result<(Self, BlockCsr<D>)> {
        if p.ncols % D != 0 || p.nrows != h.n() {
            return Err(Error::InvalidMatrix(format!(
                "prolongation is {}x{}: expected {} rows and a column count divisible by {D}",
                p.nrows,
                p.ncols,
                h.n()
            )));
        }
        let (nf, nc) = (h.nodes(), p.ncols / D);
        // Node-level entries (fine i, coarse J, r, c, value), sorted by (i, J).
        let mut entries: Vec<(usize, usize, usize, usize, f64)> = Vec::new();
        for jd in 0..p.ncols {
            let (rows, vals) = p.col(jd);
            for (&id, &v) in rows.iter().zip(vals) {
                entries.push((id / D, jd / D, id % D, jd % D, v));
            }
        }
        entries.sort_by_key(|e| (e.0, e.1));
        let mut p_ptr = vec![0usize; nf + 1];
        let mut p_col: Vec<u32> = Vec::new();
        let mut p_val: Vec<Block<D>> = Vec::new();
        let mut last: Option<(usize, usize)> = None;
        for &(i, j, r, c, v) in &entries {
            if last != Some((i, j)) {
                p_col.push(node_u32(j)?);
                p_val.push([[0.0; D]; D]);
                p_ptr[i + 1] += 1;
                last = Some((i, j));
            }
            p_val.last_mut().expect("pushed")[r][c] += v;
        }
        for i in 0..nf {
            p_ptr[i + 1] += p_ptr[i];
        }
        // Transpose.
        let mut pt_ptr = vec![0usize; nc + 1];
        for &j in &p_col {
            pt_ptr[j as usize + 1] += 1;
        }
        for j in 0..nc {
            pt_ptr[j + 1] += pt_ptr[j];
        }
        let mut fill = pt_ptr.clone();
        let mut pt = vec![(0u32, 0u32); p_col.len()];
        for i in 0..nf {
            for k in p_ptr[i]..p_ptr[i + 1] {
                let j = p_col[k] as usize;
                pt[fill[j]] = (node_u32(i)?, node_u32(k)?);
                fill[j] += 1;
            }
        }
        // Patterns of T (fine rows) and C (coarse rows, off-diagonal).
        let mut marker = vec![usize::MAX; nc];
        let mut t_ptr = vec![0];
        let mut t_col = Vec::new();
        for i in 0..nf {
            let start = t_col.len();
            for j in std::iter::once(i).chain(h.neighbours(i).map(|(q, _)| q)) {
                for &jc in &p_col[p_ptr[j]..p_ptr[j + 1]] {
                    if marker[jc as usize] != i {
                        marker[jc as usize] = i;
                        t_col.push(jc);
                    }
                }
            }
            t_col[start..].sort_unstable();
            t_ptr.push(t_col.len());
        }
        marker.fill(usize::MAX);
        let mut rows = Vec::with_capacity(nc);
        for ic in 0..nc {
            let mut cols = Vec::new();
            for &(i, _) in &pt[pt_ptr[ic]..pt_ptr[ic + 1]] {
                let i = i as usize;
                for &jc in &t_col[t_ptr[i]..t_ptr[i + 1]] {
                    let jc = jc as usize;
                    if jc != ic && marker[jc] != ic {
                        marker[jc] = ic;
                        cols.push(jc);
                    }
                }
            }
            cols.sort_unstable();
            rows.push(cols);
        }
        let coarse = BlockCsr::zeros(rows.into_iter())?;
        let nt = t_col.len();
        Ok((
            Self {
                p_ptr,
                p_col,
                p_val,
                pt_ptr,
                pt,
                t_ptr,
                t_col,
                t_val: vec![[[0.0; D]; D]; nt],
                acc: vec![[[0.0; D]; D]; nc],
            },
            coarse,
        ))
    }

    /// Numeric update `C = P_tᵀ H P_t` (all rows); `free[i]` is 1 on free fine dofs and 0
    /// on masked ones.
    pub fn update(&mut self, h: &BlockCsr<D>, free: &[f64], c: &mut BlockCsr<D>) {
        for i in 0..h.nodes() {
            self.update_t_row(h, free, i);
        }
        for ic in 0..c.nodes() {
            self.update_c_row(free, ic, c);
        }
    }

    /// Recomputes only the given rows of `T` and `C` (see [`affected`](Self::affected)).
    pub fn update_rows(
        &mut self,
        h: &BlockCsr<D>,
        free: &[f64],
        c: &mut BlockCsr<D>,
        t_rows: &[usize],
        c_rows: &[usize],
    ) {
        for &i in t_rows {
            self.update_t_row(h, free, i);
        }
        for &ic in c_rows {
            self.update_c_row(free, ic, c);
        }
    }

    /// Rows of `T` and of `C` that change when the diagonal blocks of `H` or the masks of
    /// the fine nodes marked in `changed` change: `T` rows of those nodes and their
    /// neighbours in `h` (through `F`), and every coarse row whose prolongation support
    /// meets a changed `T` row. The coarse rows are sorted.
    pub fn affected(&self, h: &BlockCsr<D>, changed: &[bool]) -> (Vec<usize>, Vec<usize>) {
        let nf = h.nodes();
        let t_changed: Vec<bool> = (0..nf)
            .map(|i| changed[i] || h.neighbours(i).any(|(q, _)| changed[q]))
            .collect();
        let t_rows = (0..nf).filter(|&i| t_changed[i]).collect();
        let c_rows = (0..self.acc.len())
            .filter(|&ic| {
                self.pt[self.pt_ptr[ic]..self.pt_ptr[ic + 1]]
                    .iter()
                    .any(|&(i, _)| t_changed[i as usize])
            })
            .collect();
        (t_rows, c_rows)
    }

    /// `T[i, :] = Σ_j H_ij F_j P[j, :]`.
    fn update_t_row(&mut self, h: &BlockCsr<D>, free: &[f64], i: usize) {
        for (j, hb) in std::iter::once((i, &h.diag[i])).chain(h.neighbours(i)) {
            let f = load::<D>(free, j);
            if f.iter().all(|&x| x == 0.0) {
                continue;
            }
            let mut hf = *hb;
            for row in hf.iter_mut() {
                for c in 0..D {
                    row[c] *= f[c];
                }
            }
            for k in self.p_ptr[j]..self.p_ptr[j + 1] {
                add_mul(&mut self.acc[self.p_col[k] as usize], &hf, &self.p_val[k]);
            }
        }
        for k in self.t_ptr[i]..self.t_ptr[i + 1] {
            let a = &mut self.acc[self.t_col[k] as usize];
            self.t_val[k] = *a;
            *a = [[0.0; D]; D];
        }
    }

    /// `C[ic, :] = Σ_i (F_i P[i, ic])ᵀ T[i, :]` (written into both triangles' row `ic`).
    fn update_c_row(&mut self, free: &[f64], ic: usize, c: &mut BlockCsr<D>) {
        for &(i, k) in &self.pt[self.pt_ptr[ic]..self.pt_ptr[ic + 1]] {
            let i = i as usize;
            let f = load::<D>(free, i);
            if f.iter().all(|&x| x == 0.0) {
                continue;
            }
            let mut pf = self.p_val[k as usize];
            for (row, &fr) in pf.iter_mut().zip(&f) {
                for v in row.iter_mut() {
                    *v *= fr;
                }
            }
            for kt in self.t_ptr[i]..self.t_ptr[i + 1] {
                add_mul_t(&mut self.acc[self.t_col[kt] as usize], &pf, &self.t_val[kt]);
            }
        }
        let zero = [[0.0; D]; D];
        c.diag[ic] = std::mem::replace(&mut self.acc[ic], zero);
        for t in [&mut c.lower, &mut c.upper] {
            let t = std::sync::Arc::make_mut(t);
            for k in t.range(ic) {
                t.val[k] = std::mem::replace(&mut self.acc[t.col[k] as usize], zero);
            }
        }
    }

    /// `coarse = P_tᵀ fine` (restriction; masked fine entries skipped through `free`).
    pub fn restrict(&self, fine: &[f64], free: &[f64], coarse: &mut [f64]) {
        for ic in 0..self.acc.len() {
            let mut s = [0.0; D];
            for &(i, k) in &self.pt[self.pt_ptr[ic]..self.pt_ptr[ic + 1]] {
                let i = i as usize;
                let (r, f) = (load::<D>(fine, i), load::<D>(free, i));
                let pb = &self.p_val[k as usize];
                for rr in 0..D {
                    let x = r[rr] * f[rr];
                    for c in 0..D {
                        s[c] += pb[rr][c] * x;
                    }
                }
            }
            coarse[D * ic..D * ic + D].copy_from_slice(&s);
        }
    }

    /// `fine += P_t coarse` (prolongation; masked fine entries left unchanged).
    pub fn prolong_add(&self, coarse: &[f64], free: &[f64], fine: &mut [f64]) {
        for i in 0..self.p_ptr.len() - 1 {
            let mut s = [0.0; D];
            for k in self.p_ptr[i]..self.p_ptr[i + 1] {
                let y = mul_vec(&self.p_val[k], &load::<D>(coarse, self.p_col[k] as usize));
                for c in 0..D {
                    s[c] += y[c];
                }
            }
            for c in 0..D {
                fine[D * i + c] += free[D * i + c] * s[c];
            }
        }
    }
}
