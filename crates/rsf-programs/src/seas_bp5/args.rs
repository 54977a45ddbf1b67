//! The flags of `seas_bp5` and its plan (judged from the flags alone, before any work).

use std::path::PathBuf;

use crate::config::ConfigArgs;
use crate::estimates::{operator_bytes, seas_output_bytes};
use crate::fields::FaultSize;
use crate::guard::{written, AnyError, Limits, Plan};
use clap::Parser;
use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::InteriorOrdering;
use rsf_scenes::{
    Bp5Condensation, Bp5Kernel, SeasBp5, SeasBp5Grid, SeasBp5Mesh, SeasBp5Run, BP5_SETUP_FILE,
};
use rsf_seas::{SeasBp5Output, SEAS_BP5_RESUME_LOG};

/// SEAS BP5-QD with the boundary-element (Okada) half-space operator.
#[derive(Parser)]
#[command(version)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/seas_bp5")]
    pub(super) out: PathBuf,
    /// The run's settings (`rsf_scenes::SeasBp5Run`: these flags, or `--config`'s keys;
    /// Python's `rsf.seas_bp5` keywords), the description's friction among them.
    #[command(flatten)]
    pub(crate) settings: SeasBp5Run,
    #[command(flatten)]
    config: ConfigArgs,
    /// `fe`: print each set-up stage's own peak memory (the process's peak is reset before
    /// every stage, so `/usr/bin/time -v` then reports the last stage's) instead of the
    /// peak so far.
    #[arg(long)]
    pub(super) stage_peaks: bool,
    /// Threads of each evaluation (the same bits for every value). Default: every core
    /// of the machine.
    #[arg(long, default_value_t = rsf::Parallelism::available_cores())]
    pub(super) threads: usize,
    #[command(flatten)]
    pub(super) header: crate::SeasHeaderArgs,
    #[command(flatten)]
    pub(super) run: crate::ResumeArgs,
    /// `--hdf5 N`: the fault's fields (crates/rsf-hdf5's `seas_bp5`).
    #[command(flatten)]
    pub(crate) fields: crate::fields::FieldArgs,
    /// Replace the files of an earlier run in `--out`.
    #[arg(long)]
    pub(super) overwrite: bool,
    #[command(flatten)]
    pub(super) limits: Limits,
}

/// The files a run writes into `--out`.
fn outputs() -> Vec<String> {
    let mut outputs = SeasBp5Output::file_names();
    outputs.extend(
        [
            "events.csv",
            SETUP_FILE,
            "summary.json",
            "overview.png",
            "checkpoint.bin",
            SEAS_BP5_RESUME_LOG,
        ]
        .map(String::from),
    );
    outputs
}

/// The volume's ordering where `--ordering` is not given: nested dissection where METIS
/// is built (this program's choice, `rsf_metis::is_available`, which rsf-scenes cannot
/// see: the settings hold `None`, "the front end's default"), else AMD.
pub(super) fn default_ordering() -> InteriorOrdering {
    if rsf_metis::is_available() {
        InteriorOrdering::NestedDissection
    } else {
        InteriorOrdering::Amd
    }
}

impl Args {
    /// Refuses `--stage-peaks` without `--kernel fe` (the Okada kernel has no volume: it
    /// would be ignored; the settings' own are refused by their check).
    pub(super) fn refuse_volume_flags_without_volume(&self) -> Result<(), AnyError> {
        if self.settings.kernel == Bp5Kernel::Okada && self.stage_peaks {
            return Err(
                "--stage-peaks: a setting of the finite-element kernel: it needs \
                        --kernel fe (the Okada kernel has no volume), without it it would be \
                        ignored"
                    .into(),
            );
        }
        Ok(())
    }

    /// `--domain-km` (km) and `--ratio` of the finite-element kernel, or their defaults.
    pub(super) fn box_size(&self) -> (f64, f64) {
        (self.settings.domain_km(), self.settings.ratio())
    }

    /// What a checkpoint continues: the scene and what changes the trajectory (the plan's
    /// too: a checkpoint is checked against it before the folder changes) — the
    /// settings' fingerprint, which the Python package's `rsf.seas_bp5` computes too.
    pub(super) fn fingerprint(&self, bp5: &SeasBp5) -> Fingerprint {
        self.settings.fingerprint_with(bp5, default_ordering())
    }

