//! Low-rank compression of one admissible block: truncated SVD, adaptive cross
//! approximation (ACA) with partial pivoting, and recompression (docs/math.md §13.3).
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
fn truncation_rank(sigma: &[f64], eps: f64) -> usize {
    let total: f64 = sigma.iter().map(|s| s * s).sum();
    let bound = eps * eps * total;
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
    k
}

/// Truncated SVD of a dense block to relative Frobenius accuracy `eps`; `None` if the
/// truncated factors would store no fewer numbers than the block.
pub(crate) fn svd_truncate(block: MatRef<'_, f64>, eps: f64) -> Result<Option<LowRank>, Error> {
    let (m, n) = (block.nrows(), block.ncols());
    let svd = block
        .thin_svd()
        .map_err(|_| Error::Svd { rows: m, cols: n })?;
    let s = svd.S().column_vector();
    let sigma: Vec<f64> = (0..s.nrows()).map(|i| s[i]).collect();
    let k = truncation_rank(&sigma, eps);
    if k > max_useful_rank(m, n) {
        return Ok(None);
    }
    let (uu, vv) = (svd.U(), svd.V());
    let mut u = Vec::with_capacity(m * k);
    let mut v = Vec::with_capacity(n * k);
    for l in 0..k {
        u.extend((0..m).map(|i| uu[(i, l)] * sigma[l]));
        v.extend((0..n).map(|j| vv[(j, l)]));
    }
    Ok(Some(LowRank { u, v, rank: k }))
}

/// Recompression of `U Vᵀ` (`m × k`, `n × k`) to relative accuracy `eps` of its own norm:
/// `U = Q_u R_u`, `V = Q_v R_v`, SVD of the small `R_u R_vᵀ`, truncation.
pub(crate) fn recompress(lr: &LowRank, m: usize, n: usize, eps: f64) -> Result<LowRank, Error> {
    let k = lr.rank;
    if k == 0 {
        return Ok(lr.clone());
    }
    let u = MatRef::from_column_major_slice(&lr.u, m, k);
    let v = MatRef::from_column_major_slice(&lr.v, n, k);
    let (qru, qrv) = (u.qr(), v.qr());
    let (qu, qv) = (qru.compute_thin_Q(), qrv.compute_thin_Q());
    let (ru, rv) = (qru.thin_R(), qrv.thin_R());
    let mut core = Mat::<f64>::zeros(ru.nrows(), rv.nrows());
    matmul(&mut core, Accum::Replace, ru, rv.transpose(), 1.0, Par::Seq);
    let svd = core.thin_svd().map_err(|_| Error::Svd {
        rows: core.nrows(),
        cols: core.ncols(),
    })?;
    let s = svd.S().column_vector();
    let sigma: Vec<f64> = (0..s.nrows()).map(|i| s[i]).collect();
    let r = truncation_rank(&sigma, eps);
    let mut w = Mat::<f64>::zeros(ru.nrows(), r);
    let mut z = Mat::<f64>::zeros(rv.nrows(), r);
    for l in 0..r {
        for i in 0..ru.nrows() {
            w[(i, l)] = svd.U()[(i, l)] * sigma[l];
        }
        for j in 0..rv.nrows() {
            z[(j, l)] = svd.V()[(j, l)];
        }
    }
    let mut nu = Mat::<f64>::zeros(m, r);
    let mut nv = Mat::<f64>::zeros(n, r);
    matmul(&mut nu, Accum::Replace, &qu, &w, 1.0, Par::Seq);
    matmul(&mut nv, Accum::Replace, &qv, &z, 1.0, Par::Seq);
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

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Adaptive cross approximation with partial pivoting of the `m × n` block whose entries
/// `entry(i, j)` returns (local indices), stopped when the newest cross `u vᵀ` has
/// `‖u‖‖v‖ ≤ eps ‖Σ u_l v_lᵀ‖_F`. Evaluates `O(k (m + n))` entries. `None` if the rank
/// grows past the point where the block is cheaper stored dense.
pub(crate) fn aca(
    m: usize,
    n: usize,
    entry: &mut dyn FnMut(usize, usize) -> Result<f64, Error>,
    eps: f64,
) -> Result<Option<LowRank>, Error> {
    let kmax = max_useful_rank(m, n);
    let mut us: Vec<Vec<f64>> = Vec::new();
    let mut vs: Vec<Vec<f64>> = Vec::new();
    let mut used = vec![false; m];
    let mut norm2 = 0.0_f64;
    let mut i = 0;
    let mut r = vec![0.0; n];
    loop {
        used[i] = true;
        for (j, rj) in r.iter_mut().enumerate() {
            *rj = entry(i, j)?;
        }
        for (ul, vl) in us.iter().zip(&vs) {
            let a = ul[i];
            for (rj, vj) in r.iter_mut().zip(vl) {
                *rj -= a * vj;
            }
        }
        let (jp, piv) = r
            .iter()
            .enumerate()
            .fold((0, 0.0_f64), |(bj, bv), (j, &x)| {
                if x.abs() > bv.abs() {
                    (j, x)
                } else {
                    (bj, bv)
                }
            });
        if piv == 0.0 {
            // This row is reproduced exactly: try the next unused row.
            match used.iter().position(|&u| !u) {
                Some(next) => {
                    i = next;
                    continue;
                }
                None => break,
            }
        }
        if us.len() >= kmax {
            return Ok(None);
        }
        let v: Vec<f64> = r.iter().map(|x| x / piv).collect();
        let mut u = vec![0.0; m];
        for (ii, ui) in u.iter_mut().enumerate() {
            *ui = entry(ii, jp)?;
        }
        for (ul, vl) in us.iter().zip(&vs) {
            let b = vl[jp];
            for (ui, uli) in u.iter_mut().zip(ul) {
                *ui -= b * uli;
            }
        }
        let (nu2, nv2) = (dot(&u, &u), dot(&v, &v));
        let cross: f64 = us
            .iter()
            .zip(&vs)
            .map(|(ul, vl)| dot(ul, &u) * dot(vl, &v))
            .sum();
        norm2 = (norm2 + 2.0 * cross + nu2 * nv2).max(0.0);
        let next = u.iter().enumerate().filter(|(ii, _)| !used[*ii]).fold(
            None,
            |best: Option<(usize, f64)>, (ii, &x)| match best {
                Some((_, bx)) if bx >= x.abs() => best,
                _ => Some((ii, x.abs())),
            },
        );
        us.push(u);
        vs.push(v);
        if (nu2 * nv2).sqrt() <= eps * norm2.sqrt() {
            break;
        }
        match next {
            Some((ii, _)) => i = ii,
            None => break,
        }
    }
    let rank = us.len();
    Ok(Some(LowRank {
        u: us.concat(),
        v: vs.concat(),
        rank,
    }))
}
