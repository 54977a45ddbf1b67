//! Truncated nonsmooth Newton multigrid (Gräser, Kornhuber, Sander).

use faer::sparse::{SparseColMat, SparseColMatRef};

use crate::block::load;
use crate::csc::Csc;
use crate::error::{Error, Result};
use crate::line_search::exact_line_search;
use crate::multigrid::LinearMultigrid;
use crate::nonlinearity::{BlockNonlinearity, Linearization};
use crate::problem::BlockedMatrix;
use crate::report::{iterate_to_tolerance, Iteration, NonsmoothSolver, SolveReport, Stopping};

/// Blocks whose nonlinearity's Hessian exceeds this multiple of `A`'s diagonal are
/// truncated in the linear correction (see `Tnnmg::is_rigid`): at this contrast the
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
    /// Linear multigrid V-cycles per iteration.
    pub v_cycles: usize,
    /// Inexact Newton: stop the V-cycles of an iteration early once the linearised residual
    /// (Euclidean norm on the untruncated dofs) is reduced by this factor; `None` always
    /// runs `v_cycles` cycles. The TNNMG iteration count then no longer inherits the growth
    /// of the V-cycle rate with refinement (mass- to stiffness-dominated `A`).
    pub linear_reduction: Option<f64>,
    /// Gauss–Seidel sweeps before and after the coarse correction in each V-cycle.
    pub smoothing: (usize, usize),
    /// Record `J(v_k)` in the report.
    pub record_energy: bool,
}

impl Default for TnnmgOptions {
    fn default() -> Self {
        Self {
            stopping: Stopping::default(),
            nonlinear_sweeps: 1,
            v_cycles: 3,
            linear_reduction: Some(0.02),
            smoothing: (3, 3),
            record_energy: false,
        }
    }
}

/// Shared set-up of the energy norm: `‖x‖² = xᵀ E x`, E symmetric positive semidefinite.
#[derive(Debug, Clone)]
pub(crate) struct EnergyNorm {
    e: Option<Csc>,
}

impl EnergyNorm {
    pub fn new(e: Option<SparseColMatRef<'_, usize, f64>>, n: usize) -> Result<Self> {
        let e = e.map(Csc::from_faer).transpose()?;
        if let Some(e) = &e {
            if e.nrows != n || e.ncols != n {
                return Err(Error::DimensionMismatch {
                    what: "energy-norm matrix",
                    expected: n,
                    got: e.nrows,
                });
            }
        }
        Ok(Self { e })
    }
    pub fn norm(&self, a: &Csc, x: &[f64]) -> f64 {
        self.e
            .as_ref()
            .unwrap_or(a)
            .quadratic_form(x)
            .max(0.0)
            .sqrt()
    }
}

/// TNNMG for `J(v) = ½ vᵀAv − bᵀv + Σ_k φ_k(v_{p_k})` (docs/math.md §5):
/// nonlinear block Gauss–Seidel presmoothing, truncated linearisation, linear multigrid
/// V-cycle(s) on the truncated Newton system over the given hierarchy, exact line search.
/// `J` never increases. Stops on the energy norm of the correction.
///
/// Set-up (once per matrix): pattern analysis, Galerkin product patterns, coarse symbolic
/// Cholesky. Solves allocate nothing per iteration (except the optional energy history).
pub struct Tnnmg<const D: usize> {
    m: BlockedMatrix<D>,
    mg: LinearMultigrid,
    norm: EnergyNorm,
    opts: TnnmgOptions,
    active_of: Vec<usize>,
    /// Active blocks for which the multigrid hierarchy is set up incrementally.
    cached_active: Option<Vec<usize>>,
    v_old: Vec<f64>,
    av: Vec<f64>,
    res: Vec<f64>,
    c: Vec<f64>,
    lin: Vec<f64>,
}

