//! A fault without a volume: the fault ODE's elastic part given as an operator and a
//! plate motion instead of condensed from a finite-element body — the formulation of
//! boundary-element earthquake-cycle codes (a planar fault in a half-space loaded by
//! back slip, docs/math.md §12, "A fault alone"; SEAS BP5, docs/seas-bp5.md).
//!
//! The model is a [`Model::fault_only`] (its vertices the fault's cells, no stiffness);
//! [`SimulationBuilder::build_fault_ode_alone`](crate::SimulationBuilder::build_fault_ode_alone)
//! runs it with a [`FaultAlone`].

use std::ops::ControlFlow;

use rsf_direct::{CheckpointPolicy, Condensation, Progress};
use rsf_linalg::Parallelism;

use crate::error::{check_len, invalid, Result};
use crate::fault_operator::FaultOperator;
use rsf_fem::NodalFrames;

use crate::model::{DirichletVelocity, FrictionalBoundary, Model};

/// The elastic part of a fault without a volume, for
/// [`SimulationBuilder::build_fault_ode_alone`](crate::SimulationBuilder::build_fault_ode_alone).
///
/// With `S` the operator ([`FaultOperator`], slip (m) → force (N)), `g₀` the model's load
/// on the slip unknowns (N: the prestress times the nodes' weights) and `v_pl` the plate
/// velocity of every slip unknown (m/s), the fault's balance is
///
/// ```text
/// g₀ − S (u_F − t v_pl) = w (τ(V, α) + η V)
/// ```
///
/// — **back slip**: a fault slipping at the plate velocity everywhere feels no stress
/// change, as the infinite plane of a half-space model creeping uniformly around the
/// fault (Savage 1983). The load rate `S v_pl` is computed once, with the operator's own
/// product.
pub struct FaultAlone {
    /// The elastic operator on the fault's slip unknowns.
    pub operator: Box<dyn FaultOperator>,
    /// The plate velocity of every slip unknown (m/s; length the operator's dimension,
    /// node by node, the free components of each in order).
    pub plate_velocity: Vec<f64>,
}

impl std::fmt::Debug for FaultAlone {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FaultAlone")
            .field("dim", &self.operator.dim())
            .field("report", self.operator.report())
            .finish_non_exhaustive()
    }
}

/// How a fault ODE gets its elastic part.
pub(crate) enum Elastic {
    /// Condensed from the model's body, with the operator `S` given or condensed too.
    Condensed(Option<Box<dyn FaultOperator>>),
    /// A fault alone.
    Alone(FaultAlone),
    /// Condensed from the model's body without its whole factor.
    SchurOnly(SchurOnlySetup),
}

/// Where a fault ODE's unknowns live: the condensed finite-element body, or the fault
/// alone (its free components, node by node).
pub(crate) enum Body<const C: usize> {
    /// A finite-element body condensed onto the fault.
    Volume(Box<Condensation<C>>),
    /// No volume: the slip unknowns' dofs.
    Alone {
        /// The model dof of every slip unknown.
        dofs: Vec<usize>,
    },
    /// A finite-element body condensed onto the fault without its factor
    /// ([`rsf_direct::SchurOnly`]): no extension off the fault but the probe's.
    Condensed {
        /// The model dof of every slip unknown.
        dofs: Vec<usize>,
    },
}

impl<const C: usize> Body<C> {
    /// Number of slip unknowns.
    pub(crate) fn dim(&self) -> usize {
        self.interface_dofs().len()
    }

    /// The model dof of every slip unknown.
    pub(crate) fn interface_dofs(&self) -> &[usize] {
        match self {
            Self::Volume(c) => c.interface_dofs(),
            Self::Alone { dofs } | Self::Condensed { dofs } => dofs,
        }
    }

    /// Entries of the volume's factor (0 without one).
    pub(crate) fn factor_nnz(&self) -> usize {
        match self {
            Self::Volume(c) => c.factor_nnz(),
            Self::Alone { .. } | Self::Condensed { .. } => 0,
        }
    }

    /// The condensation, if there is a volume.
    pub(crate) fn volume_mut(&mut self) -> Option<&mut Condensation<C>> {
        match self {
            Self::Volume(c) => Some(c),
            Self::Alone { .. } | Self::Condensed { .. } => None,
        }
    }
}

/// The free components of the frictional nodes, node by node (the slip unknowns of a
/// fault alone).
pub(crate) fn free_fault_dofs<const D: usize, const C: usize>(model: &Model<D, C>) -> Vec<usize> {
    let mut dofs = Vec::new();
    for &p in &model.frictional_boundary.nodes {
        dofs.extend((C * p..C * p + C).filter(|&i| !model.fixed[i]));
    }
    dofs
}

