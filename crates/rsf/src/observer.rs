//! What a run records. A scene that records nothing computes nothing extra: every observer
//! does its own (cheap) extraction from the state it is shown.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use rsf_time::Kinematics;

use crate::checkpoint::Checkpoint;
use crate::error::{invalid, Error, Result};
use crate::model::Model;
use crate::output::{self, Start};
use crate::simulation::{block_norm, StepReport};

/// The state after a step, as shown to observers.
pub struct StepState<'a, const D: usize> {
    /// The model.
    pub model: &'a Model<D>,
    /// `(u, v, a)` at `t_n`.
    pub kinematics: &'a Kinematics,
    /// α per frictional node (`model.frictional.nodes` order).
    pub alpha: &'a [f64],
    /// The step's report.
    pub report: &'a StepReport,
    /// Step index and time where the current τ began (see [`Checkpoint::time_origin`]).
    pub time_origin: (usize, f64),
    /// The step controller of adaptive time steps, if any.
    pub controller: Option<&'a rsf_time::StepController>,
}

impl<const D: usize> StepState<'_, D> {
    /// A checkpoint of this state.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            dim: D,
            step: self.report.step,
            time: self.report.time,
            tau: self.report.tau,
            time_origin: self.time_origin,
            controller: self
                .controller
                .map_or_else(Vec::new, rsf_time::StepController::to_state),
            u: self.kinematics.u.clone(),
            v: self.kinematics.v.clone(),
            a: self.kinematics.a.clone(),
            alpha: self.alpha.to_vec(),
        }
    }
}

/// What an observer tells the run after a step: [`Flow::Continue`] or [`Flow::Break`] (end
/// the run after this step, e.g. at a slip event).
pub type Flow = std::ops::ControlFlow<()>;

/// Something that looks at the simulation after each step.
pub trait Observer<const D: usize> {
    /// Called after every successful step; [`Flow::Break`] ends the run after this step.
    ///
    /// # Errors
    /// I/O errors end the run.
    fn observe(&mut self, state: &StepState<'_, D>) -> Result<Flow>;

    /// Called once after the last step of a [`run`](crate::Simulation::run).
    ///
    /// # Errors
    /// I/O errors.
    fn finish(&mut self) -> Result<()> {
        Ok(())
    }
}

/// Coordinate names of the CSV columns.
const AXES: [&str; 3] = ["x", "y", "z"];

/// Time series at one node: one CSV row per step,
/// `t_s,u_x0_m,v_x0_mps,max_slip_rate_mps,fpi,tau_s,step,solver_iterations,relaxed_iterations`
/// followed, for `D ≥ 2`, by `u_y0_m,v_y0_mps` (and `u_z0_m,v_z0_mps` in 3D): time,
/// displacement and velocity components at the node, the largest slip rate on Γ_F, the
/// step's fixed point iterations, τ, the step index, velocity-solver iterations and damped
/// fixed point iterations. Rows are flushed every step (by default) so that a killed run
/// keeps what it wrote; [`PointSeries::resume`] continues a file after a checkpoint.
pub struct PointSeries<const D: usize> {
    node: usize,
    out: BufWriter<File>,
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

    /// Writes to `path` (created/truncated) the series at `node` of `model`.
    ///
    /// # Errors
    /// [`Error::NodeOutOfRange`]; I/O errors.
    pub fn create(path: &Path, model: &Model<D>, node: usize) -> Result<Self> {
        Self::open(path, model, node, Start::Fresh)
    }

    /// Continues the series in `path` after a checkpoint of step `step`: rows of later
    /// steps (written before the interruption) are removed, new rows appended. Together
    /// with [`Simulation::restore`](crate::Simulation::restore) the file ends up
    /// byte-identical to that of an uninterrupted run.
    ///
    /// # Errors
    /// [`Error::NodeOutOfRange`]; [`Error::Resume`] if the file is missing, has another
    /// header, or its rows end before `step` (e.g. rows buffered by
    /// [`flush_every`](Self::flush_every) and lost); I/O errors.
    pub fn resume(path: &Path, model: &Model<D>, node: usize, step: usize) -> Result<Self> {
        let every_step = true;
        Self::open(path, model, node, Start::Resume { step, every_step })
    }

    fn open(path: &Path, model: &Model<D>, node: usize, start: Start) -> Result<Self> {
        model.check_node("point series", node)?;
        Ok(Self {
            node,
            out: output::open(path, &Self::header(), 6, start)?,
            flush_every: 1,
            rows: 0,
        })
    }

    /// Flush only every `n` rows (default 1). A checkpoint written at a step whose row is
    /// not flushed yet cannot be resumed without loss ([`resume`](Self::resume) reports
    /// it): use an `n` that divides the checkpoint interval.
    pub fn flush_every(mut self, n: usize) -> Self {
        self.flush_every = n.max(1);
        self
    }

