//! Accuracy, memory growth, determinism and input errors of the ℋ-matrix.

use faer::{Mat, Par};
use rsf_hmatrix::kernels::AntiplaneHalfSpace;
use rsf_hmatrix::{Error, ErrorMeasure, HMatrix, HOptions, Points, RowPart};
use std::num::NonZeroUsize;

/// BP1's shear modulus (Pa) and a 40 km fault.
const MU: f64 = 32.04e9;
const DEPTH: f64 = 40e3;

fn kernel(n: usize) -> AntiplaneHalfSpace {
    AntiplaneHalfSpace::new(n, DEPTH / n as f64, MU).unwrap()
}

fn dense(k: &AntiplaneHalfSpace) -> Mat<f64> {
    Mat::from_fn(k.len(), k.len(), |i, j| k.entry(i, j))
}

/// The kernel on `n` cells, its dense matrix and its points.
fn kernel_matrix(n: usize) -> (AntiplaneHalfSpace, Mat<f64>, Points) {
    let k = kernel(n);
    let s = dense(&k);
    let points = k.points();
    (k, s, points)
}

fn frob(a: &Mat<f64>) -> f64 {
    a.norm_l2()
}

fn vec_norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Deterministic pseudo-random vector in [-0.5, 0.5).
fn test_vector(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect()
}

fn dense_product(s: &Mat<f64>, x: &[f64]) -> Vec<f64> {
    (0..s.nrows())
        .map(|i| (0..s.ncols()).map(|j| s[(i, j)] * x[j]).sum())
        .collect()
}

#[test]
fn antiplane_kernel_is_symmetric_and_negative_definite() {
    let k = kernel(300);
    let s = dense(&k);
    for i in 0..300 {
        assert!(s[(i, i)] < 0.0);
        for j in 0..300 {
            assert_eq!(s[(i, j)], s[(j, i)]);
            if i != j {
                assert!(s[(i, j)] > 0.0, "({i}, {j}) = {}", s[(i, j)]);
            }
        }
    }
    let neg = Mat::from_fn(300, 300, |i, j| -s[(i, j)]);
    assert!(
        neg.llt(faer::Side::Lower).is_ok(),
        "−K is not positive definite"
    );
}

#[test]
fn svd_compression_meets_the_tolerance_in_the_matrix_and_the_product() {
    let n = 700;
    let (_, s, points) = kernel_matrix(n);
    let norm = frob(&s);
    for eps in [1e-4, 1e-6, 1e-8] {
        let mut h = HMatrix::from_dense(s.as_ref(), &points, &HOptions::with_epsilon(eps)).unwrap();
        let r = h.report().clone();
        assert_eq!(r.error_measure, ErrorMeasure::Exact);
        assert!(
            r.relative_error <= eps,
            "eps {eps}: reported {}",
            r.relative_error
        );
        assert!(r.relative_error > 0.0, "eps {eps}: nothing was compressed");
        let measured = frob(&(&h.to_dense() - &s)) / norm;
        assert!(measured <= eps, "eps {eps}: measured {measured}");
        assert!((measured - r.relative_error).abs() <= 1e-3 * eps + 1e-15);
        assert!(
            r.stored_entries < n * n / 2,
            "eps {eps}: {} stored",
            r.stored_entries
        );
        assert!(r.low_rank_blocks > 0 && r.max_rank > 0);
        for seed in 1..4 {
            let x = test_vector(n, seed);
            let exact = dense_product(&s, &x);
            let y0 = test_vector(n, seed + 10);
            let mut y = y0.clone();
            h.apply_add(&x, &mut y, -2.0, Par::Seq).unwrap();
            let diff: Vec<f64> = (0..n).map(|i| (y[i] - y0[i]) / -2.0 - exact[i]).collect();
            let rel = vec_norm(&diff) / (norm * vec_norm(&x));
            assert!(rel <= eps, "eps {eps}: product error {rel}");
        }
    }
}

