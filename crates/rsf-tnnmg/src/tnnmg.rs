//! Truncated nonsmooth Newton multigrid (Gräser, Kornhuber, Sander).

use std::sync::Arc;

use faer::sparse::{SparseColMat, SparseColMatRef};

use crate::chunks::{ChunkedOrder, ChunkedSweep};
use crate::error::{Error, Result};
use crate::line_search::exact_line_search;
use crate::linear_correction::{CycleBudget, LinearCorrection, LinearSolve};
use crate::multigrid::{CycleShape, LinearMultigrid, NewtonHierarchy};
use crate::norm::EnergyNorm;
use crate::problem::{dot, ActiveBlocks, ChunkedSmoother, NodalProblem};
use crate::report::{correction, Iteration, NodalIteration};
use crate::smoother_order::SmootherOrder;
use crate::Parallelism;
use rsf_linalg::Csc;
use rsf_nonsmooth::ProblemError;
use rsf_nonsmooth::{BlockNonlinearity, Linearization, SolveWatch, Stopping};
use rsf_ranks::block::{load, Block};
use rsf_ranks::Colouring;

/// Blocks whose nonlinearity's Hessian exceeds this multiple of `A`'s diagonal are
/// truncated in the linear correction (see [`is_rigid`]): at this contrast the
/// coarse operators still carry ~1e-6 relative accuracy (ratio × machine epsilon).
const RIGID_BLOCK_RATIO: f64 = 1e10;

/// Options of [`Tnnmg`].
#[derive(Debug, Clone, PartialEq)]
pub struct TnnmgOptions {
    /// Stopping test on the energy norm of the correction.
    pub stopping: Stopping,
    /// Nonlinear Gauss–Seidel sweeps before each linear correction (≥ 1: they carry the
    /// global convergence guarantee).
    pub nonlinear_sweeps: usize,
    /// Maximal number of linear multigrid cycles per iteration (V- or W-cycles, see
    /// [`cycle_index`](Self::cycle_index); preconditioner applications with
    /// [`LinearCorrection::PreconditionedCg`]).
    pub v_cycles: usize,
    /// How the cycles solve the truncated Newton system.
    pub linear_correction: LinearCorrection,
    /// Inexact Newton: stop the linear correction of an iteration early once the
    /// linearised residual (Euclidean norm on the untruncated dofs) is reduced by this
    /// factor; `None` always runs `v_cycles` cycles. The TNNMG iteration count then no
    /// longer inherits the growth of the V-cycle rate with refinement (mass- to
    /// stiffness-dominated `A`).
    pub linear_reduction: Option<f64>,
    /// Block Gauss–Seidel sweeps before and after the coarse correction in each cycle.
    pub smoothing: (usize, usize),
    /// Coarse corrections per level and cycle: 1 is the V-cycle, 2 the W-cycle.
    pub cycle_index: usize,
    /// Record `J(v_k)` in the report.
    pub record_energy: bool,
    /// The node order of the nonlinear Gauss–Seidel sweeps (the fine-level smoother) and,
    /// with [`SmootherOrder::RedBlackChunks`], of the linear multigrid's fine-level
    /// smoother. [`SmootherOrder::MultiColour`] and [`SmootherOrder::RedBlackChunks`] also
    /// compute the residual after the sweeps in their order, all on the solver's threads
    /// ([`Tnnmg::with_parallelism`]), bit-identical for every thread count. Default
    /// [`SmootherOrder::Lexicographic`] (sequential, the iterates of every trajectory before
    /// this option).
    pub smoother: SmootherOrder,
}

impl TnnmgOptions {
    /// The classical TNNMG iteration (docs/math.md §5 with one cycle): one nonlinear
    /// Gauss–Seidel sweep and exactly one multigrid V(3,3)-cycle as the linear correction
    /// of every iteration (no inexact-Newton rule, no Krylov acceleration) — this crate's
    /// defaults before the inexact-Newton rule. Same stopping test as [`Default`].
    pub fn classical() -> Self {
        Self {
            v_cycles: 1,
            linear_correction: LinearCorrection::Cycles,
            linear_reduction: None,
            smoothing: (3, 3),
            ..Self::default()
        }
    }
}

