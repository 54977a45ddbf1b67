//! What the physics tests of `rsf` share (issue 13): how a simulation is built, how a run is
//! recorded, and the small analyses applied to the records.
//!
//! Every construction detail lives here, so that a change of the construction API touches
//! this file only; the tests themselves see scenes as values, [`build`], the public
//! `Observer`/`Simulation` interface and the model's public matrices.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

mod internal_fault;
pub use internal_fault::{
    assert_first_order, assert_first_order_with_normal_stress, fault_ode_last_slip,
    implicit_last_slip, implicit_scheme, implicit_slip_errors, quasi_dynamic_of, tight_fault_ode,
    QuasiDynamic,
};
mod operators;
pub use operators::{mixed_slip, relative_product_difference};
mod scenes;
pub use scenes::slider;
mod shared;
pub use shared::{small_bp1, snapshot};
mod velocity;
pub use velocity::{
    newmark_rhs, newmark_velocity_matrix, slider_velocity_problem, steady_shear_strain, tnnmg_on,
    uniform_friction, with_dirichlet_values,
};

use rsf::fem::{spmv_add, SparseMatrix};
use rsf::friction::{DieterichRuina, FrictionLaw, RateStateParams};
use rsf::observe::{Checkpointer, Every, FileMode, FrictionalProfile, Interval, PointSeries};
use rsf::state::StateLaw;
use rsf::time::{Kinematics, VelocityIntegrator};
use rsf::{Integrator, Observer, RunSummary, Simulation, SolverKind, StateLawKind, StepView};
use rsf_scenes::{SceneSimulation, SliderScene, SLIDER_CENTRE};

/// A running simulation, as the tests hold it.
pub type Sim = SceneSimulation<2>;

/// The paper's scene (Table 6.1, docs/math.md §6) at refinement level `level`, N = 10⁴ steps
/// over T = 15 s, Dieterich's law, Newmark, solved by `solver`.
pub fn paper(level: usize, solver: SolverKind) -> SliderScene {
    SliderScene {
        level,
        solver,
        ..SliderScene::default()
    }
}

/// `scene` with `steps` steps over its end time (τ = T/steps).
pub fn with_steps(scene: SliderScene, steps: usize) -> SliderScene {
    SliderScene { steps, ..scene }
}

/// `scene` with another state law.
pub fn with_law(scene: SliderScene, law: StateLawKind) -> SliderScene {
    SliderScene {
        state_law: law,
        ..scene
    }
}

/// `scene` with another velocity integrator.
pub fn with_integrator(scene: SliderScene, integrator: Integrator) -> SliderScene {
    SliderScene {
        integrator,
        ..scene
    }
}

/// `scene` with a fixed point budget of `max` iterations per step.
pub fn with_fixed_point_budget(scene: SliderScene, max: usize) -> SliderScene {
    SliderScene {
        fixed_point_max_iterations: max,
        ..scene
    }
}

/// The paper's material and friction at level 2, τ = 1e-3 s, Γ_D moving at `v_load` from
/// t = 0 (no ramp) for `steps` steps: the fast-loading scene of the stability suite, which
/// reaches a slip event within a few hundred steps.
pub fn fast_loading(v_load: f64, steps: usize) -> SliderScene {
    SliderScene {
        level: 2,
        steps,
        end_time_s: 1e-3 * steps as f64,
        loading_velocity_m_per_s: v_load,
        ramp_fraction: 0.0,
        ..SliderScene::default()
    }
}

/// `scene` at another refinement level.
pub fn with_level(scene: SliderScene, level: usize) -> SliderScene {
    SliderScene { level, ..scene }
}

