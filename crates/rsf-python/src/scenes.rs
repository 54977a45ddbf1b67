//! The ready-made scenes of `rsf-scenes` as Python functions: the keyword arguments are
//! the scenes' own fields (their TOML names, checked by the scenes), a few friction
//! parameters may be given per fault node.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use rsf::checkpoint::Fingerprint;
use rsf::friction::{DieterichRuina, RateStateParams};
use rsf::SimulationBuilder;
use rsf_scenes::{
    RunConfig, SeasBp1, SeasBp1Run, Slider3dScene, SliderScene, TimeStep, SEAS_BP1_STATION_DEPTHS,
};
use rsf_seas::{SeasOutput, SeasSetup, SECONDS_PER_YEAR};
use serde_json::Value;

use crate::convert::{choice, per_node, scene, to_json, PerNode};
use crate::engine::{Engine, Files, Recording};
use crate::errors::{invalid, OrPy};
use crate::run_folder::FolderKeywords;
use crate::simulation::{End, Simulation};

/// The slider scenes' friction fields that may be given per fault node, with the
/// [`RateStateParams`] field each sets.
const PER_NODE: [(&str, &str); 4] = [
    ("a", "a"),
    ("b", "b"),
    ("l_m", "l"),
    ("sigma_n_pa", "sigma_n"),
];

/// Keyword arguments split into scene fields (JSON values) and per-node parameters.
type Split<'py> = (Vec<(String, Value)>, Vec<(String, Bound<'py, PyAny>)>);

/// The keyword arguments as scene fields, those of `per_node_names` that are not numbers
/// (arrays, functions) set aside.
pub(crate) fn split<'py>(
    kwargs: Option<&Bound<'py, PyDict>>,
    per_node_names: &[&str],
) -> PyResult<Split<'py>> {
    let mut fields = Vec::new();
    let mut per = Vec::new();
    if let Some(kw) = kwargs {
        for (k, v) in kw.iter() {
            let k: String = k.extract()?;
            if per_node_names.contains(&k.as_str()) && v.extract::<f64>().is_err() {
                per.push((k, v));
            } else {
                fields.push((k.clone(), to_json(&k, &v)?));
            }
        }
    }
    Ok((fields, per))
}

