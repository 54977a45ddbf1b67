//! Faults inside the body: split nodes ([`SimplexMesh::split_along`], docs/math.md §13,
//! docs/faults-inside.md). Mesh invariants, typed errors on bad faults, and the antiplane
//! screw dislocation in a half-space against its closed form with a measured rate.
use rsf_fem::*;
use std::f64::consts::PI;

/// `[-2, 2] × [-2, 0]` with `n` cells per metre, surface tagged `surface`.
fn half_space(n: usize, diagonal: Diagonal) -> TriangleMesh {
    let mut m = rectangle([-2.0, -2.0], [4.0, 2.0], 4 * n + 1, 2 * n + 1, diagonal).unwrap();
    m.tag_boundary("surface", |x| x[1] > -1e-12);
    m
}

#[test]
fn split_keeps_cells_and_shares_the_tip() {
    for diagonal in [Diagonal::Forward, Diagonal::Backward] {
        let m = half_space(4, diagonal);
        let (s, sides) = m
            .split_along_segment("fault", [0.0, 0.0], [0.0, -1.0])
            .unwrap();
        // 5 fault nodes (y = 0, -0.25, ..., -1): 4 split, the tip at y = -1 shared.
        assert_eq!(sides.nodes().len(), 5);
        assert_eq!(sides.pairs().len(), 4);
        assert_eq!(s.num_vertices(), m.num_vertices() + 4);
        let tips = sides.tips();
        assert_eq!(tips.len(), 1);
        assert_eq!(s.vertices()[tips[0]], [0.0, -1.0]);
        // Every cell keeps its measure and orientation (positive), vertex by vertex.
        assert_eq!(s.num_cells(), m.num_cells());
        for c in 0..m.num_cells() {
            assert_eq!(s.cell_measure(c), m.cell_measure(c));
            assert!(s.cell_measure(c) > 0.0);
            for (&a, &b) in m.cell(c).iter().zip(s.cell(c)) {
                assert_eq!(m.vertices()[a], s.vertices()[b]);
            }
        }
        assert_eq!(s.measure(), m.measure());
        // Pairs sit at one place; plus copies are used by x > 0 cells only, minus by x < 0.
        for (mi, pl) in sides.pairs() {
            assert_eq!(s.vertices()[mi], s.vertices()[pl]);
            for c in 0..s.num_cells() {
                let cx: f64 = s.cell(c).iter().map(|&v| s.vertices()[v][0]).sum();
                if s.cell(c).contains(&pl) {
                    assert!(cx > 0.0);
                }
                if s.cell(c).contains(&mi) {
                    assert!(cx < 0.0);
                }
            }
        }
        // The faces: 4 per side, tagged, outward normals ±n with n = (1, 0) (plus is x > 0).
        assert_eq!(s.facets_with_tag("fault_minus").len(), 4);
        assert_eq!(s.facets_with_tag("fault_plus").len(), 4);
        for k in 0..4 {
            let n = sides.normals()[k];
            assert_eq!(n, [1.0, -0.0].map(|x: f64| x + 0.0));
            assert_eq!(s.boundary_facet_normal(sides.minus_facets()[k]), n);
            let p = s.boundary_facet_normal(sides.plus_facets()[k]);
            assert_eq!(p, [-n[0], -n[1]]);
        }
        // The old tags survive (the surface got two more facets: none, its nodes split).
        assert_eq!(
            s.facets_with_tag("surface").len(),
            m.facets_with_tag("surface").len()
        );
        // Boundary facets: old ones plus the 8 faces.
        assert_eq!(s.num_boundary_facets(), m.num_boundary_facets() + 8);
        // The split mesh refines (the cut stays open: its facets stay boundary facets).
        let fine = refine_red(&s).0;
        assert_eq!(fine.facets_with_tag("fault_plus").len(), 8);
    }
}

#[test]
fn a_through_going_fault_splits_both_ends_and_the_jump_is_measured() {
    let m = half_space(2, Diagonal::Forward);
    let (s, sides) = m.split_along_segment("f", [0.0, 0.0], [0.0, -2.0]).unwrap();
    assert!(sides.tips().is_empty());
    assert_eq!(s.num_vertices(), m.num_vertices() + 5);
    // u = sign(x) on the split mesh (plus copies get +1): the jump is 2 everywhere.
    let mut u = vec![0.0; s.num_vertices()];
    for (mi, pl) in sides.pairs() {
        u[mi] = -1.0;
        u[pl] = 1.0;
    }
    let j = sides.jump(&u, 1).unwrap();
    assert!(j.iter().all(|x| x == &vec![2.0]));
    assert!(matches!(
        sides.jump(&u[..3], 1),
        Err(Error::DimensionMismatch { .. })
    ));
}

