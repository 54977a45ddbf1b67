//! What a rank's linear V-cycle is built from ([`LevelSource`]): a whole hierarchy
//! ([`VCycleHierarchy`]: the Galerkin coarse operators, masks and colourings of every
//! level, computed whole on every rank) or a rank's own rows of every level
//! ([`RankLevels`], TNNMG on ranks); and the one-process reference with the distributed
//! cycle's smoother order ([`ColouredVCycle`]).

use faer::sparse::{SparseColMat, SparseColMatRef};
use rsf_linalg::Csc;

use super::rank_hierarchy::RankHierarchy;
use crate::coarse::{excluded, CoarseSolver};
use crate::error::{Error, Result};
use crate::galerkin::Galerkin;
use crate::Parallelism;
use rsf_nonsmooth::ProblemError;
use rsf_ranks::bsr::BlockCsr;
use rsf_ranks::{ColouredGaussSeidel, Colouring, DistributedSweep, LocalRows, RankGroup};

/// Smoothing sweeps of a V-cycle on every level but the coarsest (solved exactly).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VCycleShape {
    /// Sweeps before the coarse correction, each over the colours in increasing order.
    pub pre: usize,
    /// Sweeps after the coarse correction, each over the colours in decreasing order.
    pub post: usize,
}

/// One level of the hierarchy, whole.
#[derive(Debug, Clone)]
pub(crate) struct Level<const D: usize> {
    pub a: BlockCsr<D>,
    /// Masked dofs: the fine level's fixed dofs; on a coarse level the dofs whose Galerkin
    /// diagonal vanishes (all of their fine support masked).
    pub fixed: Vec<bool>,
    /// 1 on free dofs, 0 on masked ones.
    pub free: Vec<f64>,
    pub colouring: Colouring,
}

/// The whole hierarchy of a linear V-cycle, as every rank builds it for now: the levels'
/// matrices (the fine matrix and the Galerkin products `C = P_tᵀ H P_t` with the truncated
/// prolongations, as the one-process multigrid forms them), their masks, a colouring of
/// each level's node graph, and the prolongations. A rank keeps its rows of each level
/// ([`DistributedVCycle`](super::DistributedVCycle)) and may drop this afterwards;
/// building each rank's rows from its part alone (the memory step) is later work.
#[derive(Debug, Clone)]
pub struct VCycleHierarchy<const D: usize> {
    /// Coarsest first; the last is the fine level.
    pub(crate) levels: Vec<Level<D>>,
    /// `prolongations[l]` maps level `l` to level `l + 1`.
    pub(crate) prolongations: Vec<SparseColMat<usize, f64>>,
    /// `galerkin[l]` restricts level `l + 1` to level `l` and prolongates back.
    pub(crate) galerkin: Vec<Galerkin<D>>,
}

