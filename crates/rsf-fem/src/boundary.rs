//! Boundary segments (Γ_D, Γ_N, Γ_F), their normals and nodal frames.

use faer::sparse::{SparseColMat, SparseColMatRef, Triplet};

use crate::mesh::{SimplexMesh, TriangleMesh};
use crate::{Error, Result};

/// A named part of the mesh boundary: a set of boundary facets and their nodes.
///
/// In 2D the facets are ordered along the boundary in its counter-clockwise traversal
/// direction (the body on the left), chain by chain; `nodes()` lists the vertices in
/// the same order, each once. On the paper's bottom edge Γ_F this is increasing `x`.
#[derive(Debug, Clone)]
pub struct BoundarySegment<const D: usize> {
    name: String,
    facets: Vec<usize>,
    nodes: Vec<usize>,
}

impl<const D: usize> BoundarySegment<D> {
    /// Name of the segment (the tag or the name given to the predicate constructor).
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Mesh vertex indices of the segment, ordered along it.
    pub fn nodes(&self) -> &[usize] {
        &self.nodes
    }
    /// Indices of the mesh's boundary facets ([`SimplexMesh::boundary_facet`]), ordered.
    pub fn facets(&self) -> &[usize] {
        &self.facets
    }
    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.nodes.len()
    }
    /// Total measure (length in 2D, m) of the segment on `mesh`.
    pub fn measure(&self, mesh: &SimplexMesh<D>) -> f64 {
        self.facets
            .iter()
            .map(|&f| mesh.boundary_facet_measure(f))
            .sum()
    }
    /// Position of mesh vertex `v` in [`BoundarySegment::nodes`], if it is on the segment.
    pub fn local_index(&self, v: usize) -> Option<usize> {
        self.nodes.iter().position(|&n| n == v)
    }
}

impl BoundarySegment<2> {
    /// All boundary facets tagged `tag`.
    ///
    /// # Errors
    /// [`Error::EmptySegment`] if no facet carries the tag.
    pub fn from_tag(mesh: &TriangleMesh, tag: &str) -> Result<Self> {
        Self::from_facets(mesh, tag, mesh.facets_with_tag(tag))
    }

    /// All boundary facets whose midpoint satisfies `predicate`, named `name`.
    ///
    /// # Errors
    /// [`Error::EmptySegment`] if no facet is selected.
    pub fn from_predicate(
        mesh: &TriangleMesh,
        name: &str,
        predicate: impl Fn(&[f64; 2]) -> bool,
    ) -> Result<Self> {
        let f = (0..mesh.num_boundary_facets())
            .filter(|&f| predicate(&mesh.boundary_facet_midpoint(f)))
            .collect();
        Self::from_facets(mesh, name, f)
    }

    fn from_facets(mesh: &TriangleMesh, name: &str, facets: Vec<usize>) -> Result<Self> {
        if facets.is_empty() {
            return Err(Error::EmptySegment {
                name: name.to_owned(),
            });
        }
        // Chain the directed edges a → b.
        let mut next_of = std::collections::HashMap::with_capacity(facets.len());
        let mut is_end = std::collections::HashSet::with_capacity(facets.len());
        for &f in &facets {
            let e = mesh.boundary_facet(f);
            next_of.insert(e[0], f);
            is_end.insert(e[1]);
        }
        let mut used = std::collections::HashSet::with_capacity(facets.len());
        let mut ordered = Vec::with_capacity(facets.len());
        let mut nodes = Vec::with_capacity(facets.len() + 1);
        let mut seen = std::collections::HashSet::with_capacity(facets.len() + 1);
        // Open chains first (starting at a vertex that ends no facet), then closed loops.
        let starts: Vec<usize> = facets
            .iter()
            .copied()
            .filter(|&f| !is_end.contains(&mesh.boundary_facet(f)[0]))
            .chain(facets.iter().copied())
            .collect();
        for f0 in starts {
            if used.contains(&f0) {
                continue;
            }
            let mut f = f0;
            let first = mesh.boundary_facet(f)[0];
            if seen.insert(first) {
                nodes.push(first);
            }
            loop {
                used.insert(f);
                ordered.push(f);
                let b = mesh.boundary_facet(f)[1];
                if seen.insert(b) {
                    nodes.push(b);
                }
                match next_of.get(&b) {
                    Some(&g) if !used.contains(&g) => f = g,
                    _ => break,
                }
            }
        }
        Ok(Self {
            name: name.to_owned(),
            facets: ordered,
            nodes,
        })
    }

    /// Outward unit normal per node (length-weighted average of the adjacent facets'
    /// normals, normalised), in the order of [`BoundarySegment::nodes`].
    pub fn normals(&self, mesh: &TriangleMesh) -> Vec<[f64; 2]> {
        let mut n = vec![[0.0; 2]; self.nodes.len()];
        let index: std::collections::HashMap<usize, usize> = self
            .nodes
            .iter()
            .enumerate()
            .map(|(i, &v)| (v, i))
            .collect();
        for &f in &self.facets {
            let nf = mesh.boundary_facet_normal(f);
            let l = mesh.boundary_facet_measure(f);
            for &v in mesh.boundary_facet(f) {
                let k = index[&v];
                n[k][0] += l * nf[0];
                n[k][1] += l * nf[1];
            }
        }
        for v in &mut n {
            let l = v[0].hypot(v[1]);
            v[0] /= l;
            v[1] /= l;
        }
        n
    }

