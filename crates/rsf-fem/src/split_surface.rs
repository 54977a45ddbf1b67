//! Faults inside a 3-D body: a surface of mesh triangles cut open (docs/math.md §13,
//! docs/faults-inside.md), the 3-D counterpart of `split.rs` with its conventions.

use std::collections::{HashMap, VecDeque};

use nalgebra::Vector3;

use crate::split::{add_plus_copy, cell_groups_around, facet_key, tag_split_facets};
use crate::{Error, FaultSides, Result, SimplexMesh};

type V3 = [f64; 3];

/// A point as a nalgebra vector.
fn v(x: &V3) -> Vector3<f64> {
    Vector3::from(*x)
}

/// The right-hand-rule normal `(b − a) × (c − a)` of the triangle `a, b, c` (twice its
/// area long).
fn area_normal(a: &V3, b: &V3, c: &V3) -> Vector3<f64> {
    (v(b) - v(a)).cross(&(v(c) - v(a)))
}

impl SimplexMesh<3> {
    /// Cuts the mesh open along a fault surface given as mesh faces `[a, b, c]` (vertex
    /// indices of interior triangles of the mesh, in any order and orientation).
    ///
    /// Orientation: the first face's right-hand-rule normal `(x_b − x_a) × (x_c − x_a)`
    /// sets the fault's; the others are reoriented consistently with it (a breadth-first
    /// walk over shared edges; two faces sharing an edge agree if they traverse it in
    /// opposite directions). [`FaultSides::normals`] has the unit normal of every face in
    /// input order, pointing from the minus into the plus side.
    ///
    /// Split rule, for every fault vertex `p` in increasing index: the cells around `p` are
    /// grouped by adjacency through faces containing `p` that are not fault faces. One
    /// group: a tip, shared (`(p, p)`; the fault's rim inside the body, including where the
    /// rim meets the outer boundary). Two groups: `p` is split, the plus group being the
    /// one holding the cells on the normal's side of the fault faces at `p`; its cells are
    /// renumbered to a plus copy `q` appended after the original vertices (in increasing
    /// `p`), and [`FaultSides::nodes`] lists `(p, q)` or `(p, p)` in increasing `p`.
    ///
    /// The split mesh keeps the vertices (plus copies appended), the cells in their order
    /// with their vertex order and refinement order, and the tags of the old boundary
    /// facets; the fault's faces become boundary facets tagged `{name}_minus` and
    /// `{name}_plus` ([`FaultSides::minus_facets`], [`FaultSides::plus_facets`]: one per
    /// face in input order). A face whose three vertices are all tips stays closed (see
    /// [`FaultSides`]). Element measures and orientations are unchanged.
    ///
    /// # Errors
    /// [`Error::EmptyFault`]; [`Error::FaultFaceNotInMesh`] (a vertex out of range, two
    /// equal vertices, or no face of the mesh); [`Error::FaultFaceOnBoundary`];
    /// [`Error::FaultFaceRepeated`]; [`Error::FaultEdgeNotManifold`] (more than two fault
    /// faces at an edge); [`Error::FaultNotOrientable`]; [`Error::FaultDisconnected`] (the
    /// faces are not connected through shared edges); [`Error::FaultSidesNotSeparated`]
    /// (more than two groups of cells around a vertex, or the fault faces at a vertex do not
    /// have their plus and minus cells in different groups: e.g. a fault surface that
    /// touches the outer boundary along two edges through one vertex).
    ///
    /// ```
    /// use rsf_fem::cuboid;
    /// // The unit cube with 4 cells per edge (vertex i + 5 j + 25 k at (i, j, k)/4), cut
    /// // through along x = 1/2: every one of the 25 fault vertices is split.
    /// let mesh = cuboid([0.0; 3], [1.0; 3], [5, 5, 5])?;
    /// let id = |i: usize, j: usize, k: usize| i + 5 * j + 25 * k;
    /// let mut faces = Vec::new();
    /// for j in 0..4 {
    ///     for k in 0..4 {
    ///         // The Kuhn cells split each square along the (0, 1, 1) diagonal.
    ///         faces.push([id(2, j, k), id(2, j + 1, k), id(2, j + 1, k + 1)]);
    ///         faces.push([id(2, j, k), id(2, j + 1, k + 1), id(2, j, k + 1)]);
    ///     }
    /// }
    /// let (split, sides) = mesh.split_along("fault", &faces)?;
    /// assert_eq!(split.num_vertices(), mesh.num_vertices() + 25);
    /// assert!(sides.tips().is_empty());
    /// assert_eq!(sides.normals()[0], [1.0, 0.0, 0.0]); // plus side: x > 1/2
    /// assert_eq!(split.facets_with_tag("fault_plus").len(), 32);
    /// # Ok::<(), rsf_fem::Error>(())
    /// ```
    pub fn split_along(&self, name: &str, faces: &[[usize; 3]]) -> Result<(Self, FaultSides<3>)> {
        if faces.is_empty() {
            return Err(Error::EmptyFault);
        }
        let nv = self.num_vertices();
        let mut vertex_cells: Vec<Vec<usize>> = vec![Vec::new(); nv];
        for c in 0..self.num_cells() {
            for &v in self.cell(c) {
                vertex_cells[v].push(c);
            }
        }
        // Validate the faces; the cells of each.
        let mut fault: HashMap<[usize; 3], usize> = HashMap::new();
        let mut face_cells = Vec::with_capacity(faces.len());
        for (i, &[a, b, c]) in faces.iter().enumerate() {
            let cells: Vec<usize> = if a < nv && b < nv && c < nv && a != b && b != c && a != c {
                vertex_cells[a]
                    .iter()
                    .copied()
                    .filter(|&x| self.cell(x).contains(&b) && self.cell(x).contains(&c))
                    .collect()
            } else {
                Vec::new()
            };
            let vertices = [a, b, c];
            match cells.len() {
                0 => return Err(Error::FaultFaceNotInMesh { face: i, vertices }),
                1 => return Err(Error::FaultFaceOnBoundary { face: i, vertices }),
                _ => {}
            }
            if fault.insert(facet_key(&vertices), i).is_some() {
                return Err(Error::FaultFaceRepeated { face: i, vertices });
            }
            face_cells.push([cells[0], cells[1]]);
        }
        let oriented = orient_faces(faces)?;
        let x = self.vertices();
        // Normals, and the cell of each face on the normal's side (the plus side).
        let mut normals = Vec::with_capacity(faces.len());
        let mut plus_cells = Vec::with_capacity(faces.len());
        let mut minus_cells = Vec::with_capacity(faces.len());
        for (f, cells) in oriented.iter().zip(&face_cells) {
            let n = area_normal(&x[f[0]], &x[f[1]], &x[f[2]]);
            let l = n.norm();
            normals.push([n[0] / l, n[1] / l, n[2] / l]);
            let d = |c: usize| {
                *self
                    .cell(c)
                    .iter()
                    .find(|v| !f.contains(v))
                    .expect("a tetrahedron has a fourth vertex")
            };
            let (p, m) = if (v(&x[d(cells[0])]) - v(&x[f[0]])).dot(&n) > 0.0 {
                (cells[0], cells[1])
            } else {
                (cells[1], cells[0])
            };
            plus_cells.push(p);
            minus_cells.push(m);
        }
        // The faces at every fault vertex, vertices in increasing order.
        let mut at_vertex: HashMap<usize, Vec<usize>> = HashMap::new();
        for (k, f) in faces.iter().enumerate() {
            for &v in f {
                at_vertex.entry(v).or_default().push(k);
            }
        }
        let mut fault_vertices: Vec<usize> = at_vertex.keys().copied().collect();
        fault_vertices.sort_unstable();
        let mut cells = self.cells().to_vec();
        let mut vertices = self.vertices().to_vec();
        let mut original: Vec<usize> = (0..nv).collect();
        let mut nodes = Vec::with_capacity(fault_vertices.len());
        for &p in &fault_vertices {
            let around = &vertex_cells[p];
            let (group, groups) = cell_groups_around(self, p, around, |k| fault.contains_key(k));
            if groups == 1 {
                nodes.push((p, p));
                continue;
            }
            let g = |c: usize| group[around.iter().position(|&x| x == c).expect("cell at p")];
            let at = &at_vertex[&p];
            let plus_group = g(plus_cells[at[0]]);
            if groups != 2
                || at
                    .iter()
                    .any(|&k| g(plus_cells[k]) != plus_group || g(minus_cells[k]) == plus_group)
            {
                return Err(Error::FaultSidesNotSeparated { vertex: p });
            }
            let q = add_plus_copy(p, around, &group, plus_group, &mut vertices, &mut cells);
            original.push(p);
            nodes.push((p, q));
        }
        let mut split = Self::new(vertices, cells)?;
        split.copy_refinement_orders(self);
        let (minus_facets, plus_facets) =
            tag_split_facets(self, &mut split, name, &original, &fault, &plus_cells);
        let sides = FaultSides::alone(name, nodes, minus_facets, plus_facets, normals);
        Ok((split, sides))
    }

