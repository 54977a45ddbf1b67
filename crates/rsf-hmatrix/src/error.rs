//! The crate's error type.

/// Errors of the set-up and of the product of an [`HMatrix`](crate::HMatrix).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The point dimension is not 1, 2 or 3.
    #[error("point dimension {0} is not 1, 2 or 3")]
    Dimension(usize),
    /// The flat coordinate slice is not a whole number of points.
    #[error("{len} coordinates are not a whole number of points of dimension {dim}")]
    CoordinateCount {
        /// Length of the coordinate slice.
        len: usize,
        /// The point dimension.
        dim: usize,
    },
    /// A point coordinate is NaN or infinite.
    #[error("coordinate {component} of point {point} is not finite")]
    NonFiniteCoordinate {
        /// Index of the point.
        point: usize,
        /// Index of the coordinate.
        component: usize,
    },
    /// The matrix is not square with one row per point.
    #[error("matrix is {rows}×{cols} but there are {points} points (one per unknown)")]
    Shape {
        /// Rows of the matrix.
        rows: usize,
        /// Columns of the matrix.
        cols: usize,
        /// Number of points.
        points: usize,
    },
    /// A matrix entry is NaN or infinite.
    #[error("matrix entry ({row}, {col}) is not finite")]
    NonFiniteEntry {
        /// Row (original numbering).
        row: usize,
        /// Column (original numbering).
        col: usize,
    },
    /// An option is out of its range.
    #[error("option {name} = {value} is out of range ({expected})")]
    Option {
        /// Name of the option.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The admissible range.
        expected: &'static str,
    },
    /// A vector of the product has the wrong length.
    #[error("vector {name} has length {len}, expected {expected}")]
    VectorLength {
        /// `"x"` or `"y"`.
        name: &'static str,
        /// Its length.
        len: usize,
        /// The matrix dimension.
        expected: usize,
    },
    /// The input vector of the product has a non-finite entry.
    #[error("x[{0}] is not finite")]
    NonFiniteInput(usize),
    /// The ℋ-matrix holds only the rows of one part
    /// ([`HMatrix::from_entries_part`](crate::HMatrix::from_entries_part)): the product of
    /// another part, or of every row, was asked for.
    #[error(
        "this ℋ-matrix holds only the rows of part {part} of {parts} (HMatrix::from_entries_part)"
    )]
    PartOnly {
        /// The part held.
        part: usize,
        /// The number of parts of its split.
        parts: usize,
    },
    /// The singular value decomposition of a block did not converge.
    #[error("the SVD of a {rows}×{cols} block did not converge")]
    Svd {
        /// Rows of the block.
        rows: usize,
        /// Columns of the block.
        cols: usize,
    },
}

/// Errors of [`HMatrix::from_symmetric_columns`](crate::HMatrix::from_symmetric_columns):
/// the column oracle's own error `E`, or the set-up's.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ColumnsError<E> {
    /// The oracle failed on a batch of columns.
    #[error("the column oracle failed on a batch of {columns} columns (the first: {first})")]
    Oracle {
        /// The first column of the batch (original numbering).
        first: usize,
        /// Number of columns in the batch.
        columns: usize,
        /// The oracle's error.
        #[source]
        source: E,
    },
    /// Invalid options, a non-finite entry of a column, or an SVD that did not converge.
    #[error(transparent)]
    HMatrix(#[from] Error),
}
