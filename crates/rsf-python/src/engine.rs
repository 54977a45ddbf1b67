//! A run of any method and dimension behind one object-safe trait ([`DynEngine`]), with
//! what the package records in memory ([`Recording`]) and the observer that lets Ctrl-C
//! stop a run at a step boundary ([`Interrupt`]).

use std::any::Any;
use std::time::{Duration, Instant};

use pyo3::prelude::*;
use rsf::checkpoint::Fingerprint;
use rsf::observe::{
    Checkpointer, EventDetector, EventThresholds, Every, FaultCatalogue, Interval, NetworkEvent,
    Progress,
};
use rsf::{Checkpoint, Flow, Observer, RunError, RunSummary, StepView, Stepping, Until};

/// One row per accepted step and the fault's fields every `fault_every` steps, in memory,
/// and the event catalogue (the library's [`EventDetector`] on the largest slip rate).
pub(crate) struct Recording {
    /// Time after the step (s).
    pub t: Vec<f64>,
    /// The step's length (s).
    pub tau: Vec<f64>,
    /// The step's index (1-based, across resumes).
    pub step: Vec<u64>,
    /// The largest slip rate on the fault (m/s).
    pub max_slip_rate: Vec<f64>,
    /// Fixed point iterations of the step (0 for the Runge–Kutta runs).
    pub fixed_point_iterations: Vec<u64>,
    /// Record the fault's fields every this many steps (0: never).
    pub fault_every: usize,
    /// Times of the fault records (s).
    pub fault_t: Vec<f64>,
    /// Slip rate `|V|` per record and fault node (m/s), record-major.
    pub slip_rate: Vec<f64>,
    /// State α = ln θ (θ in s) per record and fault node.
    pub alpha: Vec<f64>,
    /// Slip per record, fault node and component (m).
    pub slip: Vec<f64>,
    /// Shear traction `σ̄_n μ(V, α)` per record and fault node (Pa).
    pub shear_traction: Vec<f64>,
    /// The event catalogue.
    pub detector: EventDetector,
    /// The shear modulus (Pa) of the catalogue across the faults of a network (moments),
    /// `None` for a run without one.
    pub network_rigidity: Option<f64>,
    /// The catalogue across the faults ([`FaultCatalogue`] of the run's dimension and
    /// components, kept as `Any`: the recording is not generic), started by
    /// [`Engine::start_network`].
    pub network: Option<Box<dyn Any>>,
}

impl Recording {
    /// Records the fault's fields every `fault_every` steps (0: never), events with the
    /// library's default thresholds (onset 1e-3 m/s, end 1e-4 m/s).
    pub fn new(fault_every: usize) -> rsf::Result<Self> {
        Ok(Self {
            t: Vec::new(),
            tau: Vec::new(),
            step: Vec::new(),
            max_slip_rate: Vec::new(),
            fixed_point_iterations: Vec::new(),
            fault_every,
            fault_t: Vec::new(),
            slip_rate: Vec::new(),
            alpha: Vec::new(),
            slip: Vec::new(),
            shear_traction: Vec::new(),
            detector: EventDetector::new(EventThresholds::default())?,
            network_rigidity: None,
            network: None,
        })
    }

    /// The same recording with the catalogue across the faults of a network, its moments
    /// weighed by the shear modulus `rigidity` (Pa), its events detected with the same
    /// thresholds as [`detector`](Self::detector)'s (started by
    /// [`Engine::start_network`]).
    pub fn with_network(mut self, rigidity: f64) -> Self {
        self.network_rigidity = Some(rigidity);
        self
    }

    /// Forgets the rows and records (the catalogues too, the network's to be started
    /// again by [`Engine::start_network`]): after a restore.
    pub fn clear(&mut self) -> rsf::Result<()> {
        let rigidity = self.network_rigidity;
        *self = Self::new(self.fault_every)?;
        self.network_rigidity = rigidity;
        Ok(())
    }
}

