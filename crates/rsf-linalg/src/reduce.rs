//! Work over rows on several threads with the bits of one thread: sums whose per-row
//! terms are computed in parallel and added in one fixed order, and row-by-row writes of
//! node-major vectors.

use rayon::prelude::*;

use crate::parallelism::Parallelism;

/// Rows below which [`ordered_sum`] stays on the calling thread.
pub const SUM_PARALLEL_MIN: usize = 2048;

/// `Σ_i Σ_c t_i[c]` over the rows `i < rows` with `term(i) = Some(t_i)`, added in increasing
/// `i`, then `c` — the bits of the loop
/// `for i in 0..rows { if let Some(t) = term(i) { for c in 0..K { total += t[c] } } }`,
/// which is what runs on one thread or below [`SUM_PARALLEL_MIN`] rows.
///
/// With `par.threads() > 1` the terms (the expensive part: a row of a matrix each) are
/// computed on at most that many threads, in contiguous ranges of rows, and stored in
/// `scratch` (resized to `rows` on first use; kept by the caller, so repeated sums
/// allocate nothing); the calling thread then adds them in the order above.
pub fn ordered_sum<const K: usize, F>(
    rows: usize,
    par: Parallelism,
    scratch: &mut Vec<Option<[f64; K]>>,
    term: F,
) -> f64
where
    F: Fn(usize) -> Option<[f64; K]> + Sync,
{
    let add = |total: &mut f64, t: &[f64; K]| {
        for v in t {
            *total += v;
        }
    };
    let mut total = 0.0;
    let threads = par.threads();
    if threads > 1 && rows >= SUM_PARALLEL_MIN {
        scratch.resize(rows, None);
        let chunk = rows.div_ceil(threads);
        scratch[..rows]
            .par_chunks_mut(chunk)
            .enumerate()
            .for_each(|(k, out)| {
                for (j, o) in out.iter_mut().enumerate() {
                    *o = term(k * chunk + j);
                }
            });
        for t in scratch[..rows].iter().flatten() {
            add(&mut total, t);
        }
    } else {
        for i in 0..rows {
            if let Some(t) = term(i) {
                add(&mut total, &t);
            }
        }
    }
    total
}

/// Calls `row(p, out)` for every node `p` of the node-major vector `v` (`out`: its `D`
/// entries), in at most `par.threads()` contiguous ranges of nodes, on one thread below
/// `min_nodes` nodes. Each node's values are computed by one call, so the result has the
/// same bits for every thread count.
pub fn for_node_rows<const D: usize>(
    v: &mut [f64],
    (par, min_nodes): (Parallelism, usize),
    row: impl Fn(usize, &mut [f64]) + Sync,
) {
    let nodes = v.len() / D;
    let threads = if nodes >= min_nodes {
        par.threads().min(nodes)
    } else {
        1
    };
    let chunk = nodes.div_ceil(threads).max(1);
    let run = |(k, out): (usize, &mut [f64])| {
        for (j, o) in out.chunks_exact_mut(D).enumerate() {
            row(k * chunk + j, o);
        }
    };
    if threads > 1 {
        v.par_chunks_mut(D * chunk).enumerate().for_each(run);
    } else {
        v.chunks_mut(D * chunk).enumerate().for_each(run);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Terms of very different magnitudes, so that any other order of addition rounds
    /// differently.
    fn term(i: usize) -> Option<[f64; 2]> {
        (i % 7 != 3).then(|| {
            let x = (i as f64 * 0.618_033_988_75).fract() - 0.5;
            [x * 10f64.powi((i % 23) as i32 - 11), 1.0 / (1.0 + i as f64)]
        })
    }

    #[test]
    fn the_same_bits_as_the_sequential_loop_on_any_thread_count() {
        let rows = 3 * SUM_PARALLEL_MIN + 17;
        let mut sequential = 0.0;
        for i in 0..rows {
            if let Some(t) = term(i) {
                for v in t {
                    sequential += v;
                }
            }
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .expect("pool");
        pool.install(|| {
            for threads in [1, 2, 3, 4] {
                let mut scratch = Vec::new();
                for _ in 0..2 {
                    let s = ordered_sum(rows, Parallelism::rayon(threads), &mut scratch, term);
                    assert_eq!(s.to_bits(), sequential.to_bits(), "{threads} threads");
                }
            }
        });
        // A pairwise sum rounds differently: the test can tell orders apart.
        let pairwise: f64 = (0..rows)
            .filter_map(term)
            .map(|t| t[0] + t[1])
            .collect::<Vec<_>>()
            .chunks(2)
            .map(|c| c.iter().sum::<f64>())
            .sum();
        assert_ne!(pairwise.to_bits(), sequential.to_bits());
    }
}
