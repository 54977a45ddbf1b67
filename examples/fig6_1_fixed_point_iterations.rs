//! Figure 6.1 of Pipping, Sander & Kornhuber: average and maximum number of fixed point
//! iterations (FPIs) per time step over 10⁴ steps (the whole of [0, T]) against the
//! refinement level j, for Dieterich's and Ruina's law (Newmark, paper tolerances: fixed
//! point 1e-10, inner solve 1e-10).
//!
//! ```sh
//! cargo run --release --example fig6_1_fixed_point_iterations                    # j = 2..5
//! cargo run --release --example fig6_1_fixed_point_iterations -- --max-level 7   # j = 2..7 (the paper's figure)
//! cargo run --release --example fig6_1_fixed_point_iterations -- --fixed-point anderson  # the library's default scheme
//! cargo run --release --example fig6_1_fixed_point_iterations -- --solver tnnmg --levels 2,3,4
//! ```
//!
//! Prints one row per (law, j) as it finishes (with the time of the step with the most
//! FPIs) and writes to `out/fig6_1/` (or `--out DIR`): `table.csv` (`law,level,dofs,
//! steps,fpi_mean,fpi_max,relaxed_steps,solver_iterations,first_slip_event_s,wall_s`,
//! appended row by row) and
//! `fig6_1_fpi.png` (average solid on the left axis, maximum on the right axis, one
//! panel per law, as the paper).

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use plotters::prelude::*;
use rsf::method::FixedPointScheme;
use rsf::{SolverKind, StateLawKind};
use rsf_programs::cli::step_count;
use rsf_programs::estimates::{slider_memory, slider_steps, slider_what};
use rsf_programs::estimates::{FIGURE_BYTES, RECORDED_STEP_BYTES};
use rsf_programs::guard::{in_range, AnyError, Folder, Limits, Plan, Prepared, Program};
use rsf_programs::{stats, SliderRun};
use rsf_scenes::SliderScene;

/// Figure 6.1: fixed point iterations per time step against the refinement level.
#[derive(Parser)]
#[command(version)]
struct Cli {
    /// Levels j to run (comma separated) [default: 2..=--max-level].
    #[arg(long, value_delimiter = ',', value_name = "J1,J2,...")]
    levels: Option<Vec<usize>>,
    /// Largest level when --levels is not given (2 to 8).
    #[arg(long, default_value_t = 5, value_name = "J")]
    max_level: usize,
    /// State laws (comma separated).
    #[arg(long, value_enum, value_delimiter = ',', default_value = "aging,slip")]
    laws: Vec<StateLawKind>,
    /// Number of time steps N over T = 15 s (`1e4` accepted).
    #[arg(long, value_parser = step_count, default_value = "10000")]
    steps: usize,
    /// Velocity solver.
    #[arg(long, value_enum, default_value = "auto")]
    solver: SolverKind,
    /// Fixed point scheme: the paper's relaxation (what the figure counts) or the
    /// library's default (Anderson acceleration with an extrapolated predictor).
    #[arg(long, value_enum, default_value = "paper")]
    fixed_point: FixedPointScheme,
    /// Output folder.
    #[arg(long, default_value = "out/fig6_1")]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out` (without it, a folder holding any
    /// rsf program's run is refused and left untouched).
    #[arg(long)]
    overwrite: bool,
    #[command(flatten)]
    limits: Limits,
}

impl Cli {
    /// The levels to run.
    fn levels(&self) -> Vec<usize> {
        self.levels
            .clone()
            .unwrap_or_else(|| (2..=self.max_level.min(8)).collect())
    }
}

impl Program for Cli {
    rsf_programs::name_and_limits!("fig6_1");

    fn plan(&self) -> Result<Plan, AnyError> {
        in_range(
            "--max-level",
            self.max_level as f64,
            (2.0, 8.0),
            "the paper's levels",
        )?;
        let levels = self.levels();
        rsf_programs::guard::distinct("--levels", &levels)?;
        let mut plan = Plan::new();
        let mut worst = 0.0f64;
        for &level in &levels {
            let scene = SliderScene {
                level,
                steps: self.steps,
                ..SliderScene::default()
            };
            // One run at a time: its model and every step's record.
            let bytes = slider_memory(&scene) + slider_steps(&scene) * RECORDED_STEP_BYTES;
            if bytes > worst {
                worst = bytes;
                plan = plan.memory(bytes, "--levels, --max-level, --steps", slider_what(&scene));
            }
        }
        let rows = (levels.len() * self.laws.len()) as f64;
        Ok(plan
            .output(
                rows * 200.0 + FIGURE_BYTES,
                "--levels, --laws",
                "the table and figure",
            )
            .folder(
                Folder::new("--out", &self.out, &["table.csv", "fig6_1_fpi.png"])
                    .overwrite(self.overwrite),
            ))
    }
}

