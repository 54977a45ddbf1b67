//! Running the paper's slider scene with the observers the examples need.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use rsf::{
    Checkpoint, Checkpointer, FrictionalProfile, Observer, PointSeries, SliderScene, StepState,
    SLIDER_CENTRE,
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
    fn observe(&mut self, s: &StepState<'_, 2>) -> rsf::Result<rsf::Flow> {
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
        Ok(rsf::Flow::Continue(()))
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
    let x0 = sim.model().nearest_node(&SLIDER_CENTRE)?;
    {
        let fb = &sim.model().frictional;
        run.map.1 = fb
            .along
            .iter()
            .map(|&k| sim.model().vertices[fb.nodes[k]][0])
            .collect();
    }
    let remaining = scene.steps.saturating_sub(sim.step_index());
    let map_every = scene
        .steps
        .checked_div(opts.map_samples)
        .map_or(0, |k| k.max(1));
    let mut series = None;
    let mut profile = None;
    let mut checkpointer = None;
    if let Some(dir) = &opts.out_dir {
        std::fs::create_dir_all(dir)?;
        series = Some(
            PointSeries::create(&dir.join("timeseries.csv"), sim.model(), x0)?.flush_every(100),
        );
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
            ));
        }
    }
    run.seconds = run_in_chunks(remaining, "slider", opts.progress, |n| {
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
        sim.run(n, &mut observers).map(|_| ())
    })?;
    Ok(run)
}

