//! The velocity problem condensed onto the nonsmooth blocks, solved densely:
//!
//! ```text
//! minimise ½ xᵀSx − gᵀx + Σ_k φ_k(x_k)
//! ```
//!
//! over the free components of the blocks `x_k ∈ R^D` (fixed components hold their values),
//! with `S` the dense Schur complement (docs/math.md §8).
//!
//! One iteration = a nonlinear block Gauss–Seidel sweep (exact block minimisation; the
//! global convergence guarantee) followed by a truncated Newton step on the **soft**
//! blocks — those whose nonlinearity is twice differentiable there with a Hessian not
//! larger than `soft_ratio` times the diagonal of `S` — with a dense Cholesky solve, kink
//! clipping and a line search (a one-sided window, see `line_search`). Stiff blocks (e.g.
//! rate-and-state friction in deep stick, where `ϕ'' = aσ̄_n/V` exceeds the elastic
//! stiffness by orders of magnitude) are nearly decoupled and converge in the sweep at a
//! rate of about `1/soft_ratio`; excluding them keeps the dense factorisation small
//! (empty while the whole fault sticks).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::cholesky_in_place;
use faer::Mat;
use rsf_linalg::Parallelism;

use super::dense::{
    cholesky_solve, dense_par, dense_scratch, factor_norm_sq, lower_cholesky, quadratic_form,
    small_llt_params,
};
use super::norm_bounds::{euclidean, NormBounds, NORM_BOUNDS_MIN};
use crate::error::{Error, Result};
use rsf_nonsmooth::ProblemError;
use rsf_nonsmooth::{BlockNonlinearity, Linearization, SolveReport, Stopping};

/// Dense condensed problem and the state of its iteration.
pub(super) struct DenseFault<const D: usize> {
    nb: usize,
    m: usize,
    /// `S`, `m × m` column-major, on the free components.
    s: Vec<f64>,
    /// Matrix of the stopping norm on the free components, `m × m` (None: `S`).
    norm: Option<Vec<f64>>,
    /// Its Cholesky factor `L`, stored by rows (`m × m` row-major, zero above the
    /// diagonal; None if it could not be factorised): `‖x‖² = ‖Lᵀx‖²` costs half the `m²`
    /// of `xᵀ N x`.
    norm_factor: Option<Vec<f64>>,
    /// Bounds of the stopping norm by the Euclidean one (None: not set up yet; `Some(None)`:
    /// not used, for small or ill-conditioned factors).
    norm_bounds: Option<Option<NormBounds>>,
    /// Evaluations of the stopping norm (tests count them).
    #[cfg(test)]
    norm_evaluations: std::sync::atomic::AtomicUsize,
    /// Free component `i` ↦ position `D k + c` in the block vector.
    comp: Vec<usize>,
    /// Free components of block `k`: `first[k]..first[k + 1]`.
    first: Vec<usize>,
    free: Vec<[bool; D]>,
    /// Current iterate as a block vector (length `D nb`, fixed components hold values).
    pub(super) xb: Vec<f64>,
    /// Condensed right-hand side on the free components.
    pub(super) g: Vec<f64>,
    r: Vec<f64>,
    x_old: Vec<f64>,
    x_start: Vec<f64>,
    dx: Vec<f64>,
    c: Vec<f64>,
    cb: Vec<f64>,
    sc: Vec<f64>,
    grad: Vec<f64>,
    hess: Vec<[[f64; D]; D]>,
    soft_blocks: Vec<usize>,
    soft: Vec<usize>,
    is_soft: Vec<bool>,
    /// Soft components whose `S_QQ + H` is factorised in `h` (for simplified Newton steps).
    factored: Vec<usize>,
    /// Whether the factorisation in `h` may be reused (the last step was accepted by the
    /// line search with `s > 0`).
    reuse: bool,
    h: Mat<f64>,
    rhs: Mat<f64>,
    mem: MemBuffer,
    soft_ratio: f64,
    /// Threads of the dense factorisation of large Newton systems.
    par: Parallelism,
    /// Scratch of the triangular solves.
    y: Vec<f64>,
    /// Norm of the change of the last solve.
    pub(super) change: f64,
    /// Whether `r = g − S x` is up to date (reset when `g` or `xb` are set from outside).
    pub(super) residual_valid: bool,
}

