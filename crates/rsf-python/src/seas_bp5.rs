//! SEAS BP5-QD from Python (docs/seas-bp5.md): a vertical strike-slip fault in a
//! half-space, two slip components — the run of the program `seas_bp5` with either kernel
//! and its settings ([`SeasBp5Run`]: the same defaults, ranges, options and
//! fingerprint), its files and its run folder ([`FolderKeywords`]).

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use rsf::direct::CheckpointPolicy;
use rsf::fault_ode::{InteriorOrdering, SchurOnlySetup};
use rsf::{Observer, Stepping};
use rsf_scenes::{
    Bp5Condensation, Bp5Kernel, SeasBp5, SeasBp5FaultOde, SeasBp5Run, BP5_SETUP_FILE,
};
use rsf_seas::{SeasBp5Output, SeasSetup, SEAS_BP5_RESUME_LOG, SECONDS_PER_YEAR};

use crate::convert::{choice, scene};
use crate::errors::{invalid, OrPy};
use crate::run_folder::{FolderKeywords, SessionRun};
use crate::scenes::split;
use crate::simulation::Simulation;

/// SEAS BP5-QD (docs/seas-bp5.md, docs/python.md): the run of the Rust program `seas_bp5`
/// with the same settings and defaults (`rsf_scenes::SeasBp5Run`): `kernel` "okada" (a
/// fault alone in a half-space, boundary elements) or "fe" (the finite-element volume
/// condensed onto the fault), `dx` (m, dividing l_f = 100 km and W_f = 40 km),
/// `end_years`, `tolerance`, `epsilon` (the ℋ-matrix's accuracy above 4 096 unknowns),
/// `integrator`, `threads` (default: every core; the same bits for every value),
/// `modeler`, `date`; with `kernel="fe"` also `domain_km` (default 400), `ratio` (1.3),
/// `mesh` "graded" or "tensor", `condensation` "schur-only" (its elimination kept as
/// `setup.bin` in `out`) or "factor", `ordering` "amd" or "nested-dissection" (the
/// default where METIS is built, as this package is by default: feature `metis`),
/// `fault_zone_width_km` with `fault_zone_rigidity`. With `out`, the benchmark's files (ten on-fault and nine
/// off-fault stations, `global.dat`, the profiles, `rupture.dat`, `events.csv` and their
/// resume log) are written there as the program writes them, at the end of every
/// `run`/`advance` call; `overwrite`, `resume`, `allow_change` as for `seas_bp1` (a
/// checkpoint of the program resumes here and the other way round). Other keyword
/// arguments are the scene's parameters, friction included (`a0`, `a_max`, `b0`, `l`,
/// `l_nucleation`, `sigma_n`, `v_init`, `v_i`, `h_s`, `h_t`, `h`, `l_core`, `w`, …, SI
/// units).
#[pyfunction]
#[pyo3(signature = (*, kernel="okada", dx=SeasBp5Run::default().dx, domain_km=None, ratio=None, mesh=None, condensation=None, ordering=None, fault_zone_width_km=None, fault_zone_rigidity=None, end_years=SeasBp5Run::default().end_years, tolerance=SeasBp5Run::default().tolerance, epsilon=SeasBp5Run::default().epsilon, integrator=SeasBp5Run::default().integrator.name(), threads=None, out=None, overwrite=false, resume=None, allow_change=Vec::new(), modeler="rsf", date=None, fault_every=0, **kwargs))]
#[allow(clippy::too_many_arguments)] // Python's keyword arguments
pub(crate) fn seas_bp5(
    kernel: &str,
    dx: f64,
    domain_km: Option<f64>,
    ratio: Option<f64>,
    mesh: Option<&str>,
    condensation: Option<&str>,
    ordering: Option<&str>,
    fault_zone_width_km: Option<f64>,
    fault_zone_rigidity: Option<f64>,
    end_years: f64,
    tolerance: f64,
    epsilon: f64,
    integrator: &str,
    threads: Option<i128>,
    out: Option<PathBuf>,
    overwrite: bool,
    resume: Option<PathBuf>,
    allow_change: Vec<String>,
    modeler: &str,
    date: Option<String>,
    fault_every: i128,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Simulation> {
    let threads = crate::counts::threads(threads)?;
    let fault_every = crate::counts::count(fault_every, "fault_every")?;
    let run = SeasBp5Run {
        kernel: choice("kernel", kernel)?,
        dx,
        domain_km,
        ratio,
        mesh: mesh.map(|m| choice("mesh", m)).transpose()?,
        fault_zone_width_km,
        fault_zone_rigidity,
        condensation: condensation
            .map(|c| choice("condensation", c))
            .transpose()?,
        ordering: ordering
            .map(|o| o.parse().map_err(|e| invalid("ordering", e)))
            .transpose()?,
        end_years,
        tolerance,
        epsilon,
        integrator: integrator
            .parse()
            .map_err(|e: rsf::time::Error| invalid("integrator", e))?,
        ..SeasBp5Run::default()
    };
    // The scene's keywords (SI units), the friction among them, which are the run's
    // settings too.
    let (fields, _) = split(kwargs, &[])?;
    let base: SeasBp5 = scene(&SeasBp5::default(), &fields, "the BP5 scene")?;
    let run = run.with_friction_of(&base);
    run.validate_with(base).py()?;
    let bp5 = run.scene_with(base);
    // The program's default where `ordering` is not given: nested dissection where METIS
    // is built (this package's default feature `metis`), else AMD.
    let run = run.resolved(InteriorOrdering::fastest_built());
    let kernel = run.kernel;
    let folder = FolderKeywords::new(out, overwrite, resume, allow_change);
    let fingerprint = run.fingerprint_with(&bp5, InteriorOrdering::fastest_built());
    // The folder first (another run's refused before anything is computed), as the
    // program's guard does.
    let mut names = SeasBp5Output::file_names();
    names.extend(["events.csv", SEAS_BP5_RESUME_LOG].map(String::from));
    if kernel == Bp5Kernel::Fe && run.condensation() == Bp5Condensation::SchurOnly {
        names.push(BP5_SETUP_FILE.into());
    }
    folder.prepare("seas_bp5", names, &fingerprint)?;
    let setup = run.seas_setup(
        &bp5,
        modeler.to_owned(),
        date.unwrap_or_else(rsf_seas::utc_date_today),
    );
    let options = run.fault_ode_options(&bp5, threads).py()?;
    let (ode, output) = match kernel {
        Bp5Kernel::Okada => okada(&bp5, &run, options, (folder.out.as_ref(), setup))?,
        Bp5Kernel::Fe => volume_run(&bp5, &run, options, (&folder, setup))?,
    };
    let session = SessionRun {
        fingerprint,
        end: end_years * SECONDS_PER_YEAR,
        fault_every,
        program: "seas_bp5",
    };
    folder.simulation(session, ode, move |_| {
        Ok(output.map(|o| o.with_marks_where_runs_end(0)))
    })
}

/// The fault ODE and files (`None` without `out`) of a run.
type OdeAndFiles = (SeasBp5FaultOde, Option<SeasBp5Output>);

/// A fault alone with Okada's half-space operator, as the program runs it on one process;
/// its files in `out` (the body stations' displacement columns of the operator's).
fn okada(
    bp5: &SeasBp5,
    run: &SeasBp5Run,
    options: rsf::fault_ode::FaultOdeOptions,
    (out, setup): (Option<&PathBuf>, SeasSetup),
) -> PyResult<OdeAndFiles> {
    let model = bp5.model(run.dx).py()?;
    let half_space = bp5.half_space(run.epsilon).py()?;
    let (ode, columns) = bp5
        .fault_ode_on_ranks(
            model,
            options,
            &half_space,
            &SeasBp5::body_station_points(),
            None,
        )
        .py()?;
    let output = out
        .map(|out| bp5.output(out, run.dx, columns, setup).py())
        .transpose()?;
    Ok((ode, output))
}

/// The finite-element volume condensed onto the fault, as the program runs it on one
/// process: the Schur-only elimination kept in `out` (another run's removed first, a
/// resume's read), or the whole factor.
fn volume_run(
    bp5: &SeasBp5,
    run: &SeasBp5Run,
    options: rsf::fault_ode::FaultOdeOptions,
    (folder, setup): (&FolderKeywords, SeasSetup),
) -> PyResult<OdeAndFiles> {
    let model = bp5.fe_model(&run.grid(bp5)).py()?;
    let options = run.volume_options(options, 2 * model.frictional_boundary.len());
    let output = folder
        .out
        .as_ref()
        .map(|out| bp5.volume_output(out, &model, run.dx, setup).py())
        .transpose()?;
    let mut ode = match run.condensation() {
        Bp5Condensation::Factor => bp5.fe_fault_ode(model, options).py()?,
        Bp5Condensation::SchurOnly => {
            let watch_vertices = bp5.station_vertices(&model).py()?;
            let checkpoint = match &folder.out {
                Some(out) => {
                    let path = out.join(BP5_SETUP_FILE);
                    if folder.resume.is_none() {
                        // Another run's elimination is not this one's to continue.
                        match std::fs::remove_file(&path) {
                            Err(source) if source.kind() != std::io::ErrorKind::NotFound => {
                                return Err(crate::errors::to_py(rsf::Error::File {
                                    path: path.display().to_string(),
                                    action: "remove",
                                    source,
                                }))
                            }
                            _ => {}
                        }
                    }
                    Some(CheckpointPolicy::new(&path))
                }
                None => None,
            };
            let setup = SchurOnlySetup {
                watch_vertices,
                checkpoint,
                max_bytes: None,
                progress: None,
            };
            bp5.fe_fault_ode_schur_only(model, options, setup).py()?
        }
    };
    if let Some(output) = &output {
        ode.watch_vertices(&output.volume_vertices()).py()?;
    }
    Ok((ode, output))
}