    /// Reads a file written by a `PointSeries<D>`.
    ///
    /// # Errors
    /// I/O errors; [`Error::Resume`] for another header or a malformed row.
    pub fn read(path: &Path) -> Result<Vec<SeriesRow<D>>> {
        read_rows(path, &Self::header(), parse_row::<D>)
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
    fn observe(&mut self, s: &StepState<'_, D>) -> Result<Flow> {
        let (u, v) = (&s.kinematics.u, &s.kinematics.v);
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
        )?;
        for c in 1..D {
            write!(self.out, ",{:.12e},{:.12e}", u[i + c], v[i + c])?;
        }
        writeln!(self.out)?;
        self.rows += 1;
        if self.rows % self.flush_every == 0 {
            self.out.flush()?;
        }
        Ok(Flow::Continue(()))
    }
    fn finish(&mut self) -> Result<()> {
        self.out.flush()?;
        Ok(())
    }
}

/// Slip rate and state along Γ_F over a time window: CSV
/// `t_s,x_m,slip_rate_mps,alpha,step` (+ `y_m`, and `z_m` in 3D), one row per frictional
/// node (in `model.frictional.along` order) per recorded step: every `every`-th step with
/// `t ∈ [t0, t1]`. Flushed after every recorded step; [`FrictionalProfile::resume`]
/// continues a file after a checkpoint.
pub struct FrictionalProfile<const D: usize> {
    window: (f64, f64),
    every: usize,
    out: BufWriter<File>,
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

    /// Records steps with `t ∈ [t0, t1]` (s; `t1` may be `f64::INFINITY`), every
    /// `every`-th step (`every ≥ 1`).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a NaN or empty window or `every = 0`; I/O errors.
    pub fn create(path: &Path, t0: f64, t1: f64, every: usize) -> Result<Self> {
        Self::open(path, t0, t1, every, Start::Fresh)
    }

    /// As [`create`](Self::create), continuing `path` after a checkpoint of step `step`
    /// (see [`PointSeries::resume`]).
    ///
    /// # Errors
    /// As [`create`](Self::create); [`Error::Resume`] for a missing file, another header or
    /// a malformed row.
    pub fn resume(path: &Path, t0: f64, t1: f64, every: usize, step: usize) -> Result<Self> {
        let every_step = false;
        Self::open(path, t0, t1, every, Start::Resume { step, every_step })
    }

    /// Reads a file written by a `FrictionalProfile<D>`.
    ///
    /// # Errors
    /// I/O errors; [`Error::Resume`] for another header or a malformed row.
    pub fn read(path: &Path) -> Result<Vec<ProfileRow<D>>> {
        read_rows(path, &Self::header(), |f| {
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

    fn open(path: &Path, t0: f64, t1: f64, every: usize, start: Start) -> Result<Self> {
        if t0.is_nan() || t1.is_nan() || t0 > t1 {
            return Err(invalid(
                "profile window",
                format!("[{t0}, {t1}] s must be ordered numbers"),
            ));
        }
        if every == 0 {
            return Err(invalid("profile every", "must be at least 1"));
        }
        Ok(Self {
            window: (t0, t1),
            every,
            out: output::open(path, &Self::header(), 4, start)?,
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

/// The rows of a CSV file with `header`, each parsed by `parse` from its fields.
fn read_rows<T>(path: &Path, header: &str, parse: impl Fn(&[&str]) -> Option<T>) -> Result<Vec<T>> {
    let text = std::fs::read_to_string(path)?;
    let fail = |reason: String| Error::Resume {
        path: path.display().to_string(),
        reason,
    };
    let mut lines = text.lines();
    if lines.next() != Some(header) {
        return Err(fail(format!("its header is not `{header}`")));
    }
    lines
        .map(|line| {
            let fields: Vec<&str> = line.split(',').collect();
            parse(&fields).ok_or_else(|| fail(format!("malformed row `{line}`")))
        })
        .collect()
}

impl<const D: usize> Observer<D> for FrictionalProfile<D> {
    fn observe(&mut self, s: &StepState<'_, D>) -> Result<Flow> {
        let t = s.report.time;
        if t < self.window.0 || t > self.window.1 || s.report.step % self.every != 0 {
            return Ok(Flow::Continue(()));
        }
        let fb = &s.model.frictional;
        for &k in &fb.along {
            let p = fb.nodes[k];
            let x = &s.model.vertices[p];
            let rate = block_norm::<D>(&s.kinematics.v, p);
            write!(
                self.out,
                "{t:.9e},{:.6e},{rate:.9e},{:.9e},{}",
                x[0], s.alpha[k], s.report.step
            )?;
            for xc in x.iter().skip(1) {
                write!(self.out, ",{xc:.6e}")?;
            }
            writeln!(self.out)?;
        }
        self.out.flush()?;
        Ok(Flow::Continue(()))
    }
    fn finish(&mut self) -> Result<()> {
        self.out.flush()?;
        Ok(())
    }
}

/// Writes a checkpoint every `every` steps (atomically replacing `path`).
pub struct Checkpointer {
    path: PathBuf,
    every: usize,
}

impl Checkpointer {
    /// Checkpoints to `path` every `every` steps.
    pub fn new(path: impl Into<PathBuf>, every: usize) -> Self {
        Self {
            path: path.into(),
            every: every.max(1),
        }
    }
}

impl<const D: usize> Observer<D> for Checkpointer {
    fn observe(&mut self, s: &StepState<'_, D>) -> Result<Flow> {
        if s.report.step % self.every == 0 {
            s.checkpoint().write(&self.path)?;
        }
        Ok(Flow::Continue(()))
    }
}

/// Keeps every step's report in memory (for summaries and figures).
#[derive(Debug, Default, Clone)]
pub struct Reports(pub Vec<StepReport>);

impl<const D: usize> Observer<D> for Reports {
    fn observe(&mut self, s: &StepState<'_, D>) -> Result<Flow> {
        self.0.push(*s.report);
        Ok(Flow::Continue(()))
    }
}
