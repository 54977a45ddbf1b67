//! Faults inside the body: split nodes (docs/math.md §13, docs/faults-inside.md).
//!
//! A fault given as a chain of interior mesh edges (2-D) is cut open: every fault node
//! becomes a minus and a plus copy, the cells on the plus side are renumbered to the plus
//! copies, and the two faces of the cut become boundary facets tagged `{name}_minus` and
//! `{name}_plus`. A chain end inside the body (a tip) stays shared; a chain end on the outer
//! boundary (e.g. a free surface) is split. Coordinates and the order of every cell's
//! vertices are unchanged, so assembly per cell is unchanged.

use std::collections::HashMap;

use crate::{Error, Result, SimplexMesh};

/// The two sides of a fault cut by [`SimplexMesh::split_along`].
///
/// The fault is a chain of nodes `x_0, …, x_m` (m ≥ 1 edges); its direction is the
/// direction of the first listed edge. The unit normal `n_k` of edge `k` (from `x_k` to
/// `x_{k+1}`, tangent `t_k`) is `t_k` turned by +90°, `n = (−t_y, t_x)`: it points from the
/// minus side into the plus side, so it is the outward normal of the minus side's facet
/// and `−n_k` that of the plus side's. Slip is the jump `u⁺ − u⁻` (docs/math.md §13).
#[derive(Debug, Clone, PartialEq)]
pub struct FaultSides<const D: usize = 2> {
    name: String,
    nodes: Vec<(usize, usize)>,
    minus_facets: Vec<usize>,
    plus_facets: Vec<usize>,
    normals: Vec<[f64; D]>,
}

impl<const D: usize> FaultSides<D> {
    /// The fault's name (the side tags are [`FaultSides::minus_tag`], [`FaultSides::plus_tag`]).
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Tag of the minus side's boundary facets: `{name}_minus`.
    pub fn minus_tag(&self) -> String {
        format!("{}_minus", self.name)
    }
    /// Tag of the plus side's boundary facets: `{name}_plus`.
    pub fn plus_tag(&self) -> String {
        format!("{}_plus", self.name)
    }
    /// Every fault node in order along the fault as `(minus, plus)` vertex indices of the
    /// split mesh; a tip (shared node) appears as `(p, p)`.
    pub fn nodes(&self) -> &[(usize, usize)] {
        &self.nodes
    }
    /// The split pairs `(minus, plus)` in order along the fault (tips left out).
    pub fn pairs(&self) -> Vec<(usize, usize)> {
        self.nodes.iter().copied().filter(|(m, p)| m != p).collect()
    }
    /// The tips: fault nodes inside the body, shared by both sides.
    pub fn tips(&self) -> Vec<usize> {
        self.nodes
            .iter()
            .filter(|(m, p)| m == p)
            .map(|&(m, _)| m)
            .collect()
    }
    /// Boundary facet indices (of the split mesh) of the minus side, one per fault edge in
    /// order along the fault.
    pub fn minus_facets(&self) -> &[usize] {
        &self.minus_facets
    }
    /// Boundary facet indices (of the split mesh) of the plus side, one per fault edge.
    pub fn plus_facets(&self) -> &[usize] {
        &self.plus_facets
    }
    /// Unit normal of every fault edge, pointing from the minus into the plus side (the
    /// minus side's outward normal; the plus side's is its negative).
    pub fn normals(&self) -> &[[f64; D]] {
        &self.normals
    }
    /// The jump `u⁺ − u⁻` of a node-major field with `c` components per vertex at every
    /// fault node (zero at tips), in order along the fault.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if `u` is too short for the split mesh's nodes.
    pub fn jump(&self, u: &[f64], c: usize) -> Result<Vec<Vec<f64>>> {
        let need = self
            .nodes
            .iter()
            .map(|&(m, p)| m.max(p) + 1)
            .max()
            .unwrap_or(0)
            * c;
        if u.len() < need {
            return Err(Error::DimensionMismatch {
                what: "field for a fault jump",
                expected: need,
                got: u.len(),
            });
        }
        Ok(self
            .nodes
            .iter()
            .map(|&(m, p)| (0..c).map(|r| u[c * p + r] - u[c * m + r]).collect())
            .collect())
    }
}

