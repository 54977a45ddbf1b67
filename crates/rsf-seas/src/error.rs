//! Error type of the SEAS output crate.

use std::path::Path;

/// Errors of the SEAS outputs: their set-up, their files and their resume. Each converts
/// into the [`rsf::Error`] of the same name (an [`Observer`](rsf::Observer) returns
/// [`rsf::Result`]), so `?` carries it into a run's error unchanged in its message.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// An invalid parameter, named (a field of [`SeasSetup`](crate::SeasSetup), an
    /// argument).
    #[error("invalid parameter `{name}`: {reason}")]
    InvalidParameter {
        /// The parameter name.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// An output file cannot be continued from a checkpoint.
    #[error("cannot resume `{path}`: {reason}")]
    Resume {
        /// The output file (at most about 100 characters of it).
        path: String,
        /// What is wrong.
        reason: String,
    },
    /// A line of a file read back (a resume log) that is not what the output writes.
    #[error("cannot resume `{path}`: line {line}: {reason}")]
    Malformed {
        /// The file (at most about 100 characters of it).
        path: String,
        /// The line (1-based).
        line: u64,
        /// What is wrong.
        reason: String,
    },
    /// A file read back as a SEAS file ([`read_seas_file`](crate::read_seas_file)) that is
    /// not one as this crate writes it.
    #[error("`{path}`, line {line}: not a SEAS file as rsf writes it: {reason}")]
    Format {
        /// The file (at most about 100 characters of it).
        path: String,
        /// The line (1-based).
        line: u64,
        /// What is wrong.
        reason: String,
    },
    /// A file that exists where a new one would be written
    /// ([`FileMode::Create`](rsf::observe::FileMode::Create)).
    #[error("`{path}` exists and is not empty: {reason}")]
    FileExists {
        /// The file (at most about 100 characters of it).
        path: String,
        /// How to go on.
        reason: String,
    },
    /// An I/O operation on a named file or folder failed.
    #[error("cannot {action} `{path}`: {source}")]
    File {
        /// The file or folder (at most about 100 characters of it).
        path: String,
        /// What was being done (e.g. `create`, `read`, `open for appending`).
        action: &'static str,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// An error of the library underneath (a model's vertex, an atomic write, a file
    /// created by [`rsf::observe::create_file`]).
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
            Error::Malformed { path, line, reason } => rsf::Error::Resume {
                path,
                reason: format!("line {line}: {reason}"),
            },
            Error::Format { path, line, reason } => rsf::Error::File {
                path,
                action: "read the SEAS file",
                source: std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    format!("line {line}: {reason}"),
                ),
            },
            Error::FileExists { path, reason } => rsf::Error::FileExists { path, reason },
            Error::File {
                path,
                action,
                source,
            } => rsf::Error::File {
                path,
                action,
                source,
            },
            Error::Rsf(e) => e,
        }
    }
}

/// [`Error::InvalidParameter`] named `name` with `reason`.
pub(crate) fn invalid(name: &str, reason: impl Into<String>) -> Error {
    Error::InvalidParameter {
        name: name.to_string(),
        reason: reason.into(),
    }
}

/// A path as error messages quote it (at most about 100 characters).
pub(crate) fn show_path(path: &Path) -> String {
    rsf_numeric::excerpt(&path.display().to_string())
}

/// A closure turning an I/O error into [`Error::File`] for `action` on `path`.
pub(crate) fn io_at<'a>(
    action: &'static str,
    path: &'a Path,
) -> impl Fn(std::io::Error) -> Error + 'a {
    move |source| Error::File {
        path: show_path(path),
        action,
        source,
    }
}
