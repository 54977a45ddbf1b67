//! Fixed dofs (Dirichlet values, bilateral contact) and the reduced SPD system.

use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat};

use crate::{Error, Result};
use rsf_linalg::Cholesky;

/// Fixed components of nodes (node-major, `D` per node) with their prescribed values.
///
/// Dirichlet on Γ_D fixes all components; bilateral contact on Γ_F fixes the normal
/// component, which is component `D − 1` **in the nodal frame** of
/// [`BoundarySegment::frames`](crate::BoundarySegment::frames) (for the paper's
/// horizontal Γ_F the frames are the identity, so it is the Cartesian `y` component).
#[derive(Debug, Clone, PartialEq)]
pub struct Constraints<const D: usize> {
    fixed: Vec<bool>,
    values: Vec<f64>,
}

impl<const D: usize> Constraints<D> {
    /// No fixed dofs on a mesh with `num_vertices` vertices.
    pub fn new(num_vertices: usize) -> Self {
        Self {
            fixed: vec![false; D * num_vertices],
            values: vec![0.0; D * num_vertices],
        }
    }
    /// Fixes component `component` of `node` to `value`.
    ///
    /// # Errors
    /// [`Error::InvalidDof`] if out of range; [`Error::NonFiniteValue`] for a non-finite value.
    pub fn fix(&mut self, node: usize, component: usize, value: f64) -> Result<()> {
        if component >= D || D * node + component >= self.fixed.len() {
            return Err(Error::InvalidDof { node, component });
        }
        if !value.is_finite() {
            return Err(Error::NonFiniteValue("constraint value"));
        }
        self.fixed[D * node + component] = true;
        self.values[D * node + component] = value;
        Ok(())
    }
    /// Fixes the listed `components` of every node in `nodes` to `value[component]`.
    ///
    /// # Errors
    /// As [`Constraints::fix`].
    pub fn fix_nodes(
        &mut self,
        nodes: &[usize],
        components: &[usize],
        value: [f64; D],
    ) -> Result<()> {
        for &n in nodes {
            for &c in components {
                if c >= D {
                    return Err(Error::InvalidDof {
                        node: n,
                        component: c,
                    });
                }
                self.fix(n, c, value[c])?;
            }
        }
        Ok(())
    }
    /// The mask `fixed[D·node + component]` (design.md contract).
    pub fn fixed(&self) -> &[bool] {
        &self.fixed
    }
    /// Prescribed values (0 on free dofs).
    pub fn values(&self) -> &[f64] {
        &self.values
    }
    /// Mutable prescribed values, e.g. for a time-dependent Dirichlet velocity.
    pub fn values_mut(&mut self) -> &mut [f64] {
        &mut self.values
    }
    /// Number of dofs.
    pub fn num_dofs(&self) -> usize {
        self.fixed.len()
    }
    /// Number of free dofs.
    pub fn num_free(&self) -> usize {
        self.fixed.iter().filter(|f| !**f).count()
    }
    /// Writes the prescribed values into the fixed entries of `x`.
    ///
    /// # Panics
    /// If `x.len() != num_dofs()`.
    pub fn apply(&self, x: &mut [f64]) {
        assert_eq!(x.len(), self.fixed.len());
        for ((x, &f), &v) in x.iter_mut().zip(&self.fixed).zip(&self.values) {
            if f {
                *x = v;
            }
        }
    }
}

/// The reduced system `A_ff x_f = b_f − A_fc x_c` of a symmetric matrix with fixed dofs,
/// factorised by sparse Cholesky.
///
/// `A_ff` is SPD whenever the fixed dofs remove the kernel of `A` (e.g. `K` with
/// Dirichlet conditions on a boundary part of positive length, or any `A` with a mass
/// contribution). The reduced pattern and its symbolic analysis are built once;
/// [`ConstrainedSystem::refactorize`] takes new values on the same pattern (e.g. when τ
/// changes in `A = c_M M + c_K K`).
#[derive(Debug)]
pub struct ConstrainedSystem {
    n: usize,
    fixed: Vec<bool>,
    free: Vec<usize>,
    /// Position in `A`'s value array of every reduced entry.
    reduced_src: Vec<usize>,
    reduced: SparseColMat<usize, f64>,
    /// Coupling entries `(free row, fixed column, position in A's values)`.
    coupling: Vec<(usize, usize, usize)>,
    coupling_val: Vec<f64>,
    chol: Cholesky,
    work: Vec<f64>,
}

