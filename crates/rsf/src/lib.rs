//! Rate- and state-dependent friction problems, solved by the variational method of
//! Pipping, Sander and Kornhuber: the composition of the `rsf-*` crates.
//!
//! - [`Model`]: an assembled discrete model (matrices, loads, constraints, hierarchy,
//!   frictional boundary), built by [`ModelBuilder`] from a mesh, a [`Material`] and named
//!   boundary [`Part`]s (Dirichlet with a velocity × [`TimeFunction`], Neumann,
//!   frictional with bilateral contact) — or by [`SliderScene::build_model`] for the
//!   paper's problem, or filled in by hand.
//! - [`Simulation`] = [`Problem`] (the model and, per frictional node, a friction law `L`
//!   and a state law `S`) + [`Method`] (velocity integrator `I`, velocity solver, fixed
//!   point iteration, step control, state update; described by [`MethodOptions`]) +
//!   [`SimulationState`] (what a checkpoint saves), stepping by the paper's relaxed fixed
//!   point iteration (docs/math.md §4) with TNNMG or the direct solver.
//!   [`SimulationBuilder`] is the only way to build one (defaults, laws given by
//!   position); it checks everything once (fixed normal on Γ_F, state variable of
//!   friction vs state law, a monotonicity probe of user state laws, …) with typed
//!   [`Error`]s.
//! - One enum per choice, each with `name()`, `FromStr`, serde and (feature `clap`)
//!   `clap::ValueEnum`: [`SolverKind`], [`Integrator`], [`StateLawKind`],
//!   [`FixedPointScheme`], [`StateIntegrator`], [`Diagonal`](fem::Diagonal).
//! - Run control: [`Simulation::run_until`] a time or a step count; [`Observer`]s can end
//!   a run ([`Flow`]); the [`RunSummary`] says why it ended ([`Termination`]), a failed
//!   run's [`RunError`] carries the summary so far; [`Simulation::set_time_step`] between
//!   steps.
//! - [`Observer`]s see a [`StepView`] (a borrow of the state): [`PointSeries`],
//!   [`FrictionalProfile`] (CSV, resumable after a checkpoint without loss, [`FileMode`]),
//!   [`Checkpointer`], [`Recorder`] and [`FaultRecorder`] (in memory, any `D`),
//!   [`SlipEvents`] (catalogue, stop at an event), [`Reports`], [`Progress`] (feature
//!   `progress`), `VtuFrames` for ParaView (feature `vtk`); [`Every`] samples any of them
//!   every `n` steps or every `Δt`. [`Checkpoint`]s resume bit-identically.
//! - [`SliderScene`]: the paper's model problem (§6.1, Table 6.1), readable from TOML;
//!   [`Slider3dScene`]: the same block extruded to 5 m × 1 m × W (tetrahedra).
//!
//! Features: `serde` (`Serialize`/`Deserialize` on states, checkpoints, slip events, event
//! thresholds, materials and the friction and state crates' parameters), `clap`
//! (`ValueEnum` on the choice enums), `progress` (the [`Progress`] bar through
//! `indicatif`), `vtk` (ParaView output), `sprs` (matrices in and out as `sprs` matrices).
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

mod any_run;
mod checkpoint;
mod error;
mod fault_ode;
mod friction_blocks;
mod method;
mod method_state;
mod model;
mod observe;
mod problem;
mod report;
mod run;
pub mod run_folder;
mod scenes;
mod simulation;
mod simulation_state;
mod switching;

pub use any_run::{MethodKind, Run};
pub use checkpoint::{write_atomically, Checkpoint, Fingerprint, CHECKPOINT_FORMAT};
pub use error::{Error, Result};
pub use fault_ode::{FaultOde, FaultOdeOptions};
pub use friction_blocks::FrictionBlocks;
pub use method::fixed_point::{
    Acceleration, FixedPointOptions, FixedPointScheme, InnerSolves, Predictor,
};
#[allow(deprecated)]
pub use method::solver::AUTO_DIRECT_MAX_EXTENSION;
pub use method::solver::{
    SolverKind, SolverOptions, AUTO_DIRECT_MAX_CONDENSED, DEFAULT_MEMORY_BUDGET_BYTES,
};
pub use method::state_integrator::StateIntegrator;
pub use method::{Method, MethodOptions};
pub use method_state::{FaultOdeState, MethodState, Phase, SwitchingStats};
pub use model::builder::{
    AntiplaneMaterial, FacetPredicate, Material, Medium, MediumMatrices, ModelBuilder, Part,
    DEFAULT_MAX_FAULT_KINK_DEGREES, MAX_CELLS,
};
pub use model::equilibrium::{EQUILIBRIUM_DIRECT_MAX_DOFS_3D, EQUILIBRIUM_MULTIGRID_TOLERANCE};
pub use model::fault::FrictionalBoundary;
pub use model::loading::{DirichletVelocity, TimeFunction};
pub use model::{nearest_vertex, Model};
pub use observe::checkpointer::{Checkpointer, Reports};
pub use observe::events::{
    EventDetector, EventThresholds, SlipEvent, SlipEvents, StopAt, Transition,
};
pub use observe::every::{Every, Interval};
pub use observe::files::FileMode;
pub use observe::profile::{FrictionalProfile, ProfileRow};
pub use observe::progress::Progress;
pub use observe::recorder::{FaultRecorder, Recorder};
pub use observe::seas::{
    SeasEvent, SeasOutput, SeasSampling, SeasSetup, SEAS_RESUME_LOG, SECONDS_PER_YEAR,
};
pub use observe::series::{PointSeries, SeriesRow};
#[cfg(feature = "vtk")]
pub use observe::vtu::VtuFrames;
pub use observe::{FaultTractions, Flow, Observer, StepView};
pub use problem::{NoState, Problem};
pub use report::StepReport;
pub use rsf_linalg::Parallelism;
pub use rsf_state::{BuiltinStateLaw, StateLawKind};
pub use rsf_time::Integrator;
pub use run::{run_until, RunError, RunSummary, Stepping, Termination, Until};
pub use run_folder::{RunFolder, StepCap};
pub use scenes::conditioning::{representable_range, ProblemScales, ScaleFields, SLIP_RESOLUTION};
pub use scenes::seas_bp1::{
    SeasBp1, SeasBp1FaultOde, SeasBp1Grid, SeasBp1Simulation, SEAS_BP1_STATION_DEPTHS,
};
pub use scenes::slider::{
    AdaptiveTimeStep, SceneSimulation, SceneSimulationBuilder, SliderScene, TimeStep, ALPHA_RANGE,
    SLIDER_CENTRE,
};
pub use scenes::slider3d::{
    skew_rotation, slider_3d_coarse, LateralBoundary, Slider3dScene, TAG_LATERAL,
};
pub use simulation::builder::{SimulationBuilder, Unset};
pub use simulation::Simulation;
pub use simulation_state::SimulationState;
pub use switching::{SwitchingOptions, SwitchingRun};

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
