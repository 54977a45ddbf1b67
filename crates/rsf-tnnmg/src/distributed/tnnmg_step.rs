//! One iteration of [`DistributedTnnmg`] and its global sums.

use rsf_nonsmooth::BlockNonlinearity;

use super::tnnmg::DistributedTnnmg;
use crate::error::Result;
use crate::line_search::exact_line_search;
use crate::linear_correction::LinearCorrection;
use crate::problem::{coupled_rhs, node_update, NodeBlocks};
use crate::report::{Iteration, IterationState};
use crate::tnnmg::{linearize_blocks, stop_at_kinks, QuadraticPart};
use rsf_nonsmooth::ProblemError;
use rsf_ranks::block::{load, sub_mul_vec};
use rsf_ranks::{ExactSums, LocalRows};

/// Adds `xᵀ M x`'s terms of the owned rows of `rows` (`M`'s; `remap` maps their local
/// nodes to `x`'s, `None` if they are `x`'s own) to sum `i`: per owned node `p` and
/// component, `x_p[c] · (M x)_p[c]` with `(M x)_p` summed as the residual by rows
/// (diagonal block, then the off-diagonal blocks in global column order).
fn add_quadratic_terms<const D: usize>(
    rows: &LocalRows<D>,
    remap: Option<&[u32]>,
    x: &[f64],
    sums: &mut ExactSums,
    i: usize,
) {
    for p in 0..rows.owned() {
        let xp = load::<D>(x, p);
        let mut s = [0.0; D];
        sub_mul_vec(&mut s, rows.diag(p), &xp);
        for (q, blk) in rows.neighbours(p) {
            let q = remap.map_or(q, |m| m[q] as usize);
            sub_mul_vec(&mut s, blk, &load::<D>(x, q));
        }
        for c in 0..D {
            // s = −(M x)_p: the product's negation is exact.
            sums.add(i, -(xp[c] * s[c]));
        }
    }
}

impl<const D: usize> DistributedTnnmg<D> {
    /// Adds `xᵀ E x`'s owned terms (`E` the energy-norm matrix, or `A`) to sum `i` of the
    /// norms' reduction.
    pub(super) fn add_norm_terms(&mut self, x: &[f64], i: usize) {
        match &self.norm_rows {
            Some(e) => add_quadratic_terms(&e.rows, Some(&e.remap), x, &mut self.norm_sums, i),
            None => add_quadratic_terms(self.sweep.rows(), None, x, &mut self.norm_sums, i),
        }
    }

    /// Adds the owned terms of `J(v)` of the local iterate to sum `i` of the norms'
    /// reduction: `½ v_p · (A v)_p − b_p · v_p` per owned node, `φ_k(v_p)` per owned
    /// active block.
    fn add_energy_terms<N: BlockNonlinearity<D>>(&mut self, nl: &N, i: usize) {
        let rows = self.sweep.rows();
        for p in 0..rows.owned() {
            let vp = load::<D>(&self.v, p);
            let mut s = [0.0; D];
            sub_mul_vec(&mut s, rows.diag(p), &vp);
            for (q, blk) in rows.neighbours(p) {
                sub_mul_vec(&mut s, blk, &load::<D>(&self.v, q));
            }
            for c in 0..D {
                self.norm_sums.add(i, -0.5 * (vp[c] * s[c]));
                self.norm_sums.add(i, -(self.b[D * p + c] * vp[c]));
            }
            let k = self.active_of[rows.global_nodes()[p]];
            if k != usize::MAX {
                self.norm_sums.add(i, nl.value(k, &vp));
            }
        }
    }

    /// Reduces the norms' sums: sum 0 (the correction's), then the iterate's norm and
    /// energy where the options ask for them (kept for the loop's calls).
    fn reduce_norms(&mut self) -> f64 {
        let t = self.norm_sums.reduce(&mut *self.halo);
        let mut i = 1;
        let mut next = || {
            i += 1;
            t[i - 1]
        };
        let norm_v = (self.opts.stopping.relative > 0.0).then(&mut next);
        let energy = self.opts.record_energy.then(&mut next);
        let correction = t[0];
        self.pending = (norm_v.map(|q| q.max(0.0).sqrt()), energy);
        correction
    }

