//! Array-likes from Python as the arrays the library takes (issue 86, "Python at par"): any
//! sequence or array numpy converts — nested lists, tuples, `float32`, integer dtypes — is
//! accepted, converted once, and refused by the keyword that names it when it is not an
//! array of numbers of the stated shape.

use numpy::ndarray::Array2;
use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::errors::invalid;

/// `obj` as numpy sees it (`numpy.asarray`), with its dtype's kind (`"f"`, `"i"`, …).
fn as_array<'py>(name: &str, obj: &Bound<'py, PyAny>) -> PyResult<(Bound<'py, PyAny>, String)> {
    let np = obj.py().import("numpy")?;
    let array = np
        .call_method1("asarray", (obj,))
        .map_err(|e| invalid(name, format!("an array of numbers: {e}")))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    Ok((array, kind))
}

/// The rows of `array` (2-D, `columns` wide: `None` any), refused by `name` otherwise.
fn two_d<T: Copy + numpy::Element>(
    name: &str,
    array: &Bound<'_, PyArrayDyn<T>>,
    columns: Option<usize>,
) -> PyResult<Array2<T>> {
    let shape = array.shape().to_vec();
    let fits = shape.len() == 2 && columns.is_none_or(|c| shape[1] == c);
    if !fits {
        let wanted = columns.map_or("(n, k)".to_owned(), |c| format!("(n, {c})"));
        return Err(invalid(name, format!("shape {wanted}, not {shape:?}")));
    }
    let view = array.readonly();
    Ok(view
        .as_array()
        .to_owned()
        .into_dimensionality()
        .expect("two axes, checked"))
}

/// A 2-D array of real numbers (`columns` wide, or any) from any array-like: integers and
/// `float32` converted to `float64`; booleans, complex numbers, strings and objects refused
/// naming `name`.
///
/// # Errors
/// `InvalidParameterError` naming `name`: not numbers, or another shape.
pub(crate) fn reals_2d(
    name: &str,
    obj: &Bound<'_, PyAny>,
    columns: Option<usize>,
) -> PyResult<Array2<f64>> {
    let (array, kind) = as_array(name, obj)?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(invalid(
            name,
            format!("real numbers, not an array of dtype kind {kind:?}"),
        ));
    }
    let array = array
        .call_method1("astype", ("float64",))?
        .cast_into::<PyArrayDyn<f64>>()
        .map_err(|e| invalid(name, e))?;
    two_d(name, &array, columns)
}

/// A 2-D array of indices (`columns` wide) from any array-like of whole numbers: any
/// integer dtype, or floats that are whole (as `numpy.loadtxt` gives); negative ones and
/// the rest refused naming `name`.
///
/// # Errors
/// `InvalidParameterError` naming `name`: not whole numbers, negative, or another shape.
pub(crate) fn indices_2d(
    name: &str,
    obj: &Bound<'_, PyAny>,
    columns: usize,
) -> PyResult<Array2<usize>> {
    let (array, kind) = as_array(name, obj)?;
    let values: Array2<f64> = match kind.as_str() {
        // Whole numbers of any width are exact as f64 below 2^53, far beyond any mesh.
        "i" | "u" | "f" => reals_2d(name, &array, Some(columns))?,
        _ => {
            return Err(invalid(
                name,
                format!("whole numbers (vertex indices), not an array of dtype kind {kind:?}"),
            ))
        }
    };
    let bad = values
        .iter()
        .find(|x| !(x.is_finite() && x.fract() == 0.0 && **x >= 0.0 && **x < 9.007e15));
    if let Some(x) = bad {
        return Err(invalid(
            name,
            format!("vertex indices are whole numbers from 0, not {x}"),
        ));
    }
    Ok(values.mapv(|x| x as usize))
}
