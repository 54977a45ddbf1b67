//! Opening a file that is read whole (a Gmsh mesh here; a checkpoint or a scene file in
//! `rsf`, which calls this one): only a regular file is opened, its length known before
//! anything is read (issue 87: a FIFO where a file was expected blocked forever,
//! `/dev/zero` was read until memory ran out). The lowest crate that reads files holds it,
//! so that every reader above shares one check.

use std::fs::File;
use std::io::{Error, ErrorKind};
use std::path::Path;

/// Opens `path` for reading where it is a regular file (a symbolic link to one too) and
/// returns it with its length in bytes. The type is checked before the file is opened:
/// opening a FIFO for reading waits for a writer, forever if none comes; it is checked
/// again on the open file (the path may have changed in between).
///
/// # Errors
/// The operating system's error where `path` cannot be inspected or opened; an error of
/// kind [`ErrorKind::InvalidInput`], `it is a FIFO (named pipe), not a regular file`
/// (a device such as `/dev/zero`, a socket, a folder likewise), where it is not a regular
/// file.
pub fn open_regular(path: &Path) -> std::io::Result<(File, u64)> {
    let not_regular = |meta: &std::fs::Metadata| {
        Error::new(
            ErrorKind::InvalidInput,
            format!("it is {}, not a regular file", kind_of(meta)),
        )
    };
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(not_regular(&meta));
    }
    let file = File::open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(not_regular(&meta));
    }
    Ok((file, meta.len()))
}

/// What a file that is not a regular one is, as a message names it.
fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if meta.is_dir() {
        "a folder"
    } else {
        "not a file"
    }
}
