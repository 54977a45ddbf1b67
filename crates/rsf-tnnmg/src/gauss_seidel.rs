//! Nonlinear block Gauss–Seidel as a stand-alone solver (the baseline).

use faer::sparse::SparseColMatRef;

use crate::error::Result;
use crate::norm::EnergyNorm;
use crate::problem::{ActiveBlocks, NodalProblem};
use crate::report::{correction, Iteration, NodalIteration};
use rsf_nonsmooth::{BlockNonlinearity, SolveWatch, Stopping};

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
    /// wall-clock limit, at which the solve stops with
    /// [`Error::TimeLimit`](crate::Error::TimeLimit) (the iterations done and the last
    /// correction); the iteration cap stays [`Stopping::max_iterations`]
    /// ([`Error::NotConverged`](crate::Error::NotConverged)). The iterates do not depend on
    /// it.
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
}

impl<const D: usize> Iteration<D> for NonlinearGaussSeidel<D> {
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
        correction(&mut self.v_old, v, "Gauss–Seidel iterate")?;
        Ok(self.norm.norm(&self.m.a, &self.v_old))
    }
}

crate::report::iterative_solver!(
    NonlinearGaussSeidel,
    "nonlinear-gauss-seidel",
    dim: [m.n()],
    options: [],
    watch: [watch],
    reset: [],
    extra: {}
);