#[test]
fn aca_meets_the_tolerance_and_agrees_with_svd() {
    let (k, s, points) = kernel_matrix(700);
    let norm = frob(&s);
    for eps in [1e-4, 1e-6, 1e-8] {
        let options = HOptions::with_epsilon(eps);
        let aca = HMatrix::from_entries(|i, j| k.entry(i, j), &points, &options).unwrap();
        let svd = HMatrix::from_dense(s.as_ref(), &points, &options).unwrap();
        let (ha, hs) = (aca.to_dense(), svd.to_dense());
        let err_aca = frob(&(&ha - &s)) / norm;
        assert!(err_aca <= eps, "eps {eps}: ACA error {err_aca}");
        assert!(frob(&(&ha - &hs)) / norm <= 2.0 * eps);
        let r = aca.report();
        assert!(matches!(
            r.error_measure,
            ErrorMeasure::Sampled { samples: 20_000 }
        ));
        assert!(
            r.relative_error <= eps,
            "eps {eps}: estimate {}",
            r.relative_error
        );
        // ACA + recompression stores about what the optimal truncation stores.
        let (a, b) = (r.stored_entries as f64, svd.stored_entries() as f64);
        assert!(a <= 1.3 * b, "ACA {a} against SVD {b}");
    }
}

/// `n` points of the plane in rows of 30, each row shifted by 0.1 against the last.
fn sheared_grid(n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| [(i % 30) as f64 + 0.1 * (i / 30) as f64, (i / 30) as f64])
        .collect()
}

/// [`sheared_grid`] of `n` points and its [`Points`].
fn sheared_points(n: usize) -> (Vec<[f64; 2]>, Points) {
    let xy = sheared_grid(n);
    let points = Points::from_array(&xy).unwrap();
    (xy, points)
}

/// A smooth kernel of the distance d between `x` and `y`: `1 / (d + 0.5)`.
fn smooth_kernel(x: [f64; 2], y: [f64; 2]) -> f64 {
    let d = ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2)).sqrt();
    1.0 / (d + 0.5)
}

#[test]
fn two_dimensional_points_with_a_smooth_kernel() {
    let n = 900;
    let (xy, points) = sheared_points(n);
    let f = |i: usize, j: usize| smooth_kernel(xy[i], xy[j]);
    let s = Mat::from_fn(n, n, f);
    let eps = 1e-6;
    let options = HOptions::with_epsilon(eps);
    let h = HMatrix::from_entries(f, &points, &options).unwrap();
    let hd = HMatrix::from_dense(s.as_ref(), &points, &options).unwrap();
    assert!(frob(&(&h.to_dense() - &s)) / frob(&s) <= eps);
    assert!(frob(&(&hd.to_dense() - &s)) / frob(&s) <= eps);
    assert!(h.stored_entries() < n * n);
    // The error estimate on all entries (n² ≤ samples) is exact.
    let small = HOptions {
        error_samples: n * n,
        ..options
    };
    let h = HMatrix::from_entries(f, &points, &small).unwrap();
    assert_eq!(h.report().error_measure, ErrorMeasure::Exact);
    let exact = frob(&(&h.to_dense() - &s)) / frob(&s);
    assert!((h.report().relative_error - exact).abs() <= 1e-6 * exact + 1e-16);
}

#[test]
fn stored_entries_grow_like_n_log_n() {
    crate::assert_stored_entries_grow_like_n_log_n(&[256, 512, 1024, 2048, 4096], |n| {
        let k = kernel(n);
        let h =
            HMatrix::from_entries(|i, j| k.entry(i, j), &k.points(), &HOptions::default()).unwrap();
        assert!(h.report().relative_error <= 1e-6);
        h.stored_entries()
    });
}

#[test]
fn products_are_bit_identical_run_to_run_and_in_parallel() {
    let n = 1000;
    let (_, s, points) = kernel_matrix(n);
    let options = HOptions::with_epsilon(1e-6);
    let mut a = HMatrix::from_dense(s.as_ref(), &points, &options).unwrap();
    let mut b = HMatrix::from_dense(s.as_ref(), &points, &options).unwrap();
    let x = test_vector(n, 7);
    let mut y1 = vec![0.5; n];
    let mut y2 = vec![0.5; n];
    let mut y3 = vec![0.5; n];
    a.apply_add(&x, &mut y1, 1.5, Par::Seq).unwrap();
    b.apply_add(&x, &mut y2, 1.5, Par::Seq).unwrap();
    a.apply_add(&x, &mut y3, 1.5, Par::Rayon(NonZeroUsize::new(4).unwrap()))
        .unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&y1), bits(&y2));
    assert_eq!(bits(&y1), bits(&y3));
}

