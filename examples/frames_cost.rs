//! What nodal frames cost per time step (issue 24; docs/performance.md): the paper's slider
//! with its axis-aligned fault (`--angle 0`, no frames) against the same slider turned so
//! that every fault node has a frame. In 2-D the turned slider is the inclined one of
//! `examples/inclined_block.rs` (`rsf_programs::inclined_slider_model`: mesh and loading
//! turned by `--angle`, gravity vertical; its velocity problems are the unturned ones in
//! other coordinates); in 3-D the block of `rsf_scenes::Slider3dScene` (W = 1 m, free lateral
//! faces) turned by `--angle` about (1, 2, 3)/√14 with gravity
//! (`rsf_scenes::Slider3dScene::build_turned_model`). Both give the unturned trajectory (same fixed
//! point iterations), so the stepping times compare the same work.
//!
//! ```sh
//! cargo run --release --example frames_cost -- --dim 2 --level 4 --angle 30
//! cargo run --release --example frames_cost -- --dim 3 --level 3 --angle 30 --end-time 3 --steps 2000
//! ```
//!
//! Prints the model size, the set-up time (model and simulation), the stepping time and
//! the time per step, and the run's statistics (fixed point iterations, solver iterations,
//! first slip event, peak slip rate). Writes no files.

use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use rsf::{Observer, StepView, Until};
use rsf_programs::estimates::{slider_memory, slider_what};
use rsf_programs::guard::{in_range, AnyError, Limits, Plan, Prepared, Program};
use rsf_programs::SliderArgs;
use rsf_scenes::inclined_slider_model;
use rsf_scenes::{SceneSimulation, Slider3dScene, SliderScene};

/// The cost of nodal frames per time step: the slider axis-aligned or turned.
#[derive(Parser)]
#[command(version)]
struct Cli {
    #[command(flatten)]
    slider: SliderArgs,
    /// Spatial dimension: 2 (the paper's slider) or 3 (the 3-D slider).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(2..=3))]
    dim: u8,
    /// Angle the slider is turned by (degrees; 0: the axis-aligned slider, no frames).
    #[arg(long, default_value_t = 30.0, allow_negative_numbers = true)]
    angle: f64,
    #[command(flatten)]
    limits: Limits,
}

impl Cli {
    /// The scene of the flags.
    fn scene(&self) -> Result<SliderScene, AnyError> {
        self.slider.scene()
    }
}

impl Program for Cli {
    rsf_programs::name_and_limits!("frames_cost");

    fn plan(&self) -> Result<Plan, AnyError> {
        let scene = self.scene()?;
        in_range("--angle", self.angle, (-360.0, 360.0), "degrees")?;
        // A timing run: its fixed steps are bounded so that a typo does not run for ever.
        if scene.time_step == (rsf_scenes::TimeStep::Fixed {}) {
            in_range(
                "--steps",
                scene.steps as f64,
                (1.0, 1e7),
                "steps of a timing run (more time nothing new)",
            )?;
        }
        let bytes = if self.dim == 2 {
            slider_memory(&scene)
        } else {
            Slider3dScene {
                slider: scene.clone(),
                ..Slider3dScene::default()
            }
            .estimated_bytes()
            .1
        };
        Ok(Plan::new().memory(bytes, "--level, --dim (or --scene)", slider_what(&scene)))
    }
}

/// The first time the largest slip rate exceeds 1e-3 m/s, and the peak slip rate.
#[derive(Default)]
struct Events {
    first: Option<f64>,
    peak: f64,
}

impl<const D: usize> Observer<D> for Events {
    fn observe(&mut self, s: &StepView<'_, D>) -> rsf::Result<rsf::Flow> {
        let v = s.report.max_slip_rate;
        self.peak = self.peak.max(v);
        if v > 1e-3 && self.first.is_none() {
            self.first = Some(s.report.time);
        }
        Ok(rsf::Flow::Continue(()))
    }
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, _: Prepared) -> Result<(), AnyError> {
    let scene: SliderScene = cli.scene()?;
    let phi = cli.angle.to_radians();
    let start = Instant::now();
    if cli.dim == 2 {
        let model = inclined_slider_model(&scene, phi)?;
        let frames = model.frames.nodes.len();
        let sim = scene.build_with_model(model)?;
        report(cli.angle, frames, start, sim, scene.end_time_s)
    } else {
        let scene3 = Slider3dScene {
            slider: scene,
            ..Slider3dScene::default()
        };
        let model = scene3.build_turned_model(phi)?;
        let frames = model.frames.nodes.len();
        let sim = scene3.build_with_model(model)?;
        report(cli.angle, frames, start, sim, scene3.slider.end_time_s)
    }
}

fn report<const D: usize>(
    angle: f64,
    frames: usize,
    start: Instant,
    mut sim: SceneSimulation<D>,
    end_time: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    let setup = start.elapsed().as_secs_f64();
    let mut events = Events::default();
    let summary = sim.run_until(Until::Time(end_time), &mut [&mut events])?;
    println!(
        "{D}-D, turned by {angle}°: {} dofs, {} frictional nodes ({frames} with frames); \
         set-up {setup:.3} s; {} steps in {:.3} s = {:.4} ms per step",
        sim.model().num_dofs(),
        sim.model().frictional_boundary.len(),
        summary.steps,
        summary.seconds,
        1e3 * summary.seconds / summary.steps.max(1) as f64
    );
    println!(
        "fixed point iterations: mean {:.4}, max {}; solver iterations {}; first slip event \
         (max V > 1e-3 m/s): {}; peak slip rate {:.6e} m/s",
        summary.fpi_mean,
        summary.fpi_max,
        summary.solver_iterations,
        events.first.map_or("none".into(), |t| format!("{t:.6} s")),
        events.peak
    );
    Ok(())
}
