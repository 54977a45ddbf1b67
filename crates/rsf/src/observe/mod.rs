//! What a run records. A scene that records nothing computes nothing extra: every observer
//! does its own (cheap) extraction from the state it is shown.

pub(crate) mod catalogue;
pub(crate) mod checkpointer;
pub(crate) mod events;
pub(crate) mod every;
pub(crate) mod fault_stations;
pub(crate) mod fields;
pub(crate) mod files;
pub(crate) mod profile;
pub(crate) mod progress;
pub(crate) mod recorder;
pub(crate) mod series;
#[cfg(feature = "vtk")]
pub(crate) mod vtu;

pub use catalogue::{FaultCatalogue, NetworkEvent};
pub use checkpointer::{Checkpointer, Reports};
pub use events::{EventDetector, EventThresholds, SlipEvent, SlipEvents, StopAt, Transition};
pub use every::{Every, Interval};
pub use fault_stations::{FaultStation, FaultStations};
pub use fields::{point_fields, PointField, POINT_FIELDS};
pub use files::{create_file, csv_lines, refuse_existing, CsvLine, FileMode};
pub use profile::{FrictionalProfile, ProfileRow};
pub use progress::{Progress, TimeUnit, PROGRESS_LINE_SECONDS};
pub use recorder::{FaultRecorder, Recorder};
pub use series::{PointSeries, SeriesRow};
#[cfg(feature = "vtk")]
pub use vtu::VtuFrames;

use rsf_friction::{ConvexPotential, FrictionLaw};

/// Seconds per year (365.25 days): the unit of the long runs' times and intervals (the
/// SEAS benchmarks' output intervals, `rsf_seas`, which re-exports it).
pub const SECONDS_PER_YEAR: f64 = 365.25 * 24.0 * 3600.0;

use crate::checkpoint::Checkpoint;
use crate::error::Result;
use crate::method_state::MethodState;
use crate::model::fault::block_norm;
use crate::model::Model;
use crate::report::StepReport;
use crate::simulation_state::SimulationState;

/// A step as observers see it: the model, the state after the step (borrowed: observers
/// never copy what they do not keep), the step's report and the friction laws' tractions.
#[derive(Clone, Copy)]
pub struct StepView<'a, const D: usize, const C: usize = D> {
    /// The model.
    pub model: &'a Model<D, C>,
    /// The state after the step.
    pub state: &'a SimulationState,
    /// The step's report.
    pub report: &'a StepReport,
    /// The tractions of the frictional nodes' laws (the problem's friction laws).
    pub friction: &'a dyn FaultTractions,
    /// The method's own state beyond `state`, computed on demand (what a checkpoint saves
    /// besides the common state: [`MethodState`]).
    pub method: &'a dyn Fn() -> MethodState,
}

impl<const D: usize, const C: usize> std::fmt::Debug for StepView<'_, D, C> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StepView")
            .field("model", self.model)
            .field("state", self.state)
            .field("report", self.report)
            .finish_non_exhaustive()
    }
}

/// The tractions on Γ_F that the friction laws carry, per fault index `k` (a position on
/// Γ_F, not a vertex id; the vertex is `model.frictional_boundary.nodes[k]`): what observers report in slip coordinates.
/// Implemented for a vector of [`FrictionLaw`]s (one law per frictional node).
pub trait FaultTractions {
    /// The shear traction `ϕ'(V, α) = σ̄_n μ(V, α)` (Pa) of node `k` at slip rate `V ≥ 0`
    /// (m/s) and state `α`, opposing the slip rate. At `V = 0` (stick) the traction lies
    /// anywhere in the potential's subdifferential; the value is the potential's slope at 0
    /// (0 for the rate-and-state laws, whose potentials vanish below the cutoff `V_m`).
    ///
    /// # Panics
    /// If `k` is not the position of a frictional node.
    fn shear_traction(&self, k: usize, slip_rate: f64, alpha: f64) -> f64;