/// The checks of a fault alone on `model`, and its load rate `S v_pl` (N/s).
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `stiffness` for a
/// model with a stiffness, `dirichlet` for prescribed velocities, `plate_velocity` for a
/// length other than the operator's or non-finite entries, `fault_operator` for an
/// operator of another dimension than the fault's slip unknowns; the product's errors.
pub(crate) fn load_rate<const D: usize, const C: usize>(
    model: &Model<D, C>,
    alone: &mut FaultAlone,
    par: Parallelism,
) -> Result<Vec<f64>> {
    if model.stiffness.compute_nnz() != 0 {
        return Err(invalid(
            "stiffness",
            "a fault alone has no volume: the model's stiffness must be empty (Model::fault_only)",
        ));
    }
    if !model.dirichlet.dofs.is_empty() {
        return Err(invalid(
            "dirichlet",
            "a fault alone is loaded by its plate velocity (FaultAlone::plate_velocity), \
             not by prescribed velocities",
        ));
    }
    let m = free_fault_dofs(model).len();
    check_len("fault_operator", alone.operator.dim(), m, |len, m| {
        format!("an operator of {len} unknowns for a fault of {m} slip unknowns")
    })?;
    check_len("plate_velocity", alone.plate_velocity.len(), m, |len, m| {
        format!("has {len} entries for {m} slip unknowns")
    })?;
    if let Some(i) = alone.plate_velocity.iter().position(|v| !v.is_finite()) {
        return Err(invalid(
            "plate_velocity",
            format!("entry {i} is {}", alone.plate_velocity[i]),
        ));
    }
    let mut r = vec![0.0; m];
    alone
        .operator
        .subtract_product(&alone.plate_velocity, &mut r, par)?;
    Ok(r.into_iter().map(|x| -x).collect())
}

impl<const D: usize> Model<D, D> {
    /// A model of a fault alone, without a volume: one vertex per cell of the fault at
    /// `centres` (m) with weight `areas` (its area, m²; length in 1-D), the component
    /// `normal_axis` of every cell fixed (no opening) and the others its slip; no
    /// stiffness, mass, load or prescribed velocity. Set the prestress as
    /// [`load`](Model::load) (N: traction times area on each slip component) and run it with
    /// [`SimulationBuilder::build_fault_ode_alone`](crate::SimulationBuilder::build_fault_ode_alone),
    /// whose operator (e.g. Okada's half-space stiffness,
    /// [`HalfSpaceOperator::fault_alone`](crate::halfspace_operator::HalfSpaceOperator::fault_alone))
    /// gives the elasticity. The field of the model is the slip (`u⁺ − u⁻`), its
    /// frictional nodes are all vertices in order.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `centres` (none,
    /// or non-finite coordinates), `areas` (another length, non-positive or non-finite
    /// entries) or `normal_axis` (`≥ D`).
    pub fn fault_only(centres: Vec<[f64; D]>, areas: &[f64], normal_axis: usize) -> Result<Self> {
        if centres.is_empty() {
            return Err(invalid("centres", "a fault alone needs at least one cell"));
        }
        if let Some(k) = centres
            .iter()
            .position(|x| x.iter().any(|c| !c.is_finite()))
        {
            return Err(invalid(
                "centres",
                format!("cell {k} at {:?} is not finite", centres[k]),
            ));
        }
        if areas.len() != centres.len() {
            return Err(invalid(
                "areas",
                format!("{} areas for {} cells", areas.len(), centres.len()),
            ));
        }
        if normal_axis >= D {
            return Err(invalid(
                "normal_axis",
                format!("{normal_axis} must be below the dimension {D}"),
            ));
        }
        let cells: Vec<usize> = (0..centres.len()).collect();
        let frictional_boundary = FrictionalBoundary::new(&cells, areas)
            .map_err(|_| invalid("areas", "must be finite and positive"))?;
        let n = D * centres.len();
        let empty = || {
            crate::fem::SparseMatrix::try_new_from_triplets(n, n, &[])
                .expect("an empty n × n matrix is valid")
        };
        let fixed = (0..n).map(|i| i % D == normal_axis).collect();
        Ok(Self {
            vertices: centres,
            mass: None,
            stiffness: empty(),
            energy_norm: empty(),
            load: vec![0.0; n],
            fixed,
            dirichlet: DirichletVelocity::none(),
            prolongations: Vec::new(),
            frictional_boundary,
            initial_displacement: vec![0.0; n],
            cells: Vec::new(),
            frames: NodalFrames::default(),
            absorbing: None,
            internal_fault: None,
            columns: None,
        })
    }
}

