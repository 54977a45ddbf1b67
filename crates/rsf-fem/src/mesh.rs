//! Simplicial meshes ([`SimplexMesh`]): vertices, oriented cells, boundary facets and tags.

use crate::geometry::{
    facet_measure, min_dihedral_angle, norm, oriented_facet_normal, p1_gradients, signed_measure,
};
use crate::{Error, Result};

/// A conforming simplicial mesh in `R^D` (segments for `D = 1`, triangles for `D = 2`,
/// tetrahedra for `D = 3`).
///
/// * vertices: coordinates in metres, `num_vertices()` points of `[f64; D]`;
/// * cells: connectivity with stride `D + 1`, every cell positively oriented
///   (counter-clockwise in 2D, `det[x1 − x0, x2 − x0, x3 − x0] > 0` in 3D), checked on
///   construction;
/// * boundary facets: the facets (stride `D`) that belong to exactly one cell, oriented so
///   that their normal ([`SimplexMesh::boundary_facet_normal`]) points out of the body: in
///   2D the body lies to the **left** of the directed edge (counter-clockwise traversal of
///   the outer boundary), in 3D the triangle is counter-clockwise seen from outside; each
///   facet has an optional tag (e.g. `"frictional"`).
///
/// Every cell also remembers a *refinement order* of its vertices (the order given to
/// [`SimplexMesh::from_ordered_cells`]; the stored order for [`SimplexMesh::new`]) which
/// red refinement of tetrahedra uses to pick the inner diagonal (Bey's ordering,
/// docs/math.md §10).
///
/// Everything (construction, refinement, boundary parts, assembly, loads) is dimension
/// generic; [`crate::rectangle`] and [`crate::cuboid`] build structured meshes.
#[derive(Debug, Clone)]
pub struct SimplexMesh<const D: usize> {
    vertices: Vec<[f64; D]>,
    cells: Vec<usize>,
    /// Per cell: the refinement order is the stored order with the last two vertices
    /// swapped. Empty when no cell is flipped.
    flipped: Vec<bool>,
    facets: Vec<usize>,
    facet_cell: Vec<usize>,
    facet_tag: Vec<Option<u32>>,
    tags: Vec<String>,
}

/// Triangle mesh in the plane.
pub type TriangleMesh = SimplexMesh<2>;
/// Tetrahedral mesh in space.
pub type TetrahedronMesh = SimplexMesh<3>;

impl<const D: usize> SimplexMesh<D> {
    /// Builds a mesh from vertices and flat connectivity (stride `D + 1`) whose cells are
    /// all positively oriented; the given vertex order of each cell is its refinement order.
    ///
    /// Boundary facets are found from the connectivity; they carry no tags yet
    /// (see [`SimplexMesh::tag_boundary`]).
    ///
    /// # Errors
    /// [`Error::NonFiniteCoordinate`], [`Error::BadConnectivity`], [`Error::EmptyMesh`],
    /// [`Error::VertexOutOfRange`], [`Error::DegenerateCell`] (measure below
    /// `1e-12 · h^D`, `h` the longest edge of the cell) or [`Error::InvertedCell`]
    /// (negatively oriented, e.g. clockwise, cells).
    pub fn new(vertices: Vec<[f64; D]>, cells: Vec<usize>) -> Result<Self> {
        Self::build(vertices, cells, false)
    }

    /// As [`SimplexMesh::new`], but cells may have either orientation: a negatively
    /// oriented cell is stored with its last two vertices swapped (so that it is positive)
    /// and the **given** order is kept as its refinement order. Use this for meshes from
    /// other programs (e.g. Gmsh) and for cells listed in an order that matters for
    /// refinement (the Kuhn paths of [`crate::cuboid`]).
    ///
    /// # Errors
    /// As [`SimplexMesh::new`] except [`Error::InvertedCell`].
    pub fn from_ordered_cells(vertices: Vec<[f64; D]>, cells: Vec<usize>) -> Result<Self> {
        Self::build(vertices, cells, true)
    }

