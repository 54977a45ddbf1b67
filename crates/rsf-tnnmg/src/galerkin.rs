//! Galerkin coarse operators `C = P_tᵀ H P_t` in node-block form on fixed sparsity patterns.
//!
//! `P_t = F P` is the prolongation without the rows of masked (truncated) fine dofs, `F` the
//! diagonal 0/1 mask of the free fine dofs — the truncated prolongation of TNNMG. The
//! patterns of `T = H F P` (fine node rows) and `C = Pᵀ F T` (coarse node rows) are computed
//! once; every numeric update is an allocation-free pass over rows, and an incremental
//! update recomputes only the rows that a change of a few fine nodes can reach.
//!
//! Every row (of `T`, `C`, a restriction or a prolongation) is computed by one thread with
//! the same arithmetic whatever the thread count: with [`Parallelism`] the rows are split
//! into contiguous ranges, one per thread, each with its own dense accumulator, so the
//! results have the same bits on any number of threads.

use crate::error::{Error, Result};
use crate::Parallelism;
use rsf_linalg::for_node_rows;
use rsf_linalg::Csc;
use rsf_nonsmooth::ProblemError;
use rsf_ranks::block::{add_mul, add_mul_t, load, mul_vec, Block};
use rsf_ranks::bsr::BlockCsr;

/// Rows below which the Galerkin updates and the transfers stay on the calling thread.
const GALERKIN_PARALLEL_MIN: usize = 512;

/// The structure of `P` and `T` (fixed after [`Galerkin::new`]; on ranks the whole
/// structure, of which a rank computes its rows: `distributed::rank_hierarchy`).
#[derive(Debug, Clone)]
pub(crate) struct Pattern<const D: usize> {
    /// Prolongation by fine node rows: blocks `p_ptr[i]..p_ptr[i + 1]`, coarse node
    /// `p_col[k]`, value `p_val[k]`.
    pub p_ptr: Vec<usize>,
    pub p_col: Vec<u32>,
    pub p_val: Vec<Block<D>>,
    /// Its transpose by coarse node rows: `(fine node, position in p_val)`.
    pub pt_ptr: Vec<usize>,
    pub pt: Vec<(u32, u32)>,
    /// `T = H F P` by fine node rows: blocks `t_ptr[i]..t_ptr[i + 1]`, coarse node
    /// `t_col[k]`.
    pub t_ptr: Vec<usize>,
    pub t_col: Vec<u32>,
}

/// Galerkin products and grid transfers between one fine and one coarse level.
#[derive(Debug, Clone)]
pub(crate) struct Galerkin<const D: usize> {
    pattern: Pattern<D>,
    /// Values of `T`, by the pattern's rows.
    t_val: Vec<Block<D>>,
    /// Dense accumulators over the coarse nodes, one per thread used (zero between uses).
    accs: Vec<Vec<Block<D>>>,
}

/// The rows an update visits: all of `start..end`, or a sorted list.
#[derive(Debug, Clone, Copy)]
enum Rows<'a> {
    Range(usize, usize),
    List(&'a [usize]),
}

impl Rows<'_> {
    fn len(&self) -> usize {
        match self {
            Rows::Range(a, b) => b - a,
            Rows::List(l) => l.len(),
        }
    }
    fn get(&self, k: usize) -> usize {
        match self {
            Rows::Range(a, _) => a + k,
            Rows::List(l) => l[k],
        }
    }
    fn split_at(self, k: usize) -> (Self, Self) {
        match self {
            Rows::Range(a, b) => (Rows::Range(a, a + k), Rows::Range(a + k, b)),
            Rows::List(l) => {
                let (x, y) = l.split_at(k);
                (Rows::List(x), Rows::List(y))
            }
        }
    }
}

/// The values of consecutive rows of a row-compressed array: row `i` is
/// `val[ptr[i] − offset .. ptr[i + 1] − offset]`, or the single value `val[i − offset]`
/// without `ptr`.
struct RowValues<'a, T> {
    val: &'a mut [T],
    ptr: Option<&'a [usize]>,
    offset: usize,
}

