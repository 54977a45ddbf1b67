//! Figures 6.2 and 6.3 of Pipping, Sander & Kornhuber: displacement and slip rate at the
//! centre x0 = (2.5, 0) of the frictional boundary, Dieterich's law, j = 4, Newmark, for
//! the time steps τ = T/10⁴, T/10⁵ (default) and T/10⁶ (`--with-1e6`, hours).
//!
//! ```sh
//! cargo run --release --example fig6_2_6_3_centre                  # N = 1e4, 1e5 (15 min on a loaded 2-core box)
//! cargo run --release --example fig6_2_6_3_centre -- --with-1e6    # adds N = 1e6
//! cargo run --release --example fig6_2_6_3_centre -- --steps 10000 --solver tnnmg --law ruina
//! cargo run --release --example fig6_2_6_3_centre -- --reuse       # table + figures from the CSVs
//! ```
//!
//! Prints a table (per N: wall time, FPIs, first slip event, slip events, recurrence
//! interval, peak slip rates, displacement range at x0 over [0.9T, T]) and writes to
//! `out/fig6_2_6_3/` (or `--out DIR`): `centre_N{N}.csv` (a `rsf::observe::PointSeries`
//! at x0), `table.csv`, `fig6_2_displacement.png` (u_x(x0) over
//! [0.9T, T], one panel per τ, as the paper) and `fig6_3_slip_rate.png` (|v(x0)| over
//! [0.75T, T], log scale, one row per τ).

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use rsf::observe::PointSeries;
use rsf_programs::cli::StepCounts;
use rsf_programs::estimates::step_study_plan;
use rsf_programs::guard::{AnyError, Folder, Limits, Plan, Prepared, Program};
use rsf_programs::{
    old_wall_time, stats, Labels, PanelLayout, PaperFigures, Series, SliderArgs, SliderRun,
};
use rsf_scenes::SliderScene;

/// Figures 6.2/6.3: displacement and slip rate at x0 for several time steps.
#[derive(Parser)]
#[command(version)]
struct Cli {
    #[command(flatten)]
    slider: SliderArgs<PaperFigures>,
    #[command(flatten)]
    steps: StepCounts,
    /// Output folder.
    #[arg(long, default_value = "out/fig6_2_6_3")]
    out: PathBuf,
    /// Re-tabulate and re-plot the series of an earlier run in the output folder.
    #[arg(long)]
    reuse: bool,
    /// Replace the files of an earlier run in `--out` (without it, a folder holding any
    /// rsf program's run is refused and left untouched).
    #[arg(long)]
    overwrite: bool,
    #[command(flatten)]
    limits: Limits,
}

/// The scene of the flags (level 4, Newmark, the direct solver unless they say otherwise).
fn base(cli: &Cli) -> Result<SliderScene, AnyError> {
    cli.slider.scene()
}

impl Program for Cli {
    rsf_programs::name_and_limits!("fig6_2_6_3");

