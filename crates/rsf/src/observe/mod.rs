//! What a run records. A scene that records nothing computes nothing extra: every observer
//! does its own (cheap) extraction from the state it is shown.

pub(crate) mod checkpointer;
pub(crate) mod events;
pub(crate) mod every;
pub(crate) mod files;
pub(crate) mod profile;
pub(crate) mod progress;
pub(crate) mod recorder;
pub(crate) mod seas;
pub(crate) mod series;
#[cfg(feature = "vtk")]
pub(crate) mod vtu;

use crate::checkpoint::Checkpoint;
use crate::error::Result;
use crate::model::fault::block_norm;
use crate::model::Model;
use crate::report::StepReport;
use crate::simulation_state::SimulationState;

/// A step as observers see it: the model, the state after the step (borrowed: observers
/// never copy what they do not keep) and the step's report.
#[derive(Debug, Clone, Copy)]
pub struct StepView<'a, const D: usize, const C: usize = D> {
    /// The model.
    pub model: &'a Model<D, C>,
    /// The state after the step.
    pub state: &'a SimulationState,
    /// The step's report.
    pub report: &'a StepReport,
}

impl<const D: usize, const C: usize> StepView<'_, D, C> {
    /// The displacement of node `p` (m), Cartesian components (rotated back from the
    /// nodal frame at a slanted fault node, [`Model::to_global`]).
    ///
    /// # Panics
    /// If `p` is not a node of the model (callers check nodes when they are created).
    pub fn displacement(&self, p: usize) -> [f64; C] {
        self.model.to_global(p, block(&self.state.kinematics.u, p))
    }

    /// The velocity of node `p` (m/s), Cartesian components.
    ///
    /// # Panics
    /// If `p` is not a node of the model.
    pub fn velocity(&self, p: usize) -> [f64; C] {
        self.model.to_global(p, block(&self.state.kinematics.v, p))
    }

    /// The displacement of node `p` (m) in model coordinates: at a node with a nodal
    /// frame (a slanted fault node) its slip coordinates (tangential…, normal), Cartesian
    /// elsewhere ([`Model`]'s convention).
    ///
    /// # Panics
    /// If `p` is not a node of the model.
    pub fn displacement_in_frame(&self, p: usize) -> [f64; C] {
        block(&self.state.kinematics.u, p)
    }

    /// The velocity of node `p` (m/s) in model coordinates (as
    /// [`displacement_in_frame`](Self::displacement_in_frame)).
    ///
    /// # Panics
    /// If `p` is not a node of the model.
    pub fn velocity_in_frame(&self, p: usize) -> [f64; C] {
        block(&self.state.kinematics.v, p)
    }

    /// The slip rate `|v_p|` (m/s) of the `k`-th frictional node
    /// (`model.frictional_boundary.nodes[k]`).
    ///
    /// # Panics
    /// If `k` is not the position of a frictional node.
    pub fn slip_rate(&self, k: usize) -> f64 {
        block_norm::<C>(
            &self.state.kinematics.v,
            self.model.frictional_boundary.nodes[k],
        )
    }

    /// A checkpoint of this state.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint::new(D, self.state.clone())
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

    /// A name for messages and [`Termination::Observer`](crate::Termination); default the
    /// type's name.
    fn name(&self) -> String {
        std::any::type_name::<Self>().to_owned()
    }
}
