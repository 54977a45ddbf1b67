//! The paper's slider (§6.1, Table 6.1) on an elastic base instead of a rigid one: the
//! block [0, 5] × [0, 1] m of the main job sits on a base [0, 5] × [−1, 0] m whose bottom
//! is fixed; the frictional interface y = 0 is a fault inside the body
//! (`ModelBuilder::internal_fault`, both sides deforming, the slip the jump of the
//! displacement), the two materials regions of one body (`MaterialRegions`). As the
//! base's Young's modulus grows the trajectory approaches the main job's (rigid base).
//!
//! ```sh
//! cargo run --release --example slider_elastic_base                     # j = 3, T = 15 s
//! cargo run --release --example slider_elastic_base -- --base-e 5e9,5e11 --compare-solvers
//! ```
//!
//! Prints, for the rigid base (the main job) and every `--base-e`, the events (max V ≥
//! 1e-3 m/s on the interface), the peak slip rate and the largest difference of
//! log10 V at x0 = (2.5, 0) from the rigid run at the rigid run's step times up to the
//! first event, with the wall time. `--compare-solvers` runs the rigid and the stiffest
//! base with TNNMG and with the direct solver and prints all four. Writes `series.csv` (time and log10 V at
//! x0 per run) and `slip_rate_x0.png` (the rigid and the elastic bases) to
//! `out/slider_elastic_base/` (or `--out DIR`).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use rsf::fem::rectangle;
use rsf::model::MaterialRegions;
use rsf::observe::StepView;
use rsf::time::VelocityIntegrator;
use rsf::{Flow, Material, ModelBuilder, Observer, Part, SolverKind, Until};
use rsf_programs::estimates::{slider_memory, slider_steps, slider_what, FIGURE_BYTES};
use rsf_programs::guard::{in_range, AnyError, Folder, Limits, Plan, Prepared, Program};
use rsf_programs::{line_plot, Labels, PaperSliderAt, Series, SliderArgs};
use rsf_scenes::{SliderScene, SLIDER_CENTRE};

/// The paper's slider on an elastic base.
#[derive(Parser)]
#[command(version)]
struct Cli {
    #[command(flatten)]
    slider: SliderArgs<PaperSliderAt<3>>,
    /// Young's moduli of the base (Pa), comma-separated (the block's is the scene's, 5e7).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "5e7,5e8,5e9,5e10,5e11",
        allow_negative_numbers = true
    )]
    base_e: Vec<f64>,
    /// Also run the rigid and the stiffest base with both TNNMG and the direct solver.
    #[arg(long)]
    compare_solvers: bool,
    /// Output folder.
    #[arg(long, default_value = "out/slider_elastic_base")]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out` (without it, a folder holding any
    /// rsf program's run is refused and left untouched). The runs keep their rows in
    /// memory until the end, so there is no `--resume`: they take minutes.
    #[arg(long)]
    overwrite: bool,
    #[command(flatten)]
    limits: Limits,
}

/// The scene of the flags (level 3 unless they say otherwise).
fn base(cli: &Cli) -> Result<SliderScene, AnyError> {
    cli.slider.scene()
}

impl Program for Cli {
    rsf_programs::name_and_limits!("slider_elastic_base");

    fn plan(&self) -> Result<Plan, AnyError> {
        let scene = base(self)?;
        for &e in &self.base_e {
            // The scene's admissible Young's moduli (`youngs_modulus_pa`).
            in_range("--base-e", e, (1e3, 1e13), "Pa: foam to beyond diamond")?;
        }
        let runs = (1 + self.base_e.len() + if self.compare_solvers { 4 } else { 0 }) as f64;
        let steps = slider_steps(&scene);
        // A model of the block and its base (twice the block's nodes) at a time; every
        // run's rows (3 numbers) in memory, the CSV's text before it is written.
        let memory = 2.0 * slider_memory(&scene) + runs * steps * (24.0 + 80.0);
        let output = runs * steps * 80.0 + FIGURE_BYTES;
        let what = format!("{} runs of {}", runs, slider_what(&scene));
        Ok(Plan::new()
            .memory(
                memory,
                "--level, --steps, --base-e (or --scene)",
                what.clone(),
            )
            .output(output, "--steps, --end-time, --base-e (or --scene)", what)
            .folder(
                Folder::new("--out", &self.out, &["series.csv", "slip_rate_x0.png"])
                    .overwrite(self.overwrite),
            ))
    }
}

