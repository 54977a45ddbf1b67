//! Ready-made problems for [`rsf`], described by plain, TOML-readable parameters and built
//! on its [`ModelBuilder`](rsf::ModelBuilder) and [`SimulationBuilder`](rsf::SimulationBuilder):
//!
//! - [`SliderScene`]: the paper's model problem (Pipping, Sander and Kornhuber, §6.1,
//!   Table 6.1), a 5 m × 1 m elastic block on a rigid base, from a TOML file or in code;
//! - [`Slider3dScene`]: the same block extruded to 5 m × 1 m × W (tetrahedra);
//! - [`SeasBp1`]: the SCEC SEAS benchmark BP1 (antiplane, a vertical strike-slip fault,
//!   docs/seas-bp1.md); [`SeasBp3`]: BP3 (a dipping fault inside the body); [`SeasBp5`]:
//!   BP5 (3-D, a fault alone in a half-space, docs/seas-bp5.md); [`SeasBp6`]: BP6 (fluid
//!   injection, docs/seas-bp6.md); their output files (the
//!   SCEC format) are the crate `rsf-seas`'s, which the scenes set up
//!   ([`SeasBp1::seas_setup`], [`SeasBp5::output`]);
//! - [`Stepover`]: two parallel strike-slip strands in map view with BP1's friction, a
//!   fault network whose ruptures may jump the step (docs/fault-networks.md);
//! - the slider on an inclined base ([`inclined_slider_model`]) and on a curved one read from
//!   a Gmsh file ([`arc_block_model`]), with nodal frames;
//! - [`output`]: bounds on a scene's output before it runs.
//!
//! Features: `seas` (on by default) — the SEAS scenes ([`SeasBp1`] … [`SeasBp6`]), with
//! the crate `rsf-seas` and rsf's `halfspace`; `clap` and `progress` — through rsf's
//! features of those names. A program of the slider alone builds with
//! `default-features = false` (the workspace's main job does: docs/performance.md, "What a
//! newcomer waits for").
//!
//! The scenes live apart from the library so that a program that builds its own problem
//! pays for none of them (nor for the TOML reader they own). Their errors are
//! [`rsf::Error`]s: every failure of a scene is a failure of the model or simulation it
//! builds (an invalid parameter named as its field, a model that does not validate) or of
//! its scene file ([`rsf::Error::SceneFile`]).
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

#[cfg(feature = "seas")]
mod bp5_pair_run;
mod curved;
mod incline;
pub mod output;
pub mod run_config;
mod scene_file;
#[cfg(feature = "seas")]
mod seas_bp1;
#[cfg(feature = "seas")]
mod seas_bp1_run;
#[cfg(feature = "seas")]
mod seas_bp3;
#[cfg(feature = "seas")]
mod seas_bp3_run;
#[cfg(feature = "seas")]
mod seas_bp5;
#[cfg(feature = "seas")]
mod seas_bp5_output;
#[cfg(feature = "seas")]
mod seas_bp5_run;
#[cfg(feature = "seas")]
mod seas_bp6;
#[cfg(feature = "seas")]
mod seas_bp6_run;
#[cfg(feature = "seas")]
mod seas_bp7;
#[cfg(feature = "seas")]
mod seas_bp7_volume;
#[cfg(feature = "seas")]
mod seas_bp8;
#[cfg(feature = "seas")]
mod seas_bp8_volume;
#[cfg(feature = "seas")]
mod seas_square_run;
mod slider;
mod slider3d;
#[cfg(feature = "seas")]
pub mod square_fault;
#[cfg(feature = "seas")]
mod square_volume;
#[cfg(feature = "seas")]
mod stepover;
#[cfg(feature = "seas")]
mod stepover_run;

pub use curved::{arc_block_model, onto_arc, ARC_BLOCK_MESH, ARC_CENTRE, ARC_RADIUS_M};
pub use incline::{dip_point, inclined_centre, inclined_slider_model};
pub use output::{plan_output, step_cap, steps_bound, OutputLimits, OutputPlan};
pub use run_config::{check_ranges, fault_kernel, KernelChoice, RunConfig};

