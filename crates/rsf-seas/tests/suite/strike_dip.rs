//! The strike–dip layout of BP5 (docs/seas-bp5.md, "Output") on a coarse run of the fault
//! alone of rsf-scenes: two ruptures and the benchmark's files, read back by the
//! description's rules; a stopped and continued run writing the same bytes.

use std::path::Path;

use rsf::{Observer, Until};
use rsf_scenes::{SeasBp5, SeasBp5Run};
use rsf_seas::{SeasBp5Output, SeasSetup, SECONDS_PER_YEAR};

/// The prestress of the description, written out here from its formula (not the scene's
/// code): τ⁰ = σ̄_n a asinh(V/(2V₀) exp((f₀ + b ln(V₀/V_p))/a)) + η V (Pa).
fn published_tau0(a: f64, v: f64) -> f64 {
    let (sigma, f0, b, v0, v_p) = (25e6, 0.6, 0.03, 1e-6, 1e-9);
    let eta = 2670.0 * 3464.0 * 3464.0 / (2.0 * 3464.0);
    sigma * a * (v / (2.0 * v0) * ((f0 + b * (v0 / v_p).ln()) / a).exp()).asinh() + eta * v
}

/// The fault alone on cells of `dx` with the off-fault stations' columns.
fn with_stations(bp5: &SeasBp5, dx: f64) -> (rsf_scenes::SeasBp5FaultOde, Vec<Vec<f64>>) {
    bp5.fault_ode_with_stations(
        bp5.model(dx).unwrap(),
        bp5.fault_ode_options(1e-6).unwrap(),
        &bp5.half_space(1e-6).unwrap(),
        &SeasBp5::body_station_points(),
    )
    .unwrap()
}

/// The moment rate of every accepted step, computed here from the description: `μ Σ_k
/// A_k |V_k|` with `μ = ρ c_s²` (ρ = 2670 kg/m³, c_s = 3464 m/s) and the cells' areas `dx²`
/// — not from the output's code (issue 74: a moment rate with μ/2 went unnoticed).
struct MomentRates {
    area: f64,
    rates: Vec<(f64, f64)>,
}

impl MomentRates {
    fn push(&mut self, t: f64, v: &[f64]) {
        let mu = 2670.0 * 3464.0 * 3464.0;
        let speeds: f64 = v.chunks_exact(3).map(|c| c[1].hypot(c[2])).sum();
        self.rates.push((t, mu * self.area * speeds));
    }
}

impl Observer<3, 3> for MomentRates {
    fn observe(&mut self, s: &rsf::StepView<'_, 3, 3>) -> rsf::Result<rsf::Flow> {
        self.push(s.state.time, &s.state.kinematics.v);
        Ok(rsf::Flow::Continue(()))
    }
    fn reads_volume(&self) -> bool {
        false
    }
}

/// The files' headers of a BP5 run at Δx = `dx` (m), the run's own (modeler `test`, date
/// 2026-11-26).
fn setup(dx: f64) -> SeasSetup {
    let run = SeasBp5Run {
        dx,
        ..SeasBp5Run::default()
    };
    run.seas_setup(&SeasBp5::default(), "test".into(), "2026-11-26".into())
}

/// The row count `# num_time_steps=N` of a SEAS file's `lines`.
fn num_time_steps<'a>(mut lines: impl Iterator<Item = &'a str>) -> usize {
    lines
        .find_map(|l| l.strip_prefix("# num_time_steps="))
        .unwrap()
        .parse()
        .unwrap()
}