/// One measured point: law, level, mean FPIs, max FPIs.
type Row = (StateLawKind, usize, f64, usize);

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, _folder: Prepared) -> Result<(), AnyError> {
    let levels = cli.levels();
    let laws: Vec<StateLawKind> = cli.laws.clone();
    let solver = cli.solver;
    let steps = cli.steps;
    let out = cli.out;
    println!(
        "Figure 6.1: FPIs per step over N = {steps} steps, levels {levels:?}, {solver} solver \
         (tolerance 1e-10), {} fixed point, Newmark, on {}",
        cli.fixed_point,
        rsf_programs::machine()
    );
    println!(
        "{:>10} {:>3} {:>7} {:>9} {:>8} {:>8} {:>11} {:>10} {:>10} {:>8}",
        "law",
        "j",
        "dofs",
        "FPI mean",
        "FPI max",
        "relaxed",
        "solver its",
        "1st slip",
        "max at t",
        "wall s"
    );
    let table_path = out.join("table.csv");
    let mut table = std::fs::File::create(&table_path)
        .map_err(|e| format!("cannot create `{}`: {e}", table_path.display()))?;
    writeln!(
        table,
        "law,level,dofs,steps,fpi_mean,fpi_max,relaxed_steps,solver_iterations,first_slip_event_s,wall_s"
    )?;
    let mut rows: Vec<Row> = Vec::new();
    for &law in &laws {
        for &level in &levels {
            let scene = SliderScene {
                level,
                steps,
                state_law: law,
                solver,
                fixed_point: cli.fixed_point,
                ..SliderScene::default()
            };
            scene.validate()?;
            let run = SliderRun::record(&scene, 0, None)?;
            let st = stats(&run, scene.end_time_s);
            let first = st.first_slip_event_s.unwrap_or(f64::NAN);
            // Time of the (first) step with the most fixed point iterations.
            let k_max = run.fpi.iter().position(|&f| f == st.fpi_max).unwrap_or(0);
            let t_max = run.u_x0.get(k_max).map_or(f64::NAN, |p| p.0);
            println!(
                "{:>10} {:>3} {:>7} {:>9.3} {:>8} {:>8} {:>11} {:>10.3} {:>10.3} {:>8.1}",
                law.name(),
                level,
                run.dofs,
                st.fpi_mean,
                st.fpi_max,
                st.relaxed_steps,
                st.solver_iterations,
                first,
                t_max,
                run.seconds
            );
            writeln!(
                table,
                "{law},{level},{},{steps},{:.4},{},{},{},{first:.4},{:.1}",
                run.dofs,
                st.fpi_mean,
                st.fpi_max,
                st.relaxed_steps,
                st.solver_iterations,
                run.seconds
            )?;
            table.flush()?;
            rows.push((law, level, st.fpi_mean, st.fpi_max));
        }
    }
    draw(&out.join("fig6_1_fpi.png"), &laws, &rows, steps)?;
    println!("wrote {}", out.display());
    Ok(())
}

/// Two panels (one per law): average FPIs (solid, left axis) and maximum (right axis).
fn draw(
    path: &std::path::Path,
    laws: &[StateLawKind],
    rows: &[Row],
    steps: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    rsf_programs::init_fonts();
    rsf_programs::draw_png(path, (1000, 420), |root| {
        root.fill(&WHITE)?;
        let root = root.titled(
            &format!("Fig. 6.1 (ours): fixed point iterations per step over {steps} steps"),
            ("sans-serif", 18),
        )?;
        let areas = root.split_evenly((1, laws.len().max(1)));
        let jmin = rows.iter().map(|r| r.1).min().unwrap_or(2) as f64;
        let jmax = rows.iter().map(|r| r.1).max().unwrap_or(8) as f64;
        let avg_top = rows.iter().map(|r| r.2).fold(6.0, f64::max).ceil();
        let max_top = (rows.iter().map(|r| r.3).max().unwrap_or(0) as f64).max(60.0);
        let blue = RGBColor(31, 119, 180);
        let red = RGBColor(214, 39, 40);
        for (law, area) in laws.iter().zip(&areas) {
            let pts: Vec<&Row> = rows.iter().filter(|r| r.0 == *law).collect();
            let mut chart = ChartBuilder::on(area)
                .caption(paper_name(*law), ("sans-serif", 16))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .right_y_label_area_size(50)
                .build_cartesian_2d(jmin - 0.2..jmax + 0.2, 0.0..avg_top)?
                .set_secondary_coord(jmin - 0.2..jmax + 0.2, 0.0..max_top);
            chart
                .configure_mesh()
                .disable_x_mesh()
                .x_labels((jmax - jmin) as usize + 1)
                .x_label_formatter(&|j| format!("{j:.0}"))
                .x_desc("grid refinements j")
                .y_desc("average FPIs (solid)")
                .y_label_formatter(&|v| format!("{v:.0}"))
                .label_style(("sans-serif", 13))
                .draw()?;
            chart
                .configure_secondary_axes()
                .y_desc("maximum FPIs (dashed)")
                .y_label_formatter(&|v| format!("{v:.0}"))
                .label_style(("sans-serif", 13))
                .draw()?;
            chart.draw_series(LineSeries::new(
                pts.iter().map(|r| (r.1 as f64, r.2)),
                blue.stroke_width(2),
            ))?;
            chart.draw_series(
                pts.iter()
                    .map(|r| Circle::new((r.1 as f64, r.2), 4, blue.filled())),
            )?;
            chart.draw_secondary_series(DashedLineSeries::new(
                pts.iter().map(|r| (r.1 as f64, r.3 as f64)),
                6,
                4,
                red.stroke_width(2),
            ))?;
            chart.draw_secondary_series(
                pts.iter()
                    .map(|r| TriangleMarker::new((r.1 as f64, r.3 as f64), 5, red.filled())),
            )?;
        }
        Ok(())
    })
}

/// The law as the paper names it.
fn paper_name(law: StateLawKind) -> &'static str {
    match law {
        StateLawKind::Aging => "Dieterich's (aging) law",
        StateLawKind::Slip => "Ruina's (slip) law",
        StateLawKind::Discontinuous => "the discontinuous law",
    }
}
