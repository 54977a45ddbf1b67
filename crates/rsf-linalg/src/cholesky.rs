//! Sparse Cholesky (`faer` supernodal/simplicial LLᵀ) with a reusable symbolic analysis.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use crate::error::{faer_err, Error, ProblemError, Result};

/// The fill-reducing ordering of a [`Cholesky`] analysis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FillOrdering {
    /// AMD on the graph of *supervariables* (runs of consecutive columns with identical
    /// row patterns, i.e. the `D` components of a node), expanded back to the dofs. For
    /// node-major vector fields the graph is `D²` times smaller than the dof graph, which
    /// makes the analysis several times faster than plain AMD. The default.
    #[default]
    GroupedAmd,
    /// faer's approximate minimum degree ordering of the dof graph.
    Amd,
}

/// Sparse `A = L Lᵀ` factorisation of a symmetric positive definite CSC matrix.
///
/// The symbolic analysis (fill-reducing ordering, elimination tree, supernodes) is done
/// once by [`Cholesky::analyze`] (or [`Cholesky::analyze_with`]);
/// [`Cholesky::factorize`] and [`Cholesky::factorize_values`] recompute the numeric
/// factor for new values on the same pattern without allocating, and
/// [`Cholesky::solve_in_place`] solves without allocating. Only the lower triangle of `A`
/// is read (rsf matrices store both). Single-threaded (`Par::Seq`), so results are
/// bit-for-bit reproducible.
pub struct Cholesky {
    symbolic: SymbolicCholesky<usize>,
    pattern: SymbolicSparseColMat<usize>,
    l_values: Vec<f64>,
    /// Scratch of the numeric factorisation and of the solves (the larger of the two).
    buffer: MemBuffer,
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

/// [`FillOrdering::GroupedAmd`]: the permutation and its inverse.
fn grouped_amd(pattern: SymbolicSparseColMatRef<'_, usize>) -> Result<(Vec<usize>, Vec<usize>)> {
    let n = pattern.ncols();
    let cp = pattern.col_ptr();
    let ri = pattern.row_idx();
    let col = |j: usize| -> &[usize] {
        match pattern.col_nnz() {
            Some(nnz) => &ri[cp[j]..cp[j] + nnz[j]],
            None => &ri[cp[j]..cp[j + 1]],
        }
    };
    // group_start[g]..group_start[g+1]: the columns of group g.
    let mut group_of = vec![0usize; n];
    let mut group_start = Vec::with_capacity(n + 1);
    for j in 0..n {
        if j == 0 || col(j) != col(*group_start.last().expect("nonempty")) {
            group_start.push(j);
        }
        group_of[j] = group_start.len() - 1;
    }
    let ng = group_start.len();
    group_start.push(n);
    let mut gcp = Vec::with_capacity(ng + 1);
    let mut gri = Vec::with_capacity(ri.len() / ((n / ng.max(1)).max(1)).pow(2) + ng);
    gcp.push(0);
    for g in 0..ng {
        let mut last = usize::MAX;
        let mut sorted = true;
        let start = gri.len();
        for &i in col(group_start[g]) {
            let gi = group_of[i];
            if gi != last {
                if last != usize::MAX && gi < last {
                    sorted = false;
                }
                gri.push(gi);
                last = gi;
            }
        }
        if !sorted {
            gri[start..].sort_unstable();
            let mut w = start;
            for r in start..gri.len() {
                if r == start || gri[r] != gri[w - 1] {
                    gri[w] = gri[r];
                    w += 1;
                }
            }
            gri.truncate(w);
        }
        gcp.push(gri.len());
    }
    let gpat = faer::sparse::SymbolicSparseColMat::new_checked(ng, ng, gcp, None, gri);
    let mut gperm = vec![0usize; ng];
    let mut gperm_inv = vec![0usize; ng];
    let nnz = gpat.row_idx().len();
    let mut mem = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(ng, nnz))
        .map_err(faer_err)?;
    amd::order_maybe_unsorted(
        &mut gperm,
        &mut gperm_inv,
        gpat.as_ref(),
        Default::default(),
        MemStack::new(&mut mem),
    )
    .map_err(faer_err)?;
    let mut fwd = Vec::with_capacity(n);
    for &g in &gperm {
        fwd.extend(group_start[g]..group_start[g + 1]);
    }
    let mut inv = vec![0usize; n];
    for (k, &j) in fwd.iter().enumerate() {
        inv[j] = k;
    }
    Ok((fwd, inv))
}

