//! Figure 6.5 of Pipping, Sander & Kornhuber: the slip rate along the frictional boundary
//! Γ_F during the first slip event, t ∈ [0.6725T, 0.6775T], Dieterich's law, j = 4,
//! Newmark, with the paper's τ = T/10⁶ inside the window.
//!
//! ```sh
//! cargo run --release --example fig6_5_slip_event                     # τ = T/1e4 to 0.66T, then T/1e6 (2–5 min)
//! cargo run --release --example fig6_5_slip_event -- --coarse 100000  # T/1e5 before the switch
//! cargo run --release --example fig6_5_slip_event -- --straight       # T/1e6 from t = 0, as the paper (~1 h)
//! cargo run --release --example fig6_5_slip_event -- --fine 100000 --switch 0.6 --window 0.66,0.70
//! ```
//!
//! By default the run takes the coarse step τ = T/`--coarse` up to `--switch`·T (0.66T,
//! well before the event) and continues from that state with τ = T/`--fine` (10⁶) through
//! the window; `--straight` uses τ = T/`--fine` from t = 0 as the paper did. Prints the
//! event's numbers (onset, nucleation point, extent of the slipping region, peak slip
//! rate) and writes to `out/fig6_5/` (or `--out DIR`): `slip_rate_map.csv` (a
//! `rsf::observe::FrictionalProfile` over the window), `table.csv`, `fig6_5_slip_event.png` (linear
//! colour 0 … 1e-2 m/s as in the paper). The time step changes between the phases through
//! `Simulation::set_time_step`.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use plotters::prelude::*;
use rsf::observe::{Every, FaultRecorder, FrictionalProfile, Interval, Progress, Recorder};
use rsf::{Observer, Until};
use rsf_programs::cli::{step_count, window};
use rsf_programs::estimates::{slider_fault_nodes, slider_memory};
use rsf_programs::estimates::{FIGURE_BYTES, RECORDED_STEP_BYTES};
use rsf_programs::guard::{in_range, AnyError, Folder, Limits, Plan, Prepared, Program};
use rsf_programs::{PaperFigures, SliderArgs, SliderRun};
use rsf_scenes::{SliderScene, SLIDER_CENTRE};

/// Figure 6.5: the slip rate along Γ_F during the first slip event.
#[derive(Parser)]
#[command(version)]
struct Cli {
    #[command(flatten)]
    slider: SliderArgs<PaperFigures>,
    /// Steps N of the coarse τ = T/N before the switch (`1e4` accepted).
    #[arg(long, value_parser = step_count, default_value = "10000")]
    coarse: usize,
    /// Steps N of the fine τ = T/N from the switch on.
    #[arg(long, value_parser = step_count, default_value = "1000000")]
    fine: usize,
    /// Switch from the coarse to the fine τ at this fraction of T.
    #[arg(
        long,
        default_value_t = 0.66,
        value_name = "FRACTION",
        allow_negative_numbers = true
    )]
    switch: f64,
    /// Window F0,F1 as fractions of T.
    #[arg(long, value_parser = window, default_value = "0.6725,0.6775", value_name = "F0,F1")]
    window: (f64, f64),
    /// The fine τ from t = 0, as the paper (~1 h).
    #[arg(long)]
    straight: bool,
    /// Rows (time samples) of the map.
    #[arg(long, default_value_t = 500)]
    rows: usize,
    /// Output folder.
    #[arg(long, default_value = "out/fig6_5")]
    out: PathBuf,
    /// Replace the files of an earlier run in the output folder (without it, a folder
    /// holding any rsf program's run is refused and left untouched).
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
    rsf_programs::name_and_limits!("fig6_5");

    fn plan(&self) -> Result<Plan, AnyError> {
        let scene = base(self)?;
        self.slider.steps_ignored("--coarse and --fine")?;
        let (f0, f1) = self.window;
        if !(f0 >= 0.0 && f1 <= 1.0) {
            return Err(format!("--window {f0},{f1}: fractions of T inside [0, 1]").into());
        }
        if !self.straight {
            in_range(
                "--switch",
                self.switch,
                (0.0, f0),
                "a fraction of T before the window",
            )?;
        }
        in_range(
            "--rows",
            self.rows as f64,
            (1.0, 1e6),
            "time samples of the map",
        )?;
        // Every step's record in memory; the map's rows on Γ_F in memory and in the file.
        let before = if self.straight { 0.0 } else { self.switch };
        let steps = before * self.coarse as f64 + (f1 - before) * self.fine as f64 + 2.0;
        let nodes = slider_fault_nodes(scene.level);
        let window_steps = (f1 - f0) * self.fine as f64;
        let map_rows = (self.rows as f64).min(window_steps) + 1.0;
        let memory = slider_memory(&scene) + steps * RECORDED_STEP_BYTES + map_rows * nodes * 8.0;
        let output = map_rows * nodes * rsf::run_folder::PROFILE_ROW_BYTES + FIGURE_BYTES;
        let what = format!(
            "{steps:.3e} steps at level {} and a map of {map_rows:.3e} rows",
            scene.level
        );
        Ok(Plan::new()
            .memory(memory, "--level, --coarse, --fine, --rows", what.clone())
            .output(output, "--rows, --level", what)
            .folder(
                Folder::new(
                    "--out",
                    &self.out,
                    &["slip_rate_map.csv", "table.csv", "fig6_5_slip_event.png"],
                )
                .overwrite(self.overwrite),
            ))
    }
}