impl<const D: usize> VCycleHierarchy<D> {
    /// The hierarchy of the symmetric-pattern fine matrix `a` (`D n × D n`, node-major)
    /// with the fixed dofs `fixed` (length `D n`) and the node-major vector prolongations
    /// `prolongations`, coarsest first: `prolongations[l]` maps level `l` to level `l + 1`,
    /// the last one into the fine level (`D n × D n_{L−1}`).
    ///
    /// # Errors
    /// [`ProblemError::InvalidOption`] without a prolongation (a V-cycle has two levels or more);
    /// [`ProblemError::InvalidMatrix`] as [`Colouring::new`] for `a`, or if a prolongation is not
    /// `D n_{l+1} × D n_l` with `n_l ≤ n_{l+1}`; [`ProblemError::DimensionMismatch`] if `fixed` is
    /// not `D n` long; [`ProblemError::NotPositiveDefinite`] if the coarsest operator cannot be
    /// factorised.
    pub fn new(
        a: SparseColMatRef<'_, usize, f64>,
        fixed: &[bool],
        prolongations: &[SparseColMatRef<'_, usize, f64>],
    ) -> Result<Self> {
        if prolongations.is_empty() {
            return Err(ProblemError::InvalidOption(
                "a V-cycle needs at least one prolongation (two levels)".into(),
            )
            .into());
        }
        let fine = BlockCsr::<D>::from_symmetric(a)?;
        ProblemError::check_length("fixed (one flag per dof)", fine.n(), fixed.len())?;
        let mut rows = fine.n();
        for (l, p) in prolongations.iter().enumerate().rev() {
            if p.nrows() != rows || p.ncols() % D != 0 || p.ncols() > p.nrows() {
                return Err(ProblemError::InvalidMatrix(format!(
                    "prolongation {l} is {}x{}: expected {rows} rows and at most as many \
                     columns, a multiple of {D}",
                    p.nrows(),
                    p.ncols()
                ))
                .into());
            }
            rows = p.ncols();
        }
        let mut levels = vec![Level::new(fine, fixed.to_vec())];
        let mut galerkin = Vec::new();
        for p in prolongations.iter().rev() {
            let finer = levels.last().expect("the fine level");
            let (mut g, mut c) = Galerkin::new(&finer.a, &Csc::from_faer(*p)?)?;
            g.update(&finer.a, &finer.free, &mut c, Parallelism::SEQ);
            let mut mask = vec![false; c.n()];
            for (q, d) in c.diag.iter().enumerate() {
                for k in 0..D {
                    mask[D * q + k] = excluded(d[k][k]);
                }
            }
            galerkin.push(g);
            levels.push(Level::new(c, mask));
        }
        levels.reverse();
        galerkin.reverse();
        let h = Self {
            levels,
            prolongations: owned_copies(prolongations)?,
            galerkin,
        };
        h.coarse_solver()?;
        Ok(h)
    }

    /// Number of levels (≥ 2).
    pub fn num_levels(&self) -> usize {
        self.levels.len()
    }

    /// Number of nodes of level `l` (0 the coarsest).
    ///
    /// # Panics
    /// If `l ≥ num_levels()`.
    pub fn nodes(&self, l: usize) -> usize {
        self.levels[l].a.nodes()
    }

    /// Number of colours of level `l`'s colouring (exchanges per sweep on ranks).
    ///
    /// # Panics
    /// If `l ≥ num_levels()`.
    pub fn num_colours(&self, l: usize) -> usize {
        self.levels[l].colouring.num_colours()
    }

    /// Level `l`'s masked dofs (`D` per node of the level).
    ///
    /// # Panics
    /// If `l ≥ num_levels()`.
    pub fn fixed(&self, l: usize) -> &[bool] {
        &self.levels[l].fixed
    }

    /// The coarsest level's solver, factorised (each rank makes its own: the same input,
    /// the same factor).
    pub(crate) fn coarse_solver(&self) -> Result<CoarseSolver> {
        LevelSource::coarse_solver(self)
    }
}

/// What a rank's V-cycle is built from ([`DistributedVCycle`](super::DistributedVCycle)):
/// every level's matrix, masks and colouring (level 0 the coarsest), the prolongations
/// (`prolongation(l)` maps level `l` to `l + 1`) and the coarsest level's factorisation.
pub(crate) trait LevelSource<const D: usize> {
    fn num_levels(&self) -> usize;
    /// Level `l`'s node count.
    fn nodes(&self, l: usize) -> usize;
    /// Level `l`'s sweep of the rank of `halo`, the level's nodes owned by `owner`.
    fn sweep<H: RankGroup + ?Sized>(
        &self,
        l: usize,
        owner: &[usize],
        halo: &H,
    ) -> Result<DistributedSweep<D>>;
    /// The coarsest level's matrix, whole.
    fn coarsest(&self) -> &BlockCsr<D>;
    /// Masked dofs.
    fn fixed(&self, l: usize) -> &[bool];
    /// 1 on free dofs, 0 on masked ones.
    fn free(&self, l: usize) -> &[f64];
    fn prolongation(&self, l: usize) -> SparseColMatRef<'_, usize, f64>;

    /// The coarsest level's solver, factorised (each rank makes its own: the same input,
    /// the same factor).
    fn coarse_solver(&self) -> Result<CoarseSolver> {
        let mut s = CoarseSolver::new(self.coarsest())?;
        s.factorize(self.coarsest(), self.fixed(0))?;
        Ok(s)
    }
}

impl<const D: usize> LevelSource<D> for VCycleHierarchy<D> {
    fn num_levels(&self) -> usize {
        self.levels.len()
    }
    fn nodes(&self, l: usize) -> usize {
        self.levels[l].a.nodes()
    }
    fn sweep<H: RankGroup + ?Sized>(
        &self,
        l: usize,
        owner: &[usize],
        halo: &H,
    ) -> Result<DistributedSweep<D>> {
        let level = &self.levels[l];
        Ok(DistributedSweep::of_blocks(
            &level.a,
            owner,
            &level.colouring,
            halo,
        )?)
    }
    fn coarsest(&self) -> &BlockCsr<D> {
        &self.levels[0].a
    }
    fn fixed(&self, l: usize) -> &[bool] {
        &self.levels[l].fixed
    }
    fn free(&self, l: usize) -> &[f64] {
        &self.levels[l].free
    }
    fn prolongation(&self, l: usize) -> SparseColMatRef<'_, usize, f64> {
        self.prolongations[l].as_ref()
    }
}

