//! Sparse Cholesky (`faer` supernodal/simplicial LLᵀ) with reusable symbolic analysis.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef, SymbolicCholesky};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use crate::{Error, Result};

/// Sparse `A = L Lᵀ` factorisation of a symmetric positive definite CSC matrix.
///
/// The symbolic analysis (AMD ordering, elimination tree, supernodes) is done once by
/// [`Cholesky::analyze`]; [`Cholesky::factorize`] recomputes the numeric factor for new
/// values on the same pattern, reusing all buffers; [`Cholesky::solve_in_place`] solves
/// without allocating. Only the lower triangle of `A` is read (rsf matrices store both).
pub struct Cholesky {
    symbolic: SymbolicCholesky<usize>,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    l_values: Vec<f64>,
    factor_mem: MemBuffer,
    solve_mem: MemBuffer,
    factorized: bool,
}

impl std::fmt::Debug for Cholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Cholesky")
            .field("dim", &self.dim())
            .field("factor_nnz", &self.l_values.len())
            .field("factorized", &self.factorized)
            .finish()
    }
}

fn faer_err(e: impl std::fmt::Debug) -> Error {
    Error::Faer(format!("{e:?}"))
}

impl Cholesky {
    /// Symbolic analysis of a square pattern.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for a non-square pattern; [`Error::Faer`] on allocation failure.
    pub fn analyze(pattern: SymbolicSparseColMatRef<'_, usize>) -> Result<Self> {
        if pattern.nrows() != pattern.ncols() {
            return Err(Error::DimensionMismatch {
                what: "Cholesky: square matrix",
                expected: pattern.nrows(),
                got: pattern.ncols(),
            });
        }
        let symbolic = factorize_symbolic_cholesky(
            pattern,
            Side::Lower,
            Default::default(),
            Default::default(),
        )
        .map_err(faer_err)?;
        let factor_req: StackReq =
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
        let solve_req = symbolic.solve_in_place_scratch::<f64>(1, Par::Seq);
        let factor_mem = MemBuffer::try_new(factor_req).map_err(faer_err)?;
        let solve_mem = MemBuffer::try_new(solve_req).map_err(faer_err)?;
        let l_values = vec![0.0; symbolic.len_val()];
        Ok(Self {
            symbolic,
            col_ptr: pattern.col_ptr().to_vec(),
            row_idx: pattern.row_idx().to_vec(),
            l_values,
            factor_mem,
            solve_mem,
            factorized: false,
        })
    }

    /// Analysis and numeric factorisation in one call.
    ///
    /// # Errors
    /// As [`Cholesky::analyze`] and [`Cholesky::factorize`].
    pub fn new(a: SparseColMatRef<'_, usize, f64>) -> Result<Self> {
        let mut c = Self::analyze(a.symbolic())?;
        c.factorize(a)?;
        Ok(c)
    }

    /// Dimension `n` of the factorised matrix.
    pub fn dim(&self) -> usize {
        self.col_ptr.len() - 1
    }

    /// Numeric factorisation of `a`, which must have exactly the analysed pattern.
    ///
    /// # Errors
    /// [`Error::PatternMismatch`] if the pattern differs;
    /// [`Error::NotPositiveDefinite`] if a pivot is not positive.
    pub fn factorize(&mut self, a: SparseColMatRef<'_, usize, f64>) -> Result<()> {
        if a.symbolic().col_ptr() != self.col_ptr.as_slice()
            || a.symbolic().row_idx() != self.row_idx.as_slice()
            || a.symbolic().col_nnz().is_some()
        {
            return Err(Error::PatternMismatch);
        }
        self.factorized = false;
        let stack = MemStack::new(&mut self.factor_mem);
        self.symbolic
            .factorize_numeric_llt::<f64>(
                &mut self.l_values,
                a,
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                stack,
                Default::default(),
            )
            .map_err(|e| Error::NotPositiveDefinite {
                detail: format!(": {e:?}"),
            })?;
        self.factorized = true;
        Ok(())
    }

    /// Solves `A x = rhs` in place.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if `rhs.len() != dim()`;
    /// [`Error::NotPositiveDefinite`] if there is no valid factorisation.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<()> {
        let n = self.dim();
        if rhs.len() != n {
            return Err(Error::DimensionMismatch {
                what: "Cholesky right-hand side",
                expected: n,
                got: rhs.len(),
            });
        }
        if !self.factorized {
            return Err(Error::NotPositiveDefinite {
                detail: ": no valid numeric factorisation".into(),
            });
        }
        let stack = MemStack::new(&mut self.solve_mem);
        LltRef::<'_, usize, f64>::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            Par::Seq,
            stack,
        );
        Ok(())
    }

    /// Solves `A x = rhs`, returning `x`.
    ///
    /// # Errors
    /// As [`Cholesky::solve_in_place`].
    pub fn solve(&mut self, rhs: &[f64]) -> Result<Vec<f64>> {
        let mut x = rhs.to_vec();
        self.solve_in_place(&mut x)?;
        Ok(x)
    }

    /// Number of stored values of the factor `L`.
    pub fn factor_nnz(&self) -> usize {
        self.l_values.len()
    }
}