impl<const D: usize> Model<D, D> {
    /// Gives a fault alone ([`Model::fault_only`]) the stiffness of `operator` as its
    /// stiffness matrix and energy norm, so that the **implicit scheme**
    /// ([`Simulation`](crate::Simulation) with [`SolverKind::Direct`](crate::SolverKind::Direct))
    /// runs it: the fault's balance `g₀ − S u_F = w (τ + ηV)` is then the model's
    /// `K u = f` on the slip unknowns, and each step's nonsmooth problem is solved on the
    /// fault by the direct solver (its condensation has no interior: the Schur complement is
    /// `S` itself, the dense Newton iteration works on it). A rate-independent friction
    /// (Tresca, SEAS BP6-C; docs/seas-bp6.md) needs this: the fault ODE's explicit steps
    /// are limited by the damping alone there.
    ///
    /// `S` is formed densely, one product with `operator` per slip unknown (`m` products,
    /// `m²` f64 stored as a sparse matrix with every entry, twice: the stiffness and the
    /// energy norm), and symmetrised (`(S + Sᵀ)/2`, against the round-off of an FFT or an
    /// ℋ-matrix product). Suited to faults of a few thousand unknowns (4 000: 2 × 256 MB).
    /// The model is loaded by its [`load`](Model::load) only (no plate velocity: a back-slip
    /// loading is a load rate the implicit scheme does not take).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `stiffness` for a
    /// model with a stiffness already, `fault_operator` for an operator of another
    /// dimension than the fault's slip unknowns, or more than 20 000 of them; the product's
    /// errors; `stiffness` for a non-finite entry or an `S` that is not positive on the
    /// diagonal.
    pub fn set_fault_stiffness(
        &mut self,
        operator: &mut dyn FaultOperator,
        par: Parallelism,
    ) -> Result<()> {
        if self.stiffness.compute_nnz() != 0 {
            return Err(invalid(
                "stiffness",
                "the model has a stiffness already: a fault alone (Model::fault_only) has none",
            ));
        }
        let dofs = free_fault_dofs(self);
        let m = dofs.len();
        if operator.dim() != m || m == 0 || m > 20_000 {
            return Err(invalid(
                "fault_operator",
                format!(
                    "an operator of {} unknowns for a fault of {m} slip unknowns (at least \
                     one, at most 20 000 formed densely)",
                    operator.dim()
                ),
            ));
        }
        // Column j of S: −(0 − S e_j).
        let mut s = vec![0.0; m * m];
        let mut e = vec![0.0; m];
        for j in 0..m {
            e[j] = 1.0;
            operator.subtract_product(&e, &mut s[j * m..(j + 1) * m], par)?;
            e[j] = 0.0;
        }
        let n = D * self.vertices.len();
        let mut col_ptr = vec![0usize; n + 1];
        let mut row_idx = Vec::with_capacity(m * m);
        let mut values = Vec::with_capacity(m * m);
        let mut column_of = vec![usize::MAX; n];
        for (j, &d) in dofs.iter().enumerate() {
            column_of[d] = j;
        }
        // A fixed component (the normal: no opening) gets a diagonal entry alone, the
        // largest of S's (the matrix's scale; its value never enters a solve, which holds
        // the component at its value, but the solvers ask for every diagonal entry).
        let fixed_diagonal = (0..m).map(|i| -s[i * m + i]).fold(0.0_f64, f64::max);
        for c in 0..n {
            if column_of[c] == usize::MAX {
                row_idx.push(c);
                values.push(fixed_diagonal);
            } else {
                let j = column_of[c];
                for (i, &d) in dofs.iter().enumerate() {
                    let v = -0.5 * (s[j * m + i] + s[i * m + j]);
                    if !v.is_finite() || (i == j && v <= 0.0) {
                        return Err(invalid(
                            "stiffness",
                            format!("S[{i}, {j}] = {v} (a stiffness: finite, positive diagonal)"),
                        ));
                    }
                    row_idx.push(d);
                    values.push(v);
                }
            }
            col_ptr[c + 1] = row_idx.len();
        }
        let symbolic =
            faer::sparse::SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let k = crate::fem::SparseMatrix::new(symbolic, values);
        self.energy_norm = k.clone();
        self.stiffness = k;
        Ok(())
    }
}

/// What the set-up of a fault ODE condensed without the volume's whole factor needs before
/// it starts ([`SimulationBuilder::build_fault_ode_schur_only`](crate::SimulationBuilder::build_fault_ode_schur_only)).
#[derive(Default)]
pub struct SchurOnlySetup {
    /// The vertices (of the model's mesh) observers will read off the fault
    /// ([`Observer::volume_vertices`](crate::Observer::volume_vertices), e.g. surface
    /// stations): kept through the elimination, their displacement an affine function of
    /// the fault's slip. Any order; repeats are ignored. Other vertices cannot be read
    /// later.
    pub watch_vertices: Vec<usize>,
    /// Checkpoints of the elimination: a set-up killed and started again with the same
    /// model resumes from its file and gives the same bits ([`CheckpointPolicy`]).
    pub checkpoint: Option<CheckpointPolicy>,
    /// The most bytes the elimination may hold (its plan, computed before any numeric
    /// work, against this): a larger plan is refused with
    /// [`rsf_direct::Error::TooLarge`] before anything is allocated. `None`: no bound.
    pub max_bytes: Option<usize>,
    /// Told after every front with the elimination's progress (fronts, flops, time);
    /// [`ControlFlow::Break`] stops it with [`rsf_direct::Error::Stopped`] (the last
    /// checkpoint stays).
    pub progress: Option<SetupProgress>,
}

/// A watcher of the Schur-only elimination ([`SchurOnlySetup::progress`]).
pub type SetupProgress = Box<dyn FnMut(&Progress) -> ControlFlow<()>>;

impl std::fmt::Debug for SchurOnlySetup {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SchurOnlySetup")
            .field("watch_vertices", &self.watch_vertices.len())
            .field("checkpoint", &self.checkpoint)
            .field("max_bytes", &self.max_bytes)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}
