//! Truncated linear multigrid on a hierarchy of Galerkin operators.

use crate::cholesky::SparseCholesky;
use crate::csc::Csc;
use crate::error::{Error, Result};
use crate::galerkin::Galerkin;

#[derive(Debug)]
struct Level {
    diag: Vec<usize>,
    mask: Vec<bool>,
    x: Vec<f64>,
    rhs: Vec<f64>,
    res: Vec<f64>,
}

impl Level {
    fn new(a: &Csc) -> Result<Self> {
        let n = a.nrows;
        Ok(Self {
            diag: a.diagonal_positions()?,
            mask: vec![false; n],
            x: vec![0.0; n],
            rhs: vec![0.0; n],
            res: vec![0.0; n],
        })
    }
}

/// Multigrid V-cycle for `H x = r` with truncation: masked fine dofs are excluded (rows and
/// columns), the truncation is carried to the coarse levels through Galerkin products
/// `P_tᵀ H P_t`, coarse dofs whose diagonal vanishes are excluded as well. Smoother:
/// pointwise Gauss–Seidel (forward before, backward after the coarse correction); coarsest
/// level: sparse Cholesky (pattern analysed once).
#[derive(Debug)]
pub(crate) struct LinearMultigrid {
    /// Fine-level matrix; its values are set by the caller before [`update`](Self::update).
    pub fine: Csc,
    /// `galerkin[l]` maps level `l+1` (finer) to level `l`; index 0 is next to the coarsest.
    galerkin: Vec<Galerkin>,
    /// Levels, coarsest first; the last one is the fine level.
    levels: Vec<Level>,
    coarse: SparseCholesky,
    coarse_values: Vec<f64>,
    pre: usize,
    post: usize,
}

impl LinearMultigrid {
    /// `prolongations[l]` maps level `l` to level `l + 1`, the last one into the fine level
    /// whose pattern `fine` gives. Empty: a single level solved exactly.
    pub fn new(fine: Csc, prolongations: Vec<Csc>, pre: usize, post: usize) -> Result<Self> {
        let mut expected = fine.nrows;
        for (l, p) in prolongations.iter().enumerate().rev() {
            if p.nrows != expected {
                return Err(Error::DimensionMismatch {
                    what: "prolongation rows",
                    expected,
                    got: p.nrows,
                });
            }
            if p.ncols == 0 {
                return Err(Error::InvalidMatrix(format!(
                    "prolongation {l} has no columns"
                )));
            }
            expected = p.ncols;
        }
        let mut galerkin_rev = Vec::new();
        let mut levels_rev = vec![Level::new(&fine)?];
        {
            let mut current = &fine;
            for p in prolongations.iter().rev() {
                galerkin_rev.push(Galerkin::new(current, p.clone()));
                current = &galerkin_rev.last().unwrap().c;
                levels_rev.push(Level::new(current)?);
            }
        }
        galerkin_rev.reverse();
        levels_rev.reverse();
        let coarse_pat = galerkin_rev.first().map(|g| &g.c).unwrap_or(&fine);
        let coarse =
            SparseCholesky::new(coarse_pat.nrows, &coarse_pat.col_ptr, &coarse_pat.row_idx)?;
        let coarse_values = vec![0.0; coarse_pat.val.len()];
        Ok(Self {
            fine,
            galerkin: galerkin_rev,
            levels: levels_rev,
            coarse,
            coarse_values,
            pre,
            post,
        })
    }

    /// Number of levels (≥ 1).
    pub fn num_levels(&self) -> usize {
        self.levels.len()
    }

    /// Mask of the fine level (truncated dofs); set before [`update`](Self::update).
    pub fn fine_mask_mut(&mut self) -> &mut [bool] {
        &mut self.levels.last_mut().unwrap().mask
    }