    /// [`SimplexMesh::split_along`] for a planar polygon with corners `corners` (m, at least
    /// three, coplanar within `1e-9` of the polygon's size): the fault is every mesh face
    /// whose three vertices lie on the polygon's plane (within `1e-9·size`) and whose
    /// centroid lies inside the polygon, each oriented so that its normal agrees with the
    /// polygon's (the right-hand rule of the corners' order, pointing from the minus into
    /// the plus side). The polygon must be simple (not crossing itself; convex polygons,
    /// the usual case, are); the faces must tile it. For a cut through a structured mesh
    /// ([`crate::cuboid`]) whose grid planes contain the polygon, on every level of a
    /// uniformly refined hierarchy that resolves it (the 3-D analogue of
    /// `SimplexMesh::<2>::split_along_polyline`).
    ///
    /// # Errors
    /// [`Error::EmptyFault`] for fewer than three corners; [`Error::FaultSurfaceNotResolved`]
    /// for a non-finite, non-planar or degenerate (zero-area) polygon (the point is a
    /// corner), or one the mesh faces do not tile: a face sticks out of the polygon (the
    /// point is where the polygon's edge cuts it), or the faces' total area differs from the
    /// polygon's by more than `1e-9` of it (the point is a corner that is no mesh vertex, or
    /// on the edge of an uncovered part); otherwise as [`SimplexMesh::split_along`].
    pub fn split_along_polygon(
        &self,
        name: &str,
        corners: &[[f64; 3]],
    ) -> Result<(Self, FaultSides<3>)> {
        let faces = self.faces_in_polygon(corners)?;
        self.split_along(name, &faces)
    }

