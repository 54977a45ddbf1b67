//! The Python class `rsf.Simulation`: a run of any scene or problem, stepped with the GIL
//! released, stopped by Ctrl-C at a step boundary, checkpointed and resumed, its records
//! as numpy arrays.

use std::path::PathBuf;

use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rsf::{Checkpoint, Termination, Until};

use crate::engine::{Advance, DynEngine, Greens, Interrupt};
use crate::errors::{invalid, OrPy};

/// Where a scene's run ends.
#[derive(Debug, Clone, Copy)]
pub(crate) enum End {
    /// At this step index (fixed steps: the scene's step count).
    Steps(usize),
    /// At this time (s).
    Time(f64),
}

/// A simulation: a scene's or your own problem's, built by `rsf.slider(...)`,
/// `rsf.seas_bp1(...)`, `rsf.Simulation(model, ...)`, … Step it with `advance` or `run`;
/// read what it recorded with `series()`, `fault()`, `events()`, `fields()`.
// `unsendable`: a simulation may hold what cannot move between threads (the library's
// solvers on ranks box a transport that need not be `Send`), so Python may use it only on the
// thread that made it (PyO3 raises on another); see `OnThisThread` for the stepping.
#[pyclass(module = "rsf._rsf", name = "Simulation", unsendable)]
pub struct Simulation {
    engine: Box<dyn DynEngine>,
    end: Option<End>,
    label: String,
}

impl Simulation {
    pub(crate) fn new(engine: Box<dyn DynEngine>, end: Option<End>, label: &str) -> Self {
        Self {
            engine,
            end,
            label: label.to_owned(),
        }
    }

    fn go(
        &mut self,
        py: Python<'_>,
        until: Until,
        progress: bool,
        checkpoint: Option<PathBuf>,
        checkpoint_every: usize,
    ) -> PyResult<Py<PyDict>> {
        let how = Advance {
            until,
            progress,
            checkpoint_every,
            checkpoint,
        };
        let mut interrupt = Interrupt::new();
        let engine = OnThisThread(&mut *self.engine);
        let (how_ref, interrupt_ref) = (&how, &mut interrupt);
        let run = py.detach(move || {
            // A method call takes the whole wrapper (not its field) into the closure.
            engine.get().advance(how_ref, interrupt_ref)
        });
        let summary = run.map_err(|e| crate::errors::to_py(e.error))?;
        if let Some(raised) = interrupt.raised {
            let s = self.engine.state();
            let mut message = format!(
                "rsf: stopped at step {} (t = {:e} s), a step boundary",
                s.step, s.time
            );
            if let Some(path) = &how.checkpoint {
                self.engine.checkpoint().write(path).py()?;
                message.push_str(&format!("; checkpoint written to {}", path.display()));
            }
            return Err(if raised.is_instance_of::<PyKeyboardInterrupt>(py) {
                PyKeyboardInterrupt::new_err(message)
            } else {
                raised
            });
        }
        let d = PyDict::new(py);
        d.set_item("steps", summary.steps)?;
        d.set_item(
            "termination",
            match summary.termination {
                Termination::EndTime => "end_time".to_owned(),
                Termination::StepCount => "step_count".to_owned(),
                Termination::StepCap => "step_cap".to_owned(),
                Termination::Observer { name, .. } => name,
                Termination::Error => "error".to_owned(),
            },
        )?;
        d.set_item("fixed_point_iterations_mean", summary.fpi_mean)?;
        d.set_item("rejected_attempts", summary.rejected_attempts)?;
        d.set_item("seconds", summary.seconds)?;
        Ok(d.unbind())
    }
}

/// A borrow handed to `Python::detach`, which asks for `Send` (on stable Rust its `Ungil`)
/// only so that nothing tied to the GIL escapes into code run without it: `detach` runs
/// the closure at once on the calling thread, and the simulation (an `unsendable` class)
/// is only ever reached from the thread that made it.
struct OnThisThread<'a>(&'a mut dyn DynEngine);

impl<'a> OnThisThread<'a> {
    fn get(self) -> &'a mut dyn DynEngine {
        self.0
    }
}

// SAFETY: the value is used only inside `Python::detach`'s closure, which runs synchronously
// on the thread that created the borrow; it never reaches another thread.
#[allow(unsafe_code)]
unsafe impl Send for OnThisThread<'_> {}

