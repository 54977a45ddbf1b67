//! What the studies share: the context read from the flags, the scene at a level and
//! step count, the stop times, the log.

use std::path::PathBuf;
use std::time::Instant;

use rsf::{Integrator, SolverKind};
use rsf_scenes::SliderScene;

pub(crate) type Res<T> = Result<T, Box<dyn std::error::Error>>;

pub(crate) struct Ctx {
    pub(crate) out: PathBuf,
    pub(crate) figures: PathBuf,
    pub(crate) level: usize,
    pub(crate) big: bool,
    pub(crate) ref_n: usize,
    pub(crate) mesh_steps: usize,
    pub(crate) energy_steps: usize,
    /// Integrators of the time-step study.
    pub(crate) integrators: Vec<Integrator>,
    /// Solvers of the time-step study.
    pub(crate) solvers: Vec<SolverKind>,
    /// Tolerances of the adaptive study.
    pub(crate) tolerances: Vec<f64>,
    /// Uniform step counts of the adaptive study.
    pub(crate) uniform: Vec<usize>,
    /// State update of the time and adaptive studies' runs (not of their reference).
    pub(crate) state_integrator: rsf::method::StateIntegrator,
}

/// The paper's scene at `level`, τ = T/`steps`, with a fixed point budget of 1000
/// iterations (the paper's 100 fail at the first slip event for N ≤ 2000, where the fixed
/// point contracts only by 0.86–0.94 per iteration).
pub(crate) fn base(level: usize, steps: usize) -> SliderScene {
    SliderScene {
        level,
        steps,
        fixed_point_max_iterations: 1000,
        ..SliderScene::default()
    }
}

/// Stop times: (a), (c) need 0.6 T; (b) needs the first slip event (≤ 0.9 T).
pub(crate) fn window(scene: &SliderScene) -> (f64, f64) {
    (0.6 * scene.end_time_s, 0.9 * scene.end_time_s)
}

pub(crate) fn log(msg: &str) {
    eprintln!("[{:>8.1} s] {msg}", elapsed());
}

pub(crate) fn elapsed() -> f64 {
    static START: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64()
}
