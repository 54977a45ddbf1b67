//! Tetrahedral meshes: the Kuhn box, orientation checks, red refinement (Bey) and its
//! prolongations. Expected values are closed forms of the geometry, never the code's output.
use rsf_fem::*;

/// Sorted edge lengths divided by the longest: equal for similar tetrahedra.
fn shape(m: &TetrahedronMesh, c: usize) -> [f64; 6] {
    let x: Vec<[f64; 3]> = m.cell(c).iter().map(|&v| m.vertices()[v]).collect();
    let mut l = [0.0; 6];
    let mut k = 0;
    for i in 0..4 {
        for j in i + 1..4 {
            l[k] = (0..3)
                .map(|r| (x[i][r] - x[j][r]).powi(2))
                .sum::<f64>()
                .sqrt();
            k += 1;
        }
    }
    l.sort_by(f64::total_cmp);
    l.map(|v| v / l[5])
}

/// Number of similarity classes among `shapes` (to 1e-9).
fn classes(shapes: &[[f64; 6]]) -> usize {
    let mut reps: Vec<[f64; 6]> = Vec::new();
    for s in shapes {
        if !reps
            .iter()
            .any(|r| r.iter().zip(s).all(|(a, b)| (a - b).abs() < 1e-9))
        {
            reps.push(*s);
        }
    }
    reps.len()
}

fn centroid(m: &TetrahedronMesh, c: usize) -> [f64; 3] {
    let mut p = [0.0; 3];
    for &v in m.cell(c) {
        for r in 0..3 {
            p[r] += 0.25 * m.vertices()[v][r];
        }
    }
    p
}

#[test]
fn kuhn_box_volumes_counts_orientation() {
    let (o, s) = ([0.5, -1.0, 2.0], [2.0, 1.0, 1.5]);
    let m = cuboid(o, s, [4, 3, 5]).unwrap();
    assert_eq!(m.num_vertices(), 60);
    assert_eq!(m.num_cells(), 6 * 3 * 2 * 4);
    assert!((m.measure() - 3.0).abs() < 1e-13);
    let cell_volume = (2.0 / 3.0) * (1.0 / 2.0) * (1.5 / 4.0);
    for c in 0..m.num_cells() {
        assert!((m.cell_measure(c) - cell_volume / 6.0).abs() < 1e-15);
    }
    // 2 triangles per boundary square.
    assert_eq!(m.num_boundary_facets(), 4 * (3 * 2 + 2 * 4 + 3 * 4));
    let area: f64 = (0..m.num_boundary_facets())
        .map(|f| m.boundary_facet_measure(f))
        .sum();
    assert!((area - 2.0 * (2.0 * 1.0 + 1.0 * 1.5 + 2.0 * 1.5)).abs() < 1e-13);
    // Outward unit normals: ±e_k, pointing away from the cell the facet belongs to.
    for f in 0..m.num_boundary_facets() {
        let n = m.boundary_facet_normal(f);
        let xm = m.boundary_facet_midpoint(f);
        let xc = centroid(&m, m.boundary_facet_cell(f));
        let away: f64 = (0..3).map(|r| n[r] * (xm[r] - xc[r])).sum();
        assert!(away > 0.0);
        let k = (0..3).find(|&k| n[k].abs() > 0.5).unwrap();
        assert!((n[k].abs() - 1.0).abs() < 1e-15);
        let on_low = (xm[k] - o[k]).abs() < 1e-12;
        let on_high = (xm[k] - o[k] - s[k]).abs() < 1e-12;
        assert!((on_low && n[k] < 0.0) || (on_high && n[k] > 0.0));
    }
    // All Kuhn tetrahedra of a cube are congruent.
    let c = cuboid([0.0; 3], [1.0; 3], [3, 3, 3]).unwrap();
    let shapes: Vec<_> = (0..c.num_cells()).map(|k| shape(&c, k)).collect();
    assert_eq!(classes(&shapes), 1);
    let r2 = 2f64.sqrt();
    let kuhn = [1.0, 1.0, 1.0, r2, r2, 3f64.sqrt()].map(|v| v / 3f64.sqrt());
    assert!(shapes[0]
        .iter()
        .zip(kuhn)
        .all(|(a, b)| (a - b).abs() < 1e-15));
}