impl Default for TnnmgOptions {
    /// One nonlinear sweep, then conjugate gradients preconditioned by block Gauss–Seidel
    /// V(2,2)-cycles until the linearised residual dropped by 0.01 (at most 4 cycles):
    /// chosen by time-to-tolerance measurements on the slider at j = 4..8 (docs/tnnmg.md).
    fn default() -> Self {
        Self {
            stopping: Stopping::default(),
            nonlinear_sweeps: 1,
            v_cycles: 4,
            linear_correction: LinearCorrection::default(),
            linear_reduction: Some(0.01),
            smoothing: (2, 2),
            cycle_index: 1,
            record_energy: false,
            smoother: SmootherOrder::Lexicographic,
        }
    }
}

/// TNNMG for `J(v) = ½ vᵀAv − bᵀv + Σ_k φ_k(v_{p_k})` (docs/math.md §5):
/// nonlinear block Gauss–Seidel presmoothing, truncated linearisation, linear multigrid
/// cycle(s) on the truncated Newton system over the given hierarchy, exact line search.
/// `J` never increases. Stops on the energy norm of the correction.
///
/// Storage: node-block CSR (`D × D` blocks, 32-bit node indices) for `A`, the Newton
/// matrices and the Galerkin coarse operators; the linear multigrid smoother is block
/// Gauss–Seidel with the diagonal blocks' local solves precomputed per set-up.
///
/// Set-up (once per matrix): pattern analysis, Galerkin product patterns, coarse symbolic
/// Cholesky. Per solve with a new set of nonlinear blocks, one full numeric set-up of the
/// hierarchy; afterwards only the rows the nonlinear blocks reach are recomputed. Solves
/// allocate nothing per iteration (except the optional energy history).
pub struct Tnnmg<const D: usize> {
    m: NodalProblem<D>,
    mg: LinearMultigrid<D>,
    norm: EnergyNorm<D>,
    opts: TnnmgOptions,
    active_of: Vec<usize>,
    /// Active blocks for which the multigrid hierarchy is set up incrementally.
    cached_active: Option<Vec<usize>>,
    v_old: Vec<f64>,
    /// `b − A v` after the nonlinear presmoothing.
    res_a: Vec<f64>,
    /// Right-hand side of the truncated Newton system.
    res: Vec<f64>,
    c: Vec<f64>,
    linear: LinearSolve,
    /// Sweep scratch (0 between uses).
    w: Vec<f64>,
    /// Multigrid cycles of the current (or last) solve.
    cycles: usize,
    /// The fine-level colouring ([`SmootherOrder::MultiColour`] only).
    colouring: Option<Colouring>,
    /// Block updates of one colour (length of the largest colour; empty without colouring).
    colour_scratch: Vec<[f64; D]>,
    /// The nonlinear sweeps' chunked order ([`SmootherOrder::RedBlackChunks`] only).
    chunked: Option<ChunkedSweep<D>>,
    /// Per-node terms of the parallel quadratic forms (empty until used).
    sum_scratch: Vec<Option<[f64; D]>>,
    parallelism: Parallelism,
    /// Progress reports and a time limit of every solve ([`Tnnmg::with_watch`]).
    watch: Option<SolveWatch>,
}

impl<const D: usize> Tnnmg<D> {
    /// Sets up TNNMG for the symmetric positive definite (on the free dofs) matrix `a`
    /// (`n × n`, `n = D · nodes`, node-major, both triangles stored) with the dofs where
    /// `fixed` is true held at the values of the iterate. `prolongations[l]` maps level `l` to
    /// level `l + 1` in the same node-major numbering (`D n_{l+1} × D n_l`); the last one has
    /// `n` rows. An empty list gives a single-level method whose linear correction is an
    /// exact sparse solve. `energy_norm`: matrix of the stopping norm (paper: `K + M`);
    /// `None` uses `a`.
    ///
    /// # Errors
    /// Invalid shapes (including prolongation column counts not divisible by `D`),
    /// non-symmetric pattern, missing diagonal, non-positive free diagonal, invalid options.
    pub fn new(
        a: SparseColMatRef<'_, usize, f64>,
        fixed: &[bool],
        prolongations: &[SparseColMat<usize, f64>],
        energy_norm: Option<SparseColMatRef<'_, usize, f64>>,
        opts: TnnmgOptions,
    ) -> Result<Self> {
        opts.check_newton()?;
        if !(1..=2).contains(&opts.cycle_index) {
            return Err(ProblemError::InvalidOption(
                "cycle_index must be 1 (V-cycle) or 2 (W-cycle)".into(),
            )
            .into());
        }
        let m = NodalProblem::<D>::new(a, fixed)?;
        let prolongations = prolongations
            .iter()
            .map(|p| Csc::from_faer(p.as_ref()).map_err(Error::from))
            .collect::<Result<Vec<_>>>()?;
        let mut mg = LinearMultigrid::new(
            m.a.clone(),
            prolongations,
            CycleShape {
                pre: opts.smoothing.0,
                post: opts.smoothing.1,
                gamma: opts.cycle_index,
            },
        )?;
        let n = m.n();
        let (colouring, chunked) = match opts.smoother {
            SmootherOrder::Lexicographic => (None, None),
            SmootherOrder::MultiColour => (Some(Colouring::of_blocks(&m.a)), None),
            SmootherOrder::RedBlackChunks => {
                let order = Arc::new(ChunkedOrder::new(&m.a));
                mg.chunk_fine_level(order.clone());
                (None, Some(ChunkedSweep::new(order, &m.a.diag)))
            }
        };
        let colour_scratch = vec![[0.0; D]; colouring.as_ref().map_or(0, |c| c.max_colour_len())];
        Ok(Self {
            norm: EnergyNorm::new(energy_norm, n)?,
            m,
            mg,
            colouring,
            colour_scratch,
            chunked,
            sum_scratch: Vec::new(),
            parallelism: Parallelism::SEQ,
            watch: None,
            opts,
            active_of: Vec::new(),
            cached_active: None,
            v_old: vec![0.0; n],
            res_a: vec![0.0; n],
            res: vec![0.0; n],
            c: vec![0.0; n],
            linear: LinearSolve::new(n),
            w: vec![0.0; n],
            cycles: 0,
        })
    }