/// Slip rate marking the slipping region (m/s), as the issue's slip-event threshold.
const SLIPPING: f64 = 1e-3;

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, folder: Prepared) -> Result<(), AnyError> {
    let (coarse, fine, switch, (f0, f1)) = (cli.coarse, cli.fine, cli.switch, cli.window);
    let mut scene = base(&cli)?;
    let t_end = scene.end_time_s;
    let (t0, t1) = (f0 * t_end, f1 * t_end);
    let window_steps = ((t1 - t0) / (t_end / fine as f64)).round() as usize;
    let map_every = (window_steps / cli.rows.max(1)).max(1);
    // Phases (N of τ = T/N, end time, Γ_F snapshot interval); τ changes between them.
    let mut phases = Vec::new();
    if !cli.straight {
        if !(switch * t_end < t0) {
            return Err("--switch must come before the window".into());
        }
        phases.push((coarse, switch * t_end, 0));
    }
    phases.push((fine, t0, 0));
    phases.push((fine, t1, map_every));
    scene.steps = phases[0].0;
    scene.validate()?;
    let out = cli.out;
    let how = if cli.straight {
        format!("τ = T/{fine} from t = 0")
    } else {
        format!("τ = T/{coarse} up to {switch}T, then T/{fine}")
    };
    println!(
        "Figure 6.5: level {}, {} law, Newmark, {} solver, {how}; window [{f0}T, {f1}T] = [{t0:.4}, {t1:.4}] s; on {}",
        scene.level,
        scene.state_law,
        scene.solver,
        rsf_programs::machine()
    );
    let setup = std::time::Instant::now();
    let mut sim = scene.build()?;
    let mut run = SliderRun {
        setup_seconds: setup.elapsed().as_secs_f64(),
        ..SliderRun::default()
    };
    let x0 = sim.model().nearest_node(&SLIDER_CENTRE)?;
    let mut profile = Every::new(
        Interval::Steps(map_every.max(1)),
        FrictionalProfile::new(&out.join("slip_rate_map.csv"), (t0, t1), folder.mode())?,
    )?;
    for &(n, until, every) in &phases {
        sim.set_time_step(t_end / n as f64)?;
        let mut rec = Recorder::new(sim.model(), &[x0])?;
        let mut fault = Every::new(
            Interval::Steps(every.max(1)),
            FaultRecorder::new(sim.model()),
        )?;
        let steps = ((until - sim.time()) * n as f64 / t_end).round().max(0.0) as usize;
        let mut progress = Progress::steps(steps, &format!("τ = T/{n}"));
        let mut observers: Vec<&mut dyn Observer<2>> = vec![&mut rec, &mut progress];
        if every > 0 {
            observers.push(&mut fault);
            observers.push(&mut profile);
        }
        run.seconds += sim.run_until(Until::Time(until), &mut observers)?.seconds;
        run.extend_from_recorder(&rec, sim.model());
        run.extend_map(&fault.inner, sim.model());
    }
    let (times, xs, values) = &run.map;

    // The event: onset, extent of the slipping region, peak slip rate (when, where).
    let EventFacts {
        onset,
        slipped: (xmin_all, xmax_all),
        peak: (peak, peak_t, peak_x),
    } = event_facts(times, xs, values);
    // The front: the space–time connected set of slipping cells grown from the onset.
    let front = onset.map(|(it, k)| connected(values, it, k));
    let x_lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let x_hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let fpi_window: Vec<usize> = run
        .u_x0
        .iter()
        .zip(&run.fpi)
        .filter(|(p, _)| p.0 > t0)
        .map(|(_, &f)| f)
        .collect();
    let fpi_mean = fpi_window.iter().sum::<usize>() as f64 / fpi_window.len().max(1) as f64;
    let fpi_max = fpi_window.iter().copied().max().unwrap_or(0);
    println!(
        "{} dofs, {} steps in {:.1} s (set-up {:.2} s); window: {} steps, FPI mean {fpi_mean:.2}, max {fpi_max}",
        run.dofs,
        run.fpi.len(),
        run.seconds,
        run.setup_seconds,
        fpi_window.len()
    );
    let mut table = String::from("quantity,value\n");
    let mut row = |name: &str, value: String| {
        println!("  {name:<44} {value}");
        writeln!(table, "{name},\"{value}\"").expect("string write");
    };
    row("run", how.clone());
    row("window (s)", format!("{t0:.4} … {t1:.4}"));
    match (onset, front) {
        (Some((it, k)), Some((kmin, kmax, it_last))) => {
            let t = times[it];
            row(
                "onset: first slip rate > 1e-3 m/s (s)",
                format!("{t:.5} ({:.5} T)", t / t_end),
            );
            row("nucleation point x (m)", format!("{:.3}", xs[k]));
            row(
                "front (> 1e-3 m/s; connected) x range (m)",
                format!("{:.3} … {:.3} (Γ_F: {x_lo} … {x_hi})", xs[kmin], xs[kmax]),
            );
            row(
                "front: last time above 1e-3 m/s (s)",
                format!("{:.5}", times[it_last]),
            );
            row(
                "front arrested before both ends",
                format!("{}", kmin > 0 && kmax + 1 < xs.len()),
            );
            row(
                "any node > 1e-3 m/s: x range (m)",
                format!("{xmin_all:.3} … {xmax_all:.3}"),
            );
        }
        _ => row("onset", "no slip rate above 1e-3 m/s in the window".into()),
    }
    row(
        "peak slip rate (m/s)",
        format!("{peak:.3e} at t = {peak_t:.5} s, x = {peak_x:.3} m"),
    );
    row(
        "FPI in window (mean / max)",
        format!("{fpi_mean:.2} / {fpi_max}"),
    );
    row("wall time (s)", format!("{:.1}", run.seconds));
    rsf::checkpoint::write_atomically(&out.join("table.csv"), table.as_bytes())?;

    draw_map(
        &out.join("fig6_5_slip_event.png"),
        &format!(
            "Fig. 6.5 (ours): slip rate on Γ_F, j = {}, {how}",
            scene.level
        ),
        times,
        xs,
        values,
        (t0, t1),
        1e-2,
    )?;
    println!("wrote {}", out.display());
    Ok(())
}

