//! What the figures and tables of a slider run need: plot-ready series built from the
//! library's records (a [`Recorder`], or [`PointSeries`](rsf::observe::PointSeries) /
//! [`FrictionalProfile`](rsf::observe::FrictionalProfile) files read back), their statistics (slip
//! events by the library's [`EventDetector`]) and `summary.json`.

use std::path::Path;

use rsf::observe::{
    EventDetector, EventThresholds, Every, FaultRecorder, FileMode, Interval, ProfileRow, Recorder,
    SeriesRow,
};
use rsf::Observer;
use rsf_scenes::SliderScene;

/// Plot-ready series of a slider run at x0 and on Γ_F.
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
    /// Steps that used a damped fixed point step.
    pub relaxed_steps: usize,
    /// Space–time map: sample times, positions along Γ_F, slip rates (one row per time).
    pub map: (Vec<f64>, Vec<f64>, Vec<Vec<f64>>),
    /// Wall time of the stepping (s).
    pub seconds: f64,
    /// Wall time of assembly and set-up (s).
    pub setup_seconds: f64,
    /// Rejected step attempts of adaptive time steps (0 for fixed steps).
    pub rejected_steps: u64,
}

impl SliderRun {
    /// Runs `scene` to its end time with a progress bar, recording x0 every step and Γ_F
    /// every `map_every` steps (0: never); with `series_csv`, also writes the
    /// [`PointSeries`](rsf::observe::PointSeries) at x0 there (new, or replacing an earlier
    /// run's with [`FileMode::Overwrite`]).
    ///
    /// # Errors
    /// Scene, solver and I/O errors.
    pub fn record(
        scene: &SliderScene,
        map_every: usize,
        series_csv: Option<(&Path, FileMode)>,
    ) -> rsf::Result<Self> {
        let setup = std::time::Instant::now();
        let mut sim = scene.build()?;
        let x0 = sim.model().nearest_node(&rsf_scenes::SLIDER_CENTRE)?;
        let mut rec = Recorder::new(sim.model(), &[x0])?;
        let mut fault = Every::new(
            Interval::Steps(map_every.max(1)),
            FaultRecorder::new(sim.model()),
        )?;
        let mut series = match series_csv {
            Some((path, mode)) => {
                Some(rsf::observe::PointSeries::new(path, sim.model(), x0, mode)?)
            }
            None => None,
        };
        let mut progress = scene.progress(0.0, &format!("τ = T/{}", scene.steps));
        let setup_seconds = setup.elapsed().as_secs_f64();
        let mut observers: Vec<&mut dyn Observer<2>> = vec![&mut rec, &mut progress];
        if map_every > 0 {
            observers.push(&mut fault);
        }
        if let Some(s) = series.as_mut() {
            observers.push(s);
        }
        let summary = sim.run_until(rsf::Until::Time(scene.end_time_s), &mut observers)?;
        let mut run = Self {
            seconds: summary.seconds,
            setup_seconds,
            rejected_steps: sim.state().controller.map_or(0, |c| c.rejected()),
            ..Self::default()
        };
        run.extend_from_recorder(&rec, sim.model());
        run.extend_map(&fault.inner, sim.model());
        Ok(run)
    }

    /// Appends the steps of `rec` (point 0 = x0).
    pub fn extend_from_recorder(&mut self, rec: &Recorder<2>, model: &rsf::Model<2>) {
        self.dofs = model.num_dofs();
        self.frictional_nodes = model.frictional_boundary.len();
        for ((r, u), v) in rec
            .reports()
            .iter()
            .zip(rec.displacement(0))
            .zip(rec.velocity(0))
        {
            self.u_x0.push((r.time, u[0]));
            self.v_x0.push((r.time, v[0]));
            self.max_slip_rate.push((r.time, r.max_slip_rate));
            self.fpi.push(r.fixed_point_iterations);
            self.solver_iterations.push(r.solver_iterations);
            self.relaxed_steps += usize::from(r.relaxed_iterations > 0);
        }
    }

    /// Appends the Γ_F snapshots of `rec` as rows of the space–time map.
    pub fn extend_map(&mut self, rec: &FaultRecorder<2>, model: &rsf::Model<2>) {
        if self.map.1.is_empty() {
            self.map.1 = rec
                .fault_nodes()
                .iter()
                .map(|&p| model.vertices[p][0])
                .collect();
        }
        for i in 0..rec.snapshots() {
            let (_, t) = rec.snapshot_time(i).expect("snapshot in range");
            self.map.0.push(t);
            self.map.2.push(rec.slip_rates(i).to_vec());
        }
    }