    /// The normal traction (Pa, compressive positive) at node `k`: the prescribed `σ̄_n`
    /// of its law ([`FrictionLaw::normal_stress`]), `None` if the law has none.
    ///
    /// # Panics
    /// If `k` is not the position of a frictional node.
    fn normal_traction(&self, k: usize) -> Option<f64>;
}

impl<L: FrictionLaw> FaultTractions for Vec<L> {
    fn shear_traction(&self, k: usize, slip_rate: f64, alpha: f64) -> f64 {
        self[k].potential(alpha).slope(slip_rate)
    }
    fn normal_traction(&self, k: usize) -> Option<f64> {
        self[k].normal_stress()
    }
}

impl<const D: usize, const C: usize> StepView<'_, D, C> {
    /// The displacement of mesh vertex `vertex` (a vertex id, not a fault index; m),
    /// Cartesian components (rotated back from the nodal frame at a slanted fault node,
    /// [`Model::to_global`]).
    ///
    /// # Panics
    /// If `vertex` is not a vertex of the model (callers check vertices when they are
    /// created).
    pub fn displacement(&self, vertex: usize) -> [f64; C] {
        self.model.vertex_value(vertex, &self.state.kinematics.u)
    }

    /// The velocity of mesh vertex `vertex` (a vertex id; m/s), Cartesian components.
    ///
    /// # Panics
    /// If `vertex` is not a vertex of the model.
    pub fn velocity(&self, vertex: usize) -> [f64; C] {
        self.model.vertex_value(vertex, &self.state.kinematics.v)
    }

    /// The displacement of mesh vertex `vertex` (a vertex id; m) in model coordinates
    /// ([`Model`]'s convention): at a node with a nodal frame (a slanted fault node) its
    /// slip coordinates (tangential…, inward normal); at a split pair of a fault inside the
    /// body the jump in the pair frame (minus vertex) or the weighted mean (plus vertex);
    /// Cartesian elsewhere.
    ///
    /// # Panics
    /// If `vertex` is not a vertex of the model.
    pub fn displacement_in_frame(&self, vertex: usize) -> [f64; C] {
        block(&self.state.kinematics.u, vertex)
    }

    /// The velocity of mesh vertex `vertex` (a vertex id; m/s) in model coordinates (as
    /// [`displacement_in_frame`](Self::displacement_in_frame)).
    ///
    /// # Panics
    /// If `vertex` is not a vertex of the model.
    pub fn velocity_in_frame(&self, vertex: usize) -> [f64; C] {
        block(&self.state.kinematics.v, vertex)
    }

    /// The slip rate `|v_p|` (m/s) of the frictional node of fault index `k` (a position
    /// on Γ_F, not a vertex id; its vertex is `model.frictional_boundary.nodes[k]`).
    ///
    /// # Panics
    /// If `k` is not the position of a frictional node.
    pub fn slip_rate(&self, k: usize) -> f64 {
        block_norm::<C>(
            &self.state.kinematics.v,
            self.model.frictional_boundary.nodes[k],
        )
    }

    /// The slip of the `k`-th frictional node (m): the displacement since the initial state,
    /// `u_p − u₀_p`, in Cartesian components (rotated back from a nodal frame). Bilateral
    /// contact keeps the normal velocity zero, so the slip is tangential; on a model of an
    /// antisymmetric fault the field is the slip itself (twice the boundary displacement).
    ///
    /// # Panics
    /// If `k` is not the position of a frictional node.
    pub fn slip(&self, k: usize) -> [f64; C] {
        let p = self.model.frictional_boundary.nodes[k];
        let u = block::<C>(&self.state.kinematics.u, p);
        let u0 = block::<C>(&self.model.initial_displacement, p);
        self.model
            .to_global(p, std::array::from_fn(|c| u[c] - u0[c]))
    }

    /// The shear traction (Pa) on the `k`-th frictional node: `σ̄_n μ(V, α)` of its law at
    /// the node's slip rate and state ([`FaultTractions::shear_traction`]).
    ///
    /// # Panics
    /// If `k` is not the position of a frictional node.
    pub fn shear_traction(&self, k: usize) -> f64 {
        self.friction
            .shear_traction(k, self.slip_rate(k), self.state.alpha[k])
    }

    /// The normal traction (Pa) on the `k`-th frictional node, if its law has a `σ̄_n`
    /// ([`FaultTractions::normal_traction`]).
    ///
    /// # Panics
    /// If `k` is not the position of a frictional node.
    pub fn normal_traction(&self, k: usize) -> Option<f64> {
        self.friction.normal_traction(k)
    }

    /// A checkpoint of this state: the common state and the method's own.
    pub fn checkpoint(&self) -> Checkpoint {
        let mut c = Checkpoint::new(D, self.state.clone());
        c.method = (self.method)();
        c
    }
}

