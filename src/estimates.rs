//! The memory and output of the programs' runs, estimated from their inputs before any
//! work (issue 58; each constant says where it was measured, docs/reliability.md
//! "Estimates"). They are coarse — within a small factor, rounded up — and exist to refuse
//! a run the machine cannot hold, not to predict it.

use rsf_scenes::{steps_bound, SliderScene};

use crate::guard::{Folder, Plan};

/// Nodes of the paper's 2-D slider (the 5 × 1 grid of 1 m cells refined `level` times):
/// `(5·2ʲ + 1)(2ʲ + 1)` (an `f64`: a level of 30 is a number, not an overflow).
pub fn slider_nodes(level: usize) -> f64 {
    let k = 2f64.powi(level.min(1000) as i32);
    (5.0 * k + 1.0) * (k + 1.0)
}

/// Frictional nodes of the paper's 2-D slider at `level`: `5·2ʲ + 1`.
pub fn slider_fault_nodes(level: usize) -> f64 {
    5.0 * 2f64.powi(level.min(1000) as i32) + 1.0
}

/// Bytes per node of a 2-D slider run at level ≤ 7: the peak resident set of
/// `pipping_slider --level 7` (direct solver, one thread: 2.37 GB at 82 689 nodes,
/// 28.7 kB per node; 18.8 kB at level 6, 13.8 kB at level 5), rounded up. The sparse
/// factor's fill grows the bytes per node by about 1.5 per level beyond.
pub const SLIDER_BYTES_PER_NODE: f64 = 30e3;

/// Bytes of the memory of a 2-D slider run of `scene`'s level (the model, the solver and
/// the method, [`SLIDER_BYTES_PER_NODE`], times 1.5 per level above 7).
pub fn slider_memory(scene: &SliderScene) -> f64 {
    let growth = 1.5f64.powi(scene.level.saturating_sub(7).min(1000) as i32);
    slider_nodes(scene.level) * SLIDER_BYTES_PER_NODE * growth
}

/// A one-line description of a slider estimate for a message.
pub fn slider_what(scene: &SliderScene) -> String {
    format!(
        "the slider at level {}: {:.3e} nodes, at most {:.3e} steps of T = {:e} s",
        scene.level,
        slider_nodes(scene.level),
        slider_steps(scene),
        scene.end_time_s
    )
}

/// Steps of a run of `scene` over `[0, T]`: [`steps_bound`] (fixed steps `N + 1`, adaptive
/// `T / tau_min_s + 2`).
pub fn slider_steps(scene: &SliderScene) -> f64 {
    steps_bound(scene, (0.0, scene.end_time_s))
}

/// Bytes a program holds per step it records in memory (a `SliderRun`'s series, the
/// `Recorder`'s step report and the point's displacement and velocity: about 250 bytes),
/// rounded up.
pub const RECORDED_STEP_BYTES: f64 = 400.0;

/// Bytes of one row of a CSV file of numbers: `columns` numbers of at most 25 characters.
pub fn csv_row_bytes(columns: usize) -> f64 {
    25.0 * columns as f64
}

/// Bytes of a PNG figure of the programs (at most 1000 × 1000 pixels of RGB, uncompressed:
/// a bound).
pub const FIGURE_BYTES: f64 = 3e6;

/// Bytes per node of a SEAS model in a fault-ODE or implicit run: BP1's measured
/// `rsf_scenes::SeasBp1::BYTES_PER_NODE` (6.5 kB, the larger of the two methods).
pub const SEAS_BYTES_PER_NODE: f64 = rsf_scenes::SeasBp1::BYTES_PER_NODE;

/// Bytes of a fault operator of `m` unknowns stored dense (`8 m²`) or as an ℋ-matrix
/// (`hierarchical`: `8 m · 64 · log₂ m`, ranks of a few tens per block row and level —
/// docs/scaling.md measures 1e-6 compressions of a few per cent at m ≈ 10⁴).
pub fn operator_bytes(m: f64, hierarchical: bool) -> f64 {
    if hierarchical {
        8.0 * m * 64.0 * m.max(2.0).log2()
    } else {
        8.0 * m * m
    }
}

/// Rows per simulated year of a SEAS station file with the benchmark's thinning
/// (`SeasSampling::default`: every 0.1 yr between events, every 0.1 s during them),
/// assuming at most one event per 10 years lasting at most 100 s: 10 + 100 rows.
pub const SEAS_ROWS_PER_YEAR: f64 = 110.0;

/// Rows per simulated year of a SEAS profile file with the benchmark's thinning (every
/// 5 yr between events, every 1 s during them: 0.2 + 10 under the same assumption).
pub const SEAS_PROFILE_ROWS_PER_YEAR: f64 = 10.2;

/// Bytes of the thinned output of a SEAS run of `years` with `stations` station files of
/// `columns` columns and profile files holding `profile_values` values per row.
pub fn seas_output_bytes(years: f64, stations: f64, columns: usize, profile_values: f64) -> f64 {
    years
        * (SEAS_ROWS_PER_YEAR * stations * csv_row_bytes(columns)
            + SEAS_PROFILE_ROWS_PER_YEAR * 25.0 * profile_values)
        + 2.0 * FIGURE_BYTES
}

/// The plan of a study that runs `scene` once per step count in `counts` (fig6_2_6_3,
/// fig6_4): `series_per_run` recorded series of every run in memory until the figures
/// are drawn, one series file per run and two figures written into `folder`.
pub fn step_study_plan(
    scene: &SliderScene,
    counts: &[usize],
    series_per_run: f64,
    folder: Folder,
) -> Plan {
    let total: f64 = counts.iter().map(|&n| n as f64 + 1.0).sum();
    let memory = slider_memory(scene) + series_per_run * total * RECORDED_STEP_BYTES;
    let output = total * rsf::run_folder::SERIES_ROW_BYTES + 2.0 * FIGURE_BYTES;
    let what = format!("runs of N = {counts:?} at level {}", scene.level);
    Plan::new()
        .memory(memory, "--level, --steps (or --scene)", what.clone())
        .output(output, "--steps", what)
        .folder(folder)
}