/// Velocity-strengthening friction (a, b) = (0.015, 0.010) (the paper's values swapped) at
/// level 2, Γ_D loaded at `v_load` after a ramp over the first tenth of the run, `steps`
/// steps of `tau`, with the state law `law` and the velocity integrator `integrator`.
pub fn velocity_strengthening(
    v_load: f64,
    tau: f64,
    steps: usize,
    law: StateLawKind,
    integrator: Integrator,
) -> SliderScene {
    SliderScene {
        level: 2,
        steps,
        end_time_s: tau * steps as f64,
        loading_velocity_m_per_s: v_load,
        ramp_fraction: 0.1,
        a: 0.015,
        b: 0.010,
        state_law: law,
        integrator,
        ..SliderScene::default()
    }
}

/// The running simulation of a scene.
pub fn build(scene: &SliderScene) -> Sim {
    scene.build().expect("the scene builds")
}

/// The simulation of `scene` with the solver `options` instead of the scene's.
pub fn build_with_options(scene: &SliderScene, options: rsf::method::SolverOptions) -> Sim {
    scene
        .simulation_builder()
        .unwrap()
        .solver_options(options)
        .build()
        .unwrap()
}

/// The friction law of Γ_F of a scene (uniform fault).
pub fn friction_law(scene: &SliderScene) -> DieterichRuina {
    DieterichRuina::new(scene.rate_state_params()).expect("valid parameters")
}

/// The rate-and-state parameters of a scene.
pub fn params(scene: &SliderScene) -> RateStateParams {
    scene.rate_state_params()
}

/// The loading velocity of Γ_D after the ramp (m/s).
pub fn loading_velocity(scene: &SliderScene) -> f64 {
    scene.loading_velocity_m_per_s
}

/// The initial state α₀ = ln θ₀ on Γ_F of a scene (θ in s).
pub fn initial_state(scene: &SliderScene) -> f64 {
    scene.alpha0
}

/// The final time T of a scene (s).
pub fn end_time(scene: &SliderScene) -> f64 {
    scene.end_time_s
}

/// The end of the loading ramp of a scene (s).
pub fn ramp_end(scene: &SliderScene) -> f64 {
    scene.ramp_fraction * scene.end_time_s
}

/// Steps from the simulation's current time to `t_end` (rounded to the nearest step).
pub fn steps_until<L: FrictionLaw, S: StateLaw, I: VelocityIntegrator>(
    sim: &Simulation<2, L, S, I>,
    t_end: f64,
) -> usize {
    ((t_end - sim.time()) / sim.tau()).round().max(0.0) as usize
}

/// Runs to `t_end` showing every step to `observers`.
pub fn run_until<L: FrictionLaw, S: StateLaw, I: VelocityIntegrator>(
    sim: &mut Simulation<2, L, S, I>,
    t_end: f64,
    observers: &mut [&mut dyn Observer<2>],
) -> RunSummary {
    let steps = steps_until(sim, t_end);
    sim.run(steps, observers)
        .expect("every step of the run succeeds")
}

/// Per-step records on Γ_F (nodes in the order along the boundary) and at x0.
#[derive(Debug, Clone, Default)]
pub struct Recorder {
    /// Γ_F nodes in order along the boundary.
    pub nodes: Vec<usize>,
    /// Their positions in the model's frictional-node order (the order of α).
    pub along: Vec<usize>,
    /// The vertex nearest to x0 = (2.5, 0).
    pub x0: usize,
    /// u_x on Γ_F at t = 0 (m).
    pub u_start: Vec<f64>,
    /// t_n (s).
    pub t: Vec<f64>,
    /// u_x(x0, t_n) (m).
    pub u_x0: Vec<f64>,
    /// Slip u_x(p, t_n) − u_x(p, 0) per Γ_F node (m).
    pub slip: Vec<Vec<f64>>,
    /// ln V_p per Γ_F node (V in m/s).
    pub ln_v: Vec<Vec<f64>>,
    /// State α_p per Γ_F node.
    pub alpha: Vec<Vec<f64>>,
    /// Largest slip rate on Γ_F reported by the step (m/s).
    pub max_v: Vec<f64>,
    /// Fixed point iterations of the step.
    pub fpi: Vec<usize>,
    /// Velocity solver iterations of the step (over its fixed point iterations).
    pub solver_its: Vec<usize>,
}