/// A rank's hierarchy ([`RankHierarchy`], updated) with its rows of the fine level and
/// the fine level's colouring, and the prolongations it was built from (a colouring of
/// each coarse level computed here): what the set-up of TNNMG on ranks builds its
/// V-cycle from (the V-cycle reads the owned rows of each level; a coarse level's other
/// rows are not computed on this rank).
pub(crate) struct RankLevels<'a, const D: usize> {
    fine: &'a LocalRows<D>,
    h: &'a RankHierarchy<D>,
    prolongations: &'a [SparseColMatRef<'a, usize, f64>],
    /// Per level, the fine one's last.
    colourings: Vec<Colouring>,
}

impl<'a, const D: usize> RankLevels<'a, D> {
    /// `h`'s levels, the fine one's rows `fine` (its values those of `h`'s fine level at
    /// set-up) coloured by `fine_colouring`, with `prolongations` (`prolongations[l]`
    /// maps level `l` to `l + 1`).
    pub(crate) fn new(
        fine: &'a LocalRows<D>,
        fine_colouring: Colouring,
        h: &'a RankHierarchy<D>,
        prolongations: &'a [SparseColMatRef<'a, usize, f64>],
    ) -> Self {
        let nl = h.num_levels();
        let colourings = (0..nl - 1)
            .map(|l| Colouring::of_blocks(h.coarse_matrix(l)))
            .chain(std::iter::once(fine_colouring))
            .collect();
        Self {
            fine,
            h,
            prolongations,
            colourings,
        }
    }
}

impl<const D: usize> LevelSource<D> for RankLevels<'_, D> {
    fn num_levels(&self) -> usize {
        self.h.num_levels()
    }
    fn nodes(&self, l: usize) -> usize {
        self.colourings[l].num_nodes()
    }
    fn sweep<H: RankGroup + ?Sized>(
        &self,
        l: usize,
        owner: &[usize],
        halo: &H,
    ) -> Result<DistributedSweep<D>> {
        let colouring = &self.colourings[l];
        Ok(if l + 1 == self.h.num_levels() {
            DistributedSweep::of_rows(self.fine.clone(), colouring)?
        } else {
            DistributedSweep::of_blocks(self.h.coarse_matrix(l), owner, colouring, halo)?
        })
    }
    fn coarsest(&self) -> &BlockCsr<D> {
        self.h.coarse_matrix(0)
    }
    fn fixed(&self, l: usize) -> &[bool] {
        self.h.mask(l)
    }
    fn free(&self, l: usize) -> &[f64] {
        self.h.free(l)
    }
    fn prolongation(&self, l: usize) -> SparseColMatRef<'_, usize, f64> {
        self.prolongations[l]
    }
}

/// 1 on free dofs, 0 on masked ones.
fn free_of(fixed: &[bool]) -> Vec<f64> {
    fixed.iter().map(|&f| if f { 0.0 } else { 1.0 }).collect()
}

