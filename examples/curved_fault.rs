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
//! Writes to `out/curved_fault/` (or `--out DIR`): `timeseries.csv` (a `rsf::observe::PointSeries`
//! at x0 = (2.5, 0), the arc's lowest point, where the frame is Cartesian: same columns as
//! the main job's), the figure `slip_rate_max.png` (the largest slip rate on the arc) and,
//! with `--frame-every N`, VTU frames with a `frames/frames.pvd` index for ParaView (slip,
//! slip rate, shear and normal traction along the arc).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use rsf_programs::guard::{flag, AnyError, Plan, Prepared, Program};
use rsf_programs::{
    describe_method, max_slip_rate_figure, print_run, run_with_series, OwnRun, OwnRunArgs,
    SliderArgs,
};
use rsf_scenes::{arc_block_model, ARC_BLOCK_MESH};
use rsf_scenes::{SliderScene, SLIDER_CENTRE};

/// The paper's slider on a circular-arc base: time series at x0, summary, figure.
#[derive(Parser)]
#[command(version)]
struct Cli {
    #[command(flatten)]
    slider: SliderArgs,
    /// The Gmsh MSH 4.1 mesh of the block (physical groups `frictional` on the arc of
    /// radius 10 m about (2.5, 10), `dirichlet` on top, `neumann` on the sides).
    #[arg(long, default_value = ARC_BLOCK_MESH)]
    mesh: PathBuf,
    #[command(flatten)]
    output: OwnRunArgs,
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

impl Cli {
    /// The scene of the flags.
    fn scene(&self) -> Result<SliderScene, AnyError> {
        self.slider.scene()
    }

    /// The output folder.
    fn out(&self) -> PathBuf {
        self.output
            .out
            .clone()
            .unwrap_or_else(|| "out/curved_fault".into())
    }

    /// The run on its own model.
    fn own<'a>(&'a self, out: &'a Path) -> OwnRun<'a> {
        OwnRun {
            program: "curved_fault",
            label: "curved fault",
            out,
            figure: "slip_rate_max.png",
            args: &self.output,
        }
    }
}

impl Program for Cli {
    rsf_programs::name_and_limits!("curved_fault", output.limits);

    fn plan(&self) -> Result<Plan, AnyError> {
        let scene = self.scene()?;
        // The mesh must be there to be read (read with the model, after the folder).
        flag(
            &format!("--mesh {}", self.mesh.display()),
            std::fs::metadata(&self.mesh).and_then(|m| {
                if m.is_file() {
                    Ok(())
                } else {
                    Err(std::io::Error::other("not a file"))
                }
            }),
        )?;
        let out = self.out();
        self.own(&out).plan(&scene)
    }
}

fn run(cli: Cli, prepared: Prepared) -> Result<(), AnyError> {
    let scene: SliderScene = cli.scene()?;
    let out = cli.out();
    let run = cli.own(&out);
    // The folder was refused before anything was computed if it holds another run or
    // cannot be written (the guard).
    let mode = prepared.mode();
    println!(
        "curved_fault: {}, mesh {} → {}",
        describe_method(&scene),
        cli.mesh.display(),
        out.display()
    );
    let model = arc_block_model(&scene, &cli.mesh)?;
    let frames = model.frames.nodes.len();
    let mut sim = scene.build_with_model(model)?;
    let x0 = sim.model().nearest_node(&SLIDER_CENTRE)?;
    let (result, st) = run_with_series(&scene, &mut sim, x0, run, mode)?;
    max_slip_rate_figure(
        &out.join("slip_rate_max.png"),
        "Largest slip rate on the arc",
        &result,
    )?;
    print_run(&result, &st, frames);
    Ok(())
}
