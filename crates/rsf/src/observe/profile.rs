//! Slip rate and state along the frictional boundary over a time window, as CSV.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::error::{invalid, io_at, Result};

use super::files::{self, FileMode, AXES};
use super::{Flow, Observer, StepView};

/// Slip rate and state along Γ_F over a time window: CSV
/// `t_s,x_m,slip_rate_mps,alpha,step` (+ `y_m`, and `z_m` in 3D), one row per frictional
/// node (in `model.frictional_boundary.along` order) per step shown with `t ∈ [t0, t1]` (wrap it
/// in [`Every`](crate::observe::Every) to sample). Flushed after every recorded step;
/// [`FileMode::Resume`] continues a file after a checkpoint.
pub struct FrictionalProfile<const D: usize> {
    window: (f64, f64),
    out: BufWriter<File>,
    /// The file, for errors.
    path: PathBuf,
}

impl<const D: usize> FrictionalProfile<D> {
    /// The CSV header.
    pub fn header() -> String {
        let mut h = String::from("t_s,x_m,slip_rate_mps,alpha,step");
        for axis in AXES.iter().take(D).skip(1) {
            h.push_str(&format!(",{axis}_m"));
        }
        h
    }

    /// The profile of the steps with `t ∈ [t0, t1]` (s; `t1` may be `f64::INFINITY`) in the
    /// file `path`, new or continued after a checkpoint ([`FileMode`]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) for a NaN or empty window; for [`FileMode::Resume`],
    /// [`Error::Resume`](crate::Error::Resume) for a missing file, another header or a malformed row; I/O
    /// errors.
    pub fn new(path: &Path, (t0, t1): (f64, f64), mode: FileMode) -> Result<Self> {
        if t0.is_nan() || t1.is_nan() || t0 > t1 {
            return Err(invalid(
                "profile window",
                format!("[{t0}, {t1}] s must be ordered numbers"),
            ));
        }
        Ok(Self {
            window: (t0, t1),
            out: files::open(path, &Self::header(), 4, mode.start(false))?,
            path: path.to_path_buf(),
        })
    }

    /// Checks, without changing it, that the file `path` can be continued after a
    /// checkpoint of step `step` ([`FileMode::Resume`]), so that a run can check all its
    /// files before it cuts any.
    ///
    /// # Errors
    /// As [`new`](Self::new) with [`FileMode::Resume`].
    pub fn check_resume(path: &Path, step: usize) -> Result<()> {
        files::check_resume(path, &Self::header(), 4, step, false)
    }

    /// Reads a file written by a `FrictionalProfile<D>`.
    ///
    /// # Errors
    /// I/O errors; [`Error::Resume`](crate::Error::Resume) for another header or a malformed row.
    pub fn read(path: &Path) -> Result<Vec<ProfileRow<D>>> {
        files::read_rows(path, &Self::header(), |f| {
            if f.len() != 4 + D {
                return None;
            }
            let x = |i: usize| f[i].parse::<f64>().ok();
            let mut position = [0.0; D];
            position[0] = x(1)?;
            for c in 1..D {
                position[c] = x(4 + c)?;
            }
            Some(ProfileRow {
                time: x(0)?,
                position,
                slip_rate: x(2)?,
                alpha: x(3)?,
                step: f[4].parse().ok()?,
            })
        })
    }
}

/// One row of a [`FrictionalProfile`] file, as read back by [`FrictionalProfile::read`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProfileRow<const D: usize> {
    /// Step index n.
    pub step: usize,
    /// Time t_n (s; 10 significant digits).
    pub time: f64,
    /// Position of the node (m; 7 significant digits).
    pub position: [f64; D],
    /// Slip rate |v_p| (m/s).
    pub slip_rate: f64,
    /// State α_p.
    pub alpha: f64,
}

impl<const D: usize> Observer<D> for FrictionalProfile<D> {
    fn observe(&mut self, s: &StepView<'_, D>) -> Result<Flow> {
        let t = s.report.time;
        if t < self.window.0 || t > self.window.1 {
            return Ok(Flow::Continue(()));
        }
        let fb = &s.model.frictional_boundary;
        for &k in &fb.along {
            let x = &s.model.vertices[fb.nodes[k]];
            let rate = s.slip_rate(k);
            write!(
                self.out,
                "{t:.9e},{:.6e},{rate:.9e},{:.9e},{}",
                x[0], s.state.alpha[k], s.report.step
            )
            .map_err(io_at("write a row of", &self.path))?;
            for xc in x.iter().skip(1) {
                write!(self.out, ",{xc:.6e}").map_err(io_at("write a row of", &self.path))?;
            }
            writeln!(self.out).map_err(io_at("write a row of", &self.path))?;
        }
        self.out.flush().map_err(io_at("flush", &self.path))?;
        Ok(Flow::Continue(()))
    }
    fn finish(&mut self) -> Result<()> {
        self.out.flush().map_err(io_at("flush", &self.path))?;
        Ok(())
    }
    fn reads_volume(&self) -> bool {
        false
    }
}