impl<const D: usize, const C: usize> Observer<D, C> for Recording {
    fn observe(&mut self, s: &StepView<'_, D, C>) -> rsf::Result<Flow> {
        let n = s.model.frictional_boundary.len();
        let max = (0..n).map(|k| s.slip_rate(k)).fold(0.0, f64::max);
        let t = s.state.time;
        self.t.push(t);
        self.tau.push(s.report.tau);
        self.step.push(s.report.step as u64);
        self.max_slip_rate.push(max);
        self.fixed_point_iterations
            .push(s.report.fixed_point_iterations as u64);
        self.detector.push(s.report.step, t, max, &[]);
        if let Some(c) = self.network.as_mut() {
            let c = c
                .downcast_mut::<FaultCatalogue<D, C>>()
                .expect("the network catalogue of the run's dimension");
            let flow = c.observe(s)?;
            if flow.is_break() {
                return Ok(flow);
            }
        }
        if self.fault_every > 0 && s.report.step.is_multiple_of(self.fault_every) {
            self.fault_t.push(t);
            for k in 0..n {
                self.slip_rate.push(s.slip_rate(k));
                self.alpha.push(s.state.alpha[k]);
                self.slip.extend(s.slip(k));
                self.shear_traction.push(s.shear_traction(k));
            }
        }
        Ok(Flow::Continue(()))
    }

    fn reads_volume(&self) -> bool {
        false
    }

    fn name(&self) -> String {
        "the package's recording".into()
    }
}

/// Stops a run at the step boundary after Ctrl-C: every 50 ms of wall time it takes the
/// GIL and runs Python's signal handlers; a raised exception (`KeyboardInterrupt`) is kept
/// and breaks the run.
pub(crate) struct Interrupt {
    last: Instant,
    /// The exception a signal handler raised.
    pub raised: Option<PyErr>,
}

impl Interrupt {
    pub fn new() -> Self {
        Self {
            last: Instant::now(),
            raised: None,
        }
    }
}

impl<const D: usize, const C: usize> Observer<D, C> for Interrupt {
    fn observe(&mut self, _: &StepView<'_, D, C>) -> rsf::Result<Flow> {
        if self.last.elapsed() < Duration::from_millis(50) {
            return Ok(Flow::Continue(()));
        }
        self.last = Instant::now();
        match Python::attach(|py| py.check_signals()) {
            Ok(()) => Ok(Flow::Continue(())),
            Err(e) => {
                self.raised = Some(e);
                Ok(Flow::Break(()))
            }
        }
    }

    fn reads_volume(&self) -> bool {
        false
    }

    fn name(&self) -> String {
        "Ctrl-C".into()
    }
}

/// How one call of `advance` runs.
pub(crate) struct Advance {
    /// Where to stop.
    pub until: Until,
    /// A progress bar (stderr).
    pub progress: bool,
    /// A checkpoint every this many steps into `checkpoint` (0: none).
    pub checkpoint_every: usize,
    /// The checkpoint file (also written when Ctrl-C stops the run).
    pub checkpoint: Option<std::path::PathBuf>,
}

/// The folder a simulation writes its files in (`out`) and the run id its manifest
/// names: every checkpoint of the run carries the id, so that a resume proves the folder
/// the checkpoint's run's (docs/reliability.md, "Round 5").
#[derive(Debug, Clone, Default)]
pub(crate) struct Files {
    /// The run folder (`None`: the simulation writes no run folder).
    pub folder: Option<std::path::PathBuf>,
    /// The run id of the folder's manifest (empty: none).
    pub run_id: String,
    /// A file the simulation writes outside a run folder (`slider_3d`'s `hdf5`), which only
    /// the constructor's `resume=` continues (the file proving the checkpoint's run).
    pub file: Option<std::path::PathBuf>,
}

impl Files {
    /// The folder `out`'s run, its id read from its manifest.
    pub fn of_folder(out: &std::path::Path) -> Self {
        Self {
            folder: Some(out.to_owned()),
            run_id: rsf::run_folder::run_id(out).unwrap_or_default(),
            file: None,
        }
    }
}