    fn build(vertices: Vec<[f64; D]>, mut cells: Vec<usize>, reorient: bool) -> Result<Self> {
        assert!((1..=3).contains(&D), "SimplexMesh supports D = 1, 2, 3");
        for (i, v) in vertices.iter().enumerate() {
            if v.iter().any(|c| !c.is_finite()) {
                return Err(Error::NonFiniteCoordinate { vertex: i });
            }
        }
        if cells.len() % (D + 1) != 0 {
            return Err(Error::BadConnectivity {
                len: cells.len(),
                stride: D + 1,
            });
        }
        if cells.is_empty() {
            return Err(Error::EmptyMesh);
        }
        let nv = vertices.len();
        let mut flipped: Option<Vec<bool>> = None;
        for (c, cell) in cells.chunks_exact_mut(D + 1).enumerate() {
            let mut x = [[0.0; D]; 4];
            for (k, &v) in cell.iter().enumerate() {
                if v >= nv {
                    return Err(Error::VertexOutOfRange {
                        cell: c,
                        vertex: v,
                        num_vertices: nv,
                    });
                }
                x[k] = vertices[v];
            }
            let m = signed_measure::<D>(&x[..D + 1]);
            let mut h2: f64 = 0.0;
            for a in 0..=D {
                for b in a + 1..=D {
                    let d2: f64 = (0..D).map(|r| (x[a][r] - x[b][r]).powi(2)).sum();
                    h2 = h2.max(d2);
                }
            }
            let tol = 1e-12 * h2.sqrt().powi(D as i32);
            if m.abs() <= tol || !m.is_finite() {
                return Err(Error::DegenerateCell {
                    cell: c,
                    measure: m,
                });
            }
            if m < 0.0 {
                if !reorient {
                    return Err(Error::InvertedCell {
                        cell: c,
                        measure: m,
                    });
                }
                cell.swap(D - 1, D);
                flipped.get_or_insert_with(|| vec![false; c]);
            }
            if let Some(f) = flipped.as_mut() {
                f.push(m < 0.0);
            }
        }
        let mut mesh = Self {
            vertices,
            cells,
            flipped: flipped.unwrap_or_default(),
            facets: Vec::new(),
            facet_cell: Vec::new(),
            facet_tag: Vec::new(),
            tags: Vec::new(),
        };
        mesh.find_boundary_facets();
        Ok(mesh)
    }

    /// The same mesh with its vertices at `vertices` (one per vertex, in the same order):
    /// cells, refinement orders, boundary facets and tags are kept. For curved boundaries:
    /// moving the vertices a refinement put on a boundary facet's chord onto the exact
    /// boundary ([`crate::MeshHierarchy::try_refine_uniformly_onto`]).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for another number of vertices;
    /// [`Error::NonFiniteCoordinate`]; [`Error::DegenerateCell`] / [`Error::InvertedCell`]
    /// if a cell degenerates or turns over (as [`SimplexMesh::new`]).
    pub fn with_moved_vertices(&self, vertices: Vec<[f64; D]>) -> Result<Self> {
        if vertices.len() != self.vertices.len() {
            return Err(Error::DimensionMismatch {
                what: "moved vertices",
                expected: self.vertices.len(),
                got: vertices.len(),
            });
        }
        // The stored cells are positively oriented: re-check them without reorienting.
        let moved = Self::build(vertices, self.cells.clone(), false)?;
        Ok(Self {
            vertices: moved.vertices,
            ..self.clone()
        })
    }

    /// Builds a refined mesh from cells given in refinement order; `negative[c]` is the
    /// orientation of that order as predicted by the refinement rule. Panics (internal
    /// invariant) if a prediction is wrong.
    pub(crate) fn from_refinement(
        vertices: Vec<[f64; D]>,
        ordered_cells: Vec<usize>,
        negative: &[bool],
    ) -> Result<Self> {
        let mesh = Self::build(vertices, ordered_cells, true)?;
        assert!(
            (0..mesh.num_cells()).all(|c| mesh.is_flipped(c) == negative[c]),
            "refinement produced a cell of unexpected orientation"
        );
        Ok(mesh)
    }

