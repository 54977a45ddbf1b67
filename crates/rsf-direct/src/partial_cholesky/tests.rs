//! Tests of the partial Cholesky factor (and the grid matrix other tests build on).

use super::*;
use rsf_nonsmooth::ProblemError;

/// 5-point Laplacian plus identity on an `m × m` grid (node `i + m j`).
pub(crate) fn grid(m: usize) -> Csc {
    let n = m * m;
    let mut col_ptr = vec![0];
    let mut row_idx = Vec::new();
    let mut val = Vec::new();
    for j in 0..n {
        let (x, y) = (j % m, j / m);
        let mut entries = vec![(j, 5.0)];
        if x > 0 {
            entries.push((j - 1, -1.0));
        }
        if x + 1 < m {
            entries.push((j + 1, -1.0));
        }
        if y > 0 {
            entries.push((j - m, -1.0));
        }
        if y + 1 < m {
            entries.push((j + m, -1.0));
        }
        entries.sort_by_key(|e| e.0);
        for (i, v) in entries {
            row_idx.push(i);
            val.push(v);
        }
        col_ptr.push(row_idx.len());
    }
    Csc {
        nrows: n,
        ncols: n,
        col_ptr,
        row_idx,
        val,
    }
}

/// The `m × m` [`grid`] split for a partial factorisation: its first `rows` grid rows the
/// interface, the other nodes the interior: `(A, interior, interface)`.
pub(crate) fn split_grid(m: usize, rows: usize) -> (Csc, Vec<usize>, Vec<usize>) {
    let a = grid(m);
    let interface: Vec<usize> = (0..rows * m).collect();
    let interior: Vec<usize> = (rows * m..m * m).collect();
    (a, interior, interface)
}

fn dense(a: &Csc) -> Vec<Vec<f64>> {
    let mut d = vec![vec![0.0; a.ncols]; a.nrows];
    for j in 0..a.ncols {
        let (r, v) = a.col(j);
        for (&i, &x) in r.iter().zip(v) {
            d[i][j] = x;
        }
    }
    d
}

/// Dense solve of `M x = b` (Gaussian elimination without pivoting; M is SPD).
fn solve_dense(mut m: Vec<Vec<f64>>, mut x: Vec<f64>) -> Vec<f64> {
    let n = x.len();
    for p in 0..n {
        for r in p + 1..n {
            let f = m[r][p] / m[p][p];
            if f != 0.0 {
                for c in p..n {
                    m[r][c] -= f * m[p][c];
                }
                x[r] -= f * x[p];
            }
        }
    }
    for p in (0..n).rev() {
        let mut s = x[p];
        for c in p + 1..n {
            s -= m[p][c] * x[c];
        }
        x[p] = s / m[p][p];
    }
    x
}

/// The sweeps reproduce the condensed right-hand side, the Schur complement and the
/// interior recovery computed densely, on a grid large enough to be split in halves.
#[test]
fn partial_sweeps_match_dense_condensation() {
    let m = 14;
    // Interface: the bottom row of the grid.
    let (a, interior, interface) = split_grid(m, 1);
    let n = m * m;
    let ad = dense(&a);
    let (mut l, order) = PartialCholesky::new(&a, &interior, &interface).unwrap();
    assert!(
        l.p1 > 0 && l.p2 > l.p1 && l.nr > l.p2,
        "the interior is split"
    );
    assert_eq!(&order[interior.len()..], interface.as_slice());
    let nr = interior.len();
    let a_rr: Vec<Vec<f64>> = interior
        .iter()
        .map(|&i| interior.iter().map(|&j| ad[i][j]).collect())
        .collect();
    let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
    let z = solve_dense(a_rr.clone(), interior.iter().map(|&i| b[i]).collect());
    let mut y: Vec<f64> = order.iter().map(|&i| b[i]).collect();
    l.forward_interior(&mut y);
    for (f, &i) in interface.iter().enumerate() {
        let g = b[i]
            - interior
                .iter()
                .zip(&z)
                .map(|(&r, zr)| ad[i][r] * zr)
                .sum::<f64>();
        assert!((y[nr + f] - g).abs() < 1e-12, "condensed rhs {f}");
    }
    let s = l.schur_complement();
    let nf = interface.len();
    for (fj, &j) in interface.iter().enumerate() {
        let w = solve_dense(a_rr.clone(), interior.iter().map(|&r| ad[r][j]).collect());
        for (fi, &i) in interface.iter().enumerate() {
            let sij = ad[i][j]
                - interior
                    .iter()
                    .zip(&w)
                    .map(|(&r, wr)| ad[i][r] * wr)
                    .sum::<f64>();
            assert!((s[fj * nf + fi] - sij).abs() < 1e-12, "S[{fi},{fj}]");
        }
    }
    // Recovery with interface values x_F.
    let x_f: Vec<f64> = (0..nf).map(|f| (f as f64).cos()).collect();
    y[nr..].copy_from_slice(&x_f);
    l.backward_interior(&mut y);
    let rhs: Vec<f64> = interior
        .iter()
        .map(|&r| {
            b[r] - interface
                .iter()
                .zip(&x_f)
                .map(|(&f, xf)| ad[r][f] * xf)
                .sum::<f64>()
        })
        .collect();
    let x_r = solve_dense(a_rr, rhs);
    for (k, &i) in order[..nr].iter().enumerate() {
        let pos = interior.iter().position(|&r| r == i).unwrap();
        assert!((y[k] - x_r[pos]).abs() < 1e-12);
    }
}

