//! The energy norm on the interface: `N = Zᵀ E Z` for the discrete harmonic extension
//! `Z = [−A_RR⁻¹ A_RF; I]` (docs/math.md §8), by column blocks of backward sweeps.

use super::options::HARMONIC_BLOCK;
use super::partial_cholesky::PartialCholesky;

use super::dense::{symmetric_part, symmetric_product};
use faer::MatRef;

use rsf_linalg::Csc;

/// `E` restricted to the free dofs in elimination order (rows and columns): CSC column
/// pointers, row indices and values.
type EnergyInOrder = (Vec<usize>, Vec<usize>, Vec<f64>);

/// `N = Zᵀ E Z` on the interface for `Z = [−A_RR⁻¹ A_RF; I]` (elimination order), dense
/// column-major `|F| × |F|`: with `store_extension` by [`stored_extension`] (`Z` and `E Z`
/// held whole), else by [`by_blocks`] (memory `O(n)` per block and thread).
pub(super) fn harmonic_energy(
    factor: &PartialCholesky,
    e: &Csc,
    order: &[usize],
    pos: &[usize],
    store_extension: bool,
) -> Vec<f64> {
    let energy = energy_in_order(e, order, pos);
    if store_extension {
        stored_extension(factor, &energy)
    } else {
        by_blocks(factor, &energy)
    }
}

/// `N` computed in column blocks: a backward sweep with right-hand sides `[0; e_f]` gives
/// the columns of `Z`, then `E Z` by sparse products and `Zᵀ (E Z)` by a dense product.
fn stored_extension(factor: &PartialCholesky, energy: &EnergyInOrder) -> Vec<f64> {
    use rayon::prelude::*;
    let (n, nr) = (factor.n, factor.nr);
    let nf = n - nr;
    // Columns of Z: backward sweeps of [0; e_f], HARMONIC_BLOCK right-hand sides at a time
    // (one pass over the factor per block; each column's arithmetic is that of a single
    // sweep, so the result depends neither on the blocking nor on the threads). The blocks
    // go in contiguous groups to the factor's threads for large interiors only: for small
    // ones waking the pool costs more than the sweeps (and a τ change of an adaptive run
    // rebuilds this set-up).
    //
    // The block's columns of W = E Z follow from the same rows: the block is stored by
    // rows (r values of a row side by side), so W's rows are sums of scaled rows of Z,
    // `W_i += E_ik Z_k` over k in increasing order — contiguous, vectorised updates whose
    // every entry adds the same terms in the same order as a column-by-column product.
    let tasks = factor.interior_par().threads();
    let mut z = vec![0.0; n * nf];
    let mut w = vec![0.0; n * nf];
    let z_block = |(rows, wrows, tmp): &mut (Vec<f64>, Vec<f64>, Vec<f64>),
                   (b, (zb, wb)): (usize, (&mut [f64], &mut [f64]))| {
        let r = zb.len() / n;
        extension_rows(factor, energy, b * HARMONIC_BLOCK, r, rows, wrows, tmp);
        for (k, (zcol, wcol)) in zb.chunks_mut(n).zip(wb.chunks_mut(n)).enumerate() {
            for (i, (zi, wi)) in zcol.iter_mut().zip(wcol.iter_mut()).enumerate() {
                *zi = rows[i * r + k];
                *wi = wrows[i * r + k];
            }
        }
    };
    if n > 0 && nf > 0 {
        // At most `tasks` groups of `per` blocks each, one task per group.
        let per = nf.div_ceil(HARMONIC_BLOCK).div_ceil(tasks);
        let group = |(g, (zg, wg)): (usize, (&mut [f64], &mut [f64]))| {
            let mut scratch = (Vec::new(), Vec::new(), Vec::new());
            zg.chunks_mut(n * HARMONIC_BLOCK)
                .zip(wg.chunks_mut(n * HARMONIC_BLOCK))
                .enumerate()
                .for_each(|(b, c)| z_block(&mut scratch, (g * per + b, c)));
        };
        if tasks > 1 {
            z.par_chunks_mut(per * n * HARMONIC_BLOCK)
                .zip(w.par_chunks_mut(per * n * HARMONIC_BLOCK))
                .enumerate()
                .for_each(group);
        } else {
            group((0, (&mut z[..], &mut w[..])));
        }
    }
    let zm = MatRef::from_column_major_slice(&z, n, nf);
    let wm = MatRef::from_column_major_slice(&w, n, nf);
    symmetric_product(zm.transpose(), wm)
}

