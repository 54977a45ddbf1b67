//! Bit-identity as a CI fact (issue 59): short reference runs through the library, their
//! trajectories hashed (SHA-256 of the f64 bits) and compared with the labelled hashes in
//! `tests/reference_hashes.toml`.
//!
//! Each run gives two hashes: `series`, of every accepted step's time, step size and, at
//! every frictional node, slip, slip rate and state α (what the observers see), and `end`,
//! of the final state's `u`, `v`, `a` and `α` (the method's whole field). A change that
//! is meant to change the bits (a new scheme, a reordered sum) updates the file with
//!
//! ```sh
//! RSF_UPDATE_HASHES=1 cargo test --test reference_hashes
//! ```
//!
//! and says in its commit message why the bits changed; any other change must leave
//! the file as it is. Runs that take threads are hashed at one thread and at two (on a
//! pool of two, as the examples run them) and both must give the labelled hashes.
//!
//! The hashes were first produced by f23e6d1's code (the main branch that CI passed), so
//! they pin the trajectories of that commit.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Mutex;

use rsf::fault_ode::FaultKernel;
use rsf::method::SolverOptions;
use rsf::observe::StepView;
use rsf::{Flow, Observer, Parallelism, Stepping, Until};
use rsf_scenes::{SeasBp1, SeasBp1Grid, SeasBp3, SeasBp3Grid, Slider3dScene, SliderScene};
use rsf_seas::SECONDS_PER_YEAR;
use sha2::{Digest, Sha256};

/// The hashes file, next to this test.
fn hashes_file() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/reference_hashes.toml")
}

const HEADER: &str = "\
# Labelled SHA-256 hashes of short reference runs (tests/reference_hashes.rs): `series`
# hashes every step's time, step size and each frictional node's slip, slip rate and state,
# `end` the final u, v, a and state. A change meant to change the bits rewrites this file with
#   RSF_UPDATE_HASHES=1 cargo test --test reference_hashes
# and says why in its commit message. First written by f23e6d1's code.
";

/// Serialises the updates of the file by the tests of this binary (they run in parallel).
static FILE: Mutex<()> = Mutex::new(());

/// The hashes of one run.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Hashes {
    steps: usize,
    series: String,
    end: String,
}

fn put(h: &mut Sha256, values: impl IntoIterator<Item = f64>) {
    for x in values {
        h.update(x.to_bits().to_le_bytes());
    }
}

/// Hashes every accepted step as observers see it.
struct SeriesHash {
    hasher: Sha256,
    steps: usize,
}

impl SeriesHash {
    fn new() -> Self {
        Self {
            hasher: Sha256::new(),
            steps: 0,
        }
    }
}

impl<const D: usize, const C: usize> Observer<D, C> for SeriesHash {
    fn observe(&mut self, s: &StepView<'_, D, C>) -> rsf::Result<Flow> {
        self.steps += 1;
        let h = &mut self.hasher;
        put(h, [s.state.time, s.state.tau]);
        for k in 0..s.model.frictional_boundary.len() {
            put(h, s.slip(k));
            put(h, [s.slip_rate(k)]);
        }
        put(h, s.state.alpha.iter().copied());
        Ok(Flow::Continue(()))
    }

    /// The fault's values only: a fault ODE then never recovers its volume (which would
    /// not change its trajectory, only cost).
    fn reads_volume(&self) -> bool {
        false
    }
}