    /// Runs the parallel parts on `par`'s threads (default [`Parallelism::SEQ`]): in every
    /// smoother order the parts computed row by row (the quadratic forms of the line
    /// search and the energy norm as ordered sums of per-row terms, the Galerkin updates
    /// of the coarse operators, restrictions and prolongations); with
    /// [`SmootherOrder::MultiColour`] the nonlinear sweeps, with
    /// [`SmootherOrder::RedBlackChunks`] the nonlinear sweeps and the fine level's linear
    /// smoothing. The iterates do not depend on it (the same bits for every thread count).
    pub fn with_parallelism(mut self, par: Parallelism) -> Self {
        self.parallelism = par;
        self.mg.set_parallelism(par);
        self
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

    /// Replaces the watch of later solves (`None`: unwatched), returning the old one.
    pub fn set_watch(&mut self, watch: Option<SolveWatch>) -> Option<SolveWatch> {
        std::mem::replace(&mut self.watch, watch)
    }

    /// The parallelism of [`with_parallelism`](Self::with_parallelism).
    pub fn parallelism(&self) -> Parallelism {
        self.parallelism
    }

    /// The fine-level colouring ([`SmootherOrder::MultiColour`]), `None` otherwise.
    pub fn colouring(&self) -> Option<&Colouring> {
        self.colouring.as_ref()
    }

    /// Number of multigrid levels.
    pub fn num_levels(&self) -> usize {
        self.mg.num_levels()
    }

    /// The options in use.
    pub fn options(&self) -> &TnnmgOptions {
        &self.opts
    }

    /// Number of linear multigrid cycles (preconditioner applications with
    /// [`LinearCorrection::PreconditionedCg`]) in the last call of
    /// [`solve`](rsf_nonsmooth::NonsmoothSolver::solve), over all its iterations.
    pub fn last_solve_cycles(&self) -> usize {
        self.cycles
    }

    /// Sets the fine-level matrix `H = A + ∇²Φ(v)` (on the active blocks), its mask
    /// (fixed ∪ truncated) and the Newton right-hand side `res = b − Av − ∇Φ(v)` (0 on the
    /// mask), then updates the hierarchy ([`linearize_blocks`]).
    fn linearize<N: BlockNonlinearity<D>>(&mut self, nl: &N, v: &[f64]) -> Result<()> {
        self.res.copy_from_slice(&self.res_a);
        let res = &mut self.res;
        let quadratic = QuadraticPart {
            diag: &self.m.a.diag,
            fixed: &self.m.fixed,
        };
        linearize_blocks(
            nl,
            v,
            quadratic,
            &mut self.mg,
            &mut self.cached_active,
            |p, g| {
                for r in 0..D {
                    res[D * p + r] -= g[r];
                }
            },
        )?;
        for (r, &m) in self.res.iter_mut().zip(self.mg.fine_mask()) {
            if m {
                *r = 0.0;
            }
        }
        Ok(())
    }
}

impl<const D: usize> NodalIteration<D> for Tnnmg<D> {
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

impl<const D: usize> Iteration<D> for Tnnmg<D> {
    /// One TNNMG iteration from `v`; returns the energy norm of the correction.
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
        if let Some(chunked) = &mut self.chunked {
            let smoother = ChunkedSmoother {
                sweeper: chunked,
                sweeps: self.opts.nonlinear_sweeps,
                par: self.parallelism,
            };
            self.m
                .nonlinear_gauss_seidel_chunked(b, blocks, v, &mut self.res_a, smoother);
        } else {
            match &self.colouring {
                None => {
                    for _ in 0..self.opts.nonlinear_sweeps {
                        self.m
                            .nonlinear_gauss_seidel(b, blocks, v, &mut self.w, false);
                    }
                    self.m.a.residual(b, v, &mut self.res_a, &mut self.w);
                }
                Some(colouring) => {
                    for _ in 0..self.opts.nonlinear_sweeps {
                        self.m.nonlinear_gauss_seidel_coloured(
                            b,
                            blocks,
                            v,
                            colouring,
                            self.parallelism,
                            &mut self.colour_scratch,
                        );
                    }
                    self.m
                        .a
                        .residual_rows(b, v, &mut self.res_a, self.parallelism);
                }
            }
        }
        // Truncated linearisation at v, then the inexact linear correction H c = res.
        self.linearize(nl, v)?;
        self.cycles += self.linear.solve(
            self.opts.linear_correction,
            &mut self.mg,
            &mut self.res,
            &mut self.c,
            CycleBudget {
                max_cycles: self.opts.v_cycles,
                reduction: self.opts.linear_reduction,
            },
        );
        stop_at_kinks(nl, v, &mut self.c);
        // Exact line search along c: g0 = cᵀ(Av − b), h = cᵀAc.
        let g0 = -dot(&self.c, &self.res_a);
        let h = self
            .m
            .a
            .quadratic_form_par(&self.c, self.parallelism, &mut self.sum_scratch);
        if h > 0.0 && h.is_finite() {
            let s = exact_line_search(nl, v, &self.c, g0, h);
            for (vi, ci) in v.iter_mut().zip(&self.c) {
                *vi += s * ci;
            }
        }
        correction(&mut self.v_old, v, "TNNMG iterate")?;
        Ok(self.norm.norm_par(
            &self.m.a,
            &self.v_old,
            self.parallelism,
            &mut self.sum_scratch,
        ))
    }
}

crate::report::iterative_solver!(
    Tnnmg,
    "tnnmg",
    dim: [m.n()],
    options: [opts],
    watch: [watch],
    reset: [cycles],
    extra: {}
);

/// The options TNNMG on one process and on ranks share, checked alike.
pub(crate) trait NewtonOptions {
    /// The stopping test, the linear correction's reduction factor, the nonlinear sweeps and
    /// the cycles per iteration.
    fn newton(&self) -> (Stopping, Option<f64>, usize, usize);

