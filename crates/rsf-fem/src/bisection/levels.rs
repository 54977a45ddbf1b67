//! A multigrid hierarchy of graded meshes by bisection ([`BisectionMesh::hierarchy`]):
//! nested levels, each the next one's coarse space, with the P1 prolongations read from
//! the midpoints' parents.

use faer::sparse::{SparseColMat, Triplet};

use super::BisectionMesh;
use crate::mesh::TetrahedronMesh;
use crate::{MeshHierarchy, Result};

impl BisectionMesh {
    /// The graded mesh of `size` as a multigrid hierarchy of `levels + 1` nested meshes:
    /// level 0 is this mesh as it is (the root Kuhn box, or what has been refined so far),
    /// level `ℓ ≥ 1` the previous one bisected further ([`refine`](Self::refine)) with the
    /// size clamped at `root / 2^ℓ` — `max(size(lo, hi), root/2^ℓ)`, `root` the edge of
    /// [`kuhn_box`](Self::kuhn_box)'s cubes — so that each level halves the cells where
    /// the finest wants them smaller and leaves the far field as it is. With
    /// `root / 2^levels` at most the smallest size asked for, the finest level is the mesh
    /// `refine(size, …)` makes. Refinement only adds vertices, and each is the midpoint of
    /// an edge of a mesh refining the level before, so the levels are nested and the
    /// prolongation `P_ℓ` (`n_ℓ × n_{ℓ−1}`) interpolates exactly: the identity on the old
    /// vertices, at a new one the mean of its edge's two ends (themselves old, or new and
    /// interpolated before it, in creation order). Use it with
    /// `rsf::ModelBuilder::from_hierarchy` for
    /// multigrid on a graded mesh (docs/fem.md "Graded meshes by bisection").
    ///
    /// ```
    /// use rsf_fem::BisectionMesh;
    /// // Cells of 1/8 m at the face x = 0 of a 2 m cube, growing away from it.
    /// let b = BisectionMesh::kuhn_box([0.0; 3], [2.0; 3], 1.0)?;
    /// let h = b.hierarchy(|lo, _| 0.125 + 0.5 * lo[0], 3, 1_000_000)?;
    /// assert_eq!(h.num_levels(), 4);
    /// // Nested: a linear function is interpolated exactly from level to level.
    /// let f = |x: &[f64; 3]| 1.0 + x[0] - 2.0 * x[1] + 3.0 * x[2];
    /// for j in 1..4 {
    ///     let coarse: Vec<f64> = h.level(j - 1).vertices().iter().map(f).collect();
    ///     let p = h.prolongation(j);
    ///     let mut fine = vec![0.0; p.nrows()];
    ///     for c in 0..p.ncols() {
    ///         for (r, &w) in p.row_idx_of_col(c).zip(p.val_of_col(c)) {
    ///             fine[r] += w * coarse[c];
    ///         }
    ///     }
    ///     let exact: Vec<f64> = h.level(j).vertices().iter().map(f).collect();
    ///     assert!(fine.iter().zip(&exact).all(|(a, b)| (a - b).abs() < 1e-12));
    /// }
    /// # Ok::<(), rsf_fem::Error>(())
    /// ```
    ///
    /// # Errors
    /// As [`refine`](Self::refine) (a size that is not positive, more than `max_cells`
    /// cells on a level) and [`into_mesh`](Self::into_mesh).
    pub fn hierarchy(
        mut self,
        size: impl Fn([f64; 3], [f64; 3]) -> f64,
        levels: usize,
        max_cells: usize,
    ) -> Result<MeshHierarchy<3>> {
        let mut meshes = vec![self.mesh()?];
        let mut prolongations = Vec::with_capacity(levels);
        for level in 1..=levels {
            let coarse = self.vertices.len();
            let floor = self.root / 2f64.powi(level as i32);
            self.refine(|lo, hi| size(lo, hi).max(floor), max_cells)?;
            prolongations.push(self.prolongation_from(coarse));
            meshes.push(self.mesh()?);
        }
        MeshHierarchy::from_levels(meshes, prolongations)
    }

    /// The mesh as it is now (the cells copied).
    fn mesh(&self) -> Result<TetrahedronMesh> {
        let cells = self
            .cells
            .iter()
            .flat_map(|c| c.map(|v| v as usize))
            .collect();
        TetrahedronMesh::from_ordered_cells(self.vertices.clone(), cells)
    }

    /// The P1 prolongation from the mesh of the first `coarse` vertices (a coarser level
    /// this mesh refines) to this one: the identity on them, the mean of the parents'
    /// rows at every later vertex (each row at most the four corners of the coarse cell
    /// holding the vertex).
    fn prolongation_from(&self, coarse: usize) -> SparseColMat<usize, f64> {
        let n = self.vertices.len();
        let mut rows: Vec<Vec<(usize, f64)>> = Vec::with_capacity(n - coarse);
        let mut triplets: Vec<Triplet<usize, usize, f64>> =
            (0..coarse).map(|v| Triplet::new(v, v, 1.0)).collect();
        for z in coarse..n {
            let mut row: Vec<(usize, f64)> = Vec::with_capacity(8);
            for v in self.parents[z - self.roots] {
                let v = v as usize;
                if v < coarse {
                    row.push((v, 0.5));
                } else {
                    row.extend(rows[v - coarse].iter().map(|&(c, w)| (c, 0.5 * w)));
                }
            }
            row.sort_unstable_by_key(|&(c, _)| c);
            row.dedup_by(|b, a| {
                let same = a.0 == b.0;
                if same {
                    a.1 += b.1;
                }
                same
            });
            triplets.extend(row.iter().map(|&(c, w)| Triplet::new(z, c, w)));
            rows.push(row);
        }
        SparseColMat::try_new_from_triplets(n, coarse, &triplets)
            .expect("valid prolongation triplets")
    }
}