#[test]
fn a_dipping_fault_splits_along_diagonals() {
    // Forward diagonals run from (i, j) to (i + 1, j + 1): a 45° fault.
    let m = half_space(2, Diagonal::Forward);
    let (s, sides) = m
        .split_along_segment("f", [-1.0, -1.0], [0.0, 0.0])
        .unwrap();
    assert_eq!(sides.pairs().len(), 1 + 1); // surface end and the middle node; tip at (-1,-1)
    assert_eq!(s.measure(), m.measure());
    let n = sides.normals()[0];
    let h = 0.5f64.sqrt();
    assert!((n[0] + h).abs() < 1e-15 && (n[1] - h).abs() < 1e-15);
}

#[test]
fn bad_faults_are_typed_errors() {
    let m = half_space(2, Diagonal::Forward);
    let nx = 9;
    let id = |i: usize, j: usize| i + nx * j; // x = -2 + i/2, y = -2 + j/2
    let err = |edges: &[[usize; 2]]| m.split_along("f", edges).unwrap_err();
    // Not a mesh edge (Forward has no (i+1, j) - (i, j+1) diagonal).
    assert_eq!(
        err(&[[id(4, 2), id(3, 3)]]),
        Error::FaultEdgeNotInMesh {
            edge: 0,
            vertices: [id(4, 2), id(3, 3)]
        }
    );
    assert!(matches!(
        err(&[[0, 10_000]]),
        Error::FaultEdgeNotInMesh { .. }
    ));
    assert_eq!(err(&[]), Error::EmptyFault);
    // On the outer boundary.
    assert!(matches!(
        err(&[[id(0, 4), id(1, 4)]]),
        Error::FaultEdgeOnBoundary { edge: 0, .. }
    ));
    // Repeated.
    assert!(matches!(
        err(&[[id(4, 4), id(4, 3)], [id(4, 3), id(4, 4)]]),
        Error::FaultEdgeRepeated { edge: 1, .. }
    ));
    // A branch (three edges at (4, 2)).
    let t = [
        [id(4, 3), id(4, 2)],
        [id(4, 2), id(4, 1)],
        [id(4, 2), id(5, 2)],
    ];
    assert_eq!(
        err(&t),
        Error::FaultNotManifold {
            vertex: id(4, 2),
            edges: 3
        }
    );
    // A crossing (four edges at (4, 2)) is caught at its third.
    let x = [
        [id(4, 3), id(4, 2)],
        [id(4, 2), id(4, 1)],
        [id(3, 2), id(4, 2)],
        [id(4, 2), id(5, 2)],
    ];
    assert!(matches!(
        err(&x),
        Error::FaultNotManifold { vertex, .. } if vertex == id(4, 2)
    ));
    // A closed curve (a square around one cell pair).
    let sq = [
        [id(3, 1), id(4, 1)],
        [id(4, 1), id(4, 2)],
        [id(4, 2), id(3, 2)],
        [id(3, 2), id(3, 1)],
    ];
    assert!(matches!(err(&sq), Error::FaultClosed { .. }));
    // Two pieces.
    let two = [[id(2, 2), id(2, 3)], [id(6, 2), id(6, 3)]];
    assert_eq!(err(&two), Error::FaultDisconnected { vertex: id(6, 2) });
    // A chain touching the surface in its middle: the sides there are not two.
    let v = [[id(3, 3), id(4, 4)], [id(4, 4), id(4, 3)]];
    assert_eq!(err(&v), Error::FaultSidesNotSeparated { vertex: id(4, 4) });
    // A segment the mesh does not resolve (ends inside a cell; off the grid lines).
    assert!(matches!(
        m.split_along_segment("f", [0.0, 0.0], [0.0, -0.9]),
        Err(Error::FaultSegmentNotResolved { .. })
    ));
    assert!(matches!(
        m.split_along_segment("f", [0.1, 0.0], [0.1, -1.0]),
        Err(Error::FaultSegmentNotResolved { .. })
    ));
    assert!(matches!(
        m.split_along_segment("f", [0.0, 0.0], [0.0, 0.0]),
        Err(Error::FaultSegmentNotResolved { .. })
    ));
}

/// Antiplane screw dislocation: uniform slip `s` on x = 0, −W < y < 0, in the half-space
/// y < 0 with a traction-free surface. With the image fault on 0 < y < W the surface is
/// traction-free by symmetry, and the jump `s` across the segment |y| < W of a whole space
/// is carried by the difference of two angles:
/// `u(x, y) = (s/2π)[atan((y + W)/x) − atan((y − W)/x)]`, so `u(x, 0) = (s/π) atan(W/x)`.
/// `side = ±1` picks the limit on x = 0.
fn screw(x: [f64; 2], s: f64, w: f64, side: f64) -> f64 {
    if x[0] == 0.0 {
        return if x[1].abs() < w { side * s / 2.0 } else { 0.0 };
    }
    s / (2.0 * PI) * (((x[1] + w) / x[0]).atan() - ((x[1] - w) / x[0]).atan())
}

