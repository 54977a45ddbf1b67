//! Many seismic cycles of the paper's slider with adaptive time steps (issue 10,
//! docs/math.md §9): the scene of `pipping_slider` loaded for 200 s (the ramp keeps the
//! paper's 3.75 s), a few hundred slip events.
//!
//! ```sh
//! cargo run --release --example long_run                          # j = 4, 200 s, tolerance 1e-3
//! cargo run --release --example long_run -- --level 3 --end-time 50 --adaptive 1e-4
//! cargo run --release --example long_run -- --end-time 15 --reference-steps 1e5   # + fixed τ
//! ```
//!
//! Prints the event catalogue (onset, duration, peak slip rate, slip at x0 = (2.5, 0)) and
//! writes to `out/long_run/` (or `--out DIR`): `events.csv` (the catalogue), `steps.csv`
//! (t, τ, largest slip rate, fixed point iterations of every accepted step),
//! `recurrence.png` (time since the previous onset against the onset time),
//! `step_size.png` (τ over time), `max_slip_rate.png` and `summary.json`. With
//! `--reference-steps N` it also runs fixed τ = T_ref/N over the first `--compare-until`
//! seconds (default 15) and prints both catalogues side by side.
//!
//! A folder holding another run's files is refused before anything is computed
//! (`--overwrite` replaces them; docs/reliability.md); files are written atomically. The
//! catalogue is built in memory during the run, so there is no `--resume`. The per-step
//! record is bounded before the run (`--max-output-gb`, default 10): a run above it is
//! refused, or — adaptive steps without `--max-steps` — stopped at the step count that
//! fits, its files written up to there and the run ending with an error that says so.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use rsf::observe::{EventThresholds, SlipEvent, SlipEvents};
use rsf::run_folder::check_output_size;
use rsf::run_folder::until;
use rsf::{Flow, Observer, StepView, Termination};
use rsf_programs::cli::{for_flag, positive_number, step_count};
use rsf_programs::estimates::{slider_memory, slider_steps, slider_what, FIGURE_BYTES};
use rsf_programs::guard::{AnyError, Folder, Limits, Plan, Prepared, Program};
use rsf_programs::{
    describe_time_step, line_plot, Labels, PanelLayout, ProgramScene, Series, SliderArgs,
};
use rsf_scenes::step_cap;
use rsf_scenes::{SliderScene, TimeStep, SLIDER_CENTRE};

/// The scene of a long run: the paper's slider for 200 s with adaptive steps (tolerance
/// `DEFAULT_TOLERANCE`, no slip-rate floor) and a ramp of `RAMP_S`, unless the flags or the
/// scene file say otherwise.
#[derive(Debug, Clone, Copy)]
struct LongRun;

impl ProgramScene for LongRun {
    type Scene = SliderScene;

    fn base() -> SliderScene {
        SliderScene {
            end_time_s: 200.0,
            time_step: TimeStep::Adaptive(rsf_scenes::AdaptiveTimeStep {
                slip_rate_floor_mps: f64::INFINITY,
                ..rsf_scenes::AdaptiveTimeStep::new(DEFAULT_TOLERANCE)
            }),
            ramp_fraction: (RAMP_S / 200.0_f64).min(1.0),
            ..SliderScene::default()
        }
    }
}

/// The paper's slider for many cycles with adaptive time steps: event catalogue and plots.
#[derive(Parser)]
#[command(version)]
struct Cli {
    #[command(flatten)]
    slider: SliderArgs<LongRun>,
    /// Also run fixed τ = T_ref/N (T_ref = `--compare-until`) and compare the catalogues.
    #[arg(long, value_parser = step_count, value_name = "N")]
    reference_steps: Option<usize>,
    /// End of the comparison with the fixed-τ run (s).
    #[arg(long, default_value_t = 15.0, value_name = "T_REF", value_parser = positive_number)]
    compare_until: f64,
    /// Output folder.
    #[arg(long, default_value = "out/long_run")]
    out: PathBuf,
    /// Replace the files of an earlier run in the output folder.
    #[arg(long)]
    overwrite: bool,
    /// `--max-output-gb`: a run whose per-step record (`steps.csv`, and the rows held in
    /// memory until it is written) is estimated above it is refused; an adaptive run
    /// without `--max-steps` instead stops at the step count that fits.
    #[command(flatten)]
    limits: Limits,
    /// Stop after this many accepted steps: the files of the steps so far are written and
    /// the run ends with an error saying where it stopped.
    #[arg(long, value_name = "N")]
    max_steps: Option<u64>,
}