    /// The series of a [`PointSeries`](rsf::observe::PointSeries) file at x0, read back.
    pub fn from_series(rows: &[SeriesRow<2>]) -> Self {
        let mut run = Self::default();
        for r in rows {
            run.u_x0.push((r.time, r.u[0]));
            run.v_x0.push((r.time, r.v[0]));
            run.max_slip_rate.push((r.time, r.max_slip_rate));
            run.fpi.push(r.fixed_point_iterations);
            run.solver_iterations.push(r.solver_iterations);
            run.relaxed_steps += usize::from(r.relaxed_iterations > 0);
        }
        run
    }

    /// The map from the rows of a [`FrictionalProfile`](rsf::observe::FrictionalProfile) file (one
    /// block of rows per recorded step, nodes along Γ_F).
    pub fn set_map_from_profile(&mut self, rows: &[ProfileRow<2>]) {
        self.map = Default::default();
        for r in rows {
            if self.map.0.last() != Some(&r.time) || self.map.2.is_empty() {
                self.map.0.push(r.time);
                self.map.2.push(Vec::new());
            }
            let row = self.map.2.last_mut().expect("pushed above");
            if self.map.0.len() == 1 {
                self.map.1.push(r.position[0]);
            }
            row.push(r.slip_rate);
        }
    }
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
    /// Steps that needed a damped fixed point step.
    pub relaxed_steps: usize,
    /// "First slip" (s): the time `t_n` of the first **step** whose largest slip rate on
    /// Γ_F exceeds the onset threshold 1e-3 m/s ([`EventThresholds::default`]), i.e.
    /// [`SlipEvent::onset_s`](rsf::observe::SlipEvent::onset_s) of the first event of the library's
    /// [`EventDetector`] — not the interpolated crossing of the threshold
    /// ([`SlipEvent::crossing_s`](rsf::observe::SlipEvent::crossing_s), up to one step earlier).
    /// `None` without an event. Written to `summary.json` as `stats.first_slip_event_s`.
    pub first_slip_event_s: Option<f64>,
    /// Slip events: the largest slip rate on Γ_F rises above 1e-3 m/s; an event ends when
    /// it has fallen below 1e-4 m/s ([`EventThresholds::default`], so the elastic ringing
    /// of one event is not counted twice).
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

/// Computes [`SliderStats`] of a run over [0, `end_time`]: the slip events (first slip,
/// count, recurrence) by the library's [`EventDetector`] with the default thresholds fed
/// every step's largest slip rate on Γ_F (the definitions are those of [`SliderStats`]).
pub fn stats(run: &SliderRun, end_time: f64) -> SliderStats {
    let mut events =
        EventDetector::new(EventThresholds::default()).expect("the default thresholds are valid");
    for (k, &(t, v)) in run.max_slip_rate.iter().enumerate() {
        events.push(k + 1, t, v, &[]);
    }
    let range = run
        .u_x0
        .iter()
        .filter(|p| p.0 >= 0.9 * end_time)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
            (l.min(p.1), h.max(p.1))
        });
    SliderStats {
        fpi_mean: run.fpi.iter().sum::<usize>() as f64 / run.fpi.len().max(1) as f64,
        fpi_max: run.fpi.iter().copied().max().unwrap_or(0),
        solver_iterations: run.solver_iterations.iter().sum(),
        relaxed_steps: run.relaxed_steps,
        first_slip_event_s: events.events().first().map(|e| e.onset_s),
        slip_events: events.events().len(),
        recurrence_interval_s: events.recurrence_interval_s(),
        peak_slip_rate_mps: run.max_slip_rate.iter().map(|p| p.1).fold(0.0, f64::max),
        peak_slip_rate_x0_mps: run.v_x0.iter().map(|p| p.1.abs()).fold(0.0, f64::max),
        u_x0_range_last_tenth_m: range,
    }
}

/// The resolved step control of an adaptive scene for `summary.json` (the tolerances the
/// controller used, defaults such as the displacement and state scales applied), or
/// `null` for fixed steps or an invalid scene.
pub fn step_control_json(scene: &SliderScene) -> serde_json::Value {
    match scene.step_control() {
        Ok(Some(c)) => serde_json::json!({
            "tolerance": c.tolerance,
            "displacement_atol_m": c.displacement_atol,
            "state_atol_s": c.state_atol,
            "safety": c.safety,
            "min_factor": c.min_factor,
            "max_factor": c.max_factor,
            "tau_min_s": c.tau_min,
            "tau_max_s": c.tau_max,
            "state_change_cap": c.state_change_cap,
            "slip_rate_floor_mps": c.slip_rate_floor,
            "state_extrapolation": c.state_extrapolation,
        }),
        _ => serde_json::Value::Null,
    }
}