impl Simulation {
    /// The run's Green's functions and operator, or an error naming `greens_functions`.
    /// `advance` with its keywords checked: `until` (s) or `steps` (or neither: the
    /// scene's end), the checkpoint file and interval.
    fn advance_by(
        &mut self,
        py: Python<'_>,
        (until, steps): (Option<f64>, Option<usize>),
        progress: bool,
        checkpoint: Option<PathBuf>,
        checkpoint_every: usize,
    ) -> PyResult<Py<PyDict>> {
        let until = match (until, steps) {
            (Some(_), Some(_)) => {
                return Err(invalid("until", "give `until` (s) or `steps`, not both"))
            }
            (Some(t), None) => Until::Time(t),
            (None, Some(n)) => Until::Steps(n),
            (None, None) => self.end_until()?,
        };
        // A run writing files in `out` checkpoints into `out/checkpoint.bin` by default,
        // as the programs do: where a resume finds the folder of its run.
        let checkpoint = checkpoint.or_else(|| {
            let folder = self.engine.files().folder.as_ref()?;
            (checkpoint_every > 0).then(|| folder.join("checkpoint.bin"))
        });
        if checkpoint_every > 0 && checkpoint.is_none() {
            return Err(invalid(
                "checkpoint_every",
                "needs `checkpoint`, the file to write (a simulation with `out` writes \
                 `out/checkpoint.bin` by default)",
            ));
        }
        self.go(py, until, progress, checkpoint, checkpoint_every)
    }

    fn greens_of(&mut self) -> PyResult<Greens<'_>> {
        match self.engine.greens() {
            Some(g) => g.py(),
            None => Err(invalid(
                "greens_functions",
                "the run has no fault operator: only runs condensed onto the fault (the \
                 fault ODE, seas_bp1) have one",
            )),
        }
    }
}

/// The description and the dense `S` of a Green's functions file written by
/// `GreensFunctions.to_hdf5` (`rsf_hdf5::read_greens`), for `GreensFunctions.from_hdf5`.
#[pyfunction]
pub(crate) fn _read_greens_hdf5<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<(Bound<'py, PyDict>, Bound<'py, PyArray2<f64>>)> {
    let (g, s) = crate::fields::read_greens(&path)?;
    Ok((greens_dict(py, &g)?, array2(py, &s, g.dim())?))
}

/// The description of `g` as a dict of numpy arrays and numbers (`rsf.GreensFunctions`'s
/// fields).
fn greens_dict<'py>(
    py: Python<'py>,
    g: &rsf::greens::GreensFunctions,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let flat = |v: &[[f64; 3]]| v.iter().flatten().copied().collect::<Vec<f64>>();
    let (epsilon, leaf_size) = match g.accuracy.kernel {
        rsf::fault_operator::FaultKernel::Dense => (0.0, 0),
        rsf::fault_operator::FaultKernel::Hierarchical { epsilon, leaf_size } => {
            (epsilon, leaf_size)
        }
    };
    d.set_item("dimension", g.dimension)?;
    d.set_item("fault_names", g.fault_names.clone())?;
    d.set_item("fault", array1(py, g.fault.clone()))?;
    d.set_item("node", array1(py, g.node.clone()))?;
    d.set_item("component", array1(py, g.component.clone()))?;
    d.set_item("positions", array2(py, &flat(&g.positions), 3)?)?;
    d.set_item("directions", array2(py, &flat(&g.directions), 3)?)?;
    d.set_item("weights", array1(py, g.weights.clone()))?;
    d.set_item("origin", g.origin.code())?;
    d.set_item("kernel", g.accuracy.kernel.name())?;
    d.set_item("epsilon", epsilon)?;
    d.set_item("leaf_size", leaf_size)?;
    d.set_item("relative_error", g.accuracy.relative_error)?;
    d.set_item("error_samples", g.accuracy.error_samples)?;
    d.set_item("max_rank", g.accuracy.max_rank)?;
    d.set_item("low_rank_blocks", g.accuracy.low_rank_blocks)?;
    d.set_item("tolerance", g.accuracy.tolerance())?;
    d.set_item("unit_S", g.units_s())?;
    d.set_item("rsf_version", rsf::greens::RSF_VERSION)?;
    Ok(d)
}

