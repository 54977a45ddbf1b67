//! A small linear elasticity problem of fixed data on a refined box: the problem that the
//! distributed solvers (rsf-ranks' sweeps, rsf-tnnmg's `distributed` module, rsf-mpi's
//! halo exchange) are tested and measured on, built in one place so that their tests and
//! programs agree.

use faer::sparse::SparseColMat;

use crate::error::Result;
use crate::hierarchy::MeshHierarchy;
use crate::mesh::TetrahedronMesh;
use crate::structured::cuboid;
use crate::{Assembler, LinearElasticity};

/// P1 isotropic elasticity (E = 1, ν = 0.3) on the box `[0, size[0]] × [0, size[1]] ×
/// [0, size[2]]` of `vertices` Kuhn-split cubes' corners ([`cuboid`]), refined uniformly
/// `refinements` times ([`MeshHierarchy`]), with the face z = 0 clamped and the face x = 0
/// on rollers (its x component fixed).
///
/// A 5 × 3 × 3-cube box (`vertices = [6, 4, 4]`) has 10 647 dofs after 2 refinements,
/// 76 875 after 3 and 583 443 after 4.
#[derive(Debug, Clone)]
pub struct ElasticBox {
    /// The levels, coarsest first; the problem lives on the finest.
    pub hierarchy: MeshHierarchy<3>,
    /// The stiffness of the finest level (`3 n × 3 n`, node-major, both triangles stored).
    pub stiffness: SparseColMat<usize, f64>,
    /// Whether each dof (`3 n`, node-major) is fixed: every component on z = 0, the x
    /// component on x = 0.
    pub fixed: Vec<bool>,
}

impl ElasticBox {
    /// The problem on the box of `size` with `vertices` per direction, refined
    /// `refinements` times.
    ///
    /// # Errors
    /// As [`cuboid`] (fewer than 2 vertices in a direction, a size that is not positive and
    /// finite) and [`MeshHierarchy::try_refine_uniformly`].
    pub fn new(size: [f64; 3], vertices: [usize; 3], refinements: usize) -> Result<Self> {
        let coarse = cuboid([0.0; 3], size, vertices)?;
        let hierarchy = MeshHierarchy::try_refine_uniformly(coarse, refinements)?;
        let mesh = hierarchy.finest();
        let material = LinearElasticity::isotropic(1.0, 0.3)?;
        let stiffness = Assembler::new(mesh)?.stiffness(mesh, &material)?;
        let mut fixed = vec![false; 3 * mesh.num_vertices()];
        for (p, v) in mesh.vertices().iter().enumerate() {
            for c in 0..3 {
                fixed[3 * p + c] = v[2] == 0.0 || (c == 0 && v[0] == 0.0);
            }
        }
        Ok(Self {
            hierarchy,
            stiffness,
            fixed,
        })
    }

    /// The box `[0, 2] × [0, 1] × [0, 1]` of 5 × 3 × 3 cubes (`vertices = [6, 4, 4]`)
    /// refined `refinements` times: the box of docs/scaling.md's halo tables and
    /// measurements (76 875 dofs after 3 refinements, near the 3-D slider's 70 227 at j = 4).
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn bar(refinements: usize) -> Result<Self> {
        Self::new([2.0, 1.0, 1.0], [6, 4, 4], refinements)
    }

    /// The finest mesh.
    pub fn mesh(&self) -> &TetrahedronMesh {
        self.hierarchy.finest()
    }

    /// Number of dofs (3 per vertex of the finest mesh).
    pub fn dofs(&self) -> usize {
        3 * self.mesh().num_vertices()
    }

    /// A right-hand side of fixed data: `sin(0.37 i + 0.1)` at dof `i`.
    pub fn load(&self) -> Vec<f64> {
        (0..self.dofs())
            .map(|i| (0.37 * i as f64 + 0.1).sin())
            .collect()
    }

    /// A start of fixed data: `0.5 cos(1.3 i)` at dof `i`.
    pub fn start(&self) -> Vec<f64> {
        (0..self.dofs())
            .map(|i| 0.5 * (1.3 * i as f64).cos())
            .collect()
    }

    /// The owner of every vertex of the finest mesh among `parts` ranks: slabs of nearly
    /// equal vertex counts along coordinate `axis` (the vertices sorted by that coordinate,
    /// ties by index, the `k`-th of `n` to rank `⌊k · parts / n⌋`). The simple partition
    /// that the distributed solvers' tests use besides a graph partitioner's.
    ///
    /// # Panics
    /// If `axis ≥ 3` or `parts == 0`.
    pub fn slabs(&self, parts: usize, axis: usize) -> Vec<usize> {
        assert!(axis < 3 && parts > 0, "axis {axis}, {parts} parts");
        let v = self.mesh().vertices();
        let mut order: Vec<usize> = (0..v.len()).collect();
        order.sort_by(|&p, &q| v[p][axis].total_cmp(&v[q][axis]).then(p.cmp(&q)));
        let mut owner = vec![0; v.len()];
        for (k, &p) in order.iter().enumerate() {
            owner[p] = k * parts / v.len();
        }
        owner
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The documented sizes, the fixed dofs on their faces only, a symmetric stiffness.
    #[test]
    fn the_box_has_its_sizes_and_fixed_faces() {
        let b = ElasticBox::bar(2).unwrap();
        assert_eq!(b.dofs(), 10_647);
        assert_eq!(b.hierarchy.num_levels(), 3);
        assert_eq!(b.stiffness.nrows(), b.dofs());
        let v = b.mesh().vertices();
        let clamped = v.iter().filter(|x| x[2] == 0.0).count();
        let rollers = v.iter().filter(|x| x[2] != 0.0 && x[0] == 0.0).count();
        assert_eq!(clamped, 21 * 13);
        assert_eq!(
            b.fixed.iter().filter(|&&f| f).count(),
            3 * clamped + rollers
        );
        assert_eq!(b.load().len(), b.dofs());
        assert!(b.start().iter().any(|&x| x != 0.0));
        assert!(ElasticBox::new([2.0, 1.0, 1.0], [1, 4, 4], 0).is_err());
    }

    /// Slabs: every part has ⌊n / parts⌋ or ⌈n / parts⌉ vertices, and along the axis a
    /// part's vertices lie at or below the next part's.
    #[test]
    fn slabs_split_the_vertices_evenly_along_the_axis() {
        let b = ElasticBox::new([1.5, 1.0, 1.0], [4, 3, 3], 1).unwrap();
        let v = b.mesh().vertices();
        let n = v.len();
        for axis in 0..3 {
            for parts in 1..=5 {
                let owner = b.slabs(parts, axis);
                let mut count = vec![0; parts];
                let mut lo = vec![f64::INFINITY; parts];
                let mut hi = vec![f64::NEG_INFINITY; parts];
                for (p, &r) in owner.iter().enumerate() {
                    count[r] += 1;
                    lo[r] = lo[r].min(v[p][axis]);
                    hi[r] = hi[r].max(v[p][axis]);
                }
                for r in 0..parts {
                    assert!(count[r] == n / parts || count[r] == n.div_ceil(parts));
                    if r + 1 < parts {
                        assert!(hi[r] <= lo[r + 1], "axis {axis}, {parts} parts");
                    }
                }
            }
        }
    }
}
