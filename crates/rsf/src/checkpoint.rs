//! Checkpoints: the complete dynamic state of a simulation in a small binary file that
//! vouches for itself (docs/reliability.md).
//!
//! Format (little endian): magic `RSFCKPT3`, then `u64` dimension, step, and lengths of
//! `u`, `alpha` and `controller`, the `u64` step and `f64` time of the time origin, `f64`
//! time, τ and wall time of the run so far, the `u64` length of the fingerprint and its
//! UTF-8 text (`field=value` lines), then `u`, `v`, `a`, `alpha`, `controller` as raw
//! `f64` bits — exact, so a resumed run is bit-identical to an uninterrupted one — and
//! last the CRC-32 (IEEE, `u32`) of every byte before it. A method with a state of its own
//! ([`MethodState`]: the fault ODE's controller memory and current rate, the switching
//! run's phase) is written as `RSFCKPT4`: the same layout with two more header words after
//! the time origin's step (the method's tag and its number of values) and its values
//! (`f64` bits) after `controller`; the implicit simulation's files stay `RSFCKPT3`, byte
//! for byte as before. Files of the earlier formats (`RSFCKPT2`: no fingerprint, no
//! checksum; `RSFCKPT1`: also no time, no controller) are still read, with an empty
//! [`Fingerprint`] (which [`Fingerprint::check`] refuses).

use std::io::Write;
use std::path::Path;

use rsf_time::{ControllerState, Kinematics};

pub use crate::method_state::{FaultOdeState, MethodState, Phase, SwitchingStats};
pub use crate::simulation_state::SimulationState;

use crate::error::{io_at, show_path, Error, Result};

const MAGIC_V4: &[u8; 8] = b"RSFCKPT4";
const MAGIC: &[u8; 8] = b"RSFCKPT3";
const MAGIC_V2: &[u8; 8] = b"RSFCKPT2";
const MAGIC_V1: &[u8; 8] = b"RSFCKPT1";
/// The name of the format this version writes and continues (the `format` of a
/// [`Fingerprint`]); `RSFCKPT4`, its extension by a [`MethodState`], belongs to it.
pub const CHECKPOINT_FORMAT: &str = "RSFCKPT3";

/// What a checkpoint continues: the physics and method of the run that wrote it, as
/// `field = value` pairs in the order given (e.g. `SliderScene::fingerprint`:
/// every scene field, the format). A run checks a checkpoint's fingerprint against its
/// own before it resumes ([`check`](Self::check)).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Fingerprint(pub Vec<(String, String)>);

impl Fingerprint {
    /// The fingerprint with `field = value` appended. Newlines and `=` in the field are
    /// replaced by spaces and newlines in the value by `\n`, so that it round-trips.
    pub fn with(mut self, field: &str, value: impl std::fmt::Display) -> Self {
        let field = field.replace(['\n', '='], " ");
        let value = value.to_string().replace('\n', "\\n");
        self.0.push((field, value));
        self
    }

    /// The fields of a serialisable value (e.g. a scene) as JSON names and renders them:
    /// nested fields joined by `.`, array entries by their index, values in JSON (numbers
    /// exactly, as the shortest text that reads back to the same double).
    pub fn of_serialized(value: &impl serde::Serialize) -> Self {
        fn flatten(prefix: &str, v: &serde_json::Value, out: &mut Fingerprint) {
            let join = |k: &str| {
                if prefix.is_empty() {
                    k.to_owned()
                } else {
                    format!("{prefix}.{k}")
                }
            };
            match v {
                serde_json::Value::Object(m) => {
                    for (k, x) in m {
                        flatten(&join(k), x, out);
                    }
                }
                serde_json::Value::Array(a) => {
                    for (i, x) in a.iter().enumerate() {
                        flatten(&join(&i.to_string()), x, out);
                    }
                }
                x => out
                    .0
                    .push((prefix.replace(['\n', '='], " "), x.to_string())),
            }
        }
        let mut out = Self::default();
        match serde_json::to_value(value) {
            Ok(v) => flatten("", &v, &mut out),
            Err(e) => out.0.push(("unserialisable".into(), e.to_string())),
        }
        out
    }

