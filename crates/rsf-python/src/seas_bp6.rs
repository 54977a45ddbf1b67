//! SEAS BP6-QD-A/S/C from Python (docs/seas-bp6.md): fluid injected into a fault, the
//! pore pressure lowering the effective normal stress — the run of the program
//! `seas_bp6` with its settings ([`SeasBp6Run`]: the same defaults, ranges and
//! fingerprint), its files and its run folder ([`FolderKeywords`]); and the scene's pore
//! pressure `p(z, t)` and Darcy velocity along the fault.

use std::path::PathBuf;
use std::sync::Arc;

use numpy::{AllowTypeChange, IntoPyArray, PyArrayLike1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rsf::checkpoint::Fingerprint;
use rsf::pore_pressure::PorePressure;
use rsf::Stepping;
use rsf_scenes::{
    Bp6Elastic, Bp6Pressure, Bp6Variant, SeasBp6, SeasBp6Run, BP6_C_FIRST_STEP,
    BP6_DIFFUSION_CELLS, BP6_SECONDS_PER_YEAR,
};
use rsf_seas::{Bp6Fault, SeasBp6Output, SeasSetup, SEAS_BP6_RESUME_LOG};

use crate::convert::{choice, scene};
use crate::engine::WithFaultOperator;
use crate::errors::{invalid, OrPy};
use crate::run_folder::{FolderKeywords, SessionRun};
use crate::scenes::{kernel_choice, split};
use crate::simulation::Simulation;

/// SEAS BP6-QD (docs/seas-bp6.md, docs/python.md): the run of the Rust program
/// `seas_bp6` with the same settings and defaults (`rsf_scenes::SeasBp6Run`): `variant`
/// "a" (aging law), "s" (slip law) or "c" (constant friction); `dz` (m, dividing
/// 2 l_f = 40 km), `elastic` "bem" (the whole space's boundary-element kernel) or "fe"
/// (the finite-element half space, `domain_km`, `ratio`), `bem_product` "fft" or
/// "stored" (`kernel`, `kernel_epsilon`), `tolerance` (default 1e-7 for a and s, 1e-3 for
/// c), `pressure` "closed-form" or "diffusion" (`diffusion_cells`, default 800),
/// `integrator` (a, s), `threads`, `end_years` (years of 365 days), `station_interval`
/// and `profile_interval` (s), `modeler`, `date`. With `out`, the benchmark's files (nine
/// stations, `global.dat`, four profiles, and their resume log) are written there as the
/// program writes them, at the end of every `run`/`advance` call; `overwrite`, `resume`,
/// `allow_change` as for `seas_bp1` (the programs' folder rule, docs/reliability.md
/// "Round 5": a checkpoint of the program resumes here and the other way round). A
/// checkpoint whose files resume is one written where a `run`/`advance` call stopped
/// (`Simulation.checkpoint` after it, or Ctrl-C's). Other keyword arguments are the
/// scene's parameters (`sigma_n`, `a`, `b`, `d_rs`, `q0`, `t_off`, `k`, …, SI units).
#[pyfunction]
#[pyo3(signature = (*, variant="a", dz=SeasBp6Run::default().dz, elastic="bem", bem_product=None, domain_km=SeasBp6Run::default().domain_km, ratio=SeasBp6Run::default().ratio, tolerance=None, pressure="closed-form", diffusion_cells=None, kernel="hierarchical", kernel_epsilon=None, integrator="auto", threads=1, end_years=SeasBp6Run::default().end_years, station_interval=SeasBp6Run::default().station_interval, profile_interval=SeasBp6Run::default().profile_interval, out=None, overwrite=false, resume=None, allow_change=Vec::new(), modeler="rsf", date=None, fault_every=0, **kwargs))]
#[allow(clippy::too_many_arguments)] // Python's keyword arguments
pub(crate) fn seas_bp6(
    variant: &str,
    dz: f64,
    elastic: &str,
    bem_product: Option<&str>,
    domain_km: f64,
    ratio: f64,
    tolerance: Option<f64>,
    pressure: &str,
    diffusion_cells: Option<i128>,
    kernel: &str,
    kernel_epsilon: Option<f64>,
    integrator: &str,
    threads: i128,
    end_years: f64,
    station_interval: f64,
    profile_interval: f64,
    out: Option<PathBuf>,
    overwrite: bool,
    resume: Option<PathBuf>,
    allow_change: Vec<String>,
    modeler: &str,
    date: Option<String>,
    fault_every: i128,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Simulation> {
    let diffusion_cells = crate::counts::optional(diffusion_cells, "diffusion_cells")?;
    let threads = crate::counts::count(threads, "threads")?;
    let fault_every = crate::counts::count(fault_every, "fault_every")?;
    let bp6 = bp6_scene(kwargs)?;
    let run = SeasBp6Run {
        variant: choice("variant", variant)?,
        end_years,
        dz,
        elastic: choice("elastic", elastic)?,
        bem_product: bem_product.map(|p| choice("bem_product", p)).transpose()?,
        domain_km,
        ratio,
        tolerance,
        pressure: choice("pressure", pressure)?,
        station_interval,
        profile_interval,
        diffusion_cells,
        kernel: kernel_choice(kernel)?,
        kernel_epsilon,
        integrator: integrator
            .parse()
            .map_err(|e: rsf::time::Error| invalid("integrator", e))?,
    };
    run.validate_with(&bp6).py()?;
    let (variant, elastic) = (run.variant, run.elastic);
    if threads == 0 {
        return Err(invalid("threads", "at least 1"));
    }
    let folder = FolderKeywords::new(out, overwrite, resume, allow_change);
    // The folder first (another run's refused before anything is computed), as the
    // program's guard does. (The BP6 files are written whole, atomically, where a run
    // stops: they take no mode.)
    let mut names = SeasBp6Output::file_names();
    names.push(SEAS_BP6_RESUME_LOG.into());
    let fingerprint = run.fingerprint_with(&bp6);
    folder.prepare("seas_bp6", names, &fingerprint)?;
    let setup = SeasSetup {
        modeler: modeler.to_owned(),
        date: date.unwrap_or_else(rsf_seas::utc_date_today),
        ..bp6.seas_setup(variant, dz)
    };
    let drive = Drive {
        folder,
        fingerprint,
        pressure: bp6.pressure(run.pressure()).py()?,
        setup,
        run,
        fault_every,
    };
    let bem = run.bem_kernel().py()?;
    match (variant, elastic) {
        (Bp6Variant::C, Bp6Elastic::Bem) => {
            let model = bp6.bem_constant_friction_model(dz, bem).py()?;
            drive.constant_friction(&bp6, model)
        }
        (Bp6Variant::C, Bp6Elastic::Fe) => {
            let model = bp6.fe_model(&run.grid(), variant).py()?;
            drive.constant_friction(&bp6, model)
        }
        (_, Bp6Elastic::Bem) => {
            let options = fault_ode_options(&bp6, &run, threads)?;
            let ode = bp6
                .bem_fault_ode(dz, variant, bem, options, drive.pressure.clone())
                .py()?;
            let fault = bp6.output_fault(ode.model(), variant);
            drive.simulation(ode, fault)
        }
        (_, Bp6Elastic::Fe) => {
            let model = bp6.fe_model(&run.grid(), variant).py()?;
            let options = rsf::fault_ode::FaultOdeOptions {
                kernel: run.fault_kernel().py()?,
                ..fault_ode_options(&bp6, &run, threads)?
            };
            let ode = bp6
                .fe_fault_ode(model, variant, options, drive.pressure.clone())
                .py()?;
            let fault = bp6.output_fault(ode.model(), variant);
            drive.simulation(ode, fault)
        }
    }
}

/// The scene of the keyword arguments (its fields, SI units), checked.
fn bp6_scene(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<SeasBp6> {
    let (fields, _) = split(kwargs, &[])?;
    let bp6: SeasBp6 = scene(&SeasBp6::default(), &fields, "the BP6 scene")?;
    bp6.validate().py()?;
    Ok(bp6)
}

/// The fault ODE's options of A and S as the program sets them: the scene's for the
/// tolerance, `threads`, the run's integrator.
fn fault_ode_options(
    bp6: &SeasBp6,
    run: &SeasBp6Run,
    threads: usize,
) -> PyResult<rsf::fault_ode::FaultOdeOptions> {
    let mut options = bp6.fault_ode_options(run.tolerance()).py()?;
    options.parallelism = rsf::Parallelism::rayon(threads);
    options.integrator = run.integrator;
    Ok(options)
}

/// The pore pressure of `pressure` ("closed-form" or "diffusion") and `diffusion_cells`
/// (default [`BP6_DIFFUSION_CELLS`]; refused with the closed form, which would ignore it).
fn pressure_of(pressure: &str, diffusion_cells: Option<usize>) -> PyResult<Bp6Pressure> {
    match (pressure, diffusion_cells) {
        ("closed-form", None) => Ok(Bp6Pressure::ClosedForm),
        ("closed-form", Some(_)) => Err(invalid(
            "diffusion_cells",
            "a setting of pressure=\"diffusion\": with the closed form it would be ignored",
        )),
        ("diffusion", cells) => Ok(Bp6Pressure::Diffusion {
            cells: cells.unwrap_or(BP6_DIFFUSION_CELLS),
        }),
        (p, _) => Err(invalid(
            "pressure",
            format!("`{p}`: \"closed-form\" or \"diffusion\""),
        )),
    }
}

/// What every BP6 run from Python shares: its folder, fingerprint, pressure, headers and
/// settings.
struct Drive {
    folder: FolderKeywords,
    fingerprint: Fingerprint,
    pressure: Arc<dyn PorePressure<2>>,
    setup: SeasSetup,
    run: SeasBp6Run,
    fault_every: usize,
}

impl Drive {
    /// BP6-C on `model` (the fault alone or the finite-element model): the implicit
    /// scheme, as the program runs it.
    fn constant_friction<const C: usize>(
        self,
        bp6: &SeasBp6,
        model: rsf::Model<2, C>,
    ) -> PyResult<Simulation> {
        let fault = bp6.output_fault(&model, Bp6Variant::C);
        let control = bp6.step_control(self.run.tolerance()).py()?;
        let sim = bp6
            .constant_friction(model, self.pressure.clone(), BP6_C_FIRST_STEP, control)
            .py()?;
        self.simulation(sim, fault)
    }

    /// The simulation of `sim` through the session: on resume, the checkpoint restored and
    /// the files of `out` continued at its step; else their first rows written. The files
    /// keep a mark of where every `run`/`advance` call stops, from which a checkpoint
    /// written there resumes.
    fn simulation<const C: usize, M>(self, sim: M, fault: Bp6Fault) -> PyResult<Simulation>
    where
        M: Stepping<2, C> + WithFaultOperator + 'static,
    {
        let run = SessionRun {
            fingerprint: self.fingerprint,
            end: self.run.end_years * BP6_SECONDS_PER_YEAR,
            fault_every: self.fault_every,
            program: "seas_bp6",
        };
        let out = self.folder.out.clone();
        let (pressure, setup, settings) = (self.pressure, self.setup, self.run);
        self.folder.simulation(run, sim, move |_| {
            out.map(|out| {
                Ok(SeasBp6Output::new(&out, fault, pressure, setup)
                    .py()?
                    .with_intervals(settings.station_interval, settings.profile_interval)
                    .with_marks_where_runs_end(0))
            })
            .transpose()
        })
    }
}

/// BP6's pore pressure along the fault (docs/seas-bp6.md; the description's eqs. 20–27):
/// `p` (Pa) and the Darcy velocity `q = −(k/η_f) ∂p/∂z` (m/s) at the positions `z` (m,
/// along strike, the injection at 0) and times `t` (s), arrays of shape `(len(t),
/// len(z))` in a dict with keys "p" and "darcy_velocity". `pressure` "closed-form" (the
/// description's) or "diffusion" (solved on `diffusion_cells` cells between no-flux ends
/// at ±l_f), as `seas_bp6` runs it; other keyword arguments are the scene's parameters.
#[pyfunction]
#[pyo3(signature = (z, t, *, pressure="closed-form", diffusion_cells=None, **kwargs))]
pub(crate) fn seas_bp6_pore_pressure<'py>(
    py: Python<'py>,
    z: PyArrayLike1<'py, f64, AllowTypeChange>,
    t: PyArrayLike1<'py, f64, AllowTypeChange>,
    pressure: &str,
    diffusion_cells: Option<i128>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let diffusion_cells = crate::counts::optional(diffusion_cells, "diffusion_cells")?;
    let bp6 = bp6_scene(kwargs)?;
    let how = pressure_of(pressure, diffusion_cells)?;
    how.validate().py()?;
    let field = bp6.pressure(how).py()?;
    // Any strides (a column of a table).
    let z = z.as_array().to_vec();
    let t = t.as_array().to_vec();
    for (name, values) in [("z", &z), ("t", &t)] {
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            return Err(invalid(name, format!("{v}: every value must be finite")));
        }
    }
    if let Some(v) = t.iter().find(|&&v| v < 0.0) {
        return Err(invalid(
            "t",
            format!("{v}: times start at 0 s (the injection)"),
        ));
    }
    let points: Vec<[f64; 2]> = z.iter().map(|&z| [0.0, z]).collect();
    let mut p = vec![0.0; t.len() * z.len()];
    let mut q = vec![0.0; t.len() * z.len()];
    for (i, &ti) in t.iter().enumerate() {
        let row = i * z.len()..(i + 1) * z.len();
        field.pressures(ti, &points, &mut p[row.clone()]);
        for (o, x) in q[row].iter_mut().zip(&points) {
            *o = field.darcy_velocity(x, ti).unwrap_or(f64::NAN);
        }
    }
    let shape = [t.len(), z.len()];
    let d = PyDict::new(py);
    d.set_item("p", p.into_pyarray(py).reshape(shape)?)?;
    d.set_item("darcy_velocity", q.into_pyarray(py).reshape(shape)?)?;
    Ok(d)
}
