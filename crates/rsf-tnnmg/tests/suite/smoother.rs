//! The parallel smoother orders (`SmootherOrder::MultiColour`, `RedBlackChunks`): the
//! colouring is proper on 2-D and 3-D P1 patterns, their iterates are bit-identical at 1, 2
//! and 4 threads, and they converge to the same minimiser as the lexicographic order and
//! the direct solver.

use crate::common::*;
use faer::sparse::Triplet;
use rsf_linalg::Parallelism;
use rsf_nonsmooth::*;
use rsf_ranks::Colouring;
use rsf_tnnmg::*;

/// A symmetric matrix with the node pattern of P1 on a simplicial mesh given by its
/// elements (node lists), block size `D`: every pair of nodes sharing an element is
/// coupled by a dense `D × D` block (values arbitrary, diagonal dominant).
fn p1_pattern<const D: usize>(nodes: usize, elements: &[Vec<usize>]) -> Mat {
    let mut t = Vec::new();
    for e in elements {
        for &p in e {
            for &q in e {
                for r in 0..D {
                    for c in 0..D {
                        let v = if p == q && r == c {
                            10.0
                        } else {
                            -0.1 - 0.01 * ((p + q + r + c) % 5) as f64
                        };
                        t.push(Triplet::new(D * p + r, D * q + c, v));
                    }
                }
            }
        }
    }
    from_triplets(D * nodes, D * nodes, &t)
}