    /// The value of `field`, if present.
    pub fn get(&self, field: &str) -> Option<&str> {
        self.0
            .iter()
            .find(|(f, _)| f == field)
            .map(|(_, v)| v.as_str())
    }

    /// Checks that a checkpoint with this fingerprint continues a run with fingerprint
    /// `run`: every field of either is present in both with the same value, except the
    /// fields named in `allowed` (deliberate changes, e.g. a later `end_time_s`).
    ///
    /// # Errors
    /// [`Error::CheckpointMismatch`] naming the first differing field (a missing field is
    /// shown as `absent`; an empty fingerprint, of a checkpoint of an earlier format, as
    /// the field `format`).
    pub fn check(&self, run: &Fingerprint, allowed: &[&str]) -> Result<()> {
        let mismatch = |field: &str, c: Option<&str>, r: Option<&str>| Error::CheckpointMismatch {
            field: rsf_numeric::excerpt(field),
            checkpoint: rsf_numeric::excerpt(c.unwrap_or("absent")),
            run: rsf_numeric::excerpt(r.unwrap_or("absent")),
        };
        if self.0.is_empty() && !allowed.contains(&"format") {
            return Err(mismatch(
                "format",
                Some("an earlier format without fingerprint"),
                Some(CHECKPOINT_FORMAT),
            ));
        }
        for (field, value) in &run.0 {
            let mine = self.get(field);
            if mine != Some(value.as_str()) && !allowed.contains(&field.as_str()) {
                return Err(mismatch(field, mine, Some(value)));
            }
        }
        for (field, value) in &self.0 {
            if run.get(field).is_none() && !allowed.contains(&field.as_str()) {
                return Err(mismatch(field, Some(value), None));
            }
        }
        Ok(())
    }

    fn to_text(&self) -> String {
        self.0.iter().map(|(f, v)| format!("{f}={v}\n")).collect()
    }

    fn from_text(text: &str) -> Option<Self> {
        text.lines()
            .map(|l| l.split_once('=').map(|(f, v)| (f.to_owned(), v.to_owned())))
            .collect::<Option<Vec<_>>>()
            .map(Self)
    }
}

/// A [`SimulationState`] on disk: the state, the space dimension it belongs to, what it
/// continues and the wall time spent so far.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Checkpoint {
    /// Space dimension `D` of the simulation that wrote it.
    pub dim: usize,
    /// The saved state.
    pub state: SimulationState,
    /// The physics and method of the run that wrote it (empty unless the
    /// [`Checkpointer`](crate::observe::Checkpointer) was given one, and for earlier formats).
    pub fingerprint: Fingerprint,
    /// Wall time of the run up to this checkpoint, over all its resumes (s; 0 if not
    /// kept).
    pub wall_time_s: f64,
    /// The method's own state beyond `state` ([`MethodState::Implicit`] for the implicit
    /// simulation and for files of the earlier formats).
    pub method: MethodState,
}

/// Fixed-size part of a format-3 file: magic, 6 words, 4 floats, fingerprint length.
const HEADER_V3: usize = 8 + 6 * 8 + 4 * 8 + 8;
/// Fixed-size part of a format-4 file: format 3's and two words (method tag, its length).
const HEADER_V4: usize = HEADER_V3 + 2 * 8;

impl Checkpoint {
    /// A checkpoint of `state` of a `dim`-dimensional simulation, with an empty
    /// fingerprint and no wall time.
    pub fn new(dim: usize, state: SimulationState) -> Self {
        Self {
            dim,
            state,
            fingerprint: Fingerprint::default(),
            wall_time_s: 0.0,
            method: MethodState::Implicit,
        }
    }

