//! The assembly tree of the elimination: the supernodes of the interior (split where the
//! kept set begins), their update rows, parents and children, and a postorder whose
//! stack of pending contribution blocks is as small as the tree allows (Liu 1986).

use std::ops::Range;

use super::packed::{packed_len, trapezoid_len, PANEL};
use crate::error::{Error, Result};
use crate::partial_cholesky::SymbolicLayout;

/// One front: a supernode's pivot columns in the interior and its update rows.
#[derive(Debug, Clone)]
pub(super) struct Front {
    /// First pivot column (elimination position).
    pub(super) c0: usize,
    /// Number of pivot columns `w`.
    pub(super) w: usize,
    /// The update rows (elimination positions, increasing) in [`Tree::rows`]: the kept
    /// columns of a supernode that straddles the interior's end, then its rows below.
    pub(super) rows: Range<usize>,
    /// How many update rows are interior (`r`; they come first): the contribution
    /// block's first `r` columns travel to the parent, the rest is kept.
    pub(super) r: usize,
    /// Entries of the travelling contribution block (the first `r` packed columns of the
    /// lower triangle of `p × p`).
    pub(super) cb: usize,
    /// Entries of the front as it is stored: the first `w + r` packed columns of the
    /// lower triangle of `(w + p) × (w + p)` (the kept rows' and columns' block is not
    /// stored: it goes straight into `S_KK`), its last `cb` the contribution block.
    pub(super) front: usize,
    /// The children with a contribution block, as positions in the schedule, in the
    /// order they are processed (their blocks are the top of the stack, in this order).
    pub(super) children: Range<usize>,
    /// Entries of the children's blocks together.
    pub(super) children_len: usize,
}

/// The fronts in processing order and what the symbolic pass knows of the memory.
#[derive(Debug)]
pub(super) struct Tree {
    /// Interior dofs `|R|` (the columns eliminated).
    pub(super) nr: usize,
    /// Kept dofs `|K|`.
    pub(super) nk: usize,
    /// Whether the supernode of the last interior column holds kept columns too (and is
    /// split there).
    #[cfg_attr(not(test), expect(dead_code, reason = "read by the unit tests"))]
    pub(super) split: bool,
    /// The fronts, in processing order (a postorder of the assembly forest).
    pub(super) fronts: Vec<Front>,
    /// Update rows of all fronts.
    pub(super) rows: Vec<u32>,
    /// Children lists (schedule positions).
    pub(super) children: Vec<u32>,
    /// Largest order `w + p` of a front.
    pub(super) max_order: usize,
    /// Largest dense panel of pivot columns, `(w + p) min(w, PANEL)`.
    pub(super) max_panel: usize,
    /// Largest front (entries stored).
    pub(super) max_front: usize,
    /// Peak entries on the stack of contribution blocks and the front being eliminated.
    pub(super) peak_stack: usize,
    /// Floating-point operations of the elimination without right-hand sides, and per
    /// right-hand side.
    pub(super) flops: f64,
    pub(super) flops_per_rhs: f64,
}

