//! The checkpoints of one call: the checksum of the inputs a checkpoint must match, the
//! state read back from one, and when to write them ([`Log`]).

use std::time::Instant;

use super::checkpoint::{self, Checksum, Header};
use super::front::State;
use super::packed::{packed_len, try_zeros};
use super::{CheckpointPolicy, RightHandSide, SchurOnly};
use crate::error::{Error, Result};

impl<const D: usize> SchurOnly<D> {
    /// Checksum of everything the result depends on: the matrix (pattern and values after
    /// sorting and summing duplicates), the fixed dofs, the blocks and extras, the
    /// ordering, and the values read from each right-hand side.
    pub(super) fn input_sum(&self, rhs: &[RightHandSide<'_>]) -> [u64; 2] {
        let mut sum = Checksum::new("rsf-direct schur-only inputs v1");
        sum.words([D as u64, self.a.nrows as u64]);
        sum.bytes(self.ordering.to_string().as_bytes());
        sum.usizes(&self.a.col_ptr);
        sum.usizes(&self.a.row_idx);
        sum.f64s(&self.a.val);
        sum.words(self.fixed.iter().map(|&f| f as u64));
        sum.usizes(&self.blocks);
        sum.usizes(&self.extras);
        sum.word(rhs.len() as u64);
        for r in rhs {
            sum.words((0..self.a.nrows).map(|i| {
                if self.fixed[i] {
                    r.x_fixed[i].to_bits()
                } else {
                    r.b[i].to_bits()
                }
            }));
        }
        sum.finish()
    }

    /// The state of an opened checkpoint, if it is of these inputs and consistent.
    pub(super) fn resume(
        &self,
        reader: checkpoint::Reader,
        inputs: [u64; 2],
        nrhs: usize,
        path: &std::path::Path,
    ) -> Result<State> {
        let h = reader.header;
        let mismatch = |reason: &str| Error::CheckpointMismatch {
            path: path.display().to_string(),
            reason: reason.into(),
        };
        if h.inputs != inputs {
            return Err(mismatch(
                "the matrix, the fixed dofs, the blocks, the extras, the right-hand sides or \
                 the ordering differ",
            ));
        }
        if h.layout != self.layout_sum {
            return Err(mismatch(
                "the same inputs with another elimination order or schedule (another build \
                 of faer or METIS?)",
            ));
        }
        let n = self.tree.nr + self.tree.nk;
        if h.done > self.tree.fronts.len()
            || Some(h.s_len) != packed_len(self.tree.nk)
            || h.y_len != n * nrhs
            || h.stack_len != self.tree.stack_after(h.done)
        {
            return Err(Error::Checkpoint {
                path: path.display().to_string(),
                reason: "damaged: its sizes do not match its problem".into(),
            });
        }
        let mut stack = self.empty_stack()?;
        stack.resize(h.stack_len, 0.0);
        let mut s = try_zeros(h.s_len, "the packed Schur complement")?;
        let mut y = try_zeros(h.y_len, "the carried right-hand sides")?;
        reader.read_arrays([&mut stack, &mut s, &mut y])?;
        Ok(State {
            done: h.done,
            stack,
            s,
            y,
            largest_front: h.largest_front,
            peak_stack: h.peak_stack,
            flops: h.flops,
        })
    }
}

/// The checkpoints of one call: the policy and the inputs' checksum (none without a
/// policy), how many were written (with those of the calls before it), when, and the time
/// they took.
pub(super) struct Log<'p> {
    pub(super) policy: Option<(&'p CheckpointPolicy, [u64; 2])>,
    /// The call's start.
    pub(super) clock: Instant,
    /// The last write (or the start).
    last: Instant,
    /// The position of the last checkpoint written or resumed from.
    at: Option<usize>,
    pub(super) written: usize,
    /// Wall time of the calls before a resume, and this call's time writing.
    pub(super) seconds_before: f64,
    pub(super) seconds: f64,
}

impl<'p> Log<'p> {
    pub(super) fn new(clock: Instant, policy: Option<(&'p CheckpointPolicy, [u64; 2])>) -> Self {
        Self {
            policy,
            clock,
            last: clock,
            at: None,
            written: 0,
            seconds_before: 0.0,
            seconds: 0.0,
        }
    }

    /// A resume from a checkpoint at `done` fronts, the `written`-th, after `seconds` of
    /// earlier calls.
    pub(super) fn resumed(&mut self, done: usize, written: usize, seconds: f64) {
        (self.at, self.written, self.seconds_before) = (Some(done), written, seconds);
    }

    /// Whether the policy asks for a checkpoint after `done` fronts.
    pub(super) fn due(&self, done: usize) -> bool {
        self.policy.is_some_and(|(cp, _)| {
            cp.every_fronts.is_some_and(|k| done % k == 0)
                || cp
                    .every_seconds
                    .is_some_and(|s| self.last.elapsed().as_secs_f64() >= s)
        })
    }

    /// Writes the state `st` of `elim`'s elimination.
    pub(super) fn write<const D: usize>(&mut self, elim: &SchurOnly<D>, st: &State) -> Result<()> {
        let Some((cp, inputs)) = self.policy else {
            return Ok(());
        };
        let t = Instant::now();
        self.written += 1;
        let header = Header {
            inputs,
            layout: elim.layout_sum,
            done: st.done,
            stack_len: st.stack.len(),
            s_len: st.s.len(),
            y_len: st.y.len(),
            largest_front: st.largest_front,
            peak_stack: st.peak_stack,
            flops: st.flops,
            seconds: self.seconds_before + self.clock.elapsed().as_secs_f64(),
            written: self.written,
        };
        checkpoint::write(&cp.path, &header, [&st.stack, &st.s, &st.y])?;
        self.seconds += t.elapsed().as_secs_f64();
        self.last = Instant::now();
        self.at = Some(st.done);
        Ok(())
    }

    /// At the end: the finished state kept (unless it is the file already) or the file
    /// removed, as the policy says.
    pub(super) fn finish<const D: usize>(&mut self, elim: &SchurOnly<D>, st: &State) -> Result<()> {
        let Some((cp, _)) = self.policy else {
            return Ok(());
        };
        if cp.keep_result {
            if self.at != Some(st.done) {
                self.write(elim, st)?;
            }
            return Ok(());
        }
        match std::fs::remove_file(&cp.path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(Error::Checkpoint {
                path: cp.path.display().to_string(),
                reason: e.to_string(),
            }),
            _ => Ok(()),
        }
    }
}
