//! An in-memory record of a run, for any dimension: every step's report, displacement and
//! velocity at chosen nodes, and snapshots along Γ_F.

use crate::error::{invalid, Result};
use crate::model::Model;
use crate::observer::{Flow, Observer, StepState};
use crate::simulation::{block_norm, StepReport};

/// Keeps, for every step, the [`StepReport`] and `(u, v)` at the chosen nodes ("points"),
/// and every `fault_every` steps a snapshot of Γ_F: slip rate, state α and displacement
/// per frictional node in the order along the boundary (`model.frictional.along`).
/// Storage is flat (no allocation per step beyond amortised growth).
///
/// ```no_run
/// use rsf::{Recorder, SliderScene, SLIDER_CENTRE};
/// let mut sim = SliderScene { level: 2, ..SliderScene::default() }.build()?;
/// let x0 = sim.model().nearest_node(&SLIDER_CENTRE)?;
/// let mut rec = Recorder::new(sim.model(), &[x0], 10)?;
/// sim.run(1000, &mut [&mut rec])?;
/// let u_x0: Vec<f64> = rec.displacement(0).map(|u| u[0]).collect();
/// let last_profile = rec.slip_rates(rec.snapshots() - 1);
/// # Ok::<(), rsf::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Recorder<const D: usize> {
    points: Vec<usize>,
    fault_every: usize,
    reports: Vec<StepReport>,
    u: Vec<[f64; D]>,
    v: Vec<[f64; D]>,
    /// Γ_F nodes along the boundary and their positions in `frictional.nodes`.
    fault_nodes: Vec<usize>,
    fault_along: Vec<usize>,
    snapshot_steps: Vec<usize>,
    snapshot_times: Vec<f64>,
    slip_rate: Vec<f64>,
    alpha: Vec<f64>,
    fault_u: Vec<[f64; D]>,
}

impl<const D: usize> Recorder<D> {
    /// Records at `points` (nodes of `model`) every step and Γ_F every `fault_every` steps
    /// (0: never).
    ///
    /// # Errors
    /// [`Error::NodeOutOfRange`](crate::Error::NodeOutOfRange) for a point outside the
    /// model.
    pub fn new(model: &Model<D>, points: &[usize], fault_every: usize) -> Result<Self> {
        for &p in points {
            model.check_node("recorder point", p)?;
        }
        let fb = &model.frictional;
        Ok(Self {
            points: points.to_vec(),
            fault_every,
            reports: Vec::new(),
            u: Vec::new(),
            v: Vec::new(),
            fault_nodes: fb.along.iter().map(|&k| fb.nodes[k]).collect(),
            fault_along: fb.along.clone(),
            snapshot_steps: Vec::new(),
            snapshot_times: Vec::new(),
            slip_rate: Vec::new(),
            alpha: Vec::new(),
            fault_u: Vec::new(),
        })
    }

    /// Number of recorded steps.
    pub fn len(&self) -> usize {
        self.reports.len()
    }

    /// Whether no step was recorded.
    pub fn is_empty(&self) -> bool {
        self.reports.is_empty()
    }

    /// The report of every recorded step.
    pub fn reports(&self) -> &[StepReport] {
        &self.reports
    }

    /// Times t_n of the recorded steps (s).
    pub fn times(&self) -> impl Iterator<Item = f64> + '_ {
        self.reports.iter().map(|r| r.time)
    }

    /// The recorded nodes.
    pub fn points(&self) -> &[usize] {
        &self.points
    }

    fn column<'a>(&'a self, x: &'a [[f64; D]], k: usize) -> impl Iterator<Item = [f64; D]> + 'a {
        let stride = self.points.len().max(1);
        x.iter().skip(k).step_by(stride).copied()
    }

    /// Displacement (m) at point `k` (an index into [`points`](Self::points)), per step;
    /// empty for `k` out of range.
    pub fn displacement(&self, k: usize) -> impl Iterator<Item = [f64; D]> + '_ {
        let x = if k < self.points.len() {
            &self.u[..]
        } else {
            &[]
        };
        self.column(x, k)
    }

    /// Velocity (m/s) at point `k`, per step; empty for `k` out of range.
    pub fn velocity(&self, k: usize) -> impl Iterator<Item = [f64; D]> + '_ {
        let x = if k < self.points.len() {
            &self.v[..]
        } else {
            &[]
        };
        self.column(x, k)
    }

    /// Number of Γ_F snapshots.
    pub fn snapshots(&self) -> usize {
        self.snapshot_steps.len()
    }

    /// Step and time (s) of snapshot `i`.
    pub fn snapshot_time(&self, i: usize) -> Option<(usize, f64)> {
        Some((*self.snapshot_steps.get(i)?, self.snapshot_times[i]))
    }

    /// Γ_F nodes in the order along the boundary (the order of snapshot rows).
    pub fn fault_nodes(&self) -> &[usize] {
        &self.fault_nodes
    }

    fn row<'a, T>(&self, x: &'a [T], i: usize) -> &'a [T] {
        let nf = self.fault_nodes.len();
        x.get(nf * i..nf * (i + 1)).unwrap_or(&[])
    }

    /// Slip rates `|v_p|` (m/s) along Γ_F in snapshot `i` (empty if out of range).
    pub fn slip_rates(&self, i: usize) -> &[f64] {
        self.row(&self.slip_rate, i)
    }

    /// State α along Γ_F in snapshot `i`.
    pub fn states(&self, i: usize) -> &[f64] {
        self.row(&self.alpha, i)
    }

    /// Displacement (m) along Γ_F in snapshot `i`.
    pub fn fault_displacements(&self, i: usize) -> &[[f64; D]] {
        self.row(&self.fault_u, i)
    }
}

fn block<const D: usize>(x: &[f64], p: usize) -> [f64; D] {
    let mut b = [0.0; D];
    b.copy_from_slice(&x[D * p..D * p + D]);
    b
}

impl<const D: usize> Observer<D> for Recorder<D> {
    fn observe(&mut self, s: &StepState<'_, D>) -> Result<Flow> {
        let (u, v) = (&s.kinematics.u, &s.kinematics.v);
        if self.points.iter().any(|&p| D * p + D > u.len())
            || self.fault_nodes.len() != s.model.frictional.len()
        {
            return Err(invalid("recorder", "observes a model other than its own"));
        }
        self.reports.push(*s.report);
        for &p in &self.points {
            self.u.push(block(u, p));
            self.v.push(block(v, p));
        }
        if self.fault_every > 0 && s.report.step % self.fault_every == 0 {
            self.snapshot_steps.push(s.report.step);
            self.snapshot_times.push(s.report.time);
            for (&p, &k) in self.fault_nodes.iter().zip(&self.fault_along) {
                self.slip_rate.push(block_norm::<D>(v, p));
                self.alpha.push(s.alpha[k]);
                self.fault_u.push(block(u, p));
            }
        }
        Ok(Flow::Continue(()))
    }
}