/// Takes `remaining` steps in about 200 chunks through `run_k(k)`, advancing a progress bar
/// (when `progress` and stderr is a terminal); returns the wall time (s).
fn run_in_chunks(
    remaining: usize,
    label: &str,
    progress: bool,
    mut run_k: impl FnMut(usize) -> rsf::Result<()>,
) -> rsf::Result<f64> {
    let bar = if progress {
        crate::progress(remaining as u64, label)
    } else {
        None
    };
    let start = std::time::Instant::now();
    let chunk = (remaining / 200).max(1);
    let mut done = 0;
    while done < remaining {
        let k = chunk.min(remaining - done);
        run_k(k)?;
        done += k;
        if let Some(b) = &bar {
            b.set_position(done as u64);
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    Ok(start.elapsed().as_secs_f64())
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
    /// Slip events: upward crossings of 1e-3 m/s by the max slip rate on Γ_F, counting a
    /// new event only after the rate has fallen below 1e-4 m/s since the last one (so the
    /// elastic oscillations of one event are not counted twice).
    pub slip_events: usize,
    /// Mean time between the onsets of slip events (s).
    pub recurrence_interval_s: Option<f64>,
    /// Peak of the max slip rate on Γ_F (m/s).
    pub peak_slip_rate_mps: f64,
    /// Peak slip rate at x0 (m/s).
    pub peak_slip_rate_x0_mps: f64,
    /// Range of u_x(x0) over [0.9T, T] (m).
    pub u_x0_range_last_tenth_m: (f64, f64),
}

/// Onset threshold of a slip event (m/s), as in the issue.
const EVENT_ON: f64 = 1e-3;
/// The max slip rate must fall below this (m/s) before a new event can start.
const EVENT_OFF: f64 = 1e-4;

/// Onset times of slip events in `(t, max slip rate)`: upward crossings of [`EVENT_ON`],
/// re-armed only once the rate has fallen below [`EVENT_OFF`].
fn event_onsets(series: &[(f64, f64)]) -> Vec<f64> {
    let mut armed = series.first().is_none_or(|p| p.1 <= EVENT_ON);
    let mut onsets = Vec::new();
    for &(t, v) in series {
        if armed && v > EVENT_ON {
            onsets.push(t);
            armed = false;
        } else if v < EVENT_OFF {
            armed = true;
        }
    }
    onsets
}

/// Computes [`SliderStats`] (slip-event onset at 1e-3 m/s with re-arming below 1e-4 m/s).
pub fn stats(run: &SliderRun, end_time: f64) -> SliderStats {
    let events = event_onsets(&run.max_slip_rate);
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

impl SliderRun {
    /// Runs `scene` in phases with different time steps: phase `(n, until_s, map_every)`
    /// continues the previous phase's state (u, v, a, α) with τ = T/n up to the step
    /// nearest `until_s` (clamped to T), recording a row of the slip-rate map every
    /// `map_every` steps of that phase (0: none). Successive phases must be commensurate:
    /// the switching time must be a whole number of steps of the next τ.
    ///
    /// This is how the examples afford the paper's τ = T/10⁶ inside a short window: a
    /// coarse phase up to just before the window, then the fine τ through it. Newmark's
    /// state (u, v, a) does not depend on τ, so the switch is exact in the sense that the
    /// fine phase starts from the coarse trajectory at that time.
    ///
    /// # Errors
    /// Scene and solver errors; [`rsf::Error::Checkpoint`] if a switching time is not a
    /// whole number of the next phase's steps.
    pub fn run_phases(
        scene: &SliderScene,
        phases: &[(usize, f64, usize)],
        progress: bool,
    ) -> rsf::Result<SliderRun> {
        let mut run = SliderRun::default();
        let mut state: Option<Checkpoint> = None;
        let mut t_now = 0.0f64;
        let mut stepping = 0.0;
        for &(n, until_s, map_every) in phases {
            let mut sc = scene.clone();
            sc.steps = n;
            let t_setup = std::time::Instant::now();
            let mut sim = sc.build()?;
            run.setup_seconds += t_setup.elapsed().as_secs_f64();
            if run.dofs == 0 {
                run.dofs = sim.model().num_dofs();
                run.frictional_nodes = sim.model().frictional.len();
                let fb = &sim.model().frictional;
                run.map.1 = fb
                    .along
                    .iter()
                    .map(|&k| sim.model().vertices[fb.nodes[k]][0])
                    .collect();
            }
            let tau = sim.tau();
            if let Some(mut c) = state.take() {
                let step = (t_now / tau).round() as usize;
                if (step as f64 * tau - t_now).abs() > 1e-9 * tau.max(t_now) {
                    return Err(rsf::Error::Checkpoint(format!(
                        "switching time {t_now} s is not a multiple of τ = {tau} s"
                    )));
                }
                c.step = step;
                c.tau = tau;
                sim.restore(&c)?;
            }
            let target =
                ((until_s.min(scene.end_time_s) / tau).round() as usize).max(sim.step_index());
            let remaining = target - sim.step_index();
            let x0 = sim.model().nearest_node(&SLIDER_CENTRE)?;
            stepping += run_in_chunks(remaining, &format!("τ = T/{n}"), progress, |k| {
                let mut collector = Collector {
                    run: &mut run,
                    x0,
                    map_every,
                };
                sim.run(k, &mut [&mut collector]).map(|_| ())
            })?;
            t_now = sim.time();
            state = Some(sim.checkpoint());
        }
        run.seconds = stepping;
        Ok(run)
    }
}

impl crate::Series<'_> {
    /// Several plots in one PNG: side by side (`columns`) or stacked, one per
    /// `(panel title, series)`, sharing the x range `x_range` and (if given) the y range.
    /// With `log_y` the y values are plotted as log10. Long series are thinned to a
    /// min/max envelope per pixel column so that peaks survive and the file stays small.
    ///
    /// # Errors
    /// Drawing or file errors.
    pub fn panels(
        path: &Path,
        title: &str,
        x_label: &str,
        y_label: &str,
        panels: &[(&str, &[crate::Series<'_>])],
        columns: bool,
        log_y: bool,
        x_range: (f64, f64),
        y_range: Option<(f64, f64)>,
    ) -> Result<(), Box<dyn std::error::Error>> {
        use plotters::prelude::*;
        crate::init_fonts();
        let n = panels.len().max(1);
        let (w, h) = if columns {
            ((400 * n as u32 + 100).max(1000), 450)
        } else {
            (1000, 220 * n as u32 + 60)
        };
        let colors = [
            RGBColor(31, 119, 180),
            RGBColor(214, 39, 40),
            RGBColor(44, 160, 44),
            RGBColor(255, 127, 14),
        ];
        let ty = |v: f64| {
            if log_y {
                v.abs().max(1e-300).log10()
            } else {
                v
            }
        };
        let thinned: Vec<Vec<Vec<(f64, f64)>>> = panels
            .iter()
            .map(|(_, ss)| {
                ss.iter()
                    .map(|s| envelope(s.points, x_range, 1200, ty))
                    .collect()
            })
            .collect();
        let (y0, y1) = y_range.map_or_else(
            || {
                let (lo, hi) = thinned
                    .iter()
                    .flatten()
                    .flatten()
                    .filter(|p| p.1.is_finite())
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                        (l.min(p.1), h.max(p.1))
                    });
                if lo < hi {
                    (lo, hi)
                } else {
                    (lo - 1.0, lo + 1.0)
                }
            },
            |(a, b)| (ty(a), ty(b)),
        );
        let root = BitMapBackend::new(path, (w, h)).into_drawing_area();
        root.fill(&WHITE)?;
        let root = root.titled(title, ("sans-serif", 20))?;
        let areas = if columns {
            root.split_evenly((1, n))
        } else {
            root.split_evenly((n, 1))
        };
        for (i, ((name, ss), area)) in panels.iter().zip(&areas).enumerate() {
            let mut chart = ChartBuilder::on(area)
                .caption(*name, ("sans-serif", 16))
                .margin(8)
                .x_label_area_size(if columns || i + 1 == n { 40 } else { 25 })
                .y_label_area_size(70)
                .build_cartesian_2d(x_range.0..x_range.1, y0..y1)?;
            let yl = if log_y {
                format!("log10 {y_label}")
            } else {
                y_label.to_string()
            };
            chart
                .configure_mesh()
                .x_desc(if columns || i + 1 == n { x_label } else { "" })
                .y_desc(if columns && i > 0 { String::new() } else { yl })
                .x_labels(6)
                .y_labels(6)
                .label_style(("sans-serif", 13))
                .draw()?;
            for (k, s) in ss.iter().enumerate() {
                let color = colors[k % colors.len()];
                chart
                    .draw_series(LineSeries::new(
                        thinned[i][k].iter().copied(),
                        color.stroke_width(1),
                    ))?
                    .label(s.label)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
            }
            if ss.len() > 1 {
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.8))
                    .border_style(BLACK)
                    .label_font(("sans-serif", 13))
                    .draw()?;
            }
        }
        root.present()?;
        Ok(())
    }
}

/// Points of `points` inside `x_range`, y mapped by `ty`, thinned to the first, minimum,
/// maximum and last point of each of `bins` equal x bins (order kept).
fn envelope(
    points: &[(f64, f64)],
    x_range: (f64, f64),
    bins: usize,
    ty: impl Fn(f64) -> f64,
) -> Vec<(f64, f64)> {
    let inside: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.0 >= x_range.0 && p.0 <= x_range.1)
        .map(|p| (p.0, ty(p.1)))
        .collect();
    if inside.len() <= 4 * bins {
        return inside;
    }
    let width = (x_range.1 - x_range.0) / bins as f64;
    let mut out = Vec::with_capacity(4 * bins);
    let mut i = 0;
    while i < inside.len() {
        let b = ((inside[i].0 - x_range.0) / width).floor();
        let mut j = i;
        while j < inside.len() && ((inside[j].0 - x_range.0) / width).floor() == b {
            j += 1;
        }
        let bin = &inside[i..j];
        let (mut lo, mut hi) = (0, 0);
        for (k, p) in bin.iter().enumerate() {
            if p.1 < bin[lo].1 {
                lo = k;
            }
            if p.1 > bin[hi].1 {
                hi = k;
            }
        }
        let mut picks = [0, lo.min(hi), lo.max(hi), bin.len() - 1];
        picks.sort_unstable();
        let mut last = usize::MAX;
        for k in picks {
            if k != last {
                out.push(bin[k]);
                last = k;
            }
        }
        i = j;
    }
    out
}

