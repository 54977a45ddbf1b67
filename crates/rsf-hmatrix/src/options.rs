//! Options of the set-up and the report it leaves.

use crate::error::Error;

/// Options of [`HMatrix::from_dense`](crate::HMatrix::from_dense) and
/// [`HMatrix::from_entries`](crate::HMatrix::from_entries) (docs/math.md §13).
///
/// Start from [`HOptions::default`] and set the fields to change
/// (`HOptions { eta: 1.0, ..HOptions::default() }`).
#[derive(Debug, Clone, PartialEq)]
pub struct HOptions {
    /// Largest number of points in a leaf of the cluster tree (≥ 1; default 48). Leaves
    /// hold between about half of it and all of it, give or take a run of coincident
    /// points with consecutive indices, which the tree never separates (a node's slip
    /// components stay in one leaf).
    pub leaf_size: usize,
    /// Admissibility parameter `η > 0` (default 2): a block of clusters `τ × σ` is
    /// compressed when `min(diam τ, diam σ) ≤ η dist(τ, σ)` and `dist(τ, σ) > 0`.
    pub eta: f64,
    /// Relative accuracy `ε ∈ [0, 1)` in the Frobenius norm, per admissible block
    /// (default 1e-6), so that `‖S − S_H‖_F ≤ ε ‖S‖_F`.
    pub epsilon: f64,
    /// Number of random entries on which [`HMatrix::from_entries`](crate::HMatrix::from_entries)
    /// estimates its error (default 20 000; all entries when `n²` is not larger).
    pub error_samples: usize,
    /// Seed of the random choices of the set-up (default 1): the sample of the error
    /// estimates, and the reference columns and residual samples of
    /// [`HMatrix::from_entries`](crate::HMatrix::from_entries)'s cross approximation.
    pub seed: u64,
    /// Number `c ≥ 1` of interleaved components per point (default 1): unknown `i` is
    /// component `i mod c` of its point (unknowns `c p, …, c p + c − 1` at point `p`, the
    /// layout of the fault operator's free components).
    /// [`HMatrix::from_entries`](crate::HMatrix::from_entries) compresses each of a
    /// block's `c²` component blocks (rows of component `a`, columns of component `b`) by
    /// its own cross approximation, so that a component block that no row or column of
    /// another component sees (zero coupling between components) is not missed
    /// (docs/math.md §13.3). Ignored by [`HMatrix::from_dense`](crate::HMatrix::from_dense)
    /// and [`HMatrix::from_symmetric_columns`](crate::HMatrix::from_symmetric_columns),
    /// which see every entry. The number of points must be a multiple of `c`.
    pub components: usize,
    /// Number of columns per call of the column oracle of
    /// [`HMatrix::from_symmetric_columns`](crate::HMatrix::from_symmetric_columns)
    /// (≥ 1, default 64): whole leaf clusters are gathered until a batch holds at least
    /// this many columns, so a batch holds fewer than `column_batch + leaf_size`. The
    /// set-up holds two batches (`n × batch` numbers each): the one being compressed and
    /// the next one, computed meanwhile.
    pub column_batch: usize,
    /// Number of random whole columns on which
    /// [`HMatrix::from_symmetric_columns`](crate::HMatrix::from_symmetric_columns)
    /// estimates its error (default 8; all columns when `n` is not larger; 0 for none).
    pub error_columns: usize,
}

impl Default for HOptions {
    fn default() -> Self {
        Self {
            leaf_size: 48,
            eta: 2.0,
            epsilon: 1e-6,
            error_samples: 20_000,
            seed: 1,
            components: 1,
            column_batch: 64,
            error_columns: 8,
        }
    }
}

impl HOptions {
    /// The default options with relative accuracy `epsilon`.
    pub fn with_epsilon(epsilon: f64) -> Self {
        Self {
            epsilon,
            ..Self::default()
        }
    }

    /// Checks the ranges of the options, and that `n` points are a whole number of
    /// points of [`components`](Self::components) components.
    ///
    /// # Errors
    /// As [`validate`](Self::validate); [`Error::Option`] (`components`) unless `n` is a
    /// multiple of `components`.
    pub fn validate_for(&self, n: usize) -> Result<(), Error> {
        self.validate()?;
        if n % self.components != 0 {
            return Err(Error::Option {
                name: "components",
                value: self.components as f64,
                expected: "a divisor of the number of points",
            });
        }
        Ok(())
    }

    /// Checks the ranges of the options.
    ///
    /// # Errors
    /// [`Error::Option`] for a leaf size of 0, `η` not finite and positive, `ε` not in
    /// `[0, 1)`, or 0 components or a column batch of 0.
    pub fn validate(&self) -> Result<(), Error> {
        if self.leaf_size == 0 {
            return Err(Error::Option {
                name: "leaf_size",
                value: 0.0,
                expected: "≥ 1",
            });
        }
        for (name, value) in [
            ("components", self.components),
            ("column_batch", self.column_batch),
        ] {
            if value == 0 {
                return Err(Error::Option {
                    name,
                    value: 0.0,
                    expected: "≥ 1",
                });
            }
        }
        if !(self.eta.is_finite() && self.eta > 0.0) {
            return Err(Error::Option {
                name: "eta",
                value: self.eta,
                expected: "finite and > 0",
            });
        }
        if !(self.epsilon >= 0.0 && self.epsilon < 1.0) {
            return Err(Error::Option {
                name: "epsilon",
                value: self.epsilon,
                expected: "in [0, 1)",
            });
        }
        Ok(())
    }
}