/// Node `p`'s block of the node-major vector `x`.
pub(crate) fn block<const D: usize>(x: &[f64], p: usize) -> [f64; D] {
    let mut b = [0.0; D];
    b.copy_from_slice(&x[D * p..D * p + D]);
    b
}

/// What an observer tells the run after a step: [`Flow::Continue`] or [`Flow::Break`] (end
/// the run after this step, e.g. at a slip event).
pub type Flow = std::ops::ControlFlow<()>;

/// Something that looks at the simulation after each step.
pub trait Observer<const D: usize, const C: usize = D> {
    /// Called after every successful step; [`Flow::Break`] ends the run after this step
    /// (after every observer has seen it).
    ///
    /// # Errors
    /// I/O errors end the run.
    fn observe(&mut self, step: &StepView<'_, D, C>) -> Result<Flow>;

    /// Called once when a run ends, however it ends (end reached, an observer's break, or
    /// an error of a step or of another observer).
    ///
    /// # Errors
    /// I/O errors.
    fn finish(&mut self) -> Result<()> {
        Ok(())
    }

    /// Called when a run stops at its step cap ([`Until::TimeOrStepCap`](crate::Until)),
    /// after the last step's [`observe`](Self::observe) (or, for a state at its cap before
    /// any step, with a report of that state and no iterations); before
    /// [`finish`](Self::finish). Default: nothing. A
    /// [`Checkpointer`] writes the state, so a capped run can
    /// be resumed; [`Every`] passes it on.
    ///
    /// # Errors
    /// I/O errors end the run with that error.
    fn at_step_cap(&mut self, step: &StepView<'_, D, C>) -> Result<()> {
        let _ = step;
        Ok(())
    }

    /// Whether the observer reads the state off the frictional boundary (interior and
    /// Dirichlet nodes' `u`, `v`). Default `true` (safe for an observer that does not say).
    /// A run that condenses its unknowns onto Γ_F ([`FaultOde`](crate::FaultOde))
    /// computes the rest of the field only for observers that read it, and leaves it NaN
    /// otherwise: the library's observers of the fault ([`SlipEvents`],
    /// [`FrictionalProfile`],
    /// [`FaultRecorder`], [`Reports`],
    /// [`Checkpointer`], [`Progress`], [`FaultStations`], [`FaultCatalogue`];
    /// and the SEAS outputs of the crate `rsf-seas`) return `false`.
    fn reads_volume(&self) -> bool {
        true
    }

    /// The mesh vertices off Γ_F whose displacement and velocity the observer reads
    /// ([`StepView::displacement`], [`StepView::velocity`]) although it does not
    /// [read the volume](Self::reads_volume): a few stations. A run condensed onto Γ_F
    /// computes exactly these after every step, each from a precomputed row of the
    /// extension operator (one dot product with the fault's unknowns per component, instead
    /// of the whole field's sparse solves). Default: none.
    fn volume_vertices(&self) -> Vec<usize> {
        Vec::new()
    }

    /// A name for messages and [`Termination::Observer`](crate::Termination); default the
    /// type's name.
    fn name(&self) -> String {
        std::any::type_name::<Self>().to_owned()
    }
}