/// Bytes per accepted step, rounded up: its `steps.csv` row (≈ 50 bytes), the row held in
/// memory during the run (32 bytes) and in the file's text before the atomic write (≈ 50).
const STEP_BYTES: f64 = 150.0;

/// The files a run writes into its folder.
const OUTPUTS: [&str; 6] = [
    "events.csv",
    "steps.csv",
    "recurrence.png",
    "step_size.png",
    "max_slip_rate.png",
    "summary.json",
];

/// The paper's ramp duration (s): ¼ of its 15 s.
const RAMP_S: f64 = 3.75;
/// The tolerance when neither the scene nor the command line asks for adaptive steps.
/// These defaults leave out the slip test: it resolves the slip of the loading phase
/// (docs/work-precision.md) but multiplies the steps in the ringing after each event (j = 4,
/// 15 s: 24.6k steps instead of 8.7k) without moving the later event times closer to a
/// fixed-τ reference at N = 1e5; with `--adaptive` or a scene file the scene's defaults
/// apply.
const DEFAULT_TOLERANCE: f64 = 1e-3;

impl Cli {
    /// The scene of the flags ([`LongRun`]), its ramp `RAMP_S` long unless a flag or the
    /// scene file sets `ramp_fraction`.
    fn scene(&self) -> Result<SliderScene, AnyError> {
        let mut scene = self.slider.scene()?;
        if scene.ramp_fraction == LongRun::base().ramp_fraction {
            scene.ramp_fraction = (RAMP_S / scene.end_time_s).min(1.0);
        }
        self.slider.named(scene.validate())?;
        // The first step T/N of the adaptive steps below their smallest step (e.g.
        // `steps = 1e12`) would be refused by the controller only after the set-up.
        if let TimeStep::Adaptive(a) = scene.time_step {
            let first = scene.end_time_s / scene.steps as f64;
            if a.initial_tau_s.is_none() && first < a.tau_min_s {
                return Err(format!(
                    "--steps (or `steps` of --scene) {}: the first adaptive step T/N = {first:e} \
                     s is below tau_min_s = {:e} s (N only sets the first step)",
                    scene.steps, a.tau_min_s
                )
                .into());
            }
        }
        Ok(scene)
    }

    /// The step cap of the run (refused if even `--max-steps` does not fit).
    fn cap(&self, scene: &SliderScene) -> Result<Option<u64>, AnyError> {
        let cap = step_cap(scene, STEP_BYTES, self.max_steps, self.limits.max_output_gb);
        Ok(for_flag(
            "--max-steps",
            "max_steps",
            for_flag("--steps", "steps", cap),
        )?)
    }
}

impl Program for Cli {
    rsf_programs::name_and_limits!("long_run");