/// Owned copies of the prolongations.
fn owned_copies(
    prolongations: &[SparseColMatRef<'_, usize, f64>],
) -> Result<Vec<SparseColMat<usize, f64>>> {
    prolongations
        .iter()
        .map(|p| {
            // Pᵀ column-major, then its transpose column-major: an owned copy of P.
            p.transpose()
                .to_col_major()
                .and_then(|pt| pt.as_ref().transpose().to_col_major())
        })
        .collect::<std::result::Result<_, _>>()
        .map_err(|e| Error::Problem(ProblemError::InvalidMatrix(format!("prolongation: {e:?}"))))
}

impl<const D: usize> Level<D> {
    fn new(a: BlockCsr<D>, fixed: Vec<bool>) -> Self {
        let free = free_of(&fixed);
        let colouring = Colouring::of_blocks(&a);
        Self {
            a,
            fixed,
            free,
            colouring,
        }
    }
}

/// The one-process reference of the distributed V-cycle: the same cycle on the whole
/// matrices of a [`VCycleHierarchy`], on one thread. On each level but the coarsest:
/// `pre` coloured block Gauss–Seidel sweeps ([`ColouredGaussSeidel`], increasing colours;
/// the coarse levels start from 0), the residual by rows, the restriction
/// `Pᵀ (free ⊙ r)`, the coarse correction, the prolongation `x += free ⊙ P c`, `post`
/// sweeps with decreasing colours; the coarsest level solved by Cholesky on the free
/// dofs. The transfers are the one-process multigrid's (`Galerkin`'s rows); the smoother
/// order is the colouring's, not the multigrid's lexicographic or chunked order, so the
/// iterates differ from the TNNMG's linear multigrid in the last bits.
#[derive(Debug)]
pub struct ColouredVCycle<const D: usize> {
    shape: VCycleShape,
    /// `smoothers[l − 1]` smooths level `l ≥ 1` (and holds its right-hand side).
    smoothers: Vec<ColouredGaussSeidel<D>>,
    galerkin: Vec<Galerkin<D>>,
    free: Vec<Vec<f64>>,
    /// Level `l`'s iterate (`l` below the fine level) and residual.
    x: Vec<Vec<f64>>,
    r: Vec<Vec<f64>>,
    /// The coarsest level's right-hand side.
    coarse_rhs: Vec<f64>,
    coarse: CoarseSolver,
}

impl<const D: usize> ColouredVCycle<D> {
    /// The cycle of `h` with `shape`, the fine right-hand side zero
    /// ([`set_rhs`](Self::set_rhs)).
    ///
    /// # Errors
    /// As [`VCycleHierarchy::new`]'s factorisation (not expected after it succeeded).
    pub fn new(h: &VCycleHierarchy<D>, shape: VCycleShape) -> Result<Self> {
        let smoothers = h.levels[1..]
            .iter()
            .map(|l| {
                ColouredGaussSeidel::of_blocks(
                    l.a.clone(),
                    &l.fixed,
                    &vec![0.0; l.a.n()],
                    &l.colouring,
                )
            })
            .collect::<rsf_ranks::Result<_>>()?;
        let n = |l: &Level<D>| vec![0.0; l.a.n()];
        Ok(Self {
            shape,
            smoothers,
            galerkin: h.galerkin.clone(),
            free: h.levels.iter().map(|l| l.free.clone()).collect(),
            x: h.levels.iter().map(n).collect(),
            r: h.levels.iter().map(n).collect(),
            coarse_rhs: n(&h.levels[0]),
            coarse: h.coarse_solver()?,
        })
    }

    /// Sets the fine right-hand side.
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] if `b` does not have the fine level's `D n` values.
    pub fn set_rhs(&mut self, b: &[f64]) -> Result<()> {
        let fine = self.smoothers.last_mut().expect("two levels or more");
        let rhs = fine.rhs_mut();
        ProblemError::check_length("b (fine level)", rhs.len(), b.len())?;
        rhs.copy_from_slice(b);
        Ok(())
    }

    /// One V-cycle on the fine iterate `x` (`D n`; its fixed dofs are left as they are).
    ///
    /// # Panics
    /// If `x` is not `D n` long.
    pub fn cycle(&mut self, x: &mut [f64]) {
        let l = self.free.len() - 1;
        self.level_cycle(l, x, false);
    }

    fn level_cycle(&mut self, l: usize, x: &mut [f64], zero_start: bool) {
        if l == 0 {
            x.copy_from_slice(&self.coarse_rhs);
            self.coarse.solve(x, &self.free[0]);
            return;
        }
        if zero_start {
            x.fill(0.0);
        }
        let gs = &mut self.smoothers[l - 1];
        for _ in 0..self.shape.pre {
            gs.sweep(x, false);
        }
        gs.residual(x, &mut self.r[l]);
        let coarse_rhs = match l {
            1 => &mut self.coarse_rhs[..],
            _ => self.smoothers[l - 2].rhs_mut(),
        };
        self.galerkin[l - 1].restrict(&self.r[l], &self.free[l], coarse_rhs, Parallelism::SEQ);
        let mut xc = std::mem::take(&mut self.x[l - 1]);
        self.level_cycle(l - 1, &mut xc, true);
        self.galerkin[l - 1].prolong_add(&xc, &self.free[l], x, Parallelism::SEQ);
        self.x[l - 1] = xc;
        let gs = &mut self.smoothers[l - 1];
        for _ in 0..self.shape.post {
            gs.sweep(x, true);
        }
    }
}
