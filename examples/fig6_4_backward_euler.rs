//! Figure 6.4 of Pipping, Sander & Kornhuber: the slip rate at the centre x0 = (2.5, 0) of
//! Γ_F as in Figure 6.3 (Dieterich's law, j = 4), but with the dissipative backward Euler
//! method for the velocity, compared with Newmark, for τ = T/10⁴, T/10⁵ (default) and
//! T/10⁶ (`--with-1e6`, hours).
//!
//! ```sh
//! cargo run --release --example fig6_2_6_3_centre     # first: the Newmark series it compares with
//! cargo run --release --example fig6_4_backward_euler # N = 1e4, 1e5 (14 min on a loaded 2-core box)
//! cargo run --release --example fig6_4_backward_euler -- --with-1e6
//! cargo run --release --example fig6_4_backward_euler -- --reuse   # table + figures from the CSVs
//! ```
//!
//! The Newmark series are read from `--newmark-dir` (default `out/fig6_2_6_3`, the files
//! `centre_N{N}.csv` that `fig6_2_6_3_centre` writes); a missing one is computed here if
//! N ≤ 10⁴ (or always with `--run-newmark`), otherwise left out of the comparison.
//! Prints a table per (integrator, N) and writes to `out/fig6_4/` (or `--out DIR`):
//! `centre_backward_euler_N{N}.csv`, `table.csv`, `fig6_4_slip_rate.png` (|v(x0)| over
//! [0.75T, T], log scale, one row per τ, both integrators) and `fig6_4_displacement.png`
//! (u_x(x0) over [0.9T, T]).

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use rsf::observe::PointSeries;
use rsf::Integrator;
use rsf_programs::cli::StepCounts;
use rsf_programs::estimates::step_study_plan;
use rsf_programs::guard::{AnyError, Folder, Limits, Plan, Prepared, Program};
use rsf_programs::{
    old_wall_time, stats, Labels, PanelLayout, PaperFigures, Series, SliderArgs, SliderRun,
};
use rsf_scenes::SliderScene;

