//! Error type of the HDF5 output crate.

use std::path::Path;

/// Errors of the HDF5 writers. Each converts into the [`rsf::Error`] of the same kind (an
/// [`Observer`](rsf::Observer) returns [`rsf::Result`]), the HDF5 library's errors into
/// [`rsf::Error::File`] naming the file and what was being done.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// An invalid argument, named.
    #[error("invalid parameter `{name}`: {reason}")]
    InvalidParameter {
        /// The parameter name.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// A file that cannot be continued from a checkpoint.
    #[error("cannot resume `{path}`: {reason}")]
    Resume {
        /// The file (at most about 100 characters of it).
        path: String,
        /// What is wrong.
        reason: String,
    },
    /// An operation of the HDF5 library on a named file failed.
    #[error("cannot {action} `{path}`: {source}")]
    Hdf5 {
        /// The file (at most about 100 characters of it).
        path: String,
        /// What was being done (e.g. `write a frame into the HDF5 file`).
        action: &'static str,
        /// The HDF5 library's error.
        #[source]
        source: hdf5::Error,
    },
    /// An error of a SEAS file read back (`rsf_seas::read_seas_file`).
    #[error(transparent)]
    Seas(#[from] rsf_seas::Error),
    /// An error of the library underneath (an existing file, an atomic write).
    #[error(transparent)]
    Rsf(#[from] rsf::Error),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;

impl From<Error> for rsf::Error {
    fn from(e: Error) -> Self {
        match e {
            Error::InvalidParameter { name, reason } => {
                rsf::Error::InvalidParameter { name, reason }
            }
            Error::Resume { path, reason } => rsf::Error::Resume { path, reason },
            Error::Hdf5 {
                path,
                action,
                source,
            } => rsf::Error::File {
                path,
                action,
                source: std::io::Error::other(source.to_string()),
            },
            Error::Seas(e) => e.into(),
            Error::Rsf(e) => e,
        }
    }
}

/// A path as error messages quote it (at most about 100 characters).
pub(crate) fn show_path(path: &Path) -> String {
    rsf_numeric::excerpt(&path.display().to_string())
}

/// A closure turning an HDF5 error into [`Error::Hdf5`] for `action` on `path`.
pub(crate) fn h5_at<'a>(
    action: &'static str,
    path: &'a Path,
) -> impl Fn(hdf5::Error) -> Error + 'a {
    move |source| Error::Hdf5 {
        path: show_path(path),
        action,
        source,
    }
}
