//! Faults inside the body: split nodes (docs/math.md §13, docs/faults-inside.md).
//!
//! A fault given as a chain of interior mesh edges (2-D) is cut open: every fault node
//! becomes a minus and a plus copy, the cells on the plus side are renumbered to the plus
//! copies, and the two faces of the cut become boundary facets tagged `{name}_minus` and
//! `{name}_plus`. A chain end inside the body (a tip) stays shared; a chain end on the outer
//! boundary (e.g. a free surface) is split. Coordinates and the order of every cell's
//! vertices are unchanged, so assembly per cell is unchanged. The 3-D cut along a surface
//! of mesh triangles is in `split_surface.rs`; the grouping of the cells around a vertex
//! and the tags of the split mesh are shared (`cell_groups_around`, `tag_split_facets`).

use std::collections::HashMap;

use crate::{Error, Result, SimplexMesh};

/// The two sides of a fault cut by [`SimplexMesh::split_along`].
///
/// 2-D: the fault is a chain of nodes `x_0, …, x_m` (m ≥ 1 edges); its direction is the
/// direction of the first listed edge. The unit normal `n_k` of edge `k` (from `x_k` to
/// `x_{k+1}`, tangent `t_k`) is `t_k` turned by +90°, `n = (−t_y, t_x)`: it points from the
/// minus side into the plus side, so it is the outward normal of the minus side's facet
/// and `−n_k` that of the plus side's. Slip is the jump `u⁺ − u⁻` (docs/math.md §13).
///
/// 3-D (`FaultSides<3>`, from `SimplexMesh::<3>::split_along`): the fault is a surface of
/// mesh triangles ("faces", in the order given); the first face's right-hand-rule normal
/// sets the fault's orientation, the others are oriented consistently with it, and
/// `n_k` is the unit normal of face `k` so oriented, again from the minus into the plus
/// side. The nodes are the fault's vertices in increasing vertex index (not in an order
/// along the fault); the normals and the minus and plus facets are per face, in input
/// order.
///
/// A fault face or edge all of whose vertices are tips (a face at a corner of a buried
/// fault's rim in 3-D; a single buried edge in 2-D) cannot open: it stays an interior face
/// of the split mesh (the P1 jump vanishes on it anyway), untagged, and its entries of
/// [`FaultSides::minus_facets`] and [`FaultSides::plus_facets`] are `usize::MAX`.
#[derive(Debug, Clone, PartialEq)]
pub struct FaultSides<const D: usize = 2> {
    pub(crate) name: String,
    pub(crate) nodes: Vec<(usize, usize)>,
    pub(crate) minus_facets: Vec<usize>,
    pub(crate) plus_facets: Vec<usize>,
    pub(crate) normals: Vec<[f64; D]>,
    /// Positions in `nodes` of the vertices where this fault meets another of a
    /// [`FaultNetwork`](crate::FaultNetwork) (junctions; empty for a fault cut alone).
    pub(crate) junction_nodes: Vec<usize>,
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
    /// Every fault node as `(minus, plus)` vertex indices of the split mesh, in order along
    /// the fault in 2-D and in increasing vertex index `minus` in 3-D; a tip (shared node)
    /// appears as `(p, p)`.
    pub fn nodes(&self) -> &[(usize, usize)] {
        &self.nodes
    }
    /// The split pairs `(minus, plus)` in the order of [`FaultSides::nodes`] (tips and
    /// junctions left out).
    pub fn pairs(&self) -> Vec<(usize, usize)> {
        self.nodes
            .iter()
            .enumerate()
            .filter(|&(i, (m, p))| m != p && !self.is_junction_node(i))
            .map(|(_, &n)| n)
            .collect()
    }
    /// Whether node `i` (a position in [`FaultSides::nodes`]) is a junction of a
    /// [`FaultNetwork`](crate::FaultNetwork): a vertex this fault shares with another, cut
    /// into one copy per sector ([`crate::Junction`]); its entry in `nodes` is the pair of
    /// copies on the two sides of this fault's first edge at it.
    pub fn is_junction_node(&self, i: usize) -> bool {
        self.junction_nodes.binary_search(&i).is_ok()
    }
    /// The positions in [`FaultSides::nodes`] of this fault's junctions with other faults
    /// of its [`FaultNetwork`](crate::FaultNetwork), increasing (none for a fault cut alone).
    pub fn junction_nodes(&self) -> &[usize] {
        &self.junction_nodes
    }
    /// The tips: fault nodes shared by both sides (2-D: a chain end inside the body; 3-D:
    /// the rim of the fault surface inside the body, including where the rim meets the
    /// outer boundary).
    pub fn tips(&self) -> Vec<usize> {
        self.nodes
            .iter()
            .filter(|(m, p)| m == p)
            .map(|&(m, _)| m)
            .collect()
    }
    /// Boundary facet indices (of the split mesh) of the minus side, one per fault edge in
    /// order along the fault (3-D: one per fault face, in input order; `usize::MAX` for a
    /// face that stays closed, see [`FaultSides`]).
    pub fn minus_facets(&self) -> &[usize] {
        &self.minus_facets
    }
    /// Boundary facet indices (of the split mesh) of the plus side, one per fault edge (3-D:
    /// per fault face), as [`FaultSides::minus_facets`].
    pub fn plus_facets(&self) -> &[usize] {
        &self.plus_facets
    }
    /// Unit normal of every fault edge (3-D: face, in input order), pointing from the minus
    /// into the plus side (the minus side's outward normal; the plus side's is its
    /// negative).
    pub fn normals(&self) -> &[[f64; D]] {
        &self.normals
    }
    /// The jump `u⁺ − u⁻` of a node-major field with `c` components per vertex at every
    /// fault node (zero at tips), in the order of [`FaultSides::nodes`].
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
        let (edge_cells, vertex_cells) = edge_and_vertex_cells(self);
        // Validate the edges and collect the fault's adjacency.
        let mut fault_edge: HashMap<(usize, usize), usize> = HashMap::new();
        let mut at_vertex: HashMap<usize, Vec<usize>> = HashMap::new();
        for (i, &[a, b]) in edges.iter().enumerate() {
            check_fault_edge(&edge_cells, nv, i, [a, b])?;
            if fault_edge.insert(key(a, b), i).is_some() {
                return Err(Error::FaultEdgeRepeated {
                    edge: i,
                    vertices: [a, b],
                });
            }
            add_at_vertices(&mut at_vertex, i, [a, b])?;
        }
        let chain = ordered_chain(edges, &at_vertex)?;
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
            let (group, groups) =
                cell_groups_around(self, p, around, |f| fault_edge.contains_key(&(f[0], f[1])));
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
            let q = add_plus_copy(p, around, &group, plus_group, &mut vertices, &mut cells);
            original.push(p);
            nodes.push((p, q));
        }
        let mut split = Self::new(vertices, cells)?;
        split.copy_refinement_orders(self);
        // Tags: the old boundary facets keep theirs, the fault's faces get the sides' tags.
        let edge_position: HashMap<[usize; 3], usize> = (0..m)
            .map(|k| (facet_key(&[chain[k], chain[k + 1]]), k))
            .collect();
        // The plus side's cell lies left of the fault's direction.
        let plus_cells: Vec<usize> = (0..m).map(|k| left_cell(chain[k], chain[k + 1])).collect();
        let (minus_facets, plus_facets) = tag_split_facets(
            self,
            &mut split,
            name,
            &original,
            &edge_position,
            &plus_cells,
        );
        let normals = (0..m)
            .map(|k| {
                let (x, y) = (self.vertices()[chain[k]], self.vertices()[chain[k + 1]]);
                let t = [y[0] - x[0], y[1] - x[1]];
                let l = t[0].hypot(t[1]);
                [-t[1] / l, t[0] / l]
            })
            .collect();
        let sides = FaultSides::alone(name, nodes, minus_facets, plus_facets, normals);
        Ok((split, sides))
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
        let edges = self.edges_along_polyline(points)?;
        self.split_along(name, &edges)
    }

    /// The mesh edges tiling the polyline `points` (m) in order, each directed along it
    /// (the edges [`split_along_polyline`](Self::split_along_polyline) cuts).
    ///
    /// # Errors
    /// [`Error::EmptyFault`] for fewer than two points; [`Error::FaultSegmentNotResolved`]
    /// for a piece the mesh does not resolve.
    pub fn edges_along_polyline(&self, points: &[[f64; 2]]) -> Result<Vec<[usize; 2]>> {
        if points.len() < 2 {
            return Err(Error::EmptyFault);
        }
        let mut edges = Vec::new();
        for piece in points.windows(2) {
            edges.extend(self.edges_along_segment(piece[0], piece[1])?);
        }
        Ok(edges)
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

/// Checks fault edge `i`, `[a, b]`, of a triangle mesh of `nv` vertices whose edges are
/// `edge_cells`: an edge of the mesh, between two cells.
///
/// # Errors
/// [`Error::FaultEdgeNotInMesh`], [`Error::FaultEdgeOnBoundary`].
pub(crate) fn check_fault_edge(
    edge_cells: &EdgeCells,
    nv: usize,
    i: usize,
    [a, b]: [usize; 2],
) -> Result<()> {
    let cells = if a < nv && b < nv && a != b {
        edge_cells.get(&(a.min(b), a.max(b)))
    } else {
        None
    };
    let vertices = [a, b];
    match cells.map(Vec::len) {
        None => Err(Error::FaultEdgeNotInMesh { edge: i, vertices }),
        Some(1) => Err(Error::FaultEdgeOnBoundary { edge: i, vertices }),
        _ => Ok(()),
    }
}

/// Lists fault edge `i`, `[a, b]`, at both its vertices in `at_vertex`.
///
/// # Errors
/// [`Error::FaultNotManifold`] for a vertex that gets a third edge.
pub(crate) fn add_at_vertices(
    at_vertex: &mut HashMap<usize, Vec<usize>>,
    i: usize,
    [a, b]: [usize; 2],
) -> Result<()> {
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
    Ok(())
}

/// The vertices of the chain of fault edges `edges` in order, from the end before the
/// first edge's start to the end after its end (the first edge's direction); `at_vertex`
/// lists the (at most two) edges at every fault vertex.
///
/// # Errors
/// [`Error::FaultClosed`] for a closed chain; [`Error::FaultDisconnected`] if the edges
/// form more than one chain.
pub(crate) fn ordered_chain(
    edges: &[[usize; 2]],
    at_vertex: &HashMap<usize, Vec<usize>>,
) -> Result<Vec<usize>> {
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
    Ok(chain)
}

/// Appends the plus copy `q` of fault vertex `p` (the same point) and renumbers `p` to
/// `q` in the cells around it (`around`, each of `D + 1` vertices in the flat `cells`)
/// whose `group` is `plus_group`; returns `q`.
pub(crate) fn add_plus_copy<const D: usize>(
    p: usize,
    around: &[usize],
    group: &[usize],
    plus_group: usize,
    vertices: &mut Vec<[f64; D]>,
    cells: &mut [usize],
) -> usize {
    let q = vertices.len();
    vertices.push(vertices[p]);
    for (&c, _) in around.iter().zip(group).filter(|(_, &g)| g == plus_group) {
        for v in &mut cells[(D + 1) * c..(D + 1) * c + D + 1] {
            if *v == p {
                *v = q;
            }
        }
    }
    q
}

impl<const D: usize> FaultSides<D> {
    /// The sides of a fault cut alone (no junctions).
    pub(crate) fn alone(
        name: &str,
        nodes: Vec<(usize, usize)>,
        minus_facets: Vec<usize>,
        plus_facets: Vec<usize>,
        normals: Vec<[f64; D]>,
    ) -> Self {
        Self {
            name: name.to_owned(),
            nodes,
            minus_facets,
            plus_facets,
            normals,
            junction_nodes: Vec::new(),
        }
    }

    /// Checks that a mesh of `num_vertices` vertices can be the split mesh of these sides.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if a fault node's index is out of range.
    pub(crate) fn check_split_mesh(&self, num_vertices: usize) -> Result<()> {
        let need = self
            .nodes
            .iter()
            .map(|&(m, p)| m.max(p) + 1)
            .max()
            .unwrap_or(0);
        if need > num_vertices {
            return Err(Error::DimensionMismatch {
                what: "split mesh of the fault sides",
                expected: need,
                got: num_vertices,
            });
        }
        Ok(())
    }
}

/// The sorted vertices of a facet (`D ≤ 3` entries), padded with `usize::MAX`: a key equal
/// for every vertex order.
pub(crate) fn facet_key(vertices: &[usize]) -> [usize; 3] {
    let mut k = [usize::MAX; 3];
    k[..vertices.len()].copy_from_slice(vertices);
    k.sort_unstable();
    k
}

/// Groups the cells `around` vertex `p` (all cells containing it) by adjacency through
/// facets containing `p` that are not fault facets (`is_fault` of the facet's
/// [`facet_key`]). Returns each cell's group (numbered by first appearance in `around`)
/// and the number of groups.
pub(crate) fn cell_groups_around<const D: usize>(
    mesh: &SimplexMesh<D>,
    p: usize,
    around: &[usize],
    is_fault: impl Fn(&[usize; 3]) -> bool,
) -> (Vec<usize>, usize) {
    let mut root: Vec<usize> = (0..around.len()).collect();
    fn find(root: &mut [usize], mut x: usize) -> usize {
        while root[x] != x {
            root[x] = root[root[x]];
            x = root[x];
        }
        x
    }
    let mut first: HashMap<[usize; 3], usize> = HashMap::new();
    for (s, &c) in around.iter().enumerate() {
        let cell = mesh.cell(c);
        for &r in cell.iter().filter(|&&r| r != p) {
            let mut f = [0; 3];
            let mut n = 0;
            for &v in cell.iter().filter(|&&v| v != r) {
                f[n] = v;
                n += 1;
            }
            let key = facet_key(&f[..n]);
            if is_fault(&key) {
                continue;
            }
            match first.entry(key) {
                std::collections::hash_map::Entry::Occupied(e) => {
                    let (a, b) = (find(&mut root, s), find(&mut root, *e.get()));
                    root[a.max(b)] = a.min(b);
                }
                std::collections::hash_map::Entry::Vacant(e) => {
                    e.insert(s);
                }
            }
        }
    }
    let mut label = vec![usize::MAX; around.len()];
    let mut group = vec![0; around.len()];
    let mut groups = 0;
    for s in 0..around.len() {
        let r = find(&mut root, s);
        if label[r] == usize::MAX {
            label[r] = groups;
            groups += 1;
        }
        group[s] = label[r];
    }
    (group, groups)
}

/// Tags the boundary facets of `split`, the mesh `old` cut open along a fault: the old
/// boundary facets keep their tags, the fault's faces get `{name}_minus` or `{name}_plus`.
/// `original` maps every vertex of `split` to its vertex of `old`; `fault` maps the
/// [`facet_key`] (in `old`'s vertices) of every fault face to its index `k`, whose plus
/// side's cell is `plus_cells[k]`. Returns the minus and plus facets per fault face
/// (`usize::MAX` for a face that stayed closed).
pub(crate) fn tag_split_facets<const D: usize>(
    old: &SimplexMesh<D>,
    split: &mut SimplexMesh<D>,
    name: &str,
    original: &[usize],
    fault: &HashMap<[usize; 3], usize>,
    plus_cells: &[usize],
) -> (Vec<usize>, Vec<usize>) {
    let fault = fault.iter().map(|(&key, &k)| (key, (0, k))).collect();
    let mut sides = tag_network_facets(
        old,
        split,
        &[name],
        original,
        &fault,
        &[plus_cells.to_vec()],
    );
    sides.pop().expect("one fault")
}

/// [`tag_split_facets`] for the faults `names` of a network: `fault` maps every fault
/// face's [`facet_key`] to `(fault, k)`, whose plus side's cell is `plus_cells[fault][k]`;
/// the tags `{name}_minus`, `{name}_plus` are added fault by fault. Returns the minus and
/// plus facets of every fault's faces.
pub(crate) fn tag_network_facets<const D: usize>(
    old: &SimplexMesh<D>,
    split: &mut SimplexMesh<D>,
    names: &[&str],
    original: &[usize],
    fault: &HashMap<[usize; 3], (usize, usize)>,
    plus_cells: &[Vec<usize>],
) -> Vec<(Vec<usize>, Vec<usize>)> {
    let mut tag_names = old.tag_names().to_vec();
    let mut index_of = |tag: String| match tag_names.iter().position(|t| *t == tag) {
        Some(t) => t as u32,
        None => {
            tag_names.push(tag);
            (tag_names.len() - 1) as u32
        }
    };
    let side_tags: Vec<(u32, u32)> = names
        .iter()
        .map(|name| {
            (
                index_of(format!("{name}_minus")),
                index_of(format!("{name}_plus")),
            )
        })
        .collect();
    let mut old_tag: HashMap<[usize; 3], Option<u32>> = HashMap::new();
    for f in 0..old.num_boundary_facets() {
        old_tag.insert(facet_key(old.boundary_facet(f)), old.raw_facet_tag(f));
    }
    let mut tags = Vec::with_capacity(split.num_boundary_facets());
    let mut sides: Vec<(Vec<usize>, Vec<usize>)> = plus_cells
        .iter()
        .map(|cells| (vec![usize::MAX; cells.len()], vec![usize::MAX; cells.len()]))
        .collect();
    for f in 0..split.num_boundary_facets() {
        let mut v = [0; 3];
        for (slot, &x) in v.iter_mut().zip(split.boundary_facet(f)) {
            *slot = original[x];
        }
        let k0 = facet_key(&v[..D]);
        if let Some(&t) = old_tag.get(&k0) {
            tags.push(t);
            continue;
        }
        let (i, k) = *fault
            .get(&k0)
            .expect("a new boundary facet is a face of the fault");
        if split.boundary_facet_cell(f) == plus_cells[i][k] {
            sides[i].1[k] = f;
            tags.push(Some(side_tags[i].1));
        } else {
            sides[i].0[k] = f;
            tags.push(Some(side_tags[i].0));
        }
    }
    split.set_facet_tags(tag_names, tags);
    sides
}

/// The cells of every edge (its vertices in increasing order) of a triangle mesh.
pub(crate) type EdgeCells = HashMap<(usize, usize), Vec<usize>>;

/// Every edge of a triangle mesh with the cells that hold it, and every vertex with its
/// cells.
pub(crate) fn edge_and_vertex_cells(mesh: &SimplexMesh<2>) -> (EdgeCells, Vec<Vec<usize>>) {
    let mut edge_cells = EdgeCells::new();
    let mut vertex_cells: Vec<Vec<usize>> = vec![Vec::new(); mesh.num_vertices()];
    for c in 0..mesh.num_cells() {
        let cell = mesh.cell(c);
        for k in 0..3 {
            let (a, b) = (cell[k], cell[(k + 1) % 3]);
            edge_cells.entry((a.min(b), a.max(b))).or_default().push(c);
            vertex_cells[cell[k]].push(c);
        }
    }
    (edge_cells, vertex_cells)
}