impl<const D: usize> Tnnmg<D> {
    /// Sets up TNNMG for the symmetric positive definite (on the free dofs) matrix `a`
    /// (`n × n`, `n = D · nodes`, node-major, both triangles stored) with the dofs where
    /// `fixed` is true held at the values of the iterate. `prolongations[l]` maps level `l` to
    /// level `l + 1` in the same node-major numbering; the last one has `n` rows. An empty list
    /// gives a single-level method whose linear correction is an exact sparse solve.
    /// `energy_norm`: matrix of the stopping norm (paper: `K + M`); `None` uses `a`.
    ///
    /// # Errors
    /// Invalid shapes, non-symmetric pattern, missing diagonal, non-positive free diagonal,
    /// invalid options.
    pub fn new(
        a: SparseColMatRef<'_, usize, f64>,
        fixed: &[bool],
        prolongations: &[SparseColMat<usize, f64>],
        energy_norm: Option<SparseColMatRef<'_, usize, f64>>,
        opts: TnnmgOptions,
    ) -> Result<Self> {
        opts.stopping.validate()?;
        if opts.linear_reduction.is_some_and(|r| !(r > 0.0 && r < 1.0)) {
            return Err(Error::InvalidOption(
                "linear_reduction must lie in (0, 1)".into(),
            ));
        }
        if opts.nonlinear_sweeps == 0 || opts.v_cycles == 0 {
            return Err(Error::InvalidOption(
                "nonlinear_sweeps and v_cycles must be at least 1".into(),
            ));
        }
        let m = BlockedMatrix::<D>::new(Csc::from_faer(a)?, fixed)?;
        let prolongations = prolongations
            .iter()
            .map(|p| Csc::from_faer(p.as_ref()))
            .collect::<Result<Vec<_>>>()?;
        let mg = LinearMultigrid::new(
            m.a.clone(),
            prolongations,
            opts.smoothing.0,
            opts.smoothing.1,
        )?;
        let n = m.n();
        Ok(Self {
            norm: EnergyNorm::new(energy_norm, n)?,
            m,
            mg,
            opts,
            active_of: Vec::new(),
            cached_active: None,
            v_old: vec![0.0; n],
            av: vec![0.0; n],
            res: vec![0.0; n],
            c: vec![0.0; n],
            lin: vec![0.0; n],
        })
    }

    /// Number of multigrid levels.
    pub fn num_levels(&self) -> usize {
        self.mg.num_levels()
    }

    /// The options in use.
    pub fn options(&self) -> &TnnmgOptions {
        &self.opts
    }

    /// Whether the Hessian of block `p`'s nonlinearity is so large against `A`'s own block
    /// diagonal (ratio above [`RIGID_BLOCK_RATIO`] on a free component) that the block is
    /// numerically rigid: its Newton correction is negligible, and keeping it would put a
    /// contrast beyond double precision into the coarse operators (rate-and-state friction
    /// near the cutoff has `ϕ'' = κ/V` up to `κ/V_m`, e.g. 1e26 Pa·s/m against entries
    /// ~1e6 of `A`; the coarse Cholesky then fails as "not positive definite"). Such blocks
    /// are truncated like nonsmooth ones; the nonlinear smoother still updates them.
    fn is_rigid(&self, p: usize, hessian: &[[f64; D]; D]) -> bool {
        (0..D).any(|c| {
            let pos = self.m.block_pos[p][c][c];
            !self.m.fixed[D * p + c]
                && pos != usize::MAX
                && !(hessian[c][c] <= RIGID_BLOCK_RATIO * self.m.a.val[pos])
        })
    }

