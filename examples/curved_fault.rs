//! The paper's slider (§6.1, Table 6.1) on a curved base (issue 24): the block x ∈ [0, 5] m
//! below y = 1 m whose frictional base is a circular arc of radius 10 m (through (2.5, 0),
//! 0.32 m higher at the ends), from the Gmsh fixture `arc_block.msh` (with its
//! `arc_block.geo`, crates/rsf-fem/tests/fixtures). The coarse mesh is refined `--level`
//! times with the new base nodes moved onto the arc; every base node but the lowest has a
//! nodal frame (docs/math.md §10.1), so friction acts along the arc. Material, friction,
//! gravity, loading (the top moving along x) and σ̄_n are the paper's.
//!
//! ```sh
//! cargo run --release --example curved_fault -- --level 3
//! ```
//!
//! Writes to `out/curved_fault/` (or `--out DIR`): `timeseries.csv` (a `rsf::PointSeries`
//! at x0 = (2.5, 0), the arc's lowest point, where the frame is Cartesian: same columns as
//! the main job's), the figure `slip_rate_max.png` (the largest slip rate on the arc) and,
//! with `--frame-every N`, VTU frames with a `frames/frames.pvd` index for ParaView (slip,
//! slip rate, shear and normal traction along the arc).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use rsf::{FileMode, Observer, PointSeries, SliderScene, Until, SLIDER_CENTRE};
use rsf_examples::{
    arc_block_model, max_slip_rate_figure, stats, FrameArgs, SceneArgs, SliderRun, TimeStepArgs,
    ARC_BLOCK_MESH,
};

/// The paper's slider on a circular-arc base: time series at x0, summary, figure.
#[derive(Parser)]
#[command(version)]
struct Cli {
    #[command(flatten)]
    scene: SceneArgs,
    #[command(flatten)]
    time_step: TimeStepArgs,
    /// The Gmsh MSH 4.1 mesh of the block (physical groups `frictional` on the arc of
    /// radius 10 m about (2.5, 10), `dirichlet` on top, `neumann` on the sides).
    #[arg(long, default_value = ARC_BLOCK_MESH)]
    mesh: PathBuf,
    /// Output folder.
    #[arg(long, default_value = "out/curved_fault")]
    out: PathBuf,
    #[command(flatten)]
    frames: FrameArgs,
}

fn main() -> ExitCode {
    rsf_examples::main_with(|| run(Cli::parse()))
}

fn run(cli: Cli) -> Result<(), Box<dyn std::error::Error>> {
    let scene: SliderScene = cli
        .time_step
        .apply(cli.scene.scene(SliderScene::default())?)?;
    let out = cli.out;
    std::fs::create_dir_all(&out)?;
    println!(
        "curved_fault: level {}, {}, {} law, {}, {} solver, mesh {} → {}",
        scene.level,
        TimeStepArgs::describe(&scene),
        scene.state_law,
        scene.integrator,
        scene.solver,
        cli.mesh.display(),
        out.display()
    );
    let model = arc_block_model(&scene, &cli.mesh)?;
    let frames = model.frames.nodes.len();
    let mut sim = scene.build_with_model(model)?;
    let x0 = sim.model().nearest_node(&SLIDER_CENTRE)?;
    let series_csv = out.join("timeseries.csv");
    let mut frame_files = cli.frames.observer(0, &out, FileMode::Create)?;
    let mut series = PointSeries::new(&series_csv, sim.model(), x0, FileMode::Create)?;
    let mut progress = scene.progress(0.0, "curved fault");
    let mut observers: Vec<&mut dyn Observer<2>> = vec![&mut series, &mut progress];
    if let Some(f) = frame_files.as_mut() {
        observers.push(f);
    }
    let summary = sim.run_until(Until::Time(scene.end_time_s), &mut observers)?;
    drop(observers);

    let mut run = SliderRun::from_series(&PointSeries::<2>::read(&series_csv)?);
    (run.dofs, run.frictional_nodes) = (
        sim.model().num_dofs(),
        sim.model().frictional_boundary.len(),
    );
    run.seconds = summary.seconds;
    let st = stats(&run, scene.end_time_s);
    max_slip_rate_figure(
        &out.join("slip_rate_max.png"),
        "Largest slip rate on the arc",
        &run,
    )?;
    println!(
        "{} dofs, {} frictional nodes ({frames} with nodal frames), {} steps in {:.2} s",
        run.dofs,
        run.frictional_nodes,
        run.fpi.len(),
        run.seconds
    );
    println!(
        "fixed point iterations: mean {:.2}, max {}; first slip event (max V > 1e-3 m/s): {}; \
         slip events: {}; peak slip rate {:.3e} m/s",
        st.fpi_mean,
        st.fpi_max,
        st.first_slip_event_s
            .map_or("none".into(), |t| format!("{t:.3} s")),
        st.slip_events,
        st.peak_slip_rate_mps
    );
    Ok(())
}
