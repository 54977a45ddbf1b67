//! Uniform (red) refinement and the multilevel hierarchy with P1 prolongations.

use faer::sparse::{SparseColMat, Triplet};

use crate::mesh::{SimplexMesh, TriangleMesh};

/// Levels `0..=J` of uniformly refined meshes with the P1 prolongations between them.
///
/// Level `j` is obtained from level `j − 1` by one red refinement (every triangle split
/// into four similar ones through its edge midpoints). The vertices of level `j − 1` keep
/// their indices on level `j`; the new midpoint vertices follow. Boundary tags are
/// inherited by the two halves of every tagged facet.
#[derive(Debug, Clone)]
pub struct MeshHierarchy<const D: usize> {
    levels: Vec<SimplexMesh<D>>,
    prolongations: Vec<SparseColMat<usize, f64>>,
    vector_prolongations: Vec<SparseColMat<usize, f64>>,
}

impl<const D: usize> MeshHierarchy<D> {
    /// Number of levels (`finest_level() + 1`).
    pub fn num_levels(&self) -> usize {
        self.levels.len()
    }
    /// Index `J` of the finest level.
    pub fn finest_level(&self) -> usize {
        self.levels.len() - 1
    }
    /// All levels, coarsest first.
    pub fn levels(&self) -> &[SimplexMesh<D>] {
        &self.levels
    }
    /// Mesh of level `j`.
    ///
    /// # Panics
    /// If `j > finest_level()`.
    pub fn level(&self, j: usize) -> &SimplexMesh<D> {
        &self.levels[j]
    }
    /// The finest mesh.
    pub fn finest(&self) -> &SimplexMesh<D> {
        self.levels
            .last()
            .expect("hierarchy has at least one level")
    }
    /// Scalar P1 prolongation `P_j` from level `j − 1` to level `j`
    /// (`n_j × n_{j−1}`, exact for globally linear functions).
    ///
    /// # Panics
    /// If `j == 0` or `j > finest_level()`.
    pub fn prolongation(&self, j: usize) -> &SparseColMat<usize, f64> {
        assert!(j >= 1, "there is no prolongation into level 0");
        &self.prolongations[j - 1]
    }
    /// Node-major vector prolongation `P_j ⊗ I_D` (`D n_j × D n_{j−1}`).
    ///
    /// # Panics
    /// If `j == 0` or `j > finest_level()`.
    pub fn vector_prolongation(&self, j: usize) -> &SparseColMat<usize, f64> {
        assert!(j >= 1, "there is no prolongation into level 0");
        &self.vector_prolongations[j - 1]
    }
}

impl MeshHierarchy<2> {
    /// Refines `coarse` uniformly `levels` times (so the hierarchy has `levels + 1` meshes).
    ///
    /// Memory grows by ×4 per level: the paper's slider at level 8 has 655 360 triangles
    /// and 329 217 vertices.
    pub fn refine_uniformly(coarse: TriangleMesh, levels: usize) -> Self {
        let mut h = Self {
            levels: vec![coarse],
            prolongations: Vec::new(),
            vector_prolongations: Vec::new(),
        };
        for _ in 0..levels {
            let (fine, p) = refine_red(h.finest());
            h.vector_prolongations.push(vectorize::<2>(&p));
            h.prolongations.push(p);
            h.levels.push(fine);
        }
        h
    }
}

/// Node-major vector version `P ⊗ I_D` of a scalar prolongation.
pub fn vectorize<const D: usize>(p: &SparseColMat<usize, f64>) -> SparseColMat<usize, f64> {
    let mut t = Vec::with_capacity(p.compute_nnz() * D);
    for j in 0..p.ncols() {
        let col = p.as_ref();
        let rows = col.row_idx_of_col_raw(j);
        let vals = col.val_of_col(j);
        for (&i, &v) in rows.iter().zip(vals) {
            for r in 0..D {
                t.push(Triplet::new(D * i + r, D * j + r, v));
            }
        }
    }
    SparseColMat::try_new_from_triplets(D * p.nrows(), D * p.ncols(), &t)
        .expect("valid prolongation triplets")
}