impl Recorder {
    /// A recorder for `sim`, holding its current displacement as the start of the slip.
    pub fn new<L: FrictionLaw, S: StateLaw, I: VelocityIntegrator>(
        sim: &Simulation<2, L, S, I>,
    ) -> Self {
        let model = sim.model();
        let fb = &model.frictional_boundary;
        let nodes: Vec<usize> = fb.along.iter().map(|&k| fb.nodes[k]).collect();
        let u = &sim.kinematics().u;
        Self {
            along: fb.along.clone(),
            u_start: nodes.iter().map(|&p| u[2 * p]).collect(),
            nodes,
            x0: model.nearest_node(&SLIDER_CENTRE).expect("x0 is a vertex"),
            ..Self::default()
        }
    }

    /// Number of recorded steps.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Mean and maximum fixed point iterations per step.
    pub fn fpi_stats(&self) -> (f64, usize) {
        let total: usize = self.fpi.iter().sum();
        (
            total as f64 / self.fpi.len().max(1) as f64,
            self.fpi.iter().copied().max().unwrap_or(0),
        )
    }
}

impl Observer<2> for Recorder {
    fn observe(&mut self, s: &StepView<'_, 2>) -> rsf::Result<rsf::Flow> {
        let (u, v) = (&s.state.kinematics.u, &s.state.kinematics.v);
        self.t.push(s.report.time);
        self.u_x0.push(u[2 * self.x0]);
        self.slip.push(
            self.nodes
                .iter()
                .zip(&self.u_start)
                .map(|(&p, u0)| u[2 * p] - u0)
                .collect(),
        );
        self.ln_v.push(
            self.nodes
                .iter()
                .map(|&p| v[2 * p].hypot(v[2 * p + 1]).ln())
                .collect(),
        );
        self.alpha
            .push(self.along.iter().map(|&k| s.state.alpha[k]).collect());
        self.max_v.push(s.report.max_slip_rate);
        self.fpi.push(s.report.fixed_point_iterations);
        self.solver_its.push(s.report.solver_iterations);
        Ok(rsf::Flow::Continue(()))
    }
}

/// The first time after `after` at which `x` crosses `level` upwards, interpolated linearly
/// in `ln x` between the two samples around the crossing (the definition of the first-slip
/// time in docs/work-precision.md).
pub fn first_crossing(t: &[f64], x: &[f64], level: f64, after: f64) -> Option<f64> {
    let ll = level.ln();
    (1..t.len()).find_map(|i| {
        if t[i] <= after || !(x[i - 1] < level && x[i] >= level) {
            return None;
        }
        let (a, b) = (x[i - 1].ln(), x[i].ln());
        Some(t[i - 1] + (t[i] - t[i - 1]) * (ll - a) / (b - a))
    })
}

/// Start times of the slip events in `x` (the largest slip rate per step): an event starts
/// where `x` rises above `on` and ends where it has fallen back below `off < on` (the
/// library's [`rsf::observe::EventDetector`]).
pub fn event_starts(t: &[f64], x: &[f64], on: f64, off: f64) -> Vec<f64> {
    let mut d = rsf::observe::EventDetector::new(rsf::observe::EventThresholds {
        onset: on,
        end: off,
    })
    .expect("0 < off <= on");
    for (k, (&ti, &xi)) in t.iter().zip(x).enumerate() {
        d.push(k + 1, ti, xi, &[]);
    }
    d.events().iter().map(|e| e.onset_s).collect()
}

/// The observed order `log2((x₁ − x₂)/(x₂ − x₃))` of values at steps τ, τ/2, τ/4.
pub fn observed_order(x: [f64; 3]) -> f64 {
    ((x[0] - x[1]) / (x[1] - x[2])).log2()
}

