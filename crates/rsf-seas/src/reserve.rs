//! Disk space held for the rows an output keeps in memory until it writes its files whole
//! (issue 74; BP5's and BP6's files): a file of zeros in the output folder, grown as the rows grow and removed
//! just before the files are written, so that a full disk stops the run when it happens —
//! naming the folder and the cause — not after the whole run, when the files are written.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{io_at, Result};

/// The name of the reservation file in an output folder.
pub const RESERVE_FILE: &str = ".rsf-reserve";

/// Bytes the reservation holds beyond the rows: the headers and the small files.
const MARGIN: u64 = 1 << 20;

/// A held reservation of disk space (removed when dropped).
#[derive(Debug)]
pub(crate) struct Reserve {
    path: PathBuf,
    file: Option<File>,
    bytes: u64,
}

impl Reserve {
    /// No space held yet, in the folder `dir`.
    pub(crate) fn new(dir: &Path) -> Self {
        Self {
            path: dir.join(RESERVE_FILE),
            file: None,
            bytes: 0,
        }
    }

    /// Holds at least `rows + MARGIN` bytes (grown by half again each time, so that the
    /// zeros written are a few times the rows at most over a run).
    ///
    /// # Errors
    /// The write's error naming the reservation file (`No space left on device` where the
    /// disk cannot hold the rows).
    pub(crate) fn hold(&mut self, rows: u64) -> Result<()> {
        let need = rows + MARGIN;
        if need <= self.bytes {
            return Ok(());
        }
        let target = need.max(self.bytes + self.bytes / 2);
        if self.file.is_none() {
            self.file = Some(File::create(&self.path).map_err(io_at("create", &self.path))?);
            self.bytes = 0;
        }
        let file = self.file.as_mut().expect("created above");
        // Zeros written, not a sparse `set_len`: the filesystem allocates them.
        let zeros = vec![0u8; 1 << 16];
        while self.bytes < target {
            let n = (target - self.bytes).min(zeros.len() as u64) as usize;
            file.write_all(&zeros[..n])
                .map_err(io_at("reserve disk space for the output in", &self.path))?;
            self.bytes += n as u64;
        }
        file.flush()
            .map_err(io_at("reserve disk space for the output in", &self.path))
    }

    /// Gives the space back (before the files are written into it).
    ///
    /// # Errors
    /// The removal's error naming the file.
    pub(crate) fn release(&mut self) -> Result<()> {
        if self.file.take().is_some() {
            self.bytes = 0;
            std::fs::remove_file(&self.path).map_err(io_at("remove", &self.path))?;
        }
        Ok(())
    }
}

impl Drop for Reserve {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}
