//! Faults inside a 3-D body (`SimplexMesh::<3>::split_along`, `split_along_polygon`,
//! `GmshMesh::<3>::split_along_group`, `FaultSides::<3>::mean_jump_transform`): cuts
//! through, buried and reaching the surface, reorientation, typed errors, refinement, the
//! mean–jump transform and a Gmsh interior surface.
use std::collections::{HashMap, HashSet};

use rsf_fem::*;

use crate::common::parse_with_interior_facets;
use crate::split_transform::{assert_inverts, dense, largest, matvec, stiffness};

/// Vertex `(i, j, k)` of `cuboid([0; 3], [1; 3], [n; 3])`, at `(i, j, k)/(n − 1)`.
fn id(n: usize) -> impl Fn(usize, usize, usize) -> usize {
    move |i, j, k| i + n * (j + n * k)
}

/// The faces of the plane `x = i` over the squares `j0..j1 × k0..k1` (Kuhn cells split each
/// square along its (0, 1, 1) diagonal), normal +x.
fn plane_faces(n: usize, i: usize, j: (usize, usize), k: (usize, usize)) -> Vec<[usize; 3]> {
    let id = id(n);
    let mut f = Vec::new();
    for jj in j.0..j.1 {
        for kk in k.0..k.1 {
            f.push([id(i, jj, kk), id(i, jj + 1, kk), id(i, jj + 1, kk + 1)]);
            f.push([id(i, jj, kk), id(i, jj + 1, kk + 1), id(i, jj, kk + 1)]);
        }
    }
    f
}

fn unit_cube(n: usize) -> TetrahedronMesh {
    cuboid([0.0; 3], [1.0; 3], [n; 3]).unwrap()
}

/// Connected components of the cells (adjacent through shared faces), by flooding from
/// every cell not yet reached.
fn components(m: &TetrahedronMesh) -> usize {
    let mut cells_of: HashMap<[usize; 3], Vec<usize>> = HashMap::new();
    for c in 0..m.num_cells() {
        let cell = m.cell(c);
        for skip in 0..4 {
            let mut f: Vec<usize> = (0..4).filter(|&r| r != skip).map(|r| cell[r]).collect();
            f.sort_unstable();
            cells_of.entry([f[0], f[1], f[2]]).or_default().push(c);
        }
    }
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); m.num_cells()];
    for cells in cells_of.values() {
        for &c in cells {
            neighbours[c].extend(cells.iter().filter(|&&d| d != c));
        }
    }
    let mut reached = vec![false; m.num_cells()];
    let mut count = 0;
    for start in 0..m.num_cells() {
        if reached[start] {
            continue;
        }
        count += 1;
        reached[start] = true;
        let mut stack = vec![start];
        while let Some(c) = stack.pop() {
            for &d in &neighbours[c] {
                if !reached[d] {
                    reached[d] = true;
                    stack.push(d);
                }
            }
        }
    }
    count
}

fn centroid_x(m: &TetrahedronMesh, c: usize) -> f64 {
    m.cell(c).iter().map(|&v| m.vertices()[v][0]).sum::<f64>() / 4.0
}

/// Same vertices, cells, boundary facets and tags.
fn assert_same_mesh(a: &TetrahedronMesh, b: &TetrahedronMesh) {
    assert_eq!(a.vertices(), b.vertices());
    assert_eq!(a.cells(), b.cells());
    assert_eq!(a.num_boundary_facets(), b.num_boundary_facets());
    for f in 0..a.num_boundary_facets() {
        assert_eq!(a.boundary_facet(f), b.boundary_facet(f));
        assert_eq!(a.boundary_facet_tag(f), b.boundary_facet_tag(f));
    }
}