/// Runs `method` until `until` and hashes its steps and its final state.
fn hash_run<const D: usize, const C: usize, M: Stepping<D, C>>(
    method: &mut M,
    until: Until,
) -> Hashes {
    let mut series = SeriesHash::new();
    rsf::run_until(method, until, &mut [&mut series]).expect("the reference run");
    let state = method.state();
    let mut end = Sha256::new();
    let k = &state.kinematics;
    put(&mut end, k.u.iter().chain(&k.v).chain(&k.a).copied());
    put(&mut end, state.alpha.iter().copied());
    put(&mut end, [state.time]);
    Hashes {
        steps: series.steps,
        series: hex(series.hasher.finalize().as_slice()),
        end: hex(end.finalize().as_slice()),
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// `body` on a rayon pool of `threads` threads (the examples' `main_on_threads`), or on
/// this thread for one.
fn on_threads<T: Send>(threads: usize, body: impl FnOnce() -> T + Send) -> T {
    if threads <= 1 {
        return body();
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(body)
}

/// [`check`] of `run` at one thread (`Parallelism::SEQ`) and at two
/// (`Parallelism::rayon(2)` on a pool of two threads).
fn check_at_one_and_two_threads(label: &str, run: impl Fn(Parallelism) -> Hashes + Sync) {
    let runs = [
        (1, run(Parallelism::SEQ)),
        (2, on_threads(2, || run(Parallelism::rayon(2)))),
    ];
    check(label, &runs);
}

/// Until the time `years` (of [`SECONDS_PER_YEAR`]) within at most 500 000 steps.
fn within_years(years: f64) -> Until {
    Until::TimeWithin {
        time: years * SECONDS_PER_YEAR,
        max_steps: 500_000,
    }
}

fn read_file() -> BTreeMap<String, Hashes> {
    let Ok(text) = std::fs::read_to_string(hashes_file()) else {
        return BTreeMap::new();
    };
    let table: toml::Table = text.parse().expect("tests/reference_hashes.toml is TOML");
    let field = |t: &toml::Value, name: &str| t.get(name).cloned();
    table
        .iter()
        .map(|(label, t)| {
            let h = Hashes {
                steps: field(t, "steps")
                    .and_then(|v| v.as_integer())
                    .expect("steps") as usize,
                series: field(t, "series")
                    .and_then(|v| v.as_str().map(str::to_owned))
                    .expect("series"),
                end: field(t, "end")
                    .and_then(|v| v.as_str().map(str::to_owned))
                    .expect("end"),
            };
            (label.clone(), h)
        })
        .collect()
}

fn write_file(all: &BTreeMap<String, Hashes>) {
    let mut text = HEADER.to_owned();
    for (label, h) in all {
        text.push_str(&format!(
            "\n[{label}]\nsteps = {}\nseries = \"{}\"\nend = \"{}\"\n",
            h.steps, h.series, h.end
        ));
    }
    std::fs::write(hashes_file(), text).expect("write tests/reference_hashes.toml");
}

/// Compares `runs` (the hashes of one reference run, at each thread count) with the
/// labelled hashes, or with `RSF_UPDATE_HASHES=1` writes them into the file.
fn check(label: &str, runs: &[(usize, Hashes)]) {
    let (_, first) = &runs[0];
    for (threads, h) in runs {
        assert_eq!(
            h, first,
            "{label}: {threads} threads give other bits than {} thread(s)",
            runs[0].0
        );
    }
    assert!(first.steps > 0, "{label}: no step");
    let _lock = FILE.lock().unwrap_or_else(|e| e.into_inner());
    let mut all = read_file();
    if std::env::var_os("RSF_UPDATE_HASHES").is_some_and(|v| v == "1") {
        all.insert(label.to_owned(), first.clone());
        write_file(&all);
        eprintln!("{label}: wrote {first:?}");
        return;
    }
    let expected = all.get(label).unwrap_or_else(|| {
        panic!(
            "{label}: no labelled hashes in tests/reference_hashes.toml (write them with \
             RSF_UPDATE_HASHES=1 cargo test --test reference_hashes)"
        )
    });
    assert_eq!(
        first, expected,
        "{label}: the trajectory's bits changed. If that is meant, update the hashes \
         (RSF_UPDATE_HASHES=1 cargo test --test reference_hashes) and say why in the commit"
    );
}

/// The paper's slider (the main job's scene, `pipping_slider`) at level 2: all its 10⁴
/// steps of τ = 1.5 ms (15 s, through its slip events), the solver chosen by size
/// (direct), at one and two threads.
#[test]
fn pipping_slider_level_2() {
    let run = |par: Parallelism| {
        let scene = SliderScene {
            level: 2,
            ..SliderScene::default()
        };
        let options = SolverOptions {
            parallelism: par,
            ..scene.solver_options()
        };
        let mut sim = scene
            .simulation_builder()
            .unwrap()
            .solver_options(options)
            .build()
            .unwrap();
        hash_run(&mut sim, Until::Steps(10_000))
    };
    check_at_one_and_two_threads("pipping_slider_level_2_10000_steps", run);
}

/// The 3-D slider (`slider_3d`'s scene: TNNMG with red–black chunks) at level 2, 1000
/// steps (1.5 s), at one and two threads.
#[test]
fn slider_3d_level_2() {
    let run = |par: Parallelism| {
        let scene = Slider3dScene::default();
        assert_eq!(scene.slider.level, 2);
        let options = SolverOptions {
            parallelism: par,
            ..scene.slider.solver_options()
        };
        let mut sim = scene
            .simulation_builder_with_model(scene.build_model().unwrap())
            .unwrap()
            .solver_options(options)
            .build()
            .unwrap();
        hash_run(&mut sim, Until::Steps(1000))
    };
    check_at_one_and_two_threads("slider_3d_level_2_1000_steps", run);
}

/// SEAS BP1-QD at Δz = 400 m (400 km box) over 300 years with the fault ODE (tolerance
/// 1e-6) and `kernel`, at one and two threads.
fn bp1(label: &str, kernel: FaultKernel) {
    let run = |par: Parallelism| {
        let bp1 = SeasBp1::default();
        let grid = SeasBp1Grid {
            dz: 400.0,
            ..SeasBp1Grid::default()
        };
        let model = bp1.model(&grid, false).unwrap();
        let options = rsf::fault_ode::FaultOdeOptions {
            kernel,
            parallelism: par,
            ..bp1.fault_ode_options(1e-6).unwrap()
        };
        let mut ode = bp1.fault_ode(model, options).unwrap();
        hash_run(&mut ode, within_years(300.0))
    };
    check_at_one_and_two_threads(label, run);
}

#[test]
fn seas_bp1_dz_400_dense() {
    bp1("seas_bp1_dz_400_300_years_dense", FaultKernel::Dense);
}

#[test]
fn seas_bp1_dz_400_hierarchical() {
    bp1(
        "seas_bp1_dz_400_300_years_hierarchical",
        FaultKernel::matching(1e-6),
    );
}

/// SEAS BP3-QD, the thrust, at Δx = 2 km on a small box (100 km, ratio 1.2: the grid of
/// rsf-scenes' BP3 tests) over 150 years, through its first event, with the fault ODE
/// (tolerance 1e-7, dense kernel), at one and two threads.
#[test]
fn seas_bp3_dx_2000() {
    let run = |par: Parallelism| {
        let bp3 = SeasBp3::thrust();
        let grid = SeasBp3Grid {
            dx: 2000.0,
            domain: 100e3,
            ratio: 1.2,
        };
        let model = bp3.model(&grid).unwrap();
        let mut options = bp3.params.fault_ode_options(1e-7).unwrap();
        options.runge_kutta.dt_min = 1e-8;
        options.kernel = FaultKernel::Dense;
        options.parallelism = par;
        let mut ode = bp3.fault_ode(model, options).unwrap();
        hash_run(&mut ode, within_years(150.0))
    };
    check_at_one_and_two_threads("seas_bp3_thrust_dx_2000_150_years", run);
}

/// SEAS BP5-QD as a fault alone with Okada's operator (issue 56), 4 km cells (dense
/// operator) over 200 years: the patch's rupture, the interseismic period and the second
/// rupture (at ~182 years), at one and two threads. Labelled when issue 56 landed (not
/// by f23e6d1, which had no fault alone).
#[test]
fn seas_bp5_dx_4000() {
    let run = |par: Parallelism| {
        let bp5 = rsf_scenes::SeasBp5::default();
        let model = bp5.model(4000.0).unwrap();
        let mut options = bp5.fault_ode_options(1e-6).unwrap();
        options.parallelism = par;
        let mut ode = bp5
            .fault_ode(model, options, &bp5.half_space(1e-6).unwrap())
            .unwrap();
        hash_run(&mut ode, within_years(200.0))
    };
    check_at_one_and_two_threads("seas_bp5_okada_dx_4000_200_years", run);
}
