//! Dimension-generic boundary parts: nodes, lumped weights, outer normals and nodal frames.
use crate::common::{apply, check_frames};
use rsf_fem::*;

/// Column `c` of a row-major frame.
fn col(q: &[[f64; 3]; 3], c: usize) -> [f64; 3] {
    [q[0][c], q[1][c], q[2][c]]
}

fn check_rotation(q: &[[f64; 3]; 3], n: &[f64; 3]) {
    for a in 0..3 {
        for b in 0..3 {
            let d: f64 = (0..3).map(|r| q[r][a] * q[r][b]).sum();
            assert!(
                (d - f64::from(u8::from(a == b))).abs() < 1e-13,
                "orthonormal"
            );
        }
    }
    let det = q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1])
        - q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0])
        + q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0]);
    assert!((det - 1.0).abs() < 1e-13, "det {det}");
    for r in 0..3 {
        assert!(
            (q[r][2] + n[r]).abs() < 1e-13,
            "last column = inward normal"
        );
    }
}

#[test]
fn parts_on_a_box_faces() {
    let mut m = cuboid([0.0; 3], [2.0, 1.0, 0.5], [5, 3, 2]).unwrap();
    assert_eq!(m.tag_boundary("bottom", |x| x[2] < 1e-9), 2 * 4 * 2);
    let bottom = BoundaryPart::from_tag(&m, "bottom").unwrap();
    assert_eq!(bottom.name(), "bottom");
    assert_eq!(bottom.num_nodes(), 5 * 3);
    assert!(bottom.nodes().windows(2).all(|w| w[0] < w[1]));
    for (i, &v) in bottom.nodes().iter().enumerate() {
        assert_eq!(bottom.local_index(v), Some(i));
    }
    assert_eq!(bottom.local_index(m.num_vertices() - 1), None);
    assert!((bottom.measure(&m).unwrap() - 2.0).abs() < 1e-14);
    let w = bottom.weights(&m).unwrap();
    assert!((w.iter().sum::<f64>() - 2.0).abs() < 1e-14);
    assert!(w.iter().all(|&x| x > 0.0));
    assert_eq!(w, lumped_weights(&m, &bottom));
    // Flat faces: exact normals; frames: identity on the bottom (z up), (e_x, −e_z, e_y) on
    // y = 0, and t1 along a given direction when asked.
    for n in bottom.normals(&m).unwrap() {
        assert_eq!(n, [0.0, 0.0, -1.0]);
    }
    for q in bottom.frames(&m).unwrap().rotations {
        assert_eq!(q, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    }
    let front = BoundaryPart::from_predicate(&m, "front", |x| x[1] < 1e-9).unwrap();
    assert!((front.weights(&m).unwrap().iter().sum::<f64>() - 1.0).abs() < 1e-14);
    for q in front.frames(&m).unwrap().rotations {
        check_rotation(&q, &[0.0, -1.0, 0.0]);
        assert_eq!(col(&q, 0), [1.0, 0.0, 0.0]);
        assert_eq!(col(&q, 1), [0.0, 0.0, -1.0]);
    }
    for q in bottom
        .frames_with_tangent(&m, [0.0, 1.0, 1.0])
        .unwrap()
        .rotations
    {
        check_rotation(&q, &[0.0, 0.0, -1.0]);
        assert!((col(&q, 0)[1] - 1.0).abs() < 1e-15 && (col(&q, 1)[0] + 1.0).abs() < 1e-15);
    }
    // A direction normal to the face is an error naming a node of it and its position
    // (it used to fall back to the default rule silently).
    match bottom.frames_with_tangent(&m, [0.0, 0.0, 3.0]) {
        Err(rsf_fem::Error::TangentAlongNormal {
            vertex,
            position,
            normal,
            direction,
        }) => {
            assert!(bottom.nodes().contains(&vertex));
            assert_eq!(position, m.vertices()[vertex].to_vec());
            assert_eq!(normal, vec![0.0, 0.0, -1.0]);
            assert_eq!(direction, vec![0.0, 0.0, 3.0]);
        }
        other => panic!("{other:?}"),
    }
    // All of the boundary: area, and corner normals are unit averages pointing outwards.
    let all = BoundaryPart::from_predicate(&m, "all", |_| true).unwrap();
    assert_eq!(all.num_nodes(), m.num_vertices());
    let area = 2.0 * (2.0 * 1.0 + 1.0 * 0.5 + 2.0 * 0.5);
    assert!((all.weights(&m).unwrap().iter().sum::<f64>() - area).abs() < 1e-13);
    let normals = all.normals(&m).unwrap();
    for (&p, n) in all.nodes().iter().zip(&normals) {
        let x = m.vertices()[p];
        assert!((n.iter().map(|c| c * c).sum::<f64>() - 1.0).abs() < 1e-14);
        let centre = [1.0, 0.5, 0.25];
        assert!((0..3).map(|r| n[r] * (x[r] - centre[r])).sum::<f64>() > 0.0);
    }
    let frames = all.frames(&m).unwrap();
    for (q, n) in frames.rotations.iter().zip(&normals) {
        check_rotation(q, n);
    }
    // Area weighting at the corner (Lx, 0, 0) of a one-cell box of size (2, 1, 0.5): the
    // face x = Lx touches it with both triangles (area Ly·Lz), the faces y = 0 and z = 0
    // with one (Lx·Lz/2, Lx·Ly/2), so n ∝ (0.5, −0.5, −1) (counting facets instead would
    // give (2, −1, −1)).
    let one = cuboid([0.0; 3], [2.0, 1.0, 0.5], [2, 2, 2]).unwrap();
    let all = BoundaryPart::from_predicate(&one, "all", |_| true).unwrap();
    let n = all.normals(&one).unwrap()[all.local_index(1).unwrap()];
    let expected = [1.0, -1.0, -2.0].map(|c| c / 6f64.sqrt());
    assert!((0..3).all(|k| (n[k] - expected[k]).abs() < 1e-15), "{n:?}");
}

#[test]
fn normals_of_a_cylinder_are_radial() {
    // The quarter shell 1 ≤ r ≤ 2, 0 ≤ θ ≤ π/2, 0 ≤ z ≤ 1 as the image of a Kuhn box. Its
    // outer surface is made of planar chord quads; an interior node of that surface lies
    // between congruent quads (mirror images in the node's radial plane), so the averaged
    // normal is exactly radial.
    let shell = |n: usize| {
        let b = cuboid(
            [1.0, 0.0, 0.0],
            [1.0, std::f64::consts::FRAC_PI_2, 1.0],
            [n, 2 * n, n],
        )
        .unwrap();
        let v = b
            .vertices()
            .iter()
            .map(|x| [x[0] * x[1].cos(), x[0] * x[1].sin(), x[2]])
            .collect();
        TetrahedronMesh::new(v, b.cells().to_vec()).unwrap()
    };
    for n in [3, 5] {
        let m = shell(n);
        // Facets on r = 2: not on the planes z = 0, z = 1, x = 0, y = 0.
        let outer = BoundaryPart::from_predicate(&m, "outer", |x| {
            x[0].hypot(x[1]) > 1.9 && x[2] > 1e-9 && x[2] < 1.0 - 1e-9 && x[0] > 1e-9 && x[1] > 1e-9
        })
        .unwrap();
        let mut worst: f64 = 0.0;
        for (&p, nrm) in outer.nodes().iter().zip(outer.normals(&m).unwrap()) {
            let x = m.vertices()[p];
            // Interior nodes of the face only (edges of the shell average in other faces).
            if x[2] < 1e-9 || x[2] > 1.0 - 1e-9 || x[0] < 1e-9 || x[1] < 1e-9 {
                continue;
            }
            let r = x[0].hypot(x[1]);
            let radial = [x[0] / r, x[1] / r, 0.0];
            worst = worst.max(
                (0..3)
                    .map(|k| (nrm[k] - radial[k]).powi(2))
                    .sum::<f64>()
                    .sqrt(),
            );
        }
        assert!(worst < 1e-14, "{worst}");
        // Lumped weights: the polyhedral outer surface's area, below the cylinder's π.
        let w: f64 = outer.weights(&m).unwrap().iter().sum();
        assert!(w < std::f64::consts::PI && w > 0.95 * std::f64::consts::PI);
    }
}

#[test]
fn frames_rotate_matrices_and_prolongations_in_3d() {
    // A box rotated about (1, 2, 2)/3 by 40°: its bottom face has normal −R e_z.
    let (a, t) = ([1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0], 40f64.to_radians());
    let (c, s) = (t.cos(), t.sin());
    let r: [[f64; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let cross = [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]];
            c * f64::from(u8::from(i == j)) + s * cross[i][j] + (1.0 - c) * a[i] * a[j]
        })
    });
    let rot = |x: &[f64; 3]| -> [f64; 3] {
        std::array::from_fn(|i| (0..3).map(|j| r[i][j] * x[j]).sum())
    };
    let b = cuboid([0.0; 3], [1.0, 1.0, 0.5], [3, 3, 2]).unwrap();
    let mut m =
        TetrahedronMesh::new(b.vertices().iter().map(rot).collect(), b.cells().to_vec()).unwrap();
    let down = rot(&[0.0, 0.0, -1.0]);
    let on_bottom = move |x: &[f64; 3]| (0..3).map(|k| x[k] * down[k]).sum::<f64>().abs() < 1e-9;
    m.tag_boundary("fault", on_bottom);
    let fault = BoundaryPart::from_tag(&m, "fault").unwrap();
    let frames = fault.frames(&m).unwrap();
    for (q, n) in frames.rotations.iter().zip(fault.normals(&m).unwrap()) {
        assert!((0..3).all(|k| (n[k] - down[k]).abs() < 1e-14));
        check_rotation(q, &n);
    }
    let k = Assembler::new(&m)
        .unwrap()
        .stiffness(&m, &LinearElasticity::isotropic(1.0, 0.3).unwrap())
        .unwrap();
    check_frames(&k, &frames);
    let x: Vec<f64> = (0..3 * m.num_vertices())
        .map(|i| (0.37 * i as f64).sin())
        .collect();
    // A rigid sliding along the fault has zero local normal components, and the slip rate
    // (norm of the tangential components) is its speed.
    let slide = rot(&[0.6, 0.8, 0.0]);
    let mut v: Vec<f64> = (0..m.num_vertices()).flat_map(|_| slide).collect();
    frames.to_local(&mut v).unwrap();
    for &p in fault.nodes() {
        assert!(v[3 * p + 2].abs() < 1e-14);
        assert!((v[3 * p].hypot(v[3 * p + 1]) - 1.0).abs() < 1e-14);
    }
    // Rotated prolongation rows: P̃ = Rᵀ P.
    let h = MeshHierarchy::refine_uniformly(m, 1);
    let fine = h.finest();
    let ff = BoundaryPart::from_tag(fine, "fault")
        .unwrap()
        .frames(fine)
        .unwrap();
    let p = h.vector_prolongation(1);
    let pt = ff.rotate_rows(p.as_ref()).unwrap();
    let mut vf = apply(p, &x);
    ff.to_local(&mut vf).unwrap();
    for (a, b) in vf.iter().zip(apply(&pt, &x)) {
        assert!((a - b).abs() < 1e-14);
    }
}

