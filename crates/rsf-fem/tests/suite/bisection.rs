//! Graded meshes by newest-vertex bisection of a Kuhn box (`BisectionMesh`). Expected values
//! are closed forms of the geometry (volumes, areas, the Kuhn grid of half the size),
//! never the code's own output.
use crate::common::{boundary_area, graded_from_origin, plane_facets};
use rsf_fem::*;

/// Sorted edge lengths divided by the longest: equal for similar tetrahedra.
fn shape(m: &TetrahedronMesh, c: usize) -> [f64; 6] {
    let x: Vec<[f64; 3]> = m.cell(c).iter().map(|&v| m.vertices()[v]).collect();
    let mut l = Vec::with_capacity(6);
    for i in 0..4 {
        for j in i + 1..4 {
            l.push(
                (0..3)
                    .map(|r| (x[i][r] - x[j][r]).powi(2))
                    .sum::<f64>()
                    .sqrt(),
            );
        }
    }
    l.sort_by(f64::total_cmp);
    let longest = l[5];
    [0, 1, 2, 3, 4, 5].map(|k| l[k] / longest)
}

/// Number of similarity classes among the cells (to 1e-9).
fn classes(m: &TetrahedronMesh) -> usize {
    let mut reps: Vec<[f64; 6]> = Vec::new();
    for c in 0..m.num_cells() {
        let s = shape(m, c);
        if !reps
            .iter()
            .any(|r| r.iter().zip(&s).all(|(a, b)| (a - b).abs() < 1e-9))
        {
            reps.push(s);
        }
    }
    reps.len()
}

#[test]
fn three_generations_of_a_kuhn_cube_are_the_kuhn_cells_of_the_half_cubes() {
    let mut b = BisectionMesh::kuhn_box([0.0; 3], [1.0; 3], 1.0).unwrap();
    let report = b.refine(|_, _| 0.5, 1000).unwrap();
    assert_eq!(report.by_closure, 0, "uniform bisection needs no closure");
    let m = b.into_mesh().unwrap();
    // 6 · 2³ tetrahedra on the 3 × 3 × 3 lattice of the half cubes.
    assert_eq!(m.num_cells(), 48);
    assert_eq!(m.num_vertices(), 27);
    for v in m.vertices() {
        assert!(v
            .iter()
            .all(|&x| (2.0 * x - (2.0 * x).round()).abs() < 1e-15));
    }
    for c in 0..m.num_cells() {
        assert!((m.cell_measure(c) - 1.0 / 48.0).abs() < 1e-15);
    }
    // Every cell congruent to a Kuhn tetrahedron of edge ½: edges ½, ½, ½, ½√2, ½√2, ½√3.
    let kuhn = [1.0, 1.0, 1.0, 2f64.sqrt(), 2f64.sqrt(), 3f64.sqrt()].map(|l| l / 3f64.sqrt());
    for c in 0..m.num_cells() {
        let s = shape(&m, c);
        assert!(
            s.iter().zip(&kuhn).all(|(a, b)| (a - b).abs() < 1e-12),
            "{s:?}"
        );
    }
    assert!((boundary_area(&m) - 6.0).abs() < 1e-12);
    assert_eq!(m.num_boundary_facets(), 6 * 8);
}

#[test]
fn refinement_towards_a_corner_is_conforming_graded_and_keeps_three_shapes() {
    let h = 1.0 / 64.0;
    let size = graded_from_origin(h, 0.4);
    let mut b = BisectionMesh::kuhn_box([-1.0; 3], [1.0; 3], 1.0).unwrap();
    let report = b.refine(&size, 10_000_000).unwrap();
    assert!(report.by_closure > 0, "local refinement needs the closure");
    let m = b.into_mesh().unwrap();
    // Conforming: no facet inside the body belongs to one cell only.
    assert!(
        (boundary_area(&m) - 24.0).abs() < 1e-9,
        "{}",
        boundary_area(&m)
    );
    assert!((m.measure() - 8.0).abs() < 1e-12);
    // The sizes asked for: every cell at most `size` over its box (the refinement's stop).
    for c in 0..m.num_cells() {
        let x: Vec<[f64; 3]> = m.cell(c).iter().map(|&v| m.vertices()[v]).collect();
        let mut lo = x[0];
        let mut hi = x[0];
        for p in &x {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let cube = (6.0 * m.cell_measure(c)).cbrt();
        assert!(cube <= size(lo, hi) * (1.0 + 1e-9));
    }
    // The cells at the corner are the finest wanted (edge h's Kuhn cells: volume h³/6).
    let finest = (0..m.num_cells())
        .map(|c| m.cell_measure(c))
        .fold(f64::INFINITY, f64::min);
    assert!((finest - h.powi(3) / 6.0).abs() < 1e-9 * finest);
    // Graded: far fewer vertices than the uniform grid of h (129³ ≈ 2.1e6).
    assert!(
        m.num_vertices() < 129usize.pow(3) / 50,
        "{}",
        m.num_vertices()
    );
    // Maubach's bound: three shapes up to similarity at any depth.
    assert!(classes(&m) <= 3, "{} shapes", classes(&m));
    let uniform = {
        let mut b = BisectionMesh::kuhn_box([0.0; 3], [1.0; 3], 1.0).unwrap();
        b.refine(|_, _| 0.25, 10_000).unwrap();
        b.into_mesh().unwrap()
    };
    assert!((m.min_dihedral_angle() - uniform.min_dihedral_angle()).abs() < 1e-12);
}

#[test]
fn a_plane_of_the_root_grid_stays_tiled_by_facets() {
    // Refined towards a point off the plane x = 0: the facets in the plane still cover it.
    let size = |lo: [f64; 3], hi: [f64; 3]| {
        let d = (0..3)
            .map(|a| {
                let c = [0.3, 0.1, -0.2][a];
                (lo[a] - c).max(c - hi[a]).max(0.0).powi(2)
            })
            .sum::<f64>()
            .sqrt();
        0.03 + 0.5 * d
    };
    let mut b = BisectionMesh::kuhn_box([-1.0, -1.0, -1.0], [1.0, 1.0, 0.0], 0.5).unwrap();
    b.refine(size, 10_000_000).unwrap();
    let m = b.into_mesh().unwrap();
    let area: f64 = plane_facets(&m).iter().map(|(_, a)| a).sum();
    assert!((area - 2.0).abs() < 1e-12, "{area}");
}

#[test]
fn bad_boxes_sizes_and_budgets_are_refused() {
    assert!(BisectionMesh::kuhn_box([0.0; 3], [1.5, 1.0, 1.0], 1.0).is_err());
    assert!(BisectionMesh::kuhn_box([0.0; 3], [1.0; 3], 0.0).is_err());
    assert!(BisectionMesh::kuhn_box([0.0; 3], [1.0, f64::NAN, 1.0], 1.0).is_err());
    let mut b = BisectionMesh::kuhn_box([0.0; 3], [1.0; 3], 1.0).unwrap();
    assert!(b.refine(|_, _| f64::NAN, 1000).is_err());
    assert!(b.refine(|_, _| -1.0, 1000).is_err());
    let before = b.num_cells();
    let e = b.refine(|_, _| 1e-3, 10_000).unwrap_err();
    assert!(e.to_string().contains("10000 cells"), "{e}");
    assert!(b.num_cells() <= 10_000 && b.num_cells() >= before);
}