/// The invariants of every split: cells keep measure, order and coordinates; pairs sit
/// at one place; plus copies are used on the plus side only; sides' facets have ±n as
/// outward normals (`usize::MAX` exactly for faces whose vertices are all tips).
fn check_split(
    m: &TetrahedronMesh,
    s: &TetrahedronMesh,
    sides: &FaultSides<3>,
    faces: &[[usize; 3]],
) {
    assert_eq!(s.num_cells(), m.num_cells());
    for c in 0..m.num_cells() {
        assert_eq!(s.cell_measure(c), m.cell_measure(c));
        for (&a, &b) in m.cell(c).iter().zip(s.cell(c)) {
            assert_eq!(m.vertices()[a], s.vertices()[b]);
        }
    }
    assert_eq!(s.measure(), m.measure());
    let nodes = sides.nodes();
    assert!(nodes.windows(2).all(|w| w[0].0 < w[1].0));
    let mut q_expected = m.num_vertices();
    for &(p, q) in nodes {
        if p != q {
            assert_eq!(q, q_expected, "plus copies appended in increasing p");
            q_expected += 1;
            assert_eq!(s.vertices()[p], s.vertices()[q]);
        }
    }
    assert_eq!(s.num_vertices(), q_expected);
    let tips: HashSet<usize> = sides.tips().into_iter().collect();
    let mut opened = 0;
    for (k, f) in faces.iter().enumerate() {
        let n = sides.normals()[k];
        let (mi, pl) = (sides.minus_facets()[k], sides.plus_facets()[k]);
        if f.iter().all(|v| tips.contains(v)) {
            assert_eq!((mi, pl), (usize::MAX, usize::MAX));
            continue;
        }
        opened += 1;
        let (a, b) = (s.boundary_facet_normal(mi), s.boundary_facet_normal(pl));
        for r in 0..3 {
            assert!((a[r] - n[r]).abs() < 1e-14 && (b[r] + n[r]).abs() < 1e-14);
        }
        assert_eq!(s.boundary_facet_tag(mi), Some(sides.minus_tag().as_str()));
        assert_eq!(s.boundary_facet_tag(pl), Some(sides.plus_tag().as_str()));
        // The plus cell lies on the normal's side.
        let c = s.boundary_facet_cell(pl);
        let x0 = s.vertices()[f[0]];
        let d: f64 = s
            .cell(c)
            .iter()
            .map(|&v| {
                (0..3)
                    .map(|r| (s.vertices()[v][r] - x0[r]) * n[r])
                    .sum::<f64>()
            })
            .sum();
        assert!(d > 0.0);
    }
    assert_eq!(s.facets_with_tag(&sides.minus_tag()).len(), opened);
    assert_eq!(s.facets_with_tag(&sides.plus_tag()).len(), opened);
    assert_eq!(
        s.num_boundary_facets(),
        m.num_boundary_facets() + 2 * opened
    );
}

#[test]
fn a_cut_through_the_whole_body_splits_it_in_two() {
    let m = unit_cube(5);
    let faces = plane_faces(5, 2, (0, 4), (0, 4));
    assert_eq!(faces.len(), 32);
    let (s, sides) = m.split_along("fault", &faces).unwrap();
    check_split(&m, &s, &sides, &faces);
    // All 25 vertices of x = 1/2 split (the rim is on the outer boundary).
    assert_eq!(sides.nodes().len(), 25);
    assert_eq!(sides.pairs().len(), 25);
    assert!(sides.tips().is_empty());
    assert_eq!(s.num_vertices(), 125 + 25);
    assert_eq!(s.facets_with_tag("fault_minus").len(), 32);
    assert_eq!(s.facets_with_tag("fault_plus").len(), 32);
    assert!(sides.normals().iter().all(|n| *n == [1.0, 0.0, 0.0]));
    assert!((s.measure() - 1.0).abs() < 1e-14);
    // Plus copies only in cells with x > 1/2, minus ones only in x < 1/2.
    for (mi, pl) in sides.pairs() {
        for c in 0..s.num_cells() {
            if s.cell(c).contains(&pl) {
                assert!(centroid_x(&s, c) > 0.5);
            }
            if s.cell(c).contains(&mi) {
                assert!(centroid_x(&s, c) < 0.5);
            }
        }
    }
    assert_eq!(components(&m), 1);
    assert_eq!(components(&s), 2);
    // u = 1 on the minus side, 2 on the plus side is in the Laplacian's kernel.
    let mut u = vec![0.0; s.num_vertices()];
    for c in 0..s.num_cells() {
        let val = if centroid_x(&s, c) < 0.5 { 1.0 } else { 2.0 };
        for &v in s.cell(c) {
            assert!(u[v] == 0.0 || u[v] == val, "a vertex used by both sides");
            u[v] = val;
        }
    }
    let k = Assembler::scalar(&s).unwrap().laplace(&s, 1.0).unwrap();
    let mut r = vec![0.0; s.num_vertices()];
    spmv_add(k.as_ref(), 1.0, &u, &mut r);
    let scale = k.val().iter().fold(0.0f64, |a, x| a.max(x.abs()));
    assert!(r.iter().all(|x| x.abs() < 1e-13 * scale));
    // Not so on the unsplit mesh (the check can fail).
    let ku = Assembler::scalar(&m).unwrap().laplace(&m, 1.0).unwrap();
    let u0: Vec<f64> = (0..m.num_vertices()).map(|v| u[v]).collect();
    let mut r0 = vec![0.0; m.num_vertices()];
    spmv_add(ku.as_ref(), 1.0, &u0, &mut r0);
    assert!(r0.iter().any(|x| x.abs() > 1e-3 * scale));
    // The split mesh refines with the cut open.
    let fine = refine_red(&s).0;
    assert_eq!(fine.facets_with_tag("fault_plus").len(), 4 * 32);
    assert_eq!(components(&fine), 2);
}

