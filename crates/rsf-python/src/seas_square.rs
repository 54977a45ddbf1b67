//! SEAS BP7-QD and BP8-QD from Python (docs/seas-bp7.md, docs/seas-bp8.md): the runs of the
//! programs `seas_bp7` and `seas_bp8`, their settings the programs' run configurations
//! ([`SeasBp7Run`], [`SeasBp8Run`]: the keyword arguments are the struct's fields, read
//! through its serde form — the same names, defaults, ranges and fingerprint as the flags
//! and a `--config` file), their files and their run folder ([`FolderKeywords`]).

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use rsf::checkpoint::Fingerprint;
use rsf_scenes::{RunConfig, SeasBp7Run, SeasBp8, SeasBp8Run};
use rsf_seas::{SeasBp5Output, SEAS_BP7_RESUME_LOG, SEAS_BP8_RESUME_LOG};

use crate::errors::OrPy;
use crate::run_folder::{FolderKeywords, SessionRun};
use crate::scenes::split;
use crate::simulation::Simulation;

/// The run's keywords beside its settings: the folder, threads, the files' headers and
/// the recording.
struct Common {
    folder: FolderKeywords,
    threads: usize,
    modeler: String,
    date: String,
    fault_every: usize,
}

/// The run configuration `C` of the keyword arguments `settings` (its fields; defaults
/// `C::default()`), validated: an unknown keyword, a value of the wrong type or out of
/// its range refused naming the keyword.
fn settings_of<C: RunConfig>(settings: Option<&Bound<'_, PyDict>>, what: &str) -> PyResult<C> {
    let (fields, _) = split(settings, &[])?;
    let run: C = crate::convert::scene(&C::default(), &fields, what)?;
    run.validate().py()?;
    Ok(run)
}