/// `y += alpha · A x`.
pub fn apply_add(a: &SparseMatrix, alpha: f64, x: &[f64], y: &mut [f64]) {
    spmv_add(a.as_ref(), alpha, x, y);
}

/// `A x`.
pub fn apply(a: &SparseMatrix, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    apply_add(a, 1.0, x, &mut y);
    y
}

/// `xᵀ y`.
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

/// `ϕ'(|v_p|)` of the law at state `alpha`: the friction stress (Pa).
pub fn friction_stress(law: &DieterichRuina, alpha: f64, slip_rate: f64) -> f64 {
    use rsf::friction::ConvexPotential;
    law.potential(alpha).slope(slip_rate)
}

/// A [`PointSeries`] at x0 into `path`: CSV `t_s,u_x0_m,v_x0_mps,max_slip_rate_mps,fpi`.
pub fn point_series<L: FrictionLaw, S: StateLaw, I: VelocityIntegrator>(
    sim: &Simulation<2, L, S, I>,
    path: &Path,
) -> PointSeries<2> {
    let x0 = sim
        .model()
        .nearest_node(&SLIDER_CENTRE)
        .expect("x0 is a vertex");
    PointSeries::new(path, sim.model(), x0, FileMode::Create).expect("series file")
}

/// A [`FrictionalProfile`] into `path` over `[t0, t1]`, every `every`-th step: CSV
/// `t_s,x_m,slip_rate_mps,alpha`.
pub fn frictional_profile(
    path: &Path,
    t0: f64,
    t1: f64,
    every: usize,
) -> Every<FrictionalProfile<2>> {
    let profile = FrictionalProfile::new(path, (t0, t1), FileMode::Create).expect("profile file");
    Every::new(Interval::Steps(every), profile).expect("every >= 1")
}

/// A [`Checkpointer`] of `sim` writing to `path` every `every` steps.
pub fn checkpointer<L: FrictionLaw, S: StateLaw, I: VelocityIntegrator>(
    _sim: &Simulation<2, L, S, I>,
    path: &Path,
    every: usize,
) -> Every<Checkpointer> {
    Every::new(Interval::Steps(every), Checkpointer::new(path)).expect("every >= 1")
}

/// A CSV file of numbers: its header and rows (every field parsed as `f64`), read by the
/// `csv` crate.
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut reader = csv::Reader::from_path(path).expect("readable CSV");
    let header = reader
        .headers()
        .expect("a header line")
        .iter()
        .map(str::to_owned)
        .collect();
    let rows = reader
        .records()
        .map(|r| {
            r.expect("a row")
                .iter()
                .map(|x| x.parse().expect("a number"))
                .collect()
        })
        .collect();
    (header, rows)
}

/// The full state `(u, v, a)` and α after every `every`-th step, with its step index.
#[derive(Debug, Clone, Default)]
pub struct Snapshots {
    /// Keep every `every`-th step.
    pub every: usize,
    /// `(step, kinematics, alpha)`.
    pub states: Vec<(usize, Kinematics, Vec<f64>)>,
}

impl Observer<2> for Snapshots {
    fn observe(&mut self, s: &StepView<'_, 2>) -> rsf::Result<rsf::Flow> {
        if s.report.step % self.every.max(1) == 0 {
            self.states.push((
                s.report.step,
                s.state.kinematics.clone(),
                s.state.alpha.to_vec(),
            ));
        }
        Ok(rsf::Flow::Continue(()))
    }
}

/// Ends a run (through [`rsf::Flow::Break`]) once it has shown step `self.0` (the absolute
/// step number) to the observers: a run stopped through the API, as a user's would be.
pub struct StopAt(pub usize);

impl Observer<2> for StopAt {
    fn observe(&mut self, s: &StepView<'_, 2>) -> rsf::Result<rsf::Flow> {
        Ok(if s.report.step >= self.0 {
            rsf::Flow::Break(())
        } else {
            rsf::Flow::Continue(())
        })
    }
}