    fn plan(&self) -> Result<Plan, AnyError> {
        let scene = self.scene()?;
        // An output above the bound (or the cap where it fits).
        let cap = self.cap(&scene)?;
        let rows = slider_steps(&scene).min(cap.map_or(f64::INFINITY, |c| c as f64));
        let reference = self.reference_steps.map_or(0.0, |n| n as f64);
        if let Some(n) = self.reference_steps {
            for_flag(
                "--reference-steps",
                "reference_steps",
                check_output_size(
                    n as f64 * STEP_BYTES,
                    self.limits.max_output_gb,
                    "reference_steps",
                ),
            )?;
        }
        let what = slider_what(&scene);
        Ok(Plan::new()
            .memory(
                slider_memory(&scene) + rows.max(reference) * STEP_BYTES,
                "--level, --max-steps, --reference-steps",
                what.clone(),
            )
            .output(
                rows * 50.0 + 3.0 * FIGURE_BYTES,
                "--max-steps, --end-time",
                what,
            )
            .folder(Folder::new("--out", &self.out, &OUTPUTS).overwrite(self.overwrite)))
    }
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

/// Every accepted step: `(t, τ, max slip rate, fixed point iterations)`.
#[derive(Default)]
struct Steps(Vec<(f64, f64, f64, usize)>);

impl Observer<2> for Steps {
    fn observe(&mut self, s: &StepView<'_, 2>) -> rsf::Result<Flow> {
        let r = s.report;
        self.0
            .push((r.time, r.tau, r.max_slip_rate, r.fixed_point_iterations));
        Ok(Flow::Continue(()))
    }
}

/// The outcome of one run.
struct Outcome {
    events: Vec<SlipEvent>,
    steps: Steps,
    rejected: u64,
    seconds: f64,
    /// Step and time (s) where the step cap ended the run, if it did.
    stopped: Option<(usize, f64)>,
}

fn simulate(
    scene: &SliderScene,
    what: &str,
    cap: Option<u64>,
) -> Result<Outcome, Box<dyn std::error::Error>> {
    let mut sim = scene.build()?;
    let x0 = sim.model().nearest_node(&SLIDER_CENTRE)?;
    let mut events = SlipEvents::new(EventThresholds::default())?.slip_at(sim.model(), x0)?;
    let mut steps = Steps::default();
    let mut progress = scene.progress(0.0, what);
    let mut observers: Vec<&mut dyn Observer<2>> = vec![&mut events, &mut steps];
    observers.push(&mut progress);
    let summary = sim.run_until(until(scene.end_time_s, cap), &mut observers)?;
    drop(observers);
    let state = sim.state();
    Ok(Outcome {
        events: events.events().to_vec(),
        steps,
        rejected: sim.state().controller.map_or(0, |c| c.rejected()),
        seconds: summary.seconds,
        stopped: (summary.termination == Termination::StepCap).then_some((state.step, state.time)),
    })
}

fn run(cli: Cli, _prepared: Prepared) -> Result<(), AnyError> {
    // The output bound, the folder: checked by the guard before anything was computed.
    let scene = cli.scene()?;
    let cap = cli.cap(&scene)?;
    if let (Some(cap), None) = (cap, cli.max_steps) {
        println!(
            "at most {cap} steps (--max-output-gb {})",
            cli.limits.max_output_gb
        );
    }
    println!(
        "long_run: level {}, T = {} s, {}, {} law → {}",
        scene.level,
        scene.end_time_s,
        describe_time_step(&scene),
        scene.state_law,
        cli.out.display()
    );
    let cpu0 = rsf_programs::cpu_seconds();
    let main = simulate(&scene, "long run", cap)?;
    let cpu = rsf_programs::cpu_seconds() - cpu0;
    print_catalogue(&main.events);
    let recurrence = recurrence(&main.events);
    let (tau_min, tau_max) = main
        .steps
        .0
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), s| {
            (l.min(s.1), h.max(s.1))
        });
    println!(
        "{} events; {} accepted steps, {} rejected; τ in [{tau_min:.2e}, {tau_max:.2e}] s; \
         stepping {:.1} s wall, {cpu:.1} s CPU on {}",
        main.events.len(),
        main.steps.0.len(),
        main.rejected,
        main.seconds,
        rsf_programs::machine()
    );
    if !recurrence.is_empty() {
        let r: Vec<f64> = recurrence.iter().map(|p| p.1).collect();
        let mean = r.iter().sum::<f64>() / r.len() as f64;
        let (lo, hi) = r
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
        println!("recurrence: mean {mean:.3} s, range [{lo:.3}, {hi:.3}] s");
    }
    write_files(&cli.out, &main)?;
    let json = serde_json::json!({
        "scene": scene,
        "step_control": rsf_programs::step_control_json(&scene),
        "events": main.events.len(),
        "accepted_steps": main.steps.0.len(),
        "rejected_steps": main.rejected,
        "wall_time_s": main.seconds,
        "cpu_time_s": cpu,
        "machine": rsf_programs::machine(),
        "stopped_at_step_cap": main.stopped.map(|(step, t)| serde_json::json!({"step": step, "t_s": t})),
    });
    rsf::checkpoint::write_atomically(
        &cli.out.join("summary.json"),
        (serde_json::to_string_pretty(&json)? + "\n").as_bytes(),
    )?;
    if let Some((step, t)) = main.stopped {
        return Err(rsf::Error::StepCapReached {
            step_cap: step,
            step,
            time: t,
            end_time: scene.end_time_s,
            checkpoint: None,
        }
        .into());
    }

    if let Some(n) = cli.reference_steps {
        let t_ref = cli.compare_until.min(scene.end_time_s);
        let fixed = SliderScene {
            end_time_s: t_ref,
            steps: n,
            time_step: TimeStep::Fixed {},
            ramp_fraction: (RAMP_S / t_ref).min(1.0),
            ..scene.clone()
        };
        println!(
            "reference: fixed τ = {:.3e} s over [0, {t_ref}] s",
            fixed.tau()
        );
        let reference = simulate(&fixed, "reference", None)?;
        compare(&main.events, &reference.events, t_ref, reference.seconds);
    }
    Ok(())
}

fn print_catalogue(events: &[SlipEvent]) {
    println!(
        "{:>4} {:>11} {:>11} {:>12} {:>12}",
        "#", "onset (s)", "duration(s)", "peak V (m/s)", "slip x0 (m)"
    );
    for (i, e) in events.iter().enumerate() {
        println!(
            "{:>4} {:>11.5} {:>11.5} {:>12.4e} {:>12.4e}",
            i + 1,
            e.crossing_s,
            e.duration_s().unwrap_or(f64::NAN),
            e.peak_slip_rate,
            e.slip.unwrap_or(f64::NAN)
        );
    }
}