#[test]
fn products_by_parts_give_every_row_the_bits_of_the_whole_product() {
    let n = 1000;
    let (_, s, points) = kernel_matrix(n);
    let mut h = HMatrix::from_dense(s.as_ref(), &points, &HOptions::with_epsilon(1e-6)).unwrap();
    let x = test_vector(n, 11);
    let mut whole = vec![0.0; n];
    h.apply_add(&x, &mut whole, 1.0, Par::Seq).unwrap();
    // Against the dense product (so that a split that drops or repeats rows fails).
    let exact = dense_product(&s, &x);
    let diff: Vec<f64> = whole.iter().zip(&exact).map(|(a, b)| a - b).collect();
    assert!(vec_norm(&diff) <= 1e-5 * vec_norm(&exact));
    let perm = h.permutation().to_vec();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for (parts, work_per_row) in [
        (1, 0.0),
        (2, 0.0),
        (2, 500.0),
        (3, 50.0),
        (7, 0.0),
        (500, 1.0),
    ] {
        let ranges = h.split_rows(parts, work_per_row);
        assert!(!ranges.is_empty() && ranges.len() <= parts);
        assert_eq!(ranges[0].start, 0);
        assert_eq!(ranges[ranges.len() - 1].end, n);
        assert!(ranges
            .windows(2)
            .all(|w| w[0].end == w[1].start && w[0].start < w[0].end));
        // Each part writes its rows (original numbering) into its own state.
        let mut states: Vec<Vec<(usize, f64)>> = vec![Vec::new(); ranges.len()];
        h.apply_by_parts(&x, &mut states, |rows, out: &mut Vec<(usize, f64)>| {
            assert_eq!(rows.rows, ranges[rows.part]);
            assert_eq!(rows.z.len(), rows.rows.len());
            for (p, z) in rows.rows.clone().zip(rows.z) {
                out.push((perm[p], *z));
            }
        })
        .unwrap();
        let mut seen = vec![false; n];
        for (i, z) in states.iter().flatten() {
            assert!(!seen[*i], "row {i} twice");
            seen[*i] = true;
            assert_eq!(z.to_bits(), whole[*i].to_bits(), "{parts} parts, row {i}");
        }
        assert!(seen.iter().all(|&b| b), "{parts} parts: a row is missing");
        for (p, &i) in perm.iter().enumerate() {
            assert_eq!(h.last_product()[p].to_bits(), whole[i].to_bits());
        }
        let mut wrong = vec![(); ranges.len() + 1];
        assert!(matches!(
            h.apply_by_parts(&x, &mut wrong, |_, _| {}),
            Err(Error::VectorLength { name: "states", .. })
        ));
        // Each part alone (a process's share): its rows, with the whole product's bits;
        // stale values elsewhere are never read.
        let mut alone = vec![f64::NAN; n];
        for part in 0..ranges.len() {
            h.apply_part(&x, part, |rows| {
                assert_eq!((rows.part, &rows.rows), (part, &ranges[part]));
                for (p, z) in rows.rows.clone().zip(rows.z) {
                    assert!(alone[perm[p]].is_nan(), "row {} in two parts", perm[p]);
                    alone[perm[p]] = *z;
                }
            })
            .unwrap();
        }
        assert_eq!(bits(&alone), bits(&whole), "{parts} parts, one at a time");
        assert!(matches!(
            h.apply_part(&x, ranges.len(), |_| ()),
            Err(Error::VectorLength { name: "part", .. })
        ));
    }
    let mut nan = x.clone();
    nan[3] = f64::NAN;
    assert!(matches!(
        h.apply_part(&nan, 0, |_| ()),
        Err(Error::NonFiniteInput(3))
    ));
    // A non-finite whole product (another thread count) leaves the split as it was: a part
    // shared out to a process stays the part it was.
    let ranges = h.split_rows(3, 0.0);
    let last = ranges.len() - 1;
    assert!(matches!(
        h.apply_add(&nan, &mut vec![0.0; n], 1.0, Par::Seq),
        Err(Error::NonFiniteInput(3))
    ));
    h.apply_part(&x, last, |rows| assert_eq!(rows.rows, ranges[last]))
        .unwrap();
}