/// P1 triangles on an `m × m` square grid, each square split along one diagonal.
fn triangles(m: usize) -> (usize, Vec<Vec<usize>>) {
    let n1 = m + 1;
    let id = |i: usize, j: usize| j * n1 + i;
    let mut e = Vec::new();
    for j in 0..m {
        for i in 0..m {
            e.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            e.push(vec![id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (n1 * n1, e)
}

/// P1 tetrahedra on an `m³` cube grid, each cube split into the six Kuhn simplices.
fn tetrahedra(m: usize) -> (usize, Vec<Vec<usize>>) {
    let n1 = m + 1;
    let id = |i: usize, j: usize, k: usize| (k * n1 + j) * n1 + i;
    let mut e = Vec::new();
    for k in 0..m {
        for j in 0..m {
            for i in 0..m {
                for perm in rsf_fem::KUHN_PATHS {
                    let mut x = [i, j, k];
                    let mut tet = vec![id(x[0], x[1], x[2])];
                    for axis in perm {
                        x[axis] += 1;
                        tet.push(id(x[0], x[1], x[2]));
                    }
                    e.push(tet);
                }
            }
        }
    }
    (n1 * n1 * n1, e)
}

/// Checks the colouring against the scalar matrix: every node has one colour, the colour
/// lists partition the nodes (increasing), and no stored entry couples two distinct nodes
/// of one colour. Returns the number of colours.
fn check_proper<const D: usize>(a: &Mat) -> usize {
    let col = Colouring::new::<D>(a.as_ref()).unwrap();
    let nodes = a.nrows() / D;
    assert_eq!(col.num_nodes(), nodes);
    let mut seen = vec![false; nodes];
    for c in 0..col.num_colours() {
        let list = col.colour(c);
        assert!(!list.is_empty());
        assert!(list.windows(2).all(|w| w[0] < w[1]));
        for &p in list {
            assert!(!seen[p as usize]);
            seen[p as usize] = true;
            assert_eq!(col.colour_of(p as usize), c);
        }
    }
    assert!(seen.iter().all(|&s| s));
    let mut couplings = 0;
    for j in 0..a.ncols() {
        for &i in a.as_ref().symbolic().row_idx_of_col_raw(j) {
            if i / D != j / D {
                couplings += 1;
                assert_ne!(
                    col.colour_of(i / D),
                    col.colour_of(j / D),
                    "nodes {} and {} are adjacent and share a colour",
                    i / D,
                    j / D
                );
            }
        }
    }
    assert!(couplings > 0);
    col.num_colours()
}

#[test]
fn colouring_is_proper_on_p1_patterns() {
    let (n, e) = triangles(9);
    let colours = check_proper::<2>(&p1_pattern::<2>(n, &e));
    // At least 3 (a triangle's nodes are pairwise adjacent), at most 1 + max degree (6).
    assert!((3..=7).contains(&colours), "2-D: {colours} colours");
    let (n, e) = tetrahedra(5);
    let colours = check_proper::<3>(&p1_pattern::<3>(n, &e));
    // At least 4 (a tetrahedron), at most 1 + max degree (14).
    assert!((4..=15).contains(&colours), "3-D: {colours} colours");
    // The 5-point stencil graph is bipartite; greedy in lexicographic order finds that.
    assert_eq!(check_proper::<1>(&square(8, 1.0)), 2);
}

#[test]
fn smoother_order_names_round_trip() {
    for s in [
        SmootherOrder::Lexicographic,
        SmootherOrder::MultiColour,
        SmootherOrder::RedBlackChunks,
    ] {
        assert_eq!(s.to_string().parse::<SmootherOrder>().unwrap(), s);
    }
    assert!("red-black".parse::<SmootherOrder>().is_err());
    assert_eq!(SmootherOrder::default(), SmootherOrder::Lexicographic);
}

fn options(smoother: SmootherOrder) -> TnnmgOptions {
    TnnmgOptions {
        stopping: Stopping {
            absolute: 1e-13,
            relative: 0.0,
            max_iterations: 200,
        },
        record_energy: true,
        smoother,
        ..Default::default()
    }
}

/// 65² nodes: each of the two colours (over 2000 nodes) and the residual's rows are split
/// between the threads, and so are the red–black chunks (of the nonlinear sweeps and of the
/// linear multigrid's fine level) and, in every order, the quadratic forms' rows (over
/// 2048), the Galerkin updates and the transfers (over 512 rows); run inside a pool of 4
/// threads so that 4 tasks really run concurrently.
#[test]
fn every_order_gives_bit_identical_iterates_at_1_2_and_4_threads() {
    for order in [
        SmootherOrder::Lexicographic,
        SmootherOrder::MultiColour,
        SmootherOrder::RedBlackChunks,
    ] {
        bit_identical_at_1_2_and_4_threads(order);
    }
}

fn bit_identical_at_1_2_and_4_threads(order: SmootherOrder) {
    let (m0, level) = (2, 5);
    let m = m0 << level;
    let StickSlip { a, fixed, b, nl } = stick_slip(m);
    let hierarchy = square_hierarchy(m0, level);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(4)
        .build()
        .unwrap();
    let run = |threads: usize| {
        let mut tn = Tnnmg::<1>::new(a.as_ref(), &fixed, &hierarchy, None, options(order))
            .unwrap()
            .with_parallelism(Parallelism::rayon(threads));
        if order == SmootherOrder::MultiColour {
            assert_eq!(tn.colouring().unwrap().num_colours(), 2);
        }
        let mut v = vec![0.0; b.len()];
        let report = pool.install(|| tn.solve(&b, &nl, &mut v)).unwrap();
        (v, report)
    };
    let (v1, r1) = run(1);
    assert!(r1.iterations >= 3, "{} iterations", r1.iterations);
    for threads in [2, 4] {
        let (v, r) = run(threads);
        assert_eq!(r.iterations, r1.iterations, "{order}");
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(r.energy.as_ref().unwrap()),
            bits(r1.energy.as_ref().unwrap()),
            "{order}, {threads} threads"
        );
        assert_eq!(bits(&v), bits(&v1), "{order}, {threads} threads");
    }
}

/// MultiColour, RedBlackChunks, Lexicographic and the direct solver (condensation plus
/// Newton: no Gauss–Seidel at all) agree to the stopping tolerance on the stick-slip
/// problem, with both stick and slip nodes present; the parallel orders' energy never
/// increases.
#[test]
fn parallel_orders_converge_to_the_lexicographic_minimiser() {
    for (m0, level, StickSlip { a, fixed, b, nl }) in stick_slip_levels() {
        let hierarchy = square_hierarchy(m0, level);
        let solve = |smoother| {
            let mut tn = Tnnmg::<1>::new(a.as_ref(), &fixed, &hierarchy, None, options(smoother))
                .unwrap()
                .with_parallelism(Parallelism::rayon(2));
            let mut v = vec![0.0; b.len()];
            let r = tn.solve(&b, &nl, &mut v).unwrap();
            (v, r)
        };
        let (v_lex, _) = solve(SmootherOrder::Lexicographic);
        let v_d = direct_minimiser(&a, &fixed, &b, &nl);
        let diff = |x: &[f64], y: &[f64]| relative_energy_distance(&a, x, y, &v_d);
        for order in [SmootherOrder::MultiColour, SmootherOrder::RedBlackChunks] {
            let (v, r) = solve(order);
            assert!(r
                .energy
                .as_ref()
                .unwrap()
                .windows(2)
                .all(|w| w[1] <= w[0] + 1e-14 * w[0].abs()));
            let (to_direct, to_lex) = (diff(&v, &v_d), diff(&v, &v_lex));
            assert!(to_direct < 1e-9, "{order}, level {level}: {to_direct}");
            assert!(to_lex < 1e-9, "{order}, level {level}: {to_lex}");
            assert_ne!(v, v_lex, "{order}: another order gives other rounding");
        }
        let stick = nl.nodes.iter().filter(|&&p| v_d[p] == 0.0).count();
        assert!(stick > 0 && stick < nl.nodes.len());
    }
}