/// A `#[pyfunction]` `$name` (its docs the doc comments given) taking the keywords every
/// square run takes — `out`, `overwrite`, `resume`, `allow_change`, `threads`, `modeler`,
/// `date`, `fault_every` — and the settings as `**settings`: the keywords checked
/// ([`Common::new`]), the settings read (`$what` in messages) and the folder prepared for
/// the program `$name`'s `$files` and resume log `$log` ([`Common::prepare`]), then
/// `$run(common, run, fingerprint)`.
macro_rules! square_run {
    ($(#[$doc:meta])* $name:ident => $run:ident, ($what:expr, $files:expr, $log:expr)) => {
        $(#[$doc])*
        #[pyfunction]
        #[pyo3(signature = (*, out=None, overwrite=false, resume=None, allow_change=Vec::new(), threads=1, modeler="rsf", date=None, fault_every=0, **settings))]
        #[allow(clippy::too_many_arguments)] // Python's keyword arguments
        pub(crate) fn $name(
            out: Option<PathBuf>,
            overwrite: bool,
            resume: Option<PathBuf>,
            allow_change: Vec<String>,
            threads: i128,
            modeler: &str,
            date: Option<String>,
            fault_every: i128,
            settings: Option<&Bound<'_, PyDict>>,
        ) -> PyResult<Simulation> {
            let folder = FolderKeywords::new(out, overwrite, resume, allow_change);
            let common = Common::new(folder, (threads, fault_every), (modeler, date))?;
            let (run, fingerprint) =
                common.prepare((settings, $what), stringify!($name), ($files, $log))?;
            $run(common, run, fingerprint)
        }
    };
}

square_run!(
    /// SEAS BP7-QD-A/S (docs/seas-bp7.md, docs/python.md): the run of the Rust program
    /// `seas_bp7`. The settings are keyword arguments with the program's names, defaults and
    /// ranges (`rsf_scenes::SeasBp7Run`): `kernel` "bem" (the whole space's boundary
    /// elements, the default) or "fe" (a finite-element box: `domain_km`, its half-width, km,
    /// default 6.4; `ratio`, its grading, default 1.2), `law` "aging" or "slip", `end_years` (years of
    /// 365.25 days, default 10), `dx` (m, dividing 800 m; default 10), `d_rs` (mm, default
    /// 0.5), `tolerance` (default 1e-7), `station_interval` (s; 0, the default: a row every
    /// accepted step), `integrator` ("auto", "rkc", "rosenbrock", "dormand-prince",
    /// "bogacki-shampine"). `threads`, `modeler`, `date` (`YYYY-MM-DD`, default today);
    /// `fault_every` records the fault's fields every N steps. With `out`, the benchmark's
    /// files are written there as the program writes them, at the end of every
    /// `run`/`advance` call; `overwrite`, `resume`, `allow_change` as for `seas_bp1` (a
    /// checkpoint of the program resumes here and the other way round, where its files were
    /// written at the checkpoint's step).
    seas_bp7 => run_bp7,
    ("the BP7 settings", SeasBp5Output::bp7_file_names(), SEAS_BP7_RESUME_LOG)
);

/// [`seas_bp7`]'s run of the settings `run` (their `fingerprint`): its fault ODE and files.
fn run_bp7(common: Common, run: SeasBp7Run, fingerprint: Fingerprint) -> PyResult<Simulation> {
    let bp7 = run.scene();
    let options = common.options(bp7.fault_ode_options(run.tolerance), run.integrator)?;
    let (ode, body) = run.fault_ode(options, elimination()).py()?;
    let setup = run.seas_setup(common.modeler.clone(), common.date.clone());
    let output =
        |out: &std::path::Path, model: &rsf::Model<3, 3>| run.output(out, model, body, setup).py();
    common.simulation(ode, (fingerprint, run.end_seconds()), output, "seas_bp7")
}

square_run!(
    /// SEAS BP8-QD-GS/PW (docs/seas-bp8.md, docs/python.md): the run of the Rust program
    /// `seas_bp8`. The settings are keyword arguments with the program's names, defaults and
    /// ranges (`rsf_scenes::SeasBp8Run`): `kernel`, `domain_km`, `ratio` as for
    /// [`seas_bp7`], `source` "gs" (a Gaussian) or "pw" (a Peaceman
    /// well), `end_days` (default 30), `dx` (m, dividing 800 m; default 10), `tolerance`
    /// (default 1e-7), `overpressure` "floor" or "refuse", `sigma_min` (MPa, the floor's; 1
    /// if unset), `station_interval` (s; 0, the default: a row every accepted step),
    /// `profile_interval` (s, default 3600), `integrator`. The other keywords as for
    /// [`seas_bp7`].
    seas_bp8 => run_bp8,
    ("the BP8 settings", SeasBp5Output::bp8_file_names(), SEAS_BP8_RESUME_LOG)
);

/// [`seas_bp8`]'s run of the settings `run` (their `fingerprint`): its fault ODE and files.
fn run_bp8(common: Common, run: SeasBp8Run, fingerprint: Fingerprint) -> PyResult<Simulation> {
    let bp8 = SeasBp8::default();
    let field = bp8.pressure(run.source, run.dx).py()?;
    let friction_pressure = bp8
        .friction_pressure(field.clone(), run.overpressure())
        .py()?;
    let options = common.options(bp8.fault_ode_options(run.tolerance), run.integrator)?;
    let ode = run
        .fault_ode(options, friction_pressure, elimination())
        .py()?;
    let setup = run.seas_setup(common.modeler.clone(), common.date.clone());
    let output =
        |out: &std::path::Path, model: &rsf::Model<3, 3>| run.output(out, model, field, setup).py();
    common.simulation(ode, (fingerprint, run.end_seconds()), output, "seas_bp8")
}

/// How `kernel = "fe"` eliminates its volume from Python: as the programs (nested
/// dissection where METIS is built, this package's default feature), no memory bound.
fn elimination() -> rsf_scenes::VolumeElimination {
    rsf_scenes::VolumeElimination::default()
}

impl Common {
    /// The keywords checked: `threads` at least 1, counts whole, the folder's keywords
    /// together.
    fn new(
        folder: FolderKeywords,
        (threads, fault_every): (i128, i128),
        (modeler, date): (&str, Option<String>),
    ) -> PyResult<Self> {
        Ok(Self {
            folder,
            threads: crate::counts::threads(Some(threads))?,
            modeler: modeler.to_owned(),
            date: date.unwrap_or_else(rsf_seas::utc_date_today),
            fault_every: crate::counts::count(fault_every, "fault_every")?,
        })
    }

    /// The run configuration `C` of the keyword arguments `settings` (`what` in messages,
    /// [`settings_of`]) and the folder prepared for `program`'s `files` and its resume log
    /// with the run's fingerprint ([`FolderKeywords::prepare`]: another run's folder
    /// refused before anything is computed).
    ///
    /// # Errors
    /// A refused setting, named by its keyword; the folder's refusal.
    fn prepare<C: RunConfig>(
        &self,
        (settings, what): (Option<&Bound<'_, PyDict>>, &str),
        program: &str,
        (mut files, resume_log): (Vec<String>, &str),
    ) -> PyResult<(C, Fingerprint)> {
        let run: C = settings_of(settings, what)?;
        let fingerprint = run.fingerprint();
        files.push(resume_log.into());
        self.folder.prepare(program, files, &fingerprint)?;
        Ok((run, fingerprint))
    }

    /// The scene's fault-ODE `options` on this run's threads with `integrator`.
    ///
    /// # Errors
    /// The options' (a refused tolerance).
    fn options(
        &self,
        options: rsf::Result<rsf::fault_ode::FaultOdeOptions>,
        integrator: rsf::fault_ode::OdeIntegrator,
    ) -> PyResult<rsf::fault_ode::FaultOdeOptions> {
        Ok(rsf::fault_ode::FaultOdeOptions {
            parallelism: rsf::Parallelism::rayon(self.threads),
            integrator,
            ..options.py()?
        })
    }

    /// The simulation of `ode` until `end` (s) with `fingerprint` through the session: on
    /// resume the checkpoint restored and the files of `out` (made by `output`) continued
    /// at its step, else their first rows written; the files keep a mark where every
    /// `run`/`advance` call stops, from which a checkpoint written there resumes.
    fn simulation(
        self,
        ode: rsf_scenes::SeasBp8FaultOde,
        (fingerprint, end): (Fingerprint, f64),
        output: impl FnOnce(&std::path::Path, &rsf::Model<3, 3>) -> PyResult<SeasBp5Output>,
        program: &'static str,
    ) -> PyResult<Simulation> {
        let run = SessionRun {
            fingerprint,
            end,
            fault_every: self.fault_every,
            program,
        };
        let out = self.folder.out.clone();
        self.folder.simulation(run, ode, move |ode| {
            out.map(|out| Ok(output(&out, ode.model())?.with_marks_where_runs_end(0)))
                .transpose()
        })
    }
}