#[test]
fn invalid_tetrahedra_and_boxes_are_rejected() {
    let v = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    assert!(TetrahedronMesh::new(v.clone(), vec![0, 1, 2, 3]).is_ok());
    assert!(matches!(
        TetrahedronMesh::new(v.clone(), vec![0, 2, 1, 3]),
        Err(Error::InvertedCell { cell: 0, .. })
    ));
    // The same cell given negatively is accepted (and stored positively) when reoriented.
    let m = TetrahedronMesh::from_ordered_cells(v.clone(), vec![0, 2, 1, 3]).unwrap();
    assert!((m.cell_measure(0) - 1.0 / 6.0).abs() < 1e-16);
    let flat = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 1e-14],
    ];
    assert!(matches!(
        TetrahedronMesh::from_ordered_cells(flat, vec![0, 1, 2, 3]),
        Err(Error::DegenerateCell { cell: 0, .. })
    ));
    assert!(matches!(
        TetrahedronMesh::new(v.clone(), vec![0, 1, 2, 4]),
        Err(Error::VertexOutOfRange { vertex: 4, .. })
    ));
    assert!(matches!(
        TetrahedronMesh::new(v, vec![0, 1, 2]),
        Err(Error::BadConnectivity { stride: 4, .. })
    ));
    assert!(matches!(
        cuboid([0.0; 3], [1.0; 3], [2, 1, 2]),
        Err(Error::InvalidGrid(_))
    ));
    assert!(matches!(
        cuboid([0.0; 3], [1.0, 0.0, 1.0], [2, 2, 2]),
        Err(Error::InvalidGrid(_))
    ));
    assert!(matches!(
        cuboid([0.0; 3], [1.0, f64::INFINITY, 1.0], [2, 2, 2]),
        Err(Error::InvalidGrid(_))
    ));
    assert!(matches!(
        cuboid([0.0, f64::NAN, 0.0], [1.0; 3], [2, 2, 2]),
        Err(Error::NonFiniteCoordinate { .. })
    ));
    assert!(matches!(
        cuboid([0.0; 3], [1.0; 3], [usize::MAX, 2, 2]),
        Err(Error::InvalidGrid(_))
    ));
}

/// Checks one level of refinement against its parent: counts, volume, children inside
/// their parent, tags with their areas and planes, prolongations exact for linear fields.
fn check_refinement(c: &TetrahedronMesh, f: &TetrahedronMesh, h: &MeshHierarchy<3>, j: usize) {
    assert_eq!(f.num_cells(), 8 * c.num_cells());
    assert_eq!(f.num_boundary_facets(), 4 * c.num_boundary_facets());
    assert!((f.measure() - c.measure()).abs() < 1e-12 * c.measure());
    // The children of cell k are cells 8k..8k+8 and lie inside it (barycentric coordinates
    // of their centroids in the parent are positive).
    for k in 0..c.num_cells() {
        let x: Vec<[f64; 3]> = c.cell(k).iter().map(|&v| c.vertices()[v]).collect();
        let vol = c.cell_measure(k);
        let mut sum = 0.0;
        for child in 8 * k..8 * k + 8 {
            sum += f.cell_measure(child);
            let p = centroid(f, child);
            for a in 0..4 {
                let mut y = x.clone();
                y[a] = p;
                let sub = TetrahedronMesh::from_ordered_cells(y, vec![0, 1, 2, 3])
                    .map(|m| m.cell_measure(0))
                    .unwrap_or(0.0);
                assert!(sub > 0.0, "child {child} outside parent {k}");
            }
        }
        assert!((sum - vol).abs() < 1e-13 * vol);
    }
    for tag in c.tag_names() {
        let area = |m: &TetrahedronMesh| -> f64 {
            m.facets_with_tag(tag)
                .iter()
                .map(|&i| m.boundary_facet_measure(i))
                .sum()
        };
        assert_eq!(
            f.facets_with_tag(tag).len(),
            4 * c.facets_with_tag(tag).len()
        );
        assert!((area(f) - area(c)).abs() < 1e-12, "{tag}");
    }
    let lin = |x: &[f64; 3]| 0.3 + 1.7 * x[0] - 2.9 * x[1] + 0.6 * x[2];
    let uc: Vec<f64> = c.vertices().iter().map(lin).collect();
    let mut uf = vec![0.0; f.num_vertices()];
    spmv_add(h.prolongation(j).as_ref(), 1.0, &uc, &mut uf);
    for (v, x) in uf.iter().zip(f.vertices()) {
        assert!((v - lin(x)).abs() < 1e-13);
    }
    let vc: Vec<f64> = c
        .vertices()
        .iter()
        .flat_map(|x| [lin(x), 2.0 * x[0] + x[1], x[2] - x[0]])
        .collect();
    let mut vf = vec![0.0; 3 * f.num_vertices()];
    spmv_add(h.vector_prolongation(j).as_ref(), 1.0, &vc, &mut vf);
    for (i, x) in f.vertices().iter().enumerate() {
        assert!((vf[3 * i] - lin(x)).abs() < 1e-13);
        assert!((vf[3 * i + 1] - 2.0 * x[0] - x[1]).abs() < 1e-13);
        assert!((vf[3 * i + 2] - x[2] + x[0]).abs() < 1e-13);
    }
}

