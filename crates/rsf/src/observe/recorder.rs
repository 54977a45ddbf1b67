//! In-memory records of a run, for any dimension: every step's report with displacement
//! and velocity at chosen nodes ([`Recorder`]), and snapshots along Γ_F
//! ([`FaultRecorder`]).

use crate::error::{invalid, Result};
use crate::model::Model;
use crate::report::StepReport;

use super::{Flow, Observer, StepView};

/// Keeps, for every step, the [`StepReport`] and `(u, v)` at the chosen nodes ("points"),
/// in model coordinates ([`StepView::displacement_in_frame`]: slip coordinates at a slanted
/// fault node, Cartesian elsewhere).
/// Storage is flat (no allocation per step beyond amortised growth).
///
/// ```no_run
/// use rsf::observe::{Every, FaultRecorder, Interval, Recorder};
/// use rsf_scenes::{SLIDER_CENTRE, SliderScene};
/// let mut sim = SliderScene { level: 2, ..SliderScene::default() }.build()?;
/// let x0 = sim.model().nearest_node(&SLIDER_CENTRE)?;
/// let mut rec = Recorder::new(sim.model(), &[x0])?;
/// let mut fault = Every::new(Interval::Steps(10), FaultRecorder::new(sim.model()))?;
/// sim.run(1000, &mut [&mut rec, &mut fault])?;
/// let u_x0: Vec<f64> = rec.displacement(0).map(|u| u[0]).collect();
/// let last_profile = fault.inner.slip_rates(fault.inner.snapshots() - 1);
/// # Ok::<(), rsf::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Recorder<const D: usize> {
    points: Vec<usize>,
    reports: Vec<StepReport>,
    u: Vec<[f64; D]>,
    v: Vec<[f64; D]>,
}

impl<const D: usize> Recorder<D> {
    /// Records at `points` (mesh vertex ids of `model`, e.g. from
    /// [`Model::nearest_node`]; not fault indices).
    ///
    /// # Errors
    /// [`Error::NodeOutOfRange`](crate::Error::NodeOutOfRange) for a point outside the
    /// model.
    pub fn new(model: &Model<D>, points: &[usize]) -> Result<Self> {
        for &p in points {
            model.check_node("recorder point", p)?;
        }
        Ok(Self {
            points: points.to_vec(),
            reports: Vec::new(),
            u: Vec::new(),
            v: Vec::new(),
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

    /// The recorded vertex ids.
    pub fn points(&self) -> &[usize] {
        &self.points
    }

    fn column<'a>(&'a self, x: &'a [[f64; D]], k: usize) -> impl Iterator<Item = [f64; D]> + 'a {
        let stride = self.points.len().max(1);
        let x = if k < self.points.len() { x } else { &[] };
        x.iter().skip(k).step_by(stride).copied()
    }

    /// Displacement (m) at point `k` (an index into [`points`](Self::points)), per step;
    /// empty for `k` out of range.
    pub fn displacement(&self, k: usize) -> impl Iterator<Item = [f64; D]> + '_ {
        self.column(&self.u, k)
    }

    /// Velocity (m/s) at point `k`, per step; empty for `k` out of range.
    pub fn velocity(&self, k: usize) -> impl Iterator<Item = [f64; D]> + '_ {
        self.column(&self.v, k)
    }
}

impl<const D: usize> Observer<D> for Recorder<D> {
    fn observe(&mut self, s: &StepView<'_, D>) -> Result<Flow> {
        if self.points.iter().any(|&p| p >= s.model.num_nodes()) {
            return Err(invalid("recorder", "observes a model other than its own"));
        }
        self.reports.push(*s.report);
        for &p in &self.points {
            self.u.push(s.displacement_in_frame(p));
            self.v.push(s.velocity_in_frame(p));
        }
        Ok(Flow::Continue(()))
    }
}

/// Keeps a snapshot of Γ_F at every step it is shown (wrap it in [`Every`](crate::observe::Every)
/// to sample): slip rate, state α and displacement per frictional node in the order along
/// the boundary (`model.frictional_boundary.along`). Storage is flat.
#[derive(Debug, Clone, PartialEq)]
pub struct FaultRecorder<const D: usize> {
    /// Γ_F nodes along the boundary and their positions in `frictional.nodes`.
    fault_nodes: Vec<usize>,
    fault_along: Vec<usize>,
    steps: Vec<usize>,
    times: Vec<f64>,
    slip_rate: Vec<f64>,
    alpha: Vec<f64>,
    fault_u: Vec<[f64; D]>,
}

impl<const D: usize> FaultRecorder<D> {
    /// Snapshots of Γ_F of `model`.
    pub fn new(model: &Model<D>) -> Self {
        let fb = &model.frictional_boundary;
        Self {
            fault_nodes: fb.along.iter().map(|&k| fb.nodes[k]).collect(),
            fault_along: fb.along.clone(),
            steps: Vec::new(),
            times: Vec::new(),
            slip_rate: Vec::new(),
            alpha: Vec::new(),
            fault_u: Vec::new(),
        }
    }

    /// Number of snapshots.
    pub fn snapshots(&self) -> usize {
        self.steps.len()
    }

    /// Step and time (s) of snapshot `i`.
    pub fn snapshot_time(&self, i: usize) -> Option<(usize, f64)> {
        Some((*self.steps.get(i)?, self.times[i]))
    }

    /// Vertex ids of the Γ_F nodes in the order along the boundary (the order of snapshot
    /// rows; `model.frictional_boundary.along` maps them to fault indices).
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

    /// Displacement (m) along Γ_F in snapshot `i`, in slip coordinates at slanted nodes
    /// ([`StepView::displacement_in_frame`]).
    pub fn fault_displacements(&self, i: usize) -> &[[f64; D]] {
        self.row(&self.fault_u, i)
    }
}

impl<const D: usize> Observer<D> for FaultRecorder<D> {
    fn observe(&mut self, s: &StepView<'_, D>) -> Result<Flow> {
        if self.fault_nodes.len() != s.model.frictional_boundary.len() {
            return Err(invalid(
                "fault recorder",
                "observes a model other than its own",
            ));
        }
        self.steps.push(s.report.step);
        self.times.push(s.report.time);
        for (&p, &k) in self.fault_nodes.iter().zip(&self.fault_along) {
            self.slip_rate.push(s.slip_rate(k));
            self.alpha.push(s.state.alpha[k]);
            self.fault_u.push(s.displacement_in_frame(p));
        }
        Ok(Flow::Continue(()))
    }
    fn reads_volume(&self) -> bool {
        false
    }
}
