//! What a run records. A scene that records nothing computes nothing extra: every observer
//! does its own (cheap) extraction from the state it is shown.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use rsf_time::Kinematics;

use crate::checkpoint::Checkpoint;
use crate::error::Result;
use crate::model::Model;
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

/// Time series at one node (2D): CSV `t_s,u_x0_m,v_x0_mps,max_slip_rate_mps,fpi`,
/// flushed after every row so that a killed run keeps what it wrote.
pub struct PointSeries {
    node: usize,
    out: BufWriter<File>,
    flush_every: usize,
    rows: usize,
}

impl PointSeries {
    /// Writes to `path` (created/truncated) the series at `node`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn create(path: &Path, node: usize) -> Result<Self> {
        let mut out = BufWriter::new(File::create(path)?);
        writeln!(out, "t_s,u_x0_m,v_x0_mps,max_slip_rate_mps,fpi")?;
        out.flush()?;
        Ok(Self {
            node,
            out,
            flush_every: 1,
            rows: 0,
        })
    }

    /// Flush only every `n` rows (default 1).
    pub fn flush_every(mut self, n: usize) -> Self {
        self.flush_every = n.max(1);
        self
    }
}

impl<const D: usize> Observer<D> for PointSeries {
    fn observe(&mut self, s: &StepState<'_, D>) -> Result<Flow> {
        let (u, v) = (&s.kinematics.u, &s.kinematics.v);
        writeln!(
            self.out,
            "{:.9e},{:.12e},{:.12e},{:.12e},{}",
            s.report.time,
            u[D * self.node],
            v[D * self.node],
            s.report.max_slip_rate,
            s.report.fixed_point_iterations
        )?;
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

/// Slip rate and state along Γ_F over a time window: CSV `t_s,x_m,slip_rate_mps,alpha`
/// (x the first coordinate of the node), one row per node per step inside the window.
pub struct FrictionalProfile {
    window: (f64, f64),
    every: usize,
    out: BufWriter<File>,
}

impl FrictionalProfile {
    /// Records steps with `t ∈ [t0, t1]`, every `every`-th step.
    ///
    /// # Errors
    /// I/O errors.
    pub fn create(path: &Path, t0: f64, t1: f64, every: usize) -> Result<Self> {
        let mut out = BufWriter::new(File::create(path)?);
        writeln!(out, "t_s,x_m,slip_rate_mps,alpha")?;
        out.flush()?;
        Ok(Self {
            window: (t0, t1),
            every: every.max(1),
            out,
        })
    }
}

impl<const D: usize> Observer<D> for FrictionalProfile {
    fn observe(&mut self, s: &StepState<'_, D>) -> Result<Flow> {
        let t = s.report.time;
        if t < self.window.0 || t > self.window.1 || s.report.step % self.every != 0 {
            return Ok(Flow::Continue(()));
        }
        let fb = &s.model.frictional;
        for &k in &fb.along {
            let p = fb.nodes[k];
            let x = s.model.vertices[p][0];
            let rate = block_norm::<D>(&s.kinematics.v, p);
            writeln!(self.out, "{t:.9e},{x:.6e},{rate:.9e},{:.9e}", s.alpha[k])?;
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