    /// The run's settings as it runs (the volume's defaults and the ordering resolved,
    /// [`SeasBp5Run::resolved`]).
    pub(super) fn resolved(&self) -> SeasBp5Run {
        self.settings.resolved(default_ordering())
    }

    /// `--ordering`, or its default.
    pub(super) fn ordering(&self) -> InteriorOrdering {
        self.settings.ordering_or(default_ordering())
    }

    /// The scene: BP5 with the friction of the flags and the fault zone of
    /// `--fault-zone-width-km` and `--fault-zone-rigidity` if given (checked by the plan).
    ///
    /// # Errors
    /// The scene's checks.
    pub(super) fn scene(&self) -> Result<SeasBp5, AnyError> {
        let bp5 = self.settings.scene();
        crate::cli::for_fields(&crate::cli::FE_GRID_FLAGS, bp5.validate())?;
        Ok(bp5)
    }

    /// `--condensation` or its default.
    pub(super) fn condensation(&self) -> Bp5Condensation {
        self.settings.condensation()
    }

    /// The finite-element grid of the flags: the fault zone's slab meshed at `--dx`.
    pub(super) fn grid(&self, bp5: &SeasBp5) -> SeasBp5Grid {
        self.settings.grid(bp5)
    }

    /// The memory (bytes) of Okada's kernel on `bp5`'s fault of `m` slip unknowns: the
    /// operator (dense up to 4 096 unknowns, an ℋ-matrix beyond), the table of distinct
    /// source–receiver pairs it is built from (48 bytes each, if tabulated) and the body
    /// stations' columns.
    fn okada_memory(&self, bp5: &SeasBp5, m: f64) -> f64 {
        let dx = self.settings.dx;
        let (ns, nd) = (bp5.l_f / dx, bp5.w_f / dx);
        let pairs = (2.0 * ns - 1.0) * nd * nd;
        let table = if pairs <= rsf::halfspace::TABLE_MAX_PAIRS as f64 {
            48.0 * pairs
        } else {
            0.0
        };
        // The ℋ-matrix of the half-space and its set-up: three times the generic
        // budget of `operator_bytes` (measured: 163 MB peak at m = 8 000, Δx = 1 km;
        // docs/reliability.md, "Memory estimates").
        let operator = if m > 4096.0 {
            3.0 * operator_bytes(m, true)
        } else {
            operator_bytes(m, false)
        };
        operator + table + 9.0 * 3.0 * 8.0 * m
    }

    /// Refuses `--ordering nested-dissection` in a build without METIS.
    ///
    /// # Errors
    /// `--ordering`, naming the feature that builds METIS.
    fn check_ordering_built(&self) -> Result<(), AnyError> {
        if self.ordering() == InteriorOrdering::NestedDissection && !rsf_metis::is_available() {
            return Err(crate::guard::refuse(
                "--ordering",
                "nested-dissection",
                "needs METIS, which this build lacks: build with `--features metis`",
            ));
        }
        Ok(())
    }
}

crate::seas_args::configured_program!(Args, "seas_bp5");