impl<const D: usize> DenseFault<D> {
    /// `s`: dense `m × m` Schur complement on the free components; `norm`: the stopping
    /// norm's matrix on them (or `None`: `S`); `free[k]`: the free components of block `k`
    /// (their count summing to `m`).
    pub(super) fn new(
        s: Vec<f64>,
        norm: Option<Vec<f64>>,
        free: Vec<[bool; D]>,
        soft_ratio: f64,
        par: Parallelism,
    ) -> Self {
        let nb = free.len();
        let mut comp = Vec::new();
        let mut first = Vec::with_capacity(nb + 1);
        for (k, f) in free.iter().enumerate() {
            first.push(comp.len());
            for (c, &is_free) in f.iter().enumerate() {
                if is_free {
                    comp.push(D * k + c);
                }
            }
        }
        first.push(comp.len());
        let m = comp.len();
        debug_assert_eq!(s.len(), m * m);
        let mem = MemBuffer::new(dense_scratch(m, par));
        let norm_factor = lower_cholesky(norm.as_deref().unwrap_or(&s), m);
        Self {
            nb,
            m,
            s,
            norm,
            norm_factor,
            norm_bounds: None,
            #[cfg(test)]
            norm_evaluations: Default::default(),
            comp,
            first,
            free,
            xb: vec![0.0; D * nb],
            g: vec![0.0; m],
            r: vec![0.0; m],
            x_old: vec![0.0; m],
            x_start: vec![0.0; m],
            dx: vec![0.0; m],
            c: vec![0.0; m],
            cb: vec![0.0; D * nb],
            sc: vec![0.0; m],
            grad: vec![0.0; m],
            hess: vec![[[0.0; D]; D]; nb],
            soft_blocks: Vec::with_capacity(nb),
            soft: Vec::with_capacity(m),
            is_soft: vec![false; nb],
            factored: Vec::with_capacity(m),
            reuse: false,
            h: Mat::zeros(m, m),
            rhs: Mat::zeros(m, 1),
            mem,
            soft_ratio,
            par,
            y: vec![0.0; m],
            change: f64::INFINITY,
            residual_valid: false,
        }
    }

    /// Factorises large Newton systems with `par` from now on (the scratch grows if
    /// needed; a kept factorisation stays valid: its bits do not depend on `par`).
    pub(super) fn set_parallelism(&mut self, par: Parallelism) {
        if par != self.par {
            self.par = par;
            self.mem = MemBuffer::new(dense_scratch(self.m, par));
        }
    }

    /// The parallelism of the dense factorisations.
    pub(super) fn parallelism(&self) -> Parallelism {
        self.par
    }

    /// Drops the reusable factorisation (the next Newton step factorises afresh).
    pub(super) fn forget_factorization(&mut self) {
        self.reuse = false;
        self.factored.clear();
    }

    /// Number of unknowns of the last factorised Newton system (0 if none is kept).
    #[cfg(test)]
    pub(super) fn factored_len(&self) -> usize {
        self.factored.len()
    }

    /// Turns the bounds of the stopping norm off (every test evaluates the norm).
    #[cfg(test)]
    pub(super) fn without_norm_bounds(&mut self) {
        self.norm_bounds = Some(None);
    }

    /// The bounds of the stopping norm (None before the first solve or where not used).
    #[cfg(test)]
    pub(super) fn norm_bounds(&self) -> Option<NormBounds> {
        self.norm_bounds.flatten()
    }