impl SimplexMesh<2> {
    /// Cuts the mesh open along a fault given as mesh edges `[a, b]` (vertex indices; the
    /// direction of the first edge sets the fault's direction, see [`FaultSides`]).
    ///
    /// Returns the split mesh and the description of its two sides. The split mesh keeps
    /// the vertices (the plus copies appended after them, in order along the fault), the
    /// cells with their vertex order and refinement order, and the tags of the old
    /// boundary facets; the new faces carry the tags `{name}_minus` and `{name}_plus`.
    /// Element measures and orientations are unchanged.
    ///
    /// # Errors
    /// [`Error::EmptyFault`]; [`Error::FaultEdgeNotInMesh`] (an entry that is not a mesh
    /// edge), [`Error::FaultEdgeOnBoundary`] (an edge of the outer boundary, which has one
    /// side only), [`Error::FaultEdgeRepeated`]; [`Error::FaultNotManifold`] (a vertex with
    /// more than two fault edges: the fault branches or crosses itself);
    /// [`Error::FaultClosed`]; [`Error::FaultDisconnected`];
    /// [`Error::FaultSidesNotSeparated`] (the fault does not cut the cells around a vertex
    /// into two sides, e.g. a node inside the chain that lies on the outer boundary).
    ///
    /// ```
    /// use rsf_fem::{rectangle, Diagonal};
    /// let mesh = rectangle([-2.0, -2.0], [4.0, 2.0], 17, 9, Diagonal::Forward)?;
    /// // A vertical fault from the surface y = 0 to depth 1 m (vertex i + 17 j sits at
    /// // (-2 + i/4, -2 + j/4)): the surface node is split, the tip at (0, -1) is shared.
    /// let id = |i: usize, j: usize| i + 17 * j;
    /// let edges: Vec<[usize; 2]> = (4..8).rev().map(|j| [id(8, j + 1), id(8, j)]).collect();
    /// let (split, sides) = mesh.split_along("fault", &edges)?;
    /// assert_eq!(split.num_vertices(), mesh.num_vertices() + 4);
    /// assert_eq!(sides.tips(), [id(8, 4)]);
    /// assert_eq!(sides.normals()[0], [1.0, 0.0]); // plus side: x > 0
    /// assert_eq!(split.facets_with_tag("fault_plus").len(), 4);
    /// # Ok::<(), rsf_fem::Error>(())
    /// ```
    pub fn split_along(&self, name: &str, edges: &[[usize; 2]]) -> Result<(Self, FaultSides)> {
        if edges.is_empty() {
            return Err(Error::EmptyFault);
        }
        let nv = self.num_vertices();
        let key = |a: usize, b: usize| (a.min(b), a.max(b));
        // Every mesh edge with its cells.
        let mut edge_cells: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
        let mut vertex_cells: Vec<Vec<usize>> = vec![Vec::new(); nv];
        for c in 0..self.num_cells() {
            let cell = self.cell(c);
            for k in 0..3 {
                edge_cells
                    .entry(key(cell[k], cell[(k + 1) % 3]))
                    .or_default()
                    .push(c);
                vertex_cells[cell[k]].push(c);
            }
        }
        // Validate the edges and collect the fault's adjacency.
        let mut fault_edge: HashMap<(usize, usize), usize> = HashMap::new();
        let mut at_vertex: HashMap<usize, Vec<usize>> = HashMap::new();
        for (i, &[a, b]) in edges.iter().enumerate() {
            let cells = if a < nv && b < nv && a != b {
                edge_cells.get(&key(a, b))
            } else {
                None
            };
            match cells.map(Vec::len) {
                None => {
                    return Err(Error::FaultEdgeNotInMesh {
                        edge: i,
                        vertices: [a, b],
                    })
                }
                Some(1) => {
                    return Err(Error::FaultEdgeOnBoundary {
                        edge: i,
                        vertices: [a, b],
                    })
                }
                _ => {}
            }
            if fault_edge.insert(key(a, b), i).is_some() {
                return Err(Error::FaultEdgeRepeated {
                    edge: i,
                    vertices: [a, b],
                });
            }
            for v in [a, b] {
                let list = at_vertex.entry(v).or_default();
                list.push(i);
                if list.len() > 2 {
                    return Err(Error::FaultNotManifold {
                        vertex: v,
                        edges: list.len(),
                    });
                }
            }
        }
        // Order the chain: walk forward from the first edge's end, backward from its start.
        let other = |e: usize, v: usize| {
            if edges[e][0] == v {
                edges[e][1]
            } else {
                edges[e][0]
            }
        };
        let walk = |start: usize, from_edge: usize, stop: usize| -> Result<Vec<usize>> {
            let mut out = Vec::new();
            let (mut v, mut e) = (start, from_edge);
            while let Some(&next) = at_vertex[&v].iter().find(|&&x| x != e) {
                let w = other(next, v);
                if w == stop {
                    return Err(Error::FaultClosed { vertex: stop });
                }
                out.push(w);
                (v, e) = (w, next);
            }
            Ok(out)
        };
        let [a0, b0] = edges[0];
        let forward = walk(b0, 0, a0)?;
        let backward = walk(a0, 0, b0)?;
        let chain: Vec<usize> = backward
            .into_iter()
            .rev()
            .chain([a0, b0])
            .chain(forward)
            .collect();
        if chain.len() - 1 != edges.len() {
            let on_chain: std::collections::HashSet<usize> = chain.iter().copied().collect();
            let stray = edges
                .iter()
                .find(|e| !on_chain.contains(&e[0]))
                .map_or(edges[0][0], |e| e[0]);
            return Err(Error::FaultDisconnected { vertex: stray });
        }
        let mut on_boundary = vec![false; nv];
        for f in 0..self.num_boundary_facets() {
            for &v in self.boundary_facet(f) {
                on_boundary[v] = true;
            }
        }
        // The cell left of directed edge (a, b): its counter-clockwise order has a then b.
        let left_cell = |a: usize, b: usize| -> usize {
            let cells = &edge_cells[&key(a, b)];
            *cells
                .iter()
                .find(|&&c| {
                    let cell = self.cell(c);
                    (0..3).any(|k| cell[k] == a && cell[(k + 1) % 3] == b)
                })
                .expect("an interior edge has a cell on each side")
        };
        let mut cells = self.cells().to_vec();
        let mut vertices = self.vertices().to_vec();
        let mut original: Vec<usize> = (0..nv).collect();
        let mut nodes = Vec::with_capacity(chain.len());
        let m = chain.len() - 1;
        for (i, &p) in chain.iter().enumerate() {
            let end = i == 0 || i == m;
            if end && !on_boundary[p] {
                nodes.push((p, p));
                continue;
            }
            if !end && on_boundary[p] {
                return Err(Error::FaultSidesNotSeparated { vertex: p });
            }
            // Group the cells around p: neighbours across a non-fault edge through p.
            let around = &vertex_cells[p];
            let mut group = vec![usize::MAX; around.len()];
            let mut groups = 0;
            for s in 0..around.len() {
                if group[s] != usize::MAX {
                    continue;
                }
                group[s] = groups;
                let mut stack = vec![s];
                while let Some(x) = stack.pop() {
                    let cx = self.cell(around[x]);
                    for &q in cx.iter().filter(|&&q| q != p) {
                        if fault_edge.contains_key(&key(p, q)) {
                            continue;
                        }
                        for (y, &cy) in around.iter().enumerate() {
                            if group[y] == usize::MAX && self.cell(cy).contains(&q) {
                                group[y] = groups;
                                stack.push(y);
                            }
                        }
                    }
                }
                groups += 1;
            }
            let (ea, eb) = if i < m {
                (chain[i], chain[i + 1])
            } else {
                (chain[i - 1], chain[i])
            };
            let plus_cell = left_cell(ea, eb);
            let minus_cell = left_cell(eb, ea);
            let g = |c: usize| group[around.iter().position(|&x| x == c).expect("cell at p")];
            if groups != 2 || g(plus_cell) == g(minus_cell) {
                return Err(Error::FaultSidesNotSeparated { vertex: p });
            }
            let plus_group = g(plus_cell);
            let q = vertices.len();
            vertices.push(vertices[p]);
            original.push(p);
            for (s, &c) in around.iter().enumerate() {
                if group[s] == plus_group {
                    for v in &mut cells[3 * c..3 * c + 3] {
                        if *v == p {
                            *v = q;
                        }
                    }
                }
            }
            nodes.push((p, q));
        }
        let mut split = Self::new(vertices, cells)?;
        split.copy_refinement_orders(self);
        // Tags: the old boundary facets keep theirs, the fault's faces get the sides' tags.
        let mut names = self.tag_names().to_vec();
        let mut index_of = |tag: String| match names.iter().position(|t| *t == tag) {
            Some(t) => t as u32,
            None => {
                names.push(tag);
                (names.len() - 1) as u32
            }
        };
        let (minus_tag, plus_tag) = (
            index_of(format!("{name}_minus")),
            index_of(format!("{name}_plus")),
        );
        let mut old_tag: HashMap<(usize, usize), Option<u32>> = HashMap::new();
        for f in 0..self.num_boundary_facets() {
            let v = self.boundary_facet(f);
            old_tag.insert(key(v[0], v[1]), self.raw_facet_tag(f));
        }
        let mut tags = Vec::with_capacity(split.num_boundary_facets());
        let mut minus_facets = vec![usize::MAX; m];
        let mut plus_facets = vec![usize::MAX; m];
        let edge_position: HashMap<(usize, usize), usize> =
            (0..m).map(|k| (key(chain[k], chain[k + 1]), k)).collect();
        for f in 0..split.num_boundary_facets() {
            let v = split.boundary_facet(f);
            let k0 = key(original[v[0]], original[v[1]]);
            if let Some(&t) = old_tag.get(&k0) {
                tags.push(t);
                continue;
            }
            let k = edge_position[&k0];
            // The plus side's cell lies left of the fault's direction.
            let c = split.boundary_facet_cell(f);
            if c == left_cell(chain[k], chain[k + 1]) {
                plus_facets[k] = f;
                tags.push(Some(plus_tag));
            } else {
                minus_facets[k] = f;
                tags.push(Some(minus_tag));
            }
        }
        split.set_facet_tags(names, tags);
        let normals = (0..m)
            .map(|k| {
                let (x, y) = (self.vertices()[chain[k]], self.vertices()[chain[k + 1]]);
                let t = [y[0] - x[0], y[1] - x[1]];
                let l = t[0].hypot(t[1]);
                [-t[1] / l, t[0] / l]
            })
            .collect();
        Ok((
            split,
            FaultSides {
                name: name.to_owned(),
                nodes,
                minus_facets,
                plus_facets,
                normals,
            },
        ))
    }

