//! What the direct solver's set-up will hold, before it runs (for the automatic solver
//! choice by a memory budget).

use faer::sparse::SparseColMatRef;

use super::condensation::split_dofs;
use super::options::{DirectOptions, HARMONIC_BLOCK};
use super::partial_cholesky::PartialCholesky;
use crate::error::Result;
use rsf_linalg::Csc;
use rsf_nonsmooth::BlockedMatrix;

/// The memory of a [`DirectSolver`](super::DirectSolver) set up for a problem, by part
/// (bytes), from [`DirectMemory::estimate`]: the ordering and symbolic factorisation are
/// computed, nothing numeric. The matrices given to the solver (`A`, the energy norm) and
/// the vectors of length `n` are not counted: every solver holds them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DirectMemory {
    /// The sparse factor of `A` on the interior and the interface (8 bytes per stored
    /// entry, supernodal, fill-reducing order as the solver computes it).
    pub factor_bytes: usize,
    /// The dense `|F| × |F|` matrices on the interface: the Schur complement, the Newton
    /// matrix and, with an energy norm, its matrix `N` and factor (2 or 4 of them).
    pub dense_bytes: usize,
    /// The largest temporary of the set-up: the harmonic extension `Z` and `E Z`
    /// (`2 n |F|` values) when they fit in [`DirectOptions::max_extension_bytes`], else one
    /// block of columns per thread and the unsymmetrised `N`; 0 without an energy norm.
    pub extension_bytes: usize,
}

impl DirectMemory {
    /// All parts (bytes): the peak of the set-up, the extension's temporary included.
    pub fn total_bytes(&self) -> usize {
        self.factor_bytes + self.dense_bytes + self.extension_bytes
    }

    /// The memory the direct solver would need for the matrix `a` (`n × n`, symmetric,
    /// both triangles stored; `n` a multiple of `D`) with fixed dofs `fixed` (length `n`),
    /// condensed onto the free components of `blocks` (node indices, strictly
    /// increasing), with (`energy_norm`) or without a stopping norm other than `A`'s
    /// ([`DirectSolver::with_energy_norm`](super::DirectSolver::with_energy_norm)).
    /// Costs the fill-reducing ordering and the symbolic factorisation (a small part of
    /// the set-up: no numeric work).
    ///
    /// # Errors
    /// As [`DirectSolver::new`](super::DirectSolver::new) for the matrix; blocks out of
    /// range or not increasing.
    pub fn estimate<const D: usize>(
        a: SparseColMatRef<'_, usize, f64>,
        fixed: &[bool],
        blocks: &[usize],
        energy_norm: bool,
        opts: &DirectOptions,
    ) -> Result<Self> {
        let BlockedMatrix { a, fixed } = BlockedMatrix::<D>::new(Csc::from_faer(a)?, fixed)?;
        let (interior, interface) = split_dofs::<D>(a.nrows, &fixed, blocks)?;
        let factor_bytes = 8 * PartialCholesky::planned_nnz(&a, &interior, &interface)?;
        let (n, nf) = (interior.len() + interface.len(), interface.len());
        let square = 8 * nf * nf;
        let dense_bytes = if energy_norm { 4 } else { 2 } * square;
        let extension_bytes = if !energy_norm {
            0
        } else if opts.stores_extension(n, nf) {
            2 * 8 * n * nf
        } else {
            // Per thread (at most two): the block's rows of Z and E Z; then N twice.
            2 * 2 * 8 * n * HARMONIC_BLOCK + 2 * square
        };
        Ok(Self {
            factor_bytes,
            dense_bytes,
            extension_bytes,
        })
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::DirectSolver;
    use faer::sparse::{SparseColMat, Triplet};

    /// 5-point Laplacian plus identity on an `m × m` grid (node `i + m j`).
    pub(crate) fn grid(m: usize) -> SparseColMat<usize, f64> {
        let mut t = Vec::new();
        for j in 0..m {
            for i in 0..m {
                let p = i + m * j;
                t.push(Triplet::new(p, p, 5.0));
                for (di, dj) in [(1, 0), (0, 1)] {
                    if i + di < m && j + dj < m {
                        let q = (i + di) + m * (j + dj);
                        t.push(Triplet::new(p, q, -1.0));
                        t.push(Triplet::new(q, p, -1.0));
                    }
                }
            }
        }
        SparseColMat::try_new_from_triplets(m * m, m * m, &t).expect("grid")
    }

    /// The planned factor is the one the set-up computes, entry for entry; the dense and
    /// extension parts follow the solver's rule for the stored and the blocked forms.
    #[test]
    fn estimate_matches_the_factor_the_solver_builds() {
        let m = 30;
        let a = grid(m);
        let mut fixed = vec![false; m * m];
        fixed[..m].fill(true);
        let blocks: Vec<usize> = (m * (m / 2)..m * (m / 2) + m).collect();
        let opts = DirectOptions::default();
        let est = DirectMemory::estimate::<1>(a.as_ref(), &fixed, &blocks, true, &opts).unwrap();
        let mut solver = DirectSolver::<1>::new(a.as_ref(), &fixed, opts.clone()).unwrap();
        solver.prepare(&blocks).unwrap();
        assert!(solver.factor_nnz() > 0);
        assert_eq!(est.factor_bytes, 8 * solver.factor_nnz());
        assert_eq!(est.dense_bytes, 4 * 8 * m * m);
        let n = m * m - m;
        assert_eq!(est.extension_bytes, 2 * 8 * n * m);
        assert_eq!(
            est.total_bytes(),
            est.factor_bytes + est.dense_bytes + est.extension_bytes
        );
        let small = DirectOptions {
            max_extension_bytes: 1,
            ..opts
        };
        let blocked =
            DirectMemory::estimate::<1>(a.as_ref(), &fixed, &blocks, true, &small).unwrap();
        assert_eq!(blocked.factor_bytes, est.factor_bytes);
        assert_eq!(
            blocked.extension_bytes,
            4 * 8 * n * HARMONIC_BLOCK + 2 * 8 * m * m
        );
        let plain =
            DirectMemory::estimate::<1>(a.as_ref(), &fixed, &blocks, false, &small).unwrap();
        assert_eq!(
            (plain.dense_bytes, plain.extension_bytes),
            (2 * 8 * m * m, 0)
        );
        assert!(DirectMemory::estimate::<1>(a.as_ref(), &fixed, &[5, 3], true, &small).is_err());
    }
}
