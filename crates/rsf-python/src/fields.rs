//! HDF5 output (feature `hdf5` of this package, the crate `rsf-hdf5`): the fields of a
//! 3-D (or 2-D) run into an HDF5 file with an Xdmf index (`rsf_hdf5::Hdf5Fields`), and the
//! series of a SEAS run's folder into its `seas.h5` (`rsf_hdf5::SeasSeries`).

use std::path::{Path, PathBuf};

use pyo3::prelude::*;
use rsf::checkpoint::Fingerprint;
use rsf::observe::FileMode;

use crate::errors::invalid;

/// The observers writing `path` every `every` steps (none without a path; without the
/// feature `hdf5`, an error if a path is given).
pub(crate) fn hdf5_observer<const D: usize>(
    path: Option<PathBuf>,
    every: usize,
    fingerprint: &Fingerprint,
    resumed: Option<(&rsf::Checkpoint, &[String])>,
) -> PyResult<Vec<Box<dyn rsf::Observer<D>>>> {
    let Some(path) = path else {
        return Ok(Vec::new());
    };
    #[cfg(not(feature = "hdf5"))]
    {
        let _ = (path, every, fingerprint, resumed);
        Err(no_hdf5("hdf5"))
    }
    #[cfg(feature = "hdf5")]
    {
        use crate::errors::OrPy;
        use rsf::observe::{Every, Interval};
        if every == 0 {
            return Err(invalid("hdf5_every", "at least 1 (steps)"));
        }
        let fields = match resumed {
            // The file proves it holds the checkpoint's run before it is cut (issue 87).
            Some((c, allowed)) => {
                let allowed: Vec<&str> = allowed.iter().map(String::as_str).collect();
                rsf_hdf5::Hdf5Fields::continue_run(&path, c, &allowed).py()?
            }
            None => rsf_hdf5::Hdf5Fields::new(&path, FileMode::Create)
                .py()?
                .fingerprint(fingerprint.clone()),
        };
        Ok(vec![Box::new(
            Every::new(Interval::Steps(every), fields).py()?,
        )])
    }
}

/// The observer writing the series of the SEAS run in `dir` into `dir/seas.h5` at the end
/// of every run call (after the SEAS output, which it reads).
#[cfg(feature = "hdf5")]
pub(crate) fn seas_series_observer<const D: usize, const C: usize>(
    dir: &Path,
    mode: FileMode,
) -> PyResult<Box<dyn rsf::Observer<D, C>>> {
    use crate::errors::OrPy;
    Ok(Box::new(rsf_hdf5::SeasSeries::new(dir, mode).py()?))
}

/// What a build without HDF5 says when asked for a file (`argument` the keyword).
#[cfg(not(feature = "hdf5"))]
fn no_hdf5(argument: &str) -> PyErr {
    invalid(
        argument,
        "this build of the package has no HDF5 output: install it with \
         MATURIN_PEP517_ARGS=\"--features hdf5\" (docs/python.md)",
    )
}

/// Without the feature `hdf5`: an error.
#[cfg(not(feature = "hdf5"))]
pub(crate) fn seas_series_observer<const D: usize, const C: usize>(
    dir: &Path,
    mode: FileMode,
) -> PyResult<Box<dyn rsf::Observer<D, C>>> {
    let _ = (dir, mode);
    Err(no_hdf5("hdf5"))
}

/// `rsf_hdf5::write_greens` of `g` and its dense `s` into `path`.
#[cfg(feature = "hdf5")]
pub(crate) fn write_greens(
    path: &Path,
    g: &rsf::greens::GreensFunctions,
    s: &[f64],
) -> PyResult<()> {
    use crate::errors::OrPy;
    rsf_hdf5::write_greens(path, g, s).py()
}

/// `rsf_hdf5::read_greens` of `path`.
#[cfg(feature = "hdf5")]
pub(crate) fn read_greens(path: &Path) -> PyResult<(rsf::greens::GreensFunctions, Vec<f64>)> {
    use crate::errors::OrPy;
    rsf_hdf5::read_greens(path).py()
}

/// Without the feature `hdf5`: an error.
#[cfg(not(feature = "hdf5"))]
pub(crate) fn write_greens(
    path: &Path,
    g: &rsf::greens::GreensFunctions,
    s: &[f64],
) -> PyResult<()> {
    let _ = (path, g, s);
    Err(no_hdf5("path"))
}

/// Without the feature `hdf5`: an error.
#[cfg(not(feature = "hdf5"))]
pub(crate) fn read_greens(path: &Path) -> PyResult<(rsf::greens::GreensFunctions, Vec<f64>)> {
    let _ = path;
    Err(no_hdf5("path"))
}