/// Writes `summary.json` with the scene, the resolved step control
/// ([`step_control_json`]), the sizes, timings and statistics.
///
/// The file is replaced atomically ([`rsf::checkpoint::write_atomically`]): a failure leaves the
/// previous `summary.json` intact. `run.seconds` is the wall time of the stepping over
/// the whole run (across resumes, see [`rsf::Checkpoint::wall_time_s`]).
///
/// # Errors
/// [`rsf::Error::File`] naming the file.
pub fn write_summary(
    dir: &Path,
    scene: &SliderScene,
    run: &SliderRun,
    stats: &SliderStats,
) -> rsf::Result<()> {
    let json = serde_json::json!({
        "scene": scene,
        "step_control": step_control_json(scene),
        "dofs": run.dofs,
        "frictional_nodes": run.frictional_nodes,
        "steps": run.fpi.len(),
        "accepted_steps": run.fpi.len(),
        "rejected_steps": run.rejected_steps,
        "wall_time_s": run.seconds,
        "setup_time_s": run.setup_seconds,
        "machine": machine(),
        "stats": stats,
    });
    let text = serde_json::to_string_pretty(&json).expect("a JSON value serialises") + "\n";
    rsf::checkpoint::write_atomically(&dir.join("summary.json"), text.as_bytes())
}

/// User + system CPU time of this process so far (s), all threads, from the operating
/// system's process clock (`cpu-time`: `CLOCK_PROCESS_CPUTIME_ID` on Linux, nanosecond
/// resolution; the 10 ms ticks of `/proc/self/stat` used before made runs of a few
/// hundredths of a second unmeasurable); 0 where unavailable.
pub fn cpu_seconds() -> f64 {
    cpu_time::ProcessTime::try_now().map_or(0.0, |t| t.as_duration().as_secs_f64())
}

/// Least-squares slope of `ln y` against `ln x` over the points `(x, y)` (both positive):
/// the exponent `p` of a fit `y ≈ c xᵖ`, as the scaling tables quote it (docs/scaling.md).
/// NaN for fewer than two distinct `x`.
pub fn fit_exponent(xy: &[(f64, f64)]) -> f64 {
    let k = xy.len() as f64;
    let (mx, my) = xy.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + x.ln() / k, b + y.ln() / k)
    });
    let (num, den) = xy.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x.ln() - mx) * (y.ln() - my), b + (x.ln() - mx).powi(2))
    });
    num / den
}

/// The exponents ([`fit_exponent`]) of each of the `K` columns `ys` of `rows` (`(x, ys)`)
/// against `x`: `p[k]` of a fit `ys[k] ≈ c xᵖ`, in the columns' order. NaN for fewer than
/// two distinct `x`.
pub fn fit_exponents<const K: usize>(rows: &[(f64, [f64; K])]) -> [f64; K] {
    std::array::from_fn(|k| {
        let xy: Vec<(f64, f64)> = rows.iter().map(|(x, ys)| (*x, ys[k])).collect();
        fit_exponent(&xy)
    })
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

/// Wall time of the row of an earlier `table.csv` whose first `key.len()` fields are
/// `key` (wall time in column `col`); NaN if there is none.
pub fn old_wall_time(table: &Path, key: &[&str], col: usize) -> f64 {
    let Ok(mut reader) = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .quoting(false)
        .from_path(table)
    else {
        return f64::NAN;
    };
    reader
        .records()
        .map_while(std::result::Result::ok)
        .find_map(|f| {
            let keyed = f.len() >= key.len() && f.iter().zip(key).all(|(a, b)| a == *b);
            (f.len() > col && keyed).then(|| f[col].parse().ok())?
        })
        .unwrap_or(f64::NAN)
}

#[cfg(test)]
mod tests {
    /// `summary.json` names the tolerances the controller used: null for fixed steps, the
    /// defaults resolved (absolute tolerances from the displacement and state scales)
    /// for adaptive ones.
    #[test]
    fn summary_records_the_resolved_step_control() {
        use rsf_scenes::{AdaptiveTimeStep, SliderScene, TimeStep};
        let fixed = SliderScene::default();
        assert!(super::step_control_json(&fixed).is_null());
        let adaptive = SliderScene {
            time_step: TimeStep::Adaptive(AdaptiveTimeStep::new(1e-3)),
            ..SliderScene::default()
        };
        let j = super::step_control_json(&adaptive);
        let theta_s = adaptive.l_m / adaptive.loading_velocity_m_per_s;
        assert_eq!(j["tolerance"], 1e-3);
        assert_eq!(j["state_atol_s"], 1e-3 * theta_s);
        assert_eq!(j["displacement_atol_m"], 1e-3 * adaptive.l_m);
    }
}