impl Args {
    /// The plan of the checked settings.
    fn planned(&self) -> Result<Plan, AnyError> {
        let run = &self.settings;
        let bp5 = self.scene()?;
        let cells = bp5.cells(run.dx).map_err(|e| self.config.named(e))?.len() as f64;
        self.header.check()?;
        let m = 2.0 * cells;
        let (domain_km, ratio) = self.box_size();
        self.refuse_volume_flags_without_volume()?;
        self.check_ordering_built()?;
        // setup.bin, the Schur-only elimination kept in --out (0 without it).
        let mut setup_file = 0.0;
        let memory = match run.kernel {
            // The fault alone (Args::okada_memory).
            Bp5Kernel::Okada => self.okada_memory(&bp5, m),
            Bp5Kernel::Fe => {
                let (h, far) = (run.dx, domain_km * 1e3);
                // The dofs the elimination keeps: the fault's nodes (the rate-and-state
                // region's grid, edges included), two slip unknowns each, and the off-fault
                // stations' vertices, three dofs each.
                let nodes = (bp5.l_f / run.dx + 1.0) * (bp5.w_f / run.dx + 1.0);
                let kept = 2.0 * nodes + 3.0 * SeasBp5::body_station_points().len() as f64;
                let (memory, vertices) = match run.mesh() {
                    SeasBp5Mesh::Tensor | SeasBp5Mesh::TensorMirrored => {
                        // The tensor grid in closed form, its model and factor
                        // (crate::estimates::fe_3d_memory: the constants fitted to measured
                        // peaks, issue 74), and the condensed operator.
                        let vertices =
                            crate::estimates::fe_3d_box_vertices(h, bp5.l_f, bp5.w_f, ratio, far);
                        (
                            crate::estimates::fe_3d_memory(vertices)
                                + operator_bytes(m, m > 4096.0),
                            vertices,
                        )
                    }
                    SeasBp5Mesh::Graded => {
                        // The fewest vertices the mesh can have, by arithmetic before
                        // anything is built (issue 87: `--domain-km 1e4` built 62.5 million
                        // cubes in 54 s).
                        let fewest = graded_mesh_fewest_vertices(&self.grid(&bp5), domain_km)?;
                        // The set-up's peak as measured on the graded mesh: with nested
                        // dissection fitted to the vertices and the kept dofs
                        // (graded_schur_only_nd_peak); AMD's Schur-only elimination grows like
                        // vertices^1.6, the whole factor like vertices^1.9 (docs/seas-bp5.md,
                        // "The volume at the description's resolution").
                        let nested = self.ordering() == InteriorOrdering::NestedDissection;
                        let condensation = self.condensation();
                        let peak = |vertices: f64| match condensation {
                            Bp5Condensation::SchurOnly if nested => {
                                graded_schur_only_nd_peak(vertices, kept)
                            }
                            Bp5Condensation::SchurOnly => {
                                SCHUR_ONLY_PEAK_AT_1_KM
                                    * (vertices / GRADED_VERTICES_AT_1_KM).powf(1.6)
                                    + operator_bytes(m, m > 4096.0)
                            }
                            Bp5Condensation::Factor => {
                                GRADED_PEAK_AT_4_KM * (vertices / GRADED_VERTICES_AT_4_KM).powf(1.9)
                                    + operator_bytes(m, m > 4096.0)
                            }
                        };
                        // Below 1 km, or in a large box, the mesh itself takes seconds (8 s
                        // at 500 m; 13 s for a 2 900 km box at 2 km): a run whose estimate
                        // from the fewest vertices its mesh can have is already above the
                        // limit is refused on that bound, unmeshed. The root cubes' grid
                        // alone has at least as many vertices as cubes.
                        let limit = self.limits.max_memory_gb * 1e9;
                        match fewest {
                            fewest if peak(fewest) > limit => (peak(fewest), fewest),
                            _ => {
                                // The graded mesh's vertices, counted from its octree
                                // without making the mesh.
                                let vertices = crate::cli::for_fields(
                                    &crate::cli::FE_GRID_FLAGS,
                                    bp5.fe_mesh_vertices(&self.grid(&bp5)),
                                )? as f64;
                                (peak(vertices), vertices)
                            }
                        }
                    }
                };
                if self.condensation() == Bp5Condensation::SchurOnly {
                    setup_file = crate::estimates::setup_file_bytes(kept, vertices);
                }
                memory
            }
        };
        // Ten fault stations, nine body stations and global.dat; the four profiles (slip
        // and stress along dip and along strike: a row holds a column or a row of the
        // grid); rupture.dat (one row per cell, once).
        let (along_strike, along_dip) = (bp5.l_f / run.dx, bp5.w_f / run.dx);
        let output = seas_output_bytes(run.end_years, 20.0, 13, 2.0 * (along_strike + along_dip))
            + cells * rsf::run_folder::SERIES_ROW_BYTES;
        let plan = Plan::new()
            .memory(
                memory,
                "--dx, --kernel, --domain-km, --ratio",
                format!("BP5 on dx = {:e} m: {cells} cells", run.dx),
            )
            .output(
                output,
                "--end-years, --dx",
                format!("{} years of the benchmark's files", written(run.end_years)),
            )
            .output(
                setup_file,
                "--dx, --domain-km, --ratio",
                format!("the elimination kept in {SETUP_FILE}"),
            );
        // The fault's fields (--hdf5): a node per grid point of the rate-and-state region,
        // its cells quadrilaterals (a bound for both kernels).
        let nodes = (along_strike + 1.0) * (along_dip + 1.0);
        let fault = FaultSize::of(nodes, (along_strike * along_dip, 4.0));
        self.flags()
            .plan(plan, outputs(), self.fingerprint(&bp5), fault)
    }
}