#[test]
fn empty_and_one_by_one() {
    let none = Points::new(&[], 2).unwrap();
    let mut h = HMatrix::from_dense(
        Mat::<f64>::zeros(0, 0).as_ref(),
        &none,
        &HOptions::default(),
    )
    .unwrap();
    assert_eq!((h.dim(), h.stored_entries()), (0, 0));
    assert_eq!(h.report().relative_error, 0.0);
    h.apply_add(&[], &mut [], 1.0, Par::Seq).unwrap();
    let h = HMatrix::from_entries(|_, _| 1.0, &none, &HOptions::default()).unwrap();
    assert_eq!(h.dim(), 0);

    let one = Points::new(&[3.0, 4.0], 2).unwrap();
    let s = Mat::from_fn(1, 1, |_, _| -2.5);
    let mut h = HMatrix::from_dense(s.as_ref(), &one, &HOptions::default()).unwrap();
    assert_eq!((h.dim(), h.stored_entries()), (1, 1));
    let mut y = [1.0];
    h.apply_add(&[2.0], &mut y, 0.5, Par::Seq).unwrap();
    assert_eq!(y, [1.0 - 2.5]);
    let h = HMatrix::from_entries(|_, _| -2.5, &one, &HOptions::default()).unwrap();
    assert_eq!(h.to_dense()[(0, 0)], -2.5);
    assert_eq!(h.report().relative_error, 0.0);
}

#[test]
fn coincident_points_stay_dense_and_exact() {
    let n = 100;
    let points = Points::new(&vec![1.0; n], 1).unwrap();
    let s = Mat::from_fn(n, n, |i, j| 1.0 / (1.0 + (i as f64 - j as f64).abs()));
    let h = HMatrix::from_dense(s.as_ref(), &points, &HOptions::with_epsilon(0.5)).unwrap();
    assert_eq!(h.report().low_rank_blocks, 0);
    assert_eq!(h.to_dense(), s);
}

#[test]
fn non_finite_entries_are_typed_errors() {
    let n = 200;
    let k = kernel(n);
    let points = k.points();
    let mut s = dense(&k);
    s[(3, 150)] = f64::NAN;
    assert_eq!(
        HMatrix::from_dense(s.as_ref(), &points, &HOptions::default()).unwrap_err(),
        Error::NonFiniteEntry { row: 3, col: 150 }
    );
    // A far-field entry (seen by ACA) and a near-field one.
    for bad in [(0usize, 199usize), (10, 11)] {
        let f = |i: usize, j: usize| {
            if (i, j) == bad {
                f64::INFINITY
            } else {
                k.entry(i, j)
            }
        };
        let err = HMatrix::from_entries(f, &points, &HOptions::default()).unwrap_err();
        assert_eq!(
            err,
            Error::NonFiniteEntry {
                row: bad.0,
                col: bad.1
            }
        );
    }
}

