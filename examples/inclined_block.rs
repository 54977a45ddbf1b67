//! The paper's slider (§6.1, Table 6.1) on a base inclined by `--dip` degrees (issue 24):
//! the block, its base and the loading turned so that the base descends in the loading
//! direction, gravity vertical, everything else the paper's (the prescribed σ̄_n too). The
//! base is a slanted fault: the model carries nodal frames (docs/math.md §10.1), and
//! `--dip 0` is the paper's model bit for bit (no frames; `timeseries.csv` identical to the
//! main job's at the same flags).
//!
//! What the dip changes, and what it does not: the run starts, as the paper's, from the
//! equilibrium `K u₀ = F` with Γ_F free tangentially, so the down-slope part of the weight
//! is carried by the clamped top from the start, and any constant load drops out of the
//! velocity problems (`F − K u₀` is a reaction on fixed dofs only). With σ̄_n prescribed the
//! trajectory in slip coordinates is therefore independent of the dip: measured at level 2,
//! `--dip 10` and `--dip -10` give the `--dip 0` first slip (10.086 s), 7 events and peak
//! slip rate (2.432e-2 m/s). Making the weight drive the slip needs another initial state,
//! not another geometry: with `--initial-equilibrium stuck` the run starts from the
//! equilibrium with the base held, which then carries the weight's down-slope part as a
//! shear traction, and the weight drives the slip. Measured at level 2 (first slip, events,
//! peak slip rate): dip 0 10.085 s, 7, 2.488e-2 m/s (the held base changes `u₀` through
//! the Poisson effect only); dip 10 8.952 s, 9, 2.551e-2; dip 20 7.849 s, 11, 2.560e-2;
//! dip −10 (the weight pulls up-slope, against the loading) 11.216 s, 6, 2.250e-2.
//!
//! ```sh
//! cargo run --release --example inclined_block -- --dip 10 --level 3
//! cargo run --release --example inclined_block -- --dip 20 --initial-equilibrium stuck
//! cargo run --release --example inclined_block -- --dip 0 --level 4   # the main job's slider
//! ```
//!
//! Writes to `out/inclined_block/` (or `--out DIR`): `timeseries.csv` (a `rsf::observe::PointSeries`
//! at x0, the paper's (2.5, 0) turned with the block; with `--dip 0` the main job's columns,
//! on a slanted base the slip coordinates `u_t_m, v_t_mps` (tangential) and `u_n_m, v_n_mps`
//! (inward normal), named so in the header), the figure `slip_rate_x0.png` and, with `--frame-every N`, VTU frames with
//! a `frames/frames.pvd` index for ParaView (slip, slip rate, shear and normal traction on
//! the base, in slip coordinates).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use rsf::fem::ConstrainedSystem;
use rsf::Model;
use rsf_programs::guard::{number, refuse, AnyError, Plan, Prepared, Program};
use rsf_programs::{
    describe_method, max_slip_rate_figure, print_run, run_with_series, OwnRun, OwnRunArgs,
    SliderArgs,
};
use rsf_scenes::SliderScene;
use rsf_scenes::{inclined_centre, inclined_slider_model};

/// The paper's slider on an inclined base: time series at x0, summary, figure.
#[derive(Parser)]
#[command(version)]
struct Cli {
    #[command(flatten)]
    slider: SliderArgs,
    /// Dip of the base (degrees, |dip| < 90; positive: descending in the loading direction).
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    dip: f64,
    /// The initial state: `free` (the paper's: the equilibrium `K u₀ = F` with the base
    /// free tangentially, so the clamped top carries the down-slope weight) or `stuck` (the
    /// equilibrium with the base held, so the base carries the down-slope weight as a
    /// shear traction at t = 0 and the weight drives its slip).
    #[arg(long, value_enum, default_value = "free")]
    initial_equilibrium: InitialEquilibrium,
    #[command(flatten)]
    output: OwnRunArgs,
}

/// Which equilibrium the run starts from (`--initial-equilibrium`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum InitialEquilibrium {
    /// Base free tangentially (the paper's).
    Free,
    /// Base held: it starts carrying the weight's down-slope part.
    Stuck,
}

/// `model` starting from the equilibrium with its frictional nodes held: `K u₀ = F` on the
/// dofs free apart from Γ_F, `u₀ = 0` on Γ_F (the reference the slip is measured from).
///
/// # Errors
/// [`rsf::Error::Fem`] from the factorisation or solve.
fn stuck_equilibrium(mut model: Model<2>) -> rsf::Result<Model<2>> {
    let mut fixed = model.fixed.clone();
    for &p in &model.frictional_boundary.nodes {
        fixed[2 * p..2 * p + 2].fill(true);
    }
    let mut u0 = vec![0.0; model.num_dofs()];
    ConstrainedSystem::new(model.stiffness.as_ref(), &fixed)
        .and_then(|mut s| s.solve(&model.load, &mut u0))
        .map_err(rsf::Error::Fem)?;
    model.initial_displacement = u0;
    Ok(model)
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
            .unwrap_or_else(|| "out/inclined_block".into())
    }

    /// The run on its own model.
    fn own<'a>(&'a self, out: &'a Path) -> OwnRun<'a> {
        OwnRun {
            program: "inclined_block",
            label: "inclined block",
            out,
            figure: "slip_rate_x0.png",
            args: &self.output,
        }
    }
}

impl Program for Cli {
    rsf_programs::name_and_limits!("inclined_block", output.limits);

    fn plan(&self) -> Result<Plan, AnyError> {
        let scene = self.scene()?;
        if !(self.dip.abs() < 90.0) {
            return Err(refuse(
                "--dip",
                number(self.dip),
                "must be in (-90, 90) degrees",
            ));
        }
        let out = self.out();
        self.own(&out).plan(&scene)
    }
}

fn run(cli: Cli, prepared: Prepared) -> Result<(), AnyError> {
    let scene: SliderScene = cli.scene()?;
    let dip = cli.dip.to_radians();
    let out = cli.out();
    let run = cli.own(&out);
    // The folder was refused before anything was computed if it holds another run or
    // cannot be written (the guard).
    let mode = prepared.mode();
    println!(
        "inclined_block: dip {}°, {} → {}",
        cli.dip,
        describe_method(&scene),
        out.display()
    );
    let model = match cli.initial_equilibrium {
        InitialEquilibrium::Free => inclined_slider_model(&scene, dip)?,
        InitialEquilibrium::Stuck => stuck_equilibrium(inclined_slider_model(&scene, dip)?)?,
    };
    let frames = model.frames.nodes.len();
    let mut sim = scene.build_with_model(model)?;
    let x0 = sim.model().nearest_node(&inclined_centre(dip))?;
    let (result, st) = run_with_series(&scene, &mut sim, x0, run, mode)?;
    max_slip_rate_figure(
        &out.join("slip_rate_x0.png"),
        &format!("Largest slip rate on the base, dip {}°", cli.dip),
        &result,
    )?;
    print_run(&result, &st, frames);
    Ok(())
}