#[cfg(feature = "seas")]
pub use bp5_pair_run::{bp5_pair_ranges, Bp5PairRun};
#[cfg(feature = "seas")]
pub use seas_bp1::{
    GridEstimate, SeasBp1, SeasBp1Far, SeasBp1FaultOde, SeasBp1Grid, SeasBp1Simulation,
    SEAS_BP1_BOTTOM, SEAS_BP1_FAR_SIDE, SEAS_BP1_STATION_DEPTHS,
};
#[cfg(feature = "seas")]
pub use seas_bp1_run::{bp1_ranges, Bp1Absorbing, Bp1DynamicIntegrator, Bp1Scheme, SeasBp1Run};
#[cfg(feature = "seas")]
pub use seas_bp3::{
    SeasBp3, SeasBp3FaultOde, SeasBp3Grid, SEAS_BP3_STATION_DISTANCES, SEAS_BP3_SURFACE_STATIONS,
};
#[cfg(feature = "seas")]
pub use seas_bp3_run::{bp3_ranges, SeasBp3Run, BP3_DT_MIN};
#[cfg(feature = "seas")]
pub use seas_bp5::{
    Bp5Pair, Bp5PairPatch, FaultZone, SeasBp5, SeasBp5FaultOde, SeasBp5Grid, SeasBp5Mesh,
    BP5_PAIR_FAULTS, BP5_PAIR_STATIONS, GRADED_MAX_CELLS as SEAS_BP5_GRADED_MAX_CELLS,
    MAX_CELLS as SEAS_BP5_MAX_CELLS,
};
#[cfg(feature = "seas")]
pub use seas_bp5_run::{bp5_ranges, Bp5Condensation, Bp5Kernel, SeasBp5Run, BP5_SETUP_FILE};
#[cfg(feature = "seas")]
pub use seas_bp6::{
    Bp6Pressure, Bp6Variant, SeasBp6, SeasBp6FaultOde, SeasBp6Grid, SeasBp6Implicit,
    BP6_SECONDS_PER_YEAR,
};
#[cfg(feature = "seas")]
pub use seas_bp6_run::{
    bp6_ranges, Bp6BemProduct, Bp6Elastic, Bp6PressureChoice, SeasBp6Run, BP6_C_FIRST_STEP,
    BP6_DIFFUSION_CELLS,
};
#[cfg(feature = "seas")]
pub use seas_bp7::{bp7_g1, bp7_g2, Bp7Law, SeasBp7, SeasBp7FaultOde};
#[cfg(feature = "seas")]
pub use seas_bp7_volume::Bp7BodyColumns;
#[cfg(feature = "seas")]
pub use seas_bp8::{Bp8Overpressure, Bp8Source, SeasBp8, SeasBp8FaultOde, BP8_SECONDS_PER_DAY};
#[cfg(feature = "seas")]
pub use seas_square_run::{
    square_ranges, Bp8OverpressureRule, SeasBp7Run, SeasBp8Run, SquareKernel, INTEGRATOR_HELP,
    SQUARE_FE_DOMAIN_KM, SQUARE_FE_RATIO,
};
#[cfg(feature = "seas")]
pub use square_volume::{SquareVolumeGrid, VolumeElimination, SQUARE_VOLUME_MAX_CELLS};
#[cfg(feature = "seas")]
pub use stepover::{
    Stepover, StepoverFaultOde, StepoverGrid, STEPOVER_FAULTS, STEPOVER_STATION_DISTANCES,
};
#[cfg(feature = "seas")]
pub use stepover_run::{stepover_ranges, StepoverRun};
// BP5's stations: their files are the output's (rsf-seas), their positions the scene's.
#[cfg(feature = "seas")]
pub use rsf_seas::{SEAS_BP5_BODY_STATIONS, SEAS_BP5_FAULT_STATIONS};
pub use slider::{
    AdaptiveTimeStep, SceneSimulation, SceneSimulationBuilder, SliderScene, TimeStep, ALPHA_RANGE,
    SLIDER_CENTRE,
};
pub use slider3d::{skew_rotation, slider_3d_coarse, LateralBoundary, Slider3dScene, TAG_LATERAL};

/// Options of the fault ODE of the SEAS scenes: Dormand–Prince 5(4), local errors at most
/// `tolerance · slip_scale` in slip and `tolerance` in ln θ per step, steps in
/// [1e-6 s, 1 yr].
#[cfg(feature = "seas")]
fn seas_fault_ode_options(
    tolerance: f64,
    slip_scale: f64,
) -> rsf::Result<rsf::fault_ode::FaultOdeOptions> {
    let mut o = rsf::fault_ode::FaultOdeOptions {
        tolerance,
        slip_scale,
        ..rsf::fault_ode::FaultOdeOptions::default()
    };
    o.runge_kutta.dt_min = 1e-6;
    o.runge_kutta.dt_max = 3.15576e7;
    o.validate()?;
    Ok(o)
}

/// [`rsf::Error::InvalidParameter`] named `name` with `reason`.
/// The vertices of `model` nearest `points` (m), sorted, without repeats: the off-fault
/// stations' vertices a volume's output reads.
///
/// # Errors
/// [`rsf::Model::nearest_node`]'s (a model without vertices).
#[cfg(feature = "seas")]
pub(crate) fn nearest_vertices(
    model: &rsf::Model<3, 3>,
    points: &[[f64; 3]],
) -> rsf::Result<Vec<usize>> {
    let mut vertices = points
        .iter()
        .map(|x| model.nearest_node(x))
        .collect::<rsf::Result<Vec<usize>>>()?;
    vertices.sort_unstable();
    vertices.dedup();
    Ok(vertices)
}

pub(crate) fn invalid(name: &str, reason: impl Into<String>) -> rsf::Error {
    rsf::Error::InvalidParameter {
        name: name.to_string(),
        reason: reason.into(),
    }
}

/// The name of the parameter `result` refuses (tests of the settings' refusals).
///
/// # Panics
/// If `result` is not an [`rsf::Error::InvalidParameter`].
#[cfg(all(test, feature = "seas"))]
pub(crate) fn refused_name(result: rsf::Result<()>) -> String {
    match result {
        Err(rsf::Error::InvalidParameter { name, .. }) => name,
        other => panic!("{other:?}"),
    }
}

/// Checks a mesh's grading `ratio` (the growth of its cells) in [1, 2].
///
/// # Errors
/// [`rsf::Error::InvalidParameter`] named `ratio`, with its value.
#[cfg(feature = "seas")]
pub(crate) fn check_ratio(ratio: f64) -> rsf::Result<()> {
    if (1.0..=2.0).contains(&ratio) {
        Ok(())
    } else {
        Err(invalid(
            "ratio",
            format!("{} must be in [1, 2]", rsf_numeric::written(ratio)),
        ))
    }
}

/// [`invalid`] named `name` for the length `value` (m) that breaks `rule`: "`value` m
/// `rule`", the value as [`rsf_numeric::written`] writes it.
#[cfg(feature = "seas")]
pub(crate) fn invalid_length(name: &str, value: f64, rule: impl std::fmt::Display) -> rsf::Error {
    invalid(name, format!("{} m {rule}", rsf_numeric::written(value)))
}