/// How [`SetupReport::relative_error`] was measured (docs/math.md §13.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorMeasure {
    /// Over every entry: `‖S − S_H‖_F / ‖S‖_F` with `S_H` formed block by block.
    Exact,
    /// On a random sample of entries (uniform over the positions, fixed seed):
    /// `(Σ (S_ij − (S_H)_ij)²)^½ / (Σ S_ij²)^½` over the sample, an unbiased-ratio
    /// estimate, not a bound.
    Sampled {
        /// Number of sampled entries.
        samples: usize,
    },
    /// On random whole columns
    /// ([`HMatrix::from_symmetric_columns`](crate::HMatrix::from_symmetric_columns);
    /// uniform without replacement, fixed seed): `((n/s) Σ_j ‖S e_j − S_H e_j‖²)^½ / ‖S‖_F`
    /// over `s` sampled columns `j`, with the exact `‖S‖_F` (every column is seen) — an
    /// estimate, not a bound; the bound is [`ColumnReport::error_bound`].
    SampledColumns {
        /// Number of sampled columns.
        columns: usize,
    },
}

/// What the set-up measured, read with [`HMatrix::report`](crate::HMatrix::report).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct SetupReport {
    /// `‖S − S_H‖_F / ‖S‖_F` (0 for a zero matrix), measured as [`Self::error_measure`] says.
    pub relative_error: f64,
    /// Exact or estimated.
    pub error_measure: ErrorMeasure,
    /// Number of f64 stored in the blocks (dense entries plus `k (m + n)` per low-rank
    /// block).
    pub stored_entries: usize,
    /// `n²`, the size of the dense matrix.
    pub dense_entries: usize,
    /// Number of blocks stored dense (near field, and admissible blocks not worth
    /// compressing).
    pub dense_blocks: usize,
    /// Number of blocks stored low-rank.
    pub low_rank_blocks: usize,
    /// Largest rank of a low-rank block (0 if none).
    pub max_rank: usize,
    /// Mean rank of the low-rank blocks (0 if none).
    pub mean_rank: f64,
    /// Number of leaves of the cluster tree.
    pub leaf_clusters: usize,
    /// The rows held, `(part, parts)`, of an ℋ-matrix built for one part
    /// ([`HMatrix::from_entries_part`](crate::HMatrix::from_entries_part)): then the
    /// stored entries, blocks and ranks are those of the blocks that reach the part's
    /// rows, and the error is sampled on its rows. `None`: every row.
    pub part: Option<(usize, usize)>,
    /// The set-up's cost from a column oracle
    /// ([`HMatrix::from_symmetric_columns`](crate::HMatrix::from_symmetric_columns));
    /// `None` for the other constructors.
    pub columns: Option<ColumnReport>,
}

/// What [`HMatrix::from_symmetric_columns`](crate::HMatrix::from_symmetric_columns)
/// measured (docs/math.md §13.6).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct ColumnReport {
    /// Number of columns of `S` the oracle was asked for (each once: `n`).
    pub columns_computed: usize,
    /// Number of calls of the oracle.
    pub batches: usize,
    /// Largest number of columns in one call.
    pub largest_batch: usize,
    /// Peak of the set-up's own memory (bytes): the batches held, the sampled columns,
    /// the blocks being compressed and those done (logical sizes of the f64 arrays, not
    /// the oracle's memory).
    pub peak_bytes: usize,
    /// Wall time inside the oracle (s).
    pub oracle_seconds: f64,
    /// Wall time of the whole set-up (s), the oracle included (it overlaps the
    /// compression of the previous batch).
    pub setup_seconds: f64,
    /// A bound on `‖S − S_H‖_F / ‖S‖_F` (up to round-off): per block, the norms of the
    /// parts discarded by the truncations of each batch and by the recompression, added
    /// (triangle inequality), then summed in squares over the blocks.
    pub error_bound: f64,
}

impl SetupReport {
    /// `stored_entries / n²` (0 for an empty matrix).
    pub fn memory_ratio(&self) -> f64 {
        if self.dense_entries == 0 {
            0.0
        } else {
            self.stored_entries as f64 / self.dense_entries as f64
        }
    }
}

/// One part of the rows of an ℋ-matrix split into `parts` parts of about equal work
/// ([`HMatrix::from_entries_part`](crate::HMatrix::from_entries_part)): the share of one
/// process.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RowPart {
    /// The number of parts (≥ 1; fewer are made if there are fewer leaf clusters).
    pub parts: usize,
    /// This part (`< parts`).
    pub part: usize,
}