impl Cholesky {
    /// Symbolic analysis of a square pattern with the default ordering
    /// ([`FillOrdering::GroupedAmd`]).
    ///
    /// # Errors
    /// As [`Cholesky::analyze_with`].
    pub fn analyze(pattern: SymbolicSparseColMatRef<'_, usize>) -> Result<Self> {
        Self::analyze_with(pattern, FillOrdering::GroupedAmd)
    }

    /// Symbolic analysis of a square pattern (both triangles or the lower one; row indices
    /// sorted per column) with the given fill-reducing ordering.
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] for a non-square pattern; [`Error::Faer`] when faer's
    /// analysis fails (e.g. on allocation failure).
    pub fn analyze_with(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        ordering: FillOrdering,
    ) -> Result<Self> {
        ProblemError::check_length("Cholesky: square matrix", pattern.nrows(), pattern.ncols())?;
        let symbolic = match ordering {
            FillOrdering::GroupedAmd => {
                let (fwd, inv) = grouped_amd(pattern)?;
                factorize_symbolic_cholesky(
                    pattern,
                    Side::Lower,
                    SymmetricOrdering::Custom(PermRef::new_checked(&fwd, &inv, fwd.len())),
                    CholeskySymbolicParams::default(),
                )
            }
            FillOrdering::Amd => factorize_symbolic_cholesky(
                pattern,
                Side::Lower,
                SymmetricOrdering::Amd,
                CholeskySymbolicParams::default(),
            ),
        }
        .map_err(faer_err)?;
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        let buffer = MemBuffer::try_new(req).map_err(faer_err)?;
        // The factor, the largest allocation of a 3-D model's build: fallible.
        let l_values = crate::try_filled("a sparse Cholesky factor", symbolic.len_val(), 0.0)?;
        Ok(Self {
            symbolic,
            pattern: pattern.to_owned().map_err(faer_err)?,
            l_values,
            buffer,
            factorized: false,
        })
    }

    /// Analysis ([`FillOrdering::GroupedAmd`]) and numeric factorisation in one call.
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
        self.pattern.ncols()
    }

    /// Numeric factorisation of `a`, which must have exactly the analysed pattern (checked,
    /// `O(nnz)`).
    ///
    /// # Errors
    /// [`Error::PatternMismatch`] if the pattern differs;
    /// [`Error::NotPositiveDefinite`] if a pivot is not positive.
    pub fn factorize(&mut self, a: SparseColMatRef<'_, usize, f64>) -> Result<()> {
        if a.symbolic().col_ptr() != self.pattern.col_ptr()
            || a.symbolic().row_idx() != self.pattern.row_idx()
            || a.symbolic().col_nnz().is_some()
        {
            return Err(Error::PatternMismatch);
        }
        self.factorized = false;
        numeric_llt(&self.symbolic, &mut self.l_values, &mut self.buffer, a)?;
        self.factorized = true;
        Ok(())
    }

    /// Numeric factorisation of the matrix with the analysed pattern and these values
    /// (`values[k]` belongs to the k-th stored entry of the pattern); nothing is checked
    /// but the length, so this is the refactorisation of a hot loop.
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] if `values.len()` differs from the pattern's number of
    /// entries; [`Error::NotPositiveDefinite`] if a pivot is not positive.
    pub fn factorize_values(&mut self, values: &[f64]) -> Result<()> {
        let nnz = self.pattern.row_idx().len();
        ProblemError::check_length("Cholesky values", nnz, values.len())?;
        self.factorized = false;
        let a = SparseColMatRef::new(self.pattern.as_ref(), values);
        numeric_llt(&self.symbolic, &mut self.l_values, &mut self.buffer, a)?;
        self.factorized = true;
        Ok(())
    }

    /// Solves `A x = rhs` in place with the last successful factorisation.
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] if `rhs.len() != dim()`;
    /// [`Error::NotPositiveDefinite`] if there is no valid factorisation.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<()> {
        let n = self.dim();
        ProblemError::check_length("Cholesky right-hand side", n, rhs.len())?;
        if !self.factorized {
            return Err(Error::NotPositiveDefinite {
                detail: ": no valid numeric factorisation".into(),
            });
        }
        let stack = MemStack::new(&mut self.buffer);
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

/// The numeric factorisation into `l_values` (faer's supernodal or simplicial LLᵀ).
fn numeric_llt(
    symbolic: &SymbolicCholesky<usize>,
    l_values: &mut [f64],
    buffer: &mut MemBuffer,
    a: SparseColMatRef<'_, usize, f64>,
) -> Result<()> {
    symbolic
        .factorize_numeric_llt::<f64>(
            l_values,
            a,
            Side::Lower,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(buffer),
            Default::default(),
        )
        .map(|_| ())
        .map_err(|e| Error::NotPositiveDefinite {
            detail: format!(": {e:?}"),
        })
}
