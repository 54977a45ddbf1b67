use rsf_fem::*;

#[test]
fn slider_coarse_grid_matches_paper() {
    let m = pipping_slider_coarse(Diagonal::Forward);
    assert_eq!(m.num_vertices(), 12);
    assert_eq!(m.num_cells(), 10);
    assert!((m.measure() - 5.0).abs() < 1e-14);
    assert_eq!(m.num_boundary_facets(), 12);
    assert_eq!(m.facets_with_tag(TAG_DIRICHLET).len(), 5);
    assert_eq!(m.facets_with_tag(TAG_FRICTIONAL).len(), 5);
    assert_eq!(m.facets_with_tag(TAG_NEUMANN).len(), 2);
    for c in 0..m.num_cells() {
        assert!(m.cell_measure(c) > 0.0);
    }
    let b = rectangle([0.0, 0.0], [5.0, 1.0], 6, 2, Diagonal::Backward).unwrap();
    assert_eq!(b.num_cells(), 10);
    assert!((b.measure() - 5.0).abs() < 1e-14);
}

#[test]
fn invalid_meshes_are_rejected() {
    let v = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    assert!(matches!(
        TriangleMesh::new(vec![[0.0, 0.0], [f64::NAN, 0.0], [0.0, 1.0]], vec![0, 1, 2]),
        Err(Error::NonFiniteCoordinate { vertex: 1 })
    ));
    assert!(matches!(
        TriangleMesh::new(
            vec![[0.0, 0.0], [f64::INFINITY, 0.0], [0.0, 1.0]],
            vec![0, 1, 2]
        ),
        Err(Error::NonFiniteCoordinate { .. })
    ));
    assert!(matches!(
        TriangleMesh::new(v.clone(), vec![0, 2, 1]),
        Err(Error::InvertedCell { cell: 0, .. })
    ));
    assert!(matches!(
        TriangleMesh::new(vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]], vec![0, 1, 2]),
        Err(Error::DegenerateCell { cell: 0, .. })
    ));
    assert!(matches!(
        TriangleMesh::new(v.clone(), vec![0, 1, 3]),
        Err(Error::VertexOutOfRange { vertex: 3, .. })
    ));
    assert!(matches!(
        TriangleMesh::new(v.clone(), vec![0, 1]),
        Err(Error::BadConnectivity { .. })
    ));
    assert!(matches!(
        TriangleMesh::new(v, vec![]),
        Err(Error::EmptyMesh)
    ));
    assert!(matches!(
        rectangle([0.0, 0.0], [1.0, 1.0], 1, 3, Diagonal::Forward),
        Err(Error::InvalidGrid(_))
    ));
    assert!(matches!(
        rectangle([0.0, 0.0], [-1.0, 1.0], 3, 3, Diagonal::Forward),
        Err(Error::InvalidGrid(_))
    ));
    assert!(matches!(
        rectangle([f64::NAN, 0.0], [1.0, 1.0], 3, 3, Diagonal::Forward),
        Err(Error::NonFiniteCoordinate { .. })
    ));
}

#[test]
fn invalid_parameters_are_rejected() {
    assert_eq!(
        LinearElasticity::plane_strain(0.0, 0.3),
        Err(Error::InvalidYoungsModulus(0.0))
    );
    assert_eq!(
        LinearElasticity::plane_strain(-1.0, 0.3),
        Err(Error::InvalidYoungsModulus(-1.0))
    );
    assert!(matches!(
        LinearElasticity::plane_strain(f64::NAN, 0.3),
        Err(Error::InvalidYoungsModulus(_))
    ));
    assert_eq!(
        LinearElasticity::plane_strain(1.0, 0.5),
        Err(Error::InvalidPoissonRatio(0.5))
    );
    assert_eq!(
        LinearElasticity::plane_strain(1.0, -1.0),
        Err(Error::InvalidPoissonRatio(-1.0))
    );
    let m = pipping_slider_coarse(Diagonal::Forward);
    let asm = Assembler::new(&m).unwrap();
    assert_eq!(asm.mass(&m, 0.0).unwrap_err(), Error::InvalidDensity(0.0));
    assert_eq!(asm.mass(&m, -5.0).unwrap_err(), Error::InvalidDensity(-5.0));
    assert!(matches!(
        BoundarySegment::from_tag(&m, "nonexistent"),
        Err(Error::EmptySegment { .. })
    ));
    assert!(matches!(
        BoundarySegment::from_predicate(&m, "nothing", |x| x[1] > 2.0),
        Err(Error::EmptySegment { .. })
    ));
    let mut c = Constraints::<2>::new(m.num_vertices());
    assert!(matches!(c.fix(12, 0, 0.0), Err(Error::InvalidDof { .. })));
    assert!(matches!(c.fix(0, 2, 0.0), Err(Error::InvalidDof { .. })));
    assert!(matches!(
        c.fix(0, 0, f64::NAN),
        Err(Error::NonFiniteValue(_))
    ));
    // Mesh / assembler mismatch.
    let other = rectangle([0.0, 0.0], [1.0, 1.0], 3, 3, Diagonal::Forward).unwrap();
    assert!(matches!(
        asm.mass(&other, 1.0),
        Err(Error::DimensionMismatch { .. })
    ));
}

