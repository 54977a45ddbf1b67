//! Rate- and state-dependent friction problems, solved by the variational method of
//! Pipping, Sander and Kornhuber: the composition of the `rsf-*` crates.
//!
//! - [`Model`]: an assembled discrete model (matrices, loads, constraints, hierarchy,
//!   frictional boundary), built by [`ModelBuilder`] from a mesh, a [`Material`] and named
//!   boundary [`Part`]s (Dirichlet with a velocity × [`TimeFunction`], Neumann,
//!   frictional with bilateral contact) — or by [`SliderScene::build_model`] for the
//!   paper's problem, or filled in by hand.
//! - [`Simulation`]: a model plus a friction law `L`, a state law `S` and a velocity
//!   integrator `I` (all generic, one law value per frictional node), stepping by the
//!   paper's relaxed fixed point iteration (docs/math.md §4) with TNNMG or the direct
//!   solver. [`SimulationBuilder`] sets it up with defaults, laws given by position.
//!   Construction checks consistency (fixed normal on Γ_F, state variable of friction vs
//!   state law, a monotonicity probe of user state laws) with typed [`Error`]s.
//! - Run control: [`Simulation::run_until`] a time or a step count; [`Observer`]s can end
//!   a run ([`Flow`]); [`Simulation::set_time_step`] between steps.
//! - [`Observer`]s: [`PointSeries`], [`FrictionalProfile`] (CSV, resumable after a
//!   checkpoint without loss), [`Checkpointer`], [`Recorder`] (in memory, any `D`),
//!   [`SlipEvents`] (catalogue, stop at an event), [`Reports`], and `VtuFrames` for
//!   ParaView (feature `vtk`). [`Checkpoint`]s resume bit-identically.
//! - [`SliderScene`]: the paper's model problem (§6.1, Table 6.1), readable from TOML;
//!   [`Slider3dScene`]: the same block extruded to 5 m × 1 m × W (tetrahedra).
//!
//! Feature `serde`: `Serialize`/`Deserialize` on checkpoints, slip events, event
//! thresholds, materials and the friction and state crates' parameters.
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
mod slider3d;
mod solver;
mod state_integrator;
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
    nearest_vertex, AdaptiveTimeStep, DiagonalKind, FixedPointScheme, IntegratorKind, SliderScene,
    SolverChoice, StateLawKind, TimeStep, SLIDER_CENTRE,
};
pub use slider3d::{slider_3d_coarse, LateralBoundary, Slider3dScene, TAG_LATERAL};
pub use solver::{
    SolverKind, VelocitySolver, AUTO_DIRECT_MAX_CONDENSED, AUTO_DIRECT_MAX_EXTENSION,
};
pub use state_integrator::StateIntegrator;
#[cfg(feature = "vtk")]
pub use vtu::VtuFrames;

pub use faer;
pub use rsf_fem as fem;
pub use rsf_friction as friction;
pub use rsf_state as state;
pub use rsf_time as time;
pub use rsf_tnnmg as tnnmg;

/// The README's code compiles (`cargo test --doc`).
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
