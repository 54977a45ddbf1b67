//! SEAS BP3-QD from Python (docs/seas-bp3.md): a thrust or normal fault dipping under a
//! free surface — the run of the program `seas_bp3` with its settings ([`SeasBp3Run`]:
//! the same defaults, ranges, fault ODE options and fingerprint), its files and its run
//! folder ([`FolderKeywords`]).

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use rsf::Stepping;
use rsf_scenes::{SeasBp1, SeasBp3, SeasBp3Run};
use rsf_seas::{SeasOutput, SeasSampling, SeasSetup, SECONDS_PER_YEAR};

use crate::convert::scene;
use crate::engine::{Engine, Recording};
use crate::errors::{invalid, OrPy};
use crate::run_folder::FolderKeywords;
use crate::scenes::{kernel_choice, split};
use crate::simulation::{End, Simulation};

/// SEAS BP3-QD (docs/seas-bp3.md, docs/python.md): the run of the Rust program `seas_bp3`
/// with the same settings and defaults (`rsf_scenes::SeasBp3Run`): `dip` (degrees, in
/// [1, 90): below 45° the normal fault, else the thrust), `dx` (m, the element size along
/// the fault, at most W_f/4), `domain_km` (km, the box's half-width), `ratio` (the
/// elements' growth), `tolerance` (of the fault ODE), `kernel` "hierarchical" or "dense",
/// `kernel_epsilon`, `integrator`, `threads` (default: every core; the same bits for every
/// value), `end_years` (years), `modeler`, `date`. With `out`, the benchmark's files (the
/// twelve on-fault and eight surface stations, `slip.dat`, `shear_stress.dat`,
/// `normal_stress.dat`, `events.csv` and their resume log) are written there as the program
/// writes them; `overwrite`, `resume`, `allow_change` as for `seas_bp1` (the programs'
/// folder rule, docs/reliability.md "Round 5": a checkpoint of the program resumes here
/// and the other way round). Other keyword arguments are the scene's parameters, BP1's
/// table (`a0`, `a_max`, `b0`, `d_c`, `sigma_n`, …, SI units).
#[pyfunction]
#[pyo3(signature = (*, dip=SeasBp3Run::default().dip, dx=SeasBp3Run::default().dx, domain_km=SeasBp3Run::default().domain_km, ratio=SeasBp3Run::default().ratio, tolerance=SeasBp3Run::default().tolerance, kernel="hierarchical", kernel_epsilon=None, integrator="auto", threads=None, end_years=SeasBp3Run::default().end_years, out=None, overwrite=false, resume=None, allow_change=Vec::new(), modeler="rsf", date=None, fault_every=0, **kwargs))]
#[allow(clippy::too_many_arguments)] // Python's keyword arguments
pub(crate) fn seas_bp3(
    dip: f64,
    dx: f64,
    domain_km: f64,
    ratio: f64,
    tolerance: f64,
    kernel: &str,
    kernel_epsilon: Option<f64>,
    integrator: &str,
    threads: Option<i128>,
    end_years: f64,
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
    let (fields, _) = split(kwargs, &[])?;
    let params: SeasBp1 = scene(&SeasBp1::default(), &fields, "the BP3 scene")?;
    params.validate().py()?;
    let run = SeasBp3Run {
        dip,
        end_years,
        dx,
        domain_km,
        ratio,
        tolerance,
        kernel: kernel_choice(kernel)?,
        kernel_epsilon,
        integrator: integrator
            .parse()
            .map_err(|e: rsf::time::Error| invalid("integrator", e))?,
    };
    run.validate_with(&params).py()?;
    let bp3 = run.scene(params);
    let folder = FolderKeywords::new(out, overwrite, resume, allow_change);
    let fingerprint = run.fingerprint_with(&bp3.params);
    // The folder first (another run's refused before anything is computed), as the
    // program's guard does.
    let fresh = folder.prepare("seas_bp3", SeasBp3::file_names(), &fingerprint)?;
    let model = bp3.model(&run.grid()).py()?;
    let options = run.fault_ode_options(&bp3, threads).py()?;
    let mut ode = bp3.fault_ode(model, options).py()?;
    let t_end = end_years * SECONDS_PER_YEAR;
    let session = folder.session(fingerprint.clone(), t_end, &mut ode)?;
    let mut files: Vec<Box<dyn rsf::Observer<2, 2>>> = Vec::new();
    if let Some(out) = &folder.out {
        let setup = SeasSetup {
            modeler: modeler.to_owned(),
            date: date.unwrap_or_else(rsf_seas::utc_date_today),
            ..bp3.seas_setup(dx, SeasSampling::default())
        };
        let mut output = SeasOutput::for_session(
            &session,
            out,
            ode.model(),
            ode.problem().friction_laws(),
            setup,
            fresh,
        )
        .py()?;
        // The fault ODE computes the surface stations' vertices after every step; their
        // initial row needs them now.
        ode.watch_vertices(&output.surface_vertices()).py()?;
        if session.resumed().is_none() {
            output.write_initial_state(ode.model(), ode.state()).py()?;
        }
        files.push(Box::new(output));
    }
    let engine = Engine::<2, 2, _> {
        sim: ode,
        recording: Recording::new(fault_every).py()?,
        files,
        fingerprint,
        // Every file is checked: a folder whose manifest named no run is the checkpoint's.
        folder: folder.files(&session)?,
    };
    Ok(Simulation::new(
        Box::new(engine),
        Some(End::Time(t_end)),
        "seas_bp3",
    ))
}