#[test]
fn parts_agree_with_segments_in_2d() {
    let h = MeshHierarchy::refine_uniformly(pipping_slider_coarse(Diagonal::Forward), 2);
    let m = h.finest();
    for tag in [TAG_FRICTIONAL, TAG_DIRICHLET, TAG_NEUMANN] {
        let seg = BoundarySegment::from_tag(m, tag).unwrap();
        let part = BoundaryPart::from_tag(m, tag).unwrap();
        let mut sorted = seg.nodes().to_vec();
        sorted.sort_unstable();
        assert_eq!(sorted, part.nodes());
        let (ws, wp) = (lumped_weights(m, &seg), part.weights(m).unwrap());
        let (fs, fp) = (seg.frames(m), part.frames(m).unwrap());
        for (i, &v) in seg.nodes().iter().enumerate() {
            let k = part.local_index(v).unwrap();
            assert_eq!(ws[i], wp[k]);
            assert_eq!(fs.rotations[i], fp.rotations[k]);
        }
        assert_eq!(seg.as_part().nodes(), seg.nodes());
    }
}

#[test]
fn part_errors() {
    let mut m = cuboid([0.0; 3], [1.0; 3], [2, 2, 2]).unwrap();
    for empty in [
        BoundaryPart::from_tag(&m, "missing"),
        BoundaryPart::from_predicate(&m, "none", |x| x[0] > 2.0),
    ] {
        assert!(matches!(empty, Err(Error::EmptySegment { .. })));
    }
    assert!(matches!(
        BoundaryPart::from_facets(&m, "bad", vec![0, 12]),
        Err(Error::InvalidFacet {
            facet: 12,
            num_facets: 12
        })
    ));
    assert!(matches!(
        m.tag_boundary_facets("x", &[3, 99]),
        Err(Error::InvalidFacet { facet: 99, .. })
    ));
    assert!(m.facets_with_tag("x").is_empty());
    assert_eq!(m.tag_boundary_facets("x", &[3, 5]).unwrap(), 2);
    let part = BoundaryPart::from_facets(&m, "x", vec![5, 3, 5]).unwrap();
    assert_eq!(part.facets(), &[3, 5]);
    assert_eq!(part, BoundaryPart::from_tag(&m, "x").unwrap());
    let other = cuboid([0.0; 3], [1.0; 3], [3, 2, 2]).unwrap();
    assert!(matches!(
        part.weights(&other),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(matches!(
        part.normals(&other),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(matches!(
        part.frames_with_tangent(&m, [f64::NAN, 0.0, 0.0]),
        Err(Error::NonFiniteValue(_))
    ));
    // Two tetrahedra touching at a vertex, mirror images of each other through it: the
    // averaged normal of all boundary facets there cancels.
    let v = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, -1.0],
    ];
    let pinched = TetrahedronMesh::from_ordered_cells(v, vec![0, 1, 2, 3, 0, 4, 5, 6]).unwrap();
    let all = BoundaryPart::from_predicate(&pinched, "all", |_| true).unwrap();
    assert!(matches!(
        all.normals(&pinched),
        Err(Error::UndefinedNormal { vertex: 0 })
    ));
}