    /// One TNNMG iteration on the local iterate; returns the energy norm of the correction
    /// (the same bits on every rank).
    fn step<N: BlockNonlinearity<D>>(&mut self, nl: &N) -> Result<f64> {
        let Self {
            halo,
            sweep,
            inverse,
            free,
            active_of,
            b,
            v,
            v_old,
            ..
        } = self;
        let halo = &mut **halo;
        v_old.copy_from_slice(v);
        for _ in 0..self.opts.nonlinear_sweeps {
            sweep.sweep(v, false, halo, |rows, p, x| {
                let s = coupled_rhs(load::<D>(b, p), rows.neighbours(p), x);
                let mut xp = load::<D>(x, p);
                let node = NodeBlocks {
                    diag: rows.diag(p),
                    inverse: &inverse[p],
                    free: &free[p],
                };
                node_update(nl, active_of[rows.global_nodes()[p]], node, &s, &mut xp);
                xp
            });
        }
        let rows = self.sweep.rows();
        rows.residual(&self.b, &self.v, &mut self.res_a);
        let gather = self.gather.as_mut().expect("a solve started");
        gather.gather(
            &self.v,
            &mut self.v_active,
            &mut *self.halo,
            &mut self.counters.gathers,
        );
        // The truncated linearisation, replicated over all active blocks; the gradients
        // of the owned ones enter the owned Newton right-hand side.
        self.res.copy_from_slice(&self.res_a);
        let (res, local_of) = (&mut self.res, &self.local_of);
        let quadratic = QuadraticPart {
            diag: &self.a_diag,
            fixed: &self.fixed,
        };
        let full = linearize_blocks(
            nl,
            &self.v_active,
            quadratic,
            &mut self.hierarchy.with(&mut *self.halo, self.sweep.rows()),
            &mut self.cached_active,
            |p, g| {
                let q = local_of[p];
                if q != u32::MAX {
                    for r in 0..D {
                        res[D * q as usize + r] -= g[r];
                    }
                }
            },
        )?;
        let mask = self.hierarchy.fine_mask();
        for (q, &p) in rows.global_nodes()[..rows.owned()].iter().enumerate() {
            for r in 0..D {
                let masked = mask[D * p + r];
                if masked {
                    self.res[D * q + r] = 0.0;
                }
                self.free_owned[D * q + r] = if masked { 0.0 } else { 1.0 };
            }
        }
        if full {
            self.vcycle.set_variable_nodes(&self.hierarchy);
            self.counters.full_updates += 1;
        }
        self.vcycle.refresh(&self.hierarchy, full)?;
        self.linear_correction()?;
        // The kink rule on the gathered active blocks, the same on every rank; its
        // corrections written back on every local active node (owned and ghosts).
        let gather = self.gather.as_mut().expect("a solve started");
        gather.gather(
            &self.c,
            &mut self.c_active,
            &mut *self.halo,
            &mut self.counters.gathers,
        );
        stop_at_kinks(nl, &self.v_active, &mut self.c_active);
        gather.scatter(&self.c_active, &mut self.c);
        // Exact line search along c: g0 = cᵀ(Av − b), h = cᵀAc, exact global sums.
        let (g0, h) = self.line_search_sums();
        let s = if h > 0.0 && h.is_finite() {
            exact_line_search(nl, &self.v_active, &self.c_active, g0, h)
        } else {
            0.0
        };
        for (x, (o, ci)) in self.v.iter_mut().zip(self.v_old.iter_mut().zip(&self.c)) {
            *x += s * ci;
            *o = *x - *o;
        }
        let d = std::mem::take(&mut self.v_old);
        self.add_norm_terms(&d, 0);
        self.v_old = d;
        let mut i = 1;
        if self.opts.stopping.relative > 0.0 {
            let v = std::mem::take(&mut self.v);
            self.add_norm_terms(&v, i);
            self.v = v;
            i += 1;
        }
        if self.opts.record_energy {
            self.add_energy_terms(nl, i);
        }
        let correction = self.reduce_norms();
        if !correction.is_finite() {
            return Err(ProblemError::NonFinite("TNNMG iterate (on ranks)").into());
        }
        self.counters.iterations += 1;
        Ok(correction.max(0.0).sqrt())
    }

