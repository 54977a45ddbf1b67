//! A problem of your own from Python: a model of a mesh (`crate::mesh`;
//! `rsf::ModelBuilder`'s choices under its names) and a
//! simulation (`rsf::SimulationBuilder`'s: friction, state law, initial state, step,
//! integrator, solver), with friction parameters per fault node.

use numpy::{PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::FaultOdeOptions;
use rsf::fem::SimplexMesh;
use rsf::friction::{AsinhLaw, DieterichRuina, FrictionLaw, RateStateParams, Tresca};
use rsf::state::BuiltinStateLaw;
use rsf::{
    Integrator, Material, ModelBuilder, Part, SimulationBuilder, SolverKind, StateLawKind,
    TimeFunction,
};

use crate::convert::{fnv1a, PerNode};
use crate::engine::{Engine, Files, Recording, WithFaultOperator};
use crate::errors::{invalid, OrPy};
use crate::mesh::{AnyMesh, Mesh};
use crate::network::{
    explain, fault_nodes, fault_specs, faults_of, per_fault_node, FaultSpec, NetworkBuilder,
};
use crate::simulation::{End, Simulation};

/// A boundary part from Python: a tag (a Gmsh physical group's name) or `(name,
/// predicate)`, the predicate a function of a facet's midpoint `x` (shape `(dim,)`, m)
/// returning a bool.
fn part<const D: usize>(py: Python<'_>, obj: &Bound<'_, PyAny>) -> PyResult<Part<D>> {
    if let Ok(tag) = obj.extract::<String>() {
        return Ok(Part::tag(tag));
    }
    let (name, predicate): (String, Py<PyAny>) = obj.extract().map_err(|_| {
        invalid(
            "part",
            "a tag (str) or a (name, predicate) pair, the predicate a function of a facet's midpoint",
        )
    })?;
    let _ = py;
    Ok(Part::predicate(name, move |x: &[f64; D]| {
        Python::attach(|py| {
            let x = numpy::PyArray1::from_slice(py, x);
            predicate
                .call1(py, (x,))
                .and_then(|r| r.extract::<bool>(py))
                .unwrap_or(false)
        })
    }))
}

/// A part as a checkpoint's fingerprint names it: a tag as written, `(name, predicate)`
/// by its name and `predicate` (the nodes it selects are described by value, [`describe`]).
fn part_label(obj: &Bound<'_, PyAny>) -> String {
    match obj.extract::<String>() {
        Ok(tag) => tag,
        Err(_) => match obj.extract::<(String, Bound<'_, PyAny>)>() {
            Ok((name, _)) => format!("('{name}', predicate)"),
            Err(_) => obj.to_string(),
        },
    }
}

/// The model's description for a checkpoint's fingerprint: `head` (material, refinement,
/// gravity, ramp), the parts' labels (Dirichlet parts with their velocities, the
/// frictional part) and — where a part is a predicate — what it selected, by value: a hash
/// of the frictional nodes' indices and of the fixed degrees of freedom (issue 86: the
/// description held the predicate's repr, its address, so that a checkpoint never
/// resumed in a new process). A model of tags only is described as before.
fn describe(
    head: &str,
    parts: (Vec<(String, Vec<f64>)>, Option<String>),
    model: &AnyModel,
) -> String {
    let (dirichlet, friction) = parts;
    let mut text = format!("{head} dirichlet {dirichlet:?} friction {friction:?}");
    let predicates = dirichlet.iter().map(|(l, _)| l).chain(&friction);
    if predicates.into_iter().any(|l| l.ends_with(", predicate)")) {
        let (nodes, fixed) = match model {
            AnyModel::Two(m) => (&m.frictional_boundary.nodes, &m.fixed),
            AnyModel::Three(m) => (&m.frictional_boundary.nodes, &m.fixed),
        };
        let nodes = fnv1a(nodes.iter().flat_map(|&i| (i as u64).to_le_bytes()));
        let fixed = fnv1a(fixed.iter().map(|&f| u8::from(f)));
        text.push_str(&format!(
            " selected: frictional nodes {nodes:016x} fixed dofs {fixed:016x}"
        ));
    }
    text
}

/// A model of a mesh: material, gravity, boundary conditions and the frictional part.
#[pyclass(module = "rsf._rsf", name = "Model")]
pub struct Model {
    model: AnyModel,
    description: String,
    /// The material's shear modulus `E / (2 (1 + ν))` (Pa): the moments of the catalogue.
    rigidity: f64,
}

#[derive(Clone)]
enum AnyModel {
    Two(rsf::Model<2>),
    Three(rsf::Model<3>),
}

/// The builder's choices for a `D`-dimensional model.
#[allow(clippy::too_many_arguments)]
fn build_model<const D: usize>(
    py: Python<'_>,
    mesh: SimplexMesh<D>,
    refine: usize,
    material: Material,
    gravity: Option<Vec<f64>>,
    dirichlet: &[(Bound<'_, PyAny>, Vec<f64>)],
    fault: (Option<&Bound<'_, PyAny>>, &[FaultSpec]),
    ramp: Option<f64>,
) -> PyResult<rsf::Model<D>>
where
    ModelBuilder<D>: NetworkBuilder<D>,
{
    let (frictional_boundary, faults) = fault;
    let coarse = (!faults.is_empty()).then(|| mesh.clone());
    let vector = |name: &str, v: &[f64]| -> PyResult<[f64; D]> {
        <[f64; D]>::try_from(v)
            .map_err(|_| invalid(name, format!("{D} components, not {}", v.len())))
    };
    let mut b = if refine > 0 {
        ModelBuilder::refined(mesh, refine).py()?
    } else {
        ModelBuilder::new(mesh)
    };
    b = b.material(material);
    if let Some(g) = gravity {
        b = b.gravity(vector("gravity", &g)?);
    }
    for (p, v) in dirichlet {
        b = b.dirichlet(part::<D>(py, p)?, vector("dirichlet", v)?);
    }
    if let Some(f) = frictional_boundary {
        b = b.frictional_boundary(part::<D>(py, f)?);
    }
    b = b.with_faults(faults);
    if let Some(t) = ramp {
        b = b.loading(TimeFunction::ramp(t));
    }
    b.build().map_err(|e| match coarse {
        Some(mesh) => explain(e, mesh, refine, faults),
        None => crate::errors::to_py(e),
    })
}

#[pymethods]
impl Model {
    /// The model of `mesh` refined `refine` times (a hierarchy for TNNMG), of a linear
    /// elastic material (`youngs_modulus` Pa, `poisson_ratio`, `density` kg/m³; plane strain
    /// in 2-D), with `gravity` (m/s², a vector), `dirichlet` parts (a list of `(part,
    /// velocity)`: the part moves with `velocity · g(t)`, m/s), a `frictional_boundary`
    /// part (bilateral contact with friction on a rigid base) and the loading `g(t) =
    /// min(t / ramp, 1)` (s; constant 1 without `ramp`). A part is a tag (a Gmsh physical
    /// group) or `(name, predicate)`, the predicate a function of a facet's midpoint. The
    /// library's checks name the part or parameter at fault.
    ///
    /// `faults`: faults inside the body (a network: a stepover, parallel strands, a branch
    /// or a crossing in 2-D; disjoint faults in 3-D), a list of `(name, points)` — in 2-D
    /// `points` of shape `(k, 2)`, `k ≥ 2` (m): a segment or a polyline resolved by mesh
    /// edges (`rsf::ModelBuilder::internal_fault_polyline`; the slip's direction from
    /// `points[0]`, the plus side on its left); in 3-D `(k, 3)`, `k ≥ 3`: a convex planar
    /// polygon's corners tiled by mesh faces (`internal_fault_polygon`). Instead of points,
    /// the name of a Gmsh physical group inside the body of a mesh read by
    /// `Mesh.read_gmsh`: a curve in 2-D (its polyline), a surface in 3-D (its faces, any
    /// shape: `internal_fault_faces`). Beside or without a
    /// `frictional_boundary` (its nodes after the faults'). Names are unique; a name, a
    /// shape or a coordinate refused raises `InvalidParameterError`, a fault the mesh cannot
    /// be cut along (not resolved, on the outer boundary, faults meeting in a junction the
    /// network does not support) `ModelError` — both naming `faults` and the fault.
    #[new]
    #[pyo3(signature = (mesh, *, youngs_modulus, poisson_ratio, density, refine=0, gravity=None, dirichlet=Vec::new(), frictional_boundary=None, ramp=None, faults=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        mesh: &Mesh,
        youngs_modulus: f64,
        poisson_ratio: f64,
        density: f64,
        refine: i128,
        gravity: Option<Vec<f64>>,
        dirichlet: Vec<(Bound<'_, PyAny>, Vec<f64>)>,
        frictional_boundary: Option<Bound<'_, PyAny>>,
        ramp: Option<f64>,
        faults: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let refine = crate::counts::count(refine, "refine")?;
        let faults = fault_specs(faults.as_ref(), mesh.dim(), &mesh.interior)?;
        let material = Material::new(youngs_modulus, poisson_ratio, density);
        let head = format!(
            "E {youngs_modulus:e} nu {poisson_ratio:e} rho {density:e} refine {refine} \
             gravity {gravity:?} ramp {ramp:?}"
        );
        let parts = (
            dirichlet
                .iter()
                .map(|(p, v)| (part_label(p), v.clone()))
                .collect::<Vec<_>>(),
            frictional_boundary.as_ref().map(part_label),
        );
        let fb = (frictional_boundary.as_ref(), &faults[..]);
        // The model of the mesh's dimension `$D`.
        macro_rules! build {
            ($m:expr, $D:literal) => {
                build_model::<$D>(
                    py,
                    $m.clone(),
                    refine,
                    material,
                    gravity,
                    &dirichlet,
                    fb,
                    ramp,
                )?
            };
        }
        let model = match &mesh.mesh {
            AnyMesh::Two(m) => AnyModel::Two(build!(m, 2)),
            AnyMesh::Three(m) => AnyModel::Three(build!(m, 3)),
        };
        let mut description = describe(&head, parts, &model);
        if !faults.is_empty() {
            description.push_str(&format!(" faults {faults:?}"));
        }
        let rigidity = youngs_modulus / (2.0 * (1.0 + poisson_ratio));
        Ok(Self {
            model,
            description,
            rigidity,
        })
    }

    /// Mesh vertices (after refinement and splitting).
    #[getter]
    fn num_nodes(&self) -> usize {
        match &self.model {
            AnyModel::Two(m) => m.num_nodes(),
            AnyModel::Three(m) => m.num_nodes(),
        }
    }

    /// Coordinates of the frictional nodes (m), shape `(n_fault, dim)`: the order of every
    /// per-node parameter.
    #[getter]
    fn fault_coordinates<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (x, d) = match &self.model {
            AnyModel::Two(m) => (coords(m), 2),
            AnyModel::Three(m) => (coords(m), 3),
        };
        let n = x.len() / d;
        numpy::IntoPyArray::into_pyarray(x, py).reshape([n, d])
    }

    /// The names of the model's faults, in the order `faults` gave them (then the
    /// frictional boundary's part, if any); one name for a model with a frictional boundary
    /// only (its part's).
    #[getter]
    fn fault_names(&self) -> Vec<String> {
        self.faults().0
    }

    /// The fault of every frictional node: an index into `fault_names`, shape `(n_fault,)`
    /// (int64), in the order of `fault_coordinates` and of every per-node parameter.
    #[getter]
    fn fault_index<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<i64>> {
        let of: Vec<i64> = self.faults().1.iter().map(|&f| f as i64).collect();
        numpy::IntoPyArray::into_pyarray(of, py)
    }

    /// The frictional nodes of the fault `name` (positions in `fault_coordinates`, int64)
    /// in order along the fault. `InvalidParameterError` naming `name` for a name the model
    /// does not have.
    fn fault_nodes<'py>(
        &self,
        py: Python<'py>,
        name: &str,
    ) -> PyResult<Bound<'py, numpy::PyArray1<i64>>> {
        let k = match &self.model {
            AnyModel::Two(m) => fault_nodes(m, name)?,
            AnyModel::Three(m) => fault_nodes(m, name)?,
        };
        let k: Vec<i64> = k.into_iter().map(|k| k as i64).collect();
        Ok(numpy::IntoPyArray::into_pyarray(k, py))
    }
}

impl Model {
    /// The faults' names and the fault of every frictional node.
    fn faults(&self) -> (Vec<String>, Vec<usize>) {
        match &self.model {
            AnyModel::Two(m) => faults_of(m),
            AnyModel::Three(m) => faults_of(m),
        }
    }
}

fn coords<const D: usize>(m: &rsf::Model<D>) -> Vec<f64> {
    m.on_frictional_nodes(|x| *x)
        .into_iter()
        .flatten()
        .collect()
}

/// A friction law with its parameters, each a number, an array (one per fault node) or a
/// function of the fault nodes' coordinates.
#[pyclass(module = "rsf._rsf", name = "Friction")]
pub struct Friction {
    kind: FrictionKind,
    params: Vec<(&'static str, Param)>,
}

#[derive(Clone, Copy, PartialEq)]
enum FrictionKind {
    DieterichRuina,
    Regularised,
    Tresca,
}

/// A friction parameter from Python: a number, an array (one per fault node) or a
/// function of the fault nodes' coordinates.
type Param = Py<PyAny>;

impl Friction {
    /// A rate-and-state law `kind` with its parameters `mu0`, `a`, `b`, `v0`, `l`,
    /// `sigma_n` in this order.
    fn rate_state(kind: FrictionKind, values: [Param; 6]) -> Self {
        let names = ["mu0", "a", "b", "v0", "l", "sigma_n"];
        Self {
            kind,
            params: names.into_iter().zip(values).collect(),
        }
    }
}

#[pymethods]
impl Friction {
    /// Dieterich–Ruina friction with the V_m cutoff (the paper's (2.9), (2.12)–(2.13)):
    /// `mu0`, `a`, `b` (dimensionless), `v0` (m/s), `l` (m), `sigma_n` (Pa).
    #[staticmethod]
    fn dieterich_ruina(
        mu0: Param,
        a: Param,
        b: Param,
        v0: Param,
        l: Param,
        sigma_n: Param,
    ) -> Self {
        Self::rate_state(FrictionKind::DieterichRuina, [mu0, a, b, v0, l, sigma_n])
    }

    /// The regularised law `μ = a asinh(V/(2V0) exp((μ0 + b ln(V0 θ/L))/a))` (the SEAS
    /// benchmarks'): the parameters of `dieterich_ruina`.
    #[staticmethod]
    fn regularised(mu0: Param, a: Param, b: Param, v0: Param, l: Param, sigma_n: Param) -> Self {
        Self::rate_state(FrictionKind::Regularised, [mu0, a, b, v0, l, sigma_n])
    }

    /// Tresca friction: a constant friction coefficient `mu` and normal stress `sigma_n`
    /// (Pa); no state.
    #[staticmethod]
    fn tresca(mu: Param, sigma_n: Param) -> Self {
        Self {
            kind: FrictionKind::Tresca,
            params: vec![("mu", mu), ("sigma_n", sigma_n)],
        }
    }
}

/// `rsf.simulate`'s `state_law`: one law's name, or a dict from every fault's name to one.
#[derive(FromPyObject)]
pub(crate) enum StateLawArg {
    /// One law for every frictional node.
    One(String),
    /// A law per fault.
    PerFault(std::collections::BTreeMap<String, String>),
}

impl StateLawArg {
    /// The law of every fault (in `names`' order) and the fingerprint's text: the name, or
    /// `fault=law` per fault in `names`' order.
    ///
    /// # Errors
    /// `InvalidParameterError` named `state_law`: an unknown law, a dict without one of
    /// the faults or with a name that is none of them.
    fn per_fault(&self, names: &[String]) -> PyResult<(Vec<StateLawKind>, String)> {
        let parse = |law: &str| {
            law.parse::<StateLawKind>()
                .map_err(|e: rsf::state::Error| crate::errors::to_py(e.into()))
        };
        match self {
            Self::One(law) => Ok((vec![parse(law)?; names.len().max(1)], law.clone())),
            Self::PerFault(laws) => {
                if let Some(other) = laws.keys().find(|k| !names.contains(k)) {
                    return Err(invalid(
                        "state_law",
                        format!(
                            "`{}` is none of the model's faults {names:?}",
                            rsf_numeric::excerpt(other)
                        ),
                    ));
                }
                let mut kinds = Vec::with_capacity(names.len());
                let mut text = Vec::with_capacity(names.len());
                for name in names {
                    let law = laws.get(name).ok_or_else(|| {
                        invalid("state_law", format!("no law for the fault `{name}`"))
                    })?;
                    kinds.push(parse(law)?);
                    text.push(format!("{name}={law}"));
                }
                Ok((kinds, text.join(",")))
            }
        }
    }
}

/// The method's choices of `rsf.simulate`.
struct Choices {
    /// The state law of every fault (an index of `fault_of`'s), one entry for a model of
    /// one unnamed frictional part.
    state_laws: Vec<StateLawKind>,
    /// The fault of every frictional node.
    fault_of: Vec<usize>,
    integrator: Integrator,
    solver: SolverKind,
    tau: f64,
    fault_every: usize,
    end_time: Option<f64>,
    /// The radiation damping η (Pa·s/m) per fault node, if given.
    radiation_damping: Option<PerNode>,
    /// The fault ODE (`method="fault-ode"`) instead of the implicit scheme.
    fault_ode: bool,
    /// The shear modulus of the catalogue's moments (Pa).
    rigidity: f64,
}

/// Resolved parameters per fault node.
type Resolved = Vec<(&'static str, PerNode)>;

fn value(r: &Resolved, name: &str, k: usize) -> f64 {
    r.iter()
        .find(|(n, _)| *n == name)
        .map_or(f64::NAN, |(_, v)| v.at(k))
}

fn params(r: &Resolved, k: usize) -> RateStateParams {
    RateStateParams {
        mu0: value(r, "mu0", k),
        a: value(r, "a", k),
        b: value(r, "b", k),
        v0: value(r, "v0", k),
        l: value(r, "l", k),
        sigma_n: value(r, "sigma_n", k),
    }
}

/// The simulation of `model` with friction laws `law(k)` per fault node: the implicit
/// scheme's, or the fault ODE's (`c.method`).
fn simulate_with<const D: usize, L: FrictionLaw + 'static>(
    model: rsf::Model<D>,
    friction: impl Fn(usize) -> rsf::Result<L>,
    r: &Resolved,
    alpha0: &PerNode,
    c: &Choices,
    fingerprint: Fingerprint,
) -> PyResult<Simulation>
where
    rsf::Simulation<D, L, BuiltinStateLaw, Integrator>: rsf::Stepping<D, D>,
    rsf::FaultOde<D, L, BuiltinStateLaw>: rsf::Stepping<D, D>,
{
    let (mut kf, mut ks, mut ka, mut ke) = (0, 0, 0, 0);
    let mut builder = SimulationBuilder::new(model)
        .friction_at(|_x| {
            kf += 1;
            friction(kf - 1)
        })
        .state_law_at(|_x| {
            ks += 1;
            // The Tresca law has no `l`: any positive length (its state is unused).
            let l = value(r, "l", ks - 1);
            let fault = c.fault_of.get(ks - 1).copied().unwrap_or(0);
            let kind = c.state_laws[fault];
            BuiltinStateLaw::new(kind, if l.is_nan() { 1.0 } else { l })
        })
        .initial_state_at(|_x| {
            ka += 1;
            alpha0.at(ka - 1)
        })
        .time_step(c.tau)
        .integrator(c.integrator);
    if let Some(eta) = &c.radiation_damping {
        builder = builder.radiation_damping_at(|_x| {
            ke += 1;
            eta.at(ke - 1)
        });
    }
    let recording = Recording::new(c.fault_every).py()?.with_network(c.rigidity);
    let end = c.end_time.map(End::Time);
    if c.fault_ode {
        let sim = builder.build_fault_ode(FaultOdeOptions::default()).py()?;
        return own_problem(sim, recording, fingerprint, end);
    }
    let sim = builder.solver(c.solver).build().py()?;
    own_problem(sim, recording, fingerprint, end)
}

/// The Python simulation of the run `sim` of an own problem: its recording (with the
/// catalogue across the faults, started here) and its fingerprint.
fn own_problem<const D: usize, M>(
    sim: M,
    recording: Recording,
    fingerprint: Fingerprint,
    end: Option<End>,
) -> PyResult<Simulation>
where
    M: rsf::Stepping<D, D> + WithFaultOperator + 'static,
{
    let mut engine = Engine::<D, D, M> {
        sim,
        recording,
        files: Vec::new(),
        fingerprint,
        folder: Files::default(),
    };
    engine.start_network().py()?;
    Ok(Simulation::new(Box::new(engine), end, "own problem"))
}

/// A simulation of `model`: `friction` (`rsf.Friction.dieterich_ruina(...)`,
/// `.regularised(...)`, `.tresca(...)`), `state_law` ("aging", "slip"; "discontinuous", which
/// evolves θ itself, only with `.tresca(...)`; or a dict from every fault's name to one),
/// `alpha0` (the initial state α = ln θ; a number, an array or a function of the fault
/// nodes' coordinates), the time step `tau` (s), `integrator` ("newmark",
/// "backward-euler", "quasistatic"), `solver` ("auto", "tnnmg", "direct",
/// "gauss-seidel"), `end_time` (s, the end of `run()`), `fault_every` (record the fault's
/// fields every that many steps). The library's checks run here (a free normal velocity
/// on the fault, a state law that does not fit the friction law, …).
///
/// `method`: "implicit" (the default: the implicit step, `integrator` default "newmark",
/// `solver` default "auto") or "fault-ode" (quasi-dynamic, condensed onto the fault and
/// integrated by an adaptive Runge–Kutta pair, `tau` its first trial step; `integrator`
/// "quasistatic", the only one it takes, `solver` refused; it needs `radiation_damping`;
/// its `greens_functions()` are the model's). `radiation_damping`: η (Pa·s/m) per fault
/// node. Every per-node parameter (friction's, `alpha0`, `radiation_damping`) may also be
/// a dict from every fault's name (`model.fault_names`) to a number, an array of that
/// fault's nodes (in `fault_coordinates` order restricted to it) or a function of their
/// coordinates.
#[pyfunction]
#[pyo3(signature = (model, *, friction, alpha0, tau, state_law=StateLawArg::One("aging".into()), integrator=None, solver=None, end_time=None, fault_every=0, method="implicit", radiation_damping=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn simulate(
    py: Python<'_>,
    model: &Model,
    friction: &Friction,
    alpha0: Bound<'_, PyAny>,
    tau: f64,
    state_law: StateLawArg,
    integrator: Option<&str>,
    solver: Option<&str>,
    end_time: Option<f64>,
    fault_every: i128,
    method: &str,
    radiation_damping: Option<Bound<'_, PyAny>>,
) -> PyResult<Simulation> {
    let fault_every = crate::counts::count(fault_every, "fault_every")?;
    let fault_ode = match method {
        "implicit" => false,
        "fault-ode" => true,
        m => {
            return Err(invalid(
                "method",
                format!(
                    "`{}`: \"implicit\" or \"fault-ode\"",
                    rsf_numeric::excerpt(m)
                ),
            ))
        }
    };
    if let (true, Some(s)) = (fault_ode, solver) {
        return Err(invalid(
            "solver",
            format!(
                "`{}` is a setting of the implicit method, which method=\"fault-ode\" does not use",
                rsf_numeric::excerpt(s)
            ),
        ));
    }
    let integrator = integrator.unwrap_or(if fault_ode { "quasistatic" } else { "newmark" });
    let solver = solver.unwrap_or("auto");
    let (names, of) = model.faults();
    let (state_laws, state_law) = state_law.per_fault(&names)?;
    let mut c = Choices {
        state_laws,
        fault_of: of.clone(),
        integrator: integrator
            .parse()
            .map_err(|e: rsf::time::Error| crate::errors::to_py(e.into()))?,
        solver: solver.parse::<SolverKind>().py()?,
        tau,
        fault_every,
        end_time,
        radiation_damping: None,
        fault_ode,
        rigidity: model.rigidity,
    };
    if c.state_laws.contains(&StateLawKind::Discontinuous) && friction.kind != FrictionKind::Tresca
    {
        return Err(crate::errors::discontinuous_needs_theta());
    }
    let (x, d) = match &model.model {
        AnyModel::Two(m) => (coords(m), 2),
        AnyModel::Three(m) => (coords(m), 3),
    };
    let mut r: Resolved = Vec::new();
    let mut fingerprint = Fingerprint::default()
        .with("model", &model.description)
        .with("state_law", &state_law)
        .with("integrator", integrator)
        .with("solver", solver)
        .with("tau", tau);
    let faults = (&names[..], &of[..]);
    for (name, obj) in &friction.params {
        let v = per_fault_node(py, name, obj.bind(py), &x, d, faults)?;
        fingerprint = fingerprint.with(name, v.describe());
        r.push((name, v));
    }
    let alpha0 = per_fault_node(py, "alpha0", &alpha0, &x, d, faults)?;
    fingerprint = fingerprint.with("alpha0", alpha0.describe());
    if let Some(eta) = &radiation_damping {
        let eta = per_fault_node(py, "radiation_damping", eta, &x, d, faults)?;
        fingerprint = fingerprint.with("radiation_damping", eta.describe());
        c.radiation_damping = Some(eta);
    }
    if fault_ode {
        fingerprint = fingerprint.with("method", method);
    }
    macro_rules! run {
        ($m:expr, $D:literal) => {
            match friction.kind {
                FrictionKind::DieterichRuina => {
                    run!($m, $D, |k| DieterichRuina::new(params(&r, k)))
                }
                FrictionKind::Regularised => run!($m, $D, |k| AsinhLaw::new(params(&r, k))),
                FrictionKind::Tresca => run!($m, $D, |k| {
                    Tresca::new(value(&r, "mu", k), value(&r, "sigma_n", k))
                }),
            }
        };
        // The simulation of the law `$law` makes at node `k`.
        ($m:expr, $D:literal, |$k:ident| $law:expr) => {
            simulate_with::<$D, _>(
                $m,
                |$k| $law.map_err(Into::into),
                &r,
                &alpha0,
                &c,
                fingerprint,
            )
        };
    }
    match model.model.clone() {
        AnyModel::Two(m) => run!(m, 2),
        AnyModel::Three(m) => run!(m, 3),
    }
}
