//! Named boundary parts for any dimension: Dirichlet, Neumann and frictional boundaries.

use nalgebra::SVector;

use crate::dof_transform::check_len;
use crate::frames::NodalFrames;
use crate::mesh::SimplexMesh;
use crate::{Error, Result};

/// A named part of the mesh boundary: a set of boundary facets (points in 1D, segments in
/// 2D, triangles in 3D) and their nodes, for any `D`.
///
/// This is what a problem description hands to the assembly: Γ_D (nodes to constrain),
/// Γ_N ([`crate::traction_load`]) and the frictional boundary Γ_F ([`BoundaryPart::weights`],
/// [`BoundaryPart::frames`]). Obtain it from a tag ([`BoundaryPart::from_tag`], e.g. a Gmsh
/// physical group), a predicate on facet midpoints ([`BoundaryPart::from_predicate`]) or a
/// list of facets ([`BoundaryPart::from_facets`]).
///
/// Order: [`BoundaryPart::facets`] increasing, [`BoundaryPart::nodes`] increasing vertex
/// index (a [`crate::BoundarySegment`] keeps its own chain order instead). All per-node
/// results (`weights`, `normals`, `frames`) follow the order of `nodes()`.
///
/// The geometric methods take the mesh the part was built on; a mesh with a different
/// number of vertices or boundary facets is rejected with [`Error::DimensionMismatch`].
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryPart<const D: usize> {
    name: String,
    facets: Vec<usize>,
    nodes: Vec<usize>,
    /// `facet_nodes[D·k + i]`: position in `nodes` of vertex `i` of `facets[k]`.
    facet_nodes: Vec<usize>,
    /// `(vertex, position in nodes)`, sorted by vertex.
    lookup: Vec<(usize, usize)>,
    mesh_vertices: usize,
    mesh_facets: usize,
}

impl<const D: usize> BoundaryPart<D> {
    /// All boundary facets tagged `tag`.
    ///
    /// # Errors
    /// [`Error::EmptySegment`] if no facet carries the tag.
    pub fn from_tag(mesh: &SimplexMesh<D>, tag: &str) -> Result<Self> {
        Self::from_facets(mesh, tag, mesh.facets_with_tag(tag))
    }

    /// All boundary facets whose midpoint (barycentre) satisfies `predicate`, named `name`.
    ///
    /// # Errors
    /// [`Error::EmptySegment`] if no facet is selected.
    pub fn from_predicate(
        mesh: &SimplexMesh<D>,
        name: &str,
        predicate: impl Fn(&[f64; D]) -> bool,
    ) -> Result<Self> {
        let f = (0..mesh.num_boundary_facets())
            .filter(|&f| predicate(&mesh.boundary_facet_midpoint(f)))
            .collect();
        Self::from_facets(mesh, name, f)
    }

    /// The given boundary facets (indices as in [`SimplexMesh::boundary_facet`]; duplicates
    /// are removed), named `name`.
    ///
    /// # Errors
    /// [`Error::InvalidFacet`] for an index out of range; [`Error::EmptySegment`] if
    /// `facets` is empty.
    pub fn from_facets(mesh: &SimplexMesh<D>, name: &str, mut facets: Vec<usize>) -> Result<Self> {
        if let Some(&f) = facets.iter().find(|&&f| f >= mesh.num_boundary_facets()) {
            return Err(Error::InvalidFacet {
                facet: f,
                num_facets: mesh.num_boundary_facets(),
            });
        }
        facets.sort_unstable();
        facets.dedup();
        let mut nodes: Vec<usize> = facets
            .iter()
            .flat_map(|&f| mesh.boundary_facet(f).iter().copied())
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        Self::with_order(mesh, name, facets, nodes)
    }

    /// A part whose facets and nodes are listed in the given orders (`nodes` must be
    /// exactly the facets' vertices, each once).
    ///
    /// # Errors
    /// [`Error::EmptySegment`] if `facets` is empty.
    pub(crate) fn with_order(
        mesh: &SimplexMesh<D>,
        name: &str,
        facets: Vec<usize>,
        nodes: Vec<usize>,
    ) -> Result<Self> {
        if facets.is_empty() {
            return Err(Error::EmptySegment {
                name: name.to_owned(),
            });
        }
        let mut lookup: Vec<(usize, usize)> =
            nodes.iter().enumerate().map(|(i, &v)| (v, i)).collect();
        lookup.sort_unstable();
        let position = |v: usize| {
            let k = lookup
                .binary_search_by_key(&v, |&(w, _)| w)
                .expect("facet vertices are part nodes");
            lookup[k].1
        };
        let facet_nodes = facets
            .iter()
            .flat_map(|&f| mesh.boundary_facet(f).iter().map(|&v| position(v)))
            .collect();
        Ok(Self {
            name: name.to_owned(),
            facets,
            nodes,
            facet_nodes,
            lookup,
            mesh_vertices: mesh.num_vertices(),
            mesh_facets: mesh.num_boundary_facets(),
        })
    }