fn array1<'py, T: numpy::Element>(py: Python<'py>, v: Vec<T>) -> Bound<'py, PyArray1<T>> {
    v.into_pyarray(py)
}

/// `v` (row-major, `cols` per row) as an array of shape `(rows, cols)`.
fn array2<'py>(py: Python<'py>, v: &[f64], cols: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let rows = v.len().checked_div(cols).unwrap_or(0);
    v.to_vec().into_pyarray(py).reshape([rows, cols])
}

#[pymethods]
impl Simulation {
    /// Time of the state (s).
    #[getter]
    fn time(&self) -> f64 {
        self.engine.state().time
    }

    /// Steps taken so far (across resumes).
    #[getter]
    fn step(&self) -> usize {
        self.engine.state().step
    }

    /// The next step's length τ (s).
    #[getter]
    fn tau(&self) -> f64 {
        self.engine.state().tau
    }

    /// Coordinates of the fault nodes (m), shape `(n_fault, dim)`, in fault-node order: the
    /// order of every per-node array.
    #[getter]
    fn fault_coordinates<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (d, _, x) = self.engine.shape();
        array2(py, &x, d)
    }

    /// Steps until time `until` (s; the first step with t ≥ until) or, with `steps`, that
    /// many steps; with neither, to the scene's end. The GIL is released while stepping;
    /// Ctrl-C stops the run at the next step boundary (within 50 ms of wall time) and raises
    /// `KeyboardInterrupt` — after writing `checkpoint` if given. `checkpoint_every` > 0
    /// writes it every that many steps too. `progress` draws a bar on stderr. Returns a
    /// summary (steps, why it ended, mean fixed point iterations, rejected attempts).
    #[pyo3(signature = (until=None, *, steps=None, progress=false, checkpoint=None, checkpoint_every=0))]
    #[allow(clippy::too_many_arguments)] // Python's keyword arguments
    fn advance(
        &mut self,
        py: Python<'_>,
        until: Option<f64>,
        steps: Option<i128>,
        progress: bool,
        checkpoint: Option<PathBuf>,
        checkpoint_every: i128,
    ) -> PyResult<Py<PyDict>> {
        let steps = crate::counts::optional(steps, "steps")?;
        let checkpoint_every = crate::counts::count(checkpoint_every, "checkpoint_every")?;
        self.advance_by(py, (until, steps), progress, checkpoint, checkpoint_every)
    }

    /// Steps to the scene's end (its step count or end time): `advance()` with no bound.
    #[pyo3(signature = (*, progress=false, checkpoint=None, checkpoint_every=0))]
    fn run(
        &mut self,
        py: Python<'_>,
        progress: bool,
        checkpoint: Option<PathBuf>,
        checkpoint_every: i128,
    ) -> PyResult<Py<PyDict>> {
        let checkpoint_every = crate::counts::count(checkpoint_every, "checkpoint_every")?;
        self.advance_by(py, (None, None), progress, checkpoint, checkpoint_every)
    }

    /// Writes a checkpoint of the state now to `path` (the library's format, with a
    /// checksum and this run's fingerprint).
    fn checkpoint(&self, path: PathBuf) -> PyResult<()> {
        self.engine.checkpoint().write(&path).py()
    }

    /// Continues from the checkpoint `path` of this same scene or problem (its fingerprint
    /// is checked: a checkpoint of another run raises `CheckpointError` naming the
    /// differing field). The records start anew from the checkpoint's step. A simulation
    /// that writes files (`out`, `hdf5`) is not resumed here — its files, written from its
    /// own start, would be continued from another step (issue 87: 494 years missing from
    /// every file): it raises `InvalidParameterError` naming the constructor's `resume=`
    /// keyword, which continues the files at the checkpoint's step (`rsf.seas_bp1(out=…,
    /// resume=…)`, `rsf.slider_3d(hdf5=…, resume=…)`).
    fn resume(&mut self, path: PathBuf) -> PyResult<()> {
        if let Some(file) = &self.engine.files().file {
            return Err(invalid(
                "resume",
                format!(
                    "this simulation writes `{}` from its own start: resuming it from `{}` \
                     would continue that file at another step; build it with the checkpoint \
                     instead — rsf.{}(hdf5=\"{}\", resume=\"{}\", …) — which checks that the \
                     file holds the checkpoint's run and continues it at the checkpoint's step",
                    file.display(),
                    path.display(),
                    self.label,
                    file.display(),
                    path.display()
                ),
            ));
        }
        if let Some(folder) = &self.engine.files().folder {
            return Err(invalid(
                "resume",
                format!(
                    "this simulation writes its files in `{}` from its own start: resuming \
                     it from `{}` would continue them at another step; build it with the \
                     checkpoint instead — rsf.{}(out=…, resume=\"{}\", …) — which checks \
                     that the folder holds the checkpoint's run and continues its files at \
                     the checkpoint's step",
                    folder.display(),
                    path.display(),
                    self.label,
                    path.display()
                ),
            ));
        }
        let c = Checkpoint::read(&path).py()?;
        self.engine.restore(&c).py()
    }

    /// The Green's functions of the run's fault operator `S` (a run condensed onto the
    /// fault, `seas_bp1`'s), as `rsf.GreensFunctions`: the description of the slip
    /// unknowns, the operator applied matrix-free by the run (docs/fault-networks.md,
    /// "Green's functions").
    fn greens_functions<'py>(
        mut slf: PyRefMut<'py, Self>,
        py: Python<'py>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let d = {
            let (g, _) = slf.greens_of()?;
            greens_dict(py, &g)?
        };
        py.import("rsf._greens")?
            .getattr("GreensFunctions")?
            .call_method1("_of_simulation", (slf.into_pyobject(py)?, d))
    }

    /// `S x` (N, or N/m in 2-D) for the slip `x` (m, one per unknown): one product with the
    /// run's operator (what `GreensFunctions.apply` calls).
    fn _greens_apply<'py>(
        &mut self,
        py: Python<'py>,
        x: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = x.as_slice()?.to_vec();
        let (g, op) = self.greens_of()?;
        Ok(array1(py, g.apply(op, &x).py()?))
    }

    /// The dense `S` (m × m), column by column (`m` products), refused above
    /// `max_unknowns` (what `GreensFunctions.matrix` calls).
    fn _greens_dense<'py>(
        &mut self,
        py: Python<'py>,
        max_unknowns: i128,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let max_unknowns = crate::counts::count(max_unknowns, "max_unknowns")?;
        let (g, op) = self.greens_of()?;
        let m = g.dim();
        let s = g.dense(op, max_unknowns).py()?;
        array2(py, &s, m)
    }

    /// Writes the Green's functions and the dense `S` (refused above `max_unknowns`) into
    /// the HDF5 file `path` (`rsf_hdf5::write_greens`; what `GreensFunctions.to_hdf5`
    /// calls; the package built with the feature `hdf5`).
    fn _greens_to_hdf5(&mut self, path: PathBuf, max_unknowns: i128) -> PyResult<()> {
        let max_unknowns = crate::counts::count(max_unknowns, "max_unknowns")?;
        let (g, op) = self.greens_of()?;
        let s = g.dense(op, max_unknowns).py()?;
        crate::fields::write_greens(&path, &g, &s)
    }

    /// The block of `S` from the fault `source`'s slip to the fault `receiver`'s forces
    /// (`m_r × m_s`), from the source's columns alone, refused above `max_unknowns` source
    /// unknowns (what `GreensFunctions.block` calls: `rsf::greens::GreensFunctions::block`).
    fn _greens_block<'py>(
        &mut self,
        py: Python<'py>,
        receiver: &str,
        source: &str,
        max_unknowns: i128,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let max_unknowns = crate::counts::count(max_unknowns, "max_unknowns")?;
        let (g, op) = self.greens_of()?;
        let b = g.block(op, (receiver, source), max_unknowns).py()?;
        array2(py, &b, g.unknowns_of(source).len())
    }

    /// One row per accepted step: `t` (s, after the step), `tau` (s, the step's length),
    /// `step` (index), `max_slip_rate` (m/s, the largest on the fault),
    /// `fixed_point_iterations` — each an array of shape `(steps,)`.
    fn series<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let r = self.engine.recording();
        let d = PyDict::new(py);
        d.set_item("t", array1(py, r.t.clone()))?;
        d.set_item("tau", array1(py, r.tau.clone()))?;
        d.set_item("step", array1(py, r.step.clone()))?;
        d.set_item("max_slip_rate", array1(py, r.max_slip_rate.clone()))?;
        d.set_item(
            "fixed_point_iterations",
            array1(py, r.fixed_point_iterations.clone()),
        )?;
        Ok(d)
    }

    /// The fault's fields every `fault_every` steps (the simulation's setting): `t` (s,
    /// shape `(records,)`), `x` (m, `(n_fault, dim)`), `slip_rate` (m/s, `(records,
    /// n_fault)`), `alpha` (α = ln θ, θ in s, `(records, n_fault)`), `slip` (m, Cartesian,
    /// `(records, n_fault, components)`), `shear_traction` (Pa, `(records, n_fault)`),
    /// `fault_names` (the faults' names, a list) and `fault` (the fault of every node, an
    /// index into `fault_names`, int64 `(n_fault,)`).
    fn fault<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let r = self.engine.recording();
        let (d, c, x) = self.engine.shape();
        let n = x.len() / d;
        let records = r.fault_t.len();
        let out = PyDict::new(py);
        out.set_item("t", array1(py, r.fault_t.clone()))?;
        out.set_item("x", array2(py, &x, d)?)?;
        out.set_item("slip_rate", array2(py, &r.slip_rate, n)?)?;
        out.set_item("alpha", array2(py, &r.alpha, n)?)?;
        out.set_item(
            "slip",
            r.slip.clone().into_pyarray(py).reshape([records, n, c])?,
        )?;
        out.set_item("shear_traction", array2(py, &r.shear_traction, n)?)?;
        let (names, of) = self.engine.faults();
        out.set_item("fault_names", names)?;
        let of: Vec<i64> = of.into_iter().map(|f| f as i64).collect();
        out.set_item("fault", array1(py, of))?;
        Ok(out)
    }

    /// The event catalogue (an event starts when the largest slip rate exceeds 1e-3 m/s and
    /// ends below 1e-4 m/s): `onset` (s, the first step above), `crossing` (s, the
    /// interpolated crossing), `end` (s, NaN while slipping), `duration` (s), `peak_slip_rate`
    /// (m/s), `peak_time` (s), `onset_step` — arrays of shape `(events,)`.
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let ev = self.engine.recording().detector.events();
        let col = |f: &dyn Fn(&rsf::observe::SlipEvent) -> f64| {
            array1(py, ev.iter().map(f).collect::<Vec<f64>>())
        };
        let d = PyDict::new(py);
        d.set_item("onset", col(&|e| e.onset_s))?;
        d.set_item("crossing", col(&|e| e.crossing_s))?;
        d.set_item("end", col(&|e| e.end.map_or(f64::NAN, |(_, t)| t)))?;
        d.set_item("duration", col(&|e| e.duration_s().unwrap_or(f64::NAN)))?;
        d.set_item("peak_slip_rate", col(&|e| e.peak_slip_rate))?;
        d.set_item("peak_time", col(&|e| e.peak_s))?;
        d.set_item(
            "onset_step",
            array1(
                py,
                ev.iter().map(|e| e.onset_step as u64).collect::<Vec<_>>(),
            ),
        )?;
        Ok(d)
    }

    /// The event catalogue across the faults of a problem of your own (`rsf.simulate`;
    /// docs/fault-networks.md, "The catalogue"): events on the largest slip rate of the
    /// whole network with the thresholds of `events()` (onset 1e-3 m/s, end 1e-4 m/s), in
    /// the arrays of `rsf.read_catalogue` — `faults` (the names, `F`), `onset`, `end`,
    /// `duration` (s, `(n,)`; NaN while an event lasts), `nucleation_fault` (the name of
    /// the fault of the fastest node at the onset, `(n,)`), `nucleation_x` (m, `(n, dim)`),
    /// and per event and fault `ruptured` (bool: its slip rate crossed the onset threshold
    /// during the event), `peak_slip_rate` (m/s), `moment` (N·m, per metre in 2-D: the
    /// material's shear modulus times the fault's weighted slip) and `rupture` (s, its
    /// first crossing; NaN where it did not rupture), each `(n, F)`. `InvalidParameterError`
    /// for a scene's run (its programs write `catalogue.csv` instead).
    fn catalogue<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let Some((names, events)) = self.engine.network() else {
            return Err(invalid(
                "catalogue",
                "only a problem of your own (rsf.simulate) keeps the catalogue across faults",
            ));
        };
        let (d, _, _) = self.engine.shape();
        let (n, nf) = (events.len(), names.len());
        let col = |f: &dyn Fn(&rsf::observe::NetworkEvent) -> f64| {
            array1(py, events.iter().map(f).collect::<Vec<f64>>())
        };
        let per_fault = |f: &dyn Fn(&rsf::observe::NetworkEvent, usize) -> f64| {
            let v: Vec<f64> = events
                .iter()
                .flat_map(|e| (0..nf).map(move |j| f(e, j)))
                .collect();
            array2(py, &v, nf)
        };
        let out = PyDict::new(py);
        out.set_item("faults", names.to_vec())?;
        out.set_item("onset", col(&|e| e.onset_s))?;
        out.set_item("end", col(&|e| e.end.map_or(f64::NAN, |(_, t)| t)))?;
        out.set_item(
            "duration",
            col(&|e| e.end.map_or(f64::NAN, |(_, t)| t - e.onset_s)),
        )?;
        let nucleation: Vec<String> = events
            .iter()
            .map(|e| names[e.nucleation_fault].clone())
            .collect();
        let np = py.import("numpy")?;
        out.set_item(
            "nucleation_fault",
            np.call_method1("array", (nucleation, "object"))?,
        )?;
        let x: Vec<f64> = events.iter().flat_map(|e| e.nucleation_x.clone()).collect();
        out.set_item("nucleation_x", x.into_pyarray(py).reshape([n, d])?)?;
        let ruptured: Vec<bool> = events.iter().flat_map(|e| e.ruptured.clone()).collect();
        out.set_item("ruptured", ruptured.into_pyarray(py).reshape([n, nf])?)?;
        out.set_item("peak_slip_rate", per_fault(&|e, j| e.peak_slip_rate[j])?)?;
        out.set_item("moment", per_fault(&|e, j| e.moment[j])?)?;
        out.set_item(
            "rupture",
            per_fault(&|e, j| e.rupture_s[j].unwrap_or(f64::NAN))?,
        )?;
        Ok(out)
    }

    /// The state now on the whole mesh: `points` (m, `(vertices, dim)`), `cells` (vertex
    /// indices, `(cells, dim + 1)`), `displacement` (m) and `velocity` (m/s), Cartesian,
    /// `(vertices, components)`. (A run condensed onto the fault — BP1's Runge–Kutta run —
    /// computes the volume only for observers that read it: its volume fields are NaN.)
    fn fields<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (d, c, _) = self.engine.shape();
        let (points, cells) = self.engine.mesh();
        let (u, v) = self.engine.fields();
        let out = PyDict::new(py);
        out.set_item("points", array2(py, &points, d)?)?;
        let cells: Vec<u64> = cells.iter().map(|&i| i as u64).collect();
        let ncells = cells.len() / (d + 1);
        out.set_item("cells", cells.into_pyarray(py).reshape([ncells, d + 1])?)?;
        out.set_item("displacement", array2(py, &u, c)?)?;
        out.set_item("velocity", array2(py, &v, c)?)?;
        Ok(out)
    }

    /// The series as a pandas DataFrame indexed by time (needs pandas).
    fn to_pandas<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.import("rsf._frames")?
            .call_method1("series_frame", (self.series(py)?,))
    }

    /// The fault records as an xarray Dataset on (t, node) (needs xarray).
    fn to_xarray<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.import("rsf._frames")?
            .call_method1("fault_dataset", (self.fault(py)?,))
    }

    fn __repr__(&self) -> String {
        let s = self.engine.state();
        format!(
            "<rsf.Simulation {}: step {}, t = {:e} s>",
            self.label, s.step, s.time
        )
    }
}

impl Simulation {
    /// The bound of `run()`.
    fn end_until(&self) -> PyResult<Until> {
        match self.end {
            Some(End::Steps(n)) => Ok(Until::Steps(n.saturating_sub(self.engine.state().step))),
            Some(End::Time(t)) => Ok(Until::Time(t)),
            None => Err(invalid(
                "until",
                "this simulation has no end of its own: give `until` (s) or `steps`",
            )),
        }
    }
}