    /// Checks the stopping test, the reduction factor (in (0, 1) if any) and at least one
    /// nonlinear sweep and one cycle per iteration.
    ///
    /// # Errors
    /// [`ProblemError::InvalidOption`] (converted) naming the option out of range.
    fn check_newton(&self) -> Result<()> {
        let (stopping, linear_reduction, nonlinear_sweeps, v_cycles) = self.newton();
        stopping.validate()?;
        if linear_reduction.is_some_and(|r| !(r > 0.0 && r < 1.0)) {
            return Err(
                ProblemError::InvalidOption("linear_reduction must lie in (0, 1)".into()).into(),
            );
        }
        if nonlinear_sweeps == 0 || v_cycles == 0 {
            return Err(ProblemError::InvalidOption(
                "nonlinear_sweeps and v_cycles must be at least 1".into(),
            )
            .into());
        }
        Ok(())
    }
}

impl NewtonOptions for TnnmgOptions {
    fn newton(&self) -> (Stopping, Option<f64>, usize, usize) {
        (
            self.stopping,
            self.linear_reduction,
            self.nonlinear_sweeps,
            self.v_cycles,
        )
    }
}

/// Whether the Hessian of a block is so large against `A`'s own diagonal block `diag`
/// (ratio above [`RIGID_BLOCK_RATIO`] on a free component; `fixed` the block's `D` flags)
/// that the block is numerically rigid: its Newton correction is negligible, and keeping it
/// would put a contrast beyond double precision into the coarse operators (rate-and-state
/// friction near the cutoff has `ϕ'' = κ/V` up to `κ/V_m`, e.g. 1e26 Pa·s/m against entries
/// ~1e6 of `A`; the coarse Cholesky then fails as "not positive definite"). Such blocks
/// are truncated like nonsmooth ones; the nonlinear smoother still updates them.
pub(crate) fn is_rigid<const D: usize>(
    fixed: &[bool],
    diag: &Block<D>,
    hessian: &[[f64; D]; D],
) -> bool {
    (0..D).any(|c| !fixed[c] && !(hessian[c][c] <= RIGID_BLOCK_RATIO * diag[c][c]))
}

/// The quadratic part's data the truncated linearisation reads: `A`'s diagonal blocks and
/// the fixed dofs (whole, `D` flags per node).
#[derive(Debug, Clone, Copy)]
pub(crate) struct QuadraticPart<'a, const D: usize> {
    pub diag: &'a [Block<D>],
    pub fixed: &'a [bool],
}

