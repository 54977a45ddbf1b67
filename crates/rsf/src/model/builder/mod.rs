//! Building a [`Model`] from a mesh, a material and named boundary parts: the
//! [`ModelBuilder`] (its constructors and [`build`](ModelBuilder::build), the pipeline of
//! `stages/`), its setters grouped by concern (`material.rs`: the body; `boundary.rs`: the
//! boundary conditions; `faults.rs`: the fault), what they record (`settings.rs`) and the
//! boundary parts they name (`part.rs`).

mod boundary;
mod faults;
mod material;
pub(crate) mod part;
pub(crate) mod settings;
mod stage;
pub(crate) mod stages;

use rsf_fem::{DofTransform, MeshHierarchy, SimplexMesh};

use super::Model;
use crate::error::{check_len, invalid, Result};
use settings::{Body, Boundary, Faults};
use stages::constraints::constrain;
use stages::domain::Domain;
use stages::matrices::System;
use stages::pairs::{share_fault, Kinematics};
use stages::{fault_order, inputs, loads, matrices, prolongations};

pub use part::{FacetPredicate, Part};
pub use settings::DEFAULT_MAX_FAULT_KINK_DEGREES;
pub use stage::BuildStage;
use stage::StageObserver;

/// Largest number of cells [`ModelBuilder::refined`] creates (the paper's slider at level 10
/// has 10 · 4¹⁰ ≈ 1.0e7 triangles).
pub const MAX_CELLS: usize = 50_000_000;

