//! Nonlinear block Gauss–Seidel as a stand-alone solver (the baseline).

use faer::sparse::SparseColMatRef;

use crate::error::{Error, Result};
use crate::norm::EnergyNorm;
use crate::problem::{ActiveBlocks, NodalProblem};
use crate::report::{iterate_to_tolerance, IterationRun, NodalIteration};
use rsf_nonsmooth::ProblemError;
use rsf_nonsmooth::{BlockNonlinearity, NonsmoothSolver, SolveReport, SolveWatch, Stopping};

/// Nonlinear block Gauss–Seidel: symmetric sweeps (forward then backward) of exact block
/// minimisations. Globally convergent for the convex problems of this crate but slow
/// (its contraction degrades with mesh refinement); a baseline and a check for TNNMG.
pub struct NonlinearGaussSeidel<const D: usize> {
    m: NodalProblem<D>,
    norm: EnergyNorm<D>,
    stopping: Stopping,
    record_energy: bool,
    active_of: Vec<usize>,
    v_old: Vec<f64>,
    /// Sweep scratch.
    w: Vec<f64>,
    /// Progress reports and a time limit of every solve ([`with_watch`](Self::with_watch)).
    watch: Option<SolveWatch>,
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
        let m = NodalProblem::<D>::new(a, fixed)?;
        let n = m.n();
        Ok(Self {
            norm: EnergyNorm::new(energy_norm, n)?,
            m,
            stopping,
            record_energy,
            active_of: Vec::new(),
            v_old: vec![0.0; n],
            w: vec![0.0; n],
            watch: None,
        })
    }

    /// Watches every later solve ([`SolveWatch`]): progress reports as it goes and a
    /// wall-clock limit, at which the solve stops with [`Error::TimeLimit`] (the
    /// iterations done and the last correction); the iteration cap stays
    /// [`Stopping::max_iterations`] ([`Error::NotConverged`]). The iterates do not depend
    /// on it.
    pub fn with_watch(mut self, watch: SolveWatch) -> Self {
        self.watch = Some(watch);
        self
    }
}

impl<const D: usize> NodalIteration<D> for NonlinearGaussSeidel<D> {
    fn blocked(&self) -> &NodalProblem<D> {
        &self.m
    }
    fn energy_norm(&self) -> &EnergyNorm<D> {
        &self.norm
    }
    fn active_of_mut(&mut self) -> &mut Vec<usize> {
        &mut self.active_of
    }
    /// One symmetric sweep (forward, then backward).
    fn iterate<N: BlockNonlinearity<D>>(
        &mut self,
        b: &[f64],
        nl: &N,
        v: &mut [f64],
    ) -> Result<f64> {
        self.v_old.copy_from_slice(v);
        let blocks = ActiveBlocks {
            nl,
            active_of: &self.active_of,
        };
        for reverse in [false, true] {
            self.m
                .nonlinear_gauss_seidel(b, blocks, v, &mut self.w, reverse);
        }
        if v.iter().any(|x| !x.is_finite()) {
            return Err(ProblemError::NonFinite("Gauss–Seidel iterate").into());
        }
        for (o, x) in self.v_old.iter_mut().zip(v.iter()) {
            *o = x - *o;
        }
        Ok(self.norm.norm(&self.m.a, &self.v_old))
    }
}

impl<const D: usize> NonsmoothSolver<D> for NonlinearGaussSeidel<D> {
    type Error = Error;

    fn name(&self) -> &'static str {
        "nonlinear-gauss-seidel"
    }

    fn dim(&self) -> usize {
        self.m.n()
    }

    fn stopping(&self) -> Stopping {
        self.stopping
    }

    fn set_stopping(&mut self, stopping: Stopping) -> Result<()> {
        stopping.validate()?;
        self.stopping = stopping;
        Ok(())
    }

    fn solve<N: BlockNonlinearity<D>>(
        &mut self,
        b: &[f64],
        nl: &N,
        v: &mut [f64],
    ) -> Result<SolveReport> {
        let run = IterationRun {
            solver: "nonlinear-gauss-seidel",
            stop: self.stopping,
            record_energy: self.record_energy,
        };
        let mut watch = self.watch.take();
        let result = iterate_to_tolerance(self, run, b, nl, v, watch.as_mut());
        self.watch = watch;
        result
    }
}
