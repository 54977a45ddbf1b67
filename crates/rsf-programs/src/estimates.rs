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
#[cfg(feature = "seas")]
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

pub use crate::guard::PROCESS_BYTES;

// The 3-D finite-element fault models: `seas_bp5 --kernel fe` and `fault_setup_3d`.
//
// Their constants are kept here, in one place, because the build of these models is
// being rewritten (its memory: the assembly, the model builder, the initial equilibrium,
// the condensation); they are fitted to the rows "3-D finite-element models" of
// docs/reliability.md's "Memory estimates" table and must be re-fitted after any change of
// that build. To re-measure, build the examples and run, for each row of the table,
//
//     RSF_MEMORY_REPORT=1 target/release/examples/seas_bp5 --kernel fe --dx DX \
//         --domain-km KM --end-years 0.001 --threads 1 --out /tmp/m
//     RSF_MEMORY_REPORT=1 target/release/examples/fault_setup_3d --dx DX_KM --steps 1
//
// (the guard prints `rsf-memory: … estimate_bytes=E peak_bytes=P` when the run ends, `P`
// the process's `VmHWM`; `/usr/bin/time -v` reports the same peak), take `V` from
// `fe_3d_box_vertices` (the table lists it), fit `FE_3D_BYTES_PER_VERTEX` and
// `FE_3D_FACTOR_BYTES` to `P − PROCESS_BYTES` (check the exponent on the table's factor
// sizes), round up, and commit the table; `tests/memory_estimates.rs` then checks the
// small sizes against them on every CI run.

/// Bytes per vertex of a 3-D finite-element fault model that grow linearly with the mesh:
/// the mesh, the assembled matrices (81 blocks of 3 × 3 per vertex), the model's vectors,
/// the condensation's index maps. Fitted with [`FE_3D_FACTOR_BYTES`] (docs/reliability.md,
/// "Memory estimates"), rounded up.
pub const FE_3D_BYTES_PER_VERTEX: f64 = 12e3;

/// The part of a 3-D model's memory that grows faster than the mesh — the sparse Cholesky
/// factors of the volume (the initial equilibrium's, the condensation's) —
/// `FE_3D_FACTOR_BYTES · V^FE_3D_FACTOR_EXPONENT` bytes. Fitted to measured peaks at
/// 6 669 to 44 689 vertices, rounded up.
pub const FE_3D_FACTOR_BYTES: f64 = 26.0;

/// See [`FE_3D_FACTOR_BYTES`]: the exponent of the factors' growth in the vertices `V`,
/// 5/3 — the equilibrium factor's entries measured 9.0e6, 5.3e7, 3.0e8 and 3.0e9 at 8.5e3,
/// 2.3e4, 6.6e4 and 3.1e5 vertices (BP5's box at Δx = 10, 5, 2.5 and 1 km): a local
/// exponent of 1.5 to 1.8 (AMD's fill on a 3-D mesh; nested dissection would give 4/3).
pub const FE_3D_FACTOR_EXPONENT: f64 = 5.0 / 3.0;

/// Vertices of the graded box of a 3-D fault model (`rsf_scenes::SeasBp5::fe_model`,
/// `fault_setup_3d`): a fault of `length × depth` (m) in the plane `x = 0`, spacing `h` on
/// it, growing by `ratio` to the far faces at `far` (m) — `(2 n(h) − 1)(2 n(length/2) − 1)
/// n(depth)` with `n(u) = rsf::fem::geometric_grading_len(h, u, ratio, far)` (an upper
/// estimate: each `n` at most 2 above the mesh's count).
pub fn fe_3d_box_vertices(h: f64, length: f64, depth: f64, ratio: f64, far: f64) -> f64 {
    let n = |uniform: f64| rsf::fem::geometric_grading_len(h, uniform, ratio, far);
    (2.0 * n(h) - 1.0) * (2.0 * n(length / 2.0) - 1.0) * n(depth)
}

/// Bytes of a 3-D finite-element fault model of `vertices` vertices, built and condensed
/// onto its fault: `FE_3D_BYTES_PER_VERTEX · V + FE_3D_FACTOR_BYTES · V^{5/3}` (the
/// process itself and the fault operator condensed from it are the caller's:
/// [`PROCESS_BYTES`], [`operator_bytes`]).
pub fn fe_3d_memory(vertices: f64) -> f64 {
    FE_3D_BYTES_PER_VERTEX * vertices
        + FE_3D_FACTOR_BYTES * vertices.max(0.0).powf(FE_3D_FACTOR_EXPONENT)
}

/// Bytes of `setup.bin`, the finished Schur-only elimination a run keeps in its folder
/// (`seas_bp5 --kernel fe`, `bp5_pair --kernel fe`; its disk space is held before the
/// elimination, `rsf::direct::CheckpointPolicy`): the file of
/// [`SchurOnlyPlan::checkpoint_bytes_of`](rsf::direct::SchurOnlyPlan::checkpoint_bytes_of)
/// — its packed `S_KK` of the `kept` dofs (the fault's slip unknowns and the watched
/// vertices' dofs) and two carried right-hand sides (the load and the plate velocity) of
/// at most `3 · 2V` free dofs, `vertices` the mesh's before the fault's split duplicates
/// its plane (each vertex at most twice). Measured on BP5's graded box: 2.11 MB at 4 km
/// (this bound 2.83 MB), 20.4 MB at 2 km (22.0 MB; docs/reliability.md, "Round 5").
pub fn setup_file_bytes(kept: f64, vertices: f64) -> f64 {
    rsf::direct::SchurOnlyPlan::checkpoint_bytes_of(kept, 6.0 * vertices, 2.0)
}

/// Bytes of the direct solver of a 3-D slider run (`slider_3d`) beyond
/// `Slider3dScene::BYTES_PER_NODE` — where its solver is the direct one (`--solver direct`,
/// or `auto` with at most `rsf::method::AUTO_DIRECT_MAX_CONDENSED` condensed unknowns):
/// the discrete harmonic extension of every condensed unknown (`8 · 3V · |F|` bytes, a
/// bound: it is formed block by block when large) and the volume's sparse factor
/// ([`FE_3D_FACTOR_BYTES`]` · V^{5/3}`). 0 for TNNMG. Measured: `slider_3d --level 3`
/// (auto: direct, 738 condensed unknowns) peaks at 223 MB, above the 116 MB of 35 kB per
/// node (docs/reliability.md, "Memory estimates").
pub fn slider_3d_direct_bytes(scene: &rsf_scenes::Slider3dScene, nodes: f64) -> f64 {
    let s = &scene.slider;
    let k = 2f64.powi(s.level.min(1000) as i32);
    let nz = scene.width_m.round().max(1.0);
    // Two free components per node of the frictional face (bilateral contact).
    let condensed = 2.0 * (5.0 * k + 1.0) * (nz * k + 1.0);
    let direct = match s.solver {
        rsf::SolverKind::Direct => true,
        rsf::SolverKind::Auto => condensed <= rsf::method::AUTO_DIRECT_MAX_CONDENSED as f64,
        _ => false,
    };
    if direct {
        8.0 * 3.0 * nodes * condensed + FE_3D_FACTOR_BYTES * nodes.powf(FE_3D_FACTOR_EXPONENT)
    } else {
        0.0
    }
}
