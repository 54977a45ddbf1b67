//! Unit tests of the pieces: the packed layouts and their updates, the schedule.

use faer::Mat;

use super::packed::{col_start, sub_gram_cols, sub_gram_rows, trapezoid_len, PackedSymmetric};
use super::SchurOnly;
use crate::InteriorOrdering;

/// A deterministic pseudo-random matrix (`rows × cols`).
fn pseudo(rows: usize, cols: usize, seed: u64) -> Mat<f64> {
    let mut state = seed;
    Mat::from_fn(rows, cols, |_, _| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    })
}

/// `sub_gram_rows` on scattered rows of a packed matrix and `sub_gram_cols` on a
/// trapezoid subtract `X Xᵀ` exactly where a plain triple loop does (to round-off), over
/// more rows than one panel, and touch nothing else.
#[test]
fn panel_updates_equal_the_plain_products() {
    let (q, w) = (300, 7);
    let x = pseudo(q, w, 3);
    let gram = |a: usize, b: usize| (0..w).map(|t| x[(a, t)] * x[(b, t)]).sum::<f64>();
    // Rows idx (increasing, with gaps) of a 700 × 700 packed matrix.
    let m = 700;
    let idx: Vec<u32> = (0..q as u32).map(|a| 2 * a + (a % 2)).collect();
    let mut s = PackedSymmetric::zeros(m).unwrap();
    let mut tmp = vec![0.0; q * super::packed::PANEL];
    sub_gram_rows(s.rows_mut(), &idx, x.as_ref(), &mut tmp);
    let mut touched = vec![false; s.packed_rows().len()];
    for a in 0..q {
        for b in 0..=a {
            let (i, j) = (idx[a] as usize, idx[b] as usize);
            let k = i * (i + 1) / 2 + j;
            touched[k] = true;
            let want = -gram(a, b);
            assert!((s.packed_rows()[k] - want).abs() < 1e-14, "({a}, {b})");
        }
    }
    for (k, &t) in touched.iter().enumerate() {
        if !t {
            assert_eq!(s.packed_rows()[k], 0.0, "{k}");
        }
    }
    // The first r packed columns of the lower triangle of q × q.
    let r = 170;
    let mut c = vec![0.0; trapezoid_len(r, q)];
    sub_gram_cols(&mut c, r, x.as_ref(), &mut tmp);
    for j in 0..r {
        for i in j..q {
            let v = c[col_start(j, q) + i - j];
            assert!((v + gram(i, j)).abs() < 1e-14, "({i}, {j})");
        }
    }
    assert_eq!(col_start(r, q), c.len());
    // Packed rows: entry, row, dense.
    let d = s.to_dense();
    for i in [0, 5, 699] {
        for j in [0, 3, 699] {
            assert_eq!(s.entry(i, j), d[j * m + i]);
            assert_eq!(s.entry(i, j), s.entry(j, i));
        }
        assert_eq!(s.row(i).len(), i + 1);
    }
}

/// The schedule is a postorder (every child before its parent, each front's children the
/// top of the stack), the stack's size (a front on top of its children's blocks, which it
/// replaces by its own) follows the blocks pushed and popped to the peak
/// the symbolic pass planned, and it ends empty.
#[test]
fn schedule_is_a_postorder_with_the_planned_peak() {
    let m = 24;
    let a = crate::partial_cholesky::tests::grid(m);
    let n = a.nrows;
    let fixed = vec![false; n];
    let blocks: Vec<usize> = (0..m).map(|j| m / 2 + m * j).collect();
    let faer_a = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(
        n,
        n,
        &(0..n)
            .flat_map(|j| {
                let (rows, vals) = a.col(j);
                rows.iter()
                    .zip(vals)
                    .map(move |(&i, &v)| faer::sparse::Triplet::new(i, j, v))
                    .collect::<Vec<_>>()
            })
            .collect::<Vec<_>>(),
    )
    .unwrap();
    let elim =
        SchurOnly::<1>::new(faer_a.as_ref(), &fixed, &blocks, &[], InteriorOrdering::Amd).unwrap();
    let tree = &elim.tree;
    let mut stack: Vec<usize> = Vec::new();
    let mut len = 0;
    let mut peak = 0;
    for (t, f) in tree.fronts.iter().enumerate() {
        let kids = tree.children_of(t);
        assert!(stack.len() >= kids.len());
        let top = stack.split_off(stack.len() - kids.len());
        assert_eq!(top, kids.iter().map(|&c| c as usize).collect::<Vec<_>>());
        peak = peak.max(len + f.front);
        len = len - f.children_len + f.cb;
        assert_eq!(len, tree.stack_after(t + 1));
        if f.cb > 0 {
            stack.push(t);
        }
    }
    assert!(stack.is_empty());
    assert_eq!(len, 0);
    assert_eq!(peak, tree.peak_stack);
    assert!(peak > 0);
}

/// The 1-D chain condensed onto one node splits the supernode of the last interior column
/// (the case whose values the suite's `a_supernode_straddling_the_kept_set_is_split`
/// checks).
#[test]
fn the_chain_splits_a_supernode() {
    let chain = |n: usize, node: usize| {
        let mut t = Vec::new();
        for i in 0..n {
            t.push(faer::sparse::Triplet::new(i, i, 2.0 + 0.01 * i as f64));
            if i + 1 < n {
                t.push(faer::sparse::Triplet::new(i, i + 1, -1.0));
                t.push(faer::sparse::Triplet::new(i + 1, i, -1.0));
            }
        }
        let a = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
        let mut fixed = vec![false; n];
        fixed[0] = true;
        SchurOnly::<1>::new(a.as_ref(), &fixed, &[node], &[], InteriorOrdering::Amd)
            .unwrap()
            .tree
            .split
    };
    let splits: Vec<bool> = [(7, 3), (12, 11), (40, 20)]
        .iter()
        .map(|&(n, node)| chain(n, node))
        .collect();
    assert!(splits.iter().any(|&s| s), "{splits:?}");
}