#[test]
fn a_buried_fault_shares_its_rim() {
    let m = unit_cube(9); // h = 1/8
    let id = id(9);
    // x = 1/2, 1/4 ≤ y, z ≤ 3/4.
    let faces = plane_faces(9, 4, (2, 6), (2, 6));
    assert_eq!(faces.len(), 32);
    let (s, sides) = m.split_along("buried", &faces).unwrap();
    check_split(&m, &s, &sides, &faces);
    assert_eq!(sides.nodes().len(), 25);
    // The 3 × 3 inner vertices split, the 16 rim ones shared.
    let pairs: HashSet<usize> = sides.pairs().iter().map(|p| p.0).collect();
    let inner: HashSet<usize> = (3..6)
        .flat_map(|j| (3..6).map(move |k| (j, k)))
        .map(|(j, k)| id(4, j, k))
        .collect();
    assert_eq!(pairs, inner);
    let tips = sides.tips();
    assert_eq!(tips.len(), 16);
    for t in tips {
        let x = s.vertices()[t];
        assert!(x[1] == 0.25 || x[1] == 0.75 || x[2] == 0.25 || x[2] == 0.75);
    }
    assert_eq!(s.num_vertices(), m.num_vertices() + 9);
    // The two faces at the corners (3/4, 1/4) and (1/4, 3/4) have only rim vertices: closed.
    let closed: Vec<usize> = (0..32)
        .filter(|&k| sides.minus_facets()[k] == usize::MAX)
        .collect();
    assert_eq!(closed.len(), 2);
    assert_eq!(s.facets_with_tag("buried_minus").len(), 30);
    assert_eq!(s.facets_with_tag("buried_plus").len(), 30);
    assert_eq!(components(&s), 1);
}

#[test]
fn a_fault_reaching_the_surface_splits_its_trace() {
    let mut m = unit_cube(9);
    m.tag_boundary("surface", |x| x[2] > 1.0 - 1e-12);
    let id = id(9);
    // x = 1/2, 1/4 ≤ y ≤ 3/4, 1/2 ≤ z ≤ 1 (z = 1 the top).
    let faces = plane_faces(9, 4, (2, 6), (4, 8));
    let (s, sides) = m.split_along("f", &faces).unwrap();
    check_split(&m, &s, &sides, &faces);
    let pairs: HashSet<usize> = sides.pairs().iter().map(|p| p.0).collect();
    let mut expected = HashSet::new();
    for j in 3..6 {
        for k in 5..9 {
            expected.insert(id(4, j, k)); // inner rows and the trace z = 1, 3/8 ≤ y ≤ 5/8
        }
    }
    assert_eq!(pairs, expected);
    let tips: HashSet<usize> = sides.tips().into_iter().collect();
    assert_eq!(tips.len(), 13);
    assert!(tips.contains(&id(4, 2, 8)) && tips.contains(&id(4, 6, 8))); // the rim's corners
    assert!(tips.contains(&id(4, 2, 4)) && tips.contains(&id(4, 4, 4))); // buried rim
    assert_eq!(
        s.facets_with_tag("surface").len(),
        m.facets_with_tag("surface").len()
    );
    // The surface tags of the split mesh: the trace's facets on each side use the copies.
    let surf = BoundaryPart::from_tag(&s, "surface").unwrap();
    for (mi, pl) in sides.pairs() {
        if s.vertices()[mi][2] == 1.0 {
            assert!(surf.nodes().contains(&mi) && surf.nodes().contains(&pl));
        }
    }
}