/// The end time `time` (s) within 500 000 steps (the tests' bound on a run that would
/// otherwise have collapsed).
pub fn within(time: f64) -> rsf::Until {
    rsf::Until::TimeWithin {
        time,
        max_steps: 500_000,
    }
}

/// The parameter an [`rsf::Error::InvalidParameter`] names.
///
/// # Panics
/// With the error's message if `e` is another error.
pub fn parameter_name(e: rsf::Error) -> String {
    match e {
        rsf::Error::InvalidParameter { name, .. } => name,
        e => panic!("{e}"),
    }
}

/// A fresh directory under the system's temporary directory for one test's files.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rsf-test-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    dir
}

/// [`small_bp1`] of the default BP1, its grid (Δz = 500 m) and the fine one (Δz = 100 m:
/// m = 100, 101 nodes).
pub fn small_bp1_and_fine_grid() -> (
    rsf_scenes::SeasBp1,
    rsf_scenes::SeasBp1Grid,
    rsf_scenes::SeasBp1Grid,
) {
    let (bp1, coarse) = small_bp1(&rsf_scenes::SeasBp1::default());
    let fine = rsf_scenes::SeasBp1Grid {
        dz: 100.0,
        ..coarse
    };
    (bp1, coarse, fine)
}

/// The ℋ-kernel of the fine small BP1's tests on threads and ranks: ε = 1e-6, leaves of 8
/// nodes.
pub const H_LEAF_8: rsf::fault_ode::FaultKernel = rsf::fault_ode::FaultKernel::Hierarchical {
    epsilon: 1e-6,
    leaf_size: 8,
};