/// The fewest vertices the graded mesh of `grid` (`domain_km` its `--domain-km`) can have,
/// by arithmetic alone, nothing built: the octree's root cubes
/// ([`SeasBp5::graded_root_cubes`]; its grid has at least as many vertices as cubes) and,
/// below 1 km, [`graded_vertices_at_least`]. Shared by the plans of `seas_bp5` and
/// `bp5_pair` (whose mesh, refined towards two planes, has more).
///
/// # Errors
/// `--domain-km` refused when the root cubes alone exceed the mesh's cell limit.
pub(crate) fn graded_mesh_fewest_vertices(
    grid: &SeasBp5Grid,
    domain_km: f64,
) -> Result<f64, AnyError> {
    let cubes = SeasBp5::graded_root_cubes(grid);
    let most = rsf_scenes::SEAS_BP5_GRADED_MAX_CELLS as f64;
    if 48.0 * cubes > most {
        return Err(crate::guard::refuse(
            "--domain-km",
            crate::guard::number(domain_km),
            &format!(
                "the graded mesh's box holds {cubes:.3e} root cubes at --dx {}, up to {:.3e} \
                 cells before any refinement, above the mesh's limit of {most:e}: a smaller \
                 --domain-km (or a larger --dx)",
                crate::guard::number(grid.dx),
                48.0 * cubes
            ),
        ));
    }
    Ok(graded_vertices_at_least(grid.dx, domain_km, grid.ratio)
        .unwrap_or(0.0)
        .max(cubes))
}

/// A lower bound of the graded mesh's vertices at `dx` (m) below 1 km, for a box of at
/// least the default half-width (400 km) graded by at most the default ratio (1.3), the
/// sizes of the counts measured (`None` otherwise: a smaller box or a faster grading has
/// fewer vertices): the count at 1 km grown like `dx^-1.6`. Measured from 1 km to 500 m the
/// count grows like `dx^-1.62` (86 710 to 266 764 vertices) and faster below, where the
/// fine cells around the fault plane, a surface, take the larger share (`dx^-2` in the
/// limit); a fault zone only adds vertices.
pub(crate) fn graded_vertices_at_least(dx: f64, domain_km: f64, ratio: f64) -> Option<f64> {
    (dx < 1000.0 && domain_km >= 400.0 && ratio <= 1.3)
        .then(|| GRADED_VERTICES_AT_1_KM * (1000.0 / dx).powf(1.6))
}

/// The set-up's peak (bytes) of `--kernel fe` on the graded mesh at 4 km and its vertices
/// (measured: docs/three-d.md, "BP5 on the graded mesh"), the anchor of its estimate.
const GRADED_PEAK_AT_4_KM: f64 = 287e6;
/// See [`GRADED_PEAK_AT_4_KM`].
const GRADED_VERTICES_AT_4_KM: f64 = 7701.0;

/// The whole run's peak (bytes) of `--kernel fe` with the Schur-only elimination on the
/// graded mesh (octree) at 1 km, 86 710 vertices: measured 7.3 GB (the elimination's
/// stage, AMD EPYC; docs/seas-bp5.md), with a margin of 1.25 — the anchor of its estimate,
/// which at 2 km (33 142 vertices) gives 1.96 GB against the measured 1.55 GB.
const SCHUR_ONLY_PEAK_AT_1_KM: f64 = 1.25 * 7.30e9;
/// See [`SCHUR_ONLY_PEAK_AT_1_KM`].
const GRADED_VERTICES_AT_1_KM: f64 = 86_710.0;