/// Slip rate of an event (m/s), as the main job's event definition.
const SLIPPING: f64 = 1e-3;

/// One row per step: time (s), slip rate at x0, max slip rate on the interface (m/s).
#[derive(Default)]
struct Samples {
    x0: usize,
    rows: Vec<[f64; 3]>,
}

impl Observer<2> for Samples {
    fn observe(&mut self, s: &StepView<'_, 2, 2>) -> rsf::Result<Flow> {
        let max_v = (0..s.model.frictional_boundary.len())
            .map(|k| s.slip_rate(k))
            .fold(0.0, f64::max);
        let x0 = s.model.frictional_boundary.fault_index(self.x0);
        let v_x0 = x0.map_or(f64::NAN, |k| s.slip_rate(k));
        self.rows.push([s.state.time, v_x0, max_v]);
        Ok(Flow::Continue(()))
    }
}

/// Start times (s) of the stretches with max V ≥ [`SLIPPING`].
fn event_starts(rows: &[[f64; 3]]) -> Vec<f64> {
    let mut out = Vec::new();
    let mut slipping = false;
    for r in rows {
        if r[2] >= SLIPPING && !slipping {
            out.push(r[0]);
        }
        slipping = r[2] >= SLIPPING;
    }
    out
}

/// The model of `scene`'s physics on the block over a base of Young's modulus `base_e`.
fn elastic_base_model(scene: &SliderScene, base_e: f64) -> rsf::Result<rsf::Model<2>> {
    // The main job's coarse grid (1 m cells) continued one cell row down.
    let coarse = rectangle([0.0, -1.0], [5.0, 2.0], 6, 3, scene.diagonal)?;
    let block = scene.material();
    let base = Material {
        youngs_modulus: base_e,
        ..block
    };
    let medium = MaterialRegions::new(block).region("base", |x| x[1] < 0.0, base);
    let builder = ModelBuilder::refined(coarse, scene.level)?
        .material(medium)
        .gravity([0.0, -scene.gravity_m_per_s2])
        .dirichlet(
            Part::predicate("top", |x| x[1] > 1.0 - 1e-9),
            [scene.loading_velocity_m_per_s, 0.0],
        )
        .dirichlet(
            Part::predicate("bottom", |x| x[1] < -1.0 + 1e-9),
            [0.0, 0.0],
        )
        .internal_fault("interface", [0.0, 0.0], [5.0, 0.0])
        .loading(scene.loading());
    if scene.integrator.uses_mass() {
        builder.build()
    } else {
        builder.without_mass().build()
    }
}

/// A finished run: name, samples, wall time (s).
struct RunResult {
    name: String,
    rows: Vec<[f64; 3]>,
    seconds: f64,
}

