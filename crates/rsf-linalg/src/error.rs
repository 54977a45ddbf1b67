//! The errors of this crate.

/// Errors of this crate: the shared failures of a solver's input ([`Error::Problem`]) and
/// those of the factorisation, the conversions and the allocations.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A failure of a solver's input shared by every solver ([`ProblemError`]: a
    /// dimension, the matrix, a non-finite number, an option).
    #[error(transparent)]
    Problem(#[from] ProblemError),
    /// The sparsity pattern differs from the analysed one (or between two matrices that
    /// must share it).
    #[error("sparsity pattern differs from the one used for the symbolic analysis")]
    PatternMismatch,
    /// The matrix is not (numerically) symmetric positive definite, or a solve was asked
    /// for without a valid factorisation.
    #[error("matrix is not positive definite (Cholesky failed{detail})")]
    NotPositiveDefinite {
        /// Extra details from the factorisation.
        detail: String,
    },
    /// Memory allocation or another failure inside faer.
    #[error("faer error: {0}")]
    Faer(String),
    /// A compressed sparse structure is invalid (a conversion's input).
    #[error("invalid compressed sparse column structure at column {column}: {reason}")]
    InvalidStructure {
        /// The column where the problem was found.
        column: usize,
        /// What is wrong.
        reason: &'static str,
    },
    /// A sparse matrix is stored by rows (CSR) where columns (CSC) are expected.
    #[error("expected compressed sparse column (CSC) storage, got CSR")]
    RowStorage,
    /// A [`Parallelism`](crate::Parallelism) name that is neither a thread count nor
    /// `seq` or `pool`.
    #[error(
        "invalid parallelism {0:?}: expected a thread count, 0 or `pool` (rayon's pool), or `seq`"
    )]
    InvalidParallelism(String),
    /// An allocation the machine refused ([`try_filled`](crate::try_filled)): a run whose
    /// memory estimate was below its need ends with this error, never an abort.
    #[error(
        "cannot allocate {:.3} GB for {what}: the machine does not hold it (lower the \
         problem's size; the run's memory estimate was below its need, please report its \
         flags)",
        *bytes as f64 / 1e9
    )]
    OutOfMemory {
        /// What was to be allocated.
        what: &'static str,
        /// How many bytes.
        bytes: usize,
    },
}

/// The failures of a solver's input that every solver of the workspace shares: the one
/// vocabulary of the linear-algebra checks. [`Csc`](crate::Csc)'s checks return it, so do
/// the checks of `rsf-nonsmooth` (the solvers' interface); the solvers' error types
/// (`rsf_tnnmg::Error`, `rsf_direct::Error`), that of the distributed linear algebra
/// (`rsf_ranks::Error`) and this crate's [`Error`] hold it as one variant, `Problem`, with
/// the same messages.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ProblemError {
    /// Input arrays or matrices do not have matching lengths or shapes.
    #[error("dimension mismatch in {what}: expected {expected}, got {got}")]
    DimensionMismatch {
        /// What was checked (the argument).
        what: &'static str,
        /// Expected size.
        expected: usize,
        /// Actual size.
        got: usize,
    },
    /// A matrix given to the solvers is not square, not symmetric (in pattern or values) or
    /// misses a diagonal entry ([`Csc`](crate::Csc)'s checks, the solvers' own).
    #[error("invalid matrix: {0}")]
    InvalidMatrix(String),
    /// A non-finite number in the input (a matrix, a right-hand side, an initial iterate)
    /// or in an iterate.
    #[error("non-finite value in {0}")]
    NonFinite(&'static str),
    /// A (sub)matrix that must be positive definite is not (numerically): a solver's check
    /// (a non-positive free diagonal, a failed block); the failed Cholesky factorisation of
    /// this crate is [`Error::NotPositiveDefinite`].
    #[error("matrix is not positive definite ({0})")]
    NotPositiveDefinite(&'static str),
    /// An invalid solver option (e.g. a stopping test), naming what is wrong.
    #[error("invalid option: {0}")]
    InvalidOption(String),
}

impl ProblemError {
    /// Checks a length or size: `got == expected`.
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] naming `what` otherwise.
    pub fn check_length(
        what: &'static str,
        expected: usize,
        got: usize,
    ) -> std::result::Result<(), Self> {
        if got != expected {
            return Err(Self::DimensionMismatch {
                what,
                expected,
                got,
            });
        }
        Ok(())
    }
}

/// `Result` with this crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

pub(crate) fn faer_err(e: impl std::fmt::Debug) -> Error {
    Error::Faer(format!("{e:?}"))
}

/// A vector of `len` copies of `value`, its memory reserved fallibly (the large
/// allocations of the factorisations): [`Error::OutOfMemory`] naming `what` where the
/// allocator refuses it (a request above `isize::MAX` bytes included), where
/// `vec![value; len]` would abort the process.
///
/// # Errors
/// [`Error::OutOfMemory`].
///
/// ```
/// let v = rsf_linalg::try_filled("a test", 3, 0.5).unwrap();
/// assert_eq!(v, [0.5; 3]);
/// let e = rsf_linalg::try_filled("a huge table", usize::MAX / 8, 0.0).unwrap_err();
/// assert!(e.to_string().contains("a huge table"));
/// ```
pub fn try_filled<T: Clone>(what: &'static str, len: usize, value: T) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| Error::OutOfMemory {
        what,
        bytes: len.saturating_mul(std::mem::size_of::<T>()),
    })?;
    v.resize(len, value);
    Ok(v)
}