/// `builder` (a mesh of the 2 m cube `[-1, 1]³`) with its bottom clamped and the buried
/// square `|y|, |z| ≤ 0.5` in the plane `x = 0` as a fault (normal `+x`: the plus side is
/// `x > 0`).
pub fn with_buried_fault(builder: rsf::ModelBuilder<3>) -> rsf::ModelBuilder<3> {
    builder
        .material(rsf::Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(
            rsf::Part::predicate("bottom", |x| x[2] < -1.0 + 1e-9),
            [0.0; 3],
        )
        .internal_fault_polygon("fault", &plane_x0(0.5, (-0.5, 0.5)))
}

/// The 2 m cube `[-1, 1]³` of `n³` boxes refined `levels` times, with
/// [`with_buried_fault`]'s clamped bottom and buried square fault.
pub fn cube_with_buried_fault(n: usize, levels: usize) -> rsf::ModelBuilder<3> {
    let mesh = rsf::fem::cuboid([-1.0; 3], [2.0; 3], [n + 1; 3]).unwrap();
    with_buried_fault(rsf::ModelBuilder::refined(mesh, levels).unwrap())
}

/// The largest `|a_i − b_i|`.
pub fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// The observers of a resumable run of the slider into `dir`: the series at x0
/// (`x0.csv`), the frictional profile over `window` every 3 steps (`profile.csv`) and a
/// checkpoint every `every` steps (`checkpoint.bin`). With `resume`, `sim` is first
/// restored from that checkpoint and both files are continued from its step.
pub fn resumable_observers(
    sim: &mut Sim,
    dir: &Path,
    window: (f64, f64),
    every: usize,
    resume: bool,
) -> (
    PointSeries<2>,
    Every<FrictionalProfile<2>>,
    Every<Checkpointer>,
) {
    let x0 = sim.model().nearest_node(&SLIDER_CENTRE).unwrap();
    let ckpt = dir.join("checkpoint.bin");
    let mode = if resume {
        let c = rsf::Checkpoint::read(&ckpt).unwrap();
        sim.restore(&c).unwrap();
        FileMode::Resume { step: c.state.step }
    } else {
        FileMode::Create
    };
    let series = PointSeries::new(&dir.join("x0.csv"), sim.model(), x0, mode).unwrap();
    let profile = Every::new(
        Interval::Steps(3),
        FrictionalProfile::new(&dir.join("profile.csv"), window, mode).unwrap(),
    )
    .unwrap();
    let checkpointer = Every::new(Interval::Steps(every), Checkpointer::new(&ckpt)).unwrap();
    (series, profile, checkpointer)
}

/// The rectangle `|y| ≤ y`, `z0 ≤ z ≤ z1` of the plane `x = 0` (m), its corners in the
/// order `internal_fault_polygon` takes: `(−y, z0)`, `(y, z0)`, `(y, z1)`, `(−y, z1)`.
pub fn plane_x0(y: f64, (z0, z1): (f64, f64)) -> [[f64; 3]; 4] {
    [[0.0, -y, z0], [0.0, y, z0], [0.0, y, z1], [0.0, -y, z1]]
}

/// The largest slip (m) of a slip history (per step a row of the frictional nodes' slip
/// lengths), once the fault is seen to slip and, at some step, to be partly stuck (some
/// but not all nodes above 1e-9 of that largest slip); the slipping nodes per step printed.
pub fn partly_stuck_history(history: &[Vec<f64>]) -> f64 {
    let largest = largest_slip(history);
    let slipping: Vec<usize> = history
        .iter()
        .map(|row| row.iter().filter(|&&x| x > 1e-9 * largest).count())
        .collect();
    eprintln!(
        "largest slip {largest:e} m; slipping pairs per step {slipping:?} of {}",
        history[0].len()
    );
    assert!(largest > 0.0);
    assert!(
        slipping.iter().any(|&k| k > 0 && k < history[0].len()),
        "partly stuck at some step"
    );
    largest
}

/// The largest entry of a slip history (0 for none above it).
pub fn largest_slip(history: &[Vec<f64>]) -> f64 {
    history.iter().flatten().fold(0.0f64, |m, &x| m.max(x))
}

/// The largest `|a − b|` of two slip histories, step by step and node by node.
pub fn history_difference(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// `f` run in a rayon pool of `threads` threads.
pub fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

/// Whether two sparse matrices are the same to the bit: shape, pattern and values.
pub fn same_bits(a: &SparseMatrix, b: &SparseMatrix) -> bool {
    a.nrows() == b.nrows()
        && a.ncols() == b.ncols()
        && a.symbolic().col_ptr() == b.symbolic().col_ptr()
        && a.symbolic().row_idx() == b.symbolic().row_idx()
        && a.val()
            .iter()
            .zip(b.val())
            .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// The small BP1 ([`small_bp1`]) made velocity strengthening everywhere (a = 0.025 >
/// b = 0.015) and started off steady state (V_init = V_p/10).
pub fn creeping_bp1() -> (rsf_scenes::SeasBp1, rsf_scenes::SeasBp1Grid) {
    small_bp1(&rsf_scenes::SeasBp1 {
        a0: 0.025,
        v_init: 1e-10,
        ..rsf_scenes::SeasBp1::default()
    })
}

/// How far the fault of `model` (antiplane) is from steady creep at the plate rate: the largest
/// `|V/V_p − 1|` of the slip rates `v`, and the largest `|μ/μ_ss − 1|` of the friction
/// coefficients of `laws` at `v` and the states `alpha` against each node's steady-state
/// friction at V_p (`bp1`'s law at the node's depth).
pub fn steady_creep_errors(
    bp1: &rsf_scenes::SeasBp1,
    model: &rsf::Model<2, 1>,
    v: &[f64],
    alpha: &[f64],
    laws: &[rsf::friction::AsinhLaw],
) -> (f64, f64) {
    let worst_v = v
        .iter()
        .map(|v| (v / bp1.v_p - 1.0).abs())
        .fold(0.0, f64::max);
    let mut worst_tau: f64 = 0.0;
    for (k, &p) in model.frictional_boundary.nodes.iter().enumerate() {
        let law = rsf::friction::AsinhLaw::new(bp1.params(model.vertices[p][1])).unwrap();
        let steady = law.friction_coefficient(bp1.v_p, (bp1.d_c / bp1.v_p).ln());
        let now = laws[k].friction_coefficient(v[k], alpha[k]);
        worst_tau = worst_tau.max((now / steady - 1.0).abs());
    }
    (worst_v, worst_tau)
}

/// TNNMG as the paper runs it but tighter: relative 1e-12 in the energy norm.
pub fn tight_tnnmg() -> rsf::tnnmg::TnnmgOptions {
    rsf::tnnmg::TnnmgOptions {
        stopping: rsf::nonsmooth::Stopping {
            absolute: 0.0,
            relative: 1e-12,
            max_iterations: 200,
        },
        ..rsf::tnnmg::TnnmgOptions::default()
    }
}

/// The internal fault of `s`'s model and the model's Cartesian displacements now and at
/// the start: `(fault, u, u0)`.
///
/// # Panics
/// The model has no internal fault.
pub fn internal_fault_displacements<'a, const D: usize>(
    s: &StepView<'a, D, D>,
) -> rsf::Result<(&'a rsf::model::InternalFault<D>, Vec<f64>, Vec<f64>)> {
    let f = s.model.internal_fault.as_ref().expect("an internal fault");
    let u = s.model.to_cartesian(&s.state.kinematics.u)?;
    let u0 = s.model.to_cartesian(&s.model.initial_displacement)?;
    Ok((f, u, u0))
}

/// At the pair `(mi, pl)` of the internal fault of `s`'s model: the observers' slip and the
/// Cartesian jump of the two sides' displacements since the start, `(u, u0)` from
/// [`internal_fault_displacements`].
pub fn slip_and_jump<const D: usize>(
    s: &StepView<'_, D, D>,
    (u, u0): (&[f64], &[f64]),
    (mi, pl): (usize, usize),
) -> ([f64; D], [f64; D]) {
    let p = s
        .model
        .frictional_boundary
        .nodes
        .binary_search(&mi)
        .unwrap();
    let slip = s.slip(p);
    let jump = std::array::from_fn(|c| {
        (u[D * pl + c] - u0[D * pl + c]) - (u[D * mi + c] - u0[D * mi + c])
    });
    (slip, jump)
}

/// `steps` quasistatic steps of 0.5 s of `model` with Tresca friction of coefficient
/// `mu(x)` at σ̄_n = 5 MPa (no state) and `solver`, observed by `observer`.
pub fn run_tresca_steps<const D: usize>(
    model: rsf::Model<D>,
    mut mu: impl FnMut(&[f64; D]) -> f64,
    solver: SolverKind,
    steps: usize,
    observer: &mut dyn Observer<D>,
) {
    let mut sim = rsf::SimulationBuilder::new(model)
        .friction_at(|x| rsf::friction::Tresca::new(mu(x), 5e6))
        .state_law(rsf::simulation::NoState)
        .initial_state(0.0)
        .integrator(rsf::time::Quasistatic::new())
        .time_step(0.5)
        .solver(solver)
        .build()
        .unwrap();
    sim.run(steps, &mut [observer]).unwrap();
}

/// The builder of a frictionless run of `model` (Tresca with a zero bound, no state) with
/// `integrator`, fixed steps of `tau` (s) and the direct solver.
pub fn frictionless<I: VelocityIntegrator, const D: usize, const C: usize>(
    model: rsf::Model<D, C>,
    integrator: I,
    tau: f64,
) -> rsf::SimulationBuilder<D, rsf::friction::Tresca, rsf::simulation::NoState, I, C> {
    rsf::SimulationBuilder::new(model)
        .friction(rsf::friction::Tresca::new(0.0, 1.0).unwrap())
        .initial_state(0.0)
        .integrator(integrator)
        .time_step(tau)
        .solver(SolverKind::Direct)
}