    fn plan(&self) -> Result<Plan, AnyError> {
        let scene = base(self)?;
        self.slider.steps_ignored("--steps")?;
        let counts = self.steps.counts();
        let mut names = vec![
            "table.csv".to_owned(),
            "fig6_2_displacement.png".to_owned(),
            "fig6_3_slip_rate.png".to_owned(),
        ];
        names.extend(counts.iter().map(|n| format!("centre_N{n}.csv")));
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let folder = Folder::new("--out", &self.out, &names)
            .overwrite(self.overwrite)
            .reuse(self.reuse);
        // Every run's series in memory until the figures are drawn; its file meanwhile.
        Ok(step_study_plan(&scene, &counts, 1.0, folder))
    }
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, folder: Prepared) -> Result<(), AnyError> {
    let steps = cli.steps.counts();
    let scene = base(&cli)?;
    let out = cli.out;
    let reuse = cli.reuse;
    let t_end = scene.end_time_s;
    println!(
        "Figures 6.2/6.3: level {}, {} law, Newmark, {} solver, N = {:?} on {}",
        scene.level,
        scene.state_law,
        scene.solver,
        steps,
        rsf_programs::machine()
    );
    let mut runs: Vec<(usize, SliderRun)> = Vec::new();
    let mut table = String::from(
        "steps,tau_s,wall_s,fpi_mean,fpi_max,first_slip_event_s,slip_events,recurrence_interval_s,peak_slip_rate_x0_mps,peak_slip_rate_mps,u_x0_min_last_tenth_m,u_x0_max_last_tenth_m\n",
    );
    println!(
        "{:>8} {:>9} {:>8} {:>6} {:>5} {:>10} {:>6} {:>10} {:>10} {:>10} {:>21}",
        "N",
        "τ (s)",
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
    for &n in &steps {
        let sc = SliderScene {
            steps: n,
            ..scene.clone()
        };
        sc.validate()?;
        let csv = out.join(format!("centre_N{n}.csv"));
        let run = if reuse {
            SliderRun {
                seconds: old_wall_time(&out.join("table.csv"), &[&n.to_string()], 2),
                ..SliderRun::from_series(&PointSeries::<2>::read(&csv)?)
            }
        } else {
            SliderRun::record(&sc, 0, Some((&csv, folder.mode())))?
        };
        let st = stats(&run, t_end);
        let first = st.first_slip_event_s.unwrap_or(f64::NAN);
        let rec = st.recurrence_interval_s.unwrap_or(f64::NAN);
        let (ulo, uhi) = st.u_x0_range_last_tenth_m;
        println!(
            "{:>8} {:>9.2e} {:>8.1} {:>6.2} {:>5} {:>10.3} {:>6} {:>10.3} {:>10.2e} {:>10.2e} {:>10.3e}…{:.3e}",
            n, sc.tau(), run.seconds, st.fpi_mean, st.fpi_max, first, st.slip_events, rec,
            st.peak_slip_rate_x0_mps, st.peak_slip_rate_mps, ulo, uhi
        );
        writeln!(
            table,
            "{n},{:e},{:.2},{:.3},{},{first:.5},{},{rec:.5},{:.4e},{:.4e},{ulo:.5e},{uhi:.5e}",
            sc.tau(),
            run.seconds,
            st.fpi_mean,
            st.fpi_max,
            st.slip_events,
            st.peak_slip_rate_x0_mps,
            st.peak_slip_rate_mps
        )?;
        runs.push((n, run));
    }
    rsf::checkpoint::write_atomically(&out.join("table.csv"), table.as_bytes())?;

    let labels: Vec<String> = runs
        .iter()
        .map(|(n, _)| format!("τ = T/{n:.0e}", n = *n as f64))
        .collect();
    let disp: Vec<Vec<(f64, f64)>> = runs.iter().map(|(_, r)| r.u_x0.clone()).collect();
    let rate: Vec<Vec<(f64, f64)>> = runs
        .iter()
        .map(|(_, r)| {
            r.v_x0
                .iter()
                .map(|&(t, v)| (t, v.abs().max(1e-40)))
                .collect()
        })
        .collect();
    let disp_series: Vec<[Series<'_>; 1]> = disp.iter().map(|p| Series::alone(p)).collect();
    let rate_series: Vec<[Series<'_>; 1]> = rate.iter().map(|p| Series::alone(p)).collect();
    let dp: Vec<(&str, &[Series<'_>])> = labels
        .iter()
        .zip(&disp_series)
        .map(|(l, s)| (l.as_str(), &s[..]))
        .collect();
    let rp: Vec<(&str, &[Series<'_>])> = labels
        .iter()
        .zip(&rate_series)
        .map(|(l, s)| (l.as_str(), &s[..]))
        .collect();
    Series::panels(
        &out.join("fig6_2_displacement.png"),
        &Labels {
            title: "Fig. 6.2 (ours): displacement u_x at x0 = (2.5, 0), Dieterich, j = 4, Newmark",
            x: "t (s)",
            y: "u_x (m)",
        },
        &dp,
        &PanelLayout {
            columns: true,
            log_y: false,
            x_range: (0.9 * t_end, t_end),
            y_range: None,
        },
    )?;
    Series::panels(
        &out.join("fig6_3_slip_rate.png"),
        &Labels {
            title: "Fig. 6.3 (ours): slip rate |v| at x0 = (2.5, 0), Dieterich, j = 4, Newmark",
            x: "t (s)",
            y: "|v| (m/s)",
        },
        &rp,
        &PanelLayout {
            columns: false,
            log_y: true,
            x_range: (0.75 * t_end, t_end),
            y_range: Some((1e-7, 1e-1)),
        },
    )?;
    println!("wrote {}", out.display());
    Ok(())
}
