//! Checkpoints: the complete dynamic state of a simulation in a small binary file.
//!
//! Format (little endian): magic `RSFCKPT2`, then `u64` dimension, step, and lengths of
//! `u`, `alpha` and `controller`, the `u64` step and `f64` time of the time origin, `f64`
//! time and τ, then `u`, `v`, `a`, `alpha`, `controller` as raw `f64` bits — exact, so a
//! resumed run is bit-identical to an uninterrupted one. Files of the first format
//! (`RSFCKPT1`: no time, no controller) are still read (time = step · τ, origin 0).

use std::io::{Read, Write};
use std::path::Path;

use rsf_time::{ControllerState, Kinematics};

use crate::error::{Error, Result};
use crate::simulation_state::SimulationState;

const MAGIC: &[u8; 8] = b"RSFCKPT2";
const MAGIC_V1: &[u8; 8] = b"RSFCKPT1";

/// A [`SimulationState`] on disk: the state and the space dimension it belongs to.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Checkpoint {
    /// Space dimension `D` of the simulation that wrote it.
    pub dim: usize,
    /// The saved state.
    pub state: SimulationState,
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
            let s = &self.state;
            let controller = s.controller.map(|c| c.to_values());
            let controller: &[f64] = controller.as_ref().map_or(&[], |c| &c[..]);
            for x in [
                self.dim,
                s.step,
                s.kinematics.u.len(),
                s.alpha.len(),
                controller.len(),
                s.time_origin.0,
            ] {
                f.write_all(&(x as u64).to_le_bytes())?;
            }
            f.write_all(&s.time_origin.1.to_le_bytes())?;
            f.write_all(&s.time.to_le_bytes())?;
            f.write_all(&s.tau.to_le_bytes())?;
            let k = &s.kinematics;
            for vec in [&k.u[..], &k.v[..], &k.a[..], &s.alpha[..], controller] {
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
        let v1 = bytes.len() >= 8 && &bytes[..8] == MAGIC_V1;
        let header = if v1 { 48 } else { 80 };
        if bytes.len() < header || !(v1 || &bytes[..8] == MAGIC) {
            return Err(bad("not an rsf checkpoint"));
        }
        let word = |i: usize| {
            let mut w = [0u8; 8];
            w.copy_from_slice(&bytes[8 + 8 * i..16 + 8 * i]);
            u64::from_le_bytes(w)
        };
        let to_usize = |w: u64| usize::try_from(w).map_err(|_| bad("size overflow"));
        let (dim, step, n, nf) = (
            to_usize(word(0))?,
            to_usize(word(1))?,
            to_usize(word(2))?,
            to_usize(word(3))?,
        );
        let (nc, time_origin, time, tau) = if v1 {
            let tau = f64::from_bits(word(4));
            (0, (0, 0.0), step as f64 * tau, tau)
        } else {
            (
                to_usize(word(4))?,
                (to_usize(word(5))?, f64::from_bits(word(6))),
                f64::from_bits(word(7)),
                f64::from_bits(word(8)),
            )
        };
        if time_origin.0 > step {
            return Err(bad("time origin after the current step"));
        }
        let expected = n
            .checked_mul(24)
            .and_then(|x| x.checked_add(nf.checked_mul(8)?))
            .and_then(|x| x.checked_add(nc.checked_mul(8)?))
            .and_then(|x| x.checked_add(header))
            .ok_or_else(|| bad("size overflow"))?;
        if bytes.len() != expected {
            return Err(bad("truncated or oversized"));
        }
        let mut off = header;
        let mut take = |len: usize| {
            let out: Vec<f64> = bytes[off..off + 8 * len]
                .chunks_exact(8)
                .map(|c| {
                    let mut w = [0u8; 8];
                    w.copy_from_slice(c);
                    f64::from_le_bytes(w)
                })
                .collect();
            off += 8 * len;
            out
        };
        let (u, v, a, alpha, controller) = (take(n), take(n), take(n), take(nf), take(nc));
        let controller = match controller.len() {
            0 => None,
            _ => Some(
                ControllerState::from_values(&controller)
                    .map_err(|e| bad(&format!("controller state: {e}")))?,
            ),
        };
        Ok(Self {
            dim,
            state: SimulationState {
                step,
                time,
                tau,
                time_origin,
                kinematics: Kinematics { u, v, a },
                alpha,
                controller,
            },
        })
    }
}