    /// One TNNMG iteration from `v`; returns the energy norm of the correction.
    fn iterate<N: BlockNonlinearity<D>>(
        &mut self,
        b: &[f64],
        nl: &N,
        v: &mut [f64],
    ) -> Result<f64> {
        let n = self.m.n();
        self.v_old.copy_from_slice(v);
        for _ in 0..self.opts.nonlinear_sweeps {
            self.m
                .nonlinear_gauss_seidel(b, nl, &self.active_of, v, false);
        }
        // Truncated linearisation at v.
        self.m.a.sym_mul(v, &mut self.av);
        for i in 0..n {
            self.res[i] = b[i] - self.av[i];
        }
        // Fine matrix H = A + Hessians on the active blocks, mask = fixed ∪ truncated.
        // Only the active blocks' entries change from one iteration to the next, so after
        // one full set-up the coarse operators are updated incrementally.
        let incremental = self.cached_active.as_deref() == Some(nl.active_blocks());
        if incremental {
            for &p in nl.active_blocks() {
                for r in 0..D {
                    for c in 0..D {
                        let pos = self.m.block_pos[p][r][c];
                        if pos != usize::MAX {
                            self.mg.fine.val[pos] = self.m.a.val[pos];
                        }
                    }
                }
                let mask = self.mg.fine_mask_mut();
                mask[D * p..D * p + D].copy_from_slice(&self.m.fixed[D * p..D * p + D]);
            }
        } else {
            self.mg.fine.val.copy_from_slice(&self.m.a.val);
            self.mg.fine_mask_mut().copy_from_slice(&self.m.fixed);
        }
        for (k, &p) in nl.active_blocks().iter().enumerate() {
            match nl.linearize(k, &load::<D>(v, p)) {
                Linearization::Smooth { hessian, .. } if self.is_rigid(p, &hessian) => {
                    let mask = self.mg.fine_mask_mut();
                    mask[D * p..D * p + D].fill(true);
                }
                Linearization::Smooth { gradient, hessian } => {
                    for r in 0..D {
                        self.res[D * p + r] -= gradient[r];
                        for c in 0..D {
                            let pos = self.m.block_pos[p][r][c];
                            if pos != usize::MAX {
                                self.mg.fine.val[pos] += hessian[r][c];
                            } else if hessian[r][c] != 0.0 {
                                return Err(Error::InvalidMatrix(format!(
                                    "block ({p}) lacks entry ({r}, {c}) needed by the Hessian"
                                )));
                            }
                        }
                    }
                }
                Linearization::Truncate => {
                    let mask = self.mg.fine_mask_mut();
                    mask[D * p..D * p + D].fill(true);
                }
            }
        }
        {
            let mask = self.mg.fine_mask_mut();
            for (r, &m) in self.res.iter_mut().zip(mask.iter()) {
                if m {
                    *r = 0.0;
                }
            }
        }
        if incremental {
            self.mg.update_incremental()?;
        } else {
            self.mg.update()?;
            let dofs: Vec<usize> = nl
                .active_blocks()
                .iter()
                .flat_map(|&p| (0..D).map(move |c| D * p + c))
                .collect();
            self.mg.set_variable_dofs(&dofs);
            self.cached_active = Some(nl.active_blocks().to_vec());
        }
        self.c.fill(0.0);
        let r0 = self.res.iter().map(|r| r * r).sum::<f64>().sqrt();
        for cycle in 0..self.opts.v_cycles {
            self.mg.v_cycle(&mut self.c, &self.res);
            let Some(reduction) = self.opts.linear_reduction else {
                continue;
            };
            if cycle + 1 == self.opts.v_cycles {
                break;
            }
            // Linear residual res − H c on the untruncated dofs (H: the fine matrix).
            self.mg.fine.sym_mul(&self.c, &mut self.lin);
            let mask = self.mg.fine_mask_mut();
            let r: f64 = self
                .res
                .iter()
                .zip(&self.lin)
                .zip(mask.iter())
                .filter(|(_, &m)| !m)
                .map(|((a, b), _)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt();
            if r <= reduction * r0 {
                break;
            }
        }
        // Blocks with a kink at zero whose correction passes through zero stop there.
        for (k, &p) in nl.active_blocks().iter().enumerate() {
            if !nl.kink_at_zero(k) {
                continue;
            }
            let r = D * p..D * p + D;
            let (vp, cp) = (&v[r.clone()], &self.c[r.clone()]);
            let crosses = vp.iter().any(|&x| x != 0.0)
                && vp.iter().zip(cp).map(|(a, c)| a * (a + c)).sum::<f64>() < 0.0;
            if crosses {
                for i in r {
                    self.c[i] = -v[i];
                }
            }
        }
        // Exact line search along c: g0 = cᵀ(Av − b), h = cᵀAc.
        let g0: f64 = self
            .c
            .iter()
            .zip(self.av.iter().zip(b))
            .map(|(c, (av, b))| c * (av - b))
            .sum();
        let h = self.m.a.quadratic_form(&self.c);
        if h > 0.0 && h.is_finite() {
            let s = exact_line_search(nl, v, &self.c, g0, h);
            for (vi, ci) in v.iter_mut().zip(&self.c) {
                *vi += s * ci;
            }
        }
        if v.iter().any(|x| !x.is_finite()) {
            return Err(Error::NonFinite("TNNMG iterate"));
        }
        for (o, x) in self.v_old.iter_mut().zip(v.iter()) {
            *o = x - *o;
        }
        Ok(self.norm.norm(&self.m.a, &self.v_old))
    }
}

impl<const D: usize> Iteration<D> for Tnnmg<D> {
    fn blocked(&self) -> &BlockedMatrix<D> {
        &self.m
    }
    fn energy_norm(&self) -> &EnergyNorm {
        &self.norm
    }
    fn active_of_mut(&mut self) -> &mut Vec<usize> {
        &mut self.active_of
    }
    fn iterate<N: BlockNonlinearity<D>>(
        &mut self,
        b: &[f64],
        nl: &N,
        v: &mut [f64],
    ) -> Result<f64> {
        Tnnmg::iterate(self, b, nl, v)
    }
}

impl<const D: usize> NonsmoothSolver<D> for Tnnmg<D> {
    fn name(&self) -> &'static str {
        "tnnmg"
    }

    fn dim(&self) -> usize {
        self.m.n()
    }

    fn stopping(&self) -> Stopping {
        self.opts.stopping
    }

    fn set_stopping(&mut self, stopping: Stopping) -> Result<()> {
        stopping.validate()?;
        self.opts.stopping = stopping;
        Ok(())
    }

    fn solve<N: BlockNonlinearity<D>>(
        &mut self,
        b: &[f64],
        nl: &N,
        v: &mut [f64],
    ) -> Result<SolveReport> {
        let (stop, record) = (self.opts.stopping, self.opts.record_energy);
        iterate_to_tolerance(self, "tnnmg", stop, record, b, nl, v)
    }
}