    /// [`SimplexMesh::split_along`] for a straight fault from `a` to `b` (m): the mesh edges
    /// lying on the segment (within `1e-9·|b − a|`) are the fault, directed from `a` to `b`.
    /// For a cut through a structured or graded mesh ([`crate::rectangle_from_coordinates`])
    /// whose grid lines contain the segment.
    ///
    /// # Errors
    /// [`Error::FaultSegmentNotResolved`] if a non-finite or zero-length segment is given or
    /// its ends are not mesh vertices joined by mesh edges along it (the mesh does not
    /// resolve the fault); otherwise as [`SimplexMesh::split_along`].
    pub fn split_along_segment(
        &self,
        name: &str,
        a: [f64; 2],
        b: [f64; 2],
    ) -> Result<(Self, FaultSides)> {
        self.split_along_polyline(name, &[a, b])
    }

    /// [`SimplexMesh::split_along`] for a fault made of straight pieces `points[0] →
    /// points[1] → …` (m; e.g. a kinked fault, or a Gmsh physical curve's vertices in order):
    /// the mesh edges on each piece, directed from `points[0]`. A piece's ends must be mesh
    /// vertices joined by mesh edges along it.
    ///
    /// # Errors
    /// [`Error::EmptyFault`] for fewer than two points; [`Error::FaultSegmentNotResolved`]
    /// for a piece the mesh does not resolve (or a non-finite or zero-length one);
    /// otherwise as [`SimplexMesh::split_along`] (e.g. [`Error::FaultEdgeRepeated`] or
    /// [`Error::FaultNotManifold`] for a polyline that runs back over or crosses itself).
    pub fn split_along_polyline(
        &self,
        name: &str,
        points: &[[f64; 2]],
    ) -> Result<(Self, FaultSides)> {
        if points.len() < 2 {
            return Err(Error::EmptyFault);
        }
        let mut edges = Vec::new();
        for piece in points.windows(2) {
            edges.extend(self.edges_along_segment(piece[0], piece[1])?);
        }
        self.split_along(name, &edges)
    }