/// Builds a consistent [`Model`] (its magnitudes are checked when a simulation is built,
/// [`Model::validate`]) from a mesh (or a refinement hierarchy), a
/// [`Material`](crate::model::Material), body forces, and named boundary parts: Dirichlet
/// parts with a prescribed velocity, Neumann parts with a traction, and the frictional
/// boundary Γ_F with bilateral contact.
///
/// What it does for you (docs/math.md §3, §6): node-major dofs; consistent mass `M` and
/// stiffness `K` (plane strain in 2D) on one pattern; the energy norm `K + M` (`K` without
/// mass); the load `F` (body force + tractions); the constraints (all listed components of
/// Dirichlet nodes, the normal component of every frictional node); the prescribed
/// velocities `v_i(t) = w_i g(t)` with one loading history `g`
/// ([`TimeFunction`](crate::model::TimeFunction)); the initial displacement `u₀` solving
/// `K u₀ = F` under these constraints — the static problem, its fixed dofs at their held
/// values (0, or a [`dirichlet_displacement`](Self::dirichlet_displacement), or a fault's
/// prescribed slip, [`internal_slip_at`](Self::internal_slip_at)), solved as
/// [`equilibrium_solver`](Self::equilibrium_solver) says; lumped weights on Γ_F; the
/// hierarchy's prolongations for multigrid; the cells for output.
///
/// Γ_F may have any orientation (docs/math.md §10, docs/design.md "Nodal frames"). At a
/// node whose outer normal `n` (the facets' area-weighted mean) is along a coordinate axis
/// (e.g. the bottom of a block) the normal velocity is that Cartesian component, fixed, and
/// nothing is rotated: an axis-aligned fault gives exactly the model it gave before frames
/// existed. At every other node the builder sets a **nodal frame** `Q_p` (columns: the
/// tangent(s), then the inward normal `−n`; 2-D: `t = (−n_y, n_x)`; 3-D: `t₁` the
/// projection of [`fault_tangent`](Self::fault_tangent) onto the tangent plane, by default
/// of the coordinate axis with the smallest `|n_k|`, `t₂ = −n × t₁`) and rotates the model
/// block-diagonally, `Ã = Rᵀ A R` with `R = blockdiag(Q_p)` (identity elsewhere; the
/// [`DofTransform`] of [`NodalFrames`](rsf_fem::NodalFrames), [`Model::transform`]): `K`,
/// `M`, the energy norm, the load, the Dirichlet data of such nodes, `u₀` and the finest
/// prolongation (`Rᵀ P`; coarser levels stay Cartesian). The solvers then see the fault
/// velocity in slip coordinates (tangential…, normal) with the normal component (`D − 1`)
/// fixed; [`Model::frames`] keeps the `Q_p` to present results in global coordinates. A
/// fault inside the body ([`internal_fault`](ModelBuilder::internal_fault)) goes the same
/// way through its mean–jump transform instead (`Tᵀ A T`, docs/math.md §15).
/// Corners (facet normals further apart than [`max_fault_kink`](Self::max_fault_kink))
/// and zero-measure facets are typed errors naming the node.
///
/// [`build`](Self::build) is a pipeline of stages, each a function of typed inputs to a
/// typed output (`model/builder/stages/`): the domain (the mesh, cut open along a fault
/// inside the body) → the settings checked → the constraints (Dirichlet parts, Γ_F, its
/// frames, bilateral contact) → the matrices (with absorbing dashpots) → the load → an
/// antisymmetric fault's scaling → an internal fault's shared jump and prescribed pairs →
/// the change of variables (one [`DofTransform`]) → Γ_F's order and weights → the
/// prolongations → the initial equilibrium; its errors come in that order.
///
/// ```
/// use rsf::fem::{rectangle, Diagonal};
/// use rsf::{Material, ModelBuilder, Part, TimeFunction};
///
/// // A 2 m × 0.5 m block: fixed sides pushed inwards, sliding on its bottom.
/// let mesh = rectangle([0.0, 0.0], [2.0, 0.5], 5, 2, Diagonal::Forward)?;
/// let model = ModelBuilder::refined(mesh, 2)?
///     .material(Material { youngs_modulus: 1e8, poisson_ratio: 0.25, density: 2.7e3 })
///     .gravity([0.0, -9.81])
///     .dirichlet(Part::predicate("left", |x| x[0] < 1e-9), [1e-4, 0.0])
///     .dirichlet(Part::predicate("right", |x| x[0] > 2.0 - 1e-9), [-1e-4, 0.0])
///     .neumann(Part::predicate("top", |x| x[1] > 0.5 - 1e-9), |_| [0.0, -1e4])
///     .frictional_boundary(Part::predicate("bottom", |x| x[1] < 1e-9))
///     .loading(TimeFunction::ramp(1.0))
///     .build()?;
/// assert_eq!(model.frictional_boundary.len(), 17);
/// assert_eq!(model.prolongations.len(), 2);
/// # Ok::<(), rsf::Error>(())
/// ```
///
/// `ModelBuilder<D>` builds vector (elasticity) models, `C = D`; `ModelBuilder<D, 1>`
/// ([`scalar`](ModelBuilder::scalar), [`scalar_refined`](ModelBuilder::scalar_refined))
/// builds scalar ones, e.g. antiplane shear with an
/// [`AntiplaneMaterial`](crate::model::AntiplaneMaterial), where the one component is
/// tangential to every in-plane fault (no normal to fix, no frames).
pub struct ModelBuilder<const D: usize, const C: usize = D> {
    hierarchy: MeshHierarchy<D>,
    /// The medium, gravity, body force, inertia (`material.rs`).
    body: Body<D, C>,
    /// Dirichlet, Neumann and absorbing parts, the loading history (`boundary.rs`).
    boundary: Boundary<D, C>,
    /// Γ_F or a fault inside the body (`faults.rs`).
    fault: Faults<D>,
    /// Told as each stage of `build` ends ([`on_stage`](Self::on_stage)).
    observer: Option<StageObserver>,
}

impl<const D: usize> ModelBuilder<D> {
    /// A model on one mesh (no hierarchy: the direct solver, or TNNMG as a smoother only).
    pub fn new(mesh: SimplexMesh<D>) -> Self {
        Self::from_hierarchy(MeshHierarchy::refine_uniformly(mesh, 0))
    }

    /// A model on the finest level of `hierarchy`, with its prolongations for TNNMG.
    pub fn from_hierarchy(hierarchy: MeshHierarchy<D>) -> Self {
        Self::with_components(hierarchy)
    }

    /// A model on `coarse` refined `levels` times uniformly (red refinement: `2^D`
    /// children per cell and level).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `levels` if the
    /// finest mesh would have more than [`MAX_CELLS`] cells; refinement errors of
    /// [`MeshHierarchy::try_refine_uniformly`].
    pub fn refined(coarse: SimplexMesh<D>, levels: usize) -> Result<Self> {
        Ok(Self::from_hierarchy(refined_hierarchy(coarse, levels)?))
    }
}

impl<const D: usize> ModelBuilder<D, 1> {
    /// A scalar-field model (one component per vertex, e.g. antiplane shear with an
    /// [`AntiplaneMaterial`](crate::model::AntiplaneMaterial)) on one mesh (the direct solver).
    pub fn scalar(mesh: SimplexMesh<D>) -> Self {
        Self::scalar_from_hierarchy(MeshHierarchy::refine_uniformly(mesh, 0))
    }