impl ConstrainedSystem {
    /// Extracts `A_ff`, analyses and factorises it.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if `fixed.len()` differs from `A`'s size;
    /// [`Error::NotPositiveDefinite`] if `A_ff` is not SPD.
    pub fn new(a: SparseColMatRef<'_, usize, f64>, fixed: &[bool]) -> Result<Self> {
        let n = a.nrows();
        if a.ncols() != n || fixed.len() != n {
            return Err(Error::DimensionMismatch {
                what: "constrained system",
                expected: n,
                got: fixed.len(),
            });
        }
        let mut index = vec![usize::MAX; n];
        let free: Vec<usize> = (0..n).filter(|&i| !fixed[i]).collect();
        for (k, &i) in free.iter().enumerate() {
            index[i] = k;
        }
        let mut col_ptr = Vec::with_capacity(free.len() + 1);
        let mut row_idx = Vec::new();
        let mut reduced_src = Vec::new();
        let mut coupling = Vec::new();
        col_ptr.push(0);
        let cp = a.symbolic().col_ptr();
        for j in 0..n {
            let start = cp[j];
            for (k, &i) in a.row_idx_of_col_raw(j).iter().enumerate() {
                if fixed[i] {
                    continue;
                }
                if fixed[j] {
                    coupling.push((index[i], j, start + k));
                } else {
                    row_idx.push(index[i]);
                    reduced_src.push(start + k);
                }
            }
            if !fixed[j] {
                col_ptr.push(row_idx.len());
            }
        }
        let nf = free.len();
        let sym = SymbolicSparseColMat::new_checked(nf, nf, col_ptr, None, row_idx);
        let vals = reduced_src.iter().map(|&s| a.val()[s]).collect();
        let reduced = SparseColMat::new(sym, vals);
        let mut chol = Cholesky::analyze(reduced.symbolic())?;
        chol.factorize(reduced.as_ref())?;
        let coupling_val = coupling.iter().map(|&(_, _, s)| a.val()[s]).collect();
        Ok(Self {
            n,
            fixed: fixed.to_vec(),
            free,
            reduced_src,
            reduced,
            coupling,
            coupling_val,
            chol,
            work: vec![0.0; nf],
        })
    }

    /// New values of `A` on the same pattern as at construction.
    ///
    /// # Errors
    /// [`Error::PatternMismatch`] if `a` has a different number of stored entries or size;
    /// [`Error::NotPositiveDefinite`].
    pub fn refactorize(&mut self, a: SparseColMatRef<'_, usize, f64>) -> Result<()> {
        let expected = self.reduced_src.len() + self.coupling.len();
        if a.nrows() != self.n || a.val().len() < expected {
            return Err(Error::PatternMismatch);
        }
        let av = a.val();
        for (d, &s) in self.reduced.val_mut().iter_mut().zip(&self.reduced_src) {
            *d = av[s];
        }
        for (d, &(_, _, s)) in self.coupling_val.iter_mut().zip(&self.coupling) {
            *d = av[s];
        }
        Ok(self.chol.factorize(self.reduced.as_ref())?)
    }

    /// Solves `A x = b` on the free dofs: on entry the fixed entries of `x` hold the
    /// prescribed values (its free entries are ignored); on exit the free entries solve
    /// `A_ff x_f = b_f − A_fc x_c`. No allocation.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if `b` or `x` have the wrong length.
    pub fn solve(&mut self, b: &[f64], x: &mut [f64]) -> Result<()> {
        if b.len() != self.n || x.len() != self.n {
            return Err(Error::DimensionMismatch {
                what: "constrained solve vectors",
                expected: self.n,
                got: b.len().min(x.len()),
            });
        }
        for (w, &i) in self.work.iter_mut().zip(&self.free) {
            *w = b[i];
        }
        for (&(r, j, _), &v) in self.coupling.iter().zip(&self.coupling_val) {
            self.work[r] -= v * x[j];
        }
        self.chol.solve_in_place(&mut self.work)?;
        for (&w, &i) in self.work.iter().zip(&self.free) {
            x[i] = w;
        }
        Ok(())
    }

    /// The reduced matrix `A_ff` (free dofs in increasing order).
    pub fn reduced_matrix(&self) -> SparseColMatRef<'_, usize, f64> {
        self.reduced.as_ref()
    }
    /// Free dof indices, increasing.
    pub fn free_dofs(&self) -> &[usize] {
        &self.free
    }
    /// The fixed mask used at construction.
    pub fn fixed(&self) -> &[bool] {
        &self.fixed
    }
    /// The underlying factorisation of `A_ff`.
    pub fn cholesky(&self) -> &Cholesky {
        &self.chol
    }
}
