//! One step of the multifrontal elimination: a front assembled from the matrix's columns
//! and its children's contribution blocks, its pivots factored, its contribution block
//! passed on (interior columns) or added into the kept block (kept rows and columns), the
//! right-hand sides carried through, the front dropped.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, MatRef, Par};

use super::packed::{col_start, sub_gram_cols, sub_gram_rows, try_zeros, PANEL};
use super::tree::{front_flops, Tree};
use crate::error::{Error, Result};
use rsf_linalg::Csc;

const NONE: u32 = u32::MAX;

/// The matrix in elimination order: `pos[dof]` its position (`usize::MAX` if fixed),
/// `order[position]` its dof.
pub(super) struct Ordered<'a> {
    pub(super) a: &'a Csc,
    pub(super) pos: &'a [usize],
    pub(super) order: &'a [usize],
}

/// What the elimination carries from one front to the next (and what a checkpoint
/// holds).
#[derive(Debug)]
pub(super) struct State {
    /// Fronts of the schedule done.
    pub(super) done: usize,
    /// The pending contribution blocks, each the first `r` packed columns of its lower
    /// triangle, in processing order.
    pub(super) stack: Vec<f64>,
    /// The kept block `S_KK`, packed rows.
    pub(super) s: Vec<f64>,
    /// The right-hand sides in elimination order, one after the other (`n` each): after
    /// the front of a column, that column's forward-substituted value.
    pub(super) y: Vec<f64>,
    /// Largest front and peak stack so far (entries), floating-point operations so far.
    pub(super) largest_front: usize,
    pub(super) peak_stack: usize,
    pub(super) flops: f64,
}

/// The buffers every front reuses: nothing is allocated per front.
pub(super) struct Workspace {
    panel: Vec<f64>,
    tmp: Vec<f64>,
    kidx: Vec<u32>,
    map: Vec<u32>,
    chol: MemBuffer,
}

impl Workspace {
    /// Buffers for the fronts of `tree`.
    ///
    /// # Errors
    /// [`Error::OutOfMemory`] if an allocation fails.
    pub(super) fn new(tree: &Tree) -> Result<Self> {
        let n = tree.nr + tree.nk;
        let mut map = Vec::new();
        map.try_reserve_exact(n).map_err(|_| Error::OutOfMemory {
            what: "the front's index map",
            bytes: 4 * n,
        })?;
        map.resize(n, NONE);
        let chol = MemBuffer::try_new(cholesky_in_place_scratch::<f64>(
            tree.max_pivots,
            Par::Seq,
            Default::default(),
        ))
        .map_err(|_| Error::OutOfMemory {
            what: "the pivot block's scratch",
            bytes: 8 * tree.max_pivots,
        })?;
        Ok(Self {
            panel: try_zeros(tree.max_panel, "the front's pivot block")?,
            tmp: try_zeros(tree.max_rows * PANEL, "the front's update panel")?,
            kidx: Vec::with_capacity(tree.max_rows),
            map,
            chol,
        })
    }
}

