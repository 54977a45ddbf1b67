//! The symmetric result stored as the rows of its lower triangle, and the one dense update
//! the elimination makes of it (and of its contribution blocks): `S −= X Xᵀ` in panels.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch, LltError};
use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::reborrow::ReborrowMut;
use faer::{Accum, MatMut, MatRef, Par};

use crate::error::{Error, Result};

/// Width of a panel: the pivot columns factored at once and the rows (columns) of each
/// product of the updates (faer's dense product with `Par::Seq`, then subtracted entry by
/// entry). Measured on the 40³ elasticity box with nested dissection (docs/three-d.md):
/// 128 cost 23.4 s of CPU against 20.9 s with 256.
pub(super) const PANEL: usize = 256;

/// A symmetric `m × m` matrix stored as the rows of its lower triangle ("packed rows"):
/// row `i` holds the entries `(i, 0), …, (i, i)` at `i(i + 1)/2 ..= i(i + 1)/2 + i`,
/// `m(m + 1)/2` f64 in all (half of a dense copy). The layout of
/// [`SchurEntries`](crate::SchurEntries)' factor rows; rows and columns in the order of
/// the dofs they are given with (e.g. [`KeptSchur::kept_dofs`](crate::KeptSchur::kept_dofs)).
#[derive(Clone, PartialEq)]
pub struct PackedSymmetric {
    m: usize,
    rows: Vec<f64>,
}

impl std::fmt::Debug for PackedSymmetric {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PackedSymmetric")
            .field("dim", &self.m)
            .finish_non_exhaustive()
    }
}

/// Entries of the packed rows of an `m × m` symmetric matrix, if it fits in `usize` bytes.
pub(super) fn packed_len(m: usize) -> Option<usize> {
    let len = m.checked_mul(m.checked_add(1)?)? / 2;
    len.checked_mul(8)?;
    Some(len)
}

/// A zeroed vector of `len` f64 for `what`, allocated fallibly.
///
/// # Errors
/// [`Error::OutOfMemory`] if the system refuses it.
pub(super) fn try_zeros(len: usize, what: &'static str) -> Result<Vec<f64>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| Error::OutOfMemory {
        what,
        bytes: len.saturating_mul(8),
    })?;
    v.resize(len, 0.0);
    Ok(v)
}

impl PackedSymmetric {
    /// The zero matrix of dimension `m`, allocated fallibly.
    ///
    /// # Errors
    /// [`Error::TooLarge`] if `m(m + 1)/2` f64 overflow the address space,
    /// [`Error::OutOfMemory`] if the allocation fails.
    pub(super) fn zeros(m: usize) -> Result<Self> {
        let len = packed_len(m).ok_or(Error::TooLarge {
            what: "the packed Schur complement",
            bytes: (m as u128) * (m as u128 + 1) * 4,
            limit: usize::MAX,
        })?;
        Ok(Self {
            m,
            rows: try_zeros(len, "the packed Schur complement")?,
        })
    }

    /// From packed rows (`rows.len() == m(m + 1)/2`, checked by the caller).
    pub(super) fn from_rows(m: usize, rows: Vec<f64>) -> Self {
        debug_assert_eq!(Some(rows.len()), packed_len(m));
        Self { m, rows }
    }

    /// The dimension `m`.
    pub fn dim(&self) -> usize {
        self.m
    }

    /// Bytes held (8 per stored f64, `4 m (m + 1)`).
    pub fn bytes(&self) -> usize {
        8 * self.rows.len()
    }

    /// Entry `(i, j)` (the same as `(j, i)`).
    ///
    /// # Panics
    /// If `i` or `j` is not below [`dim`](Self::dim).
    #[inline]
    pub fn entry(&self, i: usize, j: usize) -> f64 {
        assert!(
            i < self.m && j < self.m,
            "entry ({i}, {j}) of a {0} × {0} matrix",
            self.m
        );
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        self.rows[i * (i + 1) / 2 + j]
    }

    /// Row `i` of the lower triangle: the entries `(i, 0), …, (i, i)`.
    ///
    /// # Panics
    /// If `i` is not below [`dim`](Self::dim).
    pub fn row(&self, i: usize) -> &[f64] {
        assert!(i < self.m, "row {i} of a {0} × {0} matrix", self.m);
        let start = i * (i + 1) / 2;
        &self.rows[start..start + i + 1]
    }

    /// All packed rows (`m(m + 1)/2` f64).
    pub fn packed_rows(&self) -> &[f64] {
        &self.rows
    }

    /// The packed rows, by value.
    pub fn into_packed_rows(self) -> Vec<f64> {
        self.rows
    }

    /// The full matrix, dense column-major (`m²` f64; entry `(i, j)` at `j m + i`).
    pub fn to_dense(&self) -> Vec<f64> {
        let m = self.m;
        let mut out = vec![0.0; m * m];
        for i in 0..m {
            for (j, &v) in self.row(i).iter().enumerate() {
                out[j * m + i] = v;
                out[i * m + j] = v;
            }
        }
        out
    }

    pub(super) fn rows_mut(&mut self) -> &mut Vec<f64> {
        &mut self.rows
    }

    /// Keeps the leading `k × k` block (a prefix of the packed rows).
    pub(super) fn truncate(&mut self, k: usize) {
        debug_assert!(k <= self.m);
        self.rows.truncate(k * (k + 1) / 2);
        self.rows.shrink_to_fit();
        self.m = k;
    }
}