    /// A scalar-field model on the finest level of `hierarchy`, with its prolongations.
    pub fn scalar_from_hierarchy(hierarchy: MeshHierarchy<D>) -> Self {
        Self::with_components(hierarchy)
    }

    /// A scalar-field model on `coarse` refined `levels` times uniformly.
    ///
    /// # Errors
    /// As [`ModelBuilder::refined`].
    pub fn scalar_refined(coarse: SimplexMesh<D>, levels: usize) -> Result<Self> {
        Ok(Self::scalar_from_hierarchy(refined_hierarchy(
            coarse, levels,
        )?))
    }
}

/// `keep` and every vertex that shares a cell of `mesh` with a kept one.
fn with_neighbours<const D: usize>(mesh: &SimplexMesh<D>, keep: &[bool]) -> Vec<bool> {
    let mut wide = keep.to_vec();
    for c in 0..mesh.num_cells() {
        let cell = mesh.cell(c);
        if cell.iter().any(|&v| keep[v]) {
            cell.iter().for_each(|&v| wide[v] = true);
        }
    }
    wide
}

/// `coarse` refined `levels` times, refusing more than [`MAX_CELLS`] cells.
fn refined_hierarchy<const D: usize>(
    coarse: SimplexMesh<D>,
    levels: usize,
) -> Result<MeshHierarchy<D>> {
    let cells = (0..levels).try_fold(coarse.num_cells(), |c, _| {
        c.checked_mul(1 << D).filter(|&c| c <= MAX_CELLS)
    });
    if cells.is_none() {
        return Err(invalid(
            "levels",
            format!(
                "{levels} refinements of {} cells exceed {MAX_CELLS} cells",
                coarse.num_cells()
            ),
        ));
    }
    Ok(MeshHierarchy::try_refine_uniformly(coarse, levels)?)
}

impl<const D: usize, const C: usize> ModelBuilder<D, C> {
    fn with_components(hierarchy: MeshHierarchy<D>) -> Self {
        Self {
            hierarchy,
            body: Body::default(),
            boundary: Boundary::default(),
            fault: Faults::default(),
            observer: None,
        }
    }

    /// Calls `observer` as each stage of [`build`](Self::build) ends, with the stage
    /// ([`BuildStage`], in the order of [`BuildStage::ALL`]; a stage with nothing to do is
    /// reported too): e.g. to read the process's peak memory stage by stage (docs/three-d.md,
    /// "The build's memory"). Nothing else changes.
    pub fn on_stage(mut self, observer: impl FnMut(BuildStage) + 'static) -> Self {
        self.observer = Some(Box::new(observer));
        self
    }

    /// The finest mesh (where parts are selected).
    pub fn mesh(&self) -> &SimplexMesh<D> {
        self.hierarchy.finest()
    }

    /// Assembles the model and checks its consistency (shapes, constraints, frames).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) for a missing material
    /// or frictional part, non-finite velocities or gravity, a component ≥ D, two Dirichlet
    /// parts prescribing different velocities to one dof;
    /// [`Error::BoundaryPart`](crate::Error::BoundaryPart) for a part that selects nothing
    /// or was built on another mesh; [`Error::FaultCorner`](crate::Error::FaultCorner) /
    /// [`Error::FaultFoldsBack`](crate::Error::FaultFoldsBack) /
    /// [`Error::DegenerateFaultFacet`](crate::Error::DegenerateFaultFacet) where Γ_F has no
    /// well-defined nodal frame;
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `dirichlet` for a
    /// slanted fault node with only some Cartesian components fixed, `max_fault_kink` or
    /// `fault_tangent` out of range, `fault_tangent` in 1-D or 2-D;
    /// [`Error::Equilibrium`](crate::Error::Equilibrium) if `K u₀ = F` is singular under
    /// the constraints; [`Error::Solver`](crate::Error::Solver) if its multigrid stops at
    /// its iteration cap or time limit ([`equilibrium_solver`](Self::equilibrium_solver));
    /// material and assembly errors ([`Error::Fem`](crate::Error::Fem)), e.g. a non-finite
    /// force or traction; those of a prescribed slip
    /// ([`internal_slip_at`](Self::internal_slip_at)) or a held displacement
    /// ([`dirichlet_displacement`](Self::dirichlet_displacement)).
    pub fn build(mut self) -> Result<Model<D, C>> {
        let equilibrium = self.body.equilibrium;
        let options = std::mem::take(&mut self.body.equilibrium_solver);
        self.build_on(None, |system, held| {
            if !equilibrium {
                return Ok(held.map_or_else(|| vec![0.0; system.load.len()], <[f64]>::to_vec));
            }
            super::equilibrium::solve::<D, C>(
                system.stiffness,
                system.fixed,
                system.load,
                system.prolongations,
                held,
                options,
            )
        })
    }

