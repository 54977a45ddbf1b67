//! The fault ODE's integrators (issue 84): the error of the event times and of the peak
//! slip rate against a tight-tolerance reference, against CPU time, from the run folders
//! of `seas_bp1` and `seas_bp5` (docs/work-precision.md, "The fault ODE's integrators").
//!
//! A run folder is named `PROBLEM_INTEGRATOR_TOLERANCE` (e.g. `fe2_rkc_1e-5`) and holds
//! the program's `summary.json`; each problem's reference is its `dormand-prince` run of
//! the smallest tolerance.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use rsf_programs::{Labels, PanelLayout, Series};

use crate::common::{log, Res};

/// A panel: its title and one line per integrator, `(log10 CPU s, log10 error)`.
type Panel = (String, BTreeMap<String, Vec<(f64, f64)>>);

/// What a run's `summary.json` says (BP1's or BP5's names).
struct Run {
    integrator: String,
    tolerance: f64,
    /// Event (rupture) start times (s, as the file's years × 1).
    events: Vec<f64>,
    /// The largest peak slip rate of the finished events (m/s).
    peak: f64,
    cpu_s: f64,
    steps: f64,
    evaluations: f64,
}

fn read(dir: &Path) -> Res<Option<(String, Run)>> {
    let name = dir.file_name().and_then(|n| n.to_str()).unwrap_or("");
    let parts: Vec<&str> = name.splitn(3, '_').collect();
    let path = dir.join("summary.json");
    if parts.len() != 3 || !path.exists() {
        return Ok(None);
    }
    let Ok(tolerance) = parts[2].parse::<f64>() else {
        return Ok(None);
    };
    let j: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path)?)?;
    let list = |key: &str| -> Vec<f64> {
        j[key]
            .as_array()
            .map(|a| a.iter().filter_map(serde_json::Value::as_f64).collect())
            .unwrap_or_default()
    };
    let (events, peak) = if j.get("peak_time_years").is_some() {
        // BP6: no events; the time of the fault's peak slip rate stands for them.
        (
            vec![j["peak_time_years"].as_f64().unwrap_or(f64::NAN)],
            j["peak_slip_rate_mps"].as_f64().unwrap_or(f64::NAN),
        )
    } else if j.get("rupture_start_years").is_some() {
        let peaks = list("peak_slip_rates_mps");
        (
            list("rupture_start_years"),
            peaks.iter().copied().fold(0.0, f64::max),
        )
    } else {
        (
            list("event_start_years"),
            j["peak_slip_rate_mps"].as_f64().unwrap_or(f64::NAN),
        )
    };
    let num = |key: &str| j[key].as_f64().unwrap_or(f64::NAN);
    // BP5's `cpu_time_s` includes the set-up, whose CPU time its log (`DIR.log`, the
    // program's output) states as `set-up: wall W s, CPU C s`: the run's is the rest.
    let setup_cpu = std::fs::read_to_string(format!("{}.log", dir.display()))
        .ok()
        .and_then(|log| {
            log.lines()
                .find_map(|l| l.strip_prefix("set-up: wall "))
                .and_then(|l| l.split("CPU ").nth(1))
                .and_then(|c| c.trim_end_matches(" s").trim().parse::<f64>().ok())
        })
        .unwrap_or(0.0);
    Ok(Some((
        parts[0].to_owned(),
        Run {
            integrator: parts[1].to_owned(),
            tolerance,
            events,
            peak,
            cpu_s: num("cpu_time_s") - setup_cpu,
            steps: num("accepted_steps"),
            evaluations: num("rate_evaluations"),
        },
    )))
}

/// The largest relative error of the event times after the first one (BP5's first
/// rupture is at t = 0) over the events both runs have, and how many they share.
fn event_error(run: &[f64], reference: &[f64]) -> (f64, usize) {
    let n = run.len().min(reference.len());
    let e = (0..n)
        .filter(|&k| reference[k] > 1e-6)
        .map(|k| ((run[k] - reference[k]) / reference[k]).abs())
        .fold(0.0, f64::max);
    (e, n)
}

/// One row of `integrators.csv`: a run's counts and its errors against its problem's
/// reference.
struct Row {
    integrator: String,
    tolerance: f64,
    steps: f64,
    evaluations: f64,
    cpu_s: f64,
    events: usize,
    event_error: f64,
    peak_error: f64,
}

const CSV_HEADER: &str =
    "problem,integrator,tolerance,steps,evaluations,cpu_s,events,event_time_error,peak_slip_rate_error";

/// The rows of an existing `integrators.csv` by problem (none if there is no file).
fn read_csv(path: &Path) -> Res<BTreeMap<String, Vec<Row>>> {
    let mut rows: BTreeMap<String, Vec<Row>> = BTreeMap::new();
    let Ok(text) = std::fs::read_to_string(path) else {
        return Ok(rows);
    };
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let f: Vec<&str> = line.split(',').collect();
        let num = |k: usize| -> Res<f64> {
            f.get(k)
                .and_then(|v| v.parse::<f64>().ok())
                .ok_or_else(|| format!("{}: bad line `{line}`", path.display()).into())
        };
        rows.entry(f[0].to_string()).or_default().push(Row {
            integrator: f.get(1).copied().unwrap_or("").to_string(),
            tolerance: num(2)?,
            steps: num(3)?,
            evaluations: num(4)?,
            cpu_s: num(5)?,
            events: num(6)? as usize,
            event_error: num(7)?,
            peak_error: num(8)?,
        });
    }
    Ok(rows)
}