    /// The bytes of the file (format `RSFCKPT3` for [`MethodState::Implicit`], else
    /// `RSFCKPT4`; with its checksum).
    pub fn to_bytes(&self) -> Vec<u8> {
        let s = &self.state;
        let controller = s.controller.map(|c| c.to_values());
        let controller: &[f64] = controller.as_ref().map_or(&[], |c| &c[..]);
        let text = self.fingerprint.to_text();
        let k = &s.kinematics;
        let (tag, method) = self.method.to_values();
        let v4 = self.method != MethodState::Implicit;
        let mut b =
            Vec::with_capacity(HEADER_V4 + text.len() + 8 * (3 * k.u.len() + 8 + method.len()) + 4);
        b.extend_from_slice(if v4 { MAGIC_V4 } else { MAGIC });
        for x in [
            self.dim,
            s.step,
            k.u.len(),
            s.alpha.len(),
            controller.len(),
            s.time_origin.0,
        ] {
            b.extend_from_slice(&(x as u64).to_le_bytes());
        }
        if v4 {
            b.extend_from_slice(&tag.to_le_bytes());
            b.extend_from_slice(&(method.len() as u64).to_le_bytes());
        }
        for x in [s.time_origin.1, s.time, s.tau, self.wall_time_s] {
            b.extend_from_slice(&x.to_le_bytes());
        }
        b.extend_from_slice(&(text.len() as u64).to_le_bytes());
        b.extend_from_slice(text.as_bytes());
        for vec in [
            &k.u[..],
            &k.v[..],
            &k.a[..],
            &s.alpha[..],
            controller,
            &method,
        ] {
            for x in vec {
                b.extend_from_slice(&x.to_le_bytes());
            }
        }
        let crc = crc32fast::hash(&b);
        b.extend_from_slice(&crc.to_le_bytes());
        b
    }

    /// Writes the checkpoint atomically: a temporary file next to `path` (`path` with the
    /// extension `tmp`), flushed to disk, then renamed over `path`, so that an
    /// interruption leaves the previous checkpoint intact.
    ///
    /// # Errors
    /// [`Error::File`] naming the file and the operation.
    pub fn write(&self, path: &Path) -> Result<()> {
        write_atomically(path, &self.to_bytes())
    }

    /// Reads a checkpoint.
    ///
    /// # Errors
    /// [`Error::File`] if it cannot be read; [`Error::CheckpointCorrupt`] if it is not an
    /// rsf checkpoint, is truncated or extended, its checksum does not match (a changed
    /// bit anywhere) or its sizes or time origin are impossible.
    pub fn read(path: &Path) -> Result<Self> {
        let bytes = std::fs::read(path).map_err(io_at("read the checkpoint", path))?;
        Self::from_bytes(&bytes).map_err(|reason| Error::CheckpointCorrupt {
            path: show_path(path),
            reason,
        })
    }

