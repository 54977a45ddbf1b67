//! The SEAS benchmark files (`SeasOutput`, docs/seas-bp1.md "Output") read back by the
//! benchmark description's rules (docs/seas-bp1.md restates them): header lines, one
//! `# Column #k` line per column, the field-list line(s) exactly, rows of as many numbers
//! as fields in the recommended formats, time strictly increasing from a first row at
//! t = 0, `num_time_steps` equal to the rows in the file. And the numbers in them: every
//! station row against the model's own slip, slip rate, shear stress (from the regularised
//! law's published formula, written here) and state at that node and time, recorded by an
//! observer beside the output; a steady-creep run against its closed form.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use rsf::observe::{FileMode, StepView};
use rsf::{Flow, Observer, Until};
use rsf_scenes::{SeasBp1, SeasBp1FaultOde, SeasBp1Grid, SEAS_BP1_STATION_DEPTHS};
use rsf_seas::{SeasOutput, SeasSetup, SEAS_BP1_STATION_COLUMNS, SECONDS_PER_YEAR};

/// The stations on the small BP1's 10 km fault (0, 2.5, 5, 7.5, 10 km).
const DEPTHS: &[f64] = &SEAS_BP1_STATION_DEPTHS;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rsf-seas-files-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The fault ODE of `bp1` on `grid` (tolerance 1e-6).
fn fault_ode(bp1: &SeasBp1, grid: &SeasBp1Grid) -> SeasBp1FaultOde {
    let model = bp1.model(grid, false).unwrap();
    bp1.fault_ode(model, bp1.fault_ode_options(1e-6).unwrap())
        .unwrap()
}

fn setup(bp1: &SeasBp1, dz: f64) -> SeasSetup {
    crate::common::five_stations(bp1, dz, "2026-11-24")
}

/// The station values of every step, computed here from the state: time → per station
/// (slip m, log10 V, shear stress MPa, log10 θ).
struct Recorder {
    /// The friction law of every frictional node.
    laws: Vec<rsf::friction::AsinhLaw>,
    /// Frictional node of each station (nearest in depth, found here).
    nodes: Vec<usize>,
    rows: HashMap<u64, Vec<[f64; 4]>>,
    times: Vec<f64>,
}

/// The regularised rate-and-state law's shear stress (Pa), as the benchmark description
/// writes it: τ = σ_n a asinh(V/(2V₀) exp((f₀ + b ln(V₀θ/L))/a)).
fn published_shear_stress(p: &rsf::friction::RateStateParams, v: f64, theta: f64) -> f64 {
    p.sigma_n
        * p.a
        * (v / (2.0 * p.v0) * ((p.mu0 + p.b * (p.v0 * theta / p.l).ln()) / p.a).exp()).asinh()
}

impl Recorder {
    fn record(&mut self, model: &rsf::model::Model<2, 1>, state: &rsf::SimulationState) {
        let fb = &model.frictional_boundary;
        if self.nodes.is_empty() {
            self.nodes = DEPTHS[..5]
                .iter()
                .map(|&d| {
                    (0..fb.len())
                        .min_by(|&i, &j| {
                            let di = (model.vertices[fb.nodes[i]][1] - d).abs();
                            let dj = (model.vertices[fb.nodes[j]][1] - d).abs();
                            di.total_cmp(&dj)
                        })
                        .unwrap()
                })
                .collect();
        }
        let laws = &self.laws;
        let row = self
            .nodes
            .iter()
            .map(|&k| {
                let p = fb.nodes[k];
                let slip = state.kinematics.u[p] - model.initial_displacement[p];
                let v = state.kinematics.v[p].abs();
                let theta = state.alpha[k].exp();
                let stress = published_shear_stress(laws[k].params(), v, theta) / 1e6;
                [slip, v.log10(), stress, theta.log10()]
            })
            .collect();
        self.times.push(state.time);
        self.rows.insert(state.time.to_bits(), row);
    }
}

/// A recorder as an observer (it sees the states after each step).
struct Recording<'a>(&'a mut Recorder);

impl Observer<2, 1> for Recording<'_> {
    fn observe(&mut self, s: &StepView<'_, 2, 1>) -> rsf::Result<Flow> {
        self.0.record(s.model, s.state);
        Ok(Flow::Continue(()))
    }
    fn reads_volume(&self) -> bool {
        false
    }
}

