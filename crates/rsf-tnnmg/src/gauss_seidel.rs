//! Nonlinear block Gauss–Seidel as a stand-alone solver (the baseline).

use std::time::Instant;

use faer::sparse::SparseColMatRef;

use crate::csc::Csc;
use crate::error::{Error, Result};
use crate::nonlinearity::BlockNonlinearity;
use crate::problem::{active_map, BlockedMatrix};
use crate::report::{check_inputs, NonsmoothSolver, SolveReport, Stopping};
use crate::tnnmg::EnergyNorm;

/// Nonlinear block Gauss–Seidel: symmetric sweeps (forward then backward) of exact block
/// minimisations. Globally convergent for the convex problems of this crate but slow
/// (its contraction degrades with mesh refinement); a baseline and a check for TNNMG.
pub struct NonlinearGaussSeidel<const D: usize> {
    m: BlockedMatrix<D>,
    norm: EnergyNorm,
    stopping: Stopping,
    record_energy: bool,
    active_of: Vec<usize>,
    v_old: Vec<f64>,
}

impl<const D: usize> NonlinearGaussSeidel<D> {
    /// Set-up; arguments as for [`Tnnmg::new`](crate::Tnnmg::new) without the hierarchy.
    ///
    /// # Errors
    /// As [`Tnnmg::new`](crate::Tnnmg::new).
    pub fn new(
        a: SparseColMatRef<'_, usize, f64>,
        fixed: &[bool],
        energy_norm: Option<SparseColMatRef<'_, usize, f64>>,
        stopping: Stopping,
        record_energy: bool,
    ) -> Result<Self> {
        stopping.validate()?;
        let m = BlockedMatrix::<D>::new(Csc::from_faer(a)?, fixed)?;
        let n = m.n();
        Ok(Self {
            norm: EnergyNorm::new(energy_norm, n)?,
            m,
            stopping,
            record_energy,
            active_of: Vec::new(),
            v_old: vec![0.0; n],
        })
    }
}

impl<const D: usize> NonsmoothSolver<D> for NonlinearGaussSeidel<D> {
    fn name(&self) -> &'static str {
        "nonlinear-gauss-seidel"
    }

    fn dim(&self) -> usize {
        self.m.n()
    }

    fn solve<N: BlockNonlinearity<D>>(
        &mut self,
        b: &[f64],
        nl: &N,
        v: &mut [f64],
    ) -> Result<SolveReport> {
        let start = Instant::now();
        let n = self.m.n();
        check_inputs(n, b, v)?;
        active_map(nl, n / D, &mut self.active_of)?;
        let mut energy = self.record_energy.then(|| vec![self.m.energy(b, nl, v)]);
        let mut correction = f64::INFINITY;
        for it in 1..=self.stopping.max_iterations {
            self.v_old.copy_from_slice(v);
            self.m
                .nonlinear_gauss_seidel(b, nl, &self.active_of, v, false);
            self.m
                .nonlinear_gauss_seidel(b, nl, &self.active_of, v, true);
            if v.iter().any(|x| !x.is_finite()) {
                return Err(Error::NonFinite("Gauss–Seidel iterate"));
            }
            for (o, x) in self.v_old.iter_mut().zip(v.iter()) {
                *o = x - *o;
            }
            correction = self.norm.norm(&self.m.a, &self.v_old);
            if let Some(e) = energy.as_mut() {
                e.push(self.m.energy(b, nl, v));
            }
            let norm_v = if self.stopping.relative > 0.0 {
                self.norm.norm(&self.m.a, v)
            } else {
                0.0
            };
            if self.stopping.met(correction, norm_v) {
                return Ok(SolveReport {
                    iterations: it,
                    correction,
                    energy,
                    seconds: start.elapsed().as_secs_f64(),
                });
            }
        }
        Err(Error::NotConverged {
            solver: "nonlinear-gauss-seidel",
            iterations: self.stopping.max_iterations,
            correction,
            tolerance: self.stopping.absolute,
        })
    }
}