#[test]
fn invalid_input_is_rejected() {
    assert_eq!(Points::new(&[1.0], 4).unwrap_err(), Error::Dimension(4));
    assert_eq!(Points::new(&[1.0], 0).unwrap_err(), Error::Dimension(0));
    assert!(matches!(
        Points::new(&[1.0, 2.0, 3.0], 2),
        Err(Error::CoordinateCount { len: 3, dim: 2 })
    ));
    assert_eq!(
        Points::new(&[1.0, f64::NAN], 2).unwrap_err(),
        Error::NonFiniteCoordinate {
            point: 0,
            component: 1
        }
    );
    let points = Points::new(&[0.0, 1.0, 2.0], 1).unwrap();
    let s = Mat::<f64>::identity(2, 2);
    assert!(matches!(
        HMatrix::from_dense(s.as_ref(), &points, &HOptions::default()),
        Err(Error::Shape {
            rows: 2,
            cols: 2,
            points: 3
        })
    ));
    for bad in [
        HOptions {
            leaf_size: 0,
            ..HOptions::default()
        },
        HOptions {
            eta: f64::NAN,
            ..HOptions::default()
        },
        HOptions {
            eta: 0.0,
            ..HOptions::default()
        },
        HOptions::with_epsilon(1.0),
        HOptions::with_epsilon(-1e-3),
        HOptions::with_epsilon(f64::NAN),
    ] {
        assert!(matches!(
            HMatrix::from_entries(|_, _| 1.0, &points, &bad),
            Err(Error::Option { .. })
        ));
    }
    let s = Mat::<f64>::identity(3, 3);
    let mut h = HMatrix::from_dense(s.as_ref(), &points, &HOptions::default()).unwrap();
    let mut y = vec![0.0; 3];
    assert!(matches!(
        h.apply_add(&[1.0; 2], &mut y, 1.0, Par::Seq),
        Err(Error::VectorLength {
            name: "x",
            len: 2,
            expected: 3
        })
    ));
    assert!(matches!(
        h.apply_add(&[1.0; 3], &mut [0.0; 4], 1.0, Par::Seq),
        Err(Error::VectorLength { name: "y", .. })
    ));
    assert_eq!(
        h.apply_add(&[1.0, f64::INFINITY, 0.0], &mut y, 1.0, Par::Seq),
        Err(Error::NonFiniteInput(1))
    );
    assert!(matches!(
        h.apply_add(&[1.0; 3], &mut y, f64::NAN, Par::Seq),
        Err(Error::Option { name: "alpha", .. })
    ));
    assert_eq!(y, vec![0.0; 3]);
    assert!(AntiplaneHalfSpace::new(3, 0.0, MU).is_err());
    assert!(AntiplaneHalfSpace::new(3, 1.0, f64::INFINITY).is_err());
}

/// The set-up from a dense matrix has the same bits whatever the size of rayon's pool it
/// runs in (its SVDs on the calling thread): before issue 57's fix, faer's `thin_svd()`
/// split its work by the pool's size, and a run's bits depended on the machine's cores.
#[test]
fn from_dense_has_the_same_bits_in_pools_of_any_size() {
    let n = 600;
    let (_, s, points) = kernel_matrix(n);
    let build = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let h = HMatrix::from_dense(s.as_ref(), &points, &HOptions::with_epsilon(1e-8))
                    .unwrap();
                let d = h.to_dense();
                (0..n * n)
                    .map(|i| d[(i % n, i / n)].to_bits())
                    .collect::<Vec<u64>>()
            })
    };
    let one = build(1);
    for threads in [2, 4] {
        assert!(build(threads) == one, "{threads} threads");
    }
}

/// The set-up from entries on rayon's threads (`from_entries_par`, each block its own
/// entry function) gives the blocks and the report of the sequential `from_entries`, bit
/// for bit, in pools of 1, 2 and 4 threads, whole and for one part of the rows.
#[test]
fn from_entries_par_has_the_bits_of_from_entries() {
    let n = 900;
    let (xy, points) = sheared_points(n);
    let f = |i: usize, j: usize| smooth_kernel(xy[i], xy[j]);
    let options = HOptions::with_epsilon(1e-7);
    let bits = |h: &HMatrix| {
        let d = h.to_dense();
        (0..n * n)
            .map(|i| d[(i % n, i / n)].to_bits())
            .collect::<Vec<u64>>()
    };
    let sequential = HMatrix::from_entries(f, &points, &options).unwrap();
    let part = RowPart { parts: 3, part: 1 };
    let sequential_part = HMatrix::from_entries_part(f, &points, &options, part).unwrap();
    let mut x = vec![0.0; n];
    x[17] = 1.0;
    x[500] = -2.0;
    let product = |h: &mut HMatrix| {
        let mut y = vec![0.0; n];
        h.apply_add(&x, &mut y, 1.0, Par::Seq).unwrap();
        y.iter().map(|v| v.to_bits()).collect::<Vec<u64>>()
    };
    for threads in [1, 2, 4] {
        let (mut whole, one_part) = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                (
                    HMatrix::from_entries_par(|| f, &points, &options).unwrap(),
                    HMatrix::from_entries_part_par(|| f, &points, &options, part).unwrap(),
                )
            });
        assert!(bits(&whole) == bits(&sequential), "{threads} threads");
        assert_eq!(whole.report(), sequential.report());
        assert_eq!(one_part.report(), sequential_part.report());
        assert_eq!(product(&mut whole), product(&mut sequential.clone()));
    }
}