/// `S[idx_a, idx_b] −= (X Xᵀ)_ab` for `a ≥ b` (so `idx_a ≥ idx_b`: `idx` increasing), with
/// `S` in packed rows and `X` of `idx.len()` rows: panels of [`PANEL`] rows `a`, each
/// product `X[..a₁] X[panel]ᵀ` by faer (one thread) into `tmp` (at least
/// `idx.len() · PANEL` f64), then subtracted in a fixed order.
pub(super) fn sub_gram_rows(s: &mut [f64], idx: &[u32], x: MatRef<'_, f64>, tmp: &mut [f64]) {
    let q = idx.len();
    debug_assert_eq!(x.nrows(), q);
    if x.ncols() == 0 {
        return;
    }
    for a0 in (0..q).step_by(PANEL) {
        let a1 = (a0 + PANEL).min(q);
        let nb = a1 - a0;
        // T (a₁ × nb) = X[..a₁] X[a₀..a₁]ᵀ: column a − a₀ holds the products of row a
        // (only its rows b ≤ a are needed: the diagonal block is upper triangular).
        let t = &mut tmp[..a1 * nb];
        let mut tm = MatMut::from_column_major_slice_mut(t, a1, nb);
        let (above, diag) = tm.rb_mut().split_at_row_mut(a0);
        let right = x.subrows(a0, nb).transpose();
        matmul(
            above,
            Accum::Replace,
            x.subrows(0, a0),
            right,
            1.0,
            Par::Seq,
        );
        triangular::matmul(
            diag,
            BlockStructure::TriangularUpper,
            Accum::Replace,
            x.subrows(a0, nb),
            BlockStructure::Rectangular,
            right,
            BlockStructure::Rectangular,
            1.0,
            Par::Seq,
        );
        for a in a0..a1 {
            let row = idx[a] as usize;
            let base = row * (row + 1) / 2;
            let col = &t[(a - a0) * a1..(a - a0) * a1 + a + 1];
            for (&j, v) in idx[..=a].iter().zip(col) {
                s[base + j as usize] -= v;
            }
        }
    }
}

/// Offset of column `j` in a contribution block stored as packed columns of the lower
/// triangle of a `p × p` matrix (column `j` holds rows `j..p`).
#[inline]
pub(super) fn col_start(j: usize, p: usize) -> usize {
    j * p - j * j.saturating_sub(1) / 2
}

/// Entries of the first `r` packed columns of a `p × p` lower triangle.
#[inline]
pub(super) fn trapezoid_len(r: usize, p: usize) -> usize {
    col_start(r, p)
}

/// `C[a, b] −= (X Xᵀ)_ab` for `a ≥ b`, `b < r`, with `C` the first `r` packed columns of
/// the lower triangle of a `p × p` matrix ([`col_start`]) and `X` of `p` rows: panels of
/// [`PANEL`] columns, each product by faer (one thread) into `tmp` (at least `p · PANEL`).
pub(super) fn sub_gram_cols(c: &mut [f64], r: usize, x: MatRef<'_, f64>, tmp: &mut [f64]) {
    let p = x.nrows();
    if x.ncols() == 0 {
        return;
    }
    for j0 in (0..r).step_by(PANEL) {
        let j1 = (j0 + PANEL).min(r);
        let nb = j1 - j0;
        let h = p - j0;
        // T (h × nb) = X[j₀..] X[j₀..j₁]ᵀ: column j − j₀ from row j − j₀ on is column j's
        // (the diagonal block is lower triangular).
        let t = &mut tmp[..h * nb];
        let mut tm = MatMut::from_column_major_slice_mut(t, h, nb);
        let (diag, below) = tm.rb_mut().split_at_row_mut(nb);
        let right = x.subrows(j0, nb).transpose();
        triangular::matmul(
            diag,
            BlockStructure::TriangularLower,
            Accum::Replace,
            x.subrows(j0, nb),
            BlockStructure::Rectangular,
            right,
            BlockStructure::Rectangular,
            1.0,
            Par::Seq,
        );
        matmul(
            below,
            Accum::Replace,
            x.subrows(j1, p - j1),
            right,
            1.0,
            Par::Seq,
        );
        for j in j0..j1 {
            let src = &t[(j - j0) * h + (j - j0)..(j - j0 + 1) * h];
            let dst = &mut c[col_start(j, p)..col_start(j, p) + p - j];
            for (d, v) in dst.iter_mut().zip(src) {
                *d -= v;
            }
        }
    }
}

/// Scratch of [`cholesky`] for blocks of up to `m` rows, allocated fallibly.
///
/// # Errors
/// [`Error::OutOfMemory`] if the allocation fails.
pub(super) fn cholesky_scratch(m: usize) -> Result<MemBuffer> {
    MemBuffer::try_new(cholesky_in_place_scratch::<f64>(
        m,
        Par::Seq,
        Default::default(),
    ))
    .map_err(|_| Error::OutOfMemory {
        what: "a Cholesky factor's scratch",
        bytes: 8 * m,
    })
}

/// The lower Cholesky factor of the SPD block `l` (lower triangle read) in place, by faer
/// on one thread; `Err(k)` if pivot `k` is not positive.
pub(super) fn cholesky(
    l: MatMut<'_, f64>,
    scratch: &mut MemBuffer,
) -> std::result::Result<(), usize> {
    cholesky_in_place(
        l,
        Default::default(),
        Par::Seq,
        MemStack::new(scratch),
        Default::default(),
    )
    .map(|_| ())
    .map_err(|LltError::NonPositivePivot { index }| index)
}