impl<'a, T> RowValues<'a, T> {
    fn new(val: &'a mut [T], ptr: Option<&'a [usize]>) -> Self {
        Self {
            val,
            ptr,
            offset: 0,
        }
    }
    fn start(&self, i: usize) -> usize {
        self.ptr.map_or(i, |p| p[i])
    }
    fn row(&mut self, i: usize) -> &mut [T] {
        let (a, b) = (self.start(i), self.start(i + 1));
        &mut self.val[a - self.offset..b - self.offset]
    }
}

/// Output arrays that split between two rows (rows below `i` in the first part).
trait SplitRows: Sized {
    fn split_at_row(self, i: usize) -> (Self, Self);
}

impl<T> SplitRows for RowValues<'_, T> {
    fn split_at_row(self, i: usize) -> (Self, Self) {
        let at = self.start(i);
        let (a, b) = self.val.split_at_mut(at - self.offset);
        (
            RowValues {
                val: a,
                ptr: self.ptr,
                offset: self.offset,
            },
            RowValues {
                val: b,
                ptr: self.ptr,
                offset: at,
            },
        )
    }
}

impl<A: SplitRows, B: SplitRows, C: SplitRows> SplitRows for (A, B, C) {
    fn split_at_row(self, i: usize) -> (Self, Self) {
        let (a, b, c) = self;
        let ((a0, a1), (b0, b1), (c0, c1)) =
            (a.split_at_row(i), b.split_at_row(i), c.split_at_row(i));
        ((a0, b0, c0), (a1, b1, c1))
    }
}

