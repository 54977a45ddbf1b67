//! One step of the multifrontal elimination: a front assembled from the matrix's columns
//! and its children's contribution blocks, its pivots factored and dropped panel by panel
//! (right-looking: each panel's update applied to the rest of the front, then the panel
//! forgotten), the right-hand sides carried through, and what remains — the contribution
//! block — passed on (interior columns) or added into the kept block (kept rows and
//! columns).
//!
//! The front lives on the stack, above its children's blocks, as the first `w + r` packed
//! columns of the lower triangle of its `(w + p) × (w + p)` matrix (pivots first, then the
//! interior update rows, then the kept ones); its kept rows' and columns' block is never
//! stored. Its last `r` columns are then exactly the contribution block's layout, which
//! moves down over the children's blocks.

use faer::dyn_stack::MemBuffer;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, MatRef, Par};

use super::packed::{
    cholesky, cholesky_scratch, col_start, sub_gram_cols, sub_gram_rows, try_zeros, PANEL,
};
use super::tree::{front_flops, update_buffer, Tree};
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
    /// One panel of the front's pivot columns, dense (`(w + p − j₀) × PANEL`).
    panel: Vec<f64>,
    /// The products of the updates.
    tmp: Vec<f64>,
    kidx: Vec<u32>,
    map: Vec<u32>,
    chol: MemBuffer,
}

impl Workspace {
    /// Buffers for the fronts of `tree` with `nrhs` right-hand sides.
    ///
    /// # Errors
    /// [`Error::OutOfMemory`] if an allocation fails.
    pub(super) fn new(tree: &Tree, nrhs: usize) -> Result<Self> {
        let n = tree.nr + tree.nk;
        let mut map = Vec::new();
        map.try_reserve_exact(n).map_err(|_| Error::OutOfMemory {
            what: "the front's index map",
            bytes: 4 * n,
        })?;
        map.resize(n, NONE);
        let chol = cholesky_scratch(PANEL)?;
        Ok(Self {
            panel: try_zeros(tree.max_panel, "the front's pivot panel")?,
            tmp: try_zeros(
                update_buffer(tree.max_order, nrhs),
                "the front's update panel",
            )?,
            kidx: Vec::with_capacity(tree.max_order),
            map,
            chol,
        })
    }
}

/// Eliminates front `t` of the schedule (its children done, their blocks on top of the
/// stack): `st.stack` loses the children's blocks and gains this front's contribution
/// block, `st.s` and `st.y` take its updates.
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
    // The front's order and its stored columns.
    let (ld, nc) = (w + p, w + r);
    let n = tree.nr + tree.nk;
    let map = &mut ws.map;
    for (q, slot) in map[c0..c0 + w].iter_mut().enumerate() {
        *slot = q as u32;
    }
    for (q, &g) in u.iter().enumerate() {
        map[g as usize] = (w + q) as u32;
    }
    // The front goes above the children's blocks; its contribution block moves down over
    // them at the end.
    let top = st.stack.len();
    let base = top - f.children_len;
    debug_assert!(st.stack.capacity() >= top + f.front);
    st.stack.resize(top + f.front, 0.0);
    st.peak_stack = st.peak_stack.max(top + f.front);
    st.largest_front = st.largest_front.max(f.front);
    {
        let (below, front) = st.stack.split_at_mut(top);
        // The matrix's entries of the pivot columns (lower triangle).
        for jj in 0..w {
            let c = c0 + jj;
            let (rows, vals) = m.a.col(m.order[c]);
            let col = &mut front[col_start(jj, ld)..col_start(jj, ld) + ld - jj];
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
                col[li as usize - jj] += v;
            }
        }
        // Extend-add of the children's blocks, in the order they were pushed.
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
                let dst = &mut front[col_start(lj, ld)..col_start(lj, ld) + ld - lj];
                for (&g, &v) in cu[j..].iter().zip(src) {
                    dst[map[g as usize] as usize - lj] += v;
                }
            }
        }
        debug_assert_eq!(off, top);
    }
    ws.kidx.clear();
    ws.kidx.extend(u[r..].iter().map(|&g| g - tree.nr as u32));
    let nrhs = st.y.len() / n.max(1);
    let front = &mut st.stack[top..top + f.front];
    for j0 in (0..w).step_by(PANEL) {
        let j1 = (j0 + PANEL).min(w);
        let nb = j1 - j0;
        let h = ld - j0;
        // The panel's columns, dense (h × nb), zero above the diagonal.
        let d = &mut ws.panel[..h * nb];
        for jj in 0..nb {
            let j = j0 + jj;
            let dcol = &mut d[jj * h..(jj + 1) * h];
            dcol[..jj].fill(0.0);
            dcol[jj..].copy_from_slice(&front[col_start(j, ld)..col_start(j, ld) + ld - j]);
        }
        let mut dm = MatMut::from_column_major_slice_mut(d, h, nb);
        let (mut l11, mut l21) = dm.rb_mut().split_at_row_mut(nb);
        cholesky(l11.rb_mut(), &mut ws.chol).map_err(|k| Error::NonPositivePivot {
            what: "the elimination of the interior",
            dof: m.order[c0 + j0 + k],
        })?;
        solve_lower_triangular_in_place(l11.rb(), l21.rb_mut().transpose_mut(), Par::Seq);
        // l21: the front's rows j₁..ld.
        let l21 = l21.rb();
        // The rest of the stored columns (pivots after the panel, then the contribution
        // block); the kept block straight into S_KK.
        sub_gram_cols(&mut front[col_start(j1, ld)..], nc - j1, l21, &mut ws.tmp);
        sub_gram_rows(
            &mut st.s,
            &ws.kidx,
            l21.subrows(nc - j1, ld - nc),
            &mut ws.tmp,
        );
        // Forward substitution of the right-hand sides, at most PANEL at a time.
        for k0 in (0..nrhs).step_by(PANEL) {
            let nr_ = (nrhs - k0).min(PANEL);
            let y = &mut st.y[k0 * n..];
            let at = c0 + j0;
            let mut piv = MatMut::from_column_major_slice_with_stride_mut(&mut y[at..], nb, nr_, n);
            solve_lower_triangular_in_place(l11.rb(), piv.rb_mut(), Par::Seq);
            let hb = h - nb;
            let tm = &mut ws.tmp[..hb * nr_];
            matmul(
                MatMut::from_column_major_slice_mut(tm, hb, nr_),
                Accum::Replace,
                l21,
                MatRef::from_column_major_slice_with_stride(&y[at..], nb, nr_, n),
                1.0,
                Par::Seq,
            );
            // Rows j₁..w of the front are the pivots c₀ + j₁.., the rest the update rows.
            let split = w - j1;
            for k in 0..nr_ {
                let y = &mut y[k * n..(k + 1) * n];
                let v = &tm[k * hb..(k + 1) * hb];
                for (yi, vi) in y[c0 + j1..c0 + w].iter_mut().zip(&v[..split]) {
                    *yi -= vi;
                }
                for (&g, vi) in u.iter().zip(&v[split..]) {
                    y[g as usize] -= vi;
                }
            }
        }
    }
    let cb_at = top + col_start(w, ld);
    debug_assert_eq!(top + f.front - cb_at, f.cb);
    st.stack.copy_within(cb_at..top + f.front, base);
    st.stack.truncate(base + f.cb);
    st.flops += front_flops(f, p, nrhs);
    for slot in &mut map[c0..c0 + w] {
        *slot = NONE;
    }
    for &g in u {
        map[g as usize] = NONE;
    }
    Ok(())
}