/// A run of any method and dimension, its recording and its extra observers (files).
pub(crate) trait DynEngine {
    /// Steps until `how.until`, the GIL released by the caller.
    fn advance(&mut self, how: &Advance, interrupt: &mut Interrupt)
        -> Result<RunSummary, RunError>;
    /// The state now.
    fn state(&self) -> &rsf::SimulationState;
    /// A checkpoint of the state now, with the run's fingerprint.
    fn checkpoint(&self) -> Checkpoint;
    /// Continues from `c` (its fingerprint checked against the run's).
    fn restore(&mut self, c: &Checkpoint) -> rsf::Result<()>;
    /// The folder the run writes its files in and its run id.
    fn files(&self) -> &Files;
    /// What was recorded.
    fn recording(&self) -> &Recording;
    /// Dimension, components and fault nodes' coordinates (fault-node-major, `D` each).
    fn shape(&self) -> (usize, usize, Vec<f64>);
    /// The faults' names and the fault of every fault node (an index into the names).
    fn faults(&self) -> (Vec<String>, Vec<usize>);
    /// The catalogue across the faults: their names and the events, `None` for a run
    /// without one.
    fn network(&self) -> Option<(&[String], &[NetworkEvent])>;
    /// The mesh: vertex coordinates (`D` each) and cells (`D + 1` vertices each).
    fn mesh(&self) -> (Vec<f64>, Vec<usize>);
    /// The displacement and velocity at every vertex (Cartesian, `C` each).
    fn fields(&self) -> (Vec<f64>, Vec<f64>);
    /// The Green's functions of the run's fault operator and the operator, `None` for a
    /// run without one (the implicit scheme's).
    fn greens(&mut self) -> Option<rsf::Result<Greens<'_>>>;
}

/// The Green's functions of a run and its operator (a fault ODE's).
pub(crate) type Greens<'a> = (
    rsf::greens::GreensFunctions,
    &'a mut dyn rsf::fault_operator::FaultOperator,
);

/// A run that may have a fault operator `S` (a fault ODE's) whose Green's functions
/// Python reads ([`DynEngine::greens`]).
pub(crate) trait WithFaultOperator {
    /// The Green's functions and the operator, `None` without one.
    fn greens(&mut self) -> Option<rsf::Result<Greens<'_>>>;
}

impl<const D: usize, L, S, const C: usize> WithFaultOperator for rsf::FaultOde<D, L, S, C>
where
    L: rsf::friction::FrictionLaw,
    S: rsf::state::StateLaw,
{
    fn greens(&mut self) -> Option<rsf::Result<Greens<'_>>> {
        Some(
            self.greens_functions()
                .map(|g| (g, self.fault_operator_mut())),
        )
    }
}

impl<const D: usize, L, S, I, const C: usize> WithFaultOperator for rsf::Simulation<D, L, S, I, C>
where
    L: rsf::friction::FrictionLaw,
    S: rsf::state::StateLaw,
    I: rsf::time::VelocityIntegrator,
{
    fn greens(&mut self) -> Option<rsf::Result<Greens<'_>>> {
        None
    }
}

impl<const D: usize, const C: usize, M: Stepping<D, C>> Engine<D, C, M> {
    /// Starts the recording's catalogue across the faults anew (no events) where it keeps
    /// one ([`Recording::with_network`]): at the start and after a restore.
    ///
    /// # Errors
    /// [`FaultCatalogue::new`]'s (a shear modulus that is not finite and positive).
    pub fn start_network(&mut self) -> rsf::Result<()> {
        if let Some(mu) = self.recording.network_rigidity {
            let c =
                FaultCatalogue::<D, C>::new(self.sim.model(), EventThresholds::default(), |_| mu)?;
            self.recording.network = Some(Box::new(c));
        }
        Ok(())
    }
}