/// The builder with Dieterich–Ruina friction of `p` except the fields `per` per fault node;
/// the fingerprint gains a hash of each.
fn rate_state_per_node<const D: usize, S, I>(
    py: Python<'_>,
    builder: SimulationBuilder<D, DieterichRuina, S, I>,
    p: RateStateParams,
    per: &[(String, Bound<'_, PyAny>)],
    mut fingerprint: Fingerprint,
) -> PyResult<(SimulationBuilder<D, DieterichRuina, S, I>, Fingerprint)> {
    if per.is_empty() {
        return Ok((builder, fingerprint));
    }
    let coords: Vec<f64> = builder
        .model()
        .on_frictional_nodes(|x| *x)
        .into_iter()
        .flatten()
        .collect();
    let mut values: Vec<(&'static str, PerNode)> = Vec::new();
    for (name, obj) in per {
        let field = PER_NODE
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, f)| *f)
            .expect("split sets aside only these names");
        let v = per_node(py, name, obj, &coords, D)?;
        fingerprint = fingerprint.with(name, v.describe());
        values.push((field, v));
    }
    let mut k = 0;
    let builder = builder.friction_at(move |_x| {
        let mut q = p;
        for (field, v) in &values {
            let x = v.at(k);
            match *field {
                "a" => q.a = x,
                "b" => q.b = x,
                "l" => q.l = x,
                _ => q.sigma_n = x,
            }
        }
        k += 1;
        DieterichRuina::new(q)
    });
    Ok((builder, fingerprint))
}

/// Where a slider scene ends.
fn slider_end(s: &SliderScene) -> End {
    match s.time_step {
        TimeStep::Fixed {} => End::Steps(s.steps),
        TimeStep::Adaptive(_) => End::Time(s.end_time_s),
    }
}

/// The paper's slider (Pipping, Sander and Kornhuber §6.1, Table 6.1): a 5 m × 1 m block
/// on a rigid base. Keyword arguments are the scene's fields (`level`, `steps`,
/// `end_time_s`, `a`, `b`, `l_m`, `sigma_n_pa`, `state_law`, `integrator`, `solver`, …:
/// docs/python.md); `a`, `b`, `l_m`, `sigma_n_pa` may be arrays (one value per fault node)
/// or functions of the fault nodes' coordinates `x` (shape `(n, 2)`, m) called once.
/// `fault_every` records the fault's fields every that many steps.
#[pyfunction]
#[pyo3(signature = (*, fault_every=0, **kwargs))]
pub(crate) fn slider(
    py: Python<'_>,
    fault_every: i128,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Simulation> {
    let fault_every = crate::counts::count(fault_every, "fault_every")?;
    let names: Vec<&str> = PER_NODE.iter().map(|(n, _)| *n).collect();
    let (fields, per) = split(kwargs, &names)?;
    let s: SliderScene = scene(&SliderScene::default(), &fields, "the slider scene")?;
    if s.state_law == rsf::StateLawKind::Discontinuous {
        return Err(crate::errors::discontinuous_needs_theta());
    }
    let builder = s.simulation_builder().py()?;
    let (builder, fingerprint) =
        rate_state_per_node(py, builder, s.rate_state_params(), &per, s.fingerprint())?;
    let sim = builder.build().py()?;
    let engine = Engine::<2, 2, _> {
        sim,
        recording: Recording::new(fault_every).py()?,
        files: Vec::new(),
        fingerprint,
        folder: Files::default(),
    };
    Ok(Simulation::new(
        Box::new(engine),
        Some(slider_end(&s)),
        "slider",
    ))
}

/// The slider as a 3-D block (5 m × 1 m × `width_m`, tetrahedra; `lateral` "free" or
/// "plane-strain"): the 2-D scene's fields and these two; `level` defaults to 2. As
/// [`slider`] for `fault_every` and per-node parameters (coordinates of shape `(n, 3)`).
/// `hdf5` writes the fields to an HDF5 file with an Xdmf index beside it every
/// `hdf5_every` steps (the package built with the feature `hdf5`). `resume` continues from
/// a checkpoint of this scene (`allow_change`: fingerprint fields that may differ), and
/// with `hdf5` continues that file at the checkpoint's step once the file shows it holds
/// the checkpoint's run (the fingerprint it recorded, the frame of that step at its time
/// and state), or raises with the file unchanged.
#[pyfunction]
#[pyo3(signature = (*, fault_every=0, hdf5=None, hdf5_every=1, resume=None, allow_change=Vec::new(), **kwargs))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn slider_3d(
    py: Python<'_>,
    fault_every: i128,
    hdf5: Option<PathBuf>,
    hdf5_every: i128,
    resume: Option<PathBuf>,
    allow_change: Vec<String>,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Simulation> {
    let fault_every = crate::counts::count(fault_every, "fault_every")?;
    let hdf5_every = crate::counts::count(hdf5_every, "hdf5_every")?;
    let names: Vec<&str> = PER_NODE.iter().map(|(n, _)| *n).collect();
    let (fields, per) = split(kwargs, &names)?;
    // The 3-D scene flattens the 2-D one into its fields, which serde cannot check for
    // unknown names: the 2-D scene's (which refuses them) checks the rest.
    let slider_fields: Vec<(String, Value)> = fields
        .iter()
        .filter(|(k, _)| k != "width_m" && k != "lateral")
        .cloned()
        .collect();
    scene(
        &SliderScene::default(),
        &slider_fields,
        "the 3-D slider scene",
    )?;
    let s: Slider3dScene = scene(&Slider3dScene::default(), &fields, "the 3-D slider scene")?;
    if s.slider.state_law == rsf::StateLawKind::Discontinuous {
        return Err(crate::errors::discontinuous_needs_theta());
    }
    let model = s.build_model().py()?;
    let builder = s.simulation_builder_with_model(model).py()?;
    let (builder, fingerprint) = rate_state_per_node(
        py,
        builder,
        s.slider.rate_state_params(),
        &per,
        s.fingerprint(),
    )?;
    let mut sim = builder.build().py()?;
    let resumed = match &resume {
        None if !allow_change.is_empty() => {
            return Err(invalid(
                "allow_change",
                "needs `resume` (a checkpoint to continue)",
            ))
        }
        None => None,
        Some(path) => {
            let c = rsf::run_folder::read_checkpoint(path, &fingerprint, &allow_change).py()?;
            rsf::Stepping::restore(&mut sim, &c).py()?;
            Some(c)
        }
    };
    let files = crate::fields::hdf5_observer::<3>(
        hdf5.clone(),
        hdf5_every,
        &fingerprint,
        resumed.as_ref().map(|c| (c, allow_change.as_slice())),
    )?;
    let engine = Engine::<3, 3, _> {
        sim,
        recording: Recording::new(fault_every).py()?,
        files,
        fingerprint,
        folder: Files {
            file: hdf5,
            ..Files::default()
        },
    };
    Ok(Simulation::new(
        Box::new(engine),
        Some(slider_end(&s.slider)),
        "slider_3d",
    ))
}

/// The SCEC SEAS benchmark BP1-QD (docs/seas-bp1.md): the quasi-dynamic equations condensed
/// onto the fault, Dormand–Prince 5(4), as the Rust program `seas_bp1` runs them with the
/// same flags (`dz` = `--dz`, `domain_km`, `ratio`, `rk_tolerance`, `kernel`
/// "hierarchical" or "dense", `kernel_epsilon`, `integrator` — "dormand-prince", the
/// program's default, "auto", "rkc", "rosenbrock" or "bogacki-shampine" —, `threads`,
/// `end_years`, `every_step`, `modeler`, `date`). With `out`, the benchmark's files (`fltst_dp*`, `devol.dat`,
/// `events.csv`, and their resume log `seas_resume.csv`) are written there as the program
/// writes them (the folder refused if it holds another run's files, unless `overwrite`);
/// with `hdf5` also their series in one HDF5 file, `seas.h5` in `out`, at the end of every
/// `run`/`advance` (the package built with the feature `hdf5`, as `crates/rsf-hdf5`'s
/// program `seas_bp1`). `resume` continues the run of a checkpoint (the program's or this
/// package's: the same fingerprint) and, with `out`, its files there by the programs' rule
/// (docs/reliability.md, "Round 5"): the checkpoint's fingerprint checked (`allow_change`
/// names fields that may differ), the folder proven the checkpoint's run's (its manifest's
/// run id, or its files where the manifest is missing), the files continued at the
/// checkpoint's step; with `overwrite=True` the folder of another run is given to the
/// checkpoint's run whole (its files copied from the checkpoint's own folder) or refused.
/// Other keyword arguments are the run's other settings (`rsf_scenes::SeasBp1Run`, the
/// program's flags of the same names): the description's parameters (`rho`, `c_s`,
/// `sigma_n`, `a0`, `a_max`, `b0`, `d_c`, `v_p`, `v_init`, `v0`, `f0`, `h_top`,
/// `h_transition`, `w_f`; SI units), each checked against its range.
#[pyfunction]
#[pyo3(signature = (*, dz=SeasBp1Run::default().dz, domain_km=SeasBp1Run::default().domain_km, ratio=SeasBp1Run::default().ratio, rk_tolerance=SeasBp1Run::default().rk_tolerance, kernel="hierarchical", kernel_epsilon=None, integrator=SeasBp1Run::default().integrator.name(), threads=None, end_years=SeasBp1Run::default().end_years, every_step=false, out=None, overwrite=false, resume=None, allow_change=Vec::new(), hdf5=false, modeler="rsf", date=None, fault_every=0, **kwargs))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn seas_bp1(
    dz: f64,
    domain_km: f64,
    ratio: f64,
    rk_tolerance: f64,
    kernel: &str,
    kernel_epsilon: Option<f64>,
    integrator: &str,
    threads: Option<i128>,
    end_years: f64,
    every_step: bool,
    out: Option<PathBuf>,
    overwrite: bool,
    resume: Option<PathBuf>,
    allow_change: Vec<String>,
    hdf5: bool,
    modeler: &str,
    date: Option<String>,
    fault_every: i128,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Simulation> {
    let threads = crate::counts::threads(threads)?;
    let fault_every = crate::counts::count(fault_every, "fault_every")?;
    // The run's settings (rsf_scenes::SeasBp1Run, the program's): the keywords above,
    // then the others — the scene's parameters (`sigma_n`, `a0`, `d_c`, …, SI units) —
    // read through serde by their names.
    let keywords = SeasBp1Run {
        dz,
        domain_km,
        ratio,
        rk_tolerance,
        kernel: kernel_choice(kernel)?,
        kernel_epsilon,
        integrator: choice("integrator", integrator)?,
        end_years,
        every_step,
        ..SeasBp1Run::default()
    };
    let (fields, _) = split(kwargs, &[])?;
    let run: SeasBp1Run = scene(&keywords, &fields, "the BP1 run")?;
    run.validate().py()?;
    if run.method() != rsf::MethodKind::FaultOde {
        let name = if run.inertia { "inertia" } else { "scheme" };
        return Err(invalid(
            name,
            "the Python package runs BP1-QD's Runge–Kutta run (the program `seas_bp1` runs \
             the implicit scheme and BP1-FD)",
        ));
    }
    let folder = FolderKeywords::new(out.clone(), overwrite, resume, allow_change);
    folder.check()?;
    if hdf5 && out.is_none() {
        return Err(invalid(
            "hdf5",
            "needs `out`: the series are those of its files",
        ));
    }
    let (bp1, grid) = (run.scene(), run.grid());
    let options = run.fault_ode_options(threads).py()?;
    let sampling = run.sampling();
    let fingerprint = run.fingerprint();
    // The folder first (another run's refused before anything is computed), as the
    // program's guard does.
    let mut names = SeasBp1::file_names();
    if hdf5 {
        names.push("seas.h5".into());
    }
    let fresh = folder.prepare("seas_bp1", names, &fingerprint)?;
    let model = bp1.model(&grid, false).py()?;
    let mut sim = bp1.fault_ode(model, options).py()?;
    let t_end = run.end_years * SECONDS_PER_YEAR;
    let session = folder.session(fingerprint.clone(), t_end, &mut sim)?;
    let mut files: Vec<Box<dyn rsf::Observer<2, 1>>> = Vec::new();
    if let Some(out) = out {
        let stations: Vec<(String, f64)> = SEAS_BP1_STATION_DEPTHS
            .iter()
            .map(|&d| (SeasBp1::station_name(d), d))
            .collect();
        let setup = SeasSetup {
            modeler: modeler.to_owned(),
            date: date.unwrap_or_else(rsf_seas::utc_date_today),
            stations,
            ..bp1.seas_setup(run.dz, false, sampling)
        };
        let model = rsf::Stepping::model(&sim);
        let mut output = SeasOutput::for_session(
            &session,
            &out,
            model,
            sim.problem().friction_laws(),
            setup,
            fresh,
        )
        .py()?;
        if session.resumed().is_none() {
            output
                .write_initial_state(model, rsf::Stepping::state(&sim))
                .py()?;
        }
        files.push(Box::new(output));
        if hdf5 {
            // After the output, whose files it reads.
            files.push(crate::fields::seas_series_observer(
                &out,
                session.mode(fresh),
            )?);
        }
    }
    let engine = Engine::<2, 1, _> {
        sim,
        recording: Recording::new(fault_every).py()?,
        files,
        fingerprint,
        // Every file is checked: a folder whose manifest named no run is the checkpoint's.
        folder: folder.files(&session)?,
    };
    Ok(Simulation::new(
        Box::new(engine),
        Some(End::Time(t_end)),
        "seas_bp1",
    ))
}

/// The kernel keyword `kernel`: "hierarchical" or "dense".
pub(crate) fn kernel_choice(kernel: &str) -> PyResult<rsf_scenes::KernelChoice> {
    match kernel {
        "dense" => Ok(rsf_scenes::KernelChoice::Dense),
        "hierarchical" => Ok(rsf_scenes::KernelChoice::Hierarchical),
        k => Err(invalid(
            "kernel",
            format!("`{k}`: \"hierarchical\" or \"dense\""),
        )),
    }
}