    /// Whether cell `i`'s refinement order is its stored order with the last two swapped.
    pub(crate) fn is_flipped(&self, i: usize) -> bool {
        self.flipped.get(i).copied().unwrap_or(false)
    }

    /// Vertices of cell `i` in its refinement order (first `D + 1` entries used).
    pub(crate) fn refinement_order(&self, i: usize) -> [usize; 4] {
        let mut v = [0usize; 4];
        v[..D + 1].copy_from_slice(self.cell(i));
        if self.is_flipped(i) {
            v.swap(D - 1, D);
        }
        v
    }

    /// Finds the facets that belong to exactly one cell.
    fn find_boundary_facets(&mut self) {
        let nc = self.num_cells();
        // (sorted key, cell * (D+1) + local facet index)
        let mut keys: Vec<([usize; 3], usize)> = Vec::with_capacity(nc * (D + 1));
        for c in 0..nc {
            let cell = self.cell(c);
            for k in 0..=D {
                let mut key = [usize::MAX; 3];
                for (m, slot) in key.iter_mut().take(D).enumerate() {
                    *slot = cell[(k + 1 + m) % (D + 1)];
                }
                key[..D].sort_unstable();
                keys.push((key, c * (D + 1) + k));
            }
        }
        keys.sort_unstable();
        self.facets.clear();
        self.facet_cell.clear();
        let mut i = 0;
        while i < keys.len() {
            let mut j = i + 1;
            while j < keys.len() && keys[j].0 == keys[i].0 {
                j += 1;
            }
            if j - i == 1 {
                let (c, k) = (keys[i].1 / (D + 1), keys[i].1 % (D + 1));
                let cell = self.cell(c);
                let mut f = [0usize; 3];
                for (m, slot) in f.iter_mut().take(D).enumerate() {
                    *slot = cell[(k + 1 + m) % (D + 1)];
                }
                // In 3D, the cyclic choice must alternate to keep outward orientation.
                if D == 3 && k % 2 == 1 {
                    f.swap(0, 1);
                }
                self.facets.extend_from_slice(&f[..D]);
                self.facet_cell.push(c);
            }
            i = j;
        }
        self.facet_tag = vec![None; self.facet_cell.len()];
    }

