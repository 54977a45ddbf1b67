//! The assembled, discretised mechanical model a simulation runs on: matrices, loads,
//! constraints, the frictional boundary and the refinement hierarchy.

pub(crate) mod absorbing;
pub(crate) mod builder;
mod columns;
pub(crate) mod conditioning;
pub(crate) mod creep;
pub(crate) mod equilibrium;
pub(crate) mod fault;
pub(crate) mod internal;
pub(crate) mod loading;
pub(crate) mod medium;
pub(crate) mod regions;
pub(crate) mod schur_columns;
#[cfg(feature = "sprs")]
mod sprs_edge;

pub use absorbing::AbsorbingBoundary;
pub use builder::{
    BuildStage, FacetPredicate, ModelBuilder, Part, DEFAULT_MAX_FAULT_KINK_DEGREES, MAX_CELLS,
};
pub use conditioning::{representable_range, ProblemScales, ScaleFields, SLIP_RESOLUTION};
pub use creep::{CreepRate, PrescribedSlip, MAX_CREEP_NORMAL_FRACTION};
pub use equilibrium::{
    equilibrium_on_ranks, EquilibriumSystem, StaticMethod, StaticOptions, StaticSolver,
    EQUILIBRIUM_DIRECT_MAX_DOFS_3D, EQUILIBRIUM_MULTIGRID_TOLERANCE,
};
pub use fault::{block_norm, FrictionalBoundary};
pub use internal::{FaultSide, InternalFault, SlipNode};

/// A frictional node as per-node settings see it ([`Model::on_fault_points`],
/// [`SimulationBuilder::friction_on_faults`](crate::SimulationBuilder::friction_on_faults)):
/// the name of its fault ([`FrictionalBoundary::fault_names`]) and its position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaultPoint<'a, const D: usize> {
    /// The fault's name (a fault inside the body's, or the frictional boundary's part).
    pub fault: &'a str,
    /// The node's position (m).
    pub x: &'a [f64; D],
}
pub use loading::{DirichletVelocity, TimeFunction};
pub use medium::{AntiplaneMaterial, Material, Medium, MediumMatrices};
pub use regions::{CellPredicate, MaterialRegions};
pub use schur_columns::{SchurColumns, SchurColumnsReport};

use rsf_fem::{DofTransform, NodalFrames, SparseMatrix};

use crate::error::{check_len, invalid, Error, Result};