    /// The mesh faces tiling the planar polygon `corners` (m), oriented along its normal
    /// (the faces `split_along_polygon` cuts).
    ///
    /// # Errors
    /// As `split_along_polygon`'s [`Error::EmptyFault`] and
    /// [`Error::FaultSurfaceNotResolved`].
    pub fn faces_in_polygon(&self, corners: &[[f64; 3]]) -> Result<Vec<[usize; 3]>> {
        if corners.len() < 3 {
            return Err(Error::EmptyFault);
        }
        if let Some(c) = corners.iter().find(|c| c.iter().any(|x| !x.is_finite())) {
            return Err(Error::FaultSurfaceNotResolved { point: *c });
        }
        let c0 = corners[0];
        let size = corners
            .iter()
            .flat_map(|a| corners.iter().map(move |b| (v(a) - v(b)).norm()))
            .fold(0.0, f64::max);
        // Area vector (twice the area, along the right-hand-rule normal).
        let av: Vector3<f64> = corners[1..]
            .windows(2)
            .map(|w| area_normal(&c0, &w[0], &w[1]))
            .sum();
        let area = 0.5 * av.norm();
        if !(area > 1e-12 * size * size) {
            return Err(Error::FaultSurfaceNotResolved { point: c0 });
        }
        let n = av * (0.5 / area);
        let tol = 1e-9 * size;
        if let Some(c) = corners.iter().find(|c| (v(c) - v(&c0)).dot(&n).abs() > tol) {
            return Err(Error::FaultSurfaceNotResolved { point: *c });
        }
        // In-plane coordinates: e1 along the first side, e2 = n × e1.
        let s1 = v(&corners[1]) - v(&c0);
        let e1 = (s1 - n * s1.dot(&n)).normalize();
        let e2 = n.cross(&e1);
        let plane = |p: &V3| {
            let r = v(p) - v(&c0);
            [r.dot(&e1), r.dot(&e2)]
        };
        let poly: Vec<[f64; 2]> = corners.iter().map(plane).collect();
        // Even–odd rule.
        let inside = |q: [f64; 2]| {
            let mut crossings = false;
            for (i, a) in poly.iter().enumerate() {
                let b = &poly[(i + 1) % poly.len()];
                if (a[1] > q[1]) != (b[1] > q[1]) {
                    let xc = a[0] + (q[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
                    if q[0] < xc {
                        crossings = !crossings;
                    }
                }
            }
            crossings
        };
        let x = self.vertices();
        let on_plane: Vec<bool> = x
            .iter()
            .map(|p| (v(p) - v(&c0)).dot(&n).abs() <= tol)
            .collect();
        let mut faces = Vec::new();
        let mut covered = 0.0;
        for mut f in self.facets() {
            if !f.iter().all(|&v| on_plane[v]) {
                continue;
            }
            let centroid: V3 =
                std::array::from_fn(|r| f.iter().map(|&v| x[v][r]).sum::<f64>() / 3.0);
            if !inside(plane(&centroid)) {
                continue;
            }
            let nf = area_normal(&x[f[0]], &x[f[1]], &x[f[2]]);
            if nf.dot(&n) < 0.0 {
                f.swap(1, 2);
            }
            covered += 0.5 * nf.norm();
            faces.push(f);
        }
        // The faces tile the polygon iff they lie in it (they do not overlap: faces of a
        // conforming mesh) and cover its area.
        let polygon = Polygon {
            corners,
            origin: c0,
            e1,
            e2,
            poly: &poly,
            tol,
        };
        if let Some(point) = polygon.not_tiled_by(x, &faces, inside, covered, area) {
            return Err(Error::FaultSurfaceNotResolved { point });
        }
        Ok(faces)
    }
}

/// A planar polygon with its in-plane coordinates `(r·e1, r·e2)`, `r = x − origin`.
struct Polygon<'a> {
    corners: &'a [V3],
    origin: V3,
    e1: Vector3<f64>,
    e2: Vector3<f64>,
    poly: &'a [[f64; 2]],
    tol: f64,
}

impl Polygon<'_> {
    fn plane(&self, p: &V3) -> [f64; 2] {
        let r = v(p) - v(&self.origin);
        [r.dot(&self.e1), r.dot(&self.e2)]
    }
    fn point(&self, q: [f64; 2]) -> V3 {
        (v(&self.origin) + self.e1 * q[0] + self.e2 * q[1]).into()
    }
    /// The point of the polygon's edges nearest to `q` (in-plane coordinates) and its
    /// distance.
    fn nearest_on_edges(&self, q: [f64; 2]) -> ([f64; 2], f64) {
        let poly = self.poly;
        (0..poly.len())
            .map(|i| {
                let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                let d = [b[0] - a[0], b[1] - a[1]];
                let t = (((q[0] - a[0]) * d[0] + (q[1] - a[1]) * d[1])
                    / (d[0] * d[0] + d[1] * d[1]))
                    .clamp(0.0, 1.0);
                let e = [a[0] + t * d[0], a[1] + t * d[1]];
                (e, (q[0] - e[0]).hypot(q[1] - e[1]))
            })
            .fold(
                ([0.0; 2], f64::INFINITY),
                |m, e| if e.1 < m.1 { e } else { m },
            )
    }