/// `(t, value)` samples.
type Points = Vec<(f64, f64)>;
/// Backward Euler and (if available) Newmark samples of one τ.
type Pair = (Points, Option<Points>);
/// The labelled series of one panel.
type Panel = Vec<(&'static str, Points)>;

/// Figure 6.4: slip rate at x0 with backward Euler, compared with Newmark.
#[derive(Parser)]
#[command(version)]
struct Cli {
    #[command(flatten)]
    slider: SliderArgs<PaperFigures>,
    #[command(flatten)]
    steps: StepCounts,
    /// Folder with the Newmark series `centre_N{N}.csv` of fig6_2_6_3_centre.
    #[arg(long, default_value = "out/fig6_2_6_3")]
    newmark_dir: PathBuf,
    /// Run the Newmark series here even if its CSV exists.
    #[arg(long)]
    run_newmark: bool,
    /// Output folder.
    #[arg(long, default_value = "out/fig6_4")]
    out: PathBuf,
    /// Re-tabulate and re-plot the backward Euler series of an earlier run.
    #[arg(long)]
    reuse: bool,
    /// Replace the files of an earlier run in `--out` (without it, a folder holding any
    /// rsf program's run is refused and left untouched).
    #[arg(long)]
    overwrite: bool,
    #[command(flatten)]
    limits: Limits,
}

/// The scene of the flags (level 4, the direct solver unless they say otherwise).
fn base(cli: &Cli) -> Result<SliderScene, AnyError> {
    cli.slider.scene()
}

impl Program for Cli {
    rsf_programs::name_and_limits!("fig6_4");

    fn plan(&self) -> Result<Plan, AnyError> {
        let scene = base(self)?;
        self.slider.steps_ignored("--steps")?;
        let counts = self.steps.counts();
        let mut names = vec![
            "table.csv".to_owned(),
            "fig6_4_slip_rate.png".to_owned(),
            "fig6_4_displacement.png".to_owned(),
        ];
        names.extend(
            counts
                .iter()
                .map(|n| format!("centre_backward_euler_N{n}.csv")),
        );
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let folder = Folder::new("--out", &self.out, &names)
            .overwrite(self.overwrite)
            .reuse(self.reuse);
        // Both integrators' series of every N in memory until the figures are drawn.
        Ok(step_study_plan(&scene, &counts, 2.0, folder))
    }
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, folder: Prepared) -> Result<(), AnyError> {
    let steps = cli.steps.counts();
    let scene = base(&cli)?;
    let (newmark_dir, run_newmark, out, reuse) =
        (cli.newmark_dir, cli.run_newmark, cli.out, cli.reuse);
    let t_end = scene.end_time_s;
    println!(
        "Figure 6.4: level {}, {} law, backward Euler vs Newmark, {} solver, N = {:?} on {}",
        scene.level,
        scene.state_law,
        scene.solver,
        steps,
        rsf_programs::machine()
    );
    let mut table = String::from(
        "integrator,steps,tau_s,wall_s,fpi_mean,fpi_max,first_slip_event_s,slip_events,recurrence_interval_s,peak_slip_rate_x0_mps,peak_slip_rate_mps,u_x0_min_last_tenth_m,u_x0_max_last_tenth_m\n",
    );
    println!(
        "{:>15} {:>8} {:>8} {:>6} {:>5} {:>10} {:>6} {:>9} {:>10} {:>10} {:>21}",
        "integrator",
        "N",
        "wall s",
        "FPI",
        "max",
        "1st slip",
        "events",
        "recur. s",
        "peak v(x0)",
        "peak V",
        "u(x0) on [0.9T,T] m"
    );
    // (N, backward Euler run, Newmark run if available)
    let mut runs: Vec<(usize, SliderRun, Option<SliderRun>)> = Vec::new();
    for &n in &steps {
        let be = SliderScene {
            steps: n,
            integrator: Integrator::BackwardEuler,
            ..scene.clone()
        };
        be.validate()?;
        let be_csv = out.join(format!("centre_backward_euler_N{n}.csv"));
        let run = if reuse {
            let wall = old_wall_time(
                &out.join("table.csv"),
                &["backward-euler", &n.to_string()],
                3,
            );
            SliderRun {
                seconds: wall,
                ..SliderRun::from_series(&PointSeries::<2>::read(&be_csv)?)
            }
        } else {
            SliderRun::record(&be, 0, Some((&be_csv, folder.mode())))?
        };
        report(&mut table, "backward-euler", &be, &run, t_end)?;
        let csv = newmark_dir.join(format!("centre_N{n}.csv"));
        let nm_scene = SliderScene {
            steps: n,
            integrator: Integrator::Newmark,
            ..scene.clone()
        };
        let newmark = if csv.exists() && !run_newmark {
            let r = SliderRun {
                seconds: f64::NAN,
                ..SliderRun::from_series(&PointSeries::<2>::read(&csv)?)
            };
            report(&mut table, "newmark (csv)", &nm_scene, &r, t_end)?;
            Some(r)
        } else if run_newmark || n <= 10_000 {
            let r = SliderRun::record(&nm_scene, 0, None)?;
            report(&mut table, "newmark", &nm_scene, &r, t_end)?;
            Some(r)
        } else {
            println!(
                "{:>15} {n:>8} (no {} — run fig6_2_6_3_centre first)",
                "newmark",
                csv.display()
            );
            None
        };
        runs.push((n, run, newmark));
    }
    rsf::checkpoint::write_atomically(&out.join("table.csv"), table.as_bytes())?;

    figures(&out, &runs, t_end, scene.level)?;
    println!("wrote {}", out.display());
    Ok(())
}

/// The two figures of the runs `(N, backward Euler, Newmark)`: the slip rate at x0 over
/// the last quarter and the displacement over the last tenth of `[0, t_end]`, a panel per N.
fn figures(
    out: &std::path::Path,
    runs: &[(usize, SliderRun, Option<SliderRun>)],
    t_end: f64,
    level: usize,
) -> Result<(), AnyError> {
    let labels: Vec<String> = runs
        .iter()
        .map(|(n, _, _)| format!("τ = T/{:.0e}", *n as f64))
        .collect();
    let abs = |r: &SliderRun| -> Vec<(f64, f64)> {
        r.v_x0
            .iter()
            .map(|&(t, v)| (t, v.abs().max(1e-40)))
            .collect()
    };
    let rates: Vec<Pair> = runs
        .iter()
        .map(|(_, b, nm)| (abs(b), nm.as_ref().map(abs)))
        .collect();
    let disps: Vec<Pair> = runs
        .iter()
        .map(|(_, b, nm)| (b.u_x0.clone(), nm.as_ref().map(|r| r.u_x0.clone())))
        .collect();
    let to_series = |pairs: &[Pair]| -> Vec<Panel> {
        pairs
            .iter()
            .map(|(b, nm)| {
                let mut v = vec![("backward Euler", b.clone())];
                if let Some(nm) = nm {
                    v.push(("Newmark", nm.clone()));
                }
                v
            })
            .collect()
    };
    for (name, data, columns, log_y, x_range, y_range, y_label) in [
        (
            "fig6_4_slip_rate.png",
            to_series(&rates),
            false,
            true,
            (0.75 * t_end, t_end),
            Some((1e-7, 1e-1)),
            "|v| (m/s)",
        ),
        (
            "fig6_4_displacement.png",
            to_series(&disps),
            true,
            false,
            (0.9 * t_end, t_end),
            None,
            "u_x (m)",
        ),
    ] {
        let series: Vec<Vec<Series<'_>>> = data.iter().map(|p| Series::labelled(p)).collect();
        let panels: Vec<(&str, &[Series<'_>])> = labels
            .iter()
            .zip(&series)
            .map(|(l, s)| (l.as_str(), &s[..]))
            .collect();
        let what = if log_y {
            "slip rate |v|"
        } else {
            "displacement u_x"
        };
        Series::panels(
            &out.join(name),
            &Labels {
                title: &format!(
                    "Fig. 6.4 (ours): {what} at x0, Dieterich, j = {}, backward Euler vs Newmark",
                    level
                ),
                x: "t (s)",
                y: y_label,
            },
            &panels,
            &PanelLayout {
                columns,
                log_y,
                x_range,
                y_range,
            },
        )?;
    }
    Ok(())
}

fn report(
    table: &mut String,
    name: &str,
    scene: &SliderScene,
    run: &SliderRun,
    t_end: f64,
) -> std::fmt::Result {
    let st = stats(run, t_end);
    let first = st.first_slip_event_s.unwrap_or(f64::NAN);
    let rec = st.recurrence_interval_s.unwrap_or(f64::NAN);
    let (ulo, uhi) = st.u_x0_range_last_tenth_m;
    println!(
        "{:>15} {:>8} {:>8.1} {:>6.2} {:>5} {:>10.3} {:>6} {:>9.3} {:>10.2e} {:>10.2e} {:>10.3e}…{:.3e}",
        name, scene.steps, run.seconds, st.fpi_mean, st.fpi_max, first, st.slip_events, rec,
        st.peak_slip_rate_x0_mps, st.peak_slip_rate_mps, ulo, uhi
    );
    writeln!(
        table,
        "{name},{},{:e},{:.2},{:.3},{},{first:.5},{},{rec:.5},{:.4e},{:.4e},{ulo:.5e},{uhi:.5e}",
        scene.steps,
        scene.tau(),
        run.seconds,
        st.fpi_mean,
        st.fpi_max,
        st.slip_events,
        st.peak_slip_rate_x0_mps,
        st.peak_slip_rate_mps
    )
}
