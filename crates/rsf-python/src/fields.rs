//! The fields of a 3-D (or 2-D) run into an HDF5 file with an Xdmf index (the library's
//! `rsf::observe::Hdf5Fields`, feature `hdf5` of this package).

use std::path::PathBuf;

use pyo3::prelude::*;

use crate::errors::invalid;

/// The observers writing `path` every `every` steps (none without a path).
#[cfg(feature = "hdf5")]
pub(crate) fn hdf5_observer<const D: usize>(
    path: Option<PathBuf>,
    every: usize,
) -> PyResult<Vec<Box<dyn rsf::Observer<D>>>> {
    use crate::errors::OrPy;
    use rsf::observe::{Every, FileMode, Hdf5Fields, Interval};
    let Some(path) = path else {
        return Ok(Vec::new());
    };
    if every == 0 {
        return Err(invalid("hdf5_every", "at least 1 (steps)"));
    }
    let fields = Hdf5Fields::new(&path, FileMode::Create).py()?;
    Ok(vec![Box::new(
        Every::new(Interval::Steps(every), fields).py()?,
    )])
}

/// Without the feature `hdf5`: an error if a file is asked for.
#[cfg(not(feature = "hdf5"))]
pub(crate) fn hdf5_observer<const D: usize>(
    path: Option<PathBuf>,
    every: usize,
) -> PyResult<Vec<Box<dyn rsf::Observer<D>>>> {
    let _ = every;
    match path {
        None => Ok(Vec::new()),
        Some(_) => Err(invalid(
            "hdf5",
            "this build of the package has no HDF5 output: install it with \
             MATURIN_PEP517_ARGS=\"--features hdf5\" (docs/python.md)",
        )),
    }
}
