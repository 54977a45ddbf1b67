//! Checkpoints: the complete dynamic state of a simulation in a small binary file that
//! vouches for itself (docs/reliability.md).
//!
//! Format `RSFCKPT6`: the magic `RSFCKPT6`, then one serde value — the pair of the private
//! `Payload` (dimension, step, time origin, time, τ, wall time, the [`Fingerprint`]'s
//! pairs, `u`, `v`, `a`, `alpha`, the step controller's values, the method's tag and
//! values) and the run's id ([`Checkpoint::run_id`]) — encoded by
//! [postcard](https://docs.rs/postcard) — varint integers and lengths, every `f64` as its 8
//! bytes, so a resumed run is bit-identical to an uninterrupted one — and last the CRC-32
//! (IEEE, `u32` little endian) of every byte before it. `RSFCKPT5` is the same without the
//! run's id. Files of `RSFCKPT5` and of the earlier, hand-written formats (`RSFCKPT4`,
//! `RSFCKPT3`: the same content, with a checksum; `RSFCKPT2`: no fingerprint, no checksum;
//! `RSFCKPT1`: also no time, no controller) are still **read** (a run checkpointed by an
//! earlier version resumes; its run is unknown: an empty id) and never written; those
//! without a fingerprint get an empty one, which [`Fingerprint::check`] refuses.

use std::borrow::Cow;
use std::io::Write;
use std::path::Path;

use rsf_time::{ControllerState, Kinematics};

pub use crate::method_state::{FaultOdeState, MethodState, Phase, SwitchingStats};
pub use crate::simulation_state::SimulationState;

use crate::error::{io_at, show_path, Error, Result};

mod fingerprint;
mod legacy;
mod payload;

pub use fingerprint::{Fingerprint, CHECKPOINT_FORMAT};
use payload::Payload;

