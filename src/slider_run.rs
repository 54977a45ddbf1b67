//! Running the paper's slider scene with the observers the examples need.

use std::path::{Path, PathBuf};

use rsf::{
    nearest_vertex, Checkpoint, Checkpointer, FrictionalProfile, Observer, PointSeries,
    SliderScene, StepState, SLIDER_CENTRE,
};

/// What to record besides the always-kept series at x0.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Output folder for CSV files (`timeseries.csv`, `frictional_profile.csv`); none: no files.
    pub out_dir: Option<PathBuf>,
    /// Window `[t0, t1]` (s) of the frictional-boundary profile.
    pub profile_window: Option<(f64, f64)>,
    /// Number of time samples of the space–time slip-rate map (0: none).
    pub map_samples: usize,
    /// Checkpoint every this many steps into `out_dir/checkpoint.bin` (0: never).
    pub checkpoint_every: usize,
    /// Resume from this checkpoint.
    pub resume: Option<PathBuf>,
    /// Show a progress bar (only when stderr is a terminal).
    pub progress: bool,
}

/// Everything a run produced, in memory.
#[derive(Debug, Clone, Default)]
pub struct SliderRun {
    /// Degrees of freedom.
    pub dofs: usize,
    /// Frictional nodes.
    pub frictional_nodes: usize,
    /// `(t, u_x(x0))`.
    pub u_x0: Vec<(f64, f64)>,
    /// `(t, v_x(x0))`.
    pub v_x0: Vec<(f64, f64)>,
    /// `(t, max_p |v_p|)` on Γ_F.
    pub max_slip_rate: Vec<(f64, f64)>,
    /// Fixed point iterations per step.
    pub fpi: Vec<usize>,
    /// Velocity-solver iterations per step.
    pub solver_iterations: Vec<usize>,
    /// Steps that used the damped relaxation.
    pub relaxed_steps: usize,
    /// Space–time map: sample times, positions along Γ_F, slip rates.
    pub map: (Vec<f64>, Vec<f64>, Vec<Vec<f64>>),
    /// Wall time of the stepping (s).
    pub seconds: f64,
    /// Wall time of assembly and set-up (s).
    pub setup_seconds: f64,
}

struct Collector<'a> {
    run: &'a mut SliderRun,
    x0: usize,
    map_every: usize,
}

impl Observer<2> for Collector<'_> {
    fn observe(&mut self, s: &StepState<'_, 2>) -> rsf::Result<()> {
        let r = s.report;
        self.run.u_x0.push((r.time, s.kinematics.u[2 * self.x0]));
        self.run.v_x0.push((r.time, s.kinematics.v[2 * self.x0]));
        self.run.max_slip_rate.push((r.time, r.max_slip_rate));
        self.run.fpi.push(r.fixed_point_iterations);
        self.run.solver_iterations.push(r.solver_iterations);
        self.run.relaxed_steps += usize::from(r.relaxed_iterations > 0);
        if self.map_every > 0 && r.step % self.map_every == 0 {
            let fb = &s.model.frictional;
            let row = fb
                .along
                .iter()
                .map(|&k| {
                    let p = fb.nodes[k];
                    s.kinematics.v[2 * p].hypot(s.kinematics.v[2 * p + 1])
                })
                .collect();
            self.run.map.0.push(r.time);
            self.run.map.2.push(row);
        }
        Ok(())
    }
}