/// What the slip-rate map `values` (rows at `times`, nodes at `xs`) says of the event.
struct EventFacts {
    /// The first (row, node) above [`SLIPPING`]: the node of the largest rate in that row.
    onset: Option<(usize, usize)>,
    /// The x range of every node ever above [`SLIPPING`] (m).
    slipped: (f64, f64),
    /// The peak slip rate (m/s), its time (s) and its x (m).
    peak: (f64, f64, f64),
}

fn event_facts(times: &[f64], xs: &[f64], values: &[Vec<f64>]) -> EventFacts {
    let mut onset = None;
    let (mut xmin_all, mut xmax_all) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut peak, mut peak_t, mut peak_x) = (0.0f64, f64::NAN, f64::NAN);
    for (it, (t, row)) in times.iter().zip(values).enumerate() {
        for (x, &v) in xs.iter().zip(row) {
            if v > SLIPPING {
                xmin_all = xmin_all.min(*x);
                xmax_all = xmax_all.max(*x);
                if onset.is_none() {
                    let k = row
                        .iter()
                        .enumerate()
                        .fold(0, |b, (k, &w)| if w > row[b] { k } else { b });
                    onset = Some((it, k));
                }
            }
            if v > peak {
                (peak, peak_t, peak_x) = (v, *t, *x);
            }
        }
    }
    EventFacts {
        onset,
        slipped: (xmin_all, xmax_all),
        peak: (peak, peak_t, peak_x),
    }
}

