//! Global assembly into `faer` CSC matrices with one shared symbolic pattern, and loads.

use faer::sparse::{SparseColMat, SymbolicSparseColMat, SymbolicSparseColMatRef};
use rsf_linalg::SparseMatrix;

use crate::dof_transform::check_len;
use crate::element::{p1_laplace, p1_mass, p1_mass_components, p1_stiffness, LinearElasticity};
use crate::geometry::p1_gradients;
use crate::mesh::SimplexMesh;
use crate::{Error, Result};

/// Assembler for node-major P1 fields with `C` components per vertex on one `D`-simplex
/// mesh: `C = D` (the default) for displacement vectors of elasticity, `C = 1` for a scalar
/// field such as the antiplane displacement of a 2-D section ([`Assembler::scalar`],
/// docs/seas-bp1.md).
///
/// [`Assembler::new`] computes the symbolic pattern once (both triangles, full `D × D`
/// node blocks, sorted rows) together with a scatter map from every cell's local node
/// pair to its position in the CSC value array. Numeric assembly then only evaluates
/// element matrices on the stack and adds them into the value array: no allocation
/// per element, no sorting. Dof `C·node + component`. All matrices produced by one
/// assembler share the pattern,
/// so `A = c_M M + c_K K` can be formed value-by-value ([`combine`](crate::combine)) and a
/// [`Cholesky`](crate::Cholesky) analysis can be reused.
///
/// # Columns of some nodes
/// [`Assembler::on_columns`] assembles only the columns of a set of kept nodes (all `C`
/// columns of each; the matrices are symmetric, so a column is also a row): the matrices
/// keep the whole `n × n` shape, the kept columns hold the whole pattern's rows and the
/// other columns are empty. Only the cells with a kept vertex are visited, in increasing
/// index, and they add only into kept columns, so every stored entry is summed over the
/// same cells in the same order as in the whole assembly: it has the same bits (the whole
/// assembly is the case "every node kept"). This is how one process of several assembles
/// the rows of the nodes it owns.
#[derive(Debug, Clone)]
pub struct Assembler<const D: usize, const C: usize = D> {
    num_vertices: usize,
    num_cells: usize,
    symbolic: SymbolicSparseColMat<usize>,
    /// The kept nodes (one flag per vertex); `None`: every node.
    columns: Option<Vec<bool>>,
    /// The cells visited (those with a kept vertex), increasing; `None`: every cell.
    cells: Option<Vec<usize>>,
    /// Per visited cell, per local pair (a, b): offset of scalar row `v_a` within scalar
    /// column `v_b` (`u32::MAX` where `v_b` is not kept).
    local_offset: Vec<u32>,
}

impl<const D: usize> Assembler<D> {
    /// Builds the pattern of `mesh` for `D`-component (vector) fields (cost
    /// `O(cells · (D+1)²)`, done once per mesh).
    ///
    /// # Errors
    /// [`Error::Faer`] if the pattern cannot be allocated.
    pub fn new(mesh: &SimplexMesh<D>) -> Result<Self> {
        Self::with_components(mesh)
    }
}

impl<const D: usize> Assembler<D, 1> {
    /// Builds the pattern of `mesh` for scalar fields (one dof per vertex).
    ///
    /// # Errors
    /// [`Error::Faer`] if the pattern cannot be allocated.
    pub fn scalar(mesh: &SimplexMesh<D>) -> Result<Self> {
        Self::with_components(mesh)
    }

    /// Scalar stiffness `K_{ij} = ∫ μ ∇φ_i·∇φ_j dx` (μ in Pa: the antiplane shear
    /// modulus; the energy is `½ uᵀKu = ½∫ μ|∇u|²`). Its kernel is the constants.
    ///
    /// # Errors
    /// [`Error::InvalidShearModulus`] unless `mu > 0` and finite; mesh mismatch.
    pub fn laplace(&self, mesh: &SimplexMesh<D>, mu: f64) -> Result<SparseMatrix> {
        if !(mu > 0.0 && mu.is_finite()) {
            return Err(Error::InvalidShearModulus(mu));
        }
        let mut out = self.zeros();
        self.assemble_into(mesh, &mut out, |g, m, loc| p1_laplace::<D>(g, m, mu, loc))?;
        Ok(out)
    }
}

impl<const D: usize, const C: usize> Assembler<D, C> {
    /// Builds the pattern of `mesh` for `C` components per vertex (`1 ≤ C ≤ 3`); see
    /// [`Assembler::new`] (`C = D`) and [`Assembler::scalar`] (`C = 1`).
    ///
    /// # Errors
    /// [`Error::Faer`] if the pattern cannot be allocated.
    pub fn with_components(mesh: &SimplexMesh<D>) -> Result<Self> {
        Self::build(mesh, None)
    }