#[test]
fn kuhn_refinement_keeps_one_shape_and_the_dihedral_angle() {
    let mut coarse = cuboid([0.0; 3], [1.0; 3], [3, 3, 3]).unwrap();
    coarse.tag_boundary("bottom", |x| x[2] < 1e-12);
    coarse.tag_boundary("top", |x| x[2] > 1.0 - 1e-12);
    coarse.tag_boundary("sides", |x| x[2] > 1e-12 && x[2] < 1.0 - 1e-12);
    let h = MeshHierarchy::refine_uniformly(coarse, 3);
    let angle0 = h.level(0).min_dihedral_angle();
    // The Kuhn tetrahedron (a cube's orthoscheme) has dihedral angles π/4, π/3, π/4 at
    // its path edges and π/2 at the others.
    assert!(
        (angle0 - std::f64::consts::FRAC_PI_4).abs() < 1e-12,
        "{angle0}"
    );
    let shape0 = shape(h.level(0), 0);
    for j in 1..=3 {
        let (c, f) = (h.level(j - 1), h.level(j));
        check_refinement(c, f, &h, j);
        assert!(f.min_dihedral_angle() >= c.min_dihedral_angle() - 1e-12);
        // Bey's children of Kuhn tetrahedra are Kuhn tetrahedra: one shape at every level.
        for k in 0..f.num_cells() {
            let s = shape(f, k);
            assert!(s.iter().zip(shape0).all(|(a, b)| (a - b).abs() < 1e-12));
        }
        for i in f.facets_with_tag("bottom") {
            assert!(f.boundary_facet_midpoint(i)[2].abs() < 1e-14);
        }
        for i in f.facets_with_tag("top") {
            assert!((f.boundary_facet_midpoint(i)[2] - 1.0).abs() < 1e-14);
        }
    }
}

/// A tetrahedral mesh of the unit cube that is not a Kuhn mesh: the 5-tetrahedron split
/// (four corners + a regular inner tetrahedron) with perturbed vertices, some cells given
/// in negative order.
fn five_tet_cube() -> TetrahedronMesh {
    let mut v = Vec::new();
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..2 {
                let s = ((i + 2 * j + 4 * k) as f64).sin();
                v.push([
                    i as f64 + 0.05 * s,
                    j as f64 - 0.04 * s,
                    k as f64 + 0.03 * s,
                ]);
            }
        }
    }
    // Corners 0,3,5,6 form the inner tetrahedron.
    let cells = vec![
        1, 0, 3, 5, // negative order
        2, 3, 0, 6, //
        4, 5, 6, 0, //
        7, 6, 5, 3, //
        0, 3, 5, 6, //
    ];
    TetrahedronMesh::from_ordered_cells(v, cells).unwrap()
}