    /// `None` if `faces` (of total area `covered`, all with their centroid inside) tile the
    /// polygon of area `area`; else a point near which they do not: a corner that is no
    /// vertex of a face, the point of the polygon's edge nearest to a face's vertex outside
    /// the polygon (the edge cuts that face), or the midpoint of an edge of the faces' rim
    /// that is not on the polygon's edges (an uncovered part), else the first corner.
    fn not_tiled_by(
        &self,
        x: &[V3],
        faces: &[[usize; 3]],
        inside: impl Fn([f64; 2]) -> bool,
        covered: f64,
        area: f64,
    ) -> Option<V3> {
        let near = |a: &V3, b: &V3| (v(a) - v(b)).norm() <= self.tol;
        if let Some(c) = self
            .corners
            .iter()
            .find(|c| !faces.iter().flatten().any(|&v| near(&x[v], c)))
        {
            return Some(*c);
        }
        for &v in faces.iter().flatten() {
            let q = self.plane(&x[v]);
            let (e, d) = self.nearest_on_edges(q);
            if d > self.tol && !inside(q) {
                return Some(self.point(e));
            }
        }
        if (covered - area).abs() <= 1e-9 * area {
            return None;
        }
        let mut count: HashMap<(usize, usize), usize> = HashMap::new();
        for f in faces {
            for k in 0..3 {
                let (a, b) = (f[k], f[(k + 1) % 3]);
                *count.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let mut rim: Vec<(usize, usize)> = count
            .into_iter()
            .filter(|&(_, n)| n == 1)
            .map(|(e, _)| e)
            .collect();
        rim.sort_unstable();
        Some(
            rim.into_iter()
                .map(|(a, b)| std::array::from_fn(|r| 0.5 * (x[a][r] + x[b][r])))
                .find(|m: &V3| self.nearest_on_edges(self.plane(m)).1 > self.tol)
                .unwrap_or(self.corners[0]),
        )
    }
}

/// Checks that no edge has more than two of `faces`, that they are connected through
/// shared edges, and orients them consistently with the first: returns every face as
/// given or with its last two vertices swapped.
fn orient_faces(faces: &[[usize; 3]]) -> Result<Vec<[usize; 3]>> {
    let mut edge_faces: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for (i, f) in faces.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            let list = edge_faces.entry((a.min(b), a.max(b))).or_default();
            list.push(i);
            if list.len() > 2 {
                return Err(Error::FaultEdgeNotManifold {
                    vertices: [a.min(b), a.max(b)],
                    faces: list.len(),
                });
            }
        }
    }
    let traverses =
        |f: &[usize; 3], a: usize, b: usize| (0..3).any(|k| f[k] == a && f[(k + 1) % 3] == b);
    // flip[i]: whether face i is reversed; None while unvisited.
    let mut flip: Vec<Option<bool>> = vec![None; faces.len()];
    flip[0] = Some(false);
    let mut queue = VecDeque::from([0]);
    let oriented = |f: [usize; 3], flipped: bool| if flipped { [f[0], f[2], f[1]] } else { f };
    while let Some(i) = queue.pop_front() {
        let fi = oriented(faces[i], flip[i].expect("visited"));
        for k in 0..3 {
            let (a, b) = (fi[k], fi[(k + 1) % 3]);
            for &j in &edge_faces[&(a.min(b), a.max(b))] {
                if j == i {
                    continue;
                }
                // Face j must traverse the edge as b → a.
                let need = traverses(&faces[j], a, b);
                match flip[j] {
                    None => {
                        flip[j] = Some(need);
                        queue.push_back(j);
                    }
                    Some(f) if f != need => return Err(Error::FaultNotOrientable { face: j }),
                    Some(_) => {}
                }
            }
        }
    }
    if let Some(i) = flip.iter().position(Option::is_none) {
        return Err(Error::FaultDisconnected {
            vertex: faces[i][0],
        });
    }
    Ok(faces
        .iter()
        .zip(&flip)
        .map(|(&f, fl)| oriented(f, fl.expect("all visited")))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_moebius_strip_is_not_orientable() {
        // The five-vertex Möbius band: triangles (i, i+1, i+2) mod 5.
        let faces: Vec<[usize; 3]> = (0..5).map(|i| [i, (i + 1) % 5, (i + 2) % 5]).collect();
        assert!(matches!(
            orient_faces(&faces),
            Err(Error::FaultNotOrientable { .. })
        ));
        // An annulus (the same band with one twist undone) is orientable: a strip of
        // triangles around a hexagonal hole, given with alternating orientations.
        let mut ring = Vec::new();
        for i in 0..6 {
            let (a, b, c, d) = (i, (i + 1) % 6, 6 + i, 6 + (i + 1) % 6);
            ring.push([a, b, c]);
            ring.push([b, c, d]); // reversed relative to [a, b, c]'s orientation
        }
        let o = orient_faces(&ring).unwrap();
        assert_eq!(o[0], ring[0]);
        assert_eq!(o[1], [1, 7, 6]);
        // Every interior edge traversed once each way.
        let mut count: HashMap<(usize, usize), i32> = HashMap::new();
        for f in &o {
            for k in 0..3 {
                *count.entry((f[k], f[(k + 1) % 3])).or_default() += 1;
            }
        }
        assert!(count.values().all(|&n| n == 1));
        assert!(matches!(
            orient_faces(&[[0, 1, 2], [3, 4, 5]]),
            Err(Error::FaultDisconnected { vertex: 3 })
        ));
    }
}