/// Solves `−∇·(μ∇u) = 0` on the split mesh with `u⁺ − u⁻ = s` at every pair (the plus
/// unknowns eliminated: `u = P v + o`, `P`ᵀ`K P v = −P`ᵀ`K o`), the closed form as
/// Dirichlet data on x = ±2 and y = −2, the surface traction-free. Returns the split mesh,
/// its sides, `u` and the residual `K u`.
fn solve_screw(n: usize, s_slip: f64, w: f64) -> (TriangleMesh, FaultSides, Vec<f64>, Vec<f64>) {
    let m = half_space(n, Diagonal::Forward);
    let (mesh, sides) = m
        .split_along_segment("fault", [0.0, 0.0], [0.0, -w])
        .unwrap();
    let nv = mesh.num_vertices();
    let k = Assembler::scalar(&mesh)
        .unwrap()
        .laplace(&mesh, 1.0)
        .unwrap();
    let mut map: Vec<usize> = (0..nv).collect();
    let mut offset = vec![0.0; nv];
    let mut side = vec![0.0; nv];
    for (mi, pl) in sides.pairs() {
        map[pl] = mi;
        offset[pl] = s_slip;
        side[pl] = 1.0;
        side[mi] = -1.0;
    }
    let mut trip = Vec::new();
    let kr = k.as_ref();
    for j in 0..nv {
        for (i, v) in kr.row_idx_of_col(j).zip(kr.val_of_col(j)) {
            trip.push(faer::sparse::Triplet::new(map[i], map[j], *v));
        }
    }
    let kt =
        faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(nv, nv, &trip).unwrap();
    let mut b = vec![0.0; nv];
    let mut ko = vec![0.0; nv];
    spmv_add(k.as_ref(), 1.0, &offset, &mut ko);
    for i in 0..nv {
        b[map[i]] -= ko[i];
    }
    let mut fixed = vec![false; nv];
    let mut x = vec![0.0; nv];
    for i in 0..nv {
        let p = mesh.vertices()[i];
        if map[i] != i {
            fixed[i] = true; // eliminated plus copy
        } else if p[0].abs() > 2.0 - 1e-12 || p[1] < -2.0 + 1e-12 {
            fixed[i] = true;
            x[i] = screw(p, s_slip, w, side[i]);
        }
    }
    let mut sys = ConstrainedSystem::new(kt.as_ref(), &fixed).unwrap();
    sys.solve(&b, &mut x).unwrap();
    let u: Vec<f64> = (0..nv).map(|i| x[map[i]] + offset[i]).collect();
    let mut r = vec![0.0; nv];
    spmv_add(k.as_ref(), 1.0, &u, &mut r);
    (mesh, sides, u, r)
}

#[test]
fn screw_dislocation_matches_the_closed_form_at_first_order() {
    let (s_slip, w) = (1.0, 1.0);
    let mut errors = Vec::new();
    for n in [4, 8, 16, 32] {
        let (mesh, sides, u, r) = solve_screw(n, s_slip, w);
        // The slip is imposed exactly, tractions are equal and opposite (the residual of a
        // pair sums to zero: one equation for the pair's mean), the tip is shared.
        let scale = r.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        for (j, &(mi, pl)) in sides.nodes().iter().enumerate() {
            let jump = sides.jump(&u, 1).unwrap()[j][0];
            if mi != pl {
                assert!((jump - s_slip).abs() < 1e-12);
                assert!((r[mi] + r[pl]).abs() < 1e-10 * scale, "{} {}", r[mi], r[pl]);
                assert!(r[mi].abs() > 1e-3 * scale);
            } else {
                assert_eq!(jump, 0.0);
            }
        }
        // Max error on the surface, both sides of the fault included.
        let mut side = vec![0.0; mesh.num_vertices()];
        for (mi, pl) in sides.pairs() {
            side[mi] = -1.0;
            side[pl] = 1.0;
        }
        let e = (0..mesh.num_vertices())
            .filter(|&i| mesh.vertices()[i][1] == 0.0)
            .map(|i| (u[i] - screw(mesh.vertices()[i], s_slip, w, side[i])).abs())
            .fold(0.0f64, f64::max);
        errors.push(e);
    }
    let rates: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    eprintln!("screw dislocation surface max errors {errors:?}, rates {rates:?}");
    // The tip is shared, so the discrete slip falls from s to 0 over the last element: an
    // O(h) change of the source, first order at the surface.
    for r in &rates {
        assert!(*r > 0.9, "rates {rates:?}");
    }
    assert!(errors[3] < 0.02);
}