    /// Nodal frames for bilateral contact: per node a rotation `Q_p` (det = +1) whose
    /// first column is the unit tangent in the segment's traversal direction and whose
    /// **last column is the inward unit normal** `−n_p`. On the paper's bottom edge Γ_F
    /// every `Q_p` is the identity, so the normal velocity is component 1 (`y`).
    pub fn frames(&self, mesh: &TriangleMesh) -> NodalFrames<2> {
        let rotations = self
            .normals(mesh)
            .into_iter()
            .map(|n| {
                let (nin, t) = ([-n[0], -n[1]], [-n[1], n[0]]);
                [[t[0], nin[0]], [t[1], nin[1]]]
            })
            .collect();
        NodalFrames {
            nodes: self.nodes.clone(),
            rotations,
        }
    }
}

/// Per-node orthonormal frames `Q_p` (row-major `D × D`, columns = local basis vectors)
/// on a set of nodes; all other nodes keep the Cartesian basis.
///
/// With `R = blockdiag(Q_p)` (identity off the frame nodes), local coefficients are
/// `ṽ = Rᵀ v`, a matrix transforms as `Ã = Rᵀ A R` and a fine-level prolongation as
/// `P̃ = Rᵀ P` (its coarse side stays Cartesian).
#[derive(Debug, Clone)]
pub struct NodalFrames<const D: usize> {
    /// Mesh vertices carrying a frame.
    pub nodes: Vec<usize>,
    /// `rotations[k][r][c]`: entry (r, c) of `Q` at `nodes[k]`.
    pub rotations: Vec<[[f64; D]; D]>,
}

impl<const D: usize> NodalFrames<D> {
    fn check(&self, n_dofs: usize) -> Result<Vec<Option<usize>>> {
        if n_dofs % D != 0 {
            return Err(Error::DimensionMismatch {
                what: "node-major vector length",
                expected: D * (n_dofs / D),
                got: n_dofs,
            });
        }
        let mut map = vec![None; n_dofs / D];
        for (k, &v) in self.nodes.iter().enumerate() {
            if v >= map.len() {
                return Err(Error::InvalidDof {
                    node: v,
                    component: 0,
                });
            }
            map[v] = Some(k);
        }
        Ok(map)
    }

    /// `v ← Rᵀ v` (Cartesian → local coefficients), node-major `v`.
    ///
    /// # Errors
    /// [`Error::InvalidDof`] if a frame node is outside `v`.
    pub fn to_local(&self, v: &mut [f64]) -> Result<()> {
        self.apply(v, true)
    }
    /// `v ← R v` (local → Cartesian coefficients).
    ///
    /// # Errors
    /// [`Error::InvalidDof`] if a frame node is outside `v`.
    pub fn to_global(&self, v: &mut [f64]) -> Result<()> {
        self.apply(v, false)
    }
    fn apply(&self, v: &mut [f64], transpose: bool) -> Result<()> {
        self.check(v.len())?;
        for (&p, q) in self.nodes.iter().zip(&self.rotations) {
            let mut w = [0.0; D];
            for r in 0..D {
                for c in 0..D {
                    w[r] += if transpose { q[c][r] } else { q[r][c] } * v[D * p + c];
                }
            }
            v[D * p..D * p + D].copy_from_slice(&w);
        }
        Ok(())
    }

    /// `Rᵀ A R` for a node-major square matrix (e.g. `A`, `K`, `M` on the finest level).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] / [`Error::InvalidDof`] on size problems.
    pub fn rotate_matrix(
        &self,
        a: SparseColMatRef<'_, usize, f64>,
    ) -> Result<SparseColMat<usize, f64>> {
        self.transform(a, true, true)
    }
    /// `Rᵀ P`: rows of a (vector) prolongation into the finest level expressed in the
    /// local bases (the coarse space stays Cartesian).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] / [`Error::InvalidDof`] on size problems.
    pub fn rotate_rows(
        &self,
        p: SparseColMatRef<'_, usize, f64>,
    ) -> Result<SparseColMat<usize, f64>> {
        self.transform(p, true, false)
    }

    fn transform(
        &self,
        a: SparseColMatRef<'_, usize, f64>,
        left: bool,
        right: bool,
    ) -> Result<SparseColMat<usize, f64>> {
        let rmap = if left {
            Some(self.check(a.nrows())?)
        } else {
            None
        };
        let cmap = if right {
            Some(self.check(a.ncols())?)
        } else {
            None
        };
        let mut t = Vec::with_capacity(a.compute_nnz() * D);
        // Left pass: B = Rᵀ A (entry (p,r),j contributes Q_p[r][c] to (p,c), j).
        let push = |i: usize, j: usize, v: f64, t: &mut Vec<Triplet<usize, usize, f64>>| match cmap
            .as_ref()
            .and_then(|m| m[j / D])
        {
            Some(k) => {
                let (q, r) = (j / D, j % D);
                for c in 0..D {
                    let f = self.rotations[k][r][c];
                    if f != 0.0 {
                        t.push(Triplet::new(i, D * q + c, v * f));
                    }
                }
            }
            None => t.push(Triplet::new(i, j, v)),
        };
        for j in 0..a.ncols() {
            for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                match rmap.as_ref().and_then(|m| m[i / D]) {
                    Some(k) => {
                        let (p, r) = (i / D, i % D);
                        for c in 0..D {
                            let f = self.rotations[k][r][c];
                            if f != 0.0 {
                                push(D * p + c, j, v * f, &mut t);
                            }
                        }
                    }
                    None => push(i, j, v, &mut t),
                }
            }
        }
        SparseColMat::try_new_from_triplets(a.nrows(), a.ncols(), &t)
            .map_err(|e| Error::Faer(format!("{e:?}")))
    }
}
