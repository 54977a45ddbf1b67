//! Rate- and state-dependent friction problems, solved by the variational method of
//! Pipping, Sander and Kornhuber: the composition of the `rsf-*` crates.
//!
//! - [`Model`]: an assembled discrete model (matrices, loads, constraints, hierarchy,
//!   frictional boundary) — from [`SliderScene::build_model`] or your own assembly.
//! - [`Simulation`]: a model plus a friction law `L`, a state law `S` and a velocity
//!   integrator `I` (all generic, one law value per frictional node), stepping by the
//!   paper's relaxed fixed point iteration (docs/math.md §4) with TNNMG or the direct solver.
//! - [`Observer`]s record what a scene asks for: [`PointSeries`], [`FrictionalProfile`],
//!   [`Checkpointer`], [`Reports`], and `VtuFrames` for ParaView (feature `vtk`).
//!   [`Checkpoint`]s resume bit-identically.
//! - [`SliderScene`]: the paper's model problem (§6.1, Table 6.1), readable from TOML.
//!
//! ```no_run
//! use rsf::SliderScene;
//! let scene = SliderScene { level: 2, steps: 100, ..SliderScene::default() };
//! let mut sim = scene.build()?;
//! let summary = sim.run(100, &mut [])?;
//! println!("{} steps, mean {:.2} fixed point iterations", summary.steps, summary.fpi_mean);
//! # Ok::<(), rsf::Error>(())
//! ```
#![warn(missing_docs)]

mod builder;
mod checkpoint;
mod checks;
mod dynamic;
mod error;
mod events;
mod fixed_point;
mod friction_blocks;
mod model;
mod observer;
mod output;
mod recorder;
mod simulation;
mod simulation_builder;
mod slider;
mod solver;
#[cfg(feature = "vtk")]
mod vtu;

pub use builder::{FacetPredicate, Material, ModelBuilder, Part, MAX_CELLS};
pub use checkpoint::Checkpoint;
pub use dynamic::AnySimulation;
pub use error::{Error, Result};
pub use events::{EventDetector, EventThresholds, SlipEvent, SlipEvents, StopAt, Transition};
pub use fixed_point::{Acceleration, FixedPointOptions, Predictor};
pub use friction_blocks::FrictionBlocks;
pub use model::{DirichletVelocity, FrictionalBoundary, Model, TimeFunction};
pub use observer::{
    Checkpointer, Flow, FrictionalProfile, Observer, PointSeries, ProfileRow, Reports, SeriesRow,
    StepState,
};
pub use recorder::Recorder;
pub use simulation::{NoState, RunSummary, Simulation, StepReport, Until};
pub use simulation_builder::{SimulationBuilder, Unset};
pub use slider::{
    nearest_vertex, DiagonalKind, FixedPointScheme, IntegratorKind, SliderScene, SolverChoice,
    StateLawKind, SLIDER_CENTRE,
};
pub use solver::{
    SolverKind, VelocitySolver, AUTO_DIRECT_MAX_CONDENSED, AUTO_DIRECT_MAX_EXTENSION,
};
#[cfg(feature = "vtk")]
pub use vtu::VtuFrames;

pub use faer;
pub use rsf_fem as fem;
pub use rsf_friction as friction;
pub use rsf_state as state;
pub use rsf_time as time;
pub use rsf_tnnmg as tnnmg;