#[test]
fn faces_in_any_orientation_give_the_same_split() {
    let m = unit_cube(9);
    let faces = plane_faces(9, 4, (2, 6), (4, 8));
    let (s, sides) = m.split_along("f", &faces).unwrap();
    // Every other face reversed, every third rotated: the same split.
    let shuffled: Vec<[usize; 3]> = faces
        .iter()
        .enumerate()
        .map(|(k, &f)| {
            let f = if k % 2 == 1 { [f[0], f[2], f[1]] } else { f };
            if k % 3 == 2 {
                [f[1], f[2], f[0]]
            } else {
                f
            }
        })
        .collect();
    assert_ne!(shuffled, faces);
    let (s2, sides2) = m.split_along("f", &shuffled).unwrap();
    assert_same_mesh(&s, &s2);
    assert_eq!(sides, sides2);
    // The first face reversed: the normal flips and the sides swap.
    let mut flipped = faces.clone();
    flipped[0] = [faces[0][0], faces[0][2], faces[0][1]];
    let (s3, sides3) = m.split_along("f", &flipped).unwrap();
    assert!(sides3.normals().iter().all(|n| *n == [-1.0, 0.0, 0.0]));
    assert_eq!(sides3.minus_facets().len(), sides.plus_facets().len());
    assert_eq!(sides3.pairs().len(), sides.pairs().len());
    for (_, pl) in sides3.pairs() {
        for c in 0..s3.num_cells() {
            if s3.cell(c).contains(&pl) {
                assert!(centroid_x(&s3, c) < 0.5);
            }
        }
    }
    check_split(&m, &s3, &sides3, &flipped);
}

#[test]
fn bad_faults_are_typed_errors() {
    let m = unit_cube(5);
    let id = id(5);
    assert_eq!(m.split_along("f", &[]).unwrap_err(), Error::EmptyFault);
    // Not a face: the anti-diagonal of a square; out of range; a repeated vertex.
    let anti = [id(2, 1, 1), id(2, 2, 1), id(2, 1, 2)];
    assert_eq!(
        m.split_along("f", &[anti]).unwrap_err(),
        Error::FaultFaceNotInMesh {
            face: 0,
            vertices: anti
        }
    );
    let good = plane_faces(5, 2, (1, 2), (1, 2));
    assert!(matches!(
        m.split_along("f", &[good[0], [0, 1, 10_000]]),
        Err(Error::FaultFaceNotInMesh { face: 1, .. })
    ));
    assert!(matches!(
        m.split_along("f", &[[id(2, 1, 1), id(2, 1, 1), id(2, 2, 2)]]),
        Err(Error::FaultFaceNotInMesh { face: 0, .. })
    ));
    // On the outer boundary x = 0.
    let outer = plane_faces(5, 0, (1, 2), (1, 2))[0];
    assert_eq!(
        m.split_along("f", &[outer]).unwrap_err(),
        Error::FaultFaceOnBoundary {
            face: 0,
            vertices: outer
        }
    );
    // Repeated (in another vertex order).
    let g = good[0];
    assert_eq!(
        m.split_along("f", &[g, good[1], [g[2], g[1], g[0]]])
            .unwrap_err(),
        Error::FaultFaceRepeated {
            face: 2,
            vertices: [g[2], g[1], g[0]]
        }
    );
    // Three faces at the edge p — p + z.
    let (p, pz) = (id(2, 2, 2), id(2, 2, 3));
    let three = [
        [p, pz, id(2, 3, 3)],
        [id(2, 1, 2), p, pz],
        [p, pz, id(3, 2, 3)],
    ];
    assert_eq!(
        m.split_along("f", &three).unwrap_err(),
        Error::FaultEdgeNotManifold {
            vertices: [p, pz],
            faces: 3
        }
    );
    // Two pieces.
    let a = plane_faces(5, 2, (0, 1), (0, 1));
    let b = plane_faces(5, 2, (3, 4), (3, 4));
    assert_eq!(
        m.split_along("f", &[a[0], a[1], b[0]]).unwrap_err(),
        Error::FaultDisconnected { vertex: b[0][0] }
    );
    // A lens touching the top along two edges through p = (1/2, 1/2, 1): the plane x = 1/2
    // below p and a bent surface on the x < 1/2 side meet there, three groups of cells.
    let p = id(2, 2, 4);
    let (py, my, myz, mz) = (id(2, 3, 4), id(2, 1, 4), id(2, 1, 3), id(2, 2, 3));
    let (mxyz, mxz) = (id(1, 1, 3), id(1, 2, 3));
    let lens = [
        [p, my, myz],
        [p, myz, mz],
        [p, mz, py],
        [p, my, mxyz],
        [p, mxyz, mxz],
        [p, mxz, py],
    ];
    assert_eq!(
        m.split_along("f", &lens).unwrap_err(),
        Error::FaultSidesNotSeparated { vertex: p }
    );
    // The plane part alone reaches the top along two edges through p: fine.
    assert!(m.split_along("f", &lens[..3]).is_ok());
}

