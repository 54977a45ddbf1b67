//! Rate- and state-dependent friction problems, solved by the variational method of
//! Pipping, Sander and Kornhuber: the composition of the `rsf-*` crates.
//!
//! The crate is organised by what a user does (docs/design.md, "The public shape"):
//!
//! - [`model`]: an assembled discrete [`Model`] (matrices, loads, constraints, hierarchy,
//!   frictional boundary), built by [`ModelBuilder`] from a mesh, a [`Material`] and named
//!   boundary [`Part`]s (Dirichlet with a velocity × [`TimeFunction`], Neumann,
//!   frictional with bilateral contact), or filled in by hand; its conditioning checks.
//! - [`simulation`]: the problem ([`Problem`]: the model, per frictional node a friction law
//!   and a state law, the radiation damping) with a method: the paper's implicit
//!   [`Simulation`] (built by [`SimulationBuilder`], which checks everything once), the
//!   quasi-dynamic [`FaultOde`] ([`fault_ode`]) and the [`SwitchingRun`] ([`switching`]);
//!   [`Run`] holds any of the three.
//! - [`method`]: the choices and options of the methods, one enum per choice with
//!   `name()`, `FromStr`, serde and (feature `clap`) `clap::ValueEnum` ([`MethodKind`],
//!   [`SolverKind`], [`Integrator`], [`StateLawKind`], …), and the one
//!   [`Parallelism`] parameter.
//! - [`run`]: the one run loop of every method: [`Stepping`] (a step, the state, a
//!   checkpoint, a restore), [`run_until`] an [`Until`], the [`RunSummary`] with its
//!   [`Termination`] or a [`RunError`].
//! - [`observe`]: [`Observer`]s see a [`StepView`] after every step and may end a run
//!   ([`Flow`]): time series, fault profiles, event catalogues, checkpoints, progress,
//!   ParaView frames (feature `vtk`); the SEAS benchmark files are observers of the crate
//!   `rsf-seas`.
//! - [`checkpoint`]: [`Checkpoint`]s of the common [`SimulationState`] and the method's own
//!   state, which every method resumes bit-identically; [`run_folder`]: the run-folder
//!   procedure of programs (refusing another run's files, resuming safely).
//! - [`prelude`]: the names most programs need.
//!
//! Ready-made problems (the paper's slider in 2-D and 3-D, SEAS BP1) are in the crate
//! `rsf-scenes`, which owns their TOML reader.
//!
//! Features: `serde` (`Serialize`/`Deserialize` on states, checkpoints, slip events, event
//! thresholds, materials and the friction and state crates' parameters), `clap`
//! (`ValueEnum` on the choice enums), `progress` (the progress bar through `indicatif`),
//! `vtk` (ParaView output), `sprs` (matrices in and out as `sprs` matrices), `halfspace`
//! (the boundary-element fault operator of Okada's half-space, crate `rsf-halfspace`:
//! `halfspace_operator`, and the re-export `halfspace`), `metis` (METIS's nested
//! dissection for the condensation onto the fault, `InteriorOrdering::NestedDissection`;
//! builds METIS's C sources).
//!
//! ```no_run
//! use rsf_scenes::SliderScene;
//! let scene = SliderScene { level: 2, steps: 100, ..SliderScene::default() };
//! let mut sim = scene.build()?;
//! let summary = sim.run(100, &mut [])?;
//! println!("{} steps, mean {:.2} fixed point iterations", summary.steps, summary.fpi_mean);
//! # Ok::<(), rsf::Error>(())
//! ```
#![warn(missing_docs)]

/// `match $value { $enum::$variant($m) => $e, … }` over the listed one-field variants: the
/// same expression `$e` of each variant's value `$m`, as an enum of methods or of solvers
/// forwards a call to the one it holds.
macro_rules! dispatch_variants {
    ($value:expr, $enum:ident { $($variant:ident),+ }, $m:ident => $e:expr) => {
        match $value {
            $($enum::$variant($m) => $e,)+
        }
    };
}

mod any_run;
pub mod checkpoint;
mod error;
pub mod fault_alone;
mod fault_kernel;
pub mod fault_ode;
pub mod fault_operator;
mod friction_blocks;
pub mod greens;
#[cfg(feature = "halfspace")]
pub mod halfspace_operator;
pub mod input_file;
pub mod method;
mod method_state;
pub mod model;
mod node_solves;
pub mod normal_stress;
pub mod observe;
#[cfg(feature = "halfspace")]
pub mod okada_comparison;
pub mod pore_pressure;
mod problem;
pub mod ranks;
mod report;
pub mod run;
pub mod run_folder;
mod run_manifest;
pub mod simulation;
mod simulation_state;
pub mod switching;
mod volume_probe;
pub mod whole_space;

/// The names most programs need, in one `use rsf::prelude::*;`.
pub mod prelude {
    pub use crate::checkpoint::Checkpoint;
    pub use crate::method::{FixedPointOptions, MethodKind, SolverKind, SolverOptions};
    pub use crate::model::{Material, Model, ModelBuilder, Part, TimeFunction};
    pub use crate::observe::{
        Checkpointer, EventThresholds, Every, FileMode, Flow, FrictionalProfile, Interval,
        Observer, PointSeries, SlipEvents, StepView,
    };
    pub use crate::run::{run_until, RunSummary, Stepping, Until};
    pub use crate::simulation::{Run, Simulation, SimulationBuilder};
    // Not `Result`: a glob import of it would shadow the standard one in the user's code.
    pub use crate::Error;
}

pub use checkpoint::{Checkpoint, SimulationState};
pub use error::{Error, Result};
pub use fault_ode::FaultOde;
pub use method::{Integrator, MethodKind, SolverKind, StateLawKind};
pub use model::{Material, Model, ModelBuilder, Part, TimeFunction};
pub use observe::{Flow, Observer, StepView};
pub use rsf_linalg::Parallelism;
pub use run::{run_until, RunError, RunSummary, StepReport, Stepping, Termination, Until};
pub use simulation::{Problem, Run, Simulation, SimulationBuilder};
pub use switching::SwitchingRun;

pub use faer;
pub use rsf_direct as direct;
pub use rsf_fem as fem;
pub use rsf_friction as friction;
#[cfg(feature = "halfspace")]
pub use rsf_halfspace as halfspace;
pub use rsf_hmatrix as hmatrix;
pub use rsf_nonsmooth as nonsmooth;
pub use rsf_state as state;
pub use rsf_time as time;
pub use rsf_tnnmg as tnnmg;

/// The README's code compiles (`cargo test --doc`).
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