/// The two halves give bit-identical results for every parallelism, in the global
/// pool and in pools of one and two threads.
#[test]
fn sweeps_are_bit_identical_for_every_thread_count() {
    let m = 20;
    let (a, interior, interface) = split_grid(m, 1);
    let run = |par: Parallelism| {
        let (mut l, order) = PartialCholesky::new(&a, &interior, &interface).unwrap();
        l.large = true; // this small grid would otherwise stay on one thread
        l.set_parallelism(par);
        assert_eq!(l.interior_par(), par);
        let mut y: Vec<f64> = order.iter().map(|&i| (i as f64).sqrt().sin()).collect();
        l.forward_interior(&mut y);
        l.backward_interior(&mut y);
        y.iter().map(|x| x.to_bits()).collect::<Vec<u64>>()
    };
    let reference = run(Parallelism::SEQ);
    for threads in [1, 2, 4] {
        assert_eq!(run(Parallelism::rayon(threads)), reference, "{threads}");
    }
    for pool_threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(pool_threads)
            .build()
            .unwrap();
        assert_eq!(pool.install(|| run(Parallelism::rayon(2))), reference);
    }
}

#[test]
fn refactorisation_equals_a_fresh_factorisation_and_checks_the_pattern() {
    let m = 20;
    let (a, interior, interface) = split_grid(m, 1);
    let (l, order) = PartialCholesky::new(&a, &interior, &interface).unwrap();
    // Another matrix with the same pattern (as c_M M + c_K K at another τ).
    let mut b = a.clone();
    for (k, v) in b.val.iter_mut().enumerate() {
        *v *= if *v > 0.0 {
            2.0 + (k % 7) as f64 * 0.1
        } else {
            1.3
        };
    }
    assert!(l.analysed_for(&b, &interior, &interface));
    let re = l.refactor(&b).unwrap();
    let (fresh, fresh_order) = PartialCholesky::new(&b, &interior, &interface).unwrap();
    assert_eq!(re.order(), &fresh_order[..]);
    assert_eq!(order, fresh_order);
    let bits = |f: &PartialCholesky| f.l.val.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&re), bits(&fresh));
    assert_eq!(re.schur_complement(), fresh.schur_complement());
    // Another pattern, or other interface dofs: no reuse.
    let c = grid(m + 1);
    assert!(!l.analysed_for(&c, &interior, &interface));
    assert!(matches!(
        l.refactor(&c),
        Err(Error::Problem(ProblemError::InvalidMatrix(_)))
    ));
    let other_interface: Vec<usize> = (1..=m).collect();
    assert!(!l.analysed_for(&b, &interior, &other_interface));
    let mut other_interior = interior.clone();
    other_interior[0] = 0; // an interface dof in place of an interior one
    assert!(!l.analysed_for(&b, &other_interior, &interface));
    // A matrix that is not positive definite is still reported as such.
    let mut d = a.clone();
    for v in d.val.iter_mut() {
        *v = -*v;
    }
    assert!(matches!(
        l.refactor(&d),
        Err(Error::Problem(ProblemError::NotPositiveDefinite(_)))
    ));
}

#[test]
fn sweeps_of_many_right_hand_sides_equal_single_sweeps_bitwise() {
    let m = 20;
    let (a, interior, interface) = split_grid(m, 1);
    let (l, _) = PartialCholesky::new(&a, &interior, &interface).unwrap();
    assert!(
        l.p1 > 0 && l.p2 > l.p1 && l.nr > l.p2,
        "two halves and a separator"
    );
    let n = l.n;
    let rhs = |k: usize| -> Vec<f64> {
        (0..n)
            .map(|i| {
                ((i * 7 + k * 13) as f64 * 0.37).sin() * if i % 5 == k % 5 { 0.0 } else { 1.0 }
            })
            .collect()
    };
    for r in [1, 3, 8] {
        let mut single = Vec::new();
        let mut tmp = Vec::new();
        for k in 0..r {
            let mut y = rhs(k);
            l.backward_interior_with(&mut y, &mut tmp);
            single.push(y);
        }
        let mut rows = vec![0.0; n * r];
        for k in 0..r {
            for (i, v) in rhs(k).into_iter().enumerate() {
                rows[i * r + k] = v;
            }
        }
        l.backward_interior_rows(&mut rows, r, &mut tmp);
        for k in 0..r {
            for i in 0..n {
                assert_eq!(
                    rows[i * r + k].to_bits(),
                    single[k][i].to_bits(),
                    "r = {r}, right-hand side {k}, row {i}"
                );
            }
        }
    }
}