    /// The model one process of several holds: as [`build`](Self::build), with matrices
    /// of only the columns of the nodes with `keep[vertex]` (one flag per vertex of the
    /// finest mesh, [`mesh`](Self::mesh); [`Model::columns`]). Every kept column of `K`,
    /// `M`, the energy norm and the absorbing dashpots has the rows and bits of the whole
    /// model's, the other columns are empty; the vectors (load, constraints, Dirichlet
    /// data), the prolongations and the frictional boundary are the whole model's. The
    /// stages are [`build`](Self::build)'s on column matrices: the medium assembles only
    /// the cells with a kept vertex ([`Medium::assemble_columns`](crate::model::Medium::assemble_columns)),
    /// the slip factor's scaling acts entry by entry, and the nodal frames' `Rᵀ A R`,
    /// made symmetric by `½(B + Bᵀ)`, reads the rows of the kept columns, i.e. the columns
    /// of their neighbours: with frames the matrices are assembled on the kept nodes and
    /// their neighbours (the cells around the kept ones) and cut down to the kept columns
    /// after the change of variables.
    ///
    /// The initial equilibrium `K u₀ = F` needs the whole `K`: `equilibrium` solves it
    /// from this process's part ([`EquilibriumSystem`](crate::model::EquilibriumSystem),
    /// e.g. by a solver distributed over the processes) and returns the whole `u₀`
    /// (`n = C · vertices` entries, m, 0 on the fixed dofs).
    ///
    /// # Errors
    /// As [`build`](Self::build) (but [`Error::Equilibrium`](crate::Error::Equilibrium):
    /// `equilibrium`'s errors); [`Error::InvalidParameter`](crate::Error::InvalidParameter)
    /// named `keep` if it does not have one flag per vertex, named `internal_fault` for a
    /// fault inside the body (its mean–jump transform mixes the columns of two nodes: not
    /// built on columns), named `equilibrium` if `equilibrium` returns a vector of
    /// another length.
    pub fn build_columns(
        self,
        keep: &[bool],
        equilibrium: impl FnOnce(&super::EquilibriumSystem<'_>) -> Result<Vec<f64>>,
    ) -> Result<Model<D, C>> {
        let nv = self.mesh().num_vertices();
        check_len("keep", keep.len(), nv, |len, nv| {
            format!("has {len} flags, the finest mesh {nv} vertices (one flag per vertex)")
        })?;
        if !self.fault.internal.is_empty() {
            return Err(invalid(
                "internal_fault",
                "a model of some columns (build_columns) has no fault inside the body: its \
                 mean–jump transform mixes the columns of two nodes",
            ));
        }
        if self
            .boundary
            .dirichlet
            .iter()
            .any(|d| d.displacement.is_some())
        {
            return Err(invalid(
                "dirichlet_displacement",
                "a model of some columns (build_columns) solves its equilibrium with held \
                 values 0: build the model whole (ModelBuilder::build)",
            ));
        }
        self.build_on(Some(keep), |system, _| equilibrium(system))
    }

    /// [`build`](Self::build) on the columns of the nodes `columns` (whole for `None`),
    /// the initial equilibrium by `equilibrium`.
    /// `equilibrium` gets the system and the held values of the fixed dofs (model
    /// unknowns; `None`: all 0).
    fn build_on(
        self,
        columns: Option<&[bool]>,
        equilibrium: impl FnOnce(&super::EquilibriumSystem<'_>, Option<&[f64]>) -> Result<Vec<f64>>,
    ) -> Result<Model<D, C>> {
        const { assert!(C == D || C == 1, "vector (C = D) or scalar (C = 1) fields") };
        let Self {
            hierarchy,
            body,
            boundary,
            fault: faults,
            mut observer,
        } = self;
        let mut ended = |stage| {
            if let Some(f) = observer.as_mut() {
                f(stage);
            }
        };
        // 1. The mesh, cut open along a fault inside the body.
        let (domain, fault) = Domain::cut(&hierarchy, &faults)?;
        ended(BuildStage::Domain);
        // 2. The settings that need no mesh data.
        let inputs = inputs::check(&body, &boundary, &faults, fault.as_ref())?;
        let (mesh, s) = (domain.mesh(), inputs.slip_factor);
        // 3. Constraints and prescribed velocities (in the frames of slanted Γ_F nodes).
        let mut constraints = constrain(
            mesh,
            &boundary.dirichlet,
            &inputs.fault_part,
            fault.as_ref(),
            &faults,
        )?;
        ended(BuildStage::Constraints);
        // 4.–5. The matrices and the load, Cartesian, in u. On some columns: with frames,
        // also their neighbours' (the congruence's `½(B + Bᵀ)` reads the kept rows).
        let assembled = columns.map(|keep| {
            if constraints.frames.is_identity() {
                keep.to_vec()
            } else {
                with_neighbours(mesh, keep)
            }
        });
        let matrices = matrices::assemble(
            mesh,
            inputs.material,
            body.with_mass,
            &boundary.absorbing,
            &constraints,
            assembled.as_deref(),
        )?;
        ended(BuildStage::Matrices);
        let load = loads::load(mesh, inputs.material, &body, &boundary)?;
        ended(BuildStage::Load);
        // 6. An antisymmetric fault: the unknown is s·u.
        let system = System { matrices, load }.scaled(s)?;
        // 7. A fault inside the body: the jump shared by the sides' stiffness, the
        // prescribed pairs' data in the mean–jump unknowns (they do not slip freely).
        let fault = share_fault(
            fault,
            &system.matrices.stiffness,
            mesh,
            Kinematics {
                creep: faults.creep.as_ref(),
                slip: faults.slip.as_ref(),
            },
            &mut constraints,
        )?;
        ended(BuildStage::Pairs);
        // 8. The change of variables: everything in the nodal frames of slanted Γ_F nodes
        // (`Rᵀ A R`), or in an internal fault's mean–jump unknowns (`Tᵀ A T`).
        let transform: &dyn DofTransform = match &fault {
            Some(f) => &f.fault.transform,
            None => &constraints.frames,
        };
        let dirichlet = constraints.dirichlet_velocity(s, boundary.loading);
        let System { mut matrices, load } = system.in_unknowns(transform)?;
        if let (Some(keep), Some(assembled)) = (columns, &assembled) {
            if assembled.as_slice() != keep {
                matrices = matrices.node_columns(keep)?;
            }
        }
        ended(BuildStage::Variables);
        // 9. Γ_F in the order of the fault indices.
        let frictional_boundary = fault_order::frictional_boundary(
            mesh,
            &constraints.gamma_f,
            s,
            fault.as_ref(),
            constraints.boundary.as_ref(),
        )?;
        ended(BuildStage::FaultOrder);
        // 10. The prolongations, the finest onto the model's unknowns.
        let prolongations = prolongations::prolongations::<D, C>(&domain, transform)?;
        ended(BuildStage::Prolongations);
        // Initial equilibrium (after the prolongations: a large 3-D model solves it by
        // multigrid on them).
        // The held displacements (Dirichlet parts, prescribed slips) of the unknown `s·u`.
        let held = constraints.held_displacement(s);
        let u0 = equilibrium(
            &super::EquilibriumSystem {
                stiffness: &matrices.stiffness,
                columns,
                fixed: &constraints.fixed,
                load: &load,
                prolongations: &prolongations,
            },
            held.as_deref(),
        )?;
        check_len("equilibrium", u0.len(), load.len(), |len, expected| {
            format!("returned {len} entries, the model has {expected} dofs")
        })?;
        ended(BuildStage::Equilibrium);

        let energy_norm = matrices.energy_norm_or_stiffness();
        let model = Model {
            vertices: mesh.vertices().to_vec(),
            mass: matrices.mass,
            stiffness: matrices.stiffness,
            energy_norm,
            load,
            fixed: constraints.fixed,
            dirichlet,
            prolongations,
            frictional_boundary,
            initial_displacement: u0,
            cells: mesh.cells().to_vec(),
            frames: constraints.frames,
            absorbing: matrices.absorbing,
            internal_fault: fault.map(|f| f.fault),
            columns: columns.map(<[bool]>::to_vec),
        };
        // Consistent by construction; a simulation built on it validates it (once), with
        // the magnitudes of the user's data.
        debug_assert!(
            model.validate_structure().is_ok(),
            "{:?}",
            model.validate_structure()
        );
        Ok(model)
    }
}