    /// Parses the bytes of a checkpoint file (any of the four formats).
    ///
    /// # Errors
    /// What is wrong, as text.
    pub fn from_bytes(bytes: &[u8]) -> std::result::Result<Self, String> {
        let magic = bytes.get(..8).ok_or("not an rsf checkpoint")?;
        let version = match magic {
            m if m == MAGIC_V4 => 4,
            m if m == MAGIC => 3,
            m if m == MAGIC_V2 => 2,
            m if m == MAGIC_V1 => 1,
            _ => return Err("not an rsf checkpoint".into()),
        };
        let body = if version >= 3 {
            let header = if version == 4 { HEADER_V4 } else { HEADER_V3 };
            if bytes.len() < header + 4 {
                return Err("truncated".into());
            }
            let (body, crc) = bytes.split_at(bytes.len() - 4);
            let stored = u32::from_le_bytes(crc.try_into().expect("4 bytes"));
            if crc32fast::hash(body) != stored {
                return Err(
                    "checksum mismatch: the file was changed or cut after it was written".into(),
                );
            }
            body
        } else {
            bytes
        };
        let header = match version {
            1 => 48,
            2 => 80,
            3 => HEADER_V3,
            _ => HEADER_V4,
        };
        if body.len() < header {
            return Err("truncated".into());
        }
        let word = |i: usize| {
            let mut w = [0u8; 8];
            w.copy_from_slice(&body[8 + 8 * i..16 + 8 * i]);
            u64::from_le_bytes(w)
        };
        let to_usize = |w: u64| usize::try_from(w).map_err(|_| "size overflow".to_string());
        let (dim, step, n, nf) = (
            to_usize(word(0))?,
            to_usize(word(1))?,
            to_usize(word(2))?,
            to_usize(word(3))?,
        );
        // Format 4 has the method's tag and length after the sixth word.
        let w = |i: usize| {
            if version == 4 && i >= 6 {
                word(i + 2)
            } else {
                word(i)
            }
        };
        let (method_tag, nm) = if version == 4 {
            (word(6), to_usize(word(7))?)
        } else {
            (0, 0)
        };
        let (nc, time_origin, time, tau, wall_time_s, text_len) = match version {
            1 => {
                let tau = f64::from_bits(word(4));
                (0, (0, 0.0), step as f64 * tau, tau, 0.0, 0)
            }
            2 => (
                to_usize(word(4))?,
                (to_usize(word(5))?, f64::from_bits(word(6))),
                f64::from_bits(word(7)),
                f64::from_bits(word(8)),
                0.0,
                0,
            ),
            _ => (
                to_usize(w(4))?,
                (to_usize(w(5))?, f64::from_bits(w(6))),
                f64::from_bits(w(7)),
                f64::from_bits(w(8)),
                f64::from_bits(w(9)),
                to_usize(w(10))?,
            ),
        };
        if time_origin.0 > step {
            return Err("time origin after the current step".into());
        }
        if !(wall_time_s.is_finite() && wall_time_s >= 0.0) {
            return Err(format!("wall time {wall_time_s} s"));
        }
        let expected = n
            .checked_mul(24)
            .and_then(|x| x.checked_add(nf.checked_mul(8)?))
            .and_then(|x| x.checked_add(nc.checked_mul(8)?))
            .and_then(|x| x.checked_add(nm.checked_mul(8)?))
            .and_then(|x| x.checked_add(header))
            .and_then(|x| x.checked_add(text_len))
            .ok_or("size overflow")?;
        if body.len() != expected {
            return Err("truncated or oversized".into());
        }
        let fingerprint = std::str::from_utf8(&body[header..header + text_len])
            .ok()
            .and_then(Fingerprint::from_text)
            .ok_or("malformed fingerprint")?;
        let mut off = header + text_len;
        let mut take = |len: usize| {
            let out: Vec<f64> = body[off..off + 8 * len]
                .chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
                .collect();
            off += 8 * len;
            out
        };
        let (u, v, a, alpha, controller) = (take(n), take(n), take(n), take(nf), take(nc));
        let method = MethodState::from_values(method_tag, &take(nm))
            .map_err(|e| format!("method state: {e}"))?;
        let controller = match controller.len() {
            0 => None,
            _ => Some(
                ControllerState::from_values(&controller)
                    .map_err(|e| format!("controller state: {e}"))?,
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
            fingerprint,
            wall_time_s,
            method,
        })
    }
}

/// [`Error::CheckpointSize`] naming `what` unless the checkpoint's size equals the
/// simulation's (the checks every method's `restore` makes).
pub(crate) fn check_size(what: &'static str, checkpoint: usize, simulation: usize) -> Result<()> {
    if checkpoint == simulation {
        Ok(())
    } else {
        Err(Error::CheckpointSize {
            what,
            checkpoint,
            simulation,
        })
    }
}

/// [`Error::CheckpointValue`]: entry `index` of `what` in a checkpoint is `value`, which
/// fails `requirement`.
pub(crate) fn bad_value(
    what: &'static str,
    index: usize,
    value: f64,
    requirement: &'static str,
) -> Error {
    Error::CheckpointValue {
        what,
        index,
        value,
        requirement,
    }
}