#[test]
fn a_polygon_finds_its_faces_on_every_level() {
    let coarse = unit_cube(5);
    let square = [
        [0.5, 0.25, 0.25],
        [0.5, 0.75, 0.25],
        [0.5, 0.75, 0.75],
        [0.5, 0.25, 0.75],
    ];
    // Level 0: the same split as the face list.
    let (s, sides) = coarse.split_along_polygon("f", &square).unwrap();
    let faces = plane_faces(5, 2, (1, 3), (1, 3));
    let (s0, sides0) = coarse.split_along("f", &faces).unwrap();
    assert_same_mesh(&s, &s0);
    assert_eq!(sides.nodes(), sides0.nodes());
    assert_eq!(sides.normals().len(), 8);
    assert!(sides.normals().iter().all(|n| *n == [1.0, 0.0, 0.0]));
    // Corners in the other order: the normal flips.
    let rev: Vec<[f64; 3]> = square.iter().rev().copied().collect();
    let (_, sides_r) = coarse.split_along_polygon("f", &rev).unwrap();
    assert!(sides_r.normals().iter().all(|n| *n == [-1.0, 0.0, 0.0]));
    // Through the whole cross-section.
    let whole = [
        [0.5, 0.0, 0.0],
        [0.5, 1.0, 0.0],
        [0.5, 1.0, 1.0],
        [0.5, 0.0, 1.0],
    ];
    let (sw, sides_w) = coarse.split_along_polygon("f", &whole).unwrap();
    assert_eq!(sides_w.normals().len(), 32);
    assert_eq!(components(&sw), 2);
    // A uniformly refined hierarchy: 4× the faces per level, (2^(l+1) − 1)² inner pairs.
    let h = MeshHierarchy::refine_uniformly(coarse, 2);
    let mut count = Vec::new();
    for (l, mesh) in h.levels().iter().enumerate() {
        let (s, sides) = mesh.split_along_polygon("f", &square).unwrap();
        count.push(sides.normals().len());
        let inner = (1usize << (l + 1)) - 1;
        assert_eq!(sides.pairs().len(), inner * inner);
        assert_eq!(sides.tips().len(), 4 << (l + 1));
        let area: f64 = sides
            .minus_facets()
            .iter()
            .filter(|&&f| f != usize::MAX)
            .map(|&f| s.boundary_facet_measure(f))
            .sum();
        let closed = sides
            .minus_facets()
            .iter()
            .filter(|&&f| f == usize::MAX)
            .count();
        let face = 0.5 / (16.0 * 4f64.powi(l as i32));
        assert!((area + closed as f64 * face - 0.25).abs() < 1e-14);
    }
    assert_eq!(count, [8, 32, 128]);
    // A non-convex (L-shaped) polygon, and a tilted one (the plane x = z through Kuhn
    // faces).
    let fine = unit_cube(9);
    let l_shape = [
        [0.5, 0.25, 0.25],
        [0.5, 0.75, 0.25],
        [0.5, 0.75, 0.5],
        [0.5, 0.5, 0.5],
        [0.5, 0.5, 0.75],
        [0.5, 0.25, 0.75],
    ];
    let (_, sides_l) = fine.split_along_polygon("f", &l_shape).unwrap();
    assert_eq!(sides_l.normals().len(), 24);
    let tilted = [
        [0.25, 0.25, 0.25],
        [0.75, 0.25, 0.75],
        [0.75, 0.75, 0.75],
        [0.25, 0.75, 0.25],
    ];
    let (_, sides_t) = fine.split_along_polygon("f", &tilted).unwrap();
    let h2 = 0.5f64.sqrt();
    for n in sides_t.normals() {
        assert!((n[0] + h2).abs() < 1e-15 && n[1].abs() < 1e-15 && (n[2] - h2).abs() < 1e-15);
    }
}