impl Tree {
    /// The tree of the supernodes of `layout` whose columns reach below `nr` (the
    /// interior is `0..nr` of the order, the kept set `nr..`).
    ///
    /// # Errors
    /// [`Error::Factorisation`] if the symbolic analysis breaks the assembly-tree property
    /// (a child's rows outside its parent's front: an internal error);
    /// [`Error::TooLarge`] if a front's size overflows.
    pub(super) fn new(layout: &SymbolicLayout, nr: usize) -> Result<Self> {
        let n = layout.order.len();
        let start = &layout.start;
        // Supernodes with a pivot: a prefix (starts increase).
        let ns = start.partition_point(|&c| c < nr).min(start.len() - 1);
        let mut rows: Vec<u32> = Vec::new();
        let mut ptr = Vec::with_capacity(ns + 1);
        ptr.push(0);
        let mut fronts = Vec::with_capacity(ns);
        let mut parent = vec![u32::MAX; ns];
        let too_large = |what| Error::TooLarge {
            what,
            bytes: u128::MAX,
            limit: usize::MAX,
        };
        for s in 0..ns {
            let (c0, c1) = (start[s], start[s + 1]);
            let end = c1.min(nr);
            rows.extend((end..c1).map(|c| c as u32));
            rows.extend_from_slice(&layout.rows[layout.row_ptr[s]..layout.row_ptr[s + 1]]);
            ptr.push(rows.len());
            let u = &rows[ptr[s]..];
            let p = u.len();
            let r = u.partition_point(|&g| (g as usize) < nr);
            if r > 0 {
                // The supernode holding the first row below: the parent.
                let t = start.partition_point(|&c| c <= u[0] as usize) - 1;
                parent[s] = t as u32;
            }
            let w = end - c0;
            packed_len(w + p).ok_or(too_large("a front"))?;
            fronts.push(Front {
                c0,
                w,
                rows: ptr[s]..ptr[s + 1],
                r,
                cb: trapezoid_len(r, p),
                front: trapezoid_len(w + r, w + p),
                children: 0..0,
                children_len: 0,
            });
        }
        // The assembly-tree property: a child's update rows are rows of its parent's front.
        check_assembly_tree(&fronts, &rows, &parent, start)?;
        // Children lists; the peak of each subtree's stack, bottom-up (a child's index is
        // below its parent's), children ordered by decreasing peak − block (Liu 1986). A
        // front is assembled on top of its children's blocks, which it then replaces by its
        // own.
        let mut count = vec![0usize; ns + 1];
        for &t in &parent {
            if t != u32::MAX {
                count[t as usize + 1] += 1;
            }
        }
        for s in 0..ns {
            count[s + 1] += count[s];
        }
        let mut kids = vec![0u32; count[ns]];
        let mut fill = count.clone();
        for (s, &t) in parent.iter().enumerate() {
            if t != u32::MAX {
                kids[fill[t as usize]] = s as u32;
                fill[t as usize] += 1;
            }
        }
        let mut peak = vec![0usize; ns];
        for s in 0..ns {
            let list = &mut kids[count[s]..count[s + 1]];
            list.sort_by(|&x, &y| {
                let (x, y) = (x as usize, y as usize);
                let kx = peak[x] - fronts[x].cb;
                let ky = peak[y] - fronts[y].cb;
                ky.cmp(&kx).then(x.cmp(&y))
            });
            let mut below = 0usize;
            let mut worst = 0usize;
            for &c in list.iter() {
                let c = c as usize;
                worst = worst.max(below.saturating_add(peak[c]));
                below = below.saturating_add(fronts[c].cb);
            }
            fronts[s].children_len = below;
            peak[s] = worst.max(below.saturating_add(fronts[s].front));
        }
        // Postorder from the roots in increasing order.
        let mut sched = Vec::with_capacity(ns);
        let mut walk: Vec<(usize, usize)> = Vec::new();
        for root in (0..ns).filter(|&s| parent[s] == u32::MAX) {
            walk.push((root, 0));
            while let Some(&mut (v, ref mut k)) = walk.last_mut() {
                if count[v] + *k < count[v + 1] {
                    let c = kids[count[v] + *k] as usize;
                    *k += 1;
                    walk.push((c, 0));
                } else {
                    sched.push(v);
                    walk.pop();
                }
            }
        }
        debug_assert_eq!(sched.len(), ns);
        let mut at = vec![0u32; ns];
        for (k, &s) in sched.iter().enumerate() {
            at[s] = k as u32;
        }
        let mut children = Vec::with_capacity(kids.len());
        let mut ordered = Vec::with_capacity(ns);
        for &s in &sched {
            let mut f = fronts[s].clone();
            let c0 = children.len();
            children.extend(kids[count[s]..count[s + 1]].iter().map(|&c| at[c as usize]));
            f.children = c0..children.len();
            ordered.push(f);
        }
        let peak_stack = (0..ns)
            .filter(|&s| parent[s] == u32::MAX)
            .map(|s| peak[s])
            .max()
            .unwrap_or(0);
        let mut tree = Self {
            nr,
            nk: n - nr,
            split: ns > 0 && start[ns] > nr,
            fronts: ordered,
            rows,
            children,
            max_order: 0,
            max_panel: 0,
            max_front: 0,
            peak_stack,
            flops: 0.0,
            flops_per_rhs: 0.0,
        };
        for f in &tree.fronts {
            let p = f.rows.len();
            tree.max_order = tree.max_order.max(f.w + p);
            tree.max_panel = tree.max_panel.max((f.w + p) * f.w.min(PANEL));
            tree.max_front = tree.max_front.max(f.front);
            tree.flops += front_flops(f, p, 0);
            tree.flops_per_rhs += front_flops(f, p, 1) - front_flops(f, p, 0);
        }
        Ok(tree)
    }