/// `E` restricted to the free dofs in elimination order (rows and columns), CSC arrays.
fn energy_in_order(e: &Csc, order: &[usize], pos: &[usize]) -> EnergyInOrder {
    let mut e_ptr = Vec::with_capacity(order.len() + 1);
    let mut e_rows = Vec::new();
    let mut e_vals = Vec::new();
    e_ptr.push(0);
    for &j in order {
        let (rows, vals) = e.col(j);
        for (&i, &v) in rows.iter().zip(vals) {
            if pos[i] != usize::MAX {
                e_rows.push(pos[i]);
                e_vals.push(v);
            }
        }
        e_ptr.push(e_rows.len());
    }
    (e_ptr, e_rows, e_vals)
}

/// The columns `f0 .. f0 + r` of the harmonic extension `Z` (`rows`) and of `E Z`
/// (`wrows`), both row-major `n × r` in elimination order: one backward sweep of
/// `[0; e_f]` for the `r` right-hand sides, then `W_i += E_ik Z_k` over `k` in increasing
/// order (contiguous, vectorised updates; each entry adds the same terms in the same order
/// as a column-by-column product).
#[expect(
    clippy::too_many_arguments,
    reason = "a hot kernel: the factor, the energy matrix, the column block and three scratch buffers reused across blocks"
)]
fn extension_rows(
    factor: &PartialCholesky,
    (e_ptr, e_rows, e_vals): &EnergyInOrder,
    f0: usize,
    r: usize,
    rows: &mut Vec<f64>,
    wrows: &mut Vec<f64>,
    tmp: &mut Vec<f64>,
) {
    let (n, nr) = (factor.n, factor.nr);
    rows.clear();
    rows.resize(n * r, 0.0);
    for k in 0..r {
        rows[(nr + f0 + k) * r + k] = 1.0;
    }
    factor.backward_interior_rows(rows, r, tmp);
    wrows.clear();
    wrows.resize(n * r, 0.0);
    for kj in 0..n {
        let zk = &rows[kj * r..kj * r + r];
        for k in e_ptr[kj]..e_ptr[kj + 1] {
            let (i, ev) = (e_rows[k], e_vals[k]);
            for (wv, &zv) in wrows[i * r..i * r + r].iter_mut().zip(zk) {
                *wv += ev * zv;
            }
        }
    }
}

/// Scratch of one thread of [`by_blocks`].
type BlockScratch = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>, [Vec<f64>; 3]);

/// [`stored_extension`] without holding `Z` and `E Z`: per block of columns, `Z_b` by a
/// backward sweep, `W_b = E Z_b`, and `N_b = Zᵀ W_b = W_{b,F} − L_FR L_RR⁻¹ W_{b,R}` by
/// a forward sweep of each column (the condensation of a right-hand side, since
/// `Zᵀ = [−A_FR A_RR⁻¹, I]` and `A_FR A_RR⁻¹ = L_FR L_RR⁻¹`). Memory `O(n)` per block and
/// thread instead of `2 n |F|`, on at most two threads whatever the factor's parallelism
/// (what [`DirectMemory`] counts); the same `N` up to the order of the sums (the dense
/// product `Zᵀ W` adds over all rows, the sweep over the factor's columns). Deterministic:
/// each column's arithmetic is fixed, whatever the blocking and the threads.
fn by_blocks(factor: &PartialCholesky, energy: &EnergyInOrder) -> Vec<f64> {
    use rayon::prelude::*;
    let (n, nr) = (factor.n, factor.nr);
    let nf = n - nr;
    let mut nmat = vec![0.0; nf * nf];
    let block = |(rows, wrows, tmp, col, fwd): &mut BlockScratch, (b, nb): (usize, &mut [f64])| {
        let r = nb.len() / nf;
        extension_rows(factor, energy, b * HARMONIC_BLOCK, r, rows, wrows, tmp);
        for (k, ncol) in nb.chunks_mut(nf).enumerate() {
            col.clear();
            col.extend((0..n).map(|i| wrows[i * r + k]));
            factor.forward_interior_with(col, fwd);
            ncol.copy_from_slice(&col[nr..]);
        }
    };
    let init = || -> BlockScratch {
        let v = Vec::new;
        (v(), v(), v(), v(), [v(), v(), v()])
    };
    if n > 0 && nf > 0 {
        // At most two groups of `per` blocks each (the memory estimate's two threads).
        let tasks = factor.interior_par().threads().min(2);
        let per = nf.div_ceil(HARMONIC_BLOCK).div_ceil(tasks);
        let group = |(g, ng): (usize, &mut [f64])| {
            let mut scratch = init();
            ng.chunks_mut(nf * HARMONIC_BLOCK)
                .enumerate()
                .for_each(|(b, c)| block(&mut scratch, (g * per + b, c)));
        };
        if tasks > 1 {
            nmat.par_chunks_mut(per * nf * HARMONIC_BLOCK)
                .enumerate()
                .for_each(group);
        } else {
            group((0, &mut nmat[..]));
        }
    }
    symmetric_part(nf, |i, j| nmat[j * nf + i])
}