    /// An assembler of the columns of the nodes with `keep[vertex]` (one flag per vertex of
    /// `mesh`; see "Columns of some nodes" on [`Assembler`]): its matrices are `n × n`
    /// (`n = C · vertices`, node-major), column `C·p + s` holds the whole pattern's rows if
    /// `keep[p]` and nothing otherwise, and every stored entry has the bits of the same
    /// entry of the whole assembly ([`Assembler::with_components`]). Cost `O(cells)` to
    /// find the cells with a kept vertex, then proportional to those.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if `keep` does not have one flag per vertex;
    /// [`Error::Faer`] if the pattern cannot be allocated.
    pub fn on_columns(mesh: &SimplexMesh<D>, keep: &[bool]) -> Result<Self> {
        if keep.len() != mesh.num_vertices() {
            return Err(Error::DimensionMismatch {
                what: "kept columns (one flag per vertex)",
                expected: mesh.num_vertices(),
                got: keep.len(),
            });
        }
        Self::build(mesh, Some(keep))
    }

    /// The pattern of the columns of the nodes `keep` (every node for `None`) and the
    /// scatter map of the cells with a kept vertex.
    fn build(mesh: &SimplexMesh<D>, keep: Option<&[bool]>) -> Result<Self> {
        const { assert!(C >= 1 && C <= 3, "1 to 3 components per vertex") };
        let nv = mesh.num_vertices();
        let nc = mesh.num_cells();
        let k = D + 1;
        let kept = |v: usize| keep.is_none_or(|keep| keep[v]);
        let cells: Option<Vec<usize>> = keep.map(|keep| {
            (0..nc)
                .filter(|&c| mesh.cell(c).iter().any(|&v| keep[v]))
                .collect()
        });
        let visited = || -> Box<dyn Iterator<Item = usize> + '_> {
            match &cells {
                Some(cells) => Box::new(cells.iter().copied()),
                None => Box::new(0..nc),
            }
        };
        // Scalar adjacency of the kept columns by bucketing (with duplicates), then sort +
        // dedup per column.
        let mut count = vec![0usize; nv + 1];
        for c in visited() {
            for &v in mesh.cell(c) {
                if kept(v) {
                    count[v + 1] += k;
                }
            }
        }
        for i in 0..nv {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let mut rows = vec![0usize; count[nv]];
        for c in visited() {
            let cell = mesh.cell(c);
            for &vb in cell.iter().filter(|&&vb| kept(vb)) {
                for &va in cell {
                    rows[fill[vb]] = va;
                    fill[vb] += 1;
                }
            }
        }
        let mut scol = vec![0usize; nv + 1];
        let mut w = 0;
        for q in 0..nv {
            let (s, e) = (count[q], count[q + 1]);
            rows[s..e].sort_unstable();
            let start = w;
            let mut last = usize::MAX;
            for i in s..e {
                if rows[i] != last {
                    last = rows[i];
                    rows[w] = last;
                    w += 1;
                }
            }
            scol[q] = start;
            scol[q + 1] = w;
        }
        rows.truncate(w);
        let num_visited = cells.as_ref().map_or(nc, Vec::len);
        let mut local_offset = Vec::with_capacity(num_visited * k * k);
        for c in visited() {
            let cell = mesh.cell(c);
            for &va in cell {
                for &vb in cell {
                    if !kept(vb) {
                        local_offset.push(u32::MAX);
                        continue;
                    }
                    let col = &rows[scol[vb]..scol[vb + 1]];
                    let o = col.binary_search(&va).expect("pair is in the pattern");
                    local_offset.push(o as u32);
                }
            }
        }
        // Vector pattern: column (q, s) holds rows (p, r) for p adjacent to q, r = 0..C
        // (none for a node not kept).
        let n = C * nv;
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(C * C * rows.len());
        col_ptr.push(0);
        for q in 0..nv {
            for _s in 0..C {
                for &p in &rows[scol[q]..scol[q + 1]] {
                    for r in 0..C {
                        row_idx.push(C * p + r);
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        Ok(Self {
            num_vertices: nv,
            num_cells: nc,
            symbolic,
            columns: keep.map(<[bool]>::to_vec),
            cells,
            local_offset,
        })
    }

    /// The kept nodes (one flag per vertex) of an assembler of some columns
    /// ([`Assembler::on_columns`]); `None` for the whole assembly.
    pub fn columns(&self) -> Option<&[bool]> {
        self.columns.as_deref()
    }

    /// Number of dofs `C · num_vertices`.
    pub fn num_dofs(&self) -> usize {
        C * self.num_vertices
    }
    /// The shared symbolic pattern.
    pub fn pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.symbolic.as_ref()
    }
    /// A matrix with the shared pattern and all values zero.
    pub fn zeros(&self) -> SparseMatrix {
        let nnz = self.symbolic.row_idx().len();
        SparseColMat::new(self.symbolic.clone(), vec![0.0; nnz])
    }

    fn check_mesh(&self, mesh: &SimplexMesh<D>) -> Result<()> {
        check_len("assembler vertices", self.num_vertices, mesh.num_vertices())?;
        check_len("assembler cells", self.num_cells, mesh.num_cells())
    }

    /// Generic numeric assembly: zeroes `out` (which must have this assembler's pattern,
    /// e.g. from [`Assembler::zeros`]) and adds `element(grads, measure, local)` for
    /// every cell, where `local` is the row-major `(C(D+1))²` element matrix to fill
    /// (see [`crate::element`]). An assembler of some columns ([`Assembler::on_columns`])
    /// visits only the cells with a kept vertex and fills only the kept columns.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if `mesh` or `out` do not match the assembler.
    pub fn assemble_into(
        &self,
        mesh: &SimplexMesh<D>,
        out: &mut SparseMatrix,
        mut element: impl FnMut(&[[f64; D]; 4], f64, &mut [f64]),
    ) -> Result<()> {
        self.assemble_cells_into(mesh, out, |_, g, m, local| element(g, m, local))
    }

    /// As [`Assembler::assemble_into`] with the cell's index passed to the element:
    /// `element(cell, grads, measure, local)`, e.g. for a material that changes from cell
    /// to cell (regions of a heterogeneous body). Cells are visited in increasing index
    /// (only those with a kept vertex for [`Assembler::on_columns`]).
    ///
    /// # Errors
    /// As [`Assembler::assemble_into`].
    pub fn assemble_cells_into(
        &self,
        mesh: &SimplexMesh<D>,
        out: &mut SparseMatrix,
        mut element: impl FnMut(usize, &[[f64; D]; 4], f64, &mut [f64]),
    ) -> Result<()> {
        self.check_mesh(mesh)?;
        if out.symbolic().row_idx().len() != self.symbolic.row_idx().len()
            || out.nrows() != self.num_dofs()
            || out.symbolic().col_ptr() != self.symbolic.col_ptr()
        {
            return Err(Error::PatternMismatch);
        }
        let k = D + 1;
        let n = C * k;
        let col_ptr = self.symbolic.col_ptr();
        let vals = out.val_mut();
        vals.fill(0.0);
        let mut local = [0.0f64; 144];
        let local = &mut local[..n * n];
        let visited: &mut dyn Iterator<Item = usize> = match &self.cells {
            Some(cells) => &mut cells.iter().copied(),
            None => &mut (0..self.num_cells),
        };
        for (i, c) in visited.enumerate() {
            let x = mesh.cell_coords(c);
            let (g, m) = p1_gradients::<D>(&x[..k]).expect("mesh cells are non-degenerate");
            element(c, &g, m, local);
            let cell = mesh.cell(c);
            let offs = &self.local_offset[i * k * k..(i + 1) * k * k];
            for a in 0..k {
                for b in 0..k {
                    let o = offs[a * k + b];
                    if o == u32::MAX {
                        // Column of a node not kept.
                        continue;
                    }
                    let o = o as usize;
                    for s in 0..C {
                        let base = col_ptr[C * cell[b] + s] + C * o;
                        for r in 0..C {
                            vals[base + r] += local[(C * a + r) * n + C * b + s];
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Consistent mass matrix `M_{ij} = ∫ ρ φ_i·φ_j dx` (`ρ` in kg/m³ in 3D, kg/m² in 2D;
    /// element matrix `ρ|T|(1 + δ_ab)/((D+1)(D+2))` per component, i.e. `/12` for
    /// triangles and `/20` for tetrahedra, docs/math.md §10), for any component count.
    ///
    /// # Errors
    /// [`Error::InvalidDensity`] unless `rho > 0` and finite; mesh mismatch.
    pub fn mass(&self, mesh: &SimplexMesh<D>, rho: f64) -> Result<SparseMatrix> {
        self.mass_by_cell(mesh, |_| rho)
    }

    /// As [`Assembler::mass`] with the density `rho(cell)` of every cell (a body of
    /// several materials).
    ///
    /// # Errors
    /// [`Error::InvalidDensity`] for the first cell whose density is not positive and
    /// finite; mesh mismatch.
    pub fn mass_by_cell(
        &self,
        mesh: &SimplexMesh<D>,
        rho: impl Fn(usize) -> f64,
    ) -> Result<SparseMatrix> {
        (0..mesh.num_cells()).try_for_each(|c| check_density(rho(c)))?;
        let mut out = self.zeros();
        if C == D {
            // The vector path, unchanged (bit-identical trajectories).
            self.assemble_cells_into(mesh, &mut out, |c, _, m, loc| p1_mass::<D>(m, rho(c), loc))?;
        } else {
            self.assemble_cells_into(mesh, &mut out, |c, _, m, loc| {
                p1_mass_components::<D, C>(m, rho(c), loc)
            })?;
        }
        Ok(out)
    }
}

impl<const D: usize> Assembler<D> {
    /// Stiffness matrix `K_{ij} = ∫ Cε(φ_j):ε(φ_i) dx` of linear elasticity.
    ///
    /// # Errors
    /// Mesh mismatch.
    pub fn stiffness(&self, mesh: &SimplexMesh<D>, mat: &LinearElasticity) -> Result<SparseMatrix> {
        self.stiffness_by_cell(mesh, |_| mat)
    }

    /// As [`Assembler::stiffness`] with the elasticity tensor `mat(cell)` of every cell.
    ///
    /// # Errors
    /// Mesh mismatch.
    pub fn stiffness_by_cell<'m>(
        &self,
        mesh: &SimplexMesh<D>,
        mat: impl Fn(usize) -> &'m LinearElasticity,
    ) -> Result<SparseMatrix> {
        let mut out = self.zeros();
        self.assemble_cells_into(mesh, &mut out, |c, g, m, loc| {
            p1_stiffness::<D>(g, m, mat(c), loc)
        })?;
        Ok(out)
    }

    /// Energy-norm matrix `K + M` (docs/math.md §3: ‖v‖² = vᵀ(K + M)v).
    ///
    /// # Errors
    /// [`Error::InvalidDensity`]; mesh mismatch.
    pub fn energy(
        &self,
        mesh: &SimplexMesh<D>,
        rho: f64,
        mat: &LinearElasticity,
    ) -> Result<SparseMatrix> {
        self.energy_by_cell(mesh, |_| (rho, mat))
    }

    /// As [`Assembler::energy`] with the density and elasticity tensor
    /// `material(cell)` of every cell.
    ///
    /// # Errors
    /// [`Error::InvalidDensity`] for the first cell whose density is not positive and
    /// finite; mesh mismatch.
    pub fn energy_by_cell<'m>(
        &self,
        mesh: &SimplexMesh<D>,
        material: impl Fn(usize) -> (f64, &'m LinearElasticity),
    ) -> Result<SparseMatrix> {
        (0..mesh.num_cells()).try_for_each(|c| check_density(material(c).0))?;
        let mut out = self.zeros();
        let mut tmp = [0.0f64; 144];
        self.assemble_cells_into(mesh, &mut out, |c, g, m, loc| {
            let (rho, mat) = material(c);
            let tmp = &mut tmp[..loc.len()];
            p1_mass::<D>(m, rho, tmp);
            p1_stiffness::<D>(g, m, mat, loc);
            for (l, t) in loc.iter_mut().zip(tmp.iter()) {
                *l += t;
            }
        })?;
        Ok(out)
    }
}

fn check_density(rho: f64) -> Result<()> {
    if rho > 0.0 && rho.is_finite() {
        Ok(())
    } else {
        Err(Error::InvalidDensity(rho))
    }
}

/// The columns of the kept nodes of a node-major matrix `a` (`C = a.ncols() / keep.len()`
/// columns per node; `keep` one flag per node): the same `nrows × ncols` shape, column
/// `C·p + s` as in `a` (rows and bits) if `keep[p]`, empty otherwise. What
/// [`Assembler::on_columns`] gives without assembling the other columns, for a matrix
/// assembled whole.
///
/// # Errors
/// [`Error::DimensionMismatch`] unless `a.ncols()` is a multiple of `keep.len()` (and
/// `keep` is not empty for a matrix with columns).
pub fn node_columns(a: &SparseMatrix, keep: &[bool]) -> Result<SparseMatrix> {
    let n = a.ncols();
    let c = if keep.is_empty() { 0 } else { n / keep.len() };
    if c * keep.len() != n || (n > 0 && c == 0) {
        return Err(Error::DimensionMismatch {
            what: "columns of a node-major matrix (components times kept-node flags)",
            expected: keep.len() * c.max(1),
            got: n,
        });
    }
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let (mut row_idx, mut val) = (Vec::new(), Vec::new());
    for j in 0..n {
        if keep[j / c] {
            row_idx.extend_from_slice(a.row_idx_of_col_raw(j));
            val.extend_from_slice(a.val_of_col(j));
        }
        col_ptr.push(row_idx.len());
    }
    let symbolic = SymbolicSparseColMat::new_checked(a.nrows(), n, col_ptr, None, row_idx);
    Ok(SparseColMat::new(symbolic, val))
}
