//! Whole-number keywords (steps, threads, intervals, cell counts) taken as any Python int
//! (`i128`: negative ones included, so that they reach the check) and checked by name: a
//! negative or oversized value is an `InvalidParameterError` naming the keyword (issue 86:
//! they raised a bare `OverflowError: can't convert negative int to unsigned`, naming
//! nothing). A value that is not an int is refused by PyO3 as a `TypeError` naming the
//! argument.

use pyo3::prelude::*;

use crate::errors::invalid;

/// `value` of the keyword `name` as a `usize`.
///
/// # Errors
/// `InvalidParameterError` naming `name` for a negative value or one beyond `usize`.
pub(crate) fn count(value: i128, name: &str) -> PyResult<usize> {
    usize::try_from(value)
        .map_err(|_| invalid(name, format!("{value}: must be a whole number from 0")))
}

/// [`count`] of an optional keyword.
///
/// # Errors
/// As [`count`].
pub(crate) fn optional(value: Option<i128>, name: &str) -> PyResult<Option<usize>> {
    value.map(|v| count(v, name)).transpose()
}

/// The keyword `threads` (`None`: every core of the machine), at least 1.
///
/// # Errors
/// `InvalidParameterError` naming `threads` for 0, a negative value or one beyond
/// `usize`.
pub(crate) fn threads(value: Option<i128>) -> PyResult<usize> {
    let threads = optional(value, "threads")?.unwrap_or_else(rsf::Parallelism::available_cores);
    if threads == 0 {
        return Err(invalid("threads", "at least 1"));
    }
    Ok(threads)
}
