//! The elimination itself: the checks of the right-hand sides and the memory bound, the
//! state before the first front, the fronts one by one with their checkpoints and
//! progress, and the result.

use std::ops::ControlFlow;
use std::time::Instant;

use super::checkpoint;
use super::front::{self, Ordered, State, Workspace};
use super::packed::{packed_len, try_zeros, PackedSymmetric};
use super::resume::Log;
use super::{KeptSchur, Progress, RightHandSide, SchurOnly, SchurOnlyOptions, SchurOnlyReport};
use crate::error::{Error, Result};
use rsf_nonsmooth::ProblemError;

impl<const D: usize> SchurOnly<D> {
    /// [`eliminate_with`](Self::eliminate_with) without a monitor.
    ///
    /// # Errors
    /// As [`eliminate_with`](Self::eliminate_with) (never [`Error::Stopped`]).
    pub fn eliminate(
        &self,
        rhs: &[RightHandSide<'_>],
        options: &SchurOnlyOptions,
    ) -> Result<KeptSchur> {
        self.eliminate_with(rhs, options, &mut |_| ControlFlow::Continue(()))
    }

    /// Eliminates the interior: `S_KK` and the condensed right-hand sides `g_K` of `rhs`,
    /// front by front, keeping no factor column. `monitor` sees the [`Progress`] after
    /// every front (and after the checkpoint written there, if any); returning
    /// `ControlFlow::Break(())` stops the elimination at once, as a kill would: nothing
    /// more is written, and a later call resumes from the last checkpoint.
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] for a right-hand side of another length;
    /// [`ProblemError::NonFinite`] for a non-finite value read from one, or a non-finite result;
    /// [`ProblemError::InvalidOption`] for an invalid [`CheckpointPolicy`];
    /// [`Error::TooLarge`] if [`SchurOnlyPlan::total_bytes`] exceeds
    /// [`SchurOnlyOptions::max_bytes`] (before any allocation); [`Error::OutOfMemory`] if a
    /// large buffer cannot be allocated; [`Error::NonPositivePivot`] at the first dof whose
    /// pivot is not positive (`A` not positive definite on the interior);
    /// [`Error::Checkpoint`] for a checkpoint that cannot be written or read, or is
    /// damaged, and — with [`CheckpointPolicy::keep_result`], before any numeric work —
    /// for a disk that cannot hold the finished checkpoint
    /// ([`SchurOnlyPlan::finished_checkpoint_bytes`]); [`Error::CheckpointMismatch`] for a
    /// checkpoint of other inputs; [`Error::Stopped`] if `monitor` stopped it.
    ///
    /// [`CheckpointPolicy`]: super::CheckpointPolicy
    /// [`SchurOnlyPlan::total_bytes`]: super::SchurOnlyPlan::total_bytes
    /// [`SchurOnlyPlan::finished_checkpoint_bytes`]: super::SchurOnlyPlan::finished_checkpoint_bytes
    /// [`CheckpointPolicy::keep_result`]: super::CheckpointPolicy::keep_result
    pub fn eliminate_with(
        &self,
        rhs: &[RightHandSide<'_>],
        options: &SchurOnlyOptions,
        monitor: &mut dyn FnMut(&Progress) -> ControlFlow<()>,
    ) -> Result<KeptSchur> {
        let clock = Instant::now();
        let n_all = self.a.nrows;
        for r in rhs {
            for (what, v) in [("right-hand side", r.b), ("fixed values", r.x_fixed)] {
                if v.len() != n_all {
                    return Err(ProblemError::DimensionMismatch {
                        what,
                        expected: n_all,
                        got: v.len(),
                    }
                    .into());
                }
            }
            if (0..n_all).any(|i| {
                let v = if self.fixed[i] { r.x_fixed[i] } else { r.b[i] };
                !v.is_finite()
            }) {
                return Err(ProblemError::NonFinite("right-hand side or fixed values").into());
            }
        }
        if let Some(cp) = &options.checkpoint {
            cp.validate()?;
        }
        let plan = self.plan();
        let need = plan.total_bytes(rhs.len());
        let limit = options.max_bytes.unwrap_or(usize::MAX);
        if need > limit as u128 || packed_len(self.tree.nk).is_none() {
            return Err(Error::TooLarge {
                what: "the Schur-only elimination",
                bytes: need,
                limit,
            });
        }
        let mut log = Log::new(
            clock,
            options
                .checkpoint
                .as_ref()
                .map(|cp| (cp, self.input_sum(rhs))),
        );
        let resumed = match log.policy {
            Some((cp, inputs)) => checkpoint::open(&cp.path)?
                .map(|reader| {
                    let h = reader.header;
                    log.resumed(h.done, h.written, h.seconds);
                    self.resume(reader, inputs, rhs.len(), &cp.path)
                })
                .transpose()?,
            None => None,
        };
        let resumed_at = resumed.as_ref().map(|st| st.done);
        let total = self.tree.fronts.len();
        // The disk space of the finished checkpoint, held before any numeric work (issue
        // 87: a disk too small for it was found after the elimination).
        let _held = match log.policy {
            Some((cp, _)) if cp.keep_result && resumed_at != Some(total) => Some(checkpoint::hold(
                &cp.path,
                plan.finished_checkpoint_bytes(rhs.len()),
            )?),
            _ => None,
        };
        let mut st = match resumed {
            Some(st) => st,
            None => self.fresh(rhs)?,
        };
        let mut ws = Workspace::new(&self.tree, rhs.len())?;
        let ordered = Ordered {
            a: &self.a,
            pos: &self.pos,
            order: &self.order,
        };
        let flops_all = plan.flops + rhs.len() as f64 * plan.flops_per_rhs;
        while st.done < total {
            front::eliminate(st.done, &self.tree, &ordered, &mut st, &mut ws)?;
            st.done += 1;
            if st.done < total && log.due(st.done) {
                log.write(self, &st)?;
            }
            let progress = Progress {
                fronts_done: st.done,
                fronts: total,
                flops_done: st.flops,
                flops: flops_all,
                seconds: log.clock.elapsed().as_secs_f64(),
                checkpoints_written: log.written,
            };
            if monitor(&progress).is_break() {
                return Err(Error::Stopped {
                    done: st.done,
                    total,
                });
            }
        }
        log.finish(self, &st)?;
        drop(ws);
        let (nr, nk) = (self.tree.nr, self.tree.nk);
        let n = nr + nk;
        let g: Vec<Vec<f64>> = (0..rhs.len())
            .map(|k| st.y[k * n + nr..(k + 1) * n].to_vec())
            .collect();
        drop(std::mem::take(&mut st.y));
        if !st.s.iter().all(|v| v.is_finite()) || !g.iter().flatten().all(|v| v.is_finite()) {
            return Err(ProblemError::NonFinite("the Schur complement on the kept set").into());
        }
        let seconds = log.clock.elapsed().as_secs_f64();
        let report = SchurOnlyReport {
            fronts: st.done,
            largest_front_bytes: 8 * st.largest_front,
            peak_pending_bytes: 8 * st.peak_stack,
            result_bytes: 8 * (st.s.len() + nk * rhs.len()),
            flops: st.flops,
            seconds,
            seconds_total: log.seconds_before + seconds,
            resumed_at,
            checkpoints_written: log.written,
            checkpoint_seconds: log.seconds,
        };
        Ok(KeptSchur {
            s: PackedSymmetric::from_rows(nk, std::mem::take(&mut st.s)),
            g,
            kept: self.kept.clone(),
            nf: self.nf,
            report,
        })
    }

    /// The state before the first front: `S_KK = A_KK`, the right-hand sides `b̃` in
    /// elimination order, an empty stack with room for its peak.
    fn fresh(&self, rhs: &[RightHandSide<'_>]) -> Result<State> {
        let (nr, nk) = (self.tree.nr, self.tree.nk);
        let n = nr + nk;
        let stack = self.empty_stack()?;
        let mut s = PackedSymmetric::zeros(nk)?.into_packed_rows();
        for c in nr..n {
            let (rows, vals) = self.a.col(self.order[c]);
            let kj = c - nr;
            for (&i, &v) in rows.iter().zip(vals) {
                let pi = self.pos[i];
                if pi != usize::MAX && pi >= c {
                    let ki = pi - nr;
                    s[ki * (ki + 1) / 2 + kj] += v;
                }
            }
        }
        let mut y = try_zeros(n * rhs.len(), "the carried right-hand sides")?;
        for (k, r) in rhs.iter().enumerate() {
            let y = &mut y[k * n..(k + 1) * n];
            for (yc, &i) in y.iter_mut().zip(&self.order) {
                *yc = r.b[i];
            }
            // b̃ = b − A_{·,fixed} x_fixed, column by column as the condensation does.
            for j in (0..self.a.nrows).filter(|&j| self.fixed[j]) {
                let xj = r.x_fixed[j];
                if xj != 0.0 {
                    let (rows, vals) = self.a.col(j);
                    for (&i, &v) in rows.iter().zip(vals) {
                        if self.pos[i] != usize::MAX {
                            y[self.pos[i]] -= v * xj;
                        }
                    }
                }
            }
        }
        Ok(State {
            done: 0,
            stack,
            s,
            y,
            largest_front: 0,
            peak_stack: 0,
            flops: 0.0,
        })
    }
}