    /// The mesh edges tiling the segment `a → b` in order, each directed from `a` to `b`.
    fn edges_along_segment(&self, a: [f64; 2], b: [f64; 2]) -> Result<Vec<[usize; 2]>> {
        let d = [b[0] - a[0], b[1] - a[1]];
        let len = d[0].hypot(d[1]);
        if !(len > 0.0 && len.is_finite() && a.iter().all(|x| x.is_finite())) {
            return Err(Error::FaultSegmentNotResolved { point: a });
        }
        let tol = 1e-9 * len;
        // Parameter along the segment of a point on it, None if off the segment.
        let on = |x: &[f64; 2]| -> Option<f64> {
            let r = [x[0] - a[0], x[1] - a[1]];
            let s = (r[0] * d[0] + r[1] * d[1]) / len;
            let off = (r[0] * d[1] - r[1] * d[0]).abs() / len;
            (off <= tol && s >= -tol && s <= len + tol).then_some(s)
        };
        let mut found: Vec<(f64, [usize; 2])> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for c in 0..self.num_cells() {
            let cell = self.cell(c);
            for k in 0..3 {
                let (p, q) = (cell[k], cell[(k + 1) % 3]);
                if !seen.insert((p.min(q), p.max(q))) {
                    continue;
                }
                if let (Some(sp), Some(sq)) = (on(&self.vertices()[p]), on(&self.vertices()[q])) {
                    let e = if sp < sq { [p, q] } else { [q, p] };
                    found.push((sp.min(sq), e));
                }
            }
        }
        found.sort_by(|x, y| x.0.total_cmp(&y.0));
        // The edges must tile the segment from a to b.
        let mut reach = 0.0;
        for &(s, [_, q]) in &found {
            if (s - reach).abs() > tol {
                return Err(Error::FaultSegmentNotResolved {
                    point: [a[0] + d[0] * reach / len, a[1] + d[1] * reach / len],
                });
            }
            reach = on(&self.vertices()[q]).expect("on the segment");
        }
        if (reach - len).abs() > tol {
            return Err(Error::FaultSegmentNotResolved {
                point: [a[0] + d[0] * reach / len, a[1] + d[1] * reach / len],
            });
        }
        Ok(found.into_iter().map(|(_, e)| e).collect())
    }
}
