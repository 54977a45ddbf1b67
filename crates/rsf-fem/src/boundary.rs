//! Boundary segments in 2D: boundary parts ordered along the boundary.

use std::collections::{HashMap, HashSet};

use crate::frames::NodalFrames;
use crate::mesh::{SimplexMesh, TriangleMesh};
use crate::part::BoundaryPart;
use crate::Result;

/// A [`BoundaryPart`] of a 2D mesh whose facets and nodes are **ordered along the
/// boundary**: in its counter-clockwise traversal direction (the body on the left), chain
/// by chain; `nodes()` lists the vertices in the same order, each once. On the paper's
/// bottom edge Γ_F this is increasing `x`.
///
/// Everything that does not need the order (weights, normals, frames, loads) is the
/// [`BoundaryPart`]'s ([`BoundarySegment::as_part`]; `&BoundarySegment` can be passed
/// wherever `impl AsRef<BoundaryPart<2>>` is taken).
#[derive(Debug, Clone, PartialEq)]
pub struct BoundarySegment<const D: usize> {
    part: BoundaryPart<D>,
}

impl<const D: usize> BoundarySegment<D> {
    /// Name of the segment (the tag or the name given to the predicate constructor).
    pub fn name(&self) -> &str {
        self.part.name()
    }
    /// Mesh vertex indices of the segment, ordered along it.
    pub fn nodes(&self) -> &[usize] {
        self.part.nodes()
    }
    /// Indices of the mesh's boundary facets ([`SimplexMesh::boundary_facet`]), ordered.
    pub fn facets(&self) -> &[usize] {
        self.part.facets()
    }
    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.part.num_nodes()
    }
    /// Total measure (length in 2D, m) of the segment on `mesh`.
    ///
    /// # Panics
    /// If `mesh` is not the mesh the segment was built on.
    pub fn measure(&self, mesh: &SimplexMesh<D>) -> f64 {
        self.part
            .measure(mesh)
            .expect("the segment belongs to this mesh")
    }
    /// Position of mesh vertex `v` in [`BoundarySegment::nodes`], if it is on the segment.
    pub fn local_index(&self, v: usize) -> Option<usize> {
        self.part.local_index(v)
    }
    /// The segment as an (ordered) boundary part.
    pub fn as_part(&self) -> &BoundaryPart<D> {
        &self.part
    }
}

impl<const D: usize> AsRef<BoundaryPart<D>> for BoundarySegment<D> {
    fn as_ref(&self) -> &BoundaryPart<D> {
        &self.part
    }
}

impl<const D: usize> From<BoundarySegment<D>> for BoundaryPart<D> {
    fn from(s: BoundarySegment<D>) -> Self {
        s.part
    }
}

impl BoundarySegment<2> {
    /// All boundary facets tagged `tag`.
    ///
    /// # Errors
    /// [`crate::Error::EmptySegment`] if no facet carries the tag.
    pub fn from_tag(mesh: &TriangleMesh, tag: &str) -> Result<Self> {
        Self::from_facets(mesh, tag, mesh.facets_with_tag(tag))
    }

    /// All boundary facets whose midpoint satisfies `predicate`, named `name`.
    ///
    /// # Errors
    /// [`crate::Error::EmptySegment`] if no facet is selected.
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
        // Chain the directed edges a → b.
        let mut next_of = HashMap::with_capacity(facets.len());
        let mut is_end = HashSet::with_capacity(facets.len());
        for &f in &facets {
            let e = mesh.boundary_facet(f);
            next_of.insert(e[0], f);
            is_end.insert(e[1]);
        }
        let mut used = HashSet::with_capacity(facets.len());
        let mut ordered = Vec::with_capacity(facets.len());
        let mut nodes = Vec::with_capacity(facets.len() + 1);
        let mut seen = HashSet::with_capacity(facets.len() + 1);
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
            part: BoundaryPart::with_order(mesh, name, ordered, nodes)?,
        })
    }

    /// Outward unit normal per node (length-weighted average of the adjacent facets'
    /// normals, normalised), in the order of [`BoundarySegment::nodes`].
    ///
    /// # Panics
    /// If `mesh` is not the mesh the segment was built on, or at a non-manifold vertex
    /// ([`BoundaryPart::normals`] returns errors instead).
    pub fn normals(&self, mesh: &TriangleMesh) -> Vec<[f64; 2]> {
        self.part
            .normals(mesh)
            .expect("the segment belongs to this mesh")
    }

    /// Nodal frames for bilateral contact: per node a rotation `Q_p` (det = +1) whose
    /// first column is the unit tangent in the segment's traversal direction and whose
    /// **last column is the inward unit normal** `−n_p` ([`BoundaryPart::frames`]). On the
    /// paper's bottom edge Γ_F every `Q_p` is the identity, so the normal velocity is
    /// component 1 (`y`).
    ///
    /// # Panics
    /// As [`BoundarySegment::normals`].
    pub fn frames(&self, mesh: &TriangleMesh) -> NodalFrames<2> {
        self.part
            .frames(mesh)
            .expect("the segment belongs to this mesh")
    }
}