/// The rows of a SEAS file: checks its header (problem, `# Column #k` lines, the field
/// line, `num_time_steps`) and every number's `%E` form.
fn parse(path: &Path, columns: usize) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let mut header = Vec::new();
    for line in lines.by_ref() {
        if !line.starts_with('#') {
            assert_eq!(
                line.split(' ').count(),
                columns,
                "{}: field line {line}",
                path.display()
            );
            break;
        }
        header.push(line);
    }
    assert!(
        header.contains(&"# problem=SEAS Benchmark BP5-QD"),
        "{}",
        path.display()
    );
    let described = header
        .iter()
        .filter(|l| l.starts_with("# Column #"))
        .count();
    assert_eq!(described, columns, "{}", path.display());
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            let tokens: Vec<&str> = l.split_whitespace().collect();
            assert_eq!(tokens.len(), columns, "{}: {l}", path.display());
            for (i, t) in tokens.iter().enumerate() {
                let (mantissa, exponent) = t.split_once('E').expect("an %E number");
                let digits = mantissa
                    .trim_start_matches('-')
                    .split_once('.')
                    .unwrap()
                    .1
                    .len();
                assert_eq!(digits, if i == 0 { 13 } else { 6 }, "{t}");
                assert!(
                    exponent.len() == 3 && (exponent.starts_with('+') || exponent.starts_with('-'))
                );
            }
            tokens.iter().map(|t| t.parse().unwrap()).collect()
        })
        .collect();
    let count = num_time_steps(header.iter().copied());
    assert_eq!(count, rows.len(), "{}", path.display());
    rows
}