/// One red refinement of a triangle mesh. Returns the fine mesh and the scalar
/// prolongation (fine × coarse).
pub fn refine_red(mesh: &TriangleMesh) -> (TriangleMesh, SparseColMat<usize, f64>) {
    let nc = mesh.num_cells();
    let nv = mesh.num_vertices();
    // Edge opposite local vertex k of cell c: slot 3c + k.
    let mut keys: Vec<(usize, usize, usize)> = Vec::with_capacity(3 * nc);
    for c in 0..nc {
        let cell = mesh.cell(c);
        for k in 0..3 {
            let (a, b) = (cell[(k + 1) % 3], cell[(k + 2) % 3]);
            keys.push((a.min(b), a.max(b), 3 * c + k));
        }
    }
    keys.sort_unstable();
    let mut edge_of = vec![0usize; 3 * nc];
    let mut edges: Vec<(usize, usize)> = Vec::with_capacity(3 * nc / 2 + 3);
    for (i, &(a, b, slot)) in keys.iter().enumerate() {
        if i == 0 || (keys[i - 1].0, keys[i - 1].1) != (a, b) {
            edges.push((a, b));
        }
        edge_of[slot] = edges.len() - 1;
    }
    drop(keys);
    let mut vertices = Vec::with_capacity(nv + edges.len());
    vertices.extend_from_slice(mesh.vertices());
    let x = mesh.vertices();
    for &(a, b) in &edges {
        vertices.push([0.5 * (x[a][0] + x[b][0]), 0.5 * (x[a][1] + x[b][1])]);
    }
    let mut cells = Vec::with_capacity(12 * nc);
    for c in 0..nc {
        let v = mesh.cell(c);
        let m0 = nv + edge_of[3 * c];
        let m1 = nv + edge_of[3 * c + 1];
        let m2 = nv + edge_of[3 * c + 2];
        cells.extend_from_slice(&[v[0], m2, m1, m2, v[1], m0, m1, m0, v[2], m0, m1, m2]);
    }
    let mut fine = SimplexMesh::new(vertices, cells).expect("red refinement of a valid mesh");
    // Carry the tags: every fine boundary edge has exactly one midpoint vertex of a
    // coarse boundary edge.
    let mut coarse_facet_of_edge = vec![usize::MAX; edges.len()];
    for f in 0..mesh.num_boundary_facets() {
        let c = mesh.boundary_facet_cell(f);
        let fv = mesh.boundary_facet(f);
        let cell = mesh.cell(c);
        let k = (0..3)
            .find(|&k| {
                let (a, b) = (cell[(k + 1) % 3], cell[(k + 2) % 3]);
                (a == fv[0] && b == fv[1]) || (a == fv[1] && b == fv[0])
            })
            .expect("boundary facet is an edge of its cell");
        coarse_facet_of_edge[edge_of[3 * c + k]] = f;
    }
    let tags = (0..fine.num_boundary_facets())
        .map(|f| {
            let fv = fine.boundary_facet(f);
            let m = fv[0].max(fv[1]);
            debug_assert!(m >= nv && fv[0].min(fv[1]) < nv);
            let cf = coarse_facet_of_edge[m - nv];
            debug_assert!(cf != usize::MAX);
            mesh.raw_facet_tag(cf)
        })
        .collect();
    fine.set_facet_tags(mesh.tag_names().to_vec(), tags);
    // Prolongation: identity on old vertices, ½ + ½ on midpoints.
    let mut t = Vec::with_capacity(nv + 2 * edges.len());
    for i in 0..nv {
        t.push(Triplet::new(i, i, 1.0));
    }
    for (e, &(a, b)) in edges.iter().enumerate() {
        t.push(Triplet::new(nv + e, a, 0.5));
        t.push(Triplet::new(nv + e, b, 0.5));
    }
    let p = SparseColMat::try_new_from_triplets(nv + edges.len(), nv, &t)
        .expect("valid prolongation triplets");
    (fine, p)
}