/// The vertices of the graded mesh at 500 m (the default box and grading), the one size
/// below 1 km with a measured count; its run with nested dissection peaked at 11.49 GB
/// (AMD EPYC; docs/three-d.md, "On BP5's graded box"). The tests' anchor of
/// [`graded_vertices_at_least`].
#[cfg(test)]
const GRADED_VERTICES_AT_500_M: f64 = 266_764.0;

/// The whole run's peak (bytes, the process's [`crate::guard::PROCESS_BYTES`] not
/// included) of `--kernel fe` with the Schur-only elimination and nested dissection on
/// the graded mesh of `vertices` vertices (before the fault's split), keeping `kept` dofs
/// (the fault's slip unknowns and the stations' dofs):
/// [`GRADED_ND_BYTES_PER_VERTEX`]` · V + `[`GRADED_ND_BYTES_PER_KEPT_SQUARED`]` · kept²` —
/// the model and the elimination's fronts away from the fault grow with the mesh, the
/// Schur complement (`kept × kept`, packed, then the run's operator built from it) and
/// the fronts of the separators that cross the fault's fine region with the fault's
/// unknowns, whatever the volume. Fitted to the peaks of 13 runs over `--dx` 4, 2, 1 km,
/// `--ratio` 1.05 to 2 and `--domain-km` 100 and 400 (docs/reliability.md, "Memory
/// estimates": the estimate, the process included, is 1.11 to 1.72 times each peak; two
/// threads peak within 8 % of one, the estimate 1.07 times the closest such peak), and
/// above the 11.49 GB measured at 500 m (17.1 GB: `--dx 500` now needs `--max-memory-gb
/// 18`). Boxes beyond 400 km are an extrapolation. Where the fit and the tests below
/// disagree after a change of the build, re-measure the table.
pub fn graded_schur_only_nd_peak(vertices: f64, kept: f64) -> f64 {
    GRADED_ND_BYTES_PER_VERTEX * vertices + GRADED_ND_BYTES_PER_KEPT_SQUARED * kept * kept
}

/// See [`graded_schur_only_nd_peak`]: bytes per vertex, fitted to the 4 km runs (kept
/// dofs 599: 14.9 kB per vertex from 3 926 to 82 530 vertices), rounded up.
pub const GRADED_ND_BYTES_PER_VERTEX: f64 = 16e3;
/// See [`graded_schur_only_nd_peak`]: bytes per kept dof squared, the largest of the 2 km
/// and 1 km runs' residuals above the vertices' share (4.7 to 12.3; 7.1 at 500 m), rounded
/// up — the packed `S` (4 bytes) and the dense operator built from it (8 bytes, up to
/// 4 096 unknowns) are 12 on their own.
pub const GRADED_ND_BYTES_PER_KEPT_SQUARED: f64 = 12.0;

/// The file of the Schur-only elimination's checkpoints in `--out` (its finished state
/// kept: a `--resume` of the run reads it instead of eliminating again).
pub(super) const SETUP_FILE: &str = BP5_SETUP_FILE;

#[cfg(test)]
mod tests {
    use super::*;

    /// The bound that refuses a run unmeshed stays below the vertices measured at 500 m
    /// (the one size below 1 km with a measured count), so no run the mesh would admit is
    /// refused on it there.
    #[test]
    fn the_unmeshed_bound_is_below_the_measured_count() {
        let at_500_m = graded_vertices_at_least(500.0, 400.0, 1.3).unwrap();
        assert!(at_500_m <= GRADED_VERTICES_AT_500_M, "{at_500_m}");
        assert!(at_500_m > 0.95 * GRADED_VERTICES_AT_500_M, "{at_500_m}");
        assert_eq!(graded_vertices_at_least(1000.0, 400.0, 1.3), None);
        // Boxes with fewer vertices than the measured ones have no bound.
        assert_eq!(graded_vertices_at_least(500.0, 100.0, 1.3), None);
        assert_eq!(graded_vertices_at_least(500.0, 400.0, 2.0), None);
    }
}

#[cfg(test)]
mod setup_file_tests {
    use super::*;
    use crate::guard::{parse_from, Program};