/// `(onset, time since the previous onset)` of every event after the first.
fn recurrence(events: &[SlipEvent]) -> Vec<(f64, f64)> {
    events
        .windows(2)
        .map(|w| (w[1].crossing_s, w[1].crossing_s - w[0].crossing_s))
        .collect()
}

fn write_files(dir: &Path, run: &Outcome) -> Result<(), Box<dyn std::error::Error>> {
    let mut f = String::new();
    writeln!(
        f,
        "onset_step,onset_s,crossing_s,duration_s,peak_slip_rate_mps,peak_s,slip_x0_m"
    )?;
    for e in &run.events {
        writeln!(
            f,
            "{},{:.10e},{:.10e},{:.6e},{:.6e},{:.10e},{:.6e}",
            e.onset_step,
            e.onset_s,
            e.crossing_s,
            e.duration_s().unwrap_or(f64::NAN),
            e.peak_slip_rate,
            e.peak_s,
            e.slip.unwrap_or(f64::NAN)
        )?;
    }
    rsf::checkpoint::write_atomically(&dir.join("events.csv"), f.as_bytes())?;
    let mut f = String::new();
    writeln!(f, "t_s,tau_s,max_slip_rate_mps,fpi")?;
    for &(t, tau, v, fpi) in &run.steps.0 {
        writeln!(f, "{t:.10e},{tau:.6e},{v:.6e},{fpi}")?;
    }
    rsf::checkpoint::write_atomically(&dir.join("steps.csv"), f.as_bytes())?;
    let rec = recurrence(&run.events);
    if !rec.is_empty() {
        line_plot(
            &dir.join("recurrence.png"),
            &Labels {
                title: "Time since the previous slip event",
                x: "onset t (s)",
                y: "recurrence (s)",
            },
            &Series::alone(&rec),
            false,
            false,
        )?;
    }
    let tau: Vec<(f64, f64)> = run.steps.0.iter().map(|s| (s.0, s.1)).collect();
    let rate: Vec<(f64, f64)> = run.steps.0.iter().map(|s| (s.0, s.2.max(1e-40))).collect();
    let t_end = run.steps.0.last().map_or(1.0, |s| s.0);
    // One file each: the panels of one figure would share the y range.
    for (file, title, points) in [
        ("step_size.png", "time step τ (s)", &tau),
        ("max_slip_rate.png", "largest slip rate on Γ_F (m/s)", &rate),
    ] {
        Series::panels(
            &dir.join(file),
            &Labels {
                title,
                x: "t (s)",
                y: "",
            },
            &[("", &Series::alone(points)[..])],
            &PanelLayout {
                columns: false,
                log_y: true,
                x_range: (0.0, t_end),
                y_range: None,
            },
        )?;
    }
    Ok(())
}

/// Prints the events of both runs up to `t_ref` side by side, with the differences.
fn compare(adaptive: &[SlipEvent], fixed: &[SlipEvent], t_ref: f64, seconds: f64) {
    let early: Vec<&SlipEvent> = adaptive.iter().filter(|e| e.onset_s <= t_ref).collect();
    println!(
        "reference: {} events over [0, {t_ref}] s in {seconds:.1} s wall; adaptive: {}",
        fixed.len(),
        early.len()
    );
    println!(
        "{:>4} {:>11} {:>11} {:>10} {:>12} {:>12} {:>9}",
        "#", "onset fixed", "onset adapt", "Δonset", "peak V fixed", "peak V adapt", "Δpeak"
    );
    for (i, (f, a)) in fixed.iter().zip(&early).enumerate() {
        println!(
            "{:>4} {:>11.5} {:>11.5} {:>10.2e} {:>12.4e} {:>12.4e} {:>8.1}%",
            i + 1,
            f.crossing_s,
            a.crossing_s,
            a.crossing_s - f.crossing_s,
            f.peak_slip_rate,
            a.peak_slip_rate,
            100.0 * (a.peak_slip_rate / f.peak_slip_rate - 1.0)
        );
    }
    let mean_rec = |e: &[&SlipEvent]| {
        (e.len() > 1).then(|| (e[e.len() - 1].crossing_s - e[0].crossing_s) / (e.len() - 1) as f64)
    };
    let fixed_refs: Vec<&SlipEvent> = fixed.iter().collect();
    println!(
        "mean recurrence over [0, {t_ref}] s: fixed {:?} s, adaptive {:?} s",
        mean_rec(&fixed_refs),
        mean_rec(&early)
    );
}
