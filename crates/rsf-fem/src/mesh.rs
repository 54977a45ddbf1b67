//! Simplicial meshes ([`SimplexMesh`]), structured rectangles and boundary tags.

use crate::geometry::{facet_measure, signed_measure};
use crate::{Error, Result};

/// Tag name used by [`pipping_slider_coarse`] for the top edge (Dirichlet, Γ_D).
pub const TAG_DIRICHLET: &str = "dirichlet";
/// Tag name used by [`pipping_slider_coarse`] for the side edges (Neumann, Γ_N).
pub const TAG_NEUMANN: &str = "neumann";
/// Tag name used by [`pipping_slider_coarse`] for the bottom edge (frictional, Γ_F).
pub const TAG_FRICTIONAL: &str = "frictional";

/// A conforming simplicial mesh in `R^D` (triangles for `D = 2`, tetrahedra for `D = 3`).
///
/// * vertices: coordinates in metres, `num_vertices()` points of `[f64; D]`;
/// * cells: connectivity with stride `D + 1`, every cell positively oriented
///   (counter-clockwise in 2D), checked on construction;
/// * boundary facets: the facets (stride `D`) that belong to exactly one cell, oriented so
///   that in 2D the body lies to the **left** of the directed edge (counter-clockwise
///   traversal of the outer boundary), each with an optional tag (e.g. `"frictional"`).
///
/// Construction ([`SimplexMesh::new`]) and the geometry kernels are dimension generic;
/// refinement, segments and loads currently have 2D implementations only.
#[derive(Debug, Clone)]
pub struct SimplexMesh<const D: usize> {
    vertices: Vec<[f64; D]>,
    cells: Vec<usize>,
    facets: Vec<usize>,
    facet_cell: Vec<usize>,
    facet_tag: Vec<Option<u32>>,
    tags: Vec<String>,
}

/// Triangle mesh in the plane.
pub type TriangleMesh = SimplexMesh<2>;

impl<const D: usize> SimplexMesh<D> {
    /// Builds a mesh from vertices and flat connectivity (stride `D + 1`).
    ///
    /// Boundary facets are found from the connectivity; they carry no tags yet
    /// (see [`SimplexMesh::tag_boundary`]).
    ///
    /// # Errors
    /// [`Error::NonFiniteCoordinate`], [`Error::BadConnectivity`], [`Error::EmptyMesh`],
    /// [`Error::VertexOutOfRange`], [`Error::DegenerateCell`] (measure below
    /// `1e-12 · h^D`, `h` the longest edge of the cell) or [`Error::InvertedCell`]
    /// (clockwise cells).
    pub fn new(vertices: Vec<[f64; D]>, cells: Vec<usize>) -> Result<Self> {
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
        for (c, cell) in cells.chunks_exact(D + 1).enumerate() {
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
                return Err(Error::InvertedCell {
                    cell: c,
                    measure: m,
                });
            }
        }
        let mut mesh = Self {
            vertices,
            cells,
            facets: Vec::new(),
            facet_cell: Vec::new(),
            facet_tag: Vec::new(),
            tags: Vec::new(),
        };
        mesh.find_boundary_facets();
        Ok(mesh)
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
}

impl SimplexMesh<2> {
    /// Smallest interior angle (radians) over all triangles.
    pub fn min_angle(&self) -> f64 {
        let mut best = f64::INFINITY;
        for c in 0..self.num_cells() {
            let x = self.cell_coords(c);
            for k in 0..3 {
                let (p, q, r) = (x[k], x[(k + 1) % 3], x[(k + 2) % 3]);
                let a = [q[0] - p[0], q[1] - p[1]];
                let b = [r[0] - p[0], r[1] - p[1]];
                let cos = (a[0] * b[0] + a[1] * b[1]) / (a[0].hypot(a[1]) * b[0].hypot(b[1]));
                best = best.min(cos.clamp(-1.0, 1.0).acos());
            }
        }
        best
    }

    /// Outward unit normal of boundary facet (edge) `i`.
    pub fn boundary_facet_normal(&self, i: usize) -> [f64; 2] {
        let f = self.boundary_facet(i);
        let (a, b) = (self.vertices[f[0]], self.vertices[f[1]]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let l = dx.hypot(dy);
        // The body is on the left of a → b, so the outward normal points right.
        [dy / l, -dx / l]
    }
}

/// Which diagonal splits each cell of a structured rectangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Diagonal {
    /// "/" : from the lower-left to the upper-right corner of every cell.
    #[default]
    Forward,
    /// "\" : from the upper-left to the lower-right corner of every cell.
    Backward,
}

/// Structured triangulation of the rectangle `[x0, x0 + lx] × [y0, y0 + ly]` with
/// `nx × ny` vertices (`nx − 1` by `ny − 1` cells, each split in two along `diagonal`).
///
/// Vertex `i + nx·j` sits at `(x0 + i·lx/(nx−1), y0 + j·ly/(ny−1))`. No tags are set.
/// The paper's coarse grid (§6.1) is `rectangle([0.0, 0.0], [5.0, 1.0], 6, 2, d)`:
/// 12 vertices, 10 triangles.
///
/// # Errors
/// [`Error::InvalidGrid`] if `nx < 2`, `ny < 2`, or a size is not positive and finite;
/// [`Error::NonFiniteCoordinate`] for a non-finite origin.
pub fn rectangle(
    origin: [f64; 2],
    size: [f64; 2],
    nx: usize,
    ny: usize,
    diagonal: Diagonal,
) -> Result<TriangleMesh> {
    if nx < 2 || ny < 2 {
        return Err(Error::InvalidGrid(format!(
            "need at least 2 x 2 vertices, got {nx} x {ny}"
        )));
    }
    if !(size[0] > 0.0 && size[1] > 0.0 && size[0].is_finite() && size[1].is_finite()) {
        return Err(Error::InvalidGrid(format!(
            "size must be positive and finite, got {size:?}"
        )));
    }
    let mut vertices = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            vertices.push([
                origin[0] + size[0] * i as f64 / (nx - 1) as f64,
                origin[1] + size[1] * j as f64 / (ny - 1) as f64,
            ]);
        }
    }
    let mut cells = Vec::with_capacity(6 * (nx - 1) * (ny - 1));
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let a = i + nx * j;
            let (b, c, d) = (a + 1, a + 1 + nx, a + nx);
            match diagonal {
                Diagonal::Forward => cells.extend_from_slice(&[a, b, c, a, c, d]),
                Diagonal::Backward => cells.extend_from_slice(&[a, b, d, b, c, d]),
            }
        }
    }
    SimplexMesh::new(vertices, cells)
}

/// The paper's coarse grid (§6.1, Table 6.1): `[0, 5] × [0, 1]` m with 6 × 2 vertices
/// (10 triangles, [`Diagonal::Forward`]) and boundary tags
/// [`TAG_DIRICHLET`] (top, y = 1), [`TAG_NEUMANN`] (sides x = 0 and x = 5) and
/// [`TAG_FRICTIONAL`] (bottom, y = 0).
pub fn pipping_slider_coarse(diagonal: Diagonal) -> TriangleMesh {
    let mut m =
        rectangle([0.0, 0.0], [5.0, 1.0], 6, 2, diagonal).expect("the slider rectangle is valid");
    m.tag_boundary(TAG_NEUMANN, |x| x[0] < 1e-9 || x[0] > 5.0 - 1e-9);
    m.tag_boundary(TAG_DIRICHLET, |x| x[1] > 1.0 - 1e-9);
    m.tag_boundary(TAG_FRICTIONAL, |x| x[1] < 1e-9);
    m
}