    /// The plan of `seas_bp5` with `flags` after `--kernel fe --dx 4000 --end-years 1e-6`.
    fn plan(flags: &[&str]) -> Plan {
        let args = [
            "seas_bp5",
            "--kernel",
            "fe",
            "--dx",
            "4000",
            "--end-years",
            "1e-6",
        ];
        let (args, _) = parse_from::<Args, _, _>(args.iter().chain(flags)).unwrap();
        args.plan().unwrap()
    }

    /// The plan's output holds `setup.bin` (issue 87: it was in no estimate): its share —
    /// the Schur-only plan's output less the whole factor's, which keeps no file — is at
    /// least the size of the file a Schur-only elimination of the same model writes (as the
    /// run does: the stations' vertices watched, two right-hand sides), and at most twice it.
    #[test]
    fn the_output_estimate_holds_the_setup_file_written() {
        let share = plan(&[]).output_bytes() - plan(&["--condensation", "factor"]).output_bytes();
        let args = parse_from::<Args, _, _>(["seas_bp5", "--kernel", "fe", "--dx", "4000"])
            .unwrap()
            .0;
        let bp5 = args.scene().unwrap();
        let model = bp5.fe_model(&args.grid(&bp5)).unwrap();
        let dir = std::env::temp_dir().join(format!("rsf-setup-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(SETUP_FILE);
        let mut options = bp5.fault_ode_options(1e-6).unwrap();
        options.ordering = args.ordering();
        let setup = rsf::fault_ode::SchurOnlySetup {
            watch_vertices: bp5.station_vertices(&model).unwrap(),
            checkpoint: Some(rsf::direct::CheckpointPolicy::new(&path)),
            max_bytes: None,
            progress: None,
        };
        bp5.fe_fault_ode_schur_only(model, options, setup).unwrap();
        let written = std::fs::metadata(&path).unwrap().len() as f64;
        std::fs::remove_dir_all(&dir).ok();
        assert!(
            share >= written && share <= 2.0 * written,
            "estimated {share} bytes, written {written}"
        );
    }
}

#[cfg(test)]
mod estimate_tests {
    use super::*;
    use crate::guard::{parse_from, Program, PROCESS_BYTES};

    /// The measured peaks (`/usr/bin/time -v`, bytes) of `seas_bp5 --kernel fe --dx DX
    /// --ratio R --domain-km KM --end-years 1e-6 --threads 1` (the Schur-only elimination,
    /// nested dissection; release build, AMD EPYC, 2 cores shared, 2026-11-29;
    /// docs/reliability.md, "Memory estimates"): `(dx, ratio, domain_km, vertices of the
    /// mesh, kept dofs, peak)`. Data from this machine, not from the code under test.
    const MEASURED: [(f64, f64, f64, f64, f64, f64); 13] = [
        (4000.0, 1.05, 100.0, 82_530.0, 599.0, 1_247_969_280.0),
        (4000.0, 1.3, 100.0, 10_554.0, 599.0, 158_998_528.0),
        (4000.0, 1.3, 400.0, 14_458.0, 599.0, 226_512_896.0),
        (4000.0, 2.0, 100.0, 3_926.0, 599.0, 76_136_448.0),
        (4000.0, 2.0, 400.0, 5_699.0, 599.0, 100_265_984.0),
        (2000.0, 1.3, 100.0, 28_944.0, 2169.0, 506_388_480.0),
        (2000.0, 1.3, 400.0, 33_142.0, 2169.0, 566_296_576.0),
        (2000.0, 2.0, 100.0, 10_412.0, 2169.0, 194_977_792.0),
        (2000.0, 2.0, 400.0, 12_185.0, 2169.0, 221_249_536.0),
        (1000.0, 1.3, 100.0, 82_239.0, 8309.0, 1_849_921_536.0),
        (1000.0, 1.3, 400.0, 86_710.0, 8309.0, 1_977_393_152.0),
        (1000.0, 2.0, 100.0, 34_105.0, 8309.0, 938_266_624.0),
        (1000.0, 2.0, 400.0, 35_878.0, 8309.0, 954_040_320.0),
    ];

    /// The graded mesh's estimate (nested dissection, Schur-only) is above every measured
    /// peak and at most 2.5 times it, row by row; the plan counts the vertices and kept
    /// dofs of the table (the mesh of the flags), so that the estimate the guard compares
    /// is this one.
    #[test]
    fn the_graded_estimate_bounds_the_measured_peaks_within_a_factor_2_5() {
        for (dx, ratio, km, vertices, kept, peak) in MEASURED {
            let estimate = PROCESS_BYTES + graded_schur_only_nd_peak(vertices, kept);
            let ratio_to_peak = estimate / peak;
            assert!(
                (1.0..=2.5).contains(&ratio_to_peak),
                "--dx {dx} --ratio {ratio} --domain-km {km}: estimate {estimate:.3e}, peak \
                 {peak:.3e}"
            );
        }
        // The plan's own count at one small row (4 km, ratio 2, 100 km).
        let args = [
            "seas_bp5",
            "--kernel",
            "fe",
            "--dx",
            "4000",
            "--ratio",
            "2",
            "--domain-km",
            "100",
        ];
        let plan = parse_from::<Args, _, _>(args).unwrap().0.plan().unwrap();
        let (_, _, _, vertices, kept, _) = MEASURED[3];
        let expected = PROCESS_BYTES + graded_schur_only_nd_peak(vertices, kept);
        assert_eq!(plan.memory_bytes(), expected);
    }

    /// The plans of the largest boxes (`--domain-km` 1e4, the range's end, and the largest
    /// the octree's root cubes admit) at every `--dx` the graded mesh takes: each returns —
    /// refused naming the flag, or admitted — with the estimate the guard judges; the
    /// time of each is printed, not asserted. A plan meshes only where the estimate from
    /// the fewest vertices its box can have is within the limit, so no plan here builds
    /// more than the bound allows: an admitted one is within `--max-memory-gb`.
    #[test]
    fn the_plans_of_the_largest_boxes_return_with_their_estimates() {
        let dx = [
            250.0, 500.0, 1000.0, 2000.0, 4000.0, 5000.0, 10_000.0, 20_000.0,
        ];
        plans_of_the_largest_boxes::<Args>(&dx);
    }
}

/// Plans `P --kernel fe --dx DX --domain-km KM` for every `dx` at `--domain-km` 1e4 (the
/// flag's range's end) and the largest box the graded octree's root cubes admit (its root
/// cube `dx` doubled up to 64 km, at most `48 (2n)² n` cells before refinement within the
/// mesh's limit): asserts each is refused naming `--domain-km` or `--dx`, or admitted
/// within the default `--max-memory-gb`; prints each one's time (not asserted: no timed
/// tests). Shared by the tests of `seas_bp5` and `bp5_pair`.
#[cfg(test)]
pub(crate) fn plans_of_the_largest_boxes<P: crate::guard::Program>(dxs: &[f64]) {
    for &dx in dxs {
        let root = dx * (64e3 / dx).log2().floor().max(0.0).exp2();
        let most = rsf_scenes::SEAS_BP5_GRADED_MAX_CELLS as f64 / 192.0;
        for km in [1e4, most.cbrt().floor() * root / 1e3] {
            let (dx_s, km_s) = (dx.to_string(), km.to_string());
            let args = [
                P::NAME,
                "--kernel",
                "fe",
                "--dx",
                &dx_s,
                "--domain-km",
                &km_s,
            ];
            let program = crate::guard::parse_from::<P, _, _>(args).unwrap().0;
            let clock = std::time::Instant::now();
            let verdict = program
                .plan()
                .and_then(|p| p.check(program.limits()).map(|()| p));
            let seconds = clock.elapsed().as_secs_f64();
            match &verdict {
                Ok(p) => assert!(p.memory_bytes() <= 16e9, "{args:?}"),
                Err(e) => {
                    let e = e.to_string();
                    assert!(e.contains("--domain-km") || e.contains("--dx"), "{e}")
                }
            }
            println!(
                "{} --kernel fe --dx {dx_s} --domain-km {km_s}: {seconds:.3} s, {}",
                P::NAME,
                verdict.map_or_else(
                    |e| format!("refused: {e}"),
                    |p| format!("admitted at {:.3e} bytes", p.memory_bytes())
                )
            );
        }
    }
}
