//! What an elimination will hold and do (the plan, before any numeric work), how far a
//! running one is, and what a finished one held and did.

use super::tree::update_buffer;

/// What the elimination will hold and do, from the symbolic analysis alone
/// ([`SchurOnly::plan`]). Bytes are 8 per f64.
///
/// [`SchurOnly::plan`]: super::SchurOnly::plan
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SchurOnlyPlan {
    /// Fronts (supernodes with a pivot in the interior).
    pub fronts: usize,
    /// Dofs eliminated, `|R|`.
    pub eliminated: usize,
    /// Dofs kept, `|K| = |F| + |P|`.
    pub kept: usize,
    /// The largest front as it is stored: the lower triangle of its pivot columns and of
    /// its interior update columns (its kept rows' and columns' block goes straight into
    /// `S_KK`).
    pub largest_front_bytes: usize,
    /// The stack of pending contribution blocks and the front being eliminated on top of
    /// them, at its peak.
    pub peak_pending_bytes: usize,
    /// The buffers every front reuses (with at most [`largest_order`](Self::largest_order)
    /// right-hand sides): a dense panel of up to 256 pivot columns of a front and the
    /// products of its updates (up to `256 (w + p)` each).
    pub workspace_bytes: usize,
    /// The largest order `w + p` of a front (pivots and update rows).
    pub largest_order: usize,
    /// `S_KK` in packed rows, `4 |K| (|K| + 1)`.
    pub result_bytes: usize,
    /// Each right-hand side carried through the elimination: one vector of `|R| + |K|`.
    pub bytes_per_rhs: usize,
    /// Floating-point operations without right-hand sides.
    pub flops: f64,
    /// Floating-point operations per right-hand side.
    pub flops_per_rhs: f64,
}

impl SchurOnlyPlan {
    /// Everything the elimination holds at its peak with `nrhs` right-hand sides, besides
    /// the [`SchurOnly`] itself (its copy of the matrix and the symbolic tree): result,
    /// workspace, pending blocks, the carried right-hand sides and their condensed
    /// copies, and the index map.
    ///
    /// [`SchurOnly`]: super::SchurOnly
    pub fn total_bytes(&self, nrhs: usize) -> u128 {
        let n = (self.eliminated + self.kept) as u128;
        let more_rhs =
            update_buffer(self.largest_order, nrhs) - update_buffer(self.largest_order, 0);
        self.result_bytes as u128
            + self.workspace_bytes as u128
            + 8 * more_rhs as u128
            + self.peak_pending_bytes as u128
            + nrhs as u128 * (self.bytes_per_rhs as u128 + 8 * self.kept as u128)
            + 4 * n
    }

    /// Bytes of the file of the finished elimination's checkpoint with `nrhs` right-hand
    /// sides ([`CheckpointPolicy::keep_result`]): `8 (15 + |K|(|K| + 1)/2 + nrhs (|R| +
    /// |K|)) + 16` — the header's 15 words, `S_KK` packed, the carried right-hand sides
    /// and the checksum ([`checkpoint_bytes_of`](Self::checkpoint_bytes_of)).
    ///
    /// [`CheckpointPolicy::keep_result`]: super::CheckpointPolicy::keep_result
    pub fn finished_checkpoint_bytes(&self, nrhs: usize) -> u64 {
        Self::checkpoint_bytes_of(
            self.kept as f64,
            (self.eliminated + self.kept) as f64,
            nrhs as f64,
        ) as u64
    }

    /// [`finished_checkpoint_bytes`](Self::finished_checkpoint_bytes) of an elimination
    /// keeping `kept` dofs of `free` free dofs (`|R| + |K|`) with `nrhs` right-hand sides,
    /// from the sizes alone (a caller's bound before anything is built: bounds of `kept`
    /// and `free` give a bound). An `f64`, exact below 2⁵³ bytes.
    pub fn checkpoint_bytes_of(kept: f64, free: f64, nrhs: f64) -> f64 {
        super::checkpoint::file_bytes(0.5 * kept * (kept + 1.0) + nrhs * free)
    }
}

/// A progress report of a running elimination, given to the monitor of
/// [`SchurOnly::eliminate_with`] after every front.
///
/// [`SchurOnly::eliminate_with`]: super::SchurOnly::eliminate_with
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Fronts done (of the schedule).
    pub fronts_done: usize,
    /// Fronts in all.
    pub fronts: usize,
    /// Floating-point operations done (before a resume included).
    pub flops_done: f64,
    /// Floating-point operations in all (the plan's count).
    pub flops: f64,
    /// Wall time of this call (s).
    pub seconds: f64,
    /// Checkpoints written (before a resume included).
    pub checkpoints_written: usize,
}

/// What an elimination held and did. Bytes are 8 per f64.
#[derive(Debug, Clone, PartialEq)]
pub struct SchurOnlyReport {
    /// Fronts eliminated (all of them, before a resume included).
    pub fronts: usize,
    /// The largest front met (as [`SchurOnlyPlan::largest_front_bytes`]).
    pub largest_front_bytes: usize,
    /// The stack of pending contribution blocks with the front on top, at its peak.
    pub peak_pending_bytes: usize,
    /// `S_KK` (packed rows) and the condensed right-hand sides.
    pub result_bytes: usize,
    /// Floating-point operations (counted as [`SchurOnlyPlan::flops`]).
    pub flops: f64,
    /// Wall time of this call (s).
    pub seconds: f64,
    /// Wall time of the elimination over all calls that worked on it (s).
    pub seconds_total: f64,
    /// The front this call resumed at from a checkpoint (`None`: started afresh).
    pub resumed_at: Option<usize>,
    /// Checkpoints written (before a resume included).
    pub checkpoints_written: usize,
    /// Wall time this call spent writing checkpoints (s).
    pub checkpoint_seconds: f64,
}
