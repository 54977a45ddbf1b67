//! Vector kernels: points carrying `c` interleaved components (unknown `c p + a` is
//! component `a` of point `p`) whose component blocks are independent low-rank matrices,
//! some of them zero. A cross approximation that searches one row and one column of a
//! block sees only the components of that row and column.

use faer::Mat;
use rsf_hmatrix::{Error, HMatrix, HOptions, Points, RowPart};

/// Points of a slightly sheared `side × side` grid of spacing 1.
fn grid(side: usize) -> Vec<[f64; 2]> {
    (0..side * side)
        .map(|p| {
            let (x, y) = ((p % side) as f64, (p / side) as f64);
            [x + 0.13 * y, y]
        })
        .collect()
}

/// Each point's coordinates repeated once per component (one point per unknown).
fn unknown_points(xy: &[[f64; 2]], c: usize) -> Points {
    let rep: Vec<[f64; 2]> = xy.iter().flat_map(|p| std::iter::repeat_n(*p, c)).collect();
    Points::from_array(&rep).unwrap()
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

/// Two components, no coupling: strike→strike `1/(r + 0.5)`, dip→dip `0.3/(r + 4)` (a
/// smoother kernel on another scale), strike→dip and dip→strike zero.
fn decoupled(xy: &[[f64; 2]], i: usize, j: usize) -> f64 {
    let (p, a, q, b) = (i / 2, i % 2, j / 2, j % 2);
    let r = dist(xy[p], xy[q]);
    match (a, b) {
        (0, 0) => 1.0 / (r + 0.5),
        (1, 1) => 0.3 / (r + 4.0),
        _ => 0.0,
    }
}

/// Three components: the diagonal blocks smooth kernels of three scales, component 2's
/// block zero on the points of the lower half of the grid (so it is zero in the first
/// rows and columns of many blocks), a weak smooth coupling 0 ↔ 1, the rest zero.
fn three_components(xy: &[[f64; 2]], i: usize, j: usize) -> f64 {
    let (p, a, q, b) = (i / 3, i % 3, j / 3, j % 3);
    let r = dist(xy[p], xy[q]);
    let upper = |p: usize| if xy[p][1] >= 14.0 { 1.0 } else { 0.0 };
    match (a, b) {
        (0, 0) => 1.0 / (r + 0.5),
        (1, 1) => 0.5 / (r + 2.0),
        (2, 2) => 0.2 * upper(p) * upper(q) / (r + 1.0),
        (0, 1) | (1, 0) => 0.05 * (xy[p][0] - xy[q][0] + xy[p][1] - xy[q][1]) / (r * r + 1.0),
        _ => 0.0,
    }
}

fn relative_error(h: &HMatrix, s: &Mat<f64>) -> f64 {
    (&h.to_dense() - s).norm_l2() / s.norm_l2()
}

#[test]
fn cross_approximation_finds_every_component_block() {
    let xy = grid(28);
    let eps = 1e-6;
    for (c, kernel) in [
        (2, decoupled as fn(&[[f64; 2]], usize, usize) -> f64),
        (3, three_components),
    ] {
        let n = c * xy.len();
        let points = unknown_points(&xy, c);
        let f = |i: usize, j: usize| kernel(&xy, i, j);
        let s = Mat::from_fn(n, n, f);
        let options = HOptions {
            components: c,
            ..HOptions::with_epsilon(eps)
        };
        let h = HMatrix::from_entries(f, &points, &options).unwrap();
        let err = relative_error(&h, &s);
        assert!(err <= eps, "{c} components: ‖S − S_H‖_F/‖S‖_F = {err:.3e}");
        let svd = HMatrix::from_dense(s.as_ref(), &points, &options).unwrap();
        assert!(h.report().low_rank_blocks > 0);
        // About what the optimal truncation of every block stores.
        let (a, b) = (h.stored_entries() as f64, svd.stored_entries() as f64);
        assert!(
            a <= 1.3 * b && a < (n * n) as f64,
            "{c} components: ACA {a} against SVD {b}"
        );
    }
}

#[test]
fn component_blocks_cost_their_crosses_not_their_entries() {
    // Two components without coupling on a line of 2 000 points: half of every admissible
    // block is zero, and evaluating it (a pivot search that falls back on every row of a
    // vanishing residual) would cost about half of the far field's entries (≈ 8 × 10⁶;
    // the near field is 5.8 × 10⁵).
    let line: Vec<[f64; 2]> = (0..2000).map(|p| [p as f64, 0.0]).collect();
    let n = 2 * line.len();
    let points = unknown_points(&line, 2);
    let options = HOptions {
        components: 2,
        error_samples: 0,
        ..HOptions::with_epsilon(1e-6)
    };
    let count = std::cell::Cell::new(0usize);
    let f = |i: usize, j: usize| {
        count.set(count.get() + 1);
        decoupled(&line, i, j)
    };
    let h = HMatrix::from_entries(f, &points, &options).unwrap();
    let r = h.report();
    let evaluated = count.get();
    // The near field, and per low-rank block its crosses, references and samples.
    assert!(
        evaluated < 3 * r.stored_entries && evaluated < n * n / 5,
        "{evaluated} entries evaluated for {} stored, n² = {}",
        r.stored_entries,
        n * n
    );
    // And the matrix is right: the error on every entry of a sample of rows.
    let mut e2 = 0.0;
    let mut s2 = 0.0;
    let hd = h.to_dense();
    for i in (0..n).step_by(37) {
        for j in 0..n {
            let s = decoupled(&line, i, j);
            e2 += (hd[(i, j)] - s).powi(2);
            s2 += s * s;
        }
    }
    assert!((e2 / s2).sqrt() <= 1e-6);
}

#[test]
fn points_must_be_whole_numbers_of_components() {
    let points = Points::new(&[0.0, 1.0, 2.0, 3.0, 4.0], 1).unwrap();
    // Two components of five points, and none.
    for components in [2, 0] {
        let options = HOptions {
            components,
            ..HOptions::default()
        };
        assert!(matches!(
            HMatrix::from_entries(|_, _| 1.0, &points, &options),
            Err(rsf_hmatrix::Error::Option {
                name: "components",
                ..
            })
        ));
    }
}

#[test]
fn cross_approximation_is_bit_identical_for_every_thread_count() {
    let xy = grid(16);
    let points = unknown_points(&xy, 3);
    let f = |i: usize, j: usize| three_components(&xy, i, j);
    let options = HOptions {
        components: 3,
        ..HOptions::with_epsilon(1e-6)
    };
    let mut first: Option<Vec<u64>> = None;
    for threads in [1, 2, 4] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let h = pool.install(|| HMatrix::from_entries(f, &points, &options).unwrap());
        let d = h.to_dense();
        let bits: Vec<u64> = d
            .col_iter()
            .flat_map(|c| c.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
            .collect();
        match &first {
            None => first = Some(bits),
            Some(b) => assert!(*b == bits, "{threads} threads: other bits"),
        }
    }
}

/// A point's components (coincident points with consecutive indices) are never separated
/// by the cluster tree, so every part of a row split holds whole points: what a process
/// sharing the product needs to finish a node's rows alone. With 2 and 3 components, leaf
/// sizes that put the median inside a point (odd halves), and every number of parts up
/// to 9.
#[test]
fn a_points_components_stay_in_one_part_of_every_row_split() {
    let xy = grid(23);
    for c in [2, 3] {
        let points = unknown_points(&xy, c);
        for leaf_size in [5, 7, 48] {
            let options = HOptions {
                leaf_size,
                components: c,
                ..HOptions::with_epsilon(1e-6)
            };
            let mut h =
                HMatrix::from_entries(|i, j| decoupled_or_coupled(&xy, c, i, j), &points, &options)
                    .unwrap();
            for parts in 1..=9 {
                let ranges = h.split_rows(parts, 0.0);
                let mut part_of = vec![usize::MAX; h.dim()];
                for (p, r) in ranges.iter().enumerate() {
                    for q in r.clone() {
                        part_of[h.permutation()[q]] = p;
                    }
                }
                for (p, rows) in part_of.chunks(c).enumerate() {
                    assert!(
                        rows.iter().all(|&r| r == rows[0]),
                        "c = {c}, leaf size {leaf_size}, {parts} parts: point {p}'s \
                         components in parts {rows:?}"
                    );
                }
            }
        }
    }
}

/// An ℋ-matrix built for one part of its rows (`from_entries_part`, the share of one
/// process) holds only that part's blocks, and its rows of the product have the bits of
/// the whole matrix's product: for 1 to 5 parts, with 2 components per point, the parts'
/// rows cover every row once, each row equals `apply_add`'s of the whole matrix to the
/// bit, each part stores less than the whole (more than 1/parts of it in total: blocks
/// that reach two parts are held by both), every point's components are in one part, and
/// a part refuses the whole product and another part's.
#[test]
fn a_matrix_built_for_one_part_has_the_bits_of_the_whole_on_its_rows() {
    let xy = grid(23);
    let c = 2;
    let points = unknown_points(&xy, c);
    let options = HOptions {
        leaf_size: 16,
        components: c,
        ..HOptions::with_epsilon(1e-6)
    };
    let kernel = |i: usize, j: usize| decoupled_or_coupled(&xy, c, i, j);
    let mut whole = HMatrix::from_entries(kernel, &points, &options).unwrap();
    let n = whole.dim();
    let x: Vec<f64> = (0..n)
        .map(|i| ((i * 37 % 101) as f64 - 50.0) / 7.0)
        .collect();
    let mut y = vec![0.0; n];
    whole.apply_add(&x, &mut y, 1.0, faer::Par::Seq).unwrap();
    for parts in 1..=5 {
        let mut covered = vec![0usize; n];
        let mut stored = 0;
        for part in 0..parts {
            let row_part = RowPart { parts, part };
            let mut h = HMatrix::from_entries_part(kernel, &points, &options, row_part).unwrap();
            assert_eq!(h.held_part(), Some((part, parts)));
            assert_eq!(h.report().part, Some((part, parts)));
            stored += h.stored_entries();
            if parts > 1 {
                assert!(h.stored_entries() < whole.stored_entries());
            }
            let perm = h.permutation().to_vec();
            let rows = h.apply_part(&x, part, |p| {
                for (q, z) in p.rows.clone().zip(p.z) {
                    let i = perm[q];
                    covered[i] += 1;
                    assert_eq!(
                        z.to_bits(),
                        y[i].to_bits(),
                        "{parts} parts, part {part}: row {i}"
                    );
                }
                p.rows.clone()
            });
            let rows = rows.unwrap();
            // A point's components in one part.
            for q in rows.clone() {
                let i = perm[q];
                let partner = perm.iter().position(|&k| k == i ^ 1).unwrap();
                assert!(rows.contains(&partner), "point {} split", i / c);
            }
            let mut r = vec![0.0; n];
            assert!(matches!(
                h.apply_add(&x, &mut r, 1.0, faer::Par::Seq),
                Err(Error::PartOnly { .. })
            ));
            if parts > 1 {
                let other = (part + 1) % parts;
                assert!(matches!(
                    h.apply_part(&x, other, |_| ()),
                    Err(Error::PartOnly { .. })
                ));
            }
            // The split is the part's whatever is asked.
            assert_eq!(h.split_rows(7, 1e3).len(), parts);
        }
        assert!(
            covered.iter().all(|&k| k == 1),
            "{parts} parts: rows covered once"
        );
        assert!(stored >= whole.stored_entries());
    }
    // A part beyond the parts.
    assert!(matches!(
        HMatrix::from_entries_part(kernel, &points, &options, RowPart { parts: 2, part: 2 }),
        Err(Error::Option { name: "part", .. })
    ));
}

/// `decoupled` for two components, a coupled smooth kernel for three.
fn decoupled_or_coupled(xy: &[[f64; 2]], c: usize, i: usize, j: usize) -> f64 {
    if c == 2 {
        return decoupled(xy, i, j);
    }
    let (p, a, q, b) = (i / c, i % c, j / c, j % c);
    (1.0 + (a * c + b) as f64 * 0.1) / (dist(xy[p], xy[q]) + 1.0)
}