/// A run `sim` of a `D`-dimensional model with `C` components.
pub(crate) struct Engine<const D: usize, const C: usize, M> {
    pub sim: M,
    pub recording: Recording,
    /// Observers writing files (SEAS output, HDF5 fields), after the recording.
    pub files: Vec<Box<dyn Observer<D, C>>>,
    pub fingerprint: Fingerprint,
    /// The folder of the files and its run id.
    pub folder: Files,
}

impl<const D: usize, const C: usize, M: Stepping<D, C> + WithFaultOperator> DynEngine
    for Engine<D, C, M>
{
    fn advance(
        &mut self,
        how: &Advance,
        interrupt: &mut Interrupt,
    ) -> Result<RunSummary, RunError> {
        let mut progress = how.progress.then(|| match how.until {
            Until::Steps(n) => Progress::steps(n, "rsf"),
            Until::Time(t)
            | Until::TimeOrStepCap { time: t, .. }
            | Until::TimeWithin { time: t, .. } => Progress::time(self.sim.state().time, t, "rsf"),
        });
        let mut checkpointer = match (&how.checkpoint, how.checkpoint_every) {
            (Some(path), n) if n > 0 => Some(
                Every::new(
                    Interval::Steps(n),
                    Checkpointer::new(path.clone())
                        .fingerprint(self.fingerprint.clone())
                        .run_id(&self.folder.run_id),
                )
                .map_err(|error| RunError {
                    error,
                    summary: Box::default(),
                })?,
            ),
            _ => None,
        };
        let mut observers: Vec<&mut dyn Observer<D, C>> = vec![&mut self.recording];
        for f in &mut self.files {
            observers.push(f.as_mut());
        }
        if let Some(p) = &mut progress {
            observers.push(p);
        }
        if let Some(c) = &mut checkpointer {
            observers.push(c);
        }
        observers.push(interrupt);
        rsf::run_until(&mut self.sim, how.until, &mut observers)
    }

    fn state(&self) -> &rsf::SimulationState {
        self.sim.state()
    }

    fn checkpoint(&self) -> Checkpoint {
        let mut c = self.sim.checkpoint();
        c.fingerprint = self.fingerprint.clone();
        c.run_id.clone_from(&self.folder.run_id);
        c
    }

    fn files(&self) -> &Files {
        &self.folder
    }

    fn restore(&mut self, c: &Checkpoint) -> rsf::Result<()> {
        c.fingerprint.check(&self.fingerprint, &[])?;
        self.sim.restore(c)?;
        self.recording.clear()?;
        self.start_network()
    }

    fn recording(&self) -> &Recording {
        &self.recording
    }

    fn shape(&self) -> (usize, usize, Vec<f64>) {
        let m = self.sim.model();
        let x = m
            .frictional_boundary
            .nodes
            .iter()
            .flat_map(|&p| m.vertices[p])
            .collect();
        (D, C, x)
    }

    fn faults(&self) -> (Vec<String>, Vec<usize>) {
        let fb = &self.sim.model().frictional_boundary;
        (fb.fault_names.clone(), fb.fault_of.clone())
    }

    fn network(&self) -> Option<(&[String], &[NetworkEvent])> {
        let c = self
            .recording
            .network
            .as_ref()?
            .downcast_ref::<FaultCatalogue<D, C>>()?;
        Some((c.fault_names(), c.events()))
    }

    fn mesh(&self) -> (Vec<f64>, Vec<usize>) {
        let m = self.sim.model();
        (
            m.vertices.iter().flatten().copied().collect(),
            m.cells.clone(),
        )
    }

    fn fields(&self) -> (Vec<f64>, Vec<f64>) {
        let m = self.sim.model();
        let k = &self.sim.state().kinematics;
        let cartesian = |x: &[f64]| m.to_cartesian(x).unwrap_or_else(|_| x.to_vec());
        (cartesian(&k.u), cartesian(&k.v))
    }

    fn greens(&mut self) -> Option<rsf::Result<Greens<'_>>> {
        self.sim.greens()
    }
}
