//! Sparse Cholesky factorisation with a reusable symbolic analysis (faer backend).

use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};

/// `L Lᵀ` factorisation of a symmetric positive definite sparse matrix whose *pattern*
/// is fixed: the symbolic analysis (fill-reducing ordering, elimination tree) is done
/// once in [`SparseCholesky::new`], and [`SparseCholesky::factorize`] recomputes only the
/// numeric factor, without allocating.
///
/// Single-threaded (`Par::Seq`) so that results are bit-for-bit reproducible.
pub struct SparseCholesky {
    symbolic: SymbolicCholesky<usize>,
    pattern: SymbolicSparseColMat<usize>,
    l_values: Vec<f64>,
    buffer: MemBuffer,
    factorized: bool,
}

impl std::fmt::Debug for SparseCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseCholesky")
            .field("dim", &self.dim())
            .field("factor_entries", &self.l_values.len())
            .finish()
    }
}

impl SparseCholesky {
    /// Symbolic analysis of an `n × n` pattern given in CSC form (both triangles or the
    /// lower one; only the lower triangle is read). Row indices must be sorted per column.
    ///
    /// # Errors
    /// [`Error::InvalidMatrix`] for an inconsistent pattern, [`Error::Factorisation`] when
    /// faer's symbolic analysis fails (e.g. out of memory).
    pub fn new(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Result<Self> {
        let pattern =
            SymbolicSparseColMat::new_checked(n, n, col_ptr.to_vec(), None, row_idx.to_vec());
        let symbolic = factorize_symbolic_cholesky(
            pattern.as_ref(),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| Error::Factorisation(format!("{e:?}")))?;
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        let buffer = MemBuffer::try_new(req).map_err(|e| Error::Factorisation(format!("{e:?}")))?;
        let l_values = vec![0.0; symbolic.len_val()];
        Ok(Self {
            symbolic,
            pattern,
            l_values,
            buffer,
            factorized: false,
        })
    }

    /// Dimension of the matrix.
    pub fn dim(&self) -> usize {
        self.pattern.nrows()
    }

    /// Numeric factorisation of the matrix with the analysed pattern and these values
    /// (`values[k]` belongs to the k-th stored entry of the pattern).
    ///
    /// # Errors
    /// [`Error::NotPositiveDefinite`] if the matrix is not numerically SPD.
    ///
    /// # Panics
    /// If `values.len()` differs from the pattern's number of entries.
    pub fn factorize(&mut self, values: &[f64]) -> Result<()> {
        assert_eq!(values.len(), self.pattern.row_idx().len());
        self.factorized = false;
        let mat = SparseColMatRef::new(self.pattern.as_ref(), values);
        let stack = MemStack::new(&mut self.buffer);
        self.symbolic
            .factorize_numeric_llt::<f64>(
                &mut self.l_values,
                mat,
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                stack,
                Default::default(),
            )
            .map_err(|_| Error::NotPositiveDefinite("Cholesky factorisation"))?;
        self.factorized = true;
        Ok(())
    }

    /// Solves `A x = rhs` in place with the last successful factorisation.
    ///
    /// # Panics
    /// If no factorisation succeeded yet or `rhs.len() != dim()`.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        assert!(self.factorized, "solve before a successful factorisation");
        let n = self.dim();
        assert_eq!(rhs.len(), n);
        let llt = LltRef::<'_, usize, f64>::new(&self.symbolic, &self.l_values);
        let stack = MemStack::new(&mut self.buffer);
        let rhs = MatMut::from_column_major_slice_mut(rhs, n, 1);
        llt.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, stack);
    }
}
