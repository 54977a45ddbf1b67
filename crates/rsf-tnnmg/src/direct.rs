//! Direct reference solver: exact condensation onto the nonsmooth blocks.

use std::time::Instant;

use faer::sparse::SparseColMatRef;

use crate::cholesky::SparseCholesky;
use crate::csc::Csc;
use crate::error::{Error, Result};
use crate::nonlinearity::{BlockNonlinearity, Renumbered};
use crate::problem::BlockedMatrix;
use crate::report::{check_inputs, NonsmoothSolver, SolveReport, Stopping};
use crate::tnnmg::{Tnnmg, TnnmgOptions};

/// Options of [`DirectSolver`].
#[derive(Debug, Clone, PartialEq)]
pub struct DirectOptions {
    /// Stopping test of the Newton phase, in the norm of the Schur complement (the energy
    /// norm of `A` of the discrete harmonic extension). Default: absolute 1e-13, relative
    /// 1e-13, 200 iterations.
    pub stopping: Stopping,
}

impl Default for DirectOptions {
    fn default() -> Self {
        Self {
            stopping: Stopping {
                absolute: 1e-13,
                relative: 1e-13,
                max_iterations: 200,
            },
        }
    }
}

struct Condensed<const D: usize> {
    blocks: Vec<usize>,
    renumbered: Vec<usize>,
    /// Global dof → position among the interior (smooth, free) dofs R, or MAX.
    r_of: Vec<usize>,
    /// Interior dofs R (global indices).
    r_dofs: Vec<usize>,
    /// Global dof of each condensed position (`D k + c` → dof of block k, component c).
    x_dofs: Vec<usize>,
    arr: Csc,
    chol: SparseCholesky,
    inner: Tnnmg<D>,
    rhs_r: Vec<f64>,
    c: Vec<f64>,
    x: Vec<f64>,
}

/// Direct reference solver (docs/math.md §5, used to verify TNNMG and as a fast path for small
/// problems): the smooth free dofs `R` are eliminated exactly with a sparse Cholesky
/// factorisation of `A_RR` (faer, AMD ordering); the remaining problem on the nonsmooth
/// blocks has the dense Schur complement `S = A_XX − A_XR A_RR⁻¹ A_RX` and is solved by a
/// globalised (Gauss–Seidel-safeguarded, exactly line-searched) truncated Newton method
/// with exact dense linear solves; `R` is recovered by back-substitution.
///
/// The factorisation and `S` are computed on the first solve and reused while the set of
/// nonsmooth blocks stays the same (cost: one Cholesky of `A_RR` plus one solve per
/// condensed dof). Each solve then costs two sparse triangular solves plus the Newton phase.
pub struct DirectSolver<const D: usize> {
    m: BlockedMatrix<D>,
    opts: DirectOptions,
    cache: Option<Condensed<D>>,
}

impl<const D: usize> DirectSolver<D> {
    /// Set-up for the matrix `a` and fixed dofs `fixed` (as [`Tnnmg::new`]).
    ///
    /// # Errors
    /// Invalid shapes or pattern, invalid options.
    pub fn new(
        a: SparseColMatRef<'_, usize, f64>,
        fixed: &[bool],
        opts: DirectOptions,
    ) -> Result<Self> {
        opts.stopping.validate()?;
        Ok(Self {
            m: BlockedMatrix::<D>::new(Csc::from_faer(a)?, fixed)?,
            opts,
            cache: None,
        })
    }