/// Runs `ode` to `years` with a `SeasOutput` into `dir` (its initial rows written first)
/// and a recorder beside it; returns the recorder.
fn run_with_output(
    ode: &mut SeasBp1FaultOde,
    setup: SeasSetup,
    dir: &Path,
    years: f64,
) -> Recorder {
    let mut out = SeasOutput::new(
        dir,
        rsf::Stepping::model(ode),
        ode.problem().friction_laws(),
        setup,
        FileMode::Overwrite,
    )
    .unwrap();
    out.write_initial_state(rsf::Stepping::model(ode), ode.state())
        .unwrap();
    let mut recorder = Recorder {
        laws: ode.problem().friction_laws().to_vec(),
        nodes: Vec::new(),
        rows: HashMap::new(),
        times: Vec::new(),
    };
    recorder.record(rsf::Stepping::model(ode), ode.state());
    let mut rec = Recording(&mut recorder);
    let mut observers: [&mut dyn Observer<2, 1>; 2] = [&mut out, &mut rec];
    ode.run_until(
        Until::TimeWithin {
            time: years * SECONDS_PER_YEAR,
            max_steps: 500_000,
        },
        &mut observers,
    )
    .unwrap();
    recorder
}

/// A file read by the description's rules.
struct SeasFile {
    header: HashMap<String, String>,
    /// `# Column #k = …` descriptions in order.
    columns: Vec<String>,
    /// The non-`#` lines before the data.
    field_lines: Vec<String>,
    rows: Vec<Vec<f64>>,
}

/// Reads `path`: `#` lines (`key=value` pairs and `Column #k = …` lines), then
/// `field_lines` non-`#` lines, then data rows of numbers in C's `%E` format (the first
/// column `%21.13E`, the others `%14.6E`; `skip_format` rows after the field lines are
/// only parsed, e.g. `devol.dat`'s row of depths).
fn read_seas_file(path: &Path, field_lines: usize, skip_format: usize) -> SeasFile {
    let text = std::fs::read_to_string(path).unwrap();
    let name = path.display();
    let mut header = HashMap::new();
    let mut columns = Vec::new();
    let mut lines = text.lines().peekable();
    while let Some(l) = lines.next_if(|l| l.starts_with('#')) {
        let body = l[1..].trim();
        if let Some(rest) = body.strip_prefix("Column #") {
            let (k, description) = rest.split_once(" = ").expect("`# Column #k = …`");
            assert_eq!(
                k.parse::<usize>().unwrap(),
                columns.len() + 1,
                "{name}: column numbers"
            );
            columns.push(description.to_owned());
        } else if let Some((k, v)) = body.split_once('=') {
            assert!(
                header.insert(k.to_owned(), v.to_owned()).is_none(),
                "{name}: {k} twice"
            );
        }
    }
    let field_lines: Vec<String> = (0..field_lines)
        .map(|_| lines.next().expect("a field-list line").to_owned())
        .collect();
    let mut rows = Vec::new();
    for (i, l) in lines.enumerate() {
        assert!(
            !l.starts_with('#'),
            "{name}: a `#` line among the data: {l}"
        );
        let fields: Vec<&str> = l.split_whitespace().collect();
        if i >= skip_format {
            assert_eq!(
                l.len(),
                21 + 15 * (fields.len() - 1),
                "{name}: row width: {l}"
            );
            for (j, f) in fields.iter().enumerate() {
                let digits = if j == 0 { 13 } else { 6 };
                let (mantissa, exponent) = f.split_once('E').expect("an exponent");
                let m = mantissa.trim_start_matches('-');
                assert!(
                    m.len() == digits + 2 && m.as_bytes()[1] == b'.',
                    "{name}: `{f}` is not %.{digits}E"
                );
                assert!(
                    exponent.starts_with(['+', '-']) && exponent.len() >= 3,
                    "{name}: exponent of `{f}`"
                );
            }
        }
        rows.push(fields.iter().map(|f| f.parse::<f64>().unwrap()).collect());
    }
    SeasFile {
        header,
        columns,
        field_lines,
        rows,
    }
}

/// The header lines the description asks of every file, with the run's values.
fn check_header(f: &SeasFile, name: &str, setup: &SeasSetup, data_rows: usize) {
    for key in [
        "problem",
        "author",
        "date",
        "code",
        "code_version",
        "element_size",
        "location",
        "minimum_time_step",
        "maximum_time_step",
        "num_time_steps",
    ] {
        assert!(f.header.contains_key(key), "{name}: no `{key}` line");
    }
    assert_eq!(f.header["problem"], setup.problem, "{name}");
    assert_eq!(f.header["author"], setup.modeler, "{name}");
    assert_eq!(f.header["date"], setup.date, "{name}");
    assert_eq!(f.header["code"], "rsf", "{name}");
    assert_eq!(
        f.header["element_size"],
        format!("{} m", setup.element_size),
        "{name}"
    );
    let lo: f64 = f.header["minimum_time_step"].parse().unwrap();
    let hi: f64 = f.header["maximum_time_step"].parse().unwrap();
    assert!(
        lo > 0.0 && lo <= hi && hi.is_finite(),
        "{name}: steps {lo} … {hi}"
    );
    assert_eq!(
        f.header["num_time_steps"].parse::<usize>().unwrap(),
        data_rows,
        "{name}: num_time_steps is the rows in the file"
    );
}