#[test]
fn polygons_the_mesh_does_not_resolve_are_typed_errors() {
    let m = unit_cube(5);
    let not_resolved = |corners: &[[f64; 3]]| match m.split_along_polygon("f", corners) {
        Err(Error::FaultSurfaceNotResolved { point }) => point,
        other => panic!("expected FaultSurfaceNotResolved, got {other:?}"),
    };
    // Off the grid planes: no faces at all.
    let off = [[0.45, 0.25, 0.25], [0.45, 0.75, 0.25], [0.45, 0.75, 0.75]];
    assert_eq!(not_resolved(&off), off[0]);
    // Corners off the grid lines.
    let loose = [
        [0.5, 0.1, 0.25],
        [0.5, 0.75, 0.25],
        [0.5, 0.75, 0.75],
        [0.5, 0.25, 0.75],
    ];
    assert_eq!(not_resolved(&loose), loose[0]);
    // A triangle whose corners are mesh vertices but whose hypotenuse z = y/3 cuts faces:
    // the faces with their centroid inside have its area (3/32 m²), but none has the
    // corner at the sharp angle.
    let across = [[0.5, 0.0, 0.0], [0.5, 0.75, 0.0], [0.5, 0.75, 0.25]];
    assert_eq!(not_resolved(&across), across[0]);
    // A quadrilateral whose corners are vertices of the faces inside, with the edge
    // z = 1/4 + y/3 cutting faces: the point is on that edge.
    let cut = [
        [0.5, 0.0, 0.0],
        [0.5, 0.75, 0.0],
        [0.5, 0.75, 0.5],
        [0.5, 0.0, 0.25],
    ];
    let p = not_resolved(&cut);
    assert!(
        p[0] == 0.5 && (p[2] - 0.25 - p[1] / 3.0).abs() < 1e-12,
        "{p:?}"
    );
    assert!(p[1] > 0.0 && p[1] < 0.75, "{p:?}");
    // The anti-diagonal: centroids on the edge, whichever way they fall.
    let anti = [[0.5, 0.25, 0.25], [0.5, 0.75, 0.25], [0.5, 0.25, 0.75]];
    not_resolved(&anti);
    // Not planar, degenerate, non-finite, too few corners.
    let bent = [
        [0.5, 0.25, 0.25],
        [0.5, 0.75, 0.25],
        [0.75, 0.75, 0.75],
        [0.5, 0.25, 0.75],
    ];
    assert!(bent.contains(&not_resolved(&bent)));
    let line = [[0.5, 0.25, 0.25], [0.5, 0.5, 0.5], [0.5, 0.75, 0.75]];
    not_resolved(&line);
    not_resolved(&[[0.5, 0.25, 0.25], [0.5, f64::NAN, 0.25], [0.5, 0.75, 0.75]]);
    assert_eq!(
        m.split_along_polygon("f", &[[0.0; 3], [1.0, 0.0, 0.0]])
            .unwrap_err(),
        Error::EmptyFault
    );
    // On the outer boundary: found, then refused by the split.
    let outer = [
        [0.0, 0.25, 0.25],
        [0.0, 0.75, 0.25],
        [0.0, 0.75, 0.75],
        [0.0, 0.25, 0.75],
    ];
    assert!(matches!(
        m.split_along_polygon("f", &outer),
        Err(Error::FaultFaceOnBoundary { .. })
    ));
}

