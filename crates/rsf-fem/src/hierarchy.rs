//! Uniform (red) refinement and the multilevel hierarchy with P1 prolongations.

use faer::sparse::{SparseColMat, Triplet};

use crate::mesh::SimplexMesh;
use crate::refine::try_refine_red;
use crate::Result;

/// Levels `0..=J` of uniformly refined meshes with the P1 prolongations between them.
///
/// Level `j` is obtained from level `j − 1` by one red refinement ([`refine_red`](crate::refine_red): every
/// triangle split into four similar ones through its edge midpoints, every tetrahedron
/// into eight by Bey's rule). The vertices of level `j − 1` keep their indices on level
/// `j`; the new midpoint vertices follow. Boundary tags are inherited by the `2^(D−1)`
/// parts of every tagged facet.
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

impl<const D: usize> MeshHierarchy<D> {
    /// A hierarchy of nested meshes made elsewhere (e.g. by bisection,
    /// [`BisectionMesh::hierarchy`](crate::BisectionMesh::hierarchy)): `levels` coarsest
    /// first, `prolongations[j − 1]` the scalar P1 prolongation from level `j − 1` to level
    /// `j` (`n_j × n_{j−1}`, exact for linear functions on nested meshes); the vertices of
    /// a level keep their indices on the finer levels, as in a uniform refinement.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`](crate::Error::DimensionMismatch) for no level, a
    /// prolongation count other than `levels − 1`, or a prolongation whose shape is not
    /// its two levels' vertex counts.
    pub fn from_levels(
        levels: Vec<SimplexMesh<D>>,
        prolongations: Vec<SparseColMat<usize, f64>>,
    ) -> Result<Self> {
        let mismatch = |what, expected, got| crate::Error::DimensionMismatch {
            what,
            expected,
            got,
        };
        if levels.is_empty() {
            return Err(mismatch("hierarchy levels", 1, 0));
        }
        if prolongations.len() + 1 != levels.len() {
            return Err(mismatch(
                "hierarchy prolongations",
                levels.len() - 1,
                prolongations.len(),
            ));
        }
        for (j, p) in prolongations.iter().enumerate() {
            let (coarse, fine) = (levels[j].num_vertices(), levels[j + 1].num_vertices());
            if p.ncols() != coarse {
                return Err(mismatch(
                    "prolongation columns (coarse vertices)",
                    coarse,
                    p.ncols(),
                ));
            }
            if p.nrows() != fine {
                return Err(mismatch(
                    "prolongation rows (fine vertices)",
                    fine,
                    p.nrows(),
                ));
            }
        }
        let vector_prolongations = prolongations.iter().map(vectorize::<D>).collect();
        Ok(Self {
            levels,
            prolongations,
            vector_prolongations,
        })
    }

    /// Refines `coarse` uniformly `levels` times (so the hierarchy has `levels + 1` meshes),
    /// see [`refine_red`](crate::refine_red).
    ///
    /// Memory grows by `2^D` per level: the paper's slider at level 8 has 655 360 triangles
    /// and 329 217 vertices; a 3D box of 6 tetrahedra has 6·8^J tetrahedra at level J.
    ///
    /// # Panics
    /// As [`refine_red`](crate::refine_red); see [`MeshHierarchy::try_refine_uniformly`].
    pub fn refine_uniformly(coarse: SimplexMesh<D>, levels: usize) -> Self {
        Self::try_refine_uniformly(coarse, levels).expect("red refinement of a valid mesh")
    }

    /// [`MeshHierarchy::refine_uniformly`] returning an error instead of panicking.
    ///
    /// # Errors
    /// As [`try_refine_red`].
    pub fn try_refine_uniformly(coarse: SimplexMesh<D>, levels: usize) -> Result<Self> {
        let mut h = Self {
            levels: vec![coarse],
            prolongations: Vec::new(),
            vector_prolongations: Vec::new(),
        };
        for _ in 0..levels {
            let (fine, p) = try_refine_red(h.finest())?;
            h.vector_prolongations.push(vectorize::<D>(&p));
            h.prolongations.push(p);
            h.levels.push(fine);
        }
        Ok(h)
    }

    /// As [`MeshHierarchy::try_refine_uniformly`] for a domain with a curved boundary part:
    /// after each refinement, every new vertex on a boundary facet tagged `tag` (the
    /// midpoint of a chord of the coarser level) is moved to `project(x)`, e.g. its
    /// projection onto the exact curve or surface the facets approximate, before the next
    /// refinement. Vertices of the coarser levels stay where they are (the coarse mesh's
    /// boundary vertices should lie on the exact boundary already), so every level's
    /// boundary vertices lie on it. The prolongations are those of the refinement (P1
    /// interpolation at the chord midpoints): the levels are nested except within a
    /// layer of cells along the curved part, which is what multigrid on curved domains
    /// usually does; the finest level is the discretisation.
    ///
    /// # Errors
    /// As [`try_refine_red`]; as [`SimplexMesh::with_moved_vertices`] if a projection turns
    /// a cell over (projections must move a vertex by much less than the cell size).
    pub fn try_refine_uniformly_onto(
        coarse: SimplexMesh<D>,
        levels: usize,
        tag: &str,
        project: impl Fn(&[f64; D]) -> [f64; D],
    ) -> Result<Self> {
        let mut h = Self {
            levels: vec![coarse],
            prolongations: Vec::new(),
            vector_prolongations: Vec::new(),
        };
        for _ in 0..levels {
            let old = h.finest().num_vertices();
            let (fine, p) = try_refine_red(h.finest())?;
            let mut vertices = fine.vertices().to_vec();
            for f in fine.facets_with_tag(tag) {
                for &v in fine.boundary_facet(f) {
                    if v >= old {
                        vertices[v] = project(&fine.vertices()[v]);
                    }
                }
            }
            let fine = fine.with_moved_vertices(vertices)?;
            h.vector_prolongations.push(vectorize::<D>(&p));
            h.prolongations.push(p);
            h.levels.push(fine);
        }
        Ok(h)
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
