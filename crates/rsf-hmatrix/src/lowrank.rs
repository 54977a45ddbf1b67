//! Low-rank compression of one admissible block: truncated SVD and recompression
//! (docs/math.md §13.3); cross approximation is in `aca.rs`.
//!
//! A low-rank block `B ≈ U Vᵀ` is kept as two column-major arrays, `U` (`m × k`) and `V`
//! (`n × k`).

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};

use crate::error::Error;

/// A compressed block `U Vᵀ`, column-major factors.
#[derive(Debug, Clone)]
pub(crate) struct LowRank {
    /// `m × k`, column-major.
    pub u: Vec<f64>,
    /// `n × k`, column-major.
    pub v: Vec<f64>,
    /// The rank `k`.
    pub rank: usize,
}

/// The largest rank at which `U Vᵀ` stores fewer numbers than the dense `m × n` block.
pub(crate) fn max_useful_rank(m: usize, n: usize) -> usize {
    // k (m + n) < m n
    (m * n).saturating_sub(1).checked_div(m + n).unwrap_or(0)
}

/// The smallest `k` with `Σ_{i ≥ k} σ_i² ≤ eps² Σ_i σ_i²` (`σ` non-increasing).
pub(crate) fn truncation_rank(sigma: &[f64], eps: f64) -> usize {
    let total: f64 = sigma.iter().map(|s| s * s).sum();
    truncation_rank_below(sigma, eps * eps * total).0
}

/// The smallest `k` with `Σ_{i ≥ k} σ_i² ≤ bound` (`σ` non-increasing), and that tail.
pub(crate) fn truncation_rank_below(sigma: &[f64], bound: f64) -> (usize, f64) {
    let mut tail = 0.0;
    let mut k = sigma.len();
    // Accumulate the tail from the smallest value up (accurate sums of small numbers).
    while k > 0 {
        let next = tail + sigma[k - 1] * sigma[k - 1];
        if next > bound {
            break;
        }
        tail = next;
        k -= 1;
    }
    (k, tail)
}

/// `(U, σ, V)` of a thin SVD.
pub(crate) type ThinSvd = (Mat<f64>, Vec<f64>, Mat<f64>);

/// Thin SVD `a = U diag(σ) Vᵀ` on the calling thread (`Par::Seq`: the same bits whatever
/// the thread pool), `σ` non-increasing: `(U, σ, V)`, `U` `m × min(m, n)`, `V`
/// `n × min(m, n)`.
pub(crate) fn thin_svd_seq(a: MatRef<'_, f64>) -> Result<ThinSvd, Error> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::svd::{svd, svd_scratch, ComputeSvdVectors};
    let (m, n) = a.shape();
    let size = m.min(n);
    let mut u = Mat::<f64>::zeros(m, size);
    let mut v = Mat::<f64>::zeros(n, size);
    let mut s = faer::diag::Diag::<f64>::zeros(size);
    let thin = ComputeSvdVectors::Thin;
    let scratch = svd_scratch::<f64>(m, n, thin, thin, Par::Seq, Default::default());
    svd(
        a,
        s.as_mut(),
        Some(u.as_mut()),
        Some(v.as_mut()),
        Par::Seq,
        MemStack::new(&mut MemBuffer::new(scratch)),
        Default::default(),
    )
    .map_err(|_| Error::Svd { rows: m, cols: n })?;
    let sv = s.column_vector();
    let sigma = (0..size).map(|i| sv[i]).collect();
    Ok((u, sigma, v))
}

/// Truncated SVD of a dense block to relative Frobenius accuracy `eps`; `None` if the
/// truncated factors would store no fewer numbers than the block. On the calling thread
/// ([`thin_svd_seq`]): faer's `thin_svd()` splits its work by the size of rayon's pool,
/// which made the factors' bits depend on the machine's cores (issue 57).
pub(crate) fn svd_truncate(block: MatRef<'_, f64>, eps: f64) -> Result<Option<LowRank>, Error> {
    let (m, n) = (block.nrows(), block.ncols());
    let (uu, sigma, vv) = thin_svd_seq(block)?;
    let k = truncation_rank(&sigma, eps);
    if k > max_useful_rank(m, n) {
        return Ok(None);
    }
    let mut u = Vec::with_capacity(m * k);
    let mut v = Vec::with_capacity(n * k);
    for l in 0..k {
        u.extend((0..m).map(|i| uu[(i, l)] * sigma[l]));
        v.extend((0..n).map(|j| vv[(j, l)]));
    }
    Ok(Some(LowRank { u, v, rank: k }))
}

/// Recompression of `U Vᵀ` (`m × k`, `n × k`) to relative accuracy `eps` of its own norm:
/// orthonormal bases of both factors, `U = Q_u R_u`, `V = Q_v R_v` (from their thin SVDs,
/// `R = Σ Bᵀ`), the SVD of the small core `R_u R_vᵀ`, truncation. Every factorisation and
/// product on the calling thread on owned (aligned) matrices: the same bits whatever the
/// thread pool and the factors' addresses.
pub(crate) fn recompress(lr: &LowRank, m: usize, n: usize, eps: f64) -> Result<LowRank, Error> {
    let k = lr.rank;
    if k == 0 {
        return Ok(lr.clone());
    }
    let u = Mat::<f64>::from_fn(m, k, |i, l| lr.u[l * m + i]);
    let v = Mat::<f64>::from_fn(n, k, |j, l| lr.v[l * n + j]);
    let (qu, su, bu) = thin_svd_seq(u.as_ref())?;
    let (qv, sv, bv) = thin_svd_seq(v.as_ref())?;
    let ru = Mat::<f64>::from_fn(su.len(), k, |i, l| su[i] * bu[(l, i)]);
    let rv = Mat::<f64>::from_fn(sv.len(), k, |i, l| sv[i] * bv[(l, i)]);
    let mut core = Mat::<f64>::zeros(ru.nrows(), rv.nrows());
    matmul(
        &mut core,
        Accum::Replace,
        &ru,
        rv.transpose(),
        1.0,
        Par::Seq,
    );
    let (w, sigma, z) = thin_svd_seq(core.as_ref())?;
    let r = truncation_rank(&sigma, eps);
    let ws = Mat::<f64>::from_fn(ru.nrows(), r, |i, l| w[(i, l)] * sigma[l]);
    let zs = Mat::<f64>::from_fn(rv.nrows(), r, |j, l| z[(j, l)]);
    let mut nu = Mat::<f64>::zeros(m, r);
    let mut nv = Mat::<f64>::zeros(n, r);
    matmul(&mut nu, Accum::Replace, &qu, &ws, 1.0, Par::Seq);
    matmul(&mut nv, Accum::Replace, &qv, &zs, 1.0, Par::Seq);
    let mut out = LowRank {
        u: Vec::with_capacity(m * r),
        v: Vec::with_capacity(n * r),
        rank: r,
    };
    for l in 0..r {
        out.u.extend((0..m).map(|i| nu[(i, l)]));
        out.v.extend((0..n).map(|j| nv[(j, l)]));
    }
    Ok(out)
}
