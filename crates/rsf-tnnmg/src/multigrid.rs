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
    /// Per level: the dofs whose rows, columns or masks may change between incremental
    /// updates (index `l` for level `l`; the fine level's set is given by the caller).
    variable: Vec<Vec<usize>>,
    /// Per Galerkin operator `l`: the coarse columns to recompute incrementally.
    affected: Vec<Vec<usize>>,
    /// Diagonal per level at the last full update (reference for the zero-diagonal test).
    ref_diag: Vec<Vec<f64>>,
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
            variable: Vec::new(),
            affected: Vec::new(),
            ref_diag: Vec::new(),
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
            // A coarse dof all of whose fine support is truncated has an exactly zero
            // row (no term is accumulated); it is excluded from smoothing and the coarse
            // solve. The diagonal is kept as the reference for incremental updates.
            if self.ref_diag.len() != nl {
                self.ref_diag = vec![Vec::new(); nl];
            }
            let r = &mut self.ref_diag[l];
            r.clear();
            for (i, &d) in level.diag.iter().enumerate() {
                let cii = c.val[d];
                level.mask[i] = !(cii > 0.0);
                r.push(cii.max(0.0));
            }
        }
        self.factorize_coarsest()
    }

    /// Declares the fine dofs whose matrix rows/columns or mask may change between calls of
    /// [`update_incremental`](Self::update_incremental), and derives the affected sets of
    /// every coarser level.
    pub fn set_variable_dofs(&mut self, fine_dofs: &[usize]) {
        let nl = self.levels.len();
        self.variable = vec![Vec::new(); nl];
        self.affected = vec![Vec::new(); nl.saturating_sub(1)];
        self.variable[nl - 1] = fine_dofs.to_vec();
        for l in (0..nl - 1).rev() {
            let mut changed = vec![false; self.levels[l + 1].mask.len()];
            for &i in &self.variable[l + 1] {
                changed[i] = true;
            }
            let cols = self.galerkin[l].affected_columns(&changed);
            self.variable[l] = cols.clone();
            self.affected[l] = cols;
        }
    }

    /// Like [`update`](Self::update), recomputing only what the variable dofs (see
    /// [`set_variable_dofs`](Self::set_variable_dofs)) can change. Requires a full
    /// [`update`](Self::update) with the same base values before.
    pub fn update_incremental(&mut self) -> Result<()> {
        let nl = self.levels.len();
        for l in (0..nl - 1).rev() {
            let (g_lo, g_hi) = self.galerkin.split_at_mut(l + 1);
            let finer: &Csc = if l + 2 == nl { &self.fine } else { &g_hi[0].c };
            g_lo[l].update_columns(finer, &self.levels[l + 1].mask, &self.affected[l]);
            let c = &g_lo[l].c;
            let level = &mut self.levels[l];
            let r = &self.ref_diag[l];
            for &i in &self.variable[l] {
                // Relative to the last full update, so that round-off left by cancelling
                // contributions of truncated dofs is not mistaken for a coupling.
                level.mask[i] = !(c.val[level.diag[i]] > 1e-13 * r[i]);
            }
        }
        self.factorize_coarsest()
    }

    fn factorize_coarsest(&mut self) -> Result<()> {
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
        match self.coarse.factorize(&self.coarse_values) {
            Ok(()) => Ok(()),
            Err(_) => {
                // Truncation can make the truncated prolongation P_t rank deficient, and then
                // P_tᵀ H P_t is only semidefinite. Its kernel is ker P_t: coarse vectors that
                // prolongate to zero, so any component there is harmless. A relative diagonal
                // shift makes the factorisation well defined without changing P_t x_c.
                for j in 0..a.ncols {
                    for k in a.col_ptr[j]..a.col_ptr[j + 1] {
                        if a.row_idx[k] == j && !mask[j] {
                            self.coarse_values[k] *= 1.0 + 1e-10;
                            self.coarse_values[k] += f64::MIN_POSITIVE;
                        }
                    }
                }
                self.coarse.factorize(&self.coarse_values)
            }
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn laplacian_1d(n: usize) -> Csc {
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut val = Vec::new();
        for j in 0..n {
            for i in j.saturating_sub(1)..(j + 2).min(n) {
                row_idx.push(i);
                val.push(if i == j { 2.0 } else { -1.0 });
            }
            col_ptr.push(row_idx.len());
        }
        Csc {
            nrows: n,
            ncols: n,
            col_ptr,
            row_idx,
            val,
        }
    }

    fn interpolation(nc: usize) -> Csc {
        let nf = 2 * nc - 1;
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut val = Vec::new();
        for j in 0..nc {
            for (i, v) in [
                (2 * j as i64 - 1, 0.5),
                (2 * j as i64, 1.0),
                (2 * j as i64 + 1, 0.5),
            ] {
                if i >= 0 && (i as usize) < nf {
                    row_idx.push(i as usize);
                    val.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        Csc {
            nrows: nf,
            ncols: nc,
            col_ptr,
            row_idx,
            val,
        }
    }

    /// The incremental update of the coarse operators equals a full recomputation after
    /// changes of the fine matrix and mask restricted to the declared variable dofs.
    #[test]
    fn incremental_update_matches_full_update() {
        let n = 33;
        let ps = vec![interpolation(5), interpolation(9), interpolation(17)];
        let fine = laplacian_1d(n);
        let mut inc = LinearMultigrid::new(fine.clone(), ps.clone(), 1, 1).unwrap();
        let mut full = LinearMultigrid::new(fine, ps, 1, 1).unwrap();
        inc.update().unwrap();
        let variable = [0usize, 1, 2, 3];
        inc.set_variable_dofs(&variable);
        for round in 0..4 {
            for m in [&mut inc, &mut full] {
                for &i in &variable {
                    let d = m.fine.position(i, i).unwrap();
                    m.fine.val[d] = 2.0 + 1e3 * (round as f64 + i as f64);
                }
                let mask = m.fine_mask_mut();
                mask[0] = round % 2 == 0;
                mask[2] = round == 3;
            }
            inc.update_incremental().unwrap();
            full.update().unwrap();
            for (gi, gf) in inc.galerkin.iter().zip(&full.galerkin) {
                assert_eq!(gi.c.val, gf.c.val, "round {round}");
            }
            for (li, lf) in inc.levels.iter().zip(&full.levels) {
                assert_eq!(li.mask, lf.mask);
            }
        }
    }
}