#[test]
fn bey_refinement_of_a_general_mesh_has_at_most_three_shapes() {
    let mut coarse = five_tet_cube();
    coarse.tag_boundary("low", |x| x[2] < 0.3);
    let h = MeshHierarchy::refine_uniformly(coarse, 3);
    let n0 = h.level(0).num_cells();
    for j in 1..=3 {
        check_refinement(h.level(j - 1), h.level(j), &h, j);
    }
    // Bey (1995): the descendants of every coarse tetrahedron (with their orders) fall
    // into at most three similarity classes.
    for c in 0..n0 {
        let mut shapes = vec![shape(h.level(0), c)];
        for j in 1..=3 {
            let per = 8usize.pow(j as u32);
            shapes.extend((c * per..(c + 1) * per).map(|k| shape(h.level(j), k)));
        }
        assert!(
            classes(&shapes) <= 3,
            "cell {c}: {} classes",
            classes(&shapes)
        );
    }
    // Hence the smallest dihedral angle stays fixed from level 1 on.
    let a1 = h.level(1).min_dihedral_angle();
    for j in 2..=3 {
        assert!((h.level(j).min_dihedral_angle() - a1).abs() < 1e-10);
    }
    assert!(a1 > 0.1);
}

#[test]
fn refinement_of_a_near_degenerate_cell_is_an_error_not_a_panic() {
    // A sliver whose edges x0x2 and x1x3 are short: volume ε²/6 just above the
    // constructor's threshold 1e-12·h³ (h ≈ 1), while the inner children keep edges of
    // length ≈ 1 (x02 to x13) at 1/8 of the volume, below the threshold.
    let e = 1.2e-11f64.sqrt();
    let v = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, e, 0.0],
        [1.0, 0.0, e],
    ];
    let m = TetrahedronMesh::new(v, vec![0, 1, 2, 3]).unwrap();
    assert!(matches!(
        MeshHierarchy::try_refine_uniformly(m.clone(), 1),
        Err(Error::DegenerateCell { .. })
    ));
    assert!(matches!(
        try_refine_red(&m),
        Err(Error::DegenerateCell { .. })
    ));
}

/// `facets()` lists every facet once: each interior facet is shared by two cells and each
/// boundary facet belongs to one, so 4·cells = 2·interior + boundary; and every boundary
/// facet is among them.
#[test]
fn facets_lists_every_facet_once() {
    let mesh = cuboid([0.0; 3], [1.0, 2.0, 3.0], [3, 4, 5]).unwrap();
    let facets = mesh.facets();
    let boundary = mesh.num_boundary_facets();
    assert_eq!(2 * facets.len(), 4 * mesh.num_cells() + boundary);
    let key = |f: &[usize]| {
        let mut k = f.to_vec();
        k.sort_unstable();
        k
    };
    let all: std::collections::HashSet<Vec<usize>> = facets.iter().map(|f| key(f)).collect();
    assert_eq!(all.len(), facets.len());
    for b in 0..boundary {
        assert!(all.contains(&key(mesh.boundary_facet(b))));
    }
}

/// The vertex graph is the node graph of the assembled matrices' pattern (every pair of
/// vertices of a cell coupled): a Kuhn box refined once and a triangle mesh, against the
/// block pattern of the vector stiffness assembler, read column by column.
#[test]
fn the_vertex_graph_is_the_matrices_node_graph() {
    fn node_graph<const D: usize>(mesh: &SimplexMesh<D>) -> (Vec<usize>, Vec<usize>) {
        let pattern = Assembler::<D>::new(mesh)
            .unwrap()
            .pattern()
            .to_owned()
            .unwrap();
        let n = mesh.num_vertices();
        let (mut xadj, mut adjncy) = (vec![0], Vec::new());
        for p in 0..n {
            let mut row: Vec<usize> = pattern
                .row_idx_of_col(D * p)
                .map(|i| i / D)
                .filter(|&q| q != p)
                .collect();
            row.dedup();
            adjncy.extend(row);
            xadj.push(adjncy.len());
        }
        (xadj, adjncy)
    }
    let cube = MeshHierarchy::try_refine_uniformly(
        cuboid([0.0; 3], [1.0, 2.0, 1.0], [2, 3, 2]).unwrap(),
        1,
    )
    .unwrap()
    .finest()
    .clone();
    assert_eq!(cube.vertex_graph(), node_graph(&cube));
    let square = rectangle([0.0; 2], [2.0, 1.0], 4, 3, Diagonal::Forward).unwrap();
    assert_eq!(square.vertex_graph(), node_graph(&square));
}
