//! The linear correction of a TNNMG iteration: an inexact solve of the truncated Newton
//! system `H c = r` (free dofs) by multigrid cycles, used either as a stationary iteration
//! or as the preconditioner of conjugate gradients.

use crate::multigrid::LinearMultigrid;
use crate::problem::dot;

/// How TNNMG solves its truncated Newton system in each iteration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LinearCorrection {
    /// Multigrid cycles as a stationary iteration (the paper's TNNMG: one cycle per
    /// iteration).
    Cycles,
    /// Conjugate gradients preconditioned by one multigrid cycle per step (each step costs
    /// one cycle plus a few vector operations: `H z` comes from the cycle's own fused
    /// residual). The cycle is symmetric when pre- and post-smoothing counts are equal;
    /// otherwise the Polak–Ribière form used here still keeps every step a descent step.
    #[default]
    PreconditionedCg,
}

/// How much work one linear correction may do: at most `max_cycles` multigrid cycles (or
/// preconditioned CG steps), stopping early once the residual's Euclidean norm on the free
/// dofs has dropped by the factor `reduction` (if given).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CycleBudget {
    /// Most cycles (or CG steps).
    pub max_cycles: usize,
    /// Relative residual reduction after which to stop, if any.
    pub reduction: Option<f64>,
}

/// Work vectors of the linear correction (length `n`, allocated once).
#[derive(Debug)]
pub(crate) struct LinearSolve {
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    hp: Vec<f64>,
}

impl LinearSolve {
    pub fn new(n: usize) -> Self {
        Self {
            r: vec![0.0; n],
            z: vec![0.0; n],
            p: vec![0.0; n],
            hp: vec![0.0; n],
        }
    }

    /// Computes `c ≈ H⁻¹ res` within the [`CycleBudget`]. `res` must vanish on the masked
    /// dofs (it is lent to the multigrid and returned unchanged); `c` is overwritten (0 on
    /// masked dofs). Returns the number of cycles.
    pub fn solve<const D: usize>(
        &mut self,
        method: LinearCorrection,
        mg: &mut LinearMultigrid<D>,
        res: &mut Vec<f64>,
        c: &mut Vec<f64>,
        budget: CycleBudget,
    ) -> usize {
        let CycleBudget {
            max_cycles,
            reduction,
        } = budget;
        c.fill(0.0);
        let r0 = dot(res, res).sqrt();
        if r0 == 0.0 {
            return 0;
        }
        match method {
            LinearCorrection::Cycles => {
                for k in 0..max_cycles {
                    let check = reduction.filter(|_| k + 1 < max_cycles);
                    mg.apply(c, res, k == 0, check.is_some());
                    if let Some(red) = check {
                        let r = free_norm(mg.fine_residual(), mg.fine_free());
                        if r <= red * r0 {
                            return k + 1;
                        }
                    }
                }
                max_cycles
            }
            LinearCorrection::PreconditionedCg => self.cg(mg, res, c, budget, r0),
        }
    }

    fn cg<const D: usize>(
        &mut self,
        mg: &mut LinearMultigrid<D>,
        res: &[f64],
        c: &mut [f64],
        budget: CycleBudget,
        r0: f64,
    ) -> usize {
        let CycleBudget {
            max_cycles,
            reduction,
        } = budget;
        let Self { r, z, p, hp } = self;
        r.copy_from_slice(res);
        let (mut rz_old, mut alpha_old) = (0.0, 0.0);
        for k in 0..max_cycles {
            // z = B r: one cycle from zero.
            mg.apply(z, r, true, true);
            // H z = r − (r − H z): the cycle's own residual, on the free dofs.
            let (q, free) = (mg.fine_residual(), mg.fine_free());
            let (mut rz, mut zhp) = (0.0, 0.0);
            for i in 0..r.len() {
                rz += r[i] * z[i];
                if k > 0 {
                    zhp += z[i] * hp[i];
                }
            }
            // Polak–Ribière: β = zᵀ(r_k − r_{k−1}) / (z_{k−1}ᵀ r_{k−1}), r_k − r_{k−1} = −α H p.
            let beta = if k == 0 {
                0.0
            } else {
                -alpha_old * zhp / rz_old
            };
            let mut php = 0.0;
            for i in 0..r.len() {
                // (The first step does not read the previous solve's directions.)
                let (p_old, hp_old) = if k == 0 { (0.0, 0.0) } else { (p[i], hp[i]) };
                p[i] = z[i] + beta * p_old;
                hp[i] = free[i] * (r[i] - q[i]) + beta * hp_old;
                php += p[i] * hp[i];
            }
            if !(php > 0.0 && rz > 0.0 && php.is_finite()) {
                // No further descent available (round-off level); keep what we have.
                if k == 0 {
                    c.copy_from_slice(z);
                }
                return k + 1;
            }
            let alpha = rz / php;
            let mut rr = 0.0;
            for i in 0..r.len() {
                c[i] += alpha * p[i];
                r[i] -= alpha * hp[i];
                rr += free[i] * r[i] * r[i];
            }
            if reduction.is_some_and(|red| rr.sqrt() <= red * r0) {
                return k + 1;
            }
            (rz_old, alpha_old) = (rz, alpha);
        }
        max_cycles
    }
}

fn free_norm(r: &[f64], free: &[f64]) -> f64 {
    r.iter()
        .zip(free)
        .map(|(r, f)| f * r * r)
        .sum::<f64>()
        .sqrt()
}