/// Time strictly increasing from a first row at t = 0.
fn check_times(rows: &[Vec<f64>], name: &str) {
    assert_eq!(rows[0][0], 0.0, "{name}: the first row is at t = 0");
    for w in rows.windows(2) {
        assert!(
            w[1][0] > w[0][0],
            "{name}: time not increasing at {}",
            w[1][0]
        );
    }
}

#[test]
fn every_file_follows_the_description_and_holds_the_models_values() {
    let (bp1, grid) = crate::common::small_bp1(&SeasBp1::default());
    let mut ode = fault_ode(&bp1, &grid);
    let dir = temp_dir("bp1");
    let setup = setup(&bp1, grid.dz);
    // Through the first event (about 80 years on the small fault).
    let recorder = run_with_output(&mut ode, setup.clone(), &dir, 150.0);
    let events = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    assert!(
        events.lines().count() > 1,
        "an event within the run:\n{events}"
    );

    let field_line = SEAS_BP1_STATION_COLUMNS
        .iter()
        .map(|c| c.0)
        .collect::<Vec<_>>()
        .join(" ");
    assert_eq!(field_line, "t slip slip_rate shear_stress state");
    let mut worst = [0.0f64; 4];
    for (s, (station, depth)) in setup.stations.iter().enumerate() {
        let name = station.as_str();
        let f = read_seas_file(&dir.join(name), 1, 0);
        check_header(&f, name, &setup, f.rows.len());
        assert_eq!(
            f.header["location"],
            format!("on fault, {} km depth", depth / 1e3),
            "{name}"
        );
        assert_eq!(
            f.columns,
            [
                "Time (s)",
                "Slip (m)",
                "Slip rate (log10 m/s)",
                "Shear stress (MPa)",
                "State (log10 s)"
            ],
            "{name}"
        );
        assert_eq!(f.field_lines, [field_line.as_str()], "{name}");
        assert!(f.rows.iter().all(|r| r.len() == 5), "{name}: rows of 5");
        check_times(&f.rows, name);
        assert!(f.rows.len() > 20, "{name}: {} rows", f.rows.len());
        // Every row against the recorded state at its time (the file's time has 14
        // significant digits: the recorded time nearest to it).
        for row in &f.rows {
            let t = *recorder
                .times
                .iter()
                .min_by(|a, b| (*a - row[0]).abs().total_cmp(&(*b - row[0]).abs()))
                .unwrap();
            assert!(
                (t - row[0]).abs() <= 1e-12 * t.abs().max(1.0),
                "{name}: no step at {}",
                row[0]
            );
            let want = recorder.rows[&t.to_bits()][s];
            for c in 0..4 {
                // %14.6E: 7 significant digits, so a relative 5e-7 of the value (slip 0
                // at t = 0 exactly).
                let err = (row[c + 1] - want[c]).abs();
                let tol = 5.1e-7 * want[c].abs() + 1e-300;
                assert!(
                    err <= tol,
                    "{name}, t = {t}, column {}: {} in the file, {} from the state",
                    c + 2,
                    row[c + 1],
                    want[c]
                );
                worst[c] = worst[c].max(err / want[c].abs().max(1e-300));
            }
        }
    }
    eprintln!(
        "largest relative differences file − state (slip, log10 V, stress, log10 θ): {worst:?}"
    );

    // devol.dat: two field-list lines, the row of depths, then `t log10(max V) slip…`.
    let f = read_seas_file(&dir.join("devol.dat"), 2, 1);
    assert_eq!(f.field_lines, ["z", "t max_slip_rate slip"]);
    let depths = &f.rows[0];
    assert_eq!(&depths[..2], &[0.0, 0.0]);
    assert!(
        depths[2..].windows(2).all(|w| w[1] > w[0]),
        "depths increase"
    );
    let data = &f.rows[1..];
    check_header(&f, "devol.dat", &setup, data.len());
    assert!(
        data.iter().all(|r| r.len() == depths.len()),
        "devol.dat: rows of {}",
        depths.len()
    );
    check_times(data, "devol.dat");
    // The slip at the surface column equals the surface station's at the same time.
    let surface = read_seas_file(&dir.join(&setup.stations[0].0), 1, 0);
    let by_time: HashMap<u64, f64> = surface
        .rows
        .iter()
        .map(|r| (r[0].to_bits(), r[1]))
        .collect();
    let mut compared = 0;
    for r in data {
        if let Some(&slip) = by_time.get(&r[0].to_bits()) {
            assert!(
                (r[2] - slip).abs() <= 5.1e-7 * slip.abs(),
                "devol.dat at {}: {} vs {slip}",
                r[0],
                r[2]
            );
            compared += 1;
        }
    }
    assert!(
        compared >= 2,
        "devol.dat and the surface station share rows ({compared})"
    );
    // The library's reader (rsf_seas::read_seas_file) gives what is read here by the
    // description's rules: the columns, a profile's positions, every number.
    let names = setup.stations.iter().map(|s| s.0.as_str());
    for name in names.chain(["devol.dat"]) {
        let field_lines = if name == "devol.dat" { 2 } else { 1 };
        let here = read_seas_file(&dir.join(name), field_lines, field_lines - 1);
        let lib = rsf_seas::read_seas_file(&dir.join(name)).unwrap();
        let fields: Vec<&str> = lib.columns.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(
            fields.join(" "),
            here.field_lines[field_lines - 1],
            "{name}"
        );
        let described: Vec<&str> = lib.columns.iter().map(|c| c.description.as_str()).collect();
        assert_eq!(described, here.columns, "{name}");
        let mut rows = here.rows.clone();
        match &lib.positions {
            Some((coordinate, positions)) => {
                assert_eq!(*coordinate, here.field_lines[0], "{name}");
                assert_eq!(positions[..], rows.remove(0)[2..], "{name}");
            }
            None => assert_eq!(field_lines, 1, "{name}: a profile without positions"),
        }
        assert_eq!(lib.rows(), rows.len(), "{name}");
        assert_eq!(lib.values, rows.concat(), "{name}");
        let second: Vec<f64> = rows.iter().map(|r| r[1]).collect();
        assert_eq!(lib.column(1), second, "{name}");
        let last = rows.iter().flat_map(|r| r[fields.len() - 1..].to_vec());
        assert_eq!(
            lib.column(fields.len() - 1),
            last.collect::<Vec<_>>(),
            "{name}"
        );
        assert_eq!(
            lib.header_value("num_time_steps"),
            Some(here.header["num_time_steps"].as_str()),
            "{name}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Steady creep: with a = a_max everywhere (velocity strengthening) the BP1 initial state
/// is the steady state at V_p, and the body translates with the plate. The files show
/// log10 V = log10 V_p, the steady shear stress σ_n a asinh(V_p/(2V₀) exp((f₀ + b
/// ln(V₀/V_p))/a)) (the friction stress, without η V_p) and log10 θ = log10(L/V_p) at
/// every row.
#[test]
fn steady_creep_files_show_the_plate_rate_and_the_steady_stress() {
    let (bp1, grid) = crate::common::small_bp1(&SeasBp1::default());
    let bp1 = SeasBp1 {
        a0: bp1.a_max,
        ..bp1
    };
    let mut ode = fault_ode(&bp1, &grid);
    let dir = temp_dir("creep");
    let setup = setup(&bp1, grid.dz);
    run_with_output(&mut ode, setup.clone(), &dir, 20.0);
    let (a, b) = (bp1.a_max, bp1.b0);
    let tau = bp1.sigma_n
        * a
        * (bp1.v_p / (2.0 * bp1.v0) * ((bp1.f0 + b * (bp1.v0 / bp1.v_p).ln()) / a).exp()).asinh()
        / 1e6;
    let log_theta = (bp1.d_c / bp1.v_p).log10();
    for (station, _) in &setup.stations {
        let f = read_seas_file(&dir.join(station), 1, 0);
        assert!(f.rows.len() > 10);
        for r in &f.rows {
            assert!(
                (r[2] - bp1.v_p.log10()).abs() <= 1e-5,
                "{station} at {}: log10 V = {}",
                r[0],
                r[2]
            );
            assert!(
                (r[3] - tau).abs() <= 1e-6 * tau,
                "{station} at {}: {} MPa, steady {tau}",
                r[0],
                r[3]
            );
            assert!(
                (r[4] - log_theta).abs() <= 1e-5,
                "{station} at {}: log10 θ = {}",
                r[0],
                r[4]
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