/// Writes a run's series at x0 as CSV `t_s,u_x0_m,v_x0_mps,max_slip_rate_mps,fpi`, one row
/// per step.
///
/// # Errors
/// I/O errors.
pub fn write_series(path: &Path, run: &SliderRun) -> std::io::Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(f, "t_s,u_x0_m,v_x0_mps,max_slip_rate_mps,fpi")?;
    for i in 0..run.u_x0.len() {
        writeln!(
            f,
            "{:.9e},{:.12e},{:.12e},{:.12e},{}",
            run.u_x0[i].0, run.u_x0[i].1, run.v_x0[i].1, run.max_slip_rate[i].1, run.fpi[i]
        )?;
    }
    f.flush()
}

/// Reads a series written by [`write_series`] (wall time: `wall_s`).
///
/// # Errors
/// I/O and parse errors.
pub fn read_series(path: &Path, wall_s: f64) -> Result<SliderRun, Box<dyn std::error::Error>> {
    let text = std::fs::read_to_string(path)?;
    let mut run = SliderRun {
        seconds: wall_s,
        ..SliderRun::default()
    };
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != 5 {
            return Err(format!("{}: malformed line `{line}`", path.display()).into());
        }
        let t: f64 = f[0].parse()?;
        run.u_x0.push((t, f[1].parse()?));
        run.v_x0.push((t, f[2].parse()?));
        run.max_slip_rate.push((t, f[3].parse()?));
        run.fpi.push(f[4].parse()?);
    }
    Ok(run)
}

/// Wall time of the row of an earlier `table.csv` whose first `key.len()` fields are
/// `key` (wall time in column `col`); NaN if there is none.
pub fn old_wall_time(table: &Path, key: &[&str], col: usize) -> f64 {
    std::fs::read_to_string(table)
        .ok()
        .and_then(|text| {
            text.lines().find_map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                (f.len() > col && f[..key.len()] == *key).then(|| f[col].parse().ok())?
            })
        })
        .unwrap_or(f64::NAN)
}

#[cfg(test)]
mod tests {
    use super::event_onsets;

    #[test]
    fn ringing_within_an_event_is_one_event() {
        let series: Vec<(f64, f64)> = [1e-6, 2e-3, 5e-4, 3e-3, 1e-3, 5e-5, 4e-3, 1e-6]
            .iter()
            .enumerate()
            .map(|(i, &v)| (i as f64, v))
            .collect();
        assert_eq!(event_onsets(&series), vec![1.0, 6.0]);
        // A series that starts above the threshold does not count its start as an onset.
        assert_eq!(event_onsets(&series[3..]), vec![6.0]);
    }
}