/// Runs `f(i, acc, out)` for every row `i` of `rows`, in contiguous ranges, one per
/// accumulator in `accs` (on rayon's threads when there are several), `out` holding the
/// range's rows.
fn for_rows<O, A, F>(rows: Rows<'_>, accs: &mut [A], out: O, f: &F)
where
    O: SplitRows + Send,
    A: Send,
    F: Fn(usize, &mut A, &mut O) + Sync,
{
    if accs.len() == 1 || rows.len() < 2 {
        let mut out = out;
        for k in 0..rows.len() {
            f(rows.get(k), &mut accs[0], &mut out);
        }
        return;
    }
    let half = accs.len() / 2;
    let (r0, r1) = rows.split_at(rows.len() * half / accs.len());
    let (o0, o1) = out.split_at_row(r1.get(0));
    let (a0, a1) = accs.split_at_mut(half);
    rayon::join(|| for_rows(r0, a0, o0, f), || for_rows(r1, a1, o1, f));
}

/// Threads for `rows` rows on `par`: one below [`GALERKIN_PARALLEL_MIN`].
fn threads_for(rows: usize, par: Parallelism) -> usize {
    if rows >= GALERKIN_PARALLEL_MIN {
        par.threads().min(rows)
    } else {
        1
    }
}

/// Node index as u32 (the block formats store node indices in 32 bits).
fn node_u32(i: usize) -> Result<u32> {
    u32::try_from(i)
        .map_err(|_| Error::Problem(ProblemError::InvalidMatrix("more than 2^32 nodes".into())))
}

/// The node blocks of a prolongation `p` (`D n_f × D n_c`, node-major on both sides;
/// `p.nrows` and `p.ncols` multiples of `D`) by fine node rows: row `i`'s blocks are
/// `val[ptr[i]..ptr[i + 1]]`, coarse node `col[k]` increasing; explicit zeros kept.
pub(crate) fn prolongation_blocks<const D: usize>(
    p: &Csc,
) -> Result<(Vec<usize>, Vec<u32>, Vec<Block<D>>)> {
    let nf = p.nrows / D;
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
    Ok((p_ptr, p_col, p_val))
}

/// `fine_i ⊙ free_i`: node `i`'s values with its masked components zeroed (the
/// restriction's input, [`restrict_row`]).
pub(crate) fn masked<const D: usize>(fine: &[f64], free: &[f64], i: usize) -> [f64; D] {
    let (r, f) = (load::<D>(fine, i), load::<D>(free, i));
    std::array::from_fn(|c| r[c] * f[c])
}

/// One coarse row of the restriction `Pᵀ x`: `Σ_k P_kᵀ x_k` over the row's `(block P_k,
/// masked fine values x_k)` in order ([`masked`]), accumulated per block row `rr`, then
/// column.
pub(crate) fn restrict_row<'a, const D: usize>(
    row: impl Iterator<Item = (&'a Block<D>, [f64; D])>,
) -> [f64; D] {
    let mut s = [0.0; D];
    for (pb, x) in row {
        for rr in 0..D {
            for c in 0..D {
                s[c] += pb[rr][c] * x[rr];
            }
        }
    }
    s
}

/// One fine row of the prolongation `P coarse`: `Σ_k P_k coarse_j` over the row's
/// `(coarse node j, block P_k)` in order.
pub(crate) fn prolong_row<'a, const D: usize>(
    row: impl Iterator<Item = (usize, &'a Block<D>)>,
    coarse: &[f64],
) -> [f64; D] {
    let mut s = [0.0; D];
    for (j, pb) in row {
        let y = mul_vec(pb, &load::<D>(coarse, j));
        for c in 0..D {
            s[c] += y[c];
        }
    }
    s
}

impl<const D: usize> Galerkin<D> {
    /// Symbolic set-up for the pattern of the fine matrix `h` and the prolongation `p`
    /// (`D n_f × D n_c`, node-major on both sides). Returns the set-up and the coarse
    /// operator (zero, with its pattern).
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] if the column count of `p` is not a multiple of `D` or the
    /// row count is not `h`'s dimension.
    pub fn new(h: &BlockCsr<D>, p: &Csc) -> Result<(Self, BlockCsr<D>)> {
        let (pattern, coarse) = Pattern::new(h, p)?;
        let (nt, nc) = (pattern.t_col.len(), coarse.nodes());
        Ok((
            Self {
                pattern,
                t_val: vec![[[0.0; D]; D]; nt],
                accs: vec![vec![[[0.0; D]; D]; nc]],
            },
            coarse,
        ))
    }

    /// Numeric update `C = P_tᵀ H P_t` (all rows) on `par`'s threads; `free[i]` is 1 on
    /// free fine dofs and 0 on masked ones.
    pub fn update(&mut self, h: &BlockCsr<D>, free: &[f64], c: &mut BlockCsr<D>, par: Parallelism) {
        self.update_rows(
            h,
            free,
            c,
            (Rows::Range(0, h.nodes()), Rows::Range(0, c.nodes())),
            par,
        );
    }

    /// Recomputes only the given rows of `T` and `C` (sorted; see
    /// [`affected`](Self::affected)) on `par`'s threads.
    pub fn update_some(
        &mut self,
        h: &BlockCsr<D>,
        free: &[f64],
        c: &mut BlockCsr<D>,
        (t_rows, c_rows): (&[usize], &[usize]),
        par: Parallelism,
    ) {
        self.update_rows(h, free, c, (Rows::List(t_rows), Rows::List(c_rows)), par);
    }

    fn update_rows(
        &mut self,
        h: &BlockCsr<D>,
        free: &[f64],
        c: &mut BlockCsr<D>,
        (t_rows, c_rows): (Rows<'_>, Rows<'_>),
        par: Parallelism,
    ) {
        let Self {
            pattern,
            t_val,
            accs,
        } = self;
        let (t_threads, c_threads) = (
            threads_for(t_rows.len(), par),
            threads_for(c_rows.len(), par),
        );
        let nc = accs[0].len();
        accs.resize_with(t_threads.max(c_threads).max(accs.len()), || {
            vec![[[0.0; D]; D]; nc]
        });
        let t_out = RowValues::new(t_val, Some(&pattern.t_ptr));
        for_rows(t_rows, &mut accs[..t_threads], t_out, &|i, acc, out| {
            pattern.t_row(h, free, i, acc, out.row(i));
        });
        let t_val = &t_val[..];
        let (lower, upper) = (
            std::sync::Arc::make_mut(&mut c.lower),
            std::sync::Arc::make_mut(&mut c.upper),
        );
        let c_out = (
            RowValues::new(&mut c.diag, None),
            RowValues::new(&mut lower.val, Some(&lower.ptr)),
            RowValues::new(&mut upper.val, Some(&upper.ptr)),
        );
        let (lower_col, upper_col) = (&lower.col, &upper.col);
        for_rows(c_rows, &mut accs[..c_threads], c_out, &|ic, acc, out| {
            pattern.c_row(free, t_val, ic, acc);
            let zero = [[0.0; D]; D];
            out.0.row(ic)[0] = std::mem::replace(&mut acc[ic], zero);
            for (v, &q) in out.1.row(ic).iter_mut().zip(&lower_col[lower.ptr[ic]..]) {
                *v = std::mem::replace(&mut acc[q as usize], zero);
            }
            for (v, &q) in out.2.row(ic).iter_mut().zip(&upper_col[upper.ptr[ic]..]) {
                *v = std::mem::replace(&mut acc[q as usize], zero);
            }
        });
    }

    /// Rows of `T` and of `C` that change when the diagonal blocks of `H` or the masks of
    /// the fine nodes marked in `changed` change: `T` rows of those nodes and their
    /// neighbours in `h` (through `F`), and every coarse row whose prolongation support
    /// meets a changed `T` row. Both lists are sorted.
    pub fn affected(&self, h: &BlockCsr<D>, changed: &[bool]) -> (Vec<usize>, Vec<usize>) {
        let Pattern { pt_ptr, pt, .. } = &self.pattern;
        let nf = h.nodes();
        let t_changed: Vec<bool> = (0..nf)
            .map(|i| changed[i] || h.neighbours(i).any(|(q, _)| changed[q]))
            .collect();
        let t_rows = (0..nf).filter(|&i| t_changed[i]).collect();
        let c_rows = (0..pt_ptr.len() - 1)
            .filter(|&ic| {
                pt[pt_ptr[ic]..pt_ptr[ic + 1]]
                    .iter()
                    .any(|&(i, _)| t_changed[i as usize])
            })
            .collect();
        (t_rows, c_rows)
    }

    /// `coarse = P_tᵀ fine` (restriction; masked fine entries skipped through `free`), on
    /// `par`'s threads by coarse rows.
    pub fn restrict(&self, fine: &[f64], free: &[f64], coarse: &mut [f64], par: Parallelism) {
        let Pattern {
            pt_ptr, pt, p_val, ..
        } = &self.pattern;
        let row = |ic: usize, out: &mut [f64]| {
            let entries = pt[pt_ptr[ic]..pt_ptr[ic + 1]]
                .iter()
                .map(|&(i, k)| (&p_val[k as usize], masked::<D>(fine, free, i as usize)));
            out.copy_from_slice(&restrict_row::<D>(entries));
        };
        for_node_rows::<D>(coarse, (par, GALERKIN_PARALLEL_MIN), row);
    }

    /// `fine += P_t coarse` (prolongation; masked fine entries left unchanged), on `par`'s
    /// threads by fine rows.
    pub fn prolong_add(&self, coarse: &[f64], free: &[f64], fine: &mut [f64], par: Parallelism) {
        let Pattern {
            p_ptr,
            p_col,
            p_val,
            ..
        } = &self.pattern;
        let row = |i: usize, out: &mut [f64]| {
            let entries = (p_ptr[i]..p_ptr[i + 1]).map(|k| (p_col[k] as usize, &p_val[k]));
            let s = prolong_row::<D>(entries, coarse);
            for c in 0..D {
                out[c] += free[D * i + c] * s[c];
            }
        };
        for_node_rows::<D>(fine, (par, GALERKIN_PARALLEL_MIN), row);
    }
}

