//! The energy norm `‖x‖ = √(xᵀ E x)` in which the iterative solvers measure corrections.

use faer::sparse::SparseColMatRef;

use crate::error::Result;
use crate::Parallelism;
use rsf_nonsmooth::energy_norm_matrix;
use rsf_ranks::bsr::BlockCsr;

/// Shared set-up of the energy norm: `‖x‖² = xᵀ E x`, E symmetric positive semidefinite.
#[derive(Debug, Clone)]
pub(crate) struct EnergyNorm<const D: usize> {
    e: Option<BlockCsr<D>>,
}

impl<const D: usize> EnergyNorm<D> {
    pub fn new(e: Option<SparseColMatRef<'_, usize, f64>>, n: usize) -> Result<Self> {
        let e = energy_norm_matrix(e, n)?;
        Ok(Self {
            e: e.as_ref().map(BlockCsr::from_csc).transpose()?,
        })
    }
    pub fn norm(&self, a: &BlockCsr<D>, x: &[f64]) -> f64 {
        self.norm_par(a, x, Parallelism::SEQ, &mut Vec::new())
    }

    /// [`norm`](Self::norm) on `par`'s threads, the same bits for every thread count
    /// ([`BlockCsr::quadratic_form_par`]; `scratch` is kept by the caller).
    pub fn norm_par(
        &self,
        a: &BlockCsr<D>,
        x: &[f64],
        par: Parallelism,
        scratch: &mut Vec<Option<[f64; D]>>,
    ) -> f64 {
        self.e
            .as_ref()
            .unwrap_or(a)
            .quadratic_form_par(x, par, scratch)
            .max(0.0)
            .sqrt()
    }
}
