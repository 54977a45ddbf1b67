//! How much of the main job's event ringing is reflection: the paper's slider (§6.1,
//! Table 6.1) run twice, once with the block's ends x = 0 and x = 5 m traction-free (the
//! paper's scene) and once absorbing (`SliderScene::absorbing_sides`: Lysmer–Kuhlemeyer
//! dashpots of impedance ρc_p normal and ρc_s tangential, as if the block went on in x).
//!
//! ```sh
//! cargo run --release --example slider_absorbing                  # j = 3, N = 1e4, T = 15 s
//! cargo run --release --example slider_absorbing -- --level 4 --window 10,11
//! ```
//!
//! Every step records the slip rate at x0 = (2.5, 0), the largest slip rate on Γ_F and the
//! kinetic energy ½vᵀMv of the body (J per metre of thickness). Prints, per run, the
//! events (max V ≥ 1e-3 m/s), the peak slip rate and the kinetic energy left in the body
//! after the first event (its mean from 0.1 to 0.6 s after the event's end, against its
//! peak during the event). Writes to `out/slider_absorbing/` (or
//! `--out DIR`): `series.csv` (both runs, one row per step), `slip_rate_x0.png` and
//! `kinetic_energy.png` over `--window` (default: from 0.05 s before the first event to
//! 1 s after it).

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use rsf::observe::StepView;
use rsf::{Flow, Observer, Until};
use rsf_programs::cli::window;
use rsf_programs::estimates::FIGURE_BYTES;
use rsf_programs::estimates::{csv_row_bytes, slider_memory, slider_steps, slider_what};
use rsf_programs::guard::{AnyError, Folder, Limits, Plan, Prepared, Program};
use rsf_programs::{line_plot, Labels, PaperSliderAt, Series, SliderArgs};
use rsf_scenes::{SliderScene, SLIDER_CENTRE};

/// The paper's slider with traction-free and with absorbing ends.
#[derive(Parser)]
#[command(version)]
struct Cli {
    #[command(flatten)]
    slider: SliderArgs<PaperSliderAt<3>>,
    /// Figure window T0,T1 (s) [default: around the first event].
    #[arg(long, value_parser = window, value_name = "T0,T1", allow_hyphen_values = true)]
    window: Option<(f64, f64)>,
    /// Output folder.
    #[arg(long, default_value = "out/slider_absorbing")]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out` (without it, a folder holding any
    /// rsf program's run is refused and left untouched). The two runs keep their rows in
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

/// Bytes of a `series.csv` row (7 numbers of 24 characters).
const ROW_BYTES: f64 = 170.0;

impl Program for Cli {
    rsf_programs::name_and_limits!("slider_absorbing");

