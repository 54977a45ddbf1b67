//! Time series at one node of the model, as CSV.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::checkpoint::Checkpoint;
use crate::error::{io_at, show_path, Error, Result};
use crate::model::Model;

use super::files::{self, FileMode, AXES};
use super::{Flow, Observer, StepView};

/// Time series at one node: one CSV row per step,
/// `t_s,u_x0_m,v_x0_mps,max_slip_rate_mps,fpi,tau_s,step,solver_iterations,relaxed_iterations`
/// followed, for `D ≥ 2`, by `u_y0_m,v_y0_mps` (and `u_z0_m,v_z0_mps` in 3D): time,
/// displacement and velocity components at the node, the largest slip rate on Γ_F, the
/// step's fixed point iterations, τ, the step index, velocity-solver iterations and damped
/// fixed point iterations. Components are in model coordinates ([`Model`]): at a slanted
/// fault node (one with a nodal frame) `x`, `y`(, `z`) stand for the frame's tangent(s) and
/// normal, i.e. slip coordinates; Cartesian elsewhere. Rows are flushed every step (by default) so that a killed run
/// keeps what it wrote; [`FileMode::Resume`] continues a file after a checkpoint.
pub struct PointSeries<const D: usize> {
    node: usize,
    out: BufWriter<File>,
    /// The file, for errors.
    path: PathBuf,
    flush_every: usize,
    rows: usize,
}

/// One row of a [`PointSeries`] file, as read back by [`PointSeries::read`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeriesRow<const D: usize> {
    /// Step index n.
    pub step: usize,
    /// Time t_n (s; written with 10 significant digits).
    pub time: f64,
    /// Time step τ of the step (s; exact).
    pub tau: f64,
    /// Displacement at the node (m).
    pub u: [f64; D],
    /// Velocity at the node (m/s).
    pub v: [f64; D],
    /// Largest slip rate on Γ_F (m/s).
    pub max_slip_rate: f64,
    /// Fixed point iterations.
    pub fixed_point_iterations: usize,
    /// Velocity-solver iterations.
    pub solver_iterations: usize,
    /// Damped fixed point iterations.
    pub relaxed_iterations: usize,
}

impl<const D: usize> PointSeries<D> {
    /// The CSV header.
    pub fn header() -> String {
        let mut h = String::from(
            "t_s,u_x0_m,v_x0_mps,max_slip_rate_mps,fpi,tau_s,step,solver_iterations,relaxed_iterations",
        );
        for axis in AXES.iter().take(D).skip(1) {
            h.push_str(&format!(",u_{axis}0_m,v_{axis}0_mps"));
        }
        h
    }

    /// The series at `node` of `model` in the file `path`, new or continued after a
    /// checkpoint ([`FileMode`]).
    ///
    /// # Errors
    /// [`Error::NodeOutOfRange`](crate::Error::NodeOutOfRange); for [`FileMode::Resume`], [`Error::Resume`](crate::Error::Resume) if the file
    /// is missing, has another header, or its rows end before the checkpoint's step (e.g.
    /// rows buffered by [`flush_every`](Self::flush_every) and lost); I/O errors.
    pub fn new(path: &Path, model: &Model<D>, node: usize, mode: FileMode) -> Result<Self> {
        model.check_node("point series", node)?;
        Ok(Self {
            node,
            out: files::open(path, &Self::header(), 6, mode.start(true))?,
            path: path.to_path_buf(),
            flush_every: 1,
            rows: 0,
        })
    }

    /// Flush only every `n` rows (default 1). A checkpoint written at a step whose row is
    /// not flushed yet cannot be resumed without loss ([`FileMode::Resume`] reports
    /// it): use an `n` that divides the checkpoint interval.
    pub fn flush_every(mut self, n: usize) -> Self {
        self.flush_every = n.max(1);
        self
    }

    /// Checks, without changing it, that the file `path` can be continued after a
    /// checkpoint of step `step` ([`FileMode::Resume`]), so that a run can check all its
    /// files before it cuts any.
    ///
    /// # Errors
    /// As [`new`](Self::new) with [`FileMode::Resume`].
    pub fn check_resume(path: &Path, step: usize) -> Result<()> {
        files::check_resume(path, &Self::header(), 6, step, true)
    }