    /// The update rows of front `t` (schedule position).
    pub(super) fn rows_of(&self, t: usize) -> &[u32] {
        &self.rows[self.fronts[t].rows.clone()]
    }

    /// The schedule positions of front `t`'s children with a contribution block.
    pub(super) fn children_of(&self, t: usize) -> &[u32] {
        &self.children[self.fronts[t].children.clone()]
    }

    /// Entries on the stack after the first `done` fronts of the schedule.
    pub(super) fn stack_after(&self, done: usize) -> usize {
        let mut len = 0usize;
        for f in &self.fronts[..done] {
            len = len - f.children_len + f.cb;
        }
        len
    }
}

/// Floating-point operations of front `f` with `p` update rows and `nrhs` right-hand
/// sides: the Cholesky factor of the pivots `w³/3`, the solve for the rows below `p w²`,
/// two per pivot for each updated entry (travelling block and kept lower triangle), and
/// `w² + 2 p w` per right-hand side.
pub(super) fn front_flops(f: &Front, p: usize, nrhs: usize) -> f64 {
    let (w, pf) = (f.w as f64, p as f64);
    let kept = (p - f.r) as f64;
    w * w * w / 3.0
        + pf * w * w
        + 2.0 * w * (f.cb as f64 + kept * (kept + 1.0) / 2.0)
        + nrhs as f64 * (w * w + 2.0 * pf * w)
}

/// Entries of the buffer of the updates' products for fronts of order up to `order` and
/// `nrhs` right-hand sides: `order` rows, as many columns as a panel has (at most
/// [`PANEL`], at most `order`, or the right-hand sides carried at once).
pub(super) fn update_buffer(order: usize, nrhs: usize) -> usize {
    order * PANEL.min(order.max(nrhs))
}

/// The assembly-tree property of the supernodes' `fronts` (update rows in `rows`, each
/// one's `parent` or `u32::MAX` for a root, `start` the supernodes' first columns): every
/// update row of a child outside its parent's own columns is a row of the parent's front.
///
/// # Errors
/// [`Error::Factorisation`] naming the first row that is not (an internal error of the
/// symbolic analysis).
fn check_assembly_tree(
    fronts: &[Front],
    rows: &[u32],
    parent: &[u32],
    start: &[usize],
) -> Result<()> {
    for s in 0..fronts.len() {
        let t = parent[s];
        if t == u32::MAX {
            continue;
        }
        let t = t as usize;
        let (pc0, pc1) = (start[t], start[t + 1]);
        let mut theirs = rows[fronts[t].rows.clone()].iter().peekable();
        for &g in &rows[fronts[s].rows.clone()] {
            let g = g as usize;
            if (pc0..pc1).contains(&g) {
                continue;
            }
            while theirs.next_if(|&&h| (h as usize) < g).is_some() {}
            if theirs.peek().map(|&&h| h as usize) != Some(g) {
                return Err(Error::Factorisation(format!(
                    "internal: row {g} of supernode {s} is not in its parent {t}'s front"
                )));
            }
        }
    }
    Ok(())
}