#[test]
fn refinement_invariants() {
    for diag in [Diagonal::Forward, Diagonal::Backward] {
        let h = MeshHierarchy::refine_uniformly(pipping_slider_coarse(diag), 4);
        assert_eq!(h.num_levels(), 5);
        for j in 1..=4 {
            let (c, f) = (h.level(j - 1), h.level(j));
            assert_eq!(f.num_cells(), 4 * c.num_cells());
            assert!((f.measure() - 5.0).abs() < 1e-12);
            assert!(f.min_angle() >= c.min_angle() - 1e-12);
            assert_eq!(f.num_boundary_facets(), 2 * c.num_boundary_facets());
            // Tags: twice as many facets, same total length per tag.
            for tag in [TAG_DIRICHLET, TAG_NEUMANN, TAG_FRICTIONAL] {
                let fc = c.facets_with_tag(tag);
                let ff = f.facets_with_tag(tag);
                assert_eq!(ff.len(), 2 * fc.len(), "{tag}");
                let lc: f64 = fc.iter().map(|&i| c.boundary_facet_measure(i)).sum();
                let lf: f64 = ff.iter().map(|&i| f.boundary_facet_measure(i)).sum();
                assert!((lc - lf).abs() < 1e-12);
                for &i in &ff {
                    let x = f.boundary_facet_midpoint(i);
                    match tag {
                        TAG_DIRICHLET => assert!((x[1] - 1.0).abs() < 1e-12),
                        TAG_FRICTIONAL => assert!(x[1].abs() < 1e-12),
                        _ => assert!(x[0].abs() < 1e-12 || (x[0] - 5.0).abs() < 1e-12),
                    }
                }
            }
            // Prolongation reproduces linear functions exactly.
            let p = h.prolongation(j);
            assert_eq!((p.nrows(), p.ncols()), (f.num_vertices(), c.num_vertices()));
            let lin = |x: &[f64; 2]| 0.3 + 1.7 * x[0] - 2.9 * x[1];
            let uc: Vec<f64> = c.vertices().iter().map(lin).collect();
            let mut uf = vec![0.0; f.num_vertices()];
            spmv_add(p.as_ref(), 1.0, &uc, &mut uf);
            for (v, x) in uf.iter().zip(f.vertices()) {
                assert!((v - lin(x)).abs() < 1e-13);
            }
            // Vector prolongation on a linear vector field.
            let pv = h.vector_prolongation(j);
            let vc: Vec<f64> = c
                .vertices()
                .iter()
                .flat_map(|x| [lin(x), 2.0 * x[0] + x[1]])
                .collect();
            let mut vf = vec![0.0; 2 * f.num_vertices()];
            spmv_add(pv.as_ref(), 1.0, &vc, &mut vf);
            for (i, x) in f.vertices().iter().enumerate() {
                assert!((vf[2 * i] - lin(x)).abs() < 1e-13);
                assert!((vf[2 * i + 1] - 2.0 * x[0] - x[1]).abs() < 1e-13);
            }
        }
    }
}

#[test]
fn segments_are_ordered_with_normals_and_frames() {
    let h = MeshHierarchy::refine_uniformly(pipping_slider_coarse(Diagonal::Forward), 2);
    let m = h.finest();
    let gf = BoundarySegment::from_tag(m, TAG_FRICTIONAL).unwrap();
    assert_eq!(gf.num_nodes(), 21);
    let xs: Vec<f64> = gf.nodes().iter().map(|&v| m.vertices()[v][0]).collect();
    assert!(
        xs.windows(2).all(|w| w[1] > w[0]),
        "ordered by increasing x"
    );
    assert!((gf.measure(m) - 5.0).abs() < 1e-13);
    for n in gf.normals(m) {
        assert!((n[0]).abs() < 1e-14 && (n[1] + 1.0).abs() < 1e-14);
    }
    for q in gf.frames(m).rotations {
        assert_eq!(q, [[1.0, 0.0], [0.0, 1.0]]);
    }
    let gd = BoundarySegment::from_predicate(m, "top", |x| x[1] > 1.0 - 1e-9).unwrap();
    assert_eq!(gd.num_nodes(), 21);
    let gn = BoundarySegment::from_tag(m, TAG_NEUMANN).unwrap();
    assert_eq!(gn.num_nodes(), 10);
    assert_eq!(gn.facets().len(), 8);
    // A slanted boundary: the unit disk's polygonal approximation → radial normals.
    let n = 16;
    let mut v = vec![[0.0, 0.0]];
    let mut cells = Vec::new();
    for k in 0..n {
        let t = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
        v.push([t.cos(), t.sin()]);
        cells.extend_from_slice(&[0, 1 + k, 1 + (k + 1) % n]);
    }
    let disk = TriangleMesh::new(v, cells).unwrap();
    let circle = BoundarySegment::from_predicate(&disk, "circle", |_| true).unwrap();
    assert_eq!(circle.num_nodes(), n);
    let frames = circle.frames(&disk);
    for (k, (&p, q)) in frames.nodes.iter().zip(&frames.rotations).enumerate() {
        let x = disk.vertices()[p];
        // last column = inward normal = −x; det = +1
        assert!(
            (q[0][1] + x[0]).abs() < 1e-12 && (q[1][1] + x[1]).abs() < 1e-12,
            "{k}"
        );
        assert!((q[0][0] * q[1][1] - q[0][1] * q[1][0] - 1.0).abs() < 1e-12);
    }
    let w = lumped_weights(&disk, &circle);
    let perimeter: f64 = (0..disk.num_boundary_facets())
        .map(|f| disk.boundary_facet_measure(f))
        .sum();
    assert!((w.iter().sum::<f64>() - perimeter).abs() < 1e-13);
}
