//! The coarsest level of a multigrid hierarchy: a sparse Cholesky factorisation of its
//! node-block matrix with the masked dofs' rows and columns replaced by the identity, and
//! the solve of the masked right-hand side — one code for the one-process multigrid and the
//! distributed V-cycle (which solves the gathered coarsest problem on every rank).

use faer::sparse::SymbolicSparseColMatRef;
use rsf_linalg::{Cholesky, Csc, FillOrdering};

use crate::error::{Error, Result};
use rsf_nonsmooth::ProblemError;
use rsf_ranks::bsr::BlockCsr;

/// The coarsest-level solver: the pattern analysed once (AMD ordering), the values
/// factorised after every change of the matrix or its mask.
#[derive(Debug)]
pub(crate) struct CoarseSolver {
    cholesky: Cholesky,
    /// The coarsest matrix as CSC (dense blocks) and where each entry comes from.
    csc: Csc,
    map: Vec<usize>,
}

/// Whether a coarse dof with Galerkin diagonal `d` is excluded from smoothing and the
/// coarse solve: all of its fine support is truncated (an exactly zero row) or round-off
/// left a non-positive diagonal.
pub(crate) fn excluded(d: f64) -> bool {
    !(d > 0.0)
}

impl CoarseSolver {
    /// The symbolic analysis of `a`'s pattern.
    ///
    /// # Errors
    /// [`Error::Factorisation`] if the analysis fails.
    pub fn new<const D: usize>(a: &BlockCsr<D>) -> Result<Self> {
        let (csc, map) = a.csc_pattern();
        let pattern = SymbolicSparseColMatRef::new_checked(
            csc.nrows,
            csc.nrows,
            &csc.col_ptr,
            None,
            &csc.row_idx,
        );
        let cholesky = Cholesky::analyze_with(pattern, FillOrdering::Amd)
            .map_err(|e| Error::Factorisation(e.to_string()))?;
        Ok(Self { cholesky, csc, map })
    }

    /// Factorises the values of `a` (the matrix of [`new`](Self::new)'s pattern) with the
    /// rows and columns of the dofs of `mask` replaced by the identity.
    ///
    /// # Errors
    /// [`ProblemError::NotPositiveDefinite`] if the factorisation fails even after a relative
    /// diagonal shift of `1e-10`.
    pub fn factorize<const D: usize>(&mut self, a: &BlockCsr<D>, mask: &[bool]) -> Result<()> {
        let m = &mut self.csc;
        for j in 0..m.ncols {
            for k in m.col_ptr[j]..m.col_ptr[j + 1] {
                let i = m.row_idx[k];
                m.val[k] = if mask[i] || mask[j] {
                    if i == j {
                        1.0
                    } else {
                        0.0
                    }
                } else {
                    a.flat_value(self.map[k])
                };
            }
        }
        match self.cholesky.factorize_values(&m.val) {
            Ok(()) => Ok(()),
            Err(_) => {
                // Truncation can make the truncated prolongation P_t rank deficient, and then
                // P_tᵀ H P_t is only semidefinite. Its kernel is ker P_t: coarse vectors that
                // prolongate to zero, so any component there is harmless. A relative diagonal
                // shift makes the factorisation well defined without changing P_t x_c.
                for j in 0..m.ncols {
                    for k in m.col_ptr[j]..m.col_ptr[j + 1] {
                        if m.row_idx[k] == j && !mask[j] {
                            m.val[k] *= 1.0 + 1e-10;
                            m.val[k] += f64::MIN_POSITIVE;
                        }
                    }
                }
                self.cholesky.factorize_values(&m.val).map_err(|_| {
                    Error::Problem(ProblemError::NotPositiveDefinite("Cholesky factorisation"))
                })
            }
        }
    }

    /// The coarsest solve: `x` holds the right-hand side on entry; it is multiplied by
    /// `free` (1 on free dofs, 0 on masked ones) and overwritten by the solution of the
    /// last factorisation. One thread, a fixed order: the same bits wherever it runs.
    ///
    /// # Panics
    /// If there is no factorisation or a length is not the matrix's dimension.
    pub fn solve(&mut self, x: &mut [f64], free: &[f64]) {
        assert_eq!(x.len(), free.len(), "one mask factor per dof");
        for (x, &f) in x.iter_mut().zip(free) {
            *x *= f;
        }
        self.cholesky
            .solve_in_place(x)
            .expect("the coarse factorisation succeeded before a solve");
    }
}