/// The truncated linearisation of TNNMG at `v` (global node-major; only the active
/// blocks' values are read), one process or replicated on every rank: sets the fine
/// level of `mg` (the one-process multigrid, or a rank's share of it) to `H = A + ∇²Φ(v)` on the active blocks and its mask to the fixed dofs
/// plus the truncated blocks (nonsmooth, [`Linearization::Truncate`], or rigid,
/// [`is_rigid`]); calls `gradient(p, ∇φ_k(v_p))` for every block kept in the Newton
/// system (the caller subtracts it from its right-hand side); then updates the hierarchy.
/// Only the active blocks' diagonal blocks and masks change from one iteration to the
/// next, so after one full set-up per set of active blocks (`cached_active` records it)
/// the coarse operators are updated incrementally. Returns whether the update was full.
pub(crate) fn linearize_blocks<const D: usize, N: BlockNonlinearity<D>>(
    nl: &N,
    v: &[f64],
    quadratic: QuadraticPart<'_, D>,
    mg: &mut impl NewtonHierarchy<D>,
    cached_active: &mut Option<Vec<usize>>,
    mut gradient: impl FnMut(usize, &[f64; D]),
) -> Result<bool> {
    let QuadraticPart { diag, fixed } = quadratic;
    let incremental = cached_active.as_deref() == Some(nl.active_blocks());
    if incremental {
        for &p in nl.active_blocks() {
            mg.fine_diag_mut()[p] = diag[p];
            mg.fine_mask_mut()[D * p..D * p + D].copy_from_slice(&fixed[D * p..D * p + D]);
        }
    } else {
        mg.fine_diag_mut().copy_from_slice(diag);
        mg.fine_mask_mut().copy_from_slice(fixed);
    }
    for (k, &p) in nl.active_blocks().iter().enumerate() {
        match nl.linearize(k, &load::<D>(v, p)) {
            Linearization::Smooth { hessian, .. }
                if is_rigid(&fixed[D * p..D * p + D], &diag[p], &hessian) =>
            {
                mg.fine_mask_mut()[D * p..D * p + D].fill(true);
            }
            Linearization::Smooth {
                gradient: g,
                hessian,
            } => {
                gradient(p, &g);
                let h = &mut mg.fine_diag_mut()[p];
                for r in 0..D {
                    for c in 0..D {
                        h[r][c] += hessian[r][c];
                    }
                }
            }
            Linearization::Truncate => {
                mg.fine_mask_mut()[D * p..D * p + D].fill(true);
            }
        }
    }
    if incremental {
        mg.update_incremental()?;
    } else {
        mg.update()?;
        mg.set_variable_nodes(nl.active_blocks());
        *cached_active = Some(nl.active_blocks().to_vec());
    }
    Ok(!incremental)
}

/// The kink rule of TNNMG: a block with a kink at zero
/// ([`BlockNonlinearity::kink_at_zero`]) whose correction `c_p` passes through zero
/// (`v_p · (v_p + c_p) < 0`, `v_p ≠ 0`) stops there (`c_p = −v_p`). `v` and `c` are global
/// node-major vectors; only the active blocks' values are read and written.
pub(crate) fn stop_at_kinks<const D: usize, N: BlockNonlinearity<D>>(
    nl: &N,
    v: &[f64],
    c: &mut [f64],
) {
    for (k, &p) in nl.active_blocks().iter().enumerate() {
        if !nl.kink_at_zero(k) {
            continue;
        }
        let r = D * p..D * p + D;
        let (vp, cp) = (&v[r.clone()], &c[r.clone()]);
        let crosses = vp.iter().any(|&x| x != 0.0)
            && vp.iter().zip(cp).map(|(a, c)| a * (a + c)).sum::<f64>() < 0.0;
        if crosses {
            for i in r {
                c[i] = -v[i];
            }
        }
    }
}
