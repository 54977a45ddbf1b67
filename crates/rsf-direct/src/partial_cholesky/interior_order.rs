//! Orders of the interior: AMD on a part, and the one-level bisection into two halves
//! and a separator.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMat;

use crate::error::{Error, Result};
use rsf_linalg::Csc;

/// A faer failure as [`Error::Factorisation`].
pub(super) fn faer_err(e: impl std::fmt::Debug) -> Error {
    Error::Factorisation(format!("{e:?}"))
}

/// Local CSC pattern (no values) of the rows/columns `idx` of `a`, and the map back.
pub(super) fn local_pattern(a: &Csc, idx: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut local = vec![usize::MAX; a.nrows];
    for (k, &i) in idx.iter().enumerate() {
        local[i] = k;
    }
    let mut col_ptr = Vec::with_capacity(idx.len() + 1);
    let mut row_idx = Vec::new();
    col_ptr.push(0);
    for &j in idx {
        let (rows, _) = a.col(j);
        row_idx.extend(rows.iter().map(|&i| local[i]).filter(|&i| i != usize::MAX));
        col_ptr.push(row_idx.len());
    }
    (col_ptr, row_idx)
}

/// Fill-reducing (AMD) order of the rows/columns `idx` of the symmetric matrix `a`:
/// returns the entries of `idx` reordered.
pub(super) fn amd_order(a: &Csc, idx: &[usize]) -> Result<Vec<usize>> {
    let n = idx.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let (col_ptr, row_idx) = local_pattern(a, idx);
    let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    let mut perm = vec![0usize; n];
    let mut perm_inv = vec![0usize; n];
    let nnz = pattern.row_idx().len();
    let mut mem =
        MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(n, nnz)).map_err(faer_err)?;
    amd::order_maybe_unsorted(
        &mut perm,
        &mut perm_inv,
        pattern.as_ref(),
        Default::default(),
        MemStack::new(&mut mem),
    )
    .map_err(faer_err)?;
    Ok(perm.iter().map(|&k| idx[k]).collect())
}

/// Splits `idx` (rows/columns of `a`) into `(R₁, R₂, C)`: `C` is the middle level of a
/// breadth-first search from a pseudo-peripheral vertex of the graph of `a` restricted to
/// `idx`, so there is no entry of `a` between `R₁` and `R₂`. Parts that are too small to
/// pay (or a disconnected graph) give empty `R₂` and `C`.
pub(super) fn bisect(a: &Csc, idx: &[usize]) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
    let n = idx.len();
    let whole = || (idx.to_vec(), Vec::new(), Vec::new());
    if n < 64 {
        return whole();
    }
    let (col_ptr, row_idx) = local_pattern(a, idx);
    let bfs = |root: usize, level: &mut Vec<usize>| -> (usize, usize) {
        level.fill(usize::MAX);
        level[root] = 0;
        let mut queue = vec![root];
        let mut head = 0;
        while head < queue.len() {
            let v = queue[head];
            head += 1;
            for &u in &row_idx[col_ptr[v]..col_ptr[v + 1]] {
                if level[u] == usize::MAX {
                    level[u] = level[v] + 1;
                    queue.push(u);
                }
            }
        }
        let last = *queue.last().expect("root");
        (queue.len(), last)
    };
    let mut level = vec![usize::MAX; n];
    let (mut reached, mut far) = bfs(0, &mut level);
    for _ in 0..3 {
        let (r, f) = bfs(far, &mut level);
        reached = r;
        if f == far {
            break;
        }
        far = f;
    }
    if reached < n {
        return whole();
    }
    let depth = level.iter().copied().max().unwrap_or(0);
    let mut count = vec![0usize; depth + 1];
    for &l in &level {
        count[l] += 1;
    }
    // The level where the cumulative count passes half.
    let mut acc = 0;
    let mut mid = 0;
    for (l, &c) in count.iter().enumerate() {
        if acc + c / 2 >= n / 2 {
            mid = l;
            break;
        }
        acc += c;
    }
    if mid == 0 || mid == depth {
        return whole();
    }
    let (mut r1, mut r2, mut c) = (Vec::new(), Vec::new(), Vec::new());
    for (k, &l) in level.iter().enumerate() {
        match l.cmp(&mid) {
            std::cmp::Ordering::Less => r1.push(idx[k]),
            std::cmp::Ordering::Greater => r2.push(idx[k]),
            std::cmp::Ordering::Equal => c.push(idx[k]),
        }
    }
    (r1, r2, c)
}