    /// Vertex coordinates (m).
    pub fn vertices(&self) -> &[[f64; D]] {
        &self.vertices
    }
    /// Flat connectivity, stride `D + 1`.
    pub fn cells(&self) -> &[usize] {
        &self.cells
    }
    /// Vertices of cell `i` (`D + 1` entries). Panics if `i ≥ num_cells()`.
    pub fn cell(&self, i: usize) -> &[usize] {
        &self.cells[(D + 1) * i..(D + 1) * (i + 1)]
    }
    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.vertices.len()
    }
    /// Number of cells.
    pub fn num_cells(&self) -> usize {
        self.cells.len() / (D + 1)
    }

    /// The vertex graph in CSR form, as graph partitioners take it: the neighbours of
    /// vertex `p` (the other vertices of the cells containing it) are
    /// `adjncy[xadj[p]..xadj[p + 1]]`, increasing; `xadj` has `num_vertices() + 1`
    /// entries. Symmetric, without self-loops: the node graph of every matrix a P1
    /// [`Assembler`](crate::Assembler) assembles on this mesh (its pattern couples the
    /// vertices of each cell), so a partition of it is one of the matrices' nodes.
    pub fn vertex_graph(&self) -> (Vec<usize>, Vec<usize>) {
        let n = self.num_vertices();
        let k = D + 1;
        let mut lists: Vec<Vec<usize>> = vec![Vec::new(); n];
        for cell in self.cells.chunks_exact(k) {
            for &p in cell {
                lists[p].extend(cell.iter().copied().filter(|&q| q != p));
            }
        }
        let mut xadj = Vec::with_capacity(n + 1);
        xadj.push(0);
        let mut adjncy = Vec::new();
        for list in &mut lists {
            list.sort_unstable();
            list.dedup();
            adjncy.extend_from_slice(list);
            xadj.push(adjncy.len());
        }
        (xadj, adjncy)
    }
    /// Every facet of the mesh (interior and boundary) once, in the order of the cells and,
    /// within a cell, of the vertex each facet leaves out; a facet's `D` vertices in the
    /// order of the first cell holding it (that cell without the left-out vertex).
    pub fn facets(&self) -> Vec<[usize; D]> {
        let mut seen = std::collections::HashSet::new();
        let mut facets = Vec::with_capacity(self.num_cells() * (D + 1) / 2 + 1);
        for c in 0..self.num_cells() {
            let cell = self.cell(c);
            for skip in 0..=D {
                let mut f = [0; D];
                for (slot, &v) in f.iter_mut().zip(
                    cell.iter()
                        .enumerate()
                        .filter(|&(k, _)| k != skip)
                        .map(|(_, v)| v),
                ) {
                    *slot = v;
                }
                let mut key = f;
                key.sort_unstable();
                if seen.insert(key) {
                    facets.push(f);
                }
            }
        }
        facets
    }
    /// Number of boundary facets.
    pub fn num_boundary_facets(&self) -> usize {
        self.facet_cell.len()
    }
    /// Vertices of boundary facet `i` (`D` entries, oriented; in 2D the body is on the left).
    pub fn boundary_facet(&self, i: usize) -> &[usize] {
        &self.facets[D * i..D * (i + 1)]
    }
    /// The cell a boundary facet belongs to.
    pub fn boundary_facet_cell(&self, i: usize) -> usize {
        self.facet_cell[i]
    }
    /// Tag of boundary facet `i`, if any.
    pub fn boundary_facet_tag(&self, i: usize) -> Option<&str> {
        self.facet_tag[i].map(|t| self.tags[t as usize].as_str())
    }
    /// Names of all tags ever assigned.
    pub fn tag_names(&self) -> &[String] {
        &self.tags
    }
    /// Indices of the boundary facets carrying `tag`.
    pub fn facets_with_tag(&self, tag: &str) -> Vec<usize> {
        match self.tags.iter().position(|t| t == tag) {
            None => Vec::new(),
            Some(t) => (0..self.num_boundary_facets())
                .filter(|&f| self.facet_tag[f] == Some(t as u32))
                .collect(),
        }
    }
    /// Midpoint (barycentre) of boundary facet `i`.
    pub fn boundary_facet_midpoint(&self, i: usize) -> [f64; D] {
        let mut m = [0.0; D];
        for &v in self.boundary_facet(i) {
            for r in 0..D {
                m[r] += self.vertices[v][r] / D as f64;
            }
        }
        m
    }
    /// Measure (length in 2D) of boundary facet `i`.
    pub fn boundary_facet_measure(&self, i: usize) -> f64 {
        let mut x = [[0.0; D]; 3];
        for (k, &v) in self.boundary_facet(i).iter().enumerate() {
            x[k] = self.vertices[v];
        }
        facet_measure::<D>(&x[..D])
    }

    /// Tags every boundary facet whose midpoint satisfies `predicate` with `tag`
    /// (overwriting earlier tags). Returns the number of facets tagged.
    pub fn tag_boundary(&mut self, tag: &str, predicate: impl Fn(&[f64; D]) -> bool) -> usize {
        let t = self.tag_index(tag);
        let mut count = 0;
        for f in 0..self.num_boundary_facets() {
            if predicate(&self.boundary_facet_midpoint(f)) {
                self.facet_tag[f] = Some(t);
                count += 1;
            }
        }
        count
    }

    fn tag_index(&mut self, tag: &str) -> u32 {
        match self.tags.iter().position(|t| t == tag) {
            Some(t) => t as u32,
            None => {
                self.tags.push(tag.to_owned());
                (self.tags.len() - 1) as u32
            }
        }
    }

    /// Replaces the boundary facet tags (used by refinement). `tags` are indices into
    /// `names`, one per boundary facet in the order of the facets.
    pub(crate) fn set_facet_tags(&mut self, names: Vec<String>, tags: Vec<Option<u32>>) {
        debug_assert_eq!(tags.len(), self.num_boundary_facets());
        self.tags = names;
        self.facet_tag = tags;
    }
    /// Copies the refinement orders of `other` (same cells in the same stored order).
    pub(crate) fn copy_refinement_orders(&mut self, other: &Self) {
        debug_assert_eq!(self.num_cells(), other.num_cells());
        self.flipped = other.flipped.clone();
    }
    pub(crate) fn raw_facet_tag(&self, i: usize) -> Option<u32> {
        self.facet_tag[i]
    }

    /// Signed measure (area in 2D) of cell `i`.
    pub fn cell_measure(&self, i: usize) -> f64 {
        let mut x = [[0.0; D]; 4];
        for (k, &v) in self.cell(i).iter().enumerate() {
            x[k] = self.vertices[v];
        }
        signed_measure::<D>(&x[..D + 1])
    }
    /// Total measure (area in 2D, m²) of the mesh.
    pub fn measure(&self) -> f64 {
        (0..self.num_cells()).map(|c| self.cell_measure(c)).sum()
    }
    /// Coordinates of the vertices of cell `i` copied into an array (first `D + 1` used).
    #[inline]
    pub(crate) fn cell_coords(&self, i: usize) -> [[f64; D]; 4] {
        let mut x = [[0.0; D]; 4];
        for (k, &v) in self.cell(i).iter().enumerate() {
            x[k] = self.vertices[v];
        }
        x
    }

    /// Outward unit normal of boundary facet `i` (for `D = 1`: `±1`).
    pub fn boundary_facet_normal(&self, i: usize) -> [f64; D] {
        let f = self.boundary_facet(i);
        let mut n = [0.0; D];
        if D == 1 {
            let cell = self.cell(self.facet_cell[i]);
            let other = if cell[0] == f[0] { cell[1] } else { cell[0] };
            n[0] = (self.vertices[f[0]][0] - self.vertices[other][0]).signum();
            return n;
        }
        let mut x = [[0.0; D]; 3];
        for (k, &v) in f.iter().enumerate() {
            x[k] = self.vertices[v];
        }
        n = oriented_facet_normal::<D>(&x[..D]);
        let l = norm(&n);
        n.iter_mut().for_each(|c| *c /= l);
        n
    }

    /// Smallest dihedral angle (radians) over all cells: the angle between two facets of
    /// a cell, measured inside it (in 2D the interior angles of the triangles). A measure
    /// of shape regularity: red refinement keeps it bounded below (docs/math.md §10).
    pub fn min_dihedral_angle(&self) -> f64 {
        (0..self.num_cells())
            .map(|c| {
                let x = self.cell_coords(c);
                let (g, _) = p1_gradients::<D>(&x[..D + 1]).expect("mesh cells are non-degenerate");
                min_dihedral_angle::<D>(&g)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Tags the listed boundary facets (indices as in [`SimplexMesh::boundary_facet`]) with
    /// `tag`, overwriting earlier tags. Returns the number of facets tagged.
    ///
    /// # Errors
    /// [`Error::InvalidFacet`] if an index is not a boundary facet (nothing is tagged then).
    pub fn tag_boundary_facets(&mut self, tag: &str, facets: &[usize]) -> Result<usize> {
        if let Some(&f) = facets.iter().find(|&&f| f >= self.num_boundary_facets()) {
            return Err(Error::InvalidFacet {
                facet: f,
                num_facets: self.num_boundary_facets(),
            });
        }
        let t = self.tag_index(tag);
        for &f in facets {
            self.facet_tag[f] = Some(t);
        }
        Ok(facets.len())
    }
}

impl SimplexMesh<2> {
    /// Smallest interior angle (radians) over all triangles
    /// (= [`SimplexMesh::min_dihedral_angle`] in 2D).
    pub fn min_angle(&self) -> f64 {
        self.min_dihedral_angle()
    }
}