#[test]
fn a_coarse_run_reaches_two_ruptures_and_writes_the_benchmarks_files() {
    let bp5 = SeasBp5::default();
    let dx = 4000.0;
    let dir = crate::common::temp_dir("bp5-coarse");
    let (mut ode, columns) = with_stations(&bp5, dx);
    let mut output = bp5.output(&dir, dx, columns, setup(dx)).unwrap();
    output.write_initial_state(
        ode.model(),
        ode.state(),
        rsf::Stepping::fault_tractions(&ode),
    );
    let mut moment = MomentRates {
        area: dx * dx,
        rates: Vec::new(),
    };
    moment.push(0.0, &ode.state().kinematics.v);
    ode.run_until(
        Until::TimeWithin {
            time: 250.0 * SECONDS_PER_YEAR,
            max_steps: 200_000,
        },
        &mut [&mut output, &mut moment],
    )
    .unwrap();
    // global.dat's moment rate is μ ∫ |V| dA of the step its row was written at (the
    // times to the file's 14 digits).
    let global = parse(&dir.join("global.dat"), 3);
    let mut compared = 0;
    for row in &global {
        let (_, rate) = moment
            .rates
            .iter()
            .find(|(t, _)| (t - row[0]).abs() <= 1e-12 * row[0].abs().max(1.0))
            .unwrap_or_else(|| panic!("global.dat: no step at t = {}", row[0]));
        assert!(
            // The file's values have 7 significant digits (`%.6E`): rounding ≤ 5e-7.
            (row[2] / rate - 1.0).abs() < 1e-6,
            "global.dat at t = {}: moment rate {} against μ Σ A|V| = {rate}",
            row[0],
            row[2]
        );
        compared += 1;
    }
    assert!(compared > 100, "{compared} rows");
    let ruptures: Vec<_> = output
        .events()
        .iter()
        .filter(|e| e.peak_slip_rate > 0.1)
        .collect();
    // The patch fails at once; the next rupture a cycle later (~180 years at 4 km cells,
    // 236 at 1 km; a cycle is at least the time to reload the stress drop of a few MPa at
    // V_p over the weakening core, far more than a few years).
    assert!(ruptures.len() >= 2, "{:?}", output.events());
    assert!(
        ruptures[0].t_start < 1000.0,
        "first rupture at {} s",
        ruptures[0].t_start
    );
    let recurrence = (ruptures[1].t_start - ruptures[0].t_start) / SECONDS_PER_YEAR;
    assert!(
        (100.0..300.0).contains(&recurrence),
        "recurrence {recurrence} yr"
    );
    // Peak slip rates of a rupture: ~1 m/s (the description's codes: 1–3 m/s).
    assert!(ruptures
        .iter()
        .all(|e| (0.3..10.0).contains(&e.peak_slip_rate)));
    let stations = SeasBp5Output::file_names()
        .into_iter()
        .filter(|n| n.starts_with("fltst") || n.starts_with("blkst") || n == "global.dat");
    // The first rows are the description's check values (τ⁰ in MPa, log10 θ), computed
    // above from its formulas: the core, the patch, and a_max at the surface.
    for (name, tau0, log_theta) in [
        ("fltst_strk+00dp+10", published_tau0(0.004, 1e-9), 8.146),
        ("fltst_strk-24dp+10", published_tau0(0.004, 0.03), 8.114),
        ("fltst_strk+36dp+00", published_tau0(0.04, 1e-9), 8.146),
    ] {
        let rows = parse(&dir.join(name), 8);
        assert!(
            (rows[0][5] - tau0 / 1e6).abs() < 1e-5,
            "{name}: {}",
            rows[0][5]
        );
        assert!(
            (rows[0][7] - log_theta).abs() < 5e-4,
            "{name}: {}",
            rows[0][7]
        );
    }
    for name in stations {
        let columns = match &name[..5] {
            "fltst" => 8,
            "blkst" => 7,
            _ => 3,
        };
        let rows = parse(&dir.join(&name), columns);
        assert!(rows.len() > 100, "{name}: {} rows", rows.len());
        assert_eq!(rows[0][0], 0.0, "{name}: the first row is t = 0");
        assert!(
            rows.windows(2).all(|w| w[1][0] > w[0][0]),
            "{name}: time increases"
        );
        if name.starts_with("fltst") {
            // Slip along x₃ (the loading is along x₂) stays small: computed, bounded.
            let slip2 = rows.iter().map(|r| r[1].abs()).fold(0.0, f64::max);
            let slip3 = rows.iter().map(|r| r[2].abs()).fold(0.0, f64::max);
            assert!(slip2 > 1.0, "{name}: slip₂ {slip2} m");
            assert!(
                slip3 < 0.05 * slip2,
                "{name}: slip₃ {slip3} m against slip₂ {slip2} m"
            );
            assert!(slip3 > 0.0, "{name}: slip₃ is computed, not assumed 0");
            // V₃ below V₂ whenever V₂ is seismic.
            for r in rows.iter().filter(|r| r[3] > -3.0) {
                assert!(
                    r[4] < r[3] - 0.5,
                    "{name}: log10 V₃ {} against log10 V₂ {}",
                    r[4],
                    r[3]
                );
            }
        }
    }
    // The profiles: the positions row (0 0 and the grid's rows or columns), then time rows
    // of t, log10 max slip rate and one value per position.
    for (name, points) in [
        ("slip_2_depth.dat", 10),
        ("slip_2_strike.dat", 25),
        ("stress_2_depth.dat", 10),
        ("stress_2_strike.dat", 25),
    ] {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        let rows: Vec<Vec<f64>> = text
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with('x') && !l.starts_with('t'))
            .map(|l| l.split_whitespace().map(|t| t.parse().unwrap()).collect())
            .collect();
        assert!(rows.iter().all(|r| r.len() == 2 + points), "{name}");
        assert_eq!(&rows[0][..2], &[0.0, 0.0], "{name}: the positions row");
        let count = num_time_steps(text.lines());
        assert_eq!(count, rows.len() - 1, "{name}");
        // Profiles every 5 years between events: about 50 in 250 years, more in events.
        assert!(rows.len() > 50, "{name}: {} rows", rows.len());
    }
    // rupture.dat: every cell once; the ruptured ones after the first event, in the
    // second rupture (its start at ~180 years) or the afterslip that follows.
    let text = std::fs::read_to_string(dir.join("rupture.dat")).unwrap();
    let times: Vec<f64> = text
        .lines()
        .filter(|l| l.starts_with(' '))
        .map(|l| l.split_whitespace().nth(2).unwrap().parse().unwrap())
        .collect();
    assert_eq!(times.len(), 250);
    let ruptured: Vec<f64> = times
        .iter()
        .copied()
        .filter(|&t| t < rsf_seas::NEVER_RUPTURED)
        .collect();
    // The weakening core (60 km × 12 km: 45 cells of 4 km) and some of its rim.
    assert!(
        (45..=250).contains(&ruptured.len()),
        "{} of 250 cells ruptured",
        ruptured.len()
    );
    assert!(ruptured.iter().all(|&t| t >= ruptures[0].t_end.unwrap()));
    // The library's reader (rsf_seas::read_seas_file, from which crates/rsf-hdf5 writes a
    // run's seas.h5) takes every file of BP5's layout: the rows its header counts, and
    // rupture.dat's times those read above line by line.
    let mut read = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if !rsf_seas::is_seas_file(&path) {
            continue;
        }
        let f = rsf_seas::read_seas_file(&path).unwrap_or_else(|e| panic!("{e}"));
        if let Some(n) = f.header_value("num_time_steps") {
            assert_eq!(n.parse::<usize>().unwrap(), f.rows(), "{}", path.display());
        }
        if path.ends_with("rupture.dat") {
            assert_eq!(f.column(2), times);
        }
        read += 1;
    }
    // The stations, global.dat, four profiles, rupture.dat: each of the layout's files.
    assert_eq!(read, SeasBp5Output::file_names().len());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_stopped_and_continued_run_writes_the_same_bytes() {
    let bp5 = SeasBp5::default();
    let dx = 4000.0;
    let base = crate::common::temp_dir("bp5-resume");
    let end = Until::TimeWithin {
        time: 190.0 * SECONDS_PER_YEAR,
        max_steps: 500_000,
    };
    let every = 200;
    let run = |dir: &Path, stop: Option<usize>, resume: Option<&rsf::Checkpoint>| {
        let (mut ode, columns) = with_stations(&bp5, dx);
        let mut output = bp5
            .output(dir, dx, columns, setup(dx))
            .unwrap()
            .with_resume_log(every);
        match resume {
            Some(c) => {
                // The mark of the step at another time (another run's: one ulp away) is
                // refused, naming the log (issue 87: no splice of two runs).
                let elsewhen = f64::from_bits(c.state.time.to_bits() + 1);
                let e = output
                    .resume(c.state.step, elsewhen)
                    .unwrap_err()
                    .to_string();
                assert!(
                    e.contains("bp5_resume.json") && e.contains("another run"),
                    "{e}"
                );
                // A log written before issue 87 (its marks without `t`) proves nothing: in a
                // folder whose manifest names no run it is refused; with a manifest naming a
                // run (compared with the checkpoint's by the run folder) it is taken.
                let log = dir.join("bp5_resume.json");
                let written = std::fs::read_to_string(&log).unwrap();
                let mut marks: Vec<serde_json::Value> = serde_json::from_str(&written).unwrap();
                for m in &mut marks {
                    assert!(m.as_object_mut().unwrap().remove("t").is_some());
                }
                std::fs::write(&log, serde_json::to_string(&marks).unwrap()).unwrap();
                let e = output
                    .resume(c.state.step, c.state.time)
                    .unwrap_err()
                    .to_string();
                assert!(
                    e.contains("holds no time") && e.contains(rsf::run_folder::MANIFEST),
                    "{e}"
                );
                let manifest = dir.join(rsf::run_folder::MANIFEST);
                std::fs::write(
                    &manifest,
                    format!("program=seas_bp5\nrun={}\n", rsf::run_folder::new_run_id()),
                )
                .unwrap();
                assert!(rsf::run_folder::run_id(dir).is_some());
                output.resume(c.state.step, c.state.time).unwrap();
                std::fs::write(&log, &written).unwrap();
                std::fs::remove_file(&manifest).unwrap();
                output.resume(c.state.step, c.state.time).unwrap();
                ode.restore(c).unwrap();
            }
            None => output.write_initial_state(
                ode.model(),
                ode.state(),
                rsf::Stepping::fault_tractions(&ode),
            ),
        }
        let until = match stop {
            Some(step) => Until::TimeOrStepCap {
                time: 190.0 * SECONDS_PER_YEAR,
                step_cap: step,
            },
            None => end,
        };
        let observers: &mut [&mut dyn Observer<3, 3>] = &mut [&mut output];
        ode.run_until(until, observers).unwrap();
        ode.checkpoint()
    };
    let (whole, parts) = (base.join("whole"), base.join("parts"));
    run(&whole, None, None);
    // Stopped in the middle of the first interseismic period and after the files were
    // persisted at step 600 and 800, continued from step 600 (a checkpoint behind the files).
    let stopped = run(&parts, Some(600), None);
    assert_eq!(stopped.state.step, 600);
    run(&parts, Some(900), Some(&stopped));
    let again = run(&parts, None, Some(&stopped));
    assert!(again.state.step > 900);
    let mut compared = 0;
    for name in SeasBp5Output::file_names()
        .into_iter()
        .chain(["events.csv".into()])
    {
        let a = std::fs::read(whole.join(&name)).unwrap();
        let b = std::fs::read(parts.join(&name)).unwrap();
        assert!(a == b, "{name} differs after the resumes");
        compared += 1;
    }
    assert_eq!(compared, 26);
    let _ = std::fs::remove_dir_all(&base);
}