/// Writes `bytes` to `path` atomically: a temporary file next to it (`path` with the
/// extension `tmp`), synced, then renamed over `path`. An interruption or a failure leaves
/// the old `path` intact.
///
/// # Errors
/// [`Error::File`] naming the file and the operation.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = tmp_path(path);
    let result = (|| {
        let mut f = std::fs::File::create(&tmp).map_err(io_at("create", &tmp))?;
        f.write_all(bytes).map_err(io_at("write", &tmp))?;
        f.sync_all().map_err(io_at("sync", &tmp))?;
        std::fs::rename(&tmp, path).map_err(io_at("rename a temporary file over", path))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// The temporary file of an atomic write of `path`: `path` with `.tmp` appended to its
/// extension (`checkpoint.bin` → `checkpoint.bin.tmp`).
pub(crate) fn tmp_path(path: &Path) -> std::path::PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    path.with_file_name(name)
}

#[cfg(test)]
mod tests {
    use super::{Checkpoint, Fingerprint};
    use crate::simulation_state::SimulationState;
    use crate::Error;
    use rsf_time::Kinematics;

    fn sample() -> Checkpoint {
        let mut c = Checkpoint::new(
            2,
            SimulationState {
                step: 7,
                time: 0.7,
                tau: 0.1,
                time_origin: (0, 0.0),
                kinematics: Kinematics {
                    u: vec![1.0, -2.0],
                    v: vec![0.5, 0.25],
                    a: vec![0.0, 1e-300],
                },
                alpha: vec![3.0],
                controller: None,
            },
        );
        c.fingerprint = Fingerprint::default()
            .with("law", "aging")
            .with("steps", 10);
        c.wall_time_s = 1.5;
        c
    }

    /// Every single-bit flip and every truncation of `bytes` is refused.
    fn assert_every_flip_and_cut_is_detected(bytes: &[u8]) {
        for i in 0..bytes.len() * 8 {
            let mut b = bytes.to_vec();
            b[i / 8] ^= 1 << (i % 8);
            assert!(Checkpoint::from_bytes(&b).is_err(), "bit {i}");
        }
        for len in 0..bytes.len() {
            assert!(
                Checkpoint::from_bytes(&bytes[..len]).is_err(),
                "length {len}"
            );
        }
    }

    #[test]
    fn round_trips_and_detects_every_single_bit_flip() {
        let c = sample();
        let bytes = c.to_bytes();
        assert_eq!(Checkpoint::from_bytes(&bytes), Ok(c));
        assert_every_flip_and_cut_is_detected(&bytes);
    }

    #[test]
    fn method_states_round_trip_as_format_4_and_detect_every_bit_flip() {
        use crate::method_state::{FaultOdeState, MethodState, Phase, SwitchingStats};
        let implicit = sample().to_bytes();
        assert_eq!(&implicit[..8], b"RSFCKPT3");
        let mut c = sample();
        c.method = MethodState::Switching {
            phase: Phase::QuasiDynamic,
            stats: SwitchingStats {
                dynamic_phases: 1,
                dynamic_steps: 10,
                quasi_dynamic_steps: 20,
                dynamic_time: 3.5,
            },
            fault_ode: Some(FaultOdeState {
                controller: rsf_time::RungeKuttaState {
                    dt: 0.5,
                    previous_error: 0.25,
                },
                rate: vec![1.0, 2.0, -3.0],
                evaluations: 99,
            }),
        };
        let bytes = c.to_bytes();
        assert_eq!(&bytes[..8], b"RSFCKPT4");
        assert_eq!(Checkpoint::from_bytes(&bytes), Ok(c));
        assert_every_flip_and_cut_is_detected(&bytes);
    }

    #[test]
    fn fingerprints_name_the_first_differing_field() {
        let c = sample().fingerprint;
        assert!(c.check(&c, &[]).is_ok());
        let run = Fingerprint::default()
            .with("law", "aging")
            .with("steps", 20);
        let e = c.check(&run, &[]).unwrap_err();
        let Error::CheckpointMismatch {
            field,
            checkpoint,
            run: r,
        } = &e
        else {
            panic!("{e}")
        };
        assert_eq!((&field[..], &checkpoint[..], &r[..]), ("steps", "10", "20"));
        assert!(c.check(&run, &["steps"]).is_ok());
        let e = Fingerprint::default().check(&run, &[]).unwrap_err();
        assert!(e.to_string().contains("`format`"), "{e}");
        let fewer = Fingerprint::default().with("law", "aging");
        assert!(c
            .check(&fewer, &[])
            .unwrap_err()
            .to_string()
            .contains("`steps`"));
    }
}