/// A kinked fault in `unit_cube(5)` across its whole width in y: x = 1/2 from the bottom
/// z = 0 up to z = 1/2, then x = z up to z = 3/4, its rim there buried (its faces found by
/// their vertices).
fn kinked() -> (TetrahedronMesh, Vec<[usize; 3]>) {
    let m = unit_cube(5);
    let on = |x: &[f64; 3]| {
        let lower = x[0] == 0.5 && x[2] <= 0.5;
        let upper = x[0] == x[2] && (0.5..=0.75).contains(&x[2]);
        lower || upper
    };
    let mut seen = HashSet::new();
    let mut faces = Vec::new();
    for c in 0..m.num_cells() {
        let cell = m.cell(c);
        for skip in 0..4 {
            let f: Vec<usize> = (0..4).filter(|&r| r != skip).map(|r| cell[r]).collect();
            let mut key = f.clone();
            key.sort_unstable();
            if f.iter().all(|&v| on(&m.vertices()[v])) && seen.insert(key) {
                faces.push([f[0], f[1], f[2]]);
            }
        }
    }
    (m, faces)
}

#[test]
fn the_mean_jump_transform_inverts_and_measures_the_jump_in_the_pair_frames() {
    let (m, faces) = kinked();
    assert_eq!(faces.len(), 16 + 8);
    let (s, sides) = m.split_along("f", &faces).unwrap();
    check_split(&m, &s, &sides, &faces);
    let pairs = sides.pairs();
    assert_eq!(pairs.len(), 15); // z = 0, 1/4, 1/2; the rim z = 3/4 shared
    assert_eq!(sides.tips().len(), 5);
    let dip = [1.0, 0.0, 1.0];
    let tr = sides.mean_jump_transform::<3>(&s, Some(&dip)).unwrap();
    assert_inverts(&tr);
    // The frames: orthonormal, right-handed, last column −n with n the area-weighted mean
    // of the faces' normals at the pair, first column the dip's projection.
    let x = m.vertices();
    let area = |f: &[usize; 3]| {
        let (a, b) = (
            [0, 1, 2].map(|r| x[f[1]][r] - x[f[0]][r]),
            [0, 1, 2].map(|r| x[f[2]][r] - x[f[0]][r]),
        );
        let c = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        0.5 * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
    };
    let mut kinds = HashSet::new();
    for (&(mi, _), r) in pairs.iter().zip(&tr.frames) {
        let mut n = [0.0; 3];
        for (k, f) in faces.iter().enumerate() {
            if f.contains(&mi) {
                (0..3).for_each(|c| n[c] += area(f) * sides.normals()[k][c]);
            }
        }
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        for c in 0..3 {
            assert!((r[c][2] + n[c] / l).abs() < 1e-15);
            for d in 0..3 {
                let g: f64 = (0..3).map(|e| r[e][c] * r[e][d]).sum();
                assert!((g - f64::from(u8::from(c == d))).abs() < 1e-15);
            }
        }
        let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
            - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
            + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
        assert!((det - 1.0).abs() < 1e-15);
        // t1 in the xz-plane (the dip's projection), t2 along ±y.
        assert!(r[1][0].abs() < 1e-15 && (r[1][1].abs() - 1.0).abs() < 1e-15);
        // Below the kink ±x; at the kink between ±x and ±(−1, 0, 1)/√2.
        let nz = (n[2] / l).abs();
        if s.vertices()[mi][2] < 0.5 {
            assert!(nz < 1e-15);
        } else {
            assert!(nz > 0.1 && nz < 0.5f64.sqrt() - 0.1);
        }
        kinds.insert((nz * 1e6).round() as i64);
    }
    assert!(kinds.len() >= 2);
    // New coordinates of a Cartesian field: R_pᵀ(u⁺ − u⁻) at p⁻, the mean at p⁺.
    let u: Vec<f64> = (0..3 * s.num_vertices())
        .map(|i| ((i * 7919) % 101) as f64 / 101.0 - 0.5)
        .collect();
    let up = matvec(&dense(&tr.t_inv), &u);
    for (&(mi, pl), r) in pairs.iter().zip(&tr.frames) {
        for c in 0..3 {
            let j: f64 = (0..3)
                .map(|e| r[e][c] * (u[3 * pl + e] - u[3 * mi + e]))
                .sum();
            assert!((up[3 * mi + c] - j).abs() < 1e-15);
            let w = 0.5 * (u[3 * pl + c] + u[3 * mi + c]);
            assert!((up[3 * pl + c] - w).abs() < 1e-15);
        }
    }
    // Rigid motions have no jump and no force.
    let k = stiffness(&s, &LinearElasticity::isotropic(1e10, 0.25).unwrap());
    let kp = dense(&tr.congruence(&k).unwrap());
    let scale = largest(&dense(&k));
    let ti = dense(&tr.t_inv);
    for (a, w) in [([1.0, 2.0, 3.0], [0.0; 3]), ([0.0; 3], [1e-3, -2e-3, 3e-3])] {
        let rigid: Vec<f64> = s
            .vertices()
            .iter()
            .flat_map(|x| {
                [
                    a[0] + w[1] * x[2] - w[2] * x[1],
                    a[1] + w[2] * x[0] - w[0] * x[2],
                    a[2] + w[0] * x[1] - w[1] * x[0],
                ]
            })
            .collect();
        let rp = matvec(&ti, &rigid);
        for &(mi, _) in &pairs {
            assert!((0..3).all(|c| rp[3 * mi + c].abs() < 1e-15));
        }
        assert!(matvec(&kp, &rp).iter().all(|f| f.abs() < 1e-12 * scale));
    }
    // Scalar fields; unsupported C; the unsplit mesh.
    let t1 = sides.mean_jump_transform::<1>(&s, None).unwrap();
    assert_eq!(t1.t.nrows(), s.num_vertices());
    assert!(matches!(
        sides.mean_jump_transform::<2>(&s, None),
        Err(Error::Unsupported(_))
    ));
    assert!(matches!(
        sides.mean_jump_transform::<3>(&m, None),
        Err(Error::DimensionMismatch { .. })
    ));
}