    /// Checks that the row of the checkpoint `c`'s step in the series file `path` (at the
    /// node `node`) shows the checkpoint's time, displacement and velocity exactly as the
    /// series writes them: the folder's rows and the checkpoint are of the same run. A
    /// checkpoint at step 0 has no row to compare. Changes nothing.
    ///
    /// # Errors
    /// [`Error::Resume`](crate::Error::Resume) naming the file if the row is missing or
    /// differs; [`Error::File`](crate::Error::File).
    pub fn check_checkpoint_row(path: &Path, c: &Checkpoint, node: usize) -> Result<()> {
        let step = c.state.step;
        if step == 0 {
            return Ok(());
        }
        let fail = |reason: String| Error::Resume {
            path: show_path(path),
            reason,
        };
        let text = std::fs::read_to_string(path).map_err(io_at("read", path))?;
        let want = step.to_string();
        let Some(row) = text
            .split_inclusive('\n')
            .filter(|l| l.ends_with('\n'))
            .map(|l| l.trim_end().split(',').collect::<Vec<_>>())
            .find(|f| f.get(6) == Some(&want.as_str()))
        else {
            return Err(fail(format!(
                "it has no row of the checkpoint's step {step}: the checkpoint is not of this \
                 run folder"
            )));
        };
        let (u, v) = (&c.state.kinematics.u, &c.state.kinematics.v);
        let i = D * node;
        if u.len() < i + D || v.len() < i + D {
            return Err(fail(
                "the checkpoint has fewer nodes than the series' node".into(),
            ));
        }
        let mut expected = vec![
            (0, format!("{:.9e}", c.state.time)),
            (1, format!("{:.12e}", u[i])),
            (2, format!("{:.12e}", v[i])),
        ];
        for k in 1..D {
            expected.push((9 + 2 * (k - 1), format!("{:.12e}", u[i + k])));
            expected.push((10 + 2 * (k - 1), format!("{:.12e}", v[i + k])));
        }
        for (col, value) in expected {
            if row.get(col) != Some(&value.as_str()) {
                return Err(fail(format!(
                    "its row of step {step} has `{}` in column {col}, the checkpoint gives \
                     `{value}`: the checkpoint belongs to another run (nothing was changed)",
                    rsf_numeric::excerpt(row.get(col).unwrap_or(&"")),
                )));
            }
        }
        Ok(())
    }

    /// Reads a file written by a `PointSeries<D>`.
    ///
    /// # Errors
    /// I/O errors; [`Error::Resume`](crate::Error::Resume) for another header or a malformed row.
    pub fn read(path: &Path) -> Result<Vec<SeriesRow<D>>> {
        files::read_rows(path, &Self::header(), parse_row::<D>)
    }
}

fn parse_row<const D: usize>(f: &[&str]) -> Option<SeriesRow<D>> {
    if f.len() != 9 + 2 * (D - 1) {
        return None;
    }
    let x = |i: usize| f[i].parse::<f64>().ok();
    let n = |i: usize| f[i].parse::<usize>().ok();
    let mut u = [0.0; D];
    let mut v = [0.0; D];
    u[0] = x(1)?;
    v[0] = x(2)?;
    for c in 1..D {
        u[c] = x(9 + 2 * (c - 1))?;
        v[c] = x(10 + 2 * (c - 1))?;
    }
    Some(SeriesRow {
        time: x(0)?,
        u,
        v,
        max_slip_rate: x(3)?,
        fixed_point_iterations: n(4)?,
        tau: x(5)?,
        step: n(6)?,
        solver_iterations: n(7)?,
        relaxed_iterations: n(8)?,
    })
}

impl<const D: usize> Observer<D> for PointSeries<D> {
    fn observe(&mut self, s: &StepView<'_, D>) -> Result<Flow> {
        let (u, v) = (&s.state.kinematics.u, &s.state.kinematics.v);
        let r = s.report;
        let i = D * self.node;
        write!(
            self.out,
            "{:.9e},{:.12e},{:.12e},{:.12e},{},{:e},{},{},{}",
            r.time,
            u[i],
            v[i],
            r.max_slip_rate,
            r.fixed_point_iterations,
            r.tau,
            r.step,
            r.solver_iterations,
            r.relaxed_iterations
        )
        .map_err(io_at("write a row of", &self.path))?;
        for c in 1..D {
            write!(self.out, ",{:.12e},{:.12e}", u[i + c], v[i + c])
                .map_err(io_at("write a row of", &self.path))?;
        }
        writeln!(self.out).map_err(io_at("write a row of", &self.path))?;
        self.rows += 1;
        if self.rows % self.flush_every == 0 {
            self.out.flush().map_err(io_at("flush", &self.path))?;
        }
        Ok(Flow::Continue(()))
    }
    fn finish(&mut self) -> Result<()> {
        self.out.flush().map_err(io_at("flush", &self.path))?;
        Ok(())
    }
}
