//! Conjugate gradients on ranks preconditioned by one application of a [`Preconditioner`]
//! per step (in `rsf-tnnmg`, one distributed V-cycle: the linear correction
//! `LinearCorrection::PreconditionedCg` of TNNMG on ranks), its inner products exact sums
//! (the same bits at every rank count).

use crate::halo::HaloCounters;
use crate::local_rows::LocalRows;
use crate::reduce::ExactSums;
use crate::transport::RankGroup;

/// A preconditioner `B ≈ H⁻¹` of [`DistributedCg`] on one rank, and the rank's rows of the
/// operator `H`.
pub trait Preconditioner<const D: usize> {
    /// The rank's rows of `H` (CG's products `H z` are [`LocalRows::residual`]s of them).
    fn rows(&self) -> &LocalRows<D>;

    /// `z = B r`: `r` holds the owned right-hand side (`D · rows().owned()` values), `z` is
    /// a local vector (`D · rows().len()` values), zero on entry, that holds `B r` with its
    /// ghosts current on return. Collective.
    fn apply<H: RankGroup + ?Sized>(&mut self, r: &[f64], z: &mut [f64], halo: &mut H);
}

/// The work vectors and sums of [`DistributedCg::solve`]: owned values (`r`, `hp`, `q`) and
/// local vectors with ghosts (`z`, `p`).
#[derive(Debug)]
pub struct DistributedCg {
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    hp: Vec<f64>,
    q: Vec<f64>,
    /// `rᵀz` and `zᵀ(Hp)_old`; then `pᵀHp`, and `|r|²` on the free dofs.
    pair: ExactSums,
    single: ExactSums,
}

impl DistributedCg {
    /// Work space for `owned` and `local` values (`D` per owned and per local node) of
    /// rank `rank` of `size`.
    pub fn new(owned: usize, local: usize, rank: usize, size: usize) -> Self {
        Self {
            r: vec![0.0; owned],
            z: vec![0.0; local],
            p: vec![0.0; local],
            hp: vec![0.0; owned],
            q: vec![0.0; owned],
            pair: ExactSums::new(2, rank, size),
            single: ExactSums::new(1, rank, size),
        }
    }

    /// What the reductions have sent.
    pub fn counters(&self) -> HaloCounters {
        self.pair.counters() + self.single.counters()
    }

    /// Sets the counters to zero.
    pub fn reset_counters(&mut self) {
        self.pair.reset_counters();
        self.single.reset_counters();
    }

    /// What one step's reductions send: two, and a third for the residual's norm when the
    /// solve may stop early (`checked`).
    pub fn per_step(&self, checked: bool) -> HaloCounters {
        self.pair.per_reduction() + self.single.per_reduction().times(1 + u64::from(checked))
    }

    /// `c ≈ H⁻¹ res` (`res` the owned right-hand side, 0 on the masked dofs; `free` the
    /// owned 0/1 factor of the unmasked dofs; `c` a local vector, overwritten, its ghosts
    /// current afterwards) by at most `max_steps` steps of conjugate gradients (the
    /// Polak–Ribière form of `rsf-tnnmg`'s one-process correction) preconditioned by one
    /// application of `precond` per step, `H z` from its rows; stops early once the free
    /// residual's norm fell by `reduction` (relative to `r0`, the right-hand side's).
    /// Returns the steps taken. Collective: every decision is taken on exact global sums.
    ///
    /// # Panics
    /// If a vector does not have the length of `precond`'s rows (as given above), or
    /// `halo` is another rank's.
    #[expect(
        clippy::too_many_arguments,
        reason = "one linear correction: the preconditioner, its transport, the system and \
                  the budget"
    )]
    pub fn solve<const D: usize, P: Preconditioner<D>, H: RankGroup + ?Sized>(
        &mut self,
        precond: &mut P,
        halo: &mut H,
        res: &[f64],
        free: &[f64],
        c: &mut [f64],
        max_steps: usize,
        reduction: Option<(f64, f64)>,
    ) -> usize {
        c.fill(0.0);
        self.r.copy_from_slice(res);
        let (mut rz_old, mut alpha_old) = (0.0, 0.0);
        for k in 0..max_steps {
            // z = B r from zero; q = r − H z by the rows.
            self.z.fill(0.0);
            precond.apply(&self.r, &mut self.z, halo);
            precond.rows().residual(&self.r, &self.z, &mut self.q);
            for i in 0..self.r.len() {
                self.pair.add(0, self.r[i] * self.z[i]);
                if k > 0 {
                    self.pair.add(1, self.z[i] * self.hp[i]);
                }
            }
            let t = self.pair.reduce(halo);
            let (rz, zhp) = (t[0], t[1]);
            let beta = if k == 0 {
                0.0
            } else {
                -alpha_old * zhp / rz_old
            };
            for i in 0..self.p.len() {
                let p_old = if k == 0 { 0.0 } else { self.p[i] };
                self.p[i] = self.z[i] + beta * p_old;
            }
            for i in 0..self.r.len() {
                let hp_old = if k == 0 { 0.0 } else { self.hp[i] };
                self.hp[i] = free[i] * (self.r[i] - self.q[i]) + beta * hp_old;
                self.single.add(0, self.p[i] * self.hp[i]);
            }
            let php = self.single.reduce(halo)[0];
            if !(php > 0.0 && rz > 0.0 && php.is_finite()) {
                // No further descent available (round-off level); keep what we have.
                if k == 0 {
                    c.copy_from_slice(&self.z);
                }
                return k + 1;
            }
            let alpha = rz / php;
            // On every local value: the ghosts of p are current (z's, combined alike).
            for (ci, pi) in c.iter_mut().zip(&self.p) {
                *ci += alpha * pi;
            }
            for i in 0..self.r.len() {
                self.r[i] -= alpha * self.hp[i];
            }
            if let Some((red, r0)) = reduction {
                for i in 0..self.r.len() {
                    self.single.add(0, free[i] * self.r[i] * self.r[i]);
                }
                if self.single.reduce(halo)[0].sqrt() <= red * r0 {
                    return k + 1;
                }
            }
            (rz_old, alpha_old) = (rz, alpha);
        }
        max_steps
    }
}