#[test]
fn an_interior_physical_surface_of_a_gmsh_file_is_a_fault_to_split() {
    // The box fixture's `fault` group gets the two triangles of the inner face x = 1
    // between its cubes (nodes 8, 5, 11 and 8, 2, 5) instead of its first two at z = 0.
    let text = include_str!("../fixtures/box.msh").replacen(
        "15 7 8 11\n16 7 11 10\n",
        "15 8 5 11\n16 8 2 5\n",
        1,
    );
    let g = parse_with_interior_facets::<3>(&text);
    // Node tag t ≤ 12 is vertex t − 1.
    assert_eq!(g.interior_facets["fault"], vec![[7, 4, 10], [7, 1, 4]]);
    let (split, sides) = g.split_along_group("fault").unwrap();
    check_split(&g.mesh, &split, &sides, &g.interior_facets["fault"]);
    // Through the whole box: the four nodes of x = 1 split, the cubes come apart.
    assert_eq!(sides.pairs().len(), 4);
    assert!(sides.tips().is_empty());
    assert_eq!(split.num_vertices(), 14 + 4);
    assert_eq!(components(&split), 2);
    assert!((split.measure() - 2.0).abs() < 1e-14);
    // (1,0,0) → (1,1,1) → (1,1,0): the right-hand rule gives −x, the plus side is x < 1.
    assert!(sides.normals().iter().all(|n| *n == [-1.0, 0.0, 0.0]));
    assert_eq!(split.facets_with_tag("fault").len(), 2);
    assert_eq!(split.facets_with_tag("fault_plus").len(), 2);
    assert_eq!(g.split_along_group("top").unwrap_err(), Error::EmptyFault);
}