    fn plan(&self) -> Result<Plan, AnyError> {
        let scene = base(self)?;
        if let Some((w0, w1)) = self.window {
            if !(w0.is_finite() && w1.is_finite()) {
                return Err(format!("--window {w0},{w1}: must be finite").into());
            }
        }
        let steps = slider_steps(&scene);
        // Two runs' rows in memory (4 numbers each) and the CSV's text before it is written.
        let memory = 2.0 * slider_memory(&scene) + steps * (2.0 * 32.0 + ROW_BYTES);
        let output = steps * csv_row_bytes(7) + 2.0 * FIGURE_BYTES;
        let what = slider_what(&scene);
        Ok(Plan::new()
            .memory(memory, "--level, --steps (or --scene)", what.clone())
            .output(output, "--steps, --end-time (or --scene)", what)
            .folder(
                Folder::new(
                    "--out",
                    &self.out,
                    &["series.csv", "slip_rate_x0.png", "kinetic_energy.png"],
                )
                .overwrite(self.overwrite),
            ))
    }
}

/// Slip rate of an event (m/s), as the main job's event definition.
const SLIPPING: f64 = 1e-3;

/// One row per step: time (s), slip rate at x0, max slip rate on Γ_F (m/s), kinetic
/// energy (J/m).
#[derive(Default)]
struct Samples {
    x0: usize,
    rows: Vec<[f64; 4]>,
}

impl Observer<2> for Samples {
    fn observe(&mut self, s: &StepView<'_, 2, 2>) -> rsf::Result<Flow> {
        let v = &s.state.kinematics.v;
        let max_v = (0..s.model.frictional_boundary.len())
            .map(|k| s.slip_rate(k))
            .fold(0.0, f64::max);
        let x0 = s.model.frictional_boundary.fault_index(self.x0);
        let v_x0 = x0.map_or(f64::NAN, |k| s.slip_rate(k));
        let kinetic = s.model.kinetic_energy(v)?;
        self.rows.push([s.state.time, v_x0, max_v, kinetic]);
        Ok(Flow::Continue(()))
    }
}

/// The events of a run: `(start, end)` (s) of each stretch with max V ≥ [`SLIPPING`].
fn events(rows: &[[f64; 4]]) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    let mut start = None;
    for r in rows {
        match (start, r[2] >= SLIPPING) {
            (None, true) => start = Some(r[0]),
            (Some(t0), false) => {
                out.push((t0, r[0]));
                start = None;
            }
            _ => {}
        }
    }
    out
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, _folder: Prepared) -> Result<(), AnyError> {
    let base = base(&cli)?;
    println!(
        "slider, level {}, N = {}, T = {} s, {} law, {}: traction-free and absorbing ends; on {}",
        base.level,
        base.steps,
        base.end_time_s,
        base.state_law,
        base.integrator,
        rsf_programs::machine()
    );
    let mut runs = Vec::new();
    for (name, absorbing) in [("traction-free ends", false), ("absorbing ends", true)] {
        let scene = SliderScene {
            absorbing_sides: absorbing,
            ..base.clone()
        };
        scene.validate()?;
        let mut sim = scene.build()?;
        let mut samples = Samples {
            x0: sim.model().nearest_node(&SLIDER_CENTRE)?,
            ..Samples::default()
        };
        let clock = std::time::Instant::now();
        sim.run_until(Until::Time(scene.end_time_s), &mut [&mut samples])?;
        let seconds = clock.elapsed().as_secs_f64();
        let ev = events(&samples.rows);
        let peak = samples.rows.iter().map(|r| r[2]).fold(0.0, f64::max);
        println!(
            "{name}: {} steps in {seconds:.1} s; {} events at {} s; peak slip rate {peak:.4e} m/s",
            samples.rows.len(),
            ev.len(),
            ev.iter()
                .map(|e| format!("{:.4}", e.0))
                .collect::<Vec<_>>()
                .join(", ")
        );
        if let Some(&(t0, t1)) = ev.first() {
            let during = samples
                .rows
                .iter()
                .filter(|r| r[0] >= t0 && r[0] <= t1)
                .map(|r| r[3])
                .fold(0.0, f64::max);
            let after: Vec<f64> = samples
                .rows
                .iter()
                .filter(|r| r[0] >= t1 + 0.1 && r[0] <= t1 + 0.6)
                .map(|r| r[3])
                .collect();
            let mean_after = after.iter().sum::<f64>() / after.len().max(1) as f64;
            println!(
                "  first event {t0:.4} … {t1:.4} s ({:.1} ms above {SLIPPING} m/s); kinetic energy: peak {during:.4e} J/m, mean from 0.1 to 0.6 s after the event {mean_after:.4e} J/m = {:.3e} of the peak",
                1e3 * (t1 - t0),
                mean_after / during
            );
        }
        runs.push((name, samples.rows, ev));
    }

    let mut csv = String::from(
        "t_s,free_v_x0_m_per_s,free_max_v_m_per_s,free_kinetic_j_per_m,absorbing_v_x0_m_per_s,absorbing_max_v_m_per_s,absorbing_kinetic_j_per_m\n",
    );
    for (a, b) in runs[0].1.iter().zip(&runs[1].1) {
        writeln!(
            csv,
            "{:.17e},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e}",
            a[0], a[1], a[2], a[3], b[1], b[2], b[3]
        )?;
    }
    rsf::checkpoint::write_atomically(&cli.out.join("series.csv"), csv.as_bytes())?;

    let onset = runs[0].2.first().map_or(0.0, |e| e.0);
    let (w0, w1) = cli.window.unwrap_or((onset - 0.05, onset + 1.0));
    let pick = |rows: &[[f64; 4]], col: usize| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| r[0] >= w0 && r[0] <= w1)
            .map(|r| (r[0], r[col].max(1e-40)))
            .collect()
    };
    for (file, col, title, y) in [
        (
            "slip_rate_x0.png",
            1,
            "Slip rate at x0 = (2.5, 0): traction-free against absorbing ends",
            "slip rate (m/s)",
        ),
        (
            "kinetic_energy.png",
            3,
            "Kinetic energy of the block: traction-free against absorbing ends",
            "kinetic energy (J/m)",
        ),
    ] {
        let (a, b) = (pick(&runs[0].1, col), pick(&runs[1].1, col));
        line_plot(
            &cli.out.join(file),
            &Labels {
                title,
                x: "t (s)",
                y,
            },
            &[
                Series {
                    label: runs[0].0,
                    points: &a,
                },
                Series {
                    label: runs[1].0,
                    points: &b,
                },
            ],
            true,
            false,
        )?;
    }
    println!("wrote {}", cli.out.display());
    Ok(())
}