/// The magic of the files this version writes.
const MAGIC: &[u8; 8] = b"RSFCKPT6";
/// The magic of the previous format: the same content without the run's id.
const MAGIC_V5: &[u8; 8] = b"RSFCKPT5";
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
    /// The run the checkpoint belongs to: the run id of the run folder it was written into
    /// ([`crate::run_folder::MANIFEST`]'s `run=`, set by the
    /// [`Checkpointer`](crate::observe::Checkpointer)), so that a resume into another
    /// run's folder is refused ([`RunFolder::prepare_resume`](crate::run_folder::RunFolder::prepare_resume)).
    /// Empty if unknown: written outside a run folder, or by a version before `RSFCKPT6`.
    pub run_id: String,
}

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
            run_id: String::new(),
        }
    }

    /// The bytes of the file (format `RSFCKPT6`, with its checksum: module docs).
    pub fn to_bytes(&self) -> Vec<u8> {
        let value = (self.payload(), self.run_id.as_str());
        let mut b = postcard::to_extend(&value, MAGIC.to_vec())
            .expect("numbers, strings and vectors always serialise");
        let crc = crc32fast::hash(&b);
        b.extend_from_slice(&crc.to_le_bytes());
        b
    }

    /// The checkpoint as the file's serde value, borrowing its vectors.
    fn payload(&self) -> Payload<'_> {
        let s = &self.state;
        let k = &s.kinematics;
        Payload {
            dim: self.dim as u64,
            step: s.step as u64,
            time_origin: (s.time_origin.0 as u64, s.time_origin.1),
            time: s.time,
            tau: s.tau,
            wall_time_s: self.wall_time_s,
            fingerprint: Cow::Borrowed(&self.fingerprint.0),
            u: Cow::Borrowed(&k.u),
            v: Cow::Borrowed(&k.v),
            a: Cow::Borrowed(&k.a),
            alpha: Cow::Borrowed(&s.alpha),
            controller: s.controller.map_or(Vec::new(), |c| c.to_values().to_vec()),
            method: self.method.to_values(),
        }
    }

    /// The checkpoint of a file's serde value, checked: sizes that fit this machine, `u`,
    /// `v` and `a` of one length, the time origin not after the step, a finite wall time,
    /// a valid controller and method state.
    fn from_payload(p: Payload<'_>) -> std::result::Result<Self, String> {
        let to_usize = |w: u64| usize::try_from(w).map_err(|_| "size overflow".to_string());
        let (dim, step) = (to_usize(p.dim)?, to_usize(p.step)?);
        let time_origin = (to_usize(p.time_origin.0)?, p.time_origin.1);
        if time_origin.0 > step {
            return Err("time origin after the current step".into());
        }
        if !(p.wall_time_s.is_finite() && p.wall_time_s >= 0.0) {
            return Err(format!("wall time {} s", p.wall_time_s));
        }
        if p.v.len() != p.u.len() || p.a.len() != p.u.len() {
            return Err("u, v and a of different lengths".into());
        }
        let method = MethodState::from_values(p.method.0, &p.method.1)
            .map_err(|e| format!("method state: {e}"))?;
        let controller = match p.controller.len() {
            0 => None,
            _ => Some(
                ControllerState::from_values(&p.controller)
                    .map_err(|e| format!("controller state: {e}"))?,
            ),
        };
        Ok(Self {
            dim,
            state: SimulationState {
                step,
                time: p.time,
                tau: p.tau,
                time_origin,
                kinematics: Kinematics {
                    u: p.u.into_owned(),
                    v: p.v.into_owned(),
                    a: p.a.into_owned(),
                },
                alpha: p.alpha.into_owned(),
                controller,
            },
            fingerprint: Fingerprint(p.fingerprint.into_owned()),
            wall_time_s: p.wall_time_s,
            method,
            run_id: String::new(),
        })
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
        let (mut file, len, mut bytes) = Self::open(path)?;
        bytes.extend(crate::input_file::read_at_most(
            &mut file,
            len.saturating_sub(8),
            path,
            READ_ACTION,
        )?);
        Self::from_bytes(&bytes).map_err(|reason| Error::CheckpointCorrupt {
            path: show_path(path),
            reason,
        })
    }

    /// Opens the checkpoint `path` and reads its magic (checks before reads, issue 87): a
    /// regular file only (not `/dev/zero`, not a FIFO), its first 8 bytes a known format's
    /// magic — so that a large file of another kind is refused after 8 bytes, not read
    /// whole. Returns the file, its length and the magic.
    fn open(path: &Path) -> Result<(std::fs::File, u64, Vec<u8>)> {
        let (mut file, len) = crate::input_file::open_regular(path, READ_ACTION)?;
        let magic = crate::input_file::read_at_most(&mut file, 8, path, READ_ACTION)?;
        if magic.len() < 8 || !known_magic(&magic) {
            return Err(Error::CheckpointCorrupt {
                path: show_path(path),
                reason: format!(
                    "not an rsf checkpoint (its first bytes are not a checkpoint's magic \
                     `RSFCKPTn`; {len} bytes)"
                ),
            });
        }
        Ok((file, len, magic))
    }

    /// Parses the bytes of a checkpoint file (`RSFCKPT6` or any earlier format).
    ///
    /// # Errors
    /// What is wrong, as text: not an rsf checkpoint, truncated or extended, a checksum
    /// mismatch (a changed bit anywhere), a malformed value, impossible sizes or times.
    pub fn from_bytes(bytes: &[u8]) -> std::result::Result<Self, String> {
        let magic = bytes.get(..8).ok_or("not an rsf checkpoint")?;
        if magic != MAGIC && magic != MAGIC_V5 {
            let version = legacy::version(magic).ok_or("not an rsf checkpoint")?;
            return Self::from_payload(legacy::parse(bytes, version)?);
        }
        let body = checked_body(bytes, MAGIC.len())?;
        let content = &body[MAGIC.len()..];
        let malformed = |e: postcard::Error| format!("malformed: {e}");
        let (payload, run_id, rest) = if magic == MAGIC {
            let ((payload, run_id), rest) =
                postcard::take_from_bytes::<(Payload<'_>, String)>(content).map_err(malformed)?;
            (payload, run_id, rest)
        } else {
            let (payload, rest) =
                postcard::take_from_bytes::<Payload<'_>>(content).map_err(malformed)?;
            (payload, String::new(), rest)
        };
        if !rest.is_empty() {
            return Err("oversized: bytes after the checkpoint's content".into());
        }
        Ok(Self {
            run_id,
            ..Self::from_payload(payload)?
        })
    }
}

