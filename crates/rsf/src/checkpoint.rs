//! Checkpoints: the complete dynamic state of a simulation in a small binary file.
//!
//! Format (little endian): magic `RSFCKPT1`, then `u64` dimension, step, and lengths of
//! `u` and `alpha`, `f64` τ, then `u`, `v`, `a`, `alpha` as raw `f64` bits — exact, so a
//! resumed run is bit-identical to an uninterrupted one.

use std::io::{Read, Write};
use std::path::Path;

use crate::error::{Error, Result};

const MAGIC: &[u8; 8] = b"RSFCKPT1";

/// The dynamic state of a simulation after `step` steps.
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpoint {
    /// Space dimension `D`.
    pub dim: usize,
    /// Steps taken.
    pub step: usize,
    /// Time step τ (s).
    pub tau: f64,
    /// Displacement (m).
    pub u: Vec<f64>,
    /// Velocity (m/s).
    pub v: Vec<f64>,
    /// Acceleration (m/s²).
    pub a: Vec<f64>,
    /// State per frictional node.
    pub alpha: Vec<f64>,
}

impl Checkpoint {
    /// Writes the checkpoint atomically (temporary file, then rename).
    ///
    /// # Errors
    /// I/O errors.
    pub fn write(&self, path: &Path) -> Result<()> {
        let tmp = path.with_extension("tmp");
        {
            let mut f = std::io::BufWriter::new(std::fs::File::create(&tmp)?);
            f.write_all(MAGIC)?;
            for x in [self.dim, self.step, self.u.len(), self.alpha.len()] {
                f.write_all(&(x as u64).to_le_bytes())?;
            }
            f.write_all(&self.tau.to_le_bytes())?;
            for vec in [&self.u, &self.v, &self.a, &self.alpha] {
                for x in vec.iter() {
                    f.write_all(&x.to_le_bytes())?;
                }
            }
            f.flush()?;
        }
        std::fs::rename(&tmp, path)?;
        Ok(())
    }

    /// Reads a checkpoint.
    ///
    /// # Errors
    /// [`Error::Checkpoint`] for a wrong magic number or truncated file; I/O errors.
    pub fn read(path: &Path) -> Result<Self> {
        let mut bytes = Vec::new();
        std::fs::File::open(path)?.read_to_end(&mut bytes)?;
        let bad = |what: &str| Error::Checkpoint(format!("{}: {what}", path.display()));
        if bytes.len() < 48 || &bytes[..8] != MAGIC {
            return Err(bad("not an rsf checkpoint"));
        }
        let word = |i: usize| u64::from_le_bytes(bytes[8 + 8 * i..16 + 8 * i].try_into().unwrap());
        let (dim, step, n, nf) = (
            word(0) as usize,
            word(1) as usize,
            word(2) as usize,
            word(3) as usize,
        );
        let tau = f64::from_bits(word(4));
        let expected = 48usize
            .checked_add(n.checked_mul(24).ok_or_else(|| bad("size overflow"))?)
            .and_then(|x| x.checked_add(nf.checked_mul(8)?))
            .ok_or_else(|| bad("size overflow"))?;
        if bytes.len() != expected {
            return Err(bad("truncated or oversized"));
        }
        let mut off = 48;
        let mut take = |len: usize| {
            let out: Vec<f64> = bytes[off..off + 8 * len]
                .chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                .collect();
            off += 8 * len;
            out
        };
        let (u, v, a, alpha) = (take(n), take(n), take(n), take(nf));
        Ok(Self {
            dim,
            step,
            tau,
            u,
            v,
            a,
            alpha,
        })
    }
}