/// The cells (row, node) above [`SLIPPING`] connected to `(it, k)` through row or node
/// neighbours: their node range and last row.
fn connected(values: &[Vec<f64>], it: usize, k: usize) -> (usize, usize, usize) {
    let (nt, nx) = (values.len(), values[0].len());
    let mut seen = vec![false; nt * nx];
    let mut stack = vec![(it, k)];
    seen[it * nx + k] = true;
    let (mut kmin, mut kmax, mut last) = (k, k, it);
    while let Some((i, j)) = stack.pop() {
        kmin = kmin.min(j);
        kmax = kmax.max(j);
        last = last.max(i);
        let mut visit = |a: usize, b: usize| {
            if values[a][b] > SLIPPING && !seen[a * nx + b] {
                seen[a * nx + b] = true;
                stack.push((a, b));
            }
        };
        if i > 0 {
            visit(i - 1, j);
        }
        if i + 1 < nt {
            visit(i + 1, j);
        }
        if j > 0 {
            visit(i, j - 1);
        }
        if j + 1 < nx {
            visit(i, j + 1);
        }
    }
    (kmin, kmax, last)
}

/// Space–time map of the slip rate, linear colour from 0 (white/blue) to `vmax` (red),
/// with a colour bar, as the paper's Figure 6.5.
#[expect(
    clippy::too_many_arguments,
    reason = "a figure: the file, its title, the map's axes and values and the colour scale"
)]
fn draw_map(
    path: &std::path::Path,
    title: &str,
    times: &[f64],
    xs: &[f64],
    values: &[Vec<f64>],
    (t0, t1): (f64, f64),
    vmax: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    rsf_programs::init_fonts();
    let colour = |v: f64| {
        let s = (v / vmax).clamp(0.0, 1.0);
        HSLColor((1.0 - s) * 0.66, 0.9, 0.5)
    };
    rsf_programs::draw_png(path, (900, 600), |root| {
        root.fill(&WHITE)?;
        let (main, bar) = root.split_horizontally(780);
        let mut chart = ChartBuilder::on(&main)
            .caption(title, ("sans-serif", 16))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..5.0, t0..t1)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("horizontal coordinate (m)")
            .y_desc("time (s)")
            .y_label_formatter(&|t| format!("{t:.4}"))
            .label_style(("sans-serif", 14))
            .draw()?;
        chart.draw_series((0..times.len()).flat_map(|it| {
            (0..xs.len()).map(move |ix| {
                let (ta, tb) = rsf_programs::cell_bounds(times, it);
                let (xa, xb) = rsf_programs::cell_bounds(xs, ix);
                Rectangle::new([(xa, ta), (xb, tb)], colour(values[it][ix]).filled())
            })
        }))?;
        let mut cb = ChartBuilder::on(&bar)
            .margin_top(40)
            .margin_bottom(57)
            .margin_right(50)
            .y_label_area_size(0)
            .right_y_label_area_size(50)
            .build_cartesian_2d(0.0..1.0, 0.0..vmax)?;
        cb.configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_labels(6)
            .y_label_formatter(&|v| format!("{v:.3}"))
            .y_desc("m/s")
            .label_style(("sans-serif", 12))
            .draw()?;
        let n = 100;
        cb.draw_series((0..n).map(|k| {
            let a = vmax * k as f64 / n as f64;
            let b = vmax * (k + 1) as f64 / n as f64;
            Rectangle::new([(0.0, a), (1.0, b)], colour(0.5 * (a + b)).filled())
        }))?;
        Ok(())
    })
}