/// Reads every run under `runs`, writes `integrators.csv` to `out` and
/// `work_precision_integrators.png` to `figures`. The rows of an existing
/// `out/integrators.csv` whose problem has no run under `runs` are kept (a study of one
/// problem adds its rows to the others').
pub(crate) fn integrator_study(runs: &Path, out: &Path, figures: &Path) -> Res<()> {
    let mut problems: BTreeMap<String, Vec<Run>> = BTreeMap::new();
    for entry in std::fs::read_dir(runs)? {
        if let Some((problem, run)) = read(&entry?.path())? {
            problems.entry(problem).or_default().push(run);
        }
    }
    if problems.is_empty() {
        return Err(format!(
            "--runs {}: no run folder PROBLEM_INTEGRATOR_TOL",
            runs.display()
        )
        .into());
    }
    let mut table = read_csv(&out.join("integrators.csv"))?;
    table.retain(|problem, _| !problems.contains_key(problem));
    for (problem, runs) in &mut problems {
        runs.sort_by(|a, b| {
            (&a.integrator, a.tolerance)
                .partial_cmp(&(&b.integrator, b.tolerance))
                .unwrap()
        });
        let Some(reference) = runs
            .iter()
            .filter(|r| r.integrator == "dormand-prince")
            .min_by(|a, b| a.tolerance.total_cmp(&b.tolerance))
        else {
            log(&format!("{problem}: no dormand-prince reference, skipped"));
            continue;
        };
        let (ref_tol, ref_events, ref_peak) = (
            reference.tolerance,
            reference.events.clone(),
            reference.peak,
        );
        let rows = runs
            .iter()
            .filter(|r| r.tolerance > ref_tol)
            .map(|r| {
                let (event_error, events) = event_error(&r.events, &ref_events);
                Row {
                    integrator: r.integrator.clone(),
                    tolerance: r.tolerance,
                    steps: r.steps,
                    evaluations: r.evaluations,
                    cpu_s: r.cpu_s,
                    events,
                    event_error,
                    peak_error: ((r.peak - ref_peak) / ref_peak).abs(),
                }
            })
            .collect();
        table.insert(problem.clone(), rows);
    }
    let mut csv = format!("{CSV_HEADER}\n");
    let mut panels: Vec<Panel> = Vec::new();
    for (problem, rows) in &table {
        let mut times = BTreeMap::new();
        let mut peaks = BTreeMap::new();
        for r in rows {
            writeln!(
                csv,
                "{problem},{},{:e},{},{},{:.2},{},{:.3e},{:.3e}",
                r.integrator,
                r.tolerance,
                r.steps,
                r.evaluations,
                r.cpu_s,
                r.events,
                r.event_error,
                r.peak_error
            )?;
            for (map, e) in [(&mut times, r.event_error), (&mut peaks, r.peak_error)] {
                if e > 0.0 && r.cpu_s > 0.0 {
                    map.entry(r.integrator.clone())
                        .or_insert_with(Vec::new)
                        .push((r.cpu_s.log10(), e.log10()));
                }
            }
        }
        panels.push((
            format!("{problem}: event times (against dormand-prince, tightest tolerance)"),
            times,
        ));
        panels.push((format!("{problem}: peak slip rate"), peaks));
    }
    std::fs::write(out.join("integrators.csv"), &csv)?;
    // Every panel lists every integrator (an empty line where it was not run), so that an
    // integrator has one colour throughout.
    let all: Vec<String> = panels
        .iter()
        .flat_map(|(_, lines)| lines.keys().cloned())
        .collect();
    for (_, lines) in &mut panels {
        for name in &all {
            lines.entry(name.clone()).or_default();
        }
    }
    let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
    for (_, lines) in &panels {
        for p in lines.values().flatten() {
            x0 = x0.min(p.0);
            x1 = x1.max(p.0);
        }
    }
    let pad = 0.05 * (x1 - x0).max(0.1);
    let series: Vec<Vec<Series<'_>>> = panels
        .iter()
        .map(|(_, lines)| {
            lines
                .iter()
                .map(|(label, points)| Series { label, points })
                .collect()
        })
        .collect();
    let titled: Vec<(&str, &[Series<'_>])> = panels
        .iter()
        .zip(&series)
        .map(|((t, _), s)| (t.as_str(), s.as_slice()))
        .collect();
    Series::panels(
        &figures.join("work_precision_integrators.png"),
        &Labels {
            title: "The fault ODE's integrators: relative error against CPU time (one thread)",
            x: "log10 CPU time (s)",
            y: "log10 relative error",
        },
        &titled,
        &PanelLayout {
            columns: false,
            log_y: false,
            x_range: (x0 - pad, x1 + pad),
            y_range: None,
        },
    )?;
    log(&format!("wrote {}", out.join("integrators.csv").display()));
    Ok(())
}