/// An assembled model: matrices, loads, constraints, hierarchy and frictional boundary,
/// independent of the friction law, state law, time integrator and solver.
///
/// `D` is the spatial dimension (vertex coordinates), `C` the number of components of the
/// unknown field per node (default `C = D`: displacement and velocity vectors; `C = 1`: a
/// scalar field such as the antiplane displacement, see
/// [`AntiplaneMaterial`]).
///
/// Vectors are node-major with `C` components per node (`n = C · nodes`) in the model's
/// unknowns `u′` of its change of variables `u = T u′` ([`Model::transform`]), "model
/// coordinates", what the solvers, the simulation state and checkpoints hold: Cartesian
/// components, except at the slanted nodes of a fault on the boundary, whose blocks are in
/// their nodal frame (tangential…, normal; [`frames`](Self::frames)), and at the split
/// pairs of a fault inside the body, where the minus vertex's block is the jump in the
/// pair's frame and the plus vertex's the (weighted) mean
/// ([`internal_fault`](Self::internal_fault)). [`Model::to_cartesian`] converts a whole
/// vector, [`Model::vertex_value`] one vertex's block. Build one with
/// [`ModelBuilder`] from a mesh, a material and boundary parts, or
/// fill the public fields yourself (e.g. a lumped spring–block system without a mesh);
/// [`Model::validate`] checks them, and every simulation validates its model.
///
/// # Two index spaces: vertex ids and fault indices
/// A **vertex id** `vertex` (also "node", `p` in docs/math.md) indexes `vertices` and the
/// node-major vectors (block `C·vertex .. C·vertex + C`): what [`nearest_node`](Self::nearest_node)
/// returns and [`PointSeries`](crate::observe::PointSeries), [`Recorder`](crate::observe::Recorder),
/// [`SlipEvents::slip_at`](crate::observe::SlipEvents::slip_at), [`frame`](Self::frame) and
/// [`to_global`](Self::to_global) take. A **fault index** `k` is a position on Γ_F, an
/// index into `frictional_boundary.nodes` (and `weights`, the per-node friction and state
/// laws, the state `α`, [`StepView::slip_rate`](crate::StepView::slip_rate) and the
/// tractions): `frictional_boundary.nodes[k]` is its vertex id,
/// [`FrictionalBoundary::fault_index`] the way back. Errors say which one they name
/// ([`Error::NodeOutOfRange`]: a vertex id; [`Error::StateLaw`]: a fault index).
///
/// ```
/// use rsf::fem::cuboid;
/// use rsf::{Material, ModelBuilder, Part};
///
/// // A 2 m × 1 m × 1 m block (not the paper's problem): its top moves in x at 0.1 mm/s,
/// // its bottom face slides with friction (bilateral contact: z velocity fixed).
/// let model = ModelBuilder::refined(cuboid([0.0; 3], [2.0, 1.0, 1.0], [3, 2, 2])?, 1)?
///     .material(Material::new(1e8, 0.25, 2.7e3))
///     .gravity([0.0, 0.0, -9.81])
///     .dirichlet(Part::predicate("top", |x| x[2] > 1.0 - 1e-9), [1e-4, 0.0, 0.0])
///     .frictional_boundary(Part::predicate("bottom", |x| x[2] < 1e-9))
///     .build()?;
/// assert_eq!((model.num_nodes(), model.frictional_boundary.len()), (45, 15));
/// assert!(model.frictional_boundary.nodes.iter().all(|&p| model.fixed[3 * p + 2]));
/// // u0 is the gravity equilibrium: the middle layer sags, fixed dofs stay at 0.
/// let u0 = &model.initial_displacement;
/// assert!((0..45).all(|p| model.vertices[p][2] != 0.5 || u0[3 * p + 2] < 0.0));
/// assert!(u0.iter().zip(&model.fixed).all(|(u, &f)| !f || *u == 0.0));
/// # Ok::<(), rsf::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Model<const D: usize, const C: usize = D> {
    /// Node coordinates (m) of the finest mesh (or of the lumped points).
    pub vertices: Vec<[f64; D]>,
    /// Mass matrix `M` (kg per unit thickness in 2D); `None` for quasistatic scenes.
    pub mass: Option<SparseMatrix>,
    /// Stiffness matrix `K` (N/m per unit thickness in 2D).
    pub stiffness: SparseMatrix,
    /// Matrix of the energy norm used in all stopping tests: `K + M` (docs/math.md §3), or `K`
    /// without mass.
    pub energy_norm: SparseMatrix,
    /// Load vector `F` (body force + Neumann tractions), constant in time (N).
    pub load: Vec<f64>,
    /// Constrained dofs (Dirichlet on Γ_D, normal component on Γ_F).
    pub fixed: Vec<bool>,
    /// Prescribed velocities on the Dirichlet dofs; other fixed dofs have velocity 0.
    pub dirichlet: DirichletVelocity,
    /// Node-major prolongations of the refinement hierarchy, coarse to fine (may be empty).
    pub prolongations: Vec<SparseMatrix>,
    /// The frictional boundary.
    pub frictional_boundary: FrictionalBoundary,
    /// Initial displacement `u_0` (m).
    pub initial_displacement: Vec<f64>,
    /// Mesh cells as vertex indices with stride `D + 1` (for output such as VTU frames);
    /// empty for models without a mesh (e.g. a spring–block).
    pub cells: Vec<usize>,
    /// The frames `Q_p` (row-major, columns: tangent(s), inward normal) of the vertices
    /// whose block of a model vector is written in a frame, nodes in increasing order:
    /// * a fault on the boundary: the nodal frames of its slanted nodes (normal not along a
    ///   coordinate axis; empty for an axis-aligned fault and for a scalar field;
    ///   docs/math.md §10.1). They are then the model's change of variables
    ///   ([`transform`](Self::transform)): the matrices, load, `u₀`, Dirichlet data and
    ///   finest prolongation are `Rᵀ A R`, `Rᵀ F`, `Rᵀ P` with `R = blockdiag(Q_p)`.
    /// * a fault inside the body: the pair frames `R_p` at the split pairs' minus vertices
    ///   (vector fields), whose block is the jump `R_pᵀ(u⁺ − u⁻)`. They are not the model's
    ///   change of variables — that is the mean–jump transform of
    ///   [`internal_fault`](Self::internal_fault) (`Tᵀ A T`), which contains them — and `Q_p`
    ///   turns a minus block into the Cartesian jump, not into the vertex's value
    ///   ([`vertex_value`](Self::vertex_value)).
    pub frames: NodalFrames<C>,
    /// Lysmer–Kuhlemeyer dashpots on absorbing parts (docs/math.md "Absorbing
    /// boundaries"); `None` (the default) for none: the velocity problem is then exactly
    /// what it was without them.
    pub absorbing: Option<AbsorbingBoundary>,
    /// A fault inside the body ([`ModelBuilder::internal_fault`]): the split pairs and the
    /// mean–jump change of variables every matrix, load and state vector is written in;
    /// `None` for a fault on the boundary.
    pub internal_fault: Option<InternalFault<D>>,
    /// The nodes whose columns the matrices hold (one flag per vertex), for a model built
    /// on one process of several ([`ModelBuilder::build_columns`]): `stiffness`, `mass`,
    /// `energy_norm` and the absorbing `damping` keep their `n × n` shape, the columns
    /// `C·p .. C·p + C` of a kept node `p` have the rows and bits of the whole model's and
    /// the other columns are empty (the matrices are symmetric: a kept column is also the
    /// node's row). Every vector (`load`, `fixed`, `initial_displacement`, the Dirichlet
    /// data, the far-field force), the prolongations and the frictional boundary are whole.
    /// `None` (the default): the whole model.
    pub columns: Option<Vec<bool>>,
}