    /// Evaluations of the stopping norm so far.
    #[cfg(test)]
    pub(super) fn norm_evaluations(&self) -> usize {
        self.norm_evaluations
            .load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Number of free components.
    pub(super) fn num_free(&self) -> usize {
        self.m
    }

    /// Block vector position of free component `i`.
    pub(super) fn comp(&self, i: usize) -> usize {
        self.comp[i]
    }

    /// `‖x‖` in the stopping norm for a vector on the free components.
    #[inline(always)]
    fn norm_of(&self, x: &[f64]) -> f64 {
        #[cfg(test)]
        self.norm_evaluations
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let m = self.m;
        let x = &x[..m];
        if let Some(l) = &self.norm_factor {
            return factor_norm_sq(l, x).sqrt();
        }
        quadratic_form(self.norm.as_deref().unwrap_or(&self.s), x)
            .max(0.0)
            .sqrt()
    }

    #[inline(always)]
    fn gather(&self, out: &mut [f64]) {
        for (o, &p) in out.iter_mut().zip(&self.comp) {
            *o = self.xb[p];
        }
    }

    /// `r = g − S x`.
    #[inline(always)]
    fn residual(&mut self) {
        self.r.copy_from_slice(&self.g);
        for j in 0..self.m {
            let xj = self.xb[self.comp[j]];
            if xj != 0.0 {
                let col = &self.s[j * self.m..(j + 1) * self.m];
                for (ri, sij) in self.r.iter_mut().zip(col) {
                    *ri -= sij * xj;
                }
            }
        }
    }

    /// One forward nonlinear block Gauss–Seidel sweep over the blocks that are not soft.
    #[inline(always)]
    fn sweep<N: BlockNonlinearity<D>>(&mut self, nl: &N) {
        let m = self.m;
        for k in 0..self.nb {
            let (f0, f1) = (self.first[k], self.first[k + 1]);
            if f0 == f1 {
                continue;
            }
            let mut a = [[0.0; D]; D];
            let mut rk = [0.0; D];
            let mut xk = [0.0; D];
            xk.copy_from_slice(&self.xb[D * k..D * k + D]);
            for i in f0..f1 {
                let ci = self.comp[i] - D * k;
                let mut s = self.r[i];
                for i2 in f0..f1 {
                    let ci2 = self.comp[i2] - D * k;
                    let sij = self.s[i2 * m + i];
                    a[ci][ci2] = sij;
                    s += sij * xk[ci2];
                }
                rk[ci] = s;
            }
            nl.minimize_block(k, &a, &rk, &self.free[k], &mut xk);
            for i in f0..f1 {
                let p = self.comp[i];
                let delta = xk[p - D * k] - self.xb[p];
                if delta != 0.0 {
                    self.xb[p] += delta;
                    let col = &self.s[i * m..(i + 1) * m];
                    for (ri, sij) in self.r.iter_mut().zip(col) {
                        *ri -= sij * delta;
                    }
                }
            }
        }
    }

    /// Linearises every block at the current iterate and marks the soft ones (twice
    /// differentiable, Hessian at most `soft_ratio` times the diagonal of `S`), storing their
    /// gradients and Hessians.
    #[inline(always)]
    fn classify<N: BlockNonlinearity<D>>(&mut self, nl: &N) {
        let m = self.m;
        self.soft_blocks.clear();
        self.soft.clear();
        for k in 0..self.nb {
            self.is_soft[k] = false;
            let (f0, f1) = (self.first[k], self.first[k + 1]);
            if f0 == f1 {
                continue;
            }
            let mut xk = [0.0; D];
            xk.copy_from_slice(&self.xb[D * k..D * k + D]);
            let Linearization::Smooth { gradient, hessian } = nl.linearize(k, &xk) else {
                continue;
            };
            let soft = (f0..f1).all(|i| {
                let c = self.comp[i] - D * k;
                hessian[c][c].is_finite() && hessian[c][c] <= self.soft_ratio * self.s[i * m + i]
            });
            if !soft {
                continue;
            }
            self.is_soft[k] = true;
            self.soft_blocks.push(k);
            self.hess[k] = hessian;
            for i in f0..f1 {
                let c = self.comp[i] - D * k;
                self.grad[i] = gradient[c];
                self.soft.push(i);
            }
        }
    }

    /// Truncated Newton step on the soft blocks (classified before) with a line search.
    /// The factorisation of `S_QQ + H` is reused while the soft set stays and the previous
    /// step was accepted (a simplified Newton step: `S_QQ + H` of a nearby point is SPD, so
    /// its direction is one of descent, and the line search keeps the step a descent step;
    /// reusing also after damped steps halves the factorisations of the main job at j = 4,
    /// 16072 → 8337, for 15 % more iterations) — but a reused factorisation whose step had
    /// to be damped is dropped (see the end of this function).
    #[inline(always)]
    fn newton<N: BlockNonlinearity<D>>(&mut self, nl: &N) {
        let m = self.m;
        let q = self.soft.len();
        if q == 0 {
            return;
        }
        // rhs = r_Q − ∇φ_Q (the negative gradient of J); H = S_QQ + Hessians.
        for (b, &j) in self.soft.iter().enumerate() {
            self.rhs[(b, 0)] = self.r[j] - self.grad[j];
        }
        let fresh = !(self.reuse && self.factored == self.soft);
        if fresh {
            for (b, &j) in self.soft.iter().enumerate() {
                let s_col = &self.s[j * m..(j + 1) * m];
                let h_col = self
                    .h
                    .col_mut(b)
                    .try_as_col_major_mut()
                    .expect("columns of a dense faer matrix are contiguous")
                    .as_slice_mut();
                for (h, &i) in h_col.iter_mut().zip(&self.soft) {
                    *h = s_col[i];
                }
            }
            let mut pos = 0;
            for &k in &self.soft_blocks {
                let (f0, f1) = (self.first[k], self.first[k + 1]);
                for i in f0..f1 {
                    for i2 in f0..f1 {
                        let (c, c2) = (self.comp[i] - D * k, self.comp[i2] - D * k);
                        self.h[(pos + i - f0, pos + i2 - f0)] += self.hess[k][c][c2];
                    }
                }
                pos += f1 - f0;
            }
            self.factored.clear();
            let stack = MemStack::new(&mut self.mem);
            let hq = self.h.as_mut().submatrix_mut(0, 0, q, q);
            let par = dense_par(q, self.par);
            if cholesky_in_place(hq, Default::default(), par, stack, small_llt_params()).is_err() {
                // Not positive definite in floating point (extreme contrast): the sweep
                // alone still converges.
                self.reuse = false;
                return;
            }
            self.factored.extend_from_slice(&self.soft);
        }
        cholesky_solve(
            self.h.as_ref().submatrix(0, 0, q, q),
            &mut self.y[..q],
            self.rhs.as_mut().col_mut(0).subrows_mut(0, q),
        );
        self.c.fill(0.0);
        for (a, &i) in self.soft.iter().enumerate() {
            self.c[i] = self.rhs[(a, 0)];
        }
        // Blocks with a kink at zero whose correction passes through zero stop there.
        for &k in &self.soft_blocks {
            if !nl.kink_at_zero(k) {
                continue;
            }
            let (f0, f1) = (self.first[k], self.first[k + 1]);
            let xk = &self.xb[D * k..D * k + D];
            let mut dot = 0.0;
            for i in f0..f1 {
                let p = self.comp[i] - D * k;
                dot += xk[p] * (xk[p] + self.c[i]);
            }
            if xk.iter().any(|&x| x != 0.0) && dot < 0.0 {
                for i in f0..f1 {
                    self.c[i] = -xk[self.comp[i] - D * k];
                }
            }
        }
        // S c over the soft columns, g0 = cᵀ(Sx − g) = −cᵀr, h = cᵀSc.
        self.sc.fill(0.0);
        self.cb.fill(0.0);
        let mut g0 = 0.0;
        for &j in &self.soft {
            let cj = self.c[j];
            self.cb[self.comp[j]] = cj;
            g0 -= cj * self.r[j];
            if cj != 0.0 {
                let col = &self.s[j * m..(j + 1) * m];
                for (o, sij) in self.sc.iter_mut().zip(col) {
                    *o += sij * cj;
                }
            }
        }
        let h: f64 = self.soft.iter().map(|&j| self.c[j] * self.sc[j]).sum();
        if !(h > 0.0 && h.is_finite()) {
            self.reuse = false;
            return;
        }
        let step = self.line_search(nl, g0, h);
        // A fresh factorisation may serve again after any accepted step; a reused one only
        // while its steps are taken in full. A damped simplified Newton step means the
        // stale Hessian no longer describes the problem, and reusing it regardless could
        // leave the iteration contracting at a linear rate close to 1 (slider, τ = 0.75 s,
        // j = 5 and 6: no convergence in 500 iterations; with this rule, a few per solve).
        self.reuse = step > 0.0 && (fresh || step >= 1.0);
        if step > 0.0 {
            for &j in &self.soft {
                self.xb[self.comp[j]] += step * self.c[j];
            }
            for (ri, sci) in self.r.iter_mut().zip(&self.sc) {
                *ri -= step * sci;
            }
        }
    }

    /// `(ψ'⁻(s), ψ'⁺(s), ψ''(s))` of `ψ(s) = J(x + s c)`, `c` supported on the soft blocks;
    /// `ψ''` counts only the blocks that are twice differentiable at `x + s c`.
    #[inline(always)]
    fn derivatives<N: BlockNonlinearity<D>>(
        &self,
        nl: &N,
        g0: f64,
        h: f64,
        s: f64,
    ) -> (f64, f64, f64) {
        let mut lo = g0 + s * h;
        let mut hi = lo;
        let mut curv = h;
        for &k in &self.soft_blocks {
            let mut d = [0.0; D];
            d.copy_from_slice(&self.cb[D * k..D * k + D]);
            if d.iter().all(|&x| x == 0.0) {
                continue;
            }
            let mut x = [0.0; D];
            for i in 0..D {
                x[i] = self.xb[D * k + i] + s * d[i];
            }
            // Where φ_k is twice differentiable its linearisation gives both derivatives;
            // elsewhere the one-sided directional derivatives.
            match nl.linearize(k, &x) {
                Linearization::Smooth { gradient, hessian } => {
                    let mut g = 0.0;
                    for i in 0..D {
                        g += gradient[i] * d[i];
                        for j in 0..D {
                            curv += d[i] * hessian[i][j] * d[j];
                        }
                    }
                    lo += g;
                    hi += g;
                }
                Linearization::Truncate => {
                    let (dl, dr) = nl.directional_derivatives(k, &x, &d);
                    lo += dl;
                    hi += dr;
                }
            }
        }
        (lo, hi, curv)
    }

    /// Step `s ≥ 0` along the Newton direction: safeguarded Newton on the monotone
    /// derivative `ψ'` starting at `s = 1` (bracket kept from the signs of `ψ'`, bisection
    /// when a Newton step leaves it), ended when `−½|ψ'(0)| ≤ ψ'(s) ≤ 1e-3 |ψ'(0)|` or the
    /// bracket has collapsed. The window is one-sided on purpose: a step short of the
    /// minimiser (`ψ'(s) < 0`) decreases the energy whatever the curvature between (`ψ'` is
    /// monotone), so it is accepted as soon as it has removed half of the slope, while a step
    /// beyond it must be nearly exact, since there `ψ(s) ≤ ψ(0)` is not implied by a small
    /// `ψ'(s)`. `ψ` is convex, so the energy does not increase. (Accepting short steps early
    /// against the former symmetric `|ψ'(s)| ≤ 1e-3 |ψ'(0)|`, with the reuse below:
    /// long_run, 40 s at j = 4, 0.82× CPU with the same events; main job unchanged.)
    #[inline(always)]
    fn line_search<N: BlockNonlinearity<D>>(&self, nl: &N, g0: f64, h: f64) -> f64 {
        // ψ'(0): the soft blocks are twice differentiable at x, with the gradients stored
        // by `classify` at this very point.
        let d0 = g0
            + self
                .soft
                .iter()
                .map(|&i| self.grad[i] * self.c[i])
                .sum::<f64>();
        if !(d0 < 0.0) {
            return 0.0;
        }
        let tol = 1e-3 * d0.abs();
        let tol_short = 0.5 * d0.abs();
        let (mut s_lo, mut s_hi) = (0.0, f64::INFINITY);
        let mut s = 1.0;
        for _ in 0..100 {
            let (dl, dr, curv) = self.derivatives(nl, g0, h, s);
            if dl <= tol && dr >= -tol_short {
                return s;
            }
            let deriv = if dr < 0.0 {
                s_lo = s;
                dr
            } else {
                s_hi = s;
                dl
            };
            let newton = s - deriv / curv;
            s = if curv > 0.0 && newton > s_lo && newton < s_hi {
                newton
            } else if s_hi.is_finite() {
                0.5 * (s_lo + s_hi)
            } else {
                4.0 * s_lo
            };
            if s_hi.is_finite() && s_hi - s_lo <= 1e-13 * s_hi {
                break;
            }
            if !s.is_finite() {
                return s_lo;
            }
        }
        if s_hi.is_finite() {
            0.5 * (s_lo + s_hi)
        } else {
            s_lo
        }
    }

    /// Minimises from the current iterate `xb` with right-hand side `g` to `stopping`
    /// (energy norm of the correction of each iteration). Sets [`change`](Self::change) to
    /// the norm of the total change of the solve.
    pub(super) fn solve<N: BlockNonlinearity<D>>(
        &mut self,
        nl: &N,
        stopping: Stopping,
    ) -> Result<SolveReport> {
        // The dense loops compiled for the machine's SIMD level (pulp, chosen at run time);
        // the order of every floating-point operation is fixed, so the results are too.
        pulp::Arch::new().dispatch(Kernel {
            fault: self,
            nl,
            stopping,
        })
    }

    /// The bounds of the stopping norm, set up on first use (see [`NormBounds`]).
    fn bounds(&mut self) -> Option<NormBounds> {
        if self.norm_bounds.is_none() {
            let bounds = match &self.norm_factor {
                Some(l) if self.m >= NORM_BOUNDS_MIN => NormBounds::of_factor(l, self.m),
                _ => None,
            };
            self.norm_bounds = Some(bounds);
        }
        self.norm_bounds.flatten()
    }

    /// `‖x‖₂` of the current iterate on the free components.
    #[inline(always)]
    fn euclidean_iterate(&self) -> f64 {
        self.comp
            .iter()
            .map(|&p| self.xb[p] * self.xb[p])
            .sum::<f64>()
            .sqrt()
    }

    #[inline(always)]
    fn solve_kernel<N: BlockNonlinearity<D>>(
        &mut self,
        nl: &N,
        stopping: Stopping,
    ) -> Result<SolveReport> {
        debug_assert_eq!(nl.active_blocks().len(), self.nb);
        let start = std::time::Instant::now();
        let mut x_start = std::mem::take(&mut self.x_start);
        self.gather(&mut x_start);
        self.x_start = x_start;
        if !self.residual_valid {
            self.residual();
            self.residual_valid = true;
        }
        let bounds = self.bounds();
        let mut correction = f64::INFINITY;
        for it in 1..=stopping.max_iterations {
            let mut x_old = std::mem::take(&mut self.x_old);
            self.gather(&mut x_old);
            self.sweep(nl);
            for i in 0..self.m {
                self.dx[i] = self.xb[self.comp[i]] - x_old[i];
            }
            // A sweep that changed nothing beyond the tolerance ends the iteration: the Newton
            // step would only confirm convergence (and the sweep's change is the correction).
            // Where the norm's lower bound already exceeds the tolerance, the norm is not
            // needed: the Newton step follows and its correction replaces the sweep's.
            let sweep_large = match bounds {
                Some(b) if b.lower * euclidean(&self.dx) > stopping.absolute => true,
                _ => {
                    correction = self.norm_of(&self.dx);
                    correction > stopping.absolute
                }
            };
            let mut certainly_not_met = false;
            if sweep_large {
                self.classify(nl);
                self.newton(nl);
                for i in 0..self.m {
                    self.dx[i] = self.xb[self.comp[i]] - x_old[i];
                }
                // The stopping test cannot pass where the correction's lower bound exceeds
                // the tolerance at the iterate's upper bound; the last iteration computes
                // the norm regardless (it is reported).
                certainly_not_met = it < stopping.max_iterations
                    && bounds.is_some_and(|b| {
                        b.lower * euclidean(&self.dx)
                            > stopping.absolute
                                + stopping.relative * b.upper * self.euclidean_iterate()
                    });
                if !certainly_not_met {
                    correction = self.norm_of(&self.dx);
                }
            }
            self.x_old = x_old;
            if self.xb.iter().any(|x| !x.is_finite()) {
                return Err(ProblemError::NonFinite("condensed iterate").into());
            }
            if certainly_not_met {
                continue;
            }
            // The iterate's norm only where its lower bound does not already pass the test
            // (the test is monotone in it).
            let met = stopping.met(correction, 0.0)
                || bounds
                    .is_some_and(|b| stopping.met(correction, b.lower * self.euclidean_iterate()))
                || (stopping.relative > 0.0 && {
                    let mut x = std::mem::take(&mut self.c);
                    self.gather(&mut x);
                    let nx = self.norm_of(&x);
                    self.c = x;
                    stopping.met(correction, nx)
                });
            if met {
                for i in 0..self.m {
                    self.dx[i] = self.xb[self.comp[i]] - self.x_start[i];
                }
                self.change = self.norm_of(&self.dx);
                return Ok(SolveReport {
                    iterations: it,
                    correction,
                    energy: None,
                    seconds: start.elapsed().as_secs_f64(),
                });
            }
        }
        Err(Error::NotConverged {
            solver: "direct",
            iterations: stopping.max_iterations,
            correction,
            tolerance: stopping.absolute,
        })
    }
}

/// [`DenseFault::solve`] as a SIMD kernel: implementing [`pulp::WithSimd`] (rather than
/// passing a closure) inlines the whole iteration into the function that pulp compiles for
/// the machine's instruction set. A closure stayed a function of its own, compiled for the
/// baseline (SSE2). Either way no operation is reordered or fused, so the bits are the same.
struct Kernel<'a, N, const D: usize> {
    fault: &'a mut DenseFault<D>,
    nl: &'a N,
    stopping: Stopping,
}

impl<N: BlockNonlinearity<D>, const D: usize> pulp::WithSimd for Kernel<'_, N, D> {
    type Output = Result<SolveReport>;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        self.fault.solve_kernel(self.nl, self.stopping)
    }
}
