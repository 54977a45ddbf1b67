//! Files a run reads whole (a checkpoint, a scene file): opened only where they are regular
//! files, their length known before anything is read (issue 87: `--resume /dev/zero` grew
//! to 8.2 GB before "out of memory"; a FIFO where a file was expected blocked forever).

use std::fs::File;
use std::io::Read;
use std::path::Path;

use crate::error::{io_at, Result};

/// Opens `path` for reading where it is a regular file (a symbolic link to one too) and
/// returns it with its length in bytes. The type is checked before the file is opened:
/// opening a FIFO for reading waits for a writer, forever if none comes
/// ([`rsf_fem::input_file::open_regular`], the one check, shared with the Gmsh reader).
///
/// # Errors
/// [`Error::File`](crate::Error::File) naming `path` and `action`: it cannot be opened, or
/// it is not a regular file (a FIFO, a device such as `/dev/zero`, a socket, a folder).
pub fn open_regular(path: &Path, action: &'static str) -> Result<(File, u64)> {
    rsf_fem::input_file::open_regular(path).map_err(io_at(action, path))
}

/// Reads at most `limit` bytes of `file` (opened from `path`) from where it is.
///
/// # Errors
/// [`Error::File`](crate::Error::File) naming `path` and `action`.
pub fn read_at_most(
    file: &mut File,
    limit: u64,
    path: &Path,
    action: &'static str,
) -> Result<Vec<u8>> {
    let mut bytes = Vec::with_capacity(usize::try_from(limit.min(1 << 20)).unwrap_or(0));
    file.take(limit)
        .read_to_end(&mut bytes)
        .map_err(io_at(action, path))?;
    Ok(bytes)
}