/// Eliminates front `t` of the schedule (its children done, their blocks on top of the
/// stack): `st.stack` loses the children's blocks and gains this front's, `st.s` and
/// `st.y` take its updates.
///
/// # Errors
/// [`Error::NonPositivePivot`] at the dof whose pivot is not positive;
/// [`Error::Factorisation`] if an entry of the matrix falls outside the symbolic front
/// (an internal error).
pub(super) fn eliminate(
    t: usize,
    tree: &Tree,
    m: &Ordered<'_>,
    st: &mut State,
    ws: &mut Workspace,
) -> Result<()> {
    let f = &tree.fronts[t];
    let u = tree.rows_of(t);
    let (c0, w, r) = (f.c0, f.w, f.r);
    let p = u.len();
    let ld = w + p;
    let n = tree.nr + tree.nk;
    let map = &mut ws.map;
    for (q, slot) in map[c0..c0 + w].iter_mut().enumerate() {
        *slot = q as u32;
    }
    for (q, &g) in u.iter().enumerate() {
        map[g as usize] = (w + q) as u32;
    }
    let panel = &mut ws.panel[..ld * w];
    panel.fill(0.0);
    // This front's block goes above the children's, then moves down over them.
    let top = st.stack.len();
    let base = top - f.children_len;
    debug_assert!(st.stack.capacity() >= top + f.cb);
    st.stack.resize(top + f.cb, 0.0);
    st.peak_stack = st.peak_stack.max(top + f.cb);
    st.largest_front = st.largest_front.max(ld * w + f.cb);
    // The matrix's entries of the pivot columns (lower triangle).
    for jj in 0..w {
        let c = c0 + jj;
        let (rows, vals) = m.a.col(m.order[c]);
        let col = &mut panel[jj * ld..(jj + 1) * ld];
        for (&i, &v) in rows.iter().zip(vals) {
            let pi = m.pos[i];
            if pi == usize::MAX || pi < c {
                continue;
            }
            let li = map[pi];
            if li == NONE {
                return Err(Error::Factorisation(format!(
                    "internal: entry ({i}, {}) outside the symbolic front",
                    m.order[c]
                )));
            }
            col[li as usize] += v;
        }
    }
    // Extend-add of the children's blocks, in the order they were pushed.
    {
        let (below, own) = st.stack.split_at_mut(top);
        let mut off = base;
        for &ct in tree.children_of(t) {
            let ct = ct as usize;
            let cu = tree.rows_of(ct);
            let pc = cu.len();
            for j in 0..tree.fronts[ct].r {
                let len = pc - j;
                let src = &below[off..off + len];
                off += len;
                let lj = map[cu[j] as usize] as usize;
                let rows = &cu[j..];
                if lj < w {
                    let col = &mut panel[lj * ld..(lj + 1) * ld];
                    for (&g, &v) in rows.iter().zip(src) {
                        col[map[g as usize] as usize] += v;
                    }
                } else {
                    let jl = lj - w;
                    let dst = &mut own[col_start(jl, p)..col_start(jl, p) + p - jl];
                    for (&g, &v) in rows.iter().zip(src) {
                        dst[map[g as usize] as usize - lj] += v;
                    }
                }
            }
        }
        debug_assert_eq!(off, top);
    }
    st.stack.copy_within(top..top + f.cb, base);
    st.stack.truncate(base + f.cb);
    // Factor the pivots; the rows below become L₂₁ = A₂₁ L₁₁⁻ᵀ.
    let mut front = MatMut::from_column_major_slice_mut(panel, ld, w);
    let (mut l11, mut l21) = front.rb_mut().split_at_row_mut(w);
    cholesky_in_place(
        l11.rb_mut(),
        Default::default(),
        Par::Seq,
        MemStack::new(&mut ws.chol),
        Default::default(),
    )
    .map_err(|e| {
        let faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } = e;
        Error::NonPositivePivot {
            what: "the elimination of the interior",
            dof: m.order[c0 + index],
        }
    })?;
    solve_lower_triangular_in_place(l11.rb(), l21.rb_mut().transpose_mut(), Par::Seq);
    let l21 = l21.rb();
    // The contribution block: its interior columns travel, its kept part is added in place.
    sub_gram_cols(&mut st.stack[base..base + f.cb], r, l21, &mut ws.tmp);
    ws.kidx.clear();
    ws.kidx.extend(u[r..].iter().map(|&g| g - tree.nr as u32));
    sub_gram_rows(&mut st.s, &ws.kidx, l21.subrows(r, p - r), &mut ws.tmp);
    // Forward substitution of the right-hand sides.
    // Forward substitution of the right-hand sides, at most PANEL at a time.
    let nrhs = st.y.len() / n.max(1);
    for k0 in (0..nrhs).step_by(PANEL) {
        let nb = (nrhs - k0).min(PANEL);
        let y = &mut st.y[k0 * n..];
        let mut piv = MatMut::from_column_major_slice_with_stride_mut(&mut y[c0..], w, nb, n);
        solve_lower_triangular_in_place(l11.rb(), piv.rb_mut(), Par::Seq);
        let t = &mut ws.tmp[..p * nb];
        matmul(
            MatMut::from_column_major_slice_mut(t, p, nb),
            Accum::Replace,
            l21,
            MatRef::from_column_major_slice_with_stride(&y[c0..], w, nb, n),
            1.0,
            Par::Seq,
        );
        for k in 0..nb {
            let y = &mut y[k * n..(k + 1) * n];
            for (&g, v) in u.iter().zip(&t[k * p..(k + 1) * p]) {
                y[g as usize] -= v;
            }
        }
    }
    st.flops += front_flops(f, p, nrhs);
    for slot in &mut map[c0..c0 + w] {
        *slot = NONE;
    }
    for &g in u {
        map[g as usize] = NONE;
    }
    Ok(())
}