/// The action of a checkpoint's read, as an error names it.
const READ_ACTION: &str = "read the checkpoint";

/// Whether `magic` (8 bytes) is the magic of a checkpoint format this version reads.
/// `bytes` without its last 4 bytes, the CRC-32 (little-endian) of the others, checked
/// against them.
///
/// # Errors
/// `truncated` if `bytes` are shorter than a `header` and the checksum; a checksum
/// mismatch.
fn checked_body(bytes: &[u8], header: usize) -> std::result::Result<&[u8], String> {
    if bytes.len() < header + 4 {
        return Err("truncated".into());
    }
    let (body, crc) = bytes.split_at(bytes.len() - 4);
    let stored = u32::from_le_bytes(crc.try_into().expect("4 bytes"));
    if crc32fast::hash(body) != stored {
        return Err("checksum mismatch: the file was changed or cut after it was written".into());
    }
    Ok(body)
}

fn known_magic(magic: &[u8]) -> bool {
    magic == MAGIC || magic == MAGIC_V5 || legacy::version(magic).is_some()
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
        c.run_id = "0123456789abcdef0123456789abcdef".into();
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
    fn method_states_round_trip_and_detect_every_bit_flip() {
        let implicit = sample().to_bytes();
        assert_eq!(&implicit[..8], b"RSFCKPT6");
        let c = switching_sample();
        let bytes = c.to_bytes();
        assert_eq!(&bytes[..8], b"RSFCKPT6");
        assert_eq!(Checkpoint::from_bytes(&bytes), Ok(c));
        assert_every_flip_and_cut_is_detected(&bytes);
    }

    fn switching_sample() -> Checkpoint {
        use crate::method_state::{FaultOdeState, MethodState, Phase, SwitchingStats};
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
                stabilized: None,
            }),
        };
        c
    }

    /// Files of the formats 3 and 4 (written by the versions before `RSFCKPT5`) are still
    /// read, to the same checkpoint (whose run is unknown), and vouch for themselves as
    /// before.
    #[test]
    fn files_of_formats_3_and_4_are_still_read() {
        for (c, magic) in [(sample(), b"RSFCKPT3"), (switching_sample(), b"RSFCKPT4")] {
            let old = super::legacy::to_bytes(&c.payload());
            assert_eq!(&old[..8], magic);
            let unknown = Checkpoint {
                run_id: String::new(),
                ..c
            };
            assert_eq!(Checkpoint::from_bytes(&old), Ok(unknown));
            assert_every_flip_and_cut_is_detected(&old);
        }
    }

    /// A file of format 5 (the payload alone, before the run's id) is still read, to the
    /// same checkpoint with an unknown run; format 6 carries the run's id.
    #[test]
    fn files_of_format_5_are_still_read_without_a_run_id() {
        let c = switching_sample();
        let mut old = postcard::to_extend(&c.payload(), b"RSFCKPT5".to_vec()).unwrap();
        let crc = crc32fast::hash(&old);
        old.extend_from_slice(&crc.to_le_bytes());
        let unknown = Checkpoint {
            run_id: String::new(),
            ..c.clone()
        };
        assert_eq!(Checkpoint::from_bytes(&old), Ok(unknown));
        assert_every_flip_and_cut_is_detected(&old);
        assert_eq!(
            Checkpoint::from_bytes(&c.to_bytes()).unwrap().run_id,
            c.run_id
        );
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