impl<const D: usize> Pattern<D> {
    /// The structure for the pattern of the fine matrix `h` (its values are not read) and
    /// the prolongation `p`, with the coarse operator's pattern (zero values): what
    /// [`Galerkin::new`] computes before its values.
    ///
    /// # Errors
    /// As [`Galerkin::new`].
    pub(crate) fn new(
        h: &impl rsf_ranks::bsr::NodePattern,
        p: &Csc,
    ) -> Result<(Self, BlockCsr<D>)> {
        if p.ncols % D != 0 || p.nrows != D * h.nodes() {
            return Err(ProblemError::InvalidMatrix(format!(
                "prolongation is {}x{}: expected {} rows and a column count divisible by {D}",
                p.nrows,
                p.ncols,
                D * h.nodes()
            ))
            .into());
        }
        let (nf, nc) = (h.nodes(), p.ncols / D);
        let (p_ptr, p_col, p_val) = prolongation_blocks::<D>(p)?;
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
            for j in std::iter::once(i).chain(h.node_neighbours(i)) {
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
        Ok((
            Self {
                p_ptr,
                p_col,
                p_val,
                pt_ptr,
                pt,
                t_ptr,
                t_col,
            },
            coarse,
        ))
    }
}

impl<const D: usize> Pattern<D> {
    /// `T[i, :] = Σ_j H_ij F_j P[j, :]` into `out` (row `i`'s values), through `acc`.
    fn t_row(
        &self,
        h: &BlockCsr<D>,
        free: &[f64],
        i: usize,
        acc: &mut [Block<D>],
        out: &mut [Block<D>],
    ) {
        let row = std::iter::once((i, &h.diag[i])).chain(h.neighbours(i));
        self.t_row_of(row, free, i, acc, out);
    }