    /// Recomputes the coarse operators and the coarse factorisation after the fine matrix
    /// values or the fine mask changed.
    pub fn update(&mut self) -> Result<()> {
        let nl = self.levels.len();
        for l in (0..nl - 1).rev() {
            let (g_lo, g_hi) = self.galerkin.split_at_mut(l + 1);
            let finer: &Csc = if l + 2 == nl { &self.fine } else { &g_hi[0].c };
            g_lo[l].update(finer, &self.levels[l + 1].mask);
            let c = &g_lo[l].c;
            let level = &mut self.levels[l];
            let scale = level
                .diag
                .iter()
                .map(|&d| c.val[d].abs())
                .fold(0.0f64, f64::max);
            for (i, &d) in level.diag.iter().enumerate() {
                level.mask[i] = !(c.val[d] > 1e-14 * scale);
            }
        }
        // Coarsest factorisation with masked rows/columns replaced by identity.
        let a = if self.levels.len() == 1 {
            &self.fine
        } else {
            &self.galerkin[0].c
        };
        let mask = &self.levels[0].mask;
        for j in 0..a.ncols {
            for k in a.col_ptr[j]..a.col_ptr[j + 1] {
                let i = a.row_idx[k];
                self.coarse_values[k] = if mask[i] || mask[j] {
                    if i == j {
                        1.0
                    } else {
                        0.0
                    }
                } else {
                    a.val[k]
                };
            }
        }
        self.coarse.factorize(&self.coarse_values)
    }

    fn smooth(a: &Csc, level: &mut Level, sweeps: usize, reverse: bool) {
        let n = a.nrows;
        for _ in 0..sweeps {
            for q in 0..n {
                let i = if reverse { n - 1 - q } else { q };
                if level.mask[i] {
                    continue;
                }
                let r = level.rhs[i] - a.sym_row_dot(i, &level.x);
                level.x[i] += r / a.val[level.diag[i]];
            }
        }
    }

    fn cycle(&mut self, l: usize) {
        if l == 0 {
            let level = &mut self.levels[0];
            level.x.copy_from_slice(&level.rhs);
            for (x, &m) in level.x.iter_mut().zip(&level.mask) {
                if m {
                    *x = 0.0;
                }
            }
            self.coarse.solve_in_place(&mut level.x);
            return;
        }
        let nl = self.levels.len();
        {
            let a = if l + 1 == nl {
                &self.fine
            } else {
                &self.galerkin[l].c
            };
            Self::smooth(a, &mut self.levels[l], self.pre, false);
            let level = &mut self.levels[l];
            for i in 0..a.nrows {
                level.res[i] = if level.mask[i] {
                    0.0
                } else {
                    level.rhs[i] - a.sym_row_dot(i, &level.x)
                };
            }
        }
        {
            let (lo, hi) = self.levels.split_at_mut(l);
            let (fine, coarse) = (&hi[0], &mut lo[l - 1]);
            self.galerkin[l - 1].restrict(&fine.res, &fine.mask, &mut coarse.rhs);
            coarse.x.fill(0.0);
        }
        self.cycle(l - 1);
        {
            let (lo, hi) = self.levels.split_at_mut(l);
            let (fine, coarse) = (&mut hi[0], &lo[l - 1]);
            self.galerkin[l - 1].prolong_add(&coarse.x, &fine.mask, &mut fine.x);
        }
        let a = if l + 1 == nl {
            &self.fine
        } else {
            &self.galerkin[l].c
        };
        Self::smooth(a, &mut self.levels[l], self.post, true);
    }

    /// One V-cycle improving `x` for `H x = rhs` on the unmasked dofs (masked entries of `x`
    /// are kept, and must be 0 for a correction).
    pub fn v_cycle(&mut self, x: &mut [f64], rhs: &[f64]) {
        let l = self.levels.len() - 1;
        let level = &mut self.levels[l];
        level.x.copy_from_slice(x);
        level.rhs.copy_from_slice(rhs);
        self.cycle(l);
        x.copy_from_slice(&self.levels[l].x);
    }
}