/// Builds and runs `scene` for all its steps (or from a checkpoint to the end).
///
/// # Errors
/// Scene, solver and I/O errors.
pub fn run_slider(scene: &SliderScene, opts: &RunOptions) -> rsf::Result<SliderRun> {
    let t_setup = std::time::Instant::now();
    let mut sim = scene.build()?;
    let mut run = SliderRun {
        dofs: sim.model().num_dofs(),
        frictional_nodes: sim.model().frictional.len(),
        setup_seconds: t_setup.elapsed().as_secs_f64(),
        ..Default::default()
    };
    if let Some(path) = &opts.resume {
        sim.restore(&Checkpoint::read(path)?)?;
    }
    let x0 = nearest_vertex(&sim.model().vertices, &SLIDER_CENTRE);
    {
        let fb = &sim.model().frictional;
        run.map.1 = fb
            .along
            .iter()
            .map(|&k| sim.model().vertices[fb.nodes[k]][0])
            .collect();
    }
    let remaining = scene.steps.saturating_sub(sim.step_index());
    let map_every = scene.steps.checked_div(opts.map_samples).map_or(0, |k| k.max(1));
    let mut series = None;
    let mut profile = None;
    let mut checkpointer = None;
    if let Some(dir) = &opts.out_dir {
        std::fs::create_dir_all(dir)?;
        series = Some(PointSeries::create(&dir.join("timeseries.csv"), x0)?.flush_every(100));
        if let Some((t0, t1)) = opts.profile_window {
            profile = Some(FrictionalProfile::create(
                &dir.join("frictional_profile.csv"),
                t0,
                t1,
                1,
            )?);
        }
        if opts.checkpoint_every > 0 {
            checkpointer = Some(Checkpointer::new(
                dir.join("checkpoint.bin"),
                opts.checkpoint_every,
                scene.tau(),
            ));
        }
    }
    let bar = if opts.progress {
        crate::progress(remaining as u64, "slider")
    } else {
        None
    };
    let start = std::time::Instant::now();
    let chunk = (remaining / 200).max(1);
    let mut done = 0;
    while done < remaining {
        let n = chunk.min(remaining - done);
        let mut collector = Collector {
            run: &mut run,
            x0,
            map_every,
        };
        let mut observers: Vec<&mut dyn Observer<2>> = vec![&mut collector];
        if let Some(s) = series.as_mut() {
            observers.push(s);
        }
        if let Some(p) = profile.as_mut() {
            observers.push(p);
        }
        if let Some(c) = checkpointer.as_mut() {
            observers.push(c);
        }
        sim.run(n, &mut observers)?;
        done += n;
        if let Some(b) = &bar {
            b.set_position(done as u64);
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    run.seconds = start.elapsed().as_secs_f64();
    Ok(run)
}

/// Statistics of a run in the units of the paper.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SliderStats {
    /// Mean fixed point iterations per step.
    pub fpi_mean: f64,
    /// Maximum fixed point iterations of a step.
    pub fpi_max: usize,
    /// Total velocity-solver iterations.
    pub solver_iterations: usize,
    /// Steps that needed the damped relaxation.
    pub relaxed_steps: usize,
    /// First time with max slip rate > 1e-3 m/s (s).
    pub first_slip_event_s: Option<f64>,
    /// Upward crossings of 1e-3 m/s by the max slip rate.
    pub slip_events: usize,
    /// Mean time between slip events (s).
    pub recurrence_interval_s: Option<f64>,
    /// Peak of the max slip rate on Γ_F (m/s).
    pub peak_slip_rate_mps: f64,
    /// Peak slip rate at x0 (m/s).
    pub peak_slip_rate_x0_mps: f64,
    /// Range of u_x(x0) over [0.9T, T] (m).
    pub u_x0_range_last_tenth_m: (f64, f64),
}

/// Computes [`SliderStats`] (slip-event threshold 1e-3 m/s, as in the issue).
pub fn stats(run: &SliderRun, end_time: f64) -> SliderStats {
    let events = crate::upcrossings(&run.max_slip_rate, 1e-3);
    let recurrence = (events.len() >= 2)
        .then(|| (events[events.len() - 1] - events[0]) / (events.len() - 1) as f64);
    let last: Vec<f64> = run
        .u_x0
        .iter()
        .filter(|p| p.0 >= 0.9 * end_time)
        .map(|p| p.1)
        .collect();
    let range = last
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    SliderStats {
        fpi_mean: run.fpi.iter().sum::<usize>() as f64 / run.fpi.len().max(1) as f64,
        fpi_max: run.fpi.iter().copied().max().unwrap_or(0),
        solver_iterations: run.solver_iterations.iter().sum(),
        relaxed_steps: run.relaxed_steps,
        first_slip_event_s: events.first().copied(),
        slip_events: events.len(),
        recurrence_interval_s: recurrence,
        peak_slip_rate_mps: run.max_slip_rate.iter().map(|p| p.1).fold(0.0, f64::max),
        peak_slip_rate_x0_mps: run.v_x0.iter().map(|p| p.1.abs()).fold(0.0, f64::max),
        u_x0_range_last_tenth_m: range,
    }
}

/// Writes `summary.json` with the scene, the sizes, timings and statistics.
///
/// # Errors
/// I/O errors.
pub fn write_summary(
    dir: &Path,
    scene: &SliderScene,
    run: &SliderRun,
    stats: &SliderStats,
) -> std::io::Result<()> {
    let json = serde_json::json!({
        "scene": scene,
        "dofs": run.dofs,
        "frictional_nodes": run.frictional_nodes,
        "steps": run.fpi.len(),
        "wall_time_s": run.seconds,
        "setup_time_s": run.setup_seconds,
        "machine": machine(),
        "stats": stats,
    });
    std::fs::write(
        dir.join("summary.json"),
        serde_json::to_string_pretty(&json)? + "\n",
    )
}

/// A one-line description of this machine (CPU model and core count).
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    format!("{cpu}, {cores} cores")
}