    /// Name of the part (the tag or the name given to the constructor).
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Mesh vertex indices of the part.
    pub fn nodes(&self) -> &[usize] {
        &self.nodes
    }
    /// Indices of the mesh's boundary facets ([`SimplexMesh::boundary_facet`]).
    pub fn facets(&self) -> &[usize] {
        &self.facets
    }
    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.nodes.len()
    }
    /// Position of mesh vertex `v` in [`BoundaryPart::nodes`], if it is on the part
    /// (binary search).
    pub fn local_index(&self, v: usize) -> Option<usize> {
        self.lookup
            .binary_search_by_key(&v, |&(w, _)| w)
            .ok()
            .map(|k| self.lookup[k].1)
    }
    /// Positions in [`BoundaryPart::nodes`] of the `D` vertices of the `k`-th facet.
    pub(crate) fn facet_nodes(&self, k: usize) -> &[usize] {
        &self.facet_nodes[D * k..D * (k + 1)]
    }

    /// Checks that `mesh` is (by its sizes) the mesh the part was built on.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`].
    pub fn check_mesh(&self, mesh: &SimplexMesh<D>) -> Result<()> {
        check_len(
            "boundary part mesh vertices",
            self.mesh_vertices,
            mesh.num_vertices(),
        )?;
        check_len(
            "boundary part mesh facets",
            self.mesh_facets,
            mesh.num_boundary_facets(),
        )
    }

    /// Total measure of the part (m in 2D, m² in 3D).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for a different mesh.
    pub fn measure(&self, mesh: &SimplexMesh<D>) -> Result<f64> {
        self.check_mesh(mesh)?;
        Ok(self
            .facets
            .iter()
            .map(|&f| mesh.boundary_facet_measure(f))
            .sum())
    }

    /// Lumped weights `w_p = ∫_Γ λ_p ds = Σ_{facets ∋ p} |facet| / D` (m in 2D, m² in 3D),
    /// in the order of [`BoundaryPart::nodes`]; they sum to the part's measure
    /// (docs/math.md §3 and §10: Φ_h = Σ_p w_p ϕ(|v_p|, α_p)).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for a different mesh.
    pub fn weights(&self, mesh: &SimplexMesh<D>) -> Result<Vec<f64>> {
        self.check_mesh(mesh)?;
        let mut w = vec![0.0; self.nodes.len()];
        for (k, &f) in self.facets.iter().enumerate() {
            let share = mesh.boundary_facet_measure(f) / D as f64;
            for &i in self.facet_nodes(k) {
                w[i] += share;
            }
        }
        Ok(w)
    }

    /// Outward unit normal per node: the measure-weighted average of the adjacent facets'
    /// outward normals, normalised (docs/math.md §10), in the order of
    /// [`BoundaryPart::nodes`].
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for a different mesh; [`Error::UndefinedNormal`] if the
    /// average vanishes (only at non-manifold points, e.g. two cells touching at a vertex).
    pub fn normals(&self, mesh: &SimplexMesh<D>) -> Result<Vec<[f64; D]>> {
        self.check_mesh(mesh)?;
        // Area-weighted sums of the facets' unit outer normals.
        let mut n = vec![SVector::<f64, D>::zeros(); self.nodes.len()];
        for (k, &f) in self.facets.iter().enumerate() {
            let nf = SVector::from(mesh.boundary_facet_normal(f));
            let a = mesh.boundary_facet_measure(f);
            for &i in self.facet_nodes(k) {
                n[i] += nf * a;
            }
        }
        n.into_iter()
            .zip(&self.nodes)
            .map(|(v, &p)| {
                let l = v.norm();
                if l > 0.0 && l.is_finite() {
                    Ok((v / l).into())
                } else {
                    Err(Error::UndefinedNormal { vertex: p })
                }
            })
            .collect()
    }

    /// Nodal frames for bilateral contact: per node a rotation `Q_p` (det = +1) whose
    /// **last column is the inward unit normal** `−n_p` and whose first `D − 1` columns are
    /// unit tangents. 2D: `t = (−n_y, n_x)`, the counter-clockwise traversal direction.
    /// 3D: `t1` is the normalised projection onto the tangent plane of the Cartesian axis
    /// `e_k` with the smallest `|n_k|` (the first such `k`), `t2 = −n × t1`; e.g. on a bottom
    /// face (`n = −e_z`) `Q_p` is the identity, on `n = −e_y` its columns are
    /// `(e_x, −e_z, e_y)`. In the local basis the normal velocity is component `D − 1` and
    /// the tangential slip rate is the norm of the first `D − 1` components.
    ///
    /// # Errors
    /// As [`BoundaryPart::normals`].
    pub fn frames(&self, mesh: &SimplexMesh<D>) -> Result<NodalFrames<D>> {
        let n = self.normals(mesh)?;
        NodalFrames::from_normals(self.nodes.clone(), &n, None, mesh.vertices())
    }

    /// As [`BoundaryPart::frames`], but in 3D the first tangent is the normalised
    /// projection of `direction` onto each node's tangent plane (e.g. the loading
    /// direction). In 1D and 2D the frames do not depend on `direction`.
    ///
    /// # Errors
    /// As [`BoundaryPart::normals`]; [`Error::NonFiniteValue`] if `direction` is not finite;
    /// [`Error::TangentAlongNormal`] naming the first node (and its position) where
    /// `direction` is (nearly, its projection `< 1e-6` of its length) normal — no other
    /// tangent is chosen silently there.
    pub fn frames_with_tangent(
        &self,
        mesh: &SimplexMesh<D>,
        direction: [f64; D],
    ) -> Result<NodalFrames<D>> {
        if direction.iter().any(|c| !c.is_finite()) {
            return Err(Error::NonFiniteValue("tangent direction"));
        }
        let n = self.normals(mesh)?;
        NodalFrames::from_normals(self.nodes.clone(), &n, Some(&direction), mesh.vertices())
    }
}

impl<const D: usize> AsRef<BoundaryPart<D>> for BoundaryPart<D> {
    fn as_ref(&self) -> &BoundaryPart<D> {
        self
    }
}