    /// [`t_row`](Self::t_row) of fine row `i` given as its blocks `(j, H_ij)`, the
    /// diagonal first, then the off-diagonal blocks in increasing `j` (the order of
    /// [`BlockCsr`]'s rows, so the same bits); `free` is read at the row's nodes.
    pub(crate) fn t_row_of<'h>(
        &self,
        row: impl Iterator<Item = (usize, &'h Block<D>)>,
        free: &[f64],
        i: usize,
        acc: &mut [Block<D>],
        out: &mut [Block<D>],
    ) {
        for (j, hb) in row {
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
                add_mul(&mut acc[self.p_col[k] as usize], &hf, &self.p_val[k]);
            }
        }
        for (o, &q) in out.iter_mut().zip(&self.t_col[self.t_ptr[i]..]) {
            *o = std::mem::replace(&mut acc[q as usize], [[0.0; D]; D]);
        }
    }

    /// Accumulates `C[ic, :] = Σ_i (F_i P[i, ic])ᵀ T[i, :]` in `acc` (the caller takes
    /// row `ic`'s entries out, leaving zeros).
    fn c_row(&self, free: &[f64], t_val: &[Block<D>], ic: usize, acc: &mut [Block<D>]) {
        self.c_row_of(free, |i| &t_val[self.t_ptr[i]..self.t_ptr[i + 1]], ic, acc);
    }

    /// [`c_row`](Self::c_row) with `T`'s rows given by `t_row(i)` (row `i`'s values in the
    /// pattern's order); `free` is read at the fine nodes of `ic`'s support.
    pub(crate) fn c_row_of<'t>(
        &self,
        free: &[f64],
        t_row: impl Fn(usize) -> &'t [Block<D>],
        ic: usize,
        acc: &mut [Block<D>],
    ) {
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
            let cols = &self.t_col[self.t_ptr[i]..self.t_ptr[i + 1]];
            for (&q, t) in cols.iter().zip(t_row(i)) {
                add_mul_t(&mut acc[q as usize], &pf, t);
            }
        }
    }

    /// The number of blocks of `T`'s fine row `i`.
    pub(crate) fn t_len(&self, i: usize) -> usize {
        self.t_ptr[i + 1] - self.t_ptr[i]
    }
}