impl<const D: usize, const C: usize> Model<D, C> {
    /// Number of dofs.
    pub fn num_dofs(&self) -> usize {
        self.load.len()
    }

    /// The kinetic energy `½ vᵀ M v` of a velocity field (J; per metre of thickness in
    /// 2-D): `v` has [`num_dofs`](Self::num_dofs) entries (m/s) in the model's unknowns —
    /// nodal frames and, for an antisymmetric fault, the scaled field `s·u` with `M/s²`,
    /// so the value is the (half) body's energy in `u` either way.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] if `v` has the wrong length or the model has no mass
    /// matrix (built [`without_mass`](ModelBuilder::without_mass) for a quasistatic run).
    ///
    /// On a model of some columns ([`columns`](Self::columns)) the sum of the kept
    /// columns' terms `v_j (M v)_j` only: the parts of the processes add up to the whole
    /// energy (to round-off).
    pub fn kinetic_energy(&self, v: &[f64]) -> Result<f64> {
        check_len("v", v.len(), self.num_dofs(), |len, expected| {
            format!("has {len} entries, the model {expected} dofs")
        })?;
        let mass = self
            .mass
            .as_ref()
            .ok_or_else(|| invalid("v", "the model has no mass matrix (no inertia)"))?;
        Ok(0.5 * rsf_linalg::quadratic_form(mass.as_ref(), v))
    }

    /// Number of nodes (mesh vertices; vertex ids are `0..num_nodes()`).
    pub fn num_nodes(&self) -> usize {
        self.vertices.len()
    }

    /// Number of free components on Γ_F: the unknowns the direct solver condenses onto
    /// (the size of its dense matrices, [`SolverKind::resolve`](crate::SolverKind::resolve)).
    pub fn condensed_unknowns(&self) -> usize {
        self.frictional_boundary
            .nodes
            .iter()
            .flat_map(|&p| (0..C).map(move |c| C * p + c))
            .filter(|&i| !self.fixed[i])
            .count()
    }