    fn condense(&self, blocks: &[usize]) -> Result<Condensed<D>> {
        let n = self.m.n();
        let a = &self.m.a;
        let mut in_x = vec![false; n];
        for &p in blocks {
            if p >= n / D {
                return Err(Error::InvalidOption(format!(
                    "active block {p} out of range"
                )));
            }
            in_x[D * p..D * p + D].fill(true);
        }
        let mut r_of = vec![usize::MAX; n];
        let mut r_dofs = Vec::new();
        for i in 0..n {
            if !in_x[i] && !self.m.fixed[i] {
                r_of[i] = r_dofs.len();
                r_dofs.push(i);
            }
        }
        // A_RR as CSC (both triangles).
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut val = Vec::new();
        for &j in &r_dofs {
            let (rows, vals) = a.col(j);
            for (&i, &v) in rows.iter().zip(vals) {
                if r_of[i] != usize::MAX {
                    row_idx.push(r_of[i]);
                    val.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let nr = r_dofs.len();
        let arr = Csc {
            nrows: nr,
            ncols: nr,
            col_ptr,
            row_idx,
            val,
        };
        let mut chol = SparseCholesky::new(nr, &arr.col_ptr, &arr.row_idx)?;
        chol.factorize(&arr.val)
            .map_err(|_| Error::NotPositiveDefinite("A restricted to the smooth free dofs"))?;
        // Dense Schur complement on X (all components of the active blocks; fixed ones get
        // identity rows so that they stay at their values).
        let nx = D * blocks.len();
        let x_dofs: Vec<usize> = blocks
            .iter()
            .flat_map(|&p| (0..D).map(move |c| D * p + c))
            .collect();
        let x_fixed: Vec<bool> = x_dofs.iter().map(|&i| self.m.fixed[i]).collect();
        let mut s = Csc::dense_pattern_free(&x_fixed);
        let mut y = vec![0.0; nr];
        for (jx, &j) in x_dofs.iter().enumerate() {
            if x_fixed[jx] {
                let d = s.position(jx, jx).expect("diagonal present");
                s.val[d] = 1.0;
                continue;
            }
            y.fill(0.0);
            let (rows, vals) = a.col(j);
            for (&i, &v) in rows.iter().zip(vals) {
                if r_of[i] != usize::MAX {
                    y[r_of[i]] = v;
                }
            }
            chol.solve_in_place(&mut y);
            for (ix, &i) in x_dofs.iter().enumerate() {
                if self.m.fixed[i] {
                    continue;
                }
                // S_ij = A_ij − Σ_r A_ir y_r (A symmetric: row i = column i).
                let (rows, vals) = a.col(i);
                let mut sij = 0.0;
                for (&r, &v) in rows.iter().zip(vals) {
                    if r == j {
                        sij += v;
                    } else if r_of[r] != usize::MAX {
                        sij -= v * y[r_of[r]];
                    }
                }
                let pos = s.position(ix, jx).expect("free entry present");
                s.val[pos] = sij;
            }
        }
        // Symmetrise against round-off.
        for j in 0..nx {
            for i in 0..j {
                if let (Some(a), Some(b)) = (s.position(i, j), s.position(j, i)) {
                    let m = 0.5 * (s.val[a] + s.val[b]);
                    s.val[a] = m;
                    s.val[b] = m;
                }
            }
        }
        let s_fixed = x_fixed;
        let inner = Tnnmg::<D>::new(
            s.to_faer().as_ref(),
            &s_fixed,
            &[],
            None,
            TnnmgOptions {
                stopping: self.opts.stopping,
                ..TnnmgOptions::default()
            },
        )?;
        Ok(Condensed {
            blocks: blocks.to_vec(),
            renumbered: (0..blocks.len()).collect(),
            r_of,
            r_dofs,
            x_dofs,
            arr,
            chol,
            inner,
            rhs_r: vec![0.0; nr],
            c: vec![0.0; nx],
            x: vec![0.0; nx],
        })
    }
}

impl<const D: usize> NonsmoothSolver<D> for DirectSolver<D> {
    fn name(&self) -> &'static str {
        "direct"
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
        if let Some(c) = self.cache.as_mut() {
            c.inner.set_stopping(stopping)?;
        }
        Ok(())
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
        if self
            .cache
            .as_ref()
            .is_none_or(|c| c.blocks != nl.active_blocks())
        {
            self.cache = Some(self.condense(nl.active_blocks())?);
        }
        let a = &self.m.a;
        let fixed = &self.m.fixed;
        let cd = self.cache.as_mut().expect("condensed above");
        let _ = &cd.arr;
        // rhs_R = b_R − A_RG g (G: every dof not in R, with its value in v, X included
        // temporarily as 0 — the X coupling is handled through S).
        let in_x = |i: usize, cd: &Condensed<D>| cd.r_of[i] == usize::MAX && !fixed[i];
        for (k, &i) in cd.r_dofs.iter().enumerate() {
            let (rows, vals) = a.col(i);
            let mut s = b[i];
            for (&j, &aij) in rows.iter().zip(vals) {
                if fixed[j] {
                    s -= aij * v[j];
                }
            }
            cd.rhs_r[k] = s;
        }
        let _ = in_x;
        // z = A_RR⁻¹ rhs_R (stored in rhs_r).
        cd.chol.solve_in_place(&mut cd.rhs_r);
        // c_X = b_X − A_XG g − A_XR z; fixed X components: c = value (identity row in S).
        for (ix, &i) in cd.x_dofs.iter().enumerate() {
            if fixed[i] {
                cd.c[ix] = v[i];
                cd.x[ix] = v[i];
                continue;
            }
            let (rows, vals) = a.col(i);
            let mut s = b[i];
            for (&j, &aij) in rows.iter().zip(vals) {
                if fixed[j] {
                    s -= aij * v[j];
                } else if cd.r_of[j] != usize::MAX {
                    s -= aij * cd.rhs_r[cd.r_of[j]];
                }
            }
            cd.c[ix] = s;
            cd.x[ix] = v[i];
        }
        let renumbered = Renumbered {
            inner: nl,
            blocks: &cd.renumbered,
        };
        let mut report = cd.inner.solve(&cd.c, &renumbered, &mut cd.x)?;
        // Back-substitution: y = A_RR⁻¹ (b_R − A_RG g − A_RX x).
        for (ix, &i) in cd.x_dofs.iter().enumerate() {
            v[i] = cd.x[ix];
        }
        for (k, &i) in cd.r_dofs.iter().enumerate() {
            let (rows, vals) = a.col(i);
            let mut s = b[i];
            for (&j, &aij) in rows.iter().zip(vals) {
                if cd.r_of[j] == usize::MAX {
                    s -= aij * v[j];
                }
            }
            cd.rhs_r[k] = s;
        }
        cd.chol.solve_in_place(&mut cd.rhs_r);
        for (k, &i) in cd.r_dofs.iter().enumerate() {
            v[i] = cd.rhs_r[k];
        }
        if v.iter().any(|x| !x.is_finite()) {
            return Err(Error::NonFinite("direct solution"));
        }
        report.seconds = start.elapsed().as_secs_f64();
        Ok(report)
    }
}