fn run_scene(
    scene: &SliderScene,
    name: String,
    model: Option<rsf::Model<2>>,
) -> Result<RunResult, Box<dyn std::error::Error>> {
    let mut sim = match model {
        Some(m) => scene.build_with_model(m)?,
        None => scene.build()?,
    };
    let mut samples = Samples {
        x0: sim.model().nearest_node(&SLIDER_CENTRE)?,
        ..Samples::default()
    };
    let clock = std::time::Instant::now();
    sim.run_until(Until::Time(scene.end_time_s), &mut [&mut samples])?;
    Ok(RunResult {
        name,
        rows: samples.rows,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

/// log10 V at x0 of `rows` at time `t` (linear interpolation between steps).
fn log_v_at(rows: &[[f64; 3]], t: f64) -> f64 {
    let k = rows.partition_point(|r| r[0] < t).clamp(1, rows.len() - 1);
    let (a, b) = (rows[k - 1], rows[k]);
    let w = ((t - a[0]) / (b[0] - a[0])).clamp(0.0, 1.0);
    (1.0 - w) * a[1].log10() + w * b[1].log10()
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, _folder: Prepared) -> Result<(), AnyError> {
    let scene = base(&cli)?;
    println!(
        "slider on an elastic base, level {}, N = {}, T = {} s, {} law, {}, solver {:?}; on {}",
        scene.level,
        scene.steps,
        scene.end_time_s,
        scene.state_law,
        scene.integrator,
        scene.solver,
        rsf_programs::machine()
    );
    let mut runs = vec![run_scene(&scene, "rigid base (main job)".into(), None)?];
    for &e in &cli.base_e {
        let model = elastic_base_model(&scene, e)?;
        runs.push(run_scene(
            &scene,
            format!("base E = {e:e} Pa"),
            Some(model),
        )?);
    }
    if cli.compare_solvers {
        let e = cli.base_e.iter().copied().fold(f64::NAN, f64::max);
        for solver in [SolverKind::Tnnmg, SolverKind::Direct] {
            let s = SliderScene {
                solver,
                ..scene.clone()
            };
            runs.push(run_scene(&s, format!("rigid base, {solver:?}"), None)?);
            let model = elastic_base_model(&s, e)?;
            runs.push(run_scene(
                &s,
                format!("base E = {e:e} Pa, {solver:?}"),
                Some(model),
            )?);
        }
    }
    let rigid = &runs[0].rows;
    let rigid_first = event_starts(rigid)
        .first()
        .copied()
        .unwrap_or(scene.end_time_s);
    println!(
        "{:<34} {:>6} {:>6} {:>12} {:>12} {:>18} {:>9}",
        "run", "steps", "events", "first (s)", "peak V (m/s)", "max|Δlog10 V(x0)|", "wall (s)"
    );
    for r in &runs {
        let starts = event_starts(&r.rows);
        let peak = r.rows.iter().map(|x| x[2]).fold(0.0, f64::max);
        // Before the rigid run's first event, at its step times.
        let diff = rigid
            .iter()
            .filter(|x| x[0] > 0.0 && x[0] < rigid_first)
            .map(|x| (log_v_at(&r.rows, x[0]) - x[1].log10()).abs())
            .fold(0.0, f64::max);
        println!(
            "{:<34} {:>6} {:>6} {:>12} {:>12.4e} {:>18.3e} {:>9.1}",
            r.name,
            r.rows.len(),
            starts.len(),
            starts
                .first()
                .map_or("none".to_string(), |t| format!("{t:.4}")),
            peak,
            diff,
            r.seconds
        );
    }

    let mut csv = String::from("run,t_s,log10_v_x0\n");
    for r in &runs {
        for x in &r.rows {
            csv.push_str(&format!("{},{:.17e},{:.17e}\n", r.name, x[0], x[1].log10()));
        }
    }
    rsf::checkpoint::write_atomically(&cli.out.join("series.csv"), csv.as_bytes())?;
    // The figure: the rigid base and the elastic ones (not the solver comparison).
    let plotted = &runs[..=cli.base_e.len()];
    let points: Vec<Vec<(f64, f64)>> = plotted
        .iter()
        .map(|r| r.rows.iter().map(|x| (x[0], x[1].max(1e-40))).collect())
        .collect();
    let series: Vec<Series> = plotted
        .iter()
        .zip(&points)
        .map(|(r, p)| Series {
            label: &r.name,
            points: p,
        })
        .collect();
    line_plot(
        &cli.out.join("slip_rate_x0.png"),
        &Labels {
            title: "Slip rate at x0 = (2.5, 0): rigid base against elastic bases",
            x: "t (s)",
            y: "slip rate (m/s)",
        },
        &series,
        true,
        false,
    )?;
    println!("wrote {}", cli.out.display());
    Ok(())
}