    /// `f(p)` for every frictional node `p` ([`FaultPoint`]: its fault's name and its
    /// position), in `frictional_boundary.nodes` order: how each fault of a network gets its
    /// own laws, parameters and state (two faults crossing share the junction's position;
    /// their names tell them apart).
    pub fn on_fault_points<T>(&self, mut f: impl FnMut(FaultPoint<'_, D>) -> T) -> Vec<T> {
        let fb = &self.frictional_boundary;
        fb.nodes
            .iter()
            .zip(&fb.fault_of)
            .map(|(&p, &g)| {
                f(FaultPoint {
                    fault: &fb.fault_names[g],
                    x: &self.vertices[p],
                })
            })
            .collect()
    }

    /// `f(x_p)` for every frictional node, in `frictional_boundary.nodes` order: entry `k`
    /// belongs to fault index `k` (the order of per-node laws and states), at vertex
    /// `frictional_boundary.nodes[k]`. How a heterogeneous fault is described by position.
    pub fn on_frictional_nodes<T>(&self, mut f: impl FnMut(&[f64; D]) -> T) -> Vec<T> {
        self.frictional_boundary
            .nodes
            .iter()
            .map(|&p| f(&self.vertices[p]))
            .collect()
    }

    /// The frame `Q_p` of mesh vertex `vertex` (a vertex id, not a fault index; row-major;
    /// columns = tangents, inward normal), if it has one ([`frames`](Self::frames): a
    /// slanted node of a boundary fault, or a split pair's minus vertex).
    pub fn frame(&self, vertex: usize) -> Option<&[[f64; C]; C]> {
        self.frames
            .nodes
            .binary_search(&vertex)
            .ok()
            .map(|k| &self.frames.rotations[k])
    }

    /// The block `x` of mesh vertex `vertex` (a vertex id) in its frame → Cartesian
    /// components: `Q_p x` at a frame node ([`frame`](Self::frame)), `x` elsewhere. On a
    /// boundary fault this is the vertex's value in model coordinates rotated back; at a
    /// split pair's minus vertex (whose block is the jump) the Cartesian jump, and at its
    /// plus vertex (the mean) `x`: the sides' values are [`vertex_value`](Self::vertex_value)'s.
    pub fn to_global(&self, vertex: usize, x: [f64; C]) -> [f64; C] {
        match self.frame(vertex) {
            None => x,
            Some(q) => std::array::from_fn(|r| (0..C).map(|c| q[r][c] * x[c]).sum()),
        }
    }

    /// The Cartesian block of mesh vertex `vertex` (a vertex id) of a whole model vector
    /// `x` (`C` entries per vertex, model coordinates): `Q_p x_p` at a frame node, at a
    /// split vertex of an internal fault its side's value `w ∓ R_p j/2` (docs/math.md §15),
    /// `x_p` elsewhere.
    ///
    /// # Panics
    /// If `vertex` is not a vertex of the model or `x` is shorter than the model's vectors.
    pub fn vertex_value(&self, vertex: usize, x: &[f64]) -> [f64; C] {
        if let Some(b) = self
            .internal_fault
            .as_ref()
            .and_then(|f| f.vertex_block::<C>(vertex, x))
        {
            return b;
        }
        self.to_global(vertex, std::array::from_fn(|c| x[C * vertex + c]))
    }

    /// A whole model vector (`C` entries per vertex) in Cartesian components at every
    /// vertex: nodal frames rotated back, an internal fault's mean and jump turned into
    /// the two sides' values (`T x`).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] if `x` does not have [`num_dofs`](Self::num_dofs) entries.
    pub fn to_cartesian(&self, x: &[f64]) -> Result<Vec<f64>> {
        check_len("x", x.len(), self.num_dofs(), |len, expected| {
            format!("has {len} entries, the model {expected} dofs")
        })?;
        let t = self.transform();
        if t.is_identity() {
            return Ok(x.to_vec());
        }
        Ok(t.to_cartesian(x)?)
    }

    /// The change of variables `u = T u′` the model is written in: the mean–jump transform
    /// of a fault inside the body ([`InternalFault::transform`]), else the nodal frames of
    /// a boundary fault's slanted nodes ([`frames`](Self::frames); the identity without
    /// any). The matrices are `Tᵀ A T`, the load `Tᵀ F`, the finest prolongation `T⁻¹ P`,
    /// and a model vector's Cartesian components are `T x`
    /// ([`to_cartesian`](Self::to_cartesian)). (An antisymmetric fault's unknown `s·u` is a
    /// scaling apart, [`FrictionalBoundary::slip_factor`].)
    pub fn transform(&self) -> &dyn DofTransform {
        match &self.internal_fault {
            Some(f) => &f.transform,
            None => &self.frames,
        }
    }

    /// The Cartesian block `x` of mesh vertex `vertex` (a vertex id) → its frame: `Q_pᵀ x`
    /// at a frame node ([`frame`](Self::frame)), `x` elsewhere (the inverse of
    /// [`to_global`](Self::to_global); model coordinates on a boundary fault, a jump in
    /// the pair frame at a split pair's minus vertex).
    pub fn to_model(&self, vertex: usize, x: [f64; C]) -> [f64; C] {
        match self.frame(vertex) {
            None => x,
            Some(q) => std::array::from_fn(|c| (0..C).map(|r| q[r][c] * x[r]).sum()),
        }
    }

    /// Checks that `vertex` is a vertex id of the model (`< num_nodes()`).
    ///
    /// # Errors
    /// [`Error::NodeOutOfRange`] naming `what` the vertex is for.
    pub fn check_node(&self, what: &'static str, vertex: usize) -> Result<()> {
        if vertex < self.vertices.len() {
            Ok(())
        } else {
            Err(Error::NodeOutOfRange {
                what,
                node: vertex,
                nodes: self.vertices.len(),
            })
        }
    }

    /// The vertex id of the node nearest to `x` (m), by Euclidean distance; the first on
    /// ties. A vertex id, not a fault index (see [`Model`]): for the position on Γ_F use
    /// [`FrictionalBoundary::fault_index`].
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a model without nodes or a non-finite `x`.
    pub fn nearest_node(&self, x: &[f64; D]) -> Result<usize> {
        nearest_vertex(&self.vertices, x)
    }

    /// Checks the shapes of all parts against each other, the Dirichlet data, that
    /// every frictional node has a fixed component (the normal velocity under bilateral
    /// contact; vector fields, `C = D ≥ 2`), and that the magnitudes of `K`, `M`, `F`
    /// and `u₀` can be squared in double precision (docs/reliability.md).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the mismatch; [`Error::NodeOutOfRange`] for a
    /// frictional node outside the mesh; [`Error::FreeNormal`] for a frictional node
    /// without a fixed component; [`Error::InvalidParameter`] naming `stiffness` or `mass`
    /// for a negative diagonal entry (not positive semi-definite); [`Error::IllConditioned`]
    /// naming `stiffness`, `mass`, `load` or `initial_displacement` for a magnitude outside
    /// [`representable_range`] (also a non-finite one);
    /// [`Error::InvalidParameter`] named `absorbing` for a dashpot matrix of another size or
    /// pattern than the stiffness, a far-field force of another length, a non-finite entry
    /// or a negative diagonal entry ([`AbsorbingBoundary`]); [`Error::InvalidParameter`]
    /// named `internal_fault` for a mean–jump transform `T` or `T⁻¹` of another size than
    /// the model's dofs; [`Error::InvalidParameter`] named `columns` or after a matrix for
    /// a model of some columns ([`columns`](Self::columns)) with another number of flags
    /// than vertices or with entries in a column not kept. On such a model the magnitudes
    /// are those of its columns ([`ProblemScales::on_columns`]).
    pub fn validate(&self) -> Result<()> {
        self.validate_structure()?;
        self.check_magnitudes()
    }

    /// The shape and consistency part of [`validate`](Self::validate) (what a model
    /// builder guarantees by construction; magnitudes depend on the user's data).
    pub(crate) fn validate_structure(&self) -> Result<()> {
        let n = C * self.vertices.len();
        let sq = |name: &str, m: &SparseMatrix| {
            if m.nrows() != n || m.ncols() != n {
                Err(invalid(
                    name,
                    format!("is {}x{}, expected {n}x{n}", m.nrows(), m.ncols()),
                ))
            } else {
                Ok(())
            }
        };
        sq("stiffness", &self.stiffness)?;
        sq("energy_norm", &self.energy_norm)?;
        if let Some(m) = &self.mass {
            sq("mass", m)?;
        }
        self.validate_columns()?;
        for (name, len) in [
            ("load", self.load.len()),
            ("fixed", self.fixed.len()),
            ("initial_displacement", self.initial_displacement.len()),
        ] {
            if len != n {
                return Err(invalid(name, format!("has length {len}, expected {n}")));
            }
        }
        if self.dirichlet.dofs.len() != self.dirichlet.factors.len()
            || self
                .dirichlet
                .dofs
                .iter()
                .any(|&d| d >= n || !self.fixed[d])
        {
            return Err(invalid(
                "dirichlet",
                "dofs must be fixed dofs with one factor each",
            ));
        }
        if self.dirichlet.factors.iter().any(|f| !f.is_finite()) {
            return Err(invalid("dirichlet", "factors must be finite"));
        }
        self.dirichlet.history.validate()?;
        if let Some(&p) = self
            .frictional_boundary
            .nodes
            .iter()
            .find(|&&p| p >= self.vertices.len())
        {
            return Err(Error::NodeOutOfRange {
                what: "frictional boundary",
                node: p,
                nodes: self.vertices.len(),
            });
        }
        if self.frictional_boundary.weights.len() != self.frictional_boundary.nodes.len()
            || self.frictional_boundary.along.len() != self.frictional_boundary.nodes.len()
        {
            return Err(invalid(
                "frictional_boundary",
                "nodes, weights and along differ in length",
            ));
        }
        // Bilateral contact: the friction acts on the whole block v_p, so the normal
        // component must be fixed (docs/math.md §3); in 1D there is no normal, and a scalar
        // (antiplane) field has only its tangential component.
        if C == D && D >= 2 {
            if let Some(&p) = self
                .frictional_boundary
                .nodes
                .iter()
                .find(|&&p| (0..C).all(|c| !self.fixed[C * p + c]))
            {
                return Err(Error::FreeNormal { node: p });
            }
        }
        self.validate_frames()?;
        if let Some(f) = &self.internal_fault {
            let (t, t_inv) = (&f.transform.t, &f.transform.t_inv);
            if [t.nrows(), t.ncols(), t_inv.nrows(), t_inv.ncols()] != [n; 4] {
                return Err(invalid(
                    "internal_fault",
                    format!(
                        "its transform T is {}x{}, the model has {n} dofs",
                        t.nrows(),
                        t.ncols()
                    ),
                ));
            }
        }
        if let Some(a) = &self.absorbing {
            a.validate(&self.stiffness)?;
        }
        if self.cells.len() % (D + 1) != 0 || self.cells.iter().any(|&c| c >= self.vertices.len()) {
            return Err(invalid(
                "cells",
                "need stride D + 1 and vertex indices in range",
            ));
        }
        if let Some(p) = self.prolongations.last() {
            if p.nrows() != n {
                return Err(invalid(
                    "prolongations",
                    "finest prolongation does not match the dofs",
                ));
            }
        }
        Ok(())
    }

    /// The magnitudes of the assembled problem (docs/reliability.md, "Conditioning"): the
    /// diagonals of `K` and `M`, `|F|∞`, `|u₀|∞` and `|F|∞ / min K_ii` over the free dofs
    /// inside [`representable_range`](crate::model::representable_range) (zero allowed). The
    /// scenes check more (the time-step matrix at their τ range, the loading, the
    /// resolution of `L`); a model built by hand gets this part, `O(nnz)`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `stiffness` or `mass` for a negative diagonal
    /// entry on a free dof; [`Error::IllConditioned`] naming the model field
    /// (`stiffness`, `mass`, `load`, `initial_displacement`).
    fn check_magnitudes(&self) -> Result<()> {
        use crate::model::conditioning::{diagonal, ProblemScales, ScaleFields};
        // A stiffness or mass matrix is positive semi-definite: no negative diagonal entry.
        let mass = self.mass.as_ref().map(|m| ("mass", m));
        for (name, m) in [("stiffness", &self.stiffness)].into_iter().chain(mass) {
            let d = diagonal(m);
            if let Some(i) = (0..d.len()).find(|&i| !self.fixed[i] && d[i] < 0.0) {
                return Err(invalid(
                    name,
                    format!(
                        "diagonal entry {i} is {:e}: a {name} matrix is positive \
                         semi-definite (a negative {name})",
                        d[i]
                    ),
                ));
            }
        }
        ProblemScales::of_model(self).check(
            &[],
            (0.0, &[]),
            f64::INFINITY,
            &ScaleFields {
                stiffness: &["stiffness"],
                mass: &["mass"],
                load: &["load"],
                displacement: &["initial_displacement", "load", "stiffness"],
                slip: &[],
            },
        )
    }
}

impl<const D: usize, const C: usize> Model<D, C> {
    fn validate_frames(&self) -> Result<()> {
        let f = &self.frames;
        if f.nodes.len() != f.rotations.len()
            || f.nodes.windows(2).any(|w| w[0] >= w[1])
            || f.nodes.last().is_some_and(|&p| p >= self.vertices.len())
        {
            return Err(invalid(
                "frames",
                "need one rotation per node, nodes increasing and in range",
            ));
        }
        for (&p, q) in f.nodes.iter().zip(&f.rotations) {
            // Orthonormal columns: QᵀQ = I.
            let off = (0..C)
                .flat_map(|a| (0..C).map(move |b| (a, b)))
                .map(|(a, b)| {
                    let d: f64 = (0..C).map(|r| q[r][a] * q[r][b]).sum();
                    (d - if a == b { 1.0 } else { 0.0 }).abs()
                })
                .fold(0.0, f64::max);
            if !(off <= 1e-12) {
                return Err(invalid(
                    "frames",
                    format!("the frame of node {p} is not orthonormal (|QᵀQ − I| = {off:e})"),
                ));
            }
        }
        Ok(())
    }
}

/// Index of the vertex nearest to `x` (Euclidean distance; the first on ties).
///
/// # Errors
/// [`Error::InvalidParameter`] for an empty vertex list or a non-finite `x`.
pub fn nearest_vertex<const D: usize>(vertices: &[[f64; D]], x: &[f64; D]) -> Result<usize> {
    if x.iter().any(|c| !c.is_finite()) {
        return Err(invalid("point", format!("{x:?} must be finite")));
    }
    let d2 = |v: &[f64; D]| v.iter().zip(x).map(|(a, b)| (a - b) * (a - b)).sum::<f64>();
    (0..vertices.len())
        .min_by(|&i, &j| d2(&vertices[i]).total_cmp(&d2(&vertices[j])))
        .ok_or_else(|| invalid("vertices", "no vertex to choose from"))
}

// Here rather than in `conditioning` (which knows no `Model`): no import circle.
impl ProblemScales {
    /// The scales of `model` ([`new`](Self::new) of its matrices and vectors); of a model of
    /// some columns ([`Model::columns`]) as
    /// [`on_columns`](Self::on_columns).
    pub fn of_model<const D: usize, const C: usize>(model: &Model<D, C>) -> Self {
        Self::on_columns(
            &model.stiffness,
            model.mass.as_ref(),
            &model.load,
            &model.initial_displacement,
            &model.fixed,
            model.columns.as_deref(),
        )
    }
}