    /// The linear correction: V-cycles on the truncated Newton system from `c = 0` (every
    /// ghost of zero is current), `v_cycles` of them, or fewer once the residual's norm on
    /// the untruncated dofs fell by `linear_reduction` (the residual by the fine rows of
    /// the Newton matrix, its norm a reproducible sum: the same decision on every rank);
    /// or conjugate gradients preconditioned by them
    /// ([`DistributedCg`](rsf_ranks::DistributedCg)).
    fn linear_correction(&mut self) -> Result<()> {
        let r0 = match self.opts.linear_reduction {
            Some(_) => self.linear_residual_norm(false),
            None => 0.0,
        };
        if self.opts.linear_correction == LinearCorrection::PreconditionedCg {
            self.cg.solve(
                &mut self.vcycle,
                &mut *self.halo,
                &self.res,
                &self.free_owned,
                &mut self.c,
                self.opts.v_cycles,
                self.opts.linear_reduction.map(|red| (red, r0)),
            );
            return Ok(());
        }
        self.c.fill(0.0);
        self.vcycle.set_rhs(&self.res)?;
        for k in 0..self.opts.v_cycles {
            self.vcycle.cycle(&mut self.c, &mut *self.halo);
            if let Some(red) = self.opts.linear_reduction {
                if k + 1 < self.opts.v_cycles && self.linear_residual_norm(true) <= red * r0 {
                    break;
                }
            }
        }
        Ok(())
    }

    /// The Euclidean norm over all ranks of the truncated system's residual `res − H c`
    /// (`after_cycle`) or of `res`, on the untruncated owned dofs: one reduction.
    fn linear_residual_norm(&mut self, after_cycle: bool) -> f64 {
        let rows = self.vcycle.rows();
        let r = if after_cycle {
            rows.residual(&self.res, &self.c, &mut self.linear_res);
            &self.linear_res
        } else {
            &self.res
        };
        let mask = self.hierarchy.fine_mask();
        for (q, &p) in rows.global_nodes()[..rows.owned()].iter().enumerate() {
            for i in 0..D {
                if !mask[D * p + i] {
                    let x = r[D * q + i];
                    self.linear_sums.add(0, x * x);
                }
            }
        }
        self.linear_sums.reduce(&mut *self.halo)[0].sqrt()
    }

    /// `g0 = −Σ c · (b − Av)` over the owned dofs and `h = Σ c_p · (A c)_p` over the owned
    /// nodes, reduced exactly (one exchange).
    fn line_search_sums(&mut self) -> (f64, f64) {
        let rows = self.sweep.rows();
        for (c, r) in self.c.iter().zip(&self.res_a) {
            self.line_sums.add(0, c * r);
        }
        add_quadratic_terms(rows, None, &self.c, &mut self.line_sums, 1);
        let t = self.line_sums.reduce(&mut *self.halo);
        (-t[0], t[1])
    }
}

impl<const D: usize> IterationState<D> for DistributedTnnmg<D> {
    fn dim(&self) -> usize {
        self.n
    }

    fn begin<N: BlockNonlinearity<D>>(&mut self, b: &[f64], nl: &N, v: &[f64]) -> Result<()> {
        self.start(b, nl, v)
    }

    fn energy<N: BlockNonlinearity<D>>(&mut self, _: &[f64], nl: &N, _: &[f64]) -> f64 {
        if let Some(e) = self.pending.1.take() {
            return e;
        }
        // Before the first iteration: its own reduction (the norm sums' other slots empty).
        let i = self.norm_sums.sums() - 1;
        self.add_energy_terms(nl, i);
        self.norm_sums.reduce(&mut *self.halo)[i]
    }

    fn norm_of_iterate(&mut self, _: &[f64]) -> f64 {
        match self.pending.0.take() {
            Some(norm) => norm,
            None => {
                let v = std::mem::take(&mut self.v);
                self.add_norm_terms(&v, 1);
                self.v = v;
                self.norm_sums.reduce(&mut *self.halo)[1].max(0.0).sqrt()
            }
        }
    }

    fn end(&mut self, v: &mut [f64]) {
        self.finish(v);
    }
}

impl<const D: usize> Iteration<D> for DistributedTnnmg<D> {
    fn iterate<N: BlockNonlinearity<D>>(
        &mut self,
        _: &[f64],
        nl: &N,
        _: &mut [f64],
    ) -> Result<f64> {
        self.step(nl)
    }
}
