//! Graded meshes from an octree of Kuhn cubes (`OctreeMesh`). Expected values are closed
//! forms of the geometry (volumes, areas, the tensor grid's Kuhn cells, lumped weights of
//! a uniform grid), never the code's own output.
use crate::common::{boundary_area, graded_from_origin, plane_facets};
use rsf_fem::*;

#[test]
fn uniform_refinement_is_the_tensor_grids_kuhn_box() {
    let mut o = OctreeMesh::new([0.0; 3], [2.0, 1.0, 1.0], 1.0).unwrap();
    let report = o.refine(|_, _| 0.25, 100_000).unwrap();
    assert_eq!(report.by_balance, 0);
    assert_eq!(o.num_vertices(), 9 * 5 * 5);
    let m = o.into_mesh().unwrap();
    let kuhn = cuboid([0.0; 3], [2.0, 1.0, 1.0], [9, 5, 5]).unwrap();
    assert_eq!(m.num_cells(), kuhn.num_cells());
    assert_eq!(m.num_vertices(), kuhn.num_vertices());
    // The same cells (as vertex sets of coordinates).
    let cells = |mesh: &TetrahedronMesh| {
        let mut all: Vec<Vec<[i64; 3]>> = (0..mesh.num_cells())
            .map(|c| {
                let mut v: Vec<[i64; 3]> = mesh
                    .cell(c)
                    .iter()
                    .map(|&p| mesh.vertices()[p].map(|x| (x * 4.0).round() as i64))
                    .collect();
                v.sort_unstable();
                v
            })
            .collect();
        all.sort_unstable();
        all
    };
    assert_eq!(cells(&m), cells(&kuhn));
}

#[test]
fn refinement_towards_a_corner_is_conforming_balanced_and_keeps_the_kuhn_cells_there() {
    let h = 1.0 / 32.0;
    let mut o = OctreeMesh::new([-1.0; 3], [1.0; 3], 1.0).unwrap();
    let report = o.refine(graded_from_origin(h, 0.4), 10_000_000).unwrap();
    assert!(report.by_size > 0);
    let counted = o.num_vertices();
    let m = o.into_mesh().unwrap();
    // The count without the mesh is the mesh's (transition cubes' centres included).
    assert_eq!(counted, m.num_vertices());
    assert!(
        (boundary_area(&m) - 24.0).abs() < 1e-9,
        "{}",
        boundary_area(&m)
    );
    assert!((m.measure() - 8.0).abs() < 1e-12);
    // Graded: far fewer vertices than the uniform grid of h (65³ ≈ 2.7e5).
    assert!(
        m.num_vertices() < 65usize.pow(3) / 20,
        "{}",
        m.num_vertices()
    );
    // The cells at the corner are the tensor grid's Kuhn cells of edge h.
    let finest = (0..m.num_cells())
        .map(|c| m.cell_measure(c))
        .fold(f64::INFINITY, f64::min);
    assert!((finest - h.powi(3) / 6.0).abs() < 1e-9 * finest, "{finest}");
    // Transition cubes keep a bounded shape.
    assert!(
        m.min_dihedral_angle() > 15f64.to_radians(),
        "{}",
        m.min_dihedral_angle().to_degrees()
    );
}

/// On a plane of the grid meshed at the finest level, every interior node's lumped weight
/// is the cell's area (the tensor grid's parallel diagonals: six triangles of half a cell
/// each), where bisection's alternating diagonals give 2/3 and 4/3 of it.
#[test]
fn a_plane_at_the_finest_level_is_tiled_with_parallel_diagonals() {
    let h = 0.125;
    // Fine within 0.5 of the square x = 0, |y|, |z| ≤ 0.5; growing beyond.
    let size = |lo: [f64; 3], hi: [f64; 3]| {
        let d = (0..3)
            .map(|a| {
                let (l, u) = if a == 0 { (0.0, 0.0) } else { (-0.5, 0.5) };
                (lo[a] - u).max(l - hi[a]).max(0.0).powi(2)
            })
            .sum::<f64>()
            .sqrt();
        h + 0.5 * d
    };
    let mut o = OctreeMesh::new([-2.0; 3], [2.0; 3], 1.0).unwrap();
    o.refine(size, 10_000_000).unwrap();
    let counted = o.num_vertices();
    let m = o.into_mesh().unwrap();
    assert_eq!(counted, m.num_vertices());
    let facets = plane_facets(&m);
    let total: f64 = facets.iter().map(|f| f.1).sum();
    assert!((total - 16.0).abs() < 1e-12, "the plane is tiled: {total}");
    let mut weight = std::collections::HashMap::new();
    for (f, area) in &facets {
        for &v in f {
            *weight.entry(v).or_insert(0.0) += area / 3.0;
        }
    }
    let mut checked = 0;
    for (&v, &w) in &weight {
        let x = m.vertices()[v];
        if x[1].abs() < 0.45 && x[2].abs() < 0.45 {
            assert!(
                (w - h * h).abs() < 1e-12,
                "node at {x:?}: {} cells",
                w / (h * h)
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 49);
}

#[test]
fn bad_boxes_sizes_and_budgets_are_refused() {
    assert!(OctreeMesh::new([0.0; 3], [1.5, 1.0, 1.0], 1.0).is_err());
    assert!(OctreeMesh::new([0.0; 3], [1.0; 3], -1.0).is_err());
    let mut o = OctreeMesh::new([0.0; 3], [1.0; 3], 1.0).unwrap();
    assert!(o.refine(|_, _| f64::NAN, 1000).is_err());
    let e = o.refine(|_, _| 1e-3, 10_000).unwrap_err();
    assert!(e.to_string().contains("10000"), "{e}");
}
