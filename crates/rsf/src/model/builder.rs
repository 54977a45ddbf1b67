//! Building a [`Model`] from a mesh, a material and named boundary parts.

use rsf_fem::{
    body_force_load_components, combine, traction_load_components, vectorize, BoundaryPart,
    DofTransform, MeshHierarchy, NodalFrames, SimplexMesh, SparseMatrix,
};
use rsf_numeric::normal_component;

use super::absorbing::{AbsorbingBoundary, ResolvedPart};
use super::creep::{CreepField, CreepRate};
use super::fault::FrictionalBoundary;
use super::internal::{faces_on_levels, split_hierarchy, InternalFault, SplitFault};
use super::loading::{DirichletVelocity, TimeFunction};
use super::medium::{Medium, MediumMatrices};
use super::Model;
use crate::error::{invalid, Error, Result};

/// A force density or traction (`C` components) as a function of position.
type VectorField<const D: usize, const C: usize> = Box<dyn Fn(&[f64; D]) -> [f64; C]>;

/// A selection of boundary facets by their midpoint.
pub type FacetPredicate<const D: usize> = Box<dyn Fn(&[f64; D]) -> bool>;

/// Which boundary facets of the finest mesh form a part: a tag (e.g. a Gmsh physical
/// group), a predicate on facet midpoints, or a [`BoundaryPart`] built on the finest mesh.
pub enum Part<const D: usize> {
    /// Facets carrying this tag.
    Tag(String),
    /// Facets whose midpoint satisfies the predicate, under a name for messages.
    Predicate {
        /// Name of the part (used in errors).
        name: String,
        /// Selects facets by their midpoint (m).
        predicate: FacetPredicate<D>,
    },
    /// A part built by the caller on the finest mesh.
    Facets(BoundaryPart<D>),
}

impl<const D: usize> Part<D> {
    /// Facets tagged `tag`.
    pub fn tag(tag: impl Into<String>) -> Self {
        Part::Tag(tag.into())
    }

    /// Facets whose midpoint `x` satisfies `predicate(x)`, named `name`.
    pub fn predicate(
        name: impl Into<String>,
        predicate: impl Fn(&[f64; D]) -> bool + 'static,
    ) -> Self {
        Part::Predicate {
            name: name.into(),
            predicate: Box::new(predicate),
        }
    }

    /// The part's name (for messages).
    pub fn name(&self) -> &str {
        match self {
            Part::Tag(t) => t,
            Part::Predicate { name, .. } => name,
            Part::Facets(p) => p.name(),
        }
    }

    fn resolve(&self, mesh: &SimplexMesh<D>) -> Result<BoundaryPart<D>> {
        let part = match self {
            Part::Tag(t) => BoundaryPart::from_tag(mesh, t),
            Part::Predicate { name, predicate } => {
                BoundaryPart::from_predicate(mesh, name, predicate)
            }
            Part::Facets(p) => p.check_mesh(mesh).map(|()| p.clone()),
        };
        part.map_err(|e| match e {
            rsf_fem::Error::EmptySegment { .. } => {
                part_error(self.name(), "selects no boundary facet")
            }
            rsf_fem::Error::DimensionMismatch { .. } => part_error(
                self.name(),
                "was built on another mesh (use the finest level)",
            ),
            e => Error::Fem(e),
        })
    }
}

impl<const D: usize> From<&str> for Part<D> {
    fn from(tag: &str) -> Self {
        Part::tag(tag)
    }
}

impl<const D: usize> From<String> for Part<D> {
    fn from(tag: String) -> Self {
        Part::Tag(tag)
    }
}

impl<const D: usize> From<BoundaryPart<D>> for Part<D> {
    fn from(part: BoundaryPart<D>) -> Self {
        Part::Facets(part)
    }
}

fn part_error(part: &str, reason: impl Into<String>) -> Error {
    Error::BoundaryPart {
        part: part.to_owned(),
        reason: reason.into(),
    }
}

/// A Dirichlet part: the listed components of its nodes move with `velocity · g(t)`.
struct Dirichlet<const D: usize, const C: usize> {
    part: Part<D>,
    components: Vec<usize>,
    velocity: [f64; C],
}

/// An absorbing part: dashpots against the motion relative to `velocity · g(t)`.
struct Absorbing<const D: usize, const C: usize> {
    part: Part<D>,
    velocity: [f64; C],
}

/// Largest number of cells [`ModelBuilder::refined`] creates (the paper's slider at level 10
/// has 10 · 4¹⁰ ≈ 1.0e7 triangles).
pub const MAX_CELLS: usize = 50_000_000;

/// Tolerance on `|n_c| = 1` for a frictional normal along a coordinate axis.
const AXIS_TOLERANCE: f64 = 1e-9;

/// Default of [`ModelBuilder::max_fault_kink`]: the largest angle (degrees) between the
/// outer normals of two frictional facets meeting at a node.
pub const DEFAULT_MAX_FAULT_KINK_DEGREES: f64 = 30.0;

/// A facet of Γ_F shorter (smaller) than this fraction of the mean facet measure counts as
/// degenerate ([`Error::DegenerateFaultFacet`]).
const DEGENERATE_FACET: f64 = 1e-12;

/// At a node of Γ_F whose facets' area-weighted normal sum is shorter than this fraction of
/// their total measure the boundary folds back ([`Error::FaultFoldsBack`]).
const FOLD: f64 = 1e-6;

/// Builds a consistent [`Model`] (its magnitudes are checked when a simulation is built,
/// [`Model::validate`]) from a mesh (or a refinement hierarchy), a [`Material`],
/// body forces, and named boundary parts: Dirichlet parts with a prescribed velocity,
/// Neumann parts with a traction, and the frictional boundary Γ_F with bilateral contact.
///
/// What it does for you (docs/math.md §3, §6): node-major dofs; consistent mass `M` and
/// stiffness `K` (plane strain in 2D) on one pattern; the energy norm `K + M` (`K` without
/// mass); the load `F` (body force + tractions); the constraints (all listed components
/// of Dirichlet nodes, the normal component of every frictional node); the prescribed
/// velocities `v_i(t) = w_i g(t)` with one loading history `g` ([`TimeFunction`]); the
/// initial displacement `u₀` solving `K u₀ = F` under these constraints; lumped weights on
/// Γ_F; the hierarchy's prolongations for multigrid; the cells for output.
///
/// Γ_F may have any orientation (docs/math.md §10, docs/design.md "Nodal frames"). At a
/// node whose outer normal `n` (the facets' area-weighted mean) is along a coordinate axis
/// (e.g. the bottom of a block) the normal velocity is that Cartesian component, fixed, and
/// nothing is rotated: an axis-aligned fault gives exactly the model it gave before frames
/// existed. At every other node the builder sets a **nodal frame** `Q_p` (columns: the
/// tangent(s), then the inward normal `−n`; 2-D: `t = (−n_y, n_x)`; 3-D: `t₁` the
/// projection of [`fault_tangent`](Self::fault_tangent) onto the tangent plane, by default
/// of the coordinate axis with the smallest `|n_k|`, `t₂ = −n × t₁`) and rotates the model
/// block-diagonally, `Ã = Rᵀ A R` with `R = blockdiag(Q_p)` (identity elsewhere): `K`,
/// `M`, the energy norm, the load, the Dirichlet data of such nodes, `u₀` and the finest
/// prolongation (`Rᵀ P`; coarser levels stay Cartesian). The solvers then see the fault
/// velocity in slip coordinates (tangential…, normal) with the normal component (`D − 1`)
/// fixed; [`Model::frames`] keeps the `Q_p` to present results in global coordinates.
/// Corners (facet normals further apart than [`max_fault_kink`](Self::max_fault_kink))
/// and zero-measure facets are typed errors naming the node.
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
/// builds scalar ones, e.g. antiplane shear with an [`AntiplaneMaterial`], where the one
/// component is tangential to every in-plane fault (no normal to fix, no frames).
pub struct ModelBuilder<const D: usize, const C: usize = D> {
    hierarchy: MeshHierarchy<D>,
    material: Option<Box<dyn Medium<D, C>>>,
    gravity: Option<[f64; D]>,
    body_force: Option<VectorField<D, C>>,
    dirichlet: Vec<Dirichlet<D, C>>,
    neumann: Vec<(Part<D>, VectorField<D, C>)>,
    frictional_boundary: Option<Part<D>>,
    loading: TimeFunction,
    with_mass: bool,
    max_kink_degrees: f64,
    fault_tangent: Option<[f64; D]>,
    slip_factor: f64,
    absorbing: Vec<Absorbing<D, C>>,
    internal_fault: Option<SplitFault<D>>,
    /// The creeping section of an internal fault: its slip rate (m/s, times `g(t)`) by a
    /// pair's position, `None` where the pair slips by friction.
    internal_creep: Option<CreepField<D>>,
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
    /// [`Error::InvalidParameter`] named `levels` if the finest mesh would have more than
    /// [`MAX_CELLS`] cells; refinement errors of [`MeshHierarchy::try_refine_uniformly`].
    pub fn refined(coarse: SimplexMesh<D>, levels: usize) -> Result<Self> {
        Ok(Self::from_hierarchy(refined_hierarchy(coarse, levels)?))
    }

    /// Gravitational acceleration `g` (m/s²): body force density `ρ g`.
    pub fn gravity(mut self, g: [f64; D]) -> Self {
        self.gravity = Some(g);
        self
    }

    /// In 3-D, the reference direction of the first tangent `t₁` of the nodal frames on
    /// slanted fault nodes: its projection onto each node's tangent plane (as PyLith's
    /// `ref_dir`; e.g. the loading direction). Where it is (nearly, its projection
    /// `< 10⁻⁶` of its length) normal to a slanted node or a split pair of an internal
    /// fault, [`build`](Self::build) fails with [`rsf_fem::Error::TangentAlongNormal`]
    /// naming the node and its position (it used to take the coordinate axis with the
    /// smallest `|n_k|` there silently; without a tangent that axis is the rule).
    ///
    /// 3-D only: in 1-D and 2-D the tangent is fixed by the normal (`t = (−n_y, n_x)`) and
    /// there is nothing to choose, so [`build`](Self::build) refuses a `fault_tangent`
    /// there with [`Error::InvalidParameter`] named `fault_tangent` (rather than ignoring
    /// the caller's choice silently).
    pub fn fault_tangent(mut self, direction: [f64; D]) -> Self {
        self.fault_tangent = Some(direction);
        self
    }
}

impl<const D: usize> ModelBuilder<D, 1> {
    /// A scalar-field model (one component per vertex, e.g. antiplane shear with an
    /// [`AntiplaneMaterial`]) on one mesh (the direct solver).
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

impl<const C: usize> ModelBuilder<2, C> {
    /// A fault inside the body along the straight segment `from` → `to` (m) instead of a
    /// frictional boundary: at [`build`](Self::build) the finest mesh is cut open along its
    /// edges on the segment ([`SimplexMesh::split_along_segment`]: a node inside the body
    /// at an end is a shared tip, an end on the outer boundary is split; the faces are
    /// tagged `{name}_minus` and `{name}_plus`), and the model is written in the mean–jump
    /// unknowns of the split pairs ([`InternalFault`], docs/math.md §15): Γ_F is the
    /// pairs' minus nodes, the slip is the jump's tangential component (the normal one is
    /// tied for a vector field: no opening), the weights are the minus face's, the friction
    /// and state laws see the slip exactly as on a boundary fault. Every coarser level of
    /// a hierarchy that resolves the segment is split too, and its prolongation
    /// interpolates each vertex from the coarse vertices on its own side, so the coarse
    /// spaces of multigrid can slip (levels too coarse to resolve the segment stay
    /// continuous; the finest prolongation is `T⁻¹ P`). Outputs at split vertices
    /// ([`StepView::displacement`](crate::observe::StepView::displacement), VTU frames)
    /// are Cartesian.
    ///
    /// # Errors (at `build`)
    /// The splitting's errors (e.g. a segment the mesh does not resolve, one lying on the
    /// outer boundary); [`Error::InvalidParameter`] with a frictional boundary as well, an
    /// [`antisymmetric_fault`](Self::antisymmetric_fault), Dirichlet parts fixing only
    /// some components of a split pair's two sides (their Cartesian data would mix the
    /// mean and the jump), or fixing both sides with velocities that open the fault. A
    /// pair whose two sides are fully fixed is prescribed and not a frictional node
    /// ([`internal_creep`](Self::internal_creep)).
    ///
    /// ```
    /// use rsf::fem::{rectangle, Diagonal};
    /// use rsf::{Material, ModelBuilder, Part};
    /// // A 2 m square sheared by its top and bottom, a fault inside from (0, −0.5) to (0, 0.5).
    /// let block = rectangle([-1.0, -1.0], [2.0, 2.0], 9, 9, Diagonal::Forward)?;
    /// let model = ModelBuilder::refined(block, 1)?
    ///     .material(Material::new(1e10, 0.25, 2700.0))
    ///     .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
    ///     .dirichlet(Part::predicate("bottom", |x| x[1] < -1.0 + 1e-9), [-1e-4, 0.0])
    ///     .internal_fault("fault", [0.0, -0.5], [0.0, 0.5])
    ///     .build()?;
    /// // 9 fault nodes on the fine mesh: 2 shared tips, 7 split pairs (the slipping nodes).
    /// assert_eq!(model.frictional_boundary.len(), 7);
    /// assert_eq!(model.num_nodes(), 17 * 17 + 7);
    /// # Ok::<(), rsf::Error>(())
    /// ```
    pub fn internal_fault(self, name: &str, from: [f64; 2], to: [f64; 2]) -> Self {
        self.internal_fault_polyline(name, &[from, to])
    }

    /// As [`internal_fault`](Self::internal_fault) for a fault of straight pieces
    /// `points[0] → points[1] → …` (m): a kinked fault, or a curved one given by the
    /// vertices of its mesh edges in order (e.g. a Gmsh physical curve's,
    /// [`GmshMesh::interior_polyline`](rsf_fem::GmshMesh::interior_polyline)). Each piece
    /// must be resolved by mesh edges ([`SimplexMesh::split_along_polyline`]); the slip's
    /// direction follows the fault from `points[0]`, the plus side on the left.
    ///
    /// # Errors (at `build`)
    /// As [`internal_fault`](Self::internal_fault); fewer than two points, a polyline
    /// running back over or crossing itself.
    ///
    /// ```
    /// use rsf::fem::{rectangle, Diagonal};
    /// use rsf::{Material, ModelBuilder, Part};
    /// // A fault kinked at (0, 0): from (−0.5, −0.5) up to (0, 0), then straight up.
    /// let block = rectangle([-1.0, -1.0], [2.0, 2.0], 9, 9, Diagonal::Forward)?;
    /// let model = ModelBuilder::refined(block, 1)?
    ///     .material(Material::new(1e10, 0.25, 2700.0))
    ///     .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
    ///     .dirichlet(Part::predicate("bottom", |x| x[1] < -1.0 + 1e-9), [-1e-4, 0.0])
    ///     .internal_fault_polyline("fault", &[[-0.5, -0.5], [0.0, 0.0], [0.0, 0.5]])
    ///     .build()?;
    /// // 4 + 4 fine edges: 9 fault nodes, 2 shared tips.
    /// assert_eq!(model.frictional_boundary.len(), 7);
    /// # Ok::<(), rsf::Error>(())
    /// ```
    pub fn internal_fault_polyline(mut self, name: &str, points: &[[f64; 2]]) -> Self {
        let name = name.to_string();
        let points = points.to_vec();
        self.internal_fault = Some(Box::new(move |hierarchy: &MeshHierarchy<2>, _| {
            split_hierarchy(
                hierarchy,
                |_, mesh| mesh.split_along_polyline(&name, &points),
                |sides, mesh| sides.mean_jump_transform::<C>(mesh),
            )
        }));
        self
    }
}

impl<const C: usize> ModelBuilder<3, C> {
    /// A fault inside a 3-D body on the convex planar polygon `corners` (m, at least three,
    /// in order around it) instead of a frictional boundary: at [`build`](Self::build) the
    /// finest mesh is cut open along its faces on the polygon
    /// ([`SimplexMesh::split_along_polygon`]: a fault vertex whose cells the fault does
    /// not separate — its rim inside the body — is a shared tip, a vertex where the fault
    /// meets the outer boundary (a free surface) is split; the faces are tagged
    /// `{name}_minus` and `{name}_plus`), and the model is written in the mean–jump
    /// unknowns of the split pairs as in 2-D ([`internal_fault`](ModelBuilder::internal_fault),
    /// docs/math.md §15). The fault's normal `n` is the polygon's by the right-hand rule of
    /// the corners' order; it points from the minus into the plus side. Each pair's frame
    /// is `(t₁, t₂, −n)` with `n` the area-weighted mean of the adjacent faces' normals and
    /// `t₁` the projection of [`fault_tangent`](Self::fault_tangent) (default: the axis
    /// with the smallest `|n_k|`): the jump's first two components are the slip (friction
    /// acts on them as on a 3-D boundary fault, the creeping section of
    /// [`internal_creep`](ModelBuilder::internal_creep) prescribes its `t₁` component), the
    /// third is tied (no opening). Every coarser level of a hierarchy that resolves the
    /// polygon is split too, as in 2-D.
    ///
    /// # Errors (at `build`)
    /// [`Error::Fem`] with the splitting's errors (a polygon the mesh does not resolve,
    /// [`rsf_fem::Error::FaultSurfaceNotResolved`]; fewer than three or non-coplanar
    /// corners; a fault face on the outer boundary); [`Error::InvalidParameter`] named
    /// `fault_tangent` for a non-finite or zero tangent, `dirichlet` for a split vertex
    /// with only some components fixed, `internal_fault` for levels not nested along the
    /// fault.
    ///
    /// ```
    /// use rsf::fem::cuboid;
    /// use rsf::{Material, ModelBuilder, Part};
    /// // A unit cube cut through by the plane x = 0.5: every fault vertex is split.
    /// let cube = cuboid([0.0; 3], [1.0; 3], [3, 3, 3])?;
    /// let model = ModelBuilder::refined(cube, 1)?
    ///     .material(Material::new(1e10, 0.25, 2700.0))
    ///     .dirichlet(Part::predicate("left", |x| x[0] < 1e-9), [0.0, -1e-4, 0.0])
    ///     .dirichlet(Part::predicate("right", |x| x[0] > 1.0 - 1e-9), [0.0, 1e-4, 0.0])
    ///     .internal_fault_polygon(
    ///         "fault",
    ///         &[[0.5, 0.0, 0.0], [0.5, 1.0, 0.0], [0.5, 1.0, 1.0], [0.5, 0.0, 1.0]],
    ///     )
    ///     .build()?;
    /// // The fine level has 5 × 5 fault vertices, all split.
    /// assert_eq!(model.frictional_boundary.len(), 25);
    /// # Ok::<(), rsf::Error>(())
    /// ```
    pub fn internal_fault_polygon(mut self, name: &str, corners: &[[f64; 3]]) -> Self {
        let name = name.to_string();
        let corners = corners.to_vec();
        self.internal_fault = Some(Box::new(
            move |hierarchy: &MeshHierarchy<3>, tangent: Option<&[f64; 3]>| {
                split_hierarchy(
                    hierarchy,
                    |_, mesh| mesh.split_along_polygon(&name, &corners),
                    |sides, mesh| sides.mean_jump_transform::<C>(mesh, tangent),
                )
            },
        ));
        self
    }

    /// As [`internal_fault_polygon`](Self::internal_fault_polygon) for a fault given as
    /// triangles of the coarsest mesh (vertex indices of the hierarchy's level 0, any
    /// orientation: the first face's right-hand-rule normal points from the minus into the
    /// plus side, [`SimplexMesh::split_along`]) — any surface of mesh faces, curved or
    /// kinked, e.g. a Gmsh physical surface inside the body
    /// ([`GmshMesh::interior_facets`](rsf_fem::GmshMesh::interior_facets) read with
    /// `interior_facets: true`). Every level of the hierarchy is split: a finer level's
    /// fault is the four children of each face of the level below (a curved fault stays
    /// the piecewise-planar surface of its coarse faces, as a 2-D fault is the polyline of
    /// its coarse edges).
    ///
    /// # Errors (at `build`)
    /// As [`internal_fault_polygon`](Self::internal_fault_polygon), with the face errors
    /// of [`SimplexMesh::split_along`] (a face not in the mesh or on its boundary, three
    /// faces at an edge, a non-orientable or disconnected set, sides not separated).
    pub fn internal_fault_faces(mut self, name: &str, faces: &[[usize; 3]]) -> Self {
        let name = name.to_string();
        let faces = faces.to_vec();
        self.internal_fault = Some(Box::new(
            move |hierarchy: &MeshHierarchy<3>, tangent: Option<&[f64; 3]>| {
                // The given faces' own errors first (as faces of level 0).
                hierarchy.level(0).split_along(&name, &faces)?;
                let levels = faces_on_levels(hierarchy, &faces)?;
                split_hierarchy(
                    hierarchy,
                    |j, mesh| mesh.split_along(&name, &levels[j]),
                    |sides, mesh| sides.mean_jump_transform::<C>(mesh, tangent),
                )
            },
        ));
        self
    }
}

impl<const D: usize, const C: usize> ModelBuilder<D, C> {
    /// The creeping section of the internal fault: the split pairs at positions `x` (m)
    /// with `inside(x)` slip at the prescribed rate `slip_rate · g(t)` (m/s; `g` the loading
    /// history) instead of by friction — along the pair's tangent, in 2-D the fault's
    /// direction turned by 180° (`t = −d`, `d` from the first point to the last; the same
    /// sign as [`StepView::slip`](crate::StepView::slip)), in 3-D the frame's first tangent
    /// `t₁` ([`internal_fault_polygon`](ModelBuilder::internal_fault_polygon)), with the
    /// second tangential component fixed at 0 (a vector of prescribed direction; other
    /// directions, a rake or a rate per node: [`internal_creep_at`](Self::internal_creep_at)).
    /// Used for a fault loaded by steady creep below the seismogenic depth (SEAS BP3). Pairs
    /// whose two sides are both fully fixed by Dirichlet parts (each side's far-field
    /// motion where the fault meets a far boundary) are prescribed too. Prescribed pairs are
    /// not frictional nodes.
    ///
    /// # Errors (at `build`)
    /// As [`internal_fault`](Self::internal_fault); [`Error::InvalidParameter`] named
    /// `internal_creep` for a non-finite rate or without an internal fault.
    pub fn internal_creep(
        self,
        inside: impl Fn(&[f64; D]) -> bool + 'static,
        slip_rate: f64,
    ) -> Self {
        self.internal_creep_at(move |x| inside(x).then_some(CreepRate::InFrame([slip_rate, 0.0])))
    }

    /// The creeping section of the internal fault with a slip-rate vector per pair: the
    /// pair at position `x` (m) slips at `rate(x)` times the loading history `g(t)` where
    /// it is `Some` ([`CreepRate`]: components in the pair's frame, a rake, or a Cartesian
    /// vector tangent to the fault), by friction where it is `None`. Every tangential
    /// component of a creeping pair is fixed (docs/math.md "Slip as a vector").
    ///
    /// ```
    /// use rsf::fem::cuboid;
    /// use rsf::model::CreepRate;
    /// use rsf::{Material, ModelBuilder, Part};
    /// // The plane x = 0.5 of a unit cube: its upper half creeps along (0, cos 30°, sin 30°).
    /// let cube = cuboid([0.0; 3], [1.0; 3], [3, 3, 3])?;
    /// let v = 1e-9;
    /// let model = ModelBuilder::refined(cube, 1)?
    ///     .material(Material::new(1e10, 0.25, 2700.0))
    ///     .dirichlet(Part::predicate("left", |x| x[0] < 1e-9), [0.0; 3])
    ///     .internal_fault_polygon(
    ///         "fault",
    ///         &[[0.5, 0.0, 0.0], [0.5, 1.0, 0.0], [0.5, 1.0, 1.0], [0.5, 0.0, 1.0]],
    ///     )
    ///     .internal_creep_at(move |x| {
    ///         let rake = 30f64.to_radians();
    ///         (x[2] > 0.6).then_some(CreepRate::Cartesian([0.0, v * rake.cos(), v * rake.sin()]))
    ///     })
    ///     .build()?;
    /// // 5 × 5 fault vertices, the 5 at z = 0.75 and the 5 at z = 1 creep.
    /// assert_eq!(model.frictional_boundary.len(), 15);
    /// # Ok::<(), rsf::Error>(())
    /// ```
    ///
    /// # Errors (at `build`)
    /// As [`internal_creep`](Self::internal_creep); [`Error::InvalidParameter`] named
    /// `internal_creep` for a rate [`CreepRate`] refuses (a second tangential component in
    /// 2-D, a Cartesian rate with a normal part or on a scalar field), naming the position.
    pub fn internal_creep_at(
        mut self,
        rate: impl Fn(&[f64; D]) -> Option<CreepRate<D>> + 'static,
    ) -> Self {
        self.internal_creep = Some(Box::new(rate));
        self
    }

    /// Per pair of the internal fault `fault`: whether its slip is prescribed. A pair whose
    /// two sides are fully fixed by Dirichlet parts gets their velocities in its
    /// mean–jump unknowns (`j = Rᵀ(v⁺ − v⁻)`, `w = (1 − β) v⁻ + β v⁺`; an opening is
    /// refused); a pair in the creeping section gets its jump's tangential component fixed
    /// at the creep rate.
    fn prescribed_pairs(
        &self,
        fault: &InternalFault<D>,
        mesh: &SimplexMesh<D>,
        fixed: &mut [bool],
        velocity: &mut [Option<f64>],
    ) -> Result<Vec<bool>> {
        let mut prescribed = Vec::with_capacity(fault.pairs().len());
        for (k, &(mi, pl)) in fault.pairs().iter().enumerate() {
            let beta = fault.transform.minus_share[k];
            if fixed[C * mi] {
                // Both sides fully fixed (checked by internal_fault_frames).
                let v = |p: usize| -> [f64; C] {
                    std::array::from_fn(|c| velocity[C * p + c].unwrap_or(0.0))
                };
                let (vm, vp) = (v(mi), v(pl));
                let dv: [f64; C] = std::array::from_fn(|c| vp[c] - vm[c]);
                let vector = C == D && C > 1;
                let j: [f64; C] = if vector {
                    let r = fault.transform.frames[k];
                    std::array::from_fn(|a| (0..C).map(|b| r[b][a] * dv[b]).sum())
                } else {
                    dv
                };
                let scale = vm.iter().chain(&vp).fold(0.0f64, |m, x| m.max(x.abs()));
                if vector && j[normal_component(C)].abs() > 1e-12 * scale {
                    return Err(invalid(
                        "dirichlet",
                        format!(
                            "the Dirichlet parts at split node {mi} of the internal fault `{}` \
                             open or close it (normal jump {:e} m/s): the fault's normal jump \
                             is tied",
                            fault.sides.name(),
                            j[normal_component(C)]
                        ),
                    ));
                }
                for c in 0..C {
                    let tied = c == normal_component(C) && vector;
                    velocity[C * mi + c] = Some(if tied { 0.0 } else { j[c] });
                    velocity[C * pl + c] = Some((1.0 - beta) * vm[c] + beta * vp[c]);
                }
                prescribed.push(true);
            } else if let Some(rate) = self
                .internal_creep
                .as_ref()
                .and_then(|creep| creep(&mesh.vertices()[mi]))
            {
                let x = &mesh.vertices()[mi];
                let j = rate.in_frame::<C>(&fault.transform.frames[k], x)?;
                let tangential = if C == D && C > 1 { C - 1 } else { 1 };
                for (c, &jc) in j.iter().enumerate().take(tangential) {
                    fixed[C * mi + c] = true;
                    velocity[C * mi + c] = Some(jc);
                }
                prescribed.push(true);
            } else {
                prescribed.push(false);
            }
        }
        Ok(prescribed)
    }

    fn with_components(hierarchy: MeshHierarchy<D>) -> Self {
        Self {
            hierarchy,
            material: None,
            gravity: None,
            body_force: None,
            dirichlet: Vec::new(),
            neumann: Vec::new(),
            frictional_boundary: None,
            loading: TimeFunction::Constant(1.0),
            with_mass: true,
            max_kink_degrees: DEFAULT_MAX_FAULT_KINK_DEGREES,
            fault_tangent: None,
            slip_factor: 1.0,
            absorbing: Vec::new(),
            internal_fault: None,
            internal_creep: None,
        }
    }

    /// The finest mesh (where parts are selected).
    pub fn mesh(&self) -> &SimplexMesh<D> {
        self.hierarchy.finest()
    }

    /// The material (required): a [`Material`] for elasticity (`C = D`), an
    /// [`AntiplaneMaterial`] for a scalar field (`C = 1`), or a user's [`Medium`].
    pub fn material(mut self, material: impl Medium<D, C> + 'static) -> Self {
        self.material = Some(Box::new(material));
        self
    }

    /// A body force density `f(x)` (N/m³; N/m² per unit thickness in 2D), added to gravity.
    pub fn body_force(mut self, f: impl Fn(&[f64; D]) -> [f64; C] + 'static) -> Self {
        self.body_force = Some(Box::new(f));
        self
    }

    /// A Dirichlet part whose nodes move with velocity `velocity · g(t)` (m/s; `g` the
    /// [`loading`](Self::loading) history), all components fixed. `[0.0; C]` clamps.
    pub fn dirichlet(self, part: impl Into<Part<D>>, velocity: [f64; C]) -> Self {
        self.dirichlet_components(part, &(0..C).collect::<Vec<_>>(), velocity)
    }

    /// A Dirichlet part fixing only the listed components (e.g. a roller: the normal
    /// component only); component `c` moves with `velocity[c] · g(t)`.
    pub fn dirichlet_components(
        mut self,
        part: impl Into<Part<D>>,
        components: &[usize],
        velocity: [f64; C],
    ) -> Self {
        self.dirichlet.push(Dirichlet {
            part: part.into(),
            components: components.to_vec(),
            velocity,
        });
        self
    }

    /// A Neumann part with traction `t(x)` (Pa; N/m per unit thickness in 2D). Parts
    /// without any condition are traction-free.
    pub fn neumann(
        mut self,
        part: impl Into<Part<D>>,
        traction: impl Fn(&[f64; D]) -> [f64; C] + 'static,
    ) -> Self {
        self.neumann.push((part.into(), Box::new(traction)));
        self
    }

    /// An absorbing part Γ_A (a truncation boundary of a dynamic model): Lysmer–Kuhlemeyer
    /// dashpots with the medium's impedances ([`Medium::impedances`]), the far field at
    /// rest ([`AbsorbingBoundary`](crate::model::AbsorbingBoundary), docs/math.md
    /// "Absorbing boundaries"). May be called for several parts; a part's dofs that are
    /// also Dirichlet dofs stay prescribed (the dashpot does nothing there).
    pub fn absorbing_boundary(self, part: impl Into<Part<D>>) -> Self {
        self.absorbing_boundary_moving(part, [0.0; C])
    }

    /// An absorbing part whose far field moves with velocity `velocity · g(t)` (m/s, of
    /// the field `u` as Dirichlet velocities are given; `g` the [`loading`](Self::loading)
    /// history): the dashpots act on `v − velocity · g(t)`, so a body translating with the
    /// far field feels no force (e.g. SEAS BP1's half-space moving at `V_p/2`).
    pub fn absorbing_boundary_moving(
        mut self,
        part: impl Into<Part<D>>,
        velocity: [f64; C],
    ) -> Self {
        self.absorbing.push(Absorbing {
            part: part.into(),
            velocity,
        });
        self
    }

    /// The frictional boundary Γ_F (required unless the fault is inside the body,
    /// [`internal_fault`](ModelBuilder::internal_fault)), with bilateral contact: the normal
    /// velocity component of its nodes is fixed (vector fields; a scalar field's one
    /// component is tangential).
    pub fn frictional_boundary(mut self, part: impl Into<Part<D>>) -> Self {
        self.frictional_boundary = Some(part.into());
        self
    }

    /// Γ_F is a plane of antisymmetry with slip `δ = s·u` (`s = 2`: a fault between two
    /// halves moving oppositely, of which the model is one; default `s = 1`, a body on a
    /// rigid surface). The model's unknown becomes `ũ = s·u` everywhere, so that every
    /// block on Γ_F is the slip (and its norm the slip rate) for friction, state, observers
    /// and outputs: `K̃ = K/s²`, `M̃ = M/s²`, `F̃ = F/s`, weights `w̃ = w/s`, prescribed
    /// velocities `s·v` (they are given for `u`, as usual). With these, the energy, the
    /// friction functional `Σ w̃ ϕ(|ṽ|)` and the radiation damping `Σ w̃ η/2 |ṽ|²` are
    /// those of the half model in `u` (docs/seas-bp1.md);
    /// [`FrictionalBoundary::slip_factor`](crate::model::FrictionalBoundary::slip_factor) keeps `s`.
    pub fn antisymmetric_fault(mut self, slip_factor: f64) -> Self {
        self.slip_factor = slip_factor;
        self
    }

    /// The loading history `g(t)` scaling every Dirichlet velocity (default `g ≡ 1`).
    pub fn loading(mut self, history: TimeFunction) -> Self {
        self.loading = history;
        self
    }

    /// The largest angle (degrees, in `[0, 180]`) between the outer normals of two
    /// frictional facets meeting at a node (default
    /// [`DEFAULT_MAX_FAULT_KINK_DEGREES`]); a node beyond it is a corner
    /// ([`Error::FaultCorner`]), where no nodal frame is well defined.
    pub fn max_fault_kink(mut self, degrees: f64) -> Self {
        self.max_kink_degrees = degrees;
        self
    }

    /// No mass matrix (quasistatic problems); the energy norm is then `K`.
    pub fn without_mass(mut self) -> Self {
        self.with_mass = false;
        self
    }

    /// Assembles the model and checks its consistency (shapes, constraints, frames).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a missing material or frictional part, non-finite
    /// velocities or gravity, a component ≥ D, two Dirichlet parts prescribing different
    /// velocities to one dof; [`Error::BoundaryPart`] for a part that selects nothing
    /// or was built on another mesh; [`Error::FaultCorner`] / [`Error::FaultFoldsBack`] /
    /// [`Error::DegenerateFaultFacet`] where Γ_F has no well-defined nodal frame; [`Error::InvalidParameter`] named
    /// `dirichlet` for a slanted fault node with only some Cartesian components fixed,
    /// `max_fault_kink` or `fault_tangent` out of range, `fault_tangent` in 1-D or 2-D;
    /// [`Error::Equilibrium`] if `K u₀ = F` is singular under the constraints; material
    /// and assembly errors ([`Error::Fem`]), e.g. a non-finite force or traction.
    pub fn build(self) -> Result<Model<D, C>> {
        const { assert!(C == D || C == 1, "vector (C = D) or scalar (C = 1) fields") };
        // A fault inside the body: the finest mesh cut open along it.
        let (split, fault, split_prolongations) = match &self.internal_fault {
            Some(split_fault) => {
                let s = split_fault(&self.hierarchy, self.checked_fault_tangent()?.as_ref())?;
                (Some(s.mesh), Some(s.fault), Some(s.prolongations))
            }
            None => (None, None, None),
        };
        if self.internal_creep.is_some() && fault.is_none() {
            return Err(invalid(
                "internal_creep",
                "a creeping section needs an internal fault (ModelBuilder::internal_fault)",
            ));
        }
        let mesh = split.as_ref().unwrap_or_else(|| self.hierarchy.finest());
        let n = C * mesh.num_vertices();
        let material = self
            .material
            .as_ref()
            .ok_or_else(|| invalid("material", "not set"))?;
        let s = self.slip_factor;
        if !(s.is_finite() && s > 0.0) {
            return Err(invalid(
                "slip_factor",
                format!("{s} must be finite and positive"),
            ));
        }
        let minus_face: Part<D>;
        let fpart = match (&self.frictional_boundary, &fault) {
            (Some(p), None) => p,
            (None, Some(f)) => {
                minus_face = Part::from(f.sides.minus_tag());
                &minus_face
            }
            (Some(_), Some(_)) => {
                return Err(invalid(
                    "frictional_boundary",
                    "given besides an internal fault (whose minus face is Γ_F): give one",
                ))
            }
            (None, None) => {
                return Err(invalid(
                    "frictional_boundary",
                    "not set (ModelBuilder::frictional_boundary or internal_fault)",
                ))
            }
        };
        if fault.is_some() && s != 1.0 {
            return Err(invalid(
                "slip_factor",
                "an internal fault's slip is its jump: no antisymmetric_fault with it",
            ));
        }
        self.loading.validate()?;
        if let Some(g) = self.gravity {
            if g.iter().any(|c| !c.is_finite()) {
                return Err(invalid("gravity", format!("{g:?} must be finite")));
            }
        }

        // Constraints and prescribed velocities.
        let mut fixed = vec![false; n];
        let mut velocity: Vec<Option<f64>> = vec![None; n];
        for d in &self.dirichlet {
            let name = d.part.name();
            if d.components.is_empty() || d.components.iter().any(|&c| c >= C) {
                return Err(invalid(
                    "dirichlet",
                    format!(
                        "part `{name}`: components {:?} must be in 0..{C}",
                        d.components
                    ),
                ));
            }
            if d.velocity.iter().any(|c| !c.is_finite()) {
                return Err(invalid(
                    "dirichlet",
                    format!("part `{name}`: velocity {:?} must be finite", d.velocity),
                ));
            }
            let part = d.part.resolve(mesh)?;
            for &p in part.nodes() {
                for &c in &d.components {
                    let i = C * p + c;
                    let w = d.velocity[c];
                    match velocity[i] {
                        Some(old) if old != w => {
                            return Err(invalid(
                                "dirichlet",
                                format!(
                                    "node {p} component {c}: part `{name}` prescribes {w} m/s, \
                                     an earlier part {old} m/s"
                                ),
                            ))
                        }
                        _ => velocity[i] = Some(w),
                    }
                    fixed[i] = true;
                }
            }
        }
        let gamma_f = fpart.resolve(mesh)?;
        // A vector field slides tangentially (normal component fixed, nodal frames on
        // slanted nodes); a scalar field's one component is tangential to any in-plane Γ_F.
        // An internal fault: the pair frames (kept for outputs; its matrices take `T`).
        let frames: NodalFrames<C> = match &fault {
            Some(f) => internal_fault_frames(f, &fixed)?,
            None if C == D => same_block_size(self.fault_frames(mesh, &gamma_f, fpart.name())?),
            None => NodalFrames::default(),
        };
        if let Some(f) = &fault {
            // The normal jump is tied (no opening); a scalar field has only the slip.
            if C == D {
                for &(mi, _) in f.pairs() {
                    fixed[C * mi + normal_component(C)] = true;
                }
            }
        } else if C == D {
            for (&p, nrm) in gamma_f.nodes().iter().zip(&gamma_f.normals(mesh)?) {
                if let Some(c) = normal_axis(nrm) {
                    fixed[C * p + c] = true;
                }
            }
        }
        for (&p, q) in frames
            .nodes
            .iter()
            .zip(&frames.rotations)
            .filter(|_| fault.is_none())
        {
            let dofs = C * p..C * p + C;
            match fixed[dofs.clone()].iter().filter(|&&f| f).count() {
                // Bilateral contact: the normal component in the frame.
                0 => fixed[C * p + normal_component(C)] = true,
                // A Dirichlet node on the slanted fault: its prescribed velocity in the frame.
                k if k == C => {
                    let w: Vec<f64> = dofs.map(|i| velocity[i].unwrap_or(0.0)).collect();
                    for c in 0..C {
                        let wc: f64 = (0..C).map(|r| q[r][c] * w[r]).sum();
                        velocity[C * p + c] = Some(wc);
                    }
                }
                _ => {
                    return Err(invalid(
                        "dirichlet",
                        format!(
                            "node {p} is on the slanted frictional boundary `{}` (it has a \
                             nodal frame) and a Dirichlet part fixes only some of its \
                             Cartesian components; fix all of them or none",
                            fpart.name()
                        ),
                    ))
                }
            }
        }

        // Matrices.
        self.check_absorbing(material.as_ref())?;
        let MediumMatrices {
            stiffness,
            mass,
            energy_norm,
        } = material.assemble(mesh, self.with_mass)?;
        let absorbing =
            self.absorbing_parts(mesh, material.as_ref(), &gamma_f, &fixed, &stiffness)?;

        // Loads (gravity only for vector fields: its setter needs C = D).
        let gravity = |g: [f64; D], x: &[f64; D]| -> [f64; C] {
            let rho = material.density_at(x);
            std::array::from_fn(|c| rho * g[c])
        };
        let mut load = match (self.gravity, &self.body_force) {
            (None, None) => vec![0.0; n],
            (Some(g), None) => body_force_load_components(mesh, |x| gravity(g, x))?,
            (None, Some(f)) => body_force_load_components(mesh, f)?,
            (Some(g), Some(f)) => body_force_load_components(mesh, |x| {
                let mut v = f(x);
                for (vc, gc) in v.iter_mut().zip(gravity(g, x)) {
                    *vc += gc;
                }
                v
            })?,
        };
        for (part, traction) in &self.neumann {
            let t = traction_load_components(mesh, &part.resolve(mesh)?, traction)?;
            for (l, ti) in load.iter_mut().zip(t) {
                *l += ti;
            }
        }
        // An antisymmetric fault: the unknown is s·u (K/s², M/s², C/s², F/s, w/s).
        let (mass, stiffness, energy_norm, absorbing) = if s == 1.0 {
            (mass, stiffness, energy_norm, absorbing)
        } else {
            let k = 1.0 / (s * s);
            let scaled = |a: &SparseMatrix| combine(0.0, a, k, a).map_err(rsf_fem::Error::from);
            for l in &mut load {
                *l /= s;
            }
            let absorbing = match absorbing {
                Some(mut a) => {
                    a.damping = scaled(&a.damping)?;
                    // C̃ (s w) = C w / s.
                    a.far_field_force.iter_mut().for_each(|f| *f /= s);
                    Some(a)
                }
                None => None,
            };
            (
                mass.as_ref().map(scaled).transpose()?,
                scaled(&stiffness)?,
                scaled(&energy_norm)?,
                absorbing,
            )
        };

        // An internal fault: the jump shared between the sides by their stiffness, then
        // everything in the mean–jump unknowns, `Tᵀ A T` and `Tᵀ F`.
        // Slanted fault nodes: everything in the nodal frames (identity elsewhere).
        let fault = match fault {
            Some(f) => Some(f.shared_by_stiffness::<C>(&stiffness)?),
            None => None,
        };
        // An internal fault's prescribed pairs (both sides' velocities given, or a
        // creeping section): their data in the mean–jump unknowns; they do not slip freely.
        let prescribed = match &fault {
            Some(f) => self.prescribed_pairs(f, mesh, &mut fixed, &mut velocity)?,
            None => Vec::new(),
        };
        let (dofs, factors): (Vec<usize>, Vec<f64>) = velocity
            .iter()
            .enumerate()
            .filter_map(|(i, w)| w.filter(|w| *w != 0.0).map(|w| (i, s * w)))
            .unzip();
        let (mass, stiffness, energy_norm, absorbing) = if let Some(f) = &fault {
            load = f.transform.pull_back(&load)?;
            let congruence = |a: &SparseMatrix| f.transform.congruence(a);
            let absorbing = match absorbing {
                Some(mut a) => {
                    a.damping = congruence(&a.damping)?;
                    if !a.far_field_force.is_empty() {
                        a.far_field_force = f.transform.pull_back(&a.far_field_force)?;
                    }
                    Some(a)
                }
                None => None,
            };
            (
                mass.as_ref().map(congruence).transpose()?,
                congruence(&stiffness)?,
                congruence(&energy_norm)?,
                absorbing,
            )
        } else if frames.nodes.is_empty() {
            (mass, stiffness, energy_norm, absorbing)
        } else {
            frames.to_local(&mut load)?;
            let rotate = |a: &SparseMatrix| -> Result<SparseMatrix> {
                symmetrized(&frames.rotate_matrix(a.as_ref())?)
            };
            let absorbing = match absorbing {
                Some(mut a) => {
                    a.damping = rotate(&a.damping)?;
                    if !a.far_field_force.is_empty() {
                        frames.to_local(&mut a.far_field_force)?;
                    }
                    Some(a)
                }
                None => None,
            };
            (
                mass.as_ref().map(rotate).transpose()?,
                rotate(&stiffness)?,
                rotate(&energy_norm)?,
                absorbing,
            )
        };

        // Γ_F in increasing node order; `along` by coordinates (lexicographic).
        let mut weights = gamma_f.weights(mesh)?;
        if s != 1.0 {
            for w in &mut weights {
                *w /= s;
            }
        }
        let vertices = mesh.vertices();
        let mut order: Vec<usize> = (0..gamma_f.num_nodes()).collect();
        order.sort_by(|&a, &b| {
            let (xa, xb) = (&vertices[gamma_f.nodes()[a]], &vertices[gamma_f.nodes()[b]]);
            xa.iter()
                .zip(xb)
                .map(|(u, v)| u.total_cmp(v))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        let (nodes_along, weights_along): (Vec<usize>, Vec<f64>) = match &fault {
            // The pairs' minus nodes in order along the fault (a tip does not slip).
            Some(f) => {
                let mut weight_of = vec![f64::NAN; mesh.num_vertices()];
                for (&p, &w) in gamma_f.nodes().iter().zip(&weights) {
                    weight_of[p] = w;
                }
                f.pairs()
                    .iter()
                    .zip(&prescribed)
                    .filter(|(_, &given)| !given)
                    .map(|(&(mi, _), _)| (mi, weight_of[mi]))
                    .unzip()
            }
            None => order
                .iter()
                .map(|&k| (gamma_f.nodes()[k], weights[k]))
                .unzip(),
        };
        let frictional_boundary =
            FrictionalBoundary::new(&nodes_along, &weights_along)?.with_slip_factor(s)?;

        let mut prolongations: Vec<_> = match &split_prolongations {
            // Split levels: Cartesian coarse spaces, discontinuous across the fault.
            Some(split) => split.iter().map(vectorize::<C>).collect(),
            None => (1..self.hierarchy.num_levels())
                .map(|j| match C {
                    1 => self.hierarchy.prolongation(j).clone(),
                    _ if C == D => self.hierarchy.vector_prolongation(j).clone(),
                    _ => vectorize::<C>(self.hierarchy.prolongation(j)),
                })
                .collect(),
        };
        if let (Some(p), Some(f)) = (prolongations.last_mut(), &fault) {
            // Onto the finest level's mean–jump unknowns: T⁻¹ P.
            *p = f.transform.prolongation(p)?;
        } else if let Some(p) = prolongations
            .last_mut()
            .filter(|_| !frames.nodes.is_empty())
        {
            *p = frames.rotate_rows(p.as_ref())?;
        }
        // Initial equilibrium (after the prolongations: a large 3-D model solves it by
        // multigrid on them).
        let u0 = super::equilibrium::solve::<D, C>(&stiffness, &fixed, &load, &prolongations)?;

        let model = Model {
            vertices: vertices.to_vec(),
            mass,
            stiffness,
            energy_norm,
            load,
            fixed,
            dirichlet: DirichletVelocity {
                dofs,
                factors,
                history: self.loading,
            },
            prolongations,
            frictional_boundary,
            initial_displacement: u0,
            cells: mesh.cells().to_vec(),
            frames,
            absorbing,
            internal_fault: fault,
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

/// The pair frames of an internal fault on its minus nodes, in increasing node order (for
/// outputs: the jump block rotated back is the Cartesian jump); none for a scalar field.
/// A Dirichlet constraint on a split node is refused: its Cartesian data would mix the
/// mean and the jump.
fn internal_fault_frames<const D: usize, const C: usize>(
    fault: &InternalFault<D>,
    fixed: &[bool],
) -> Result<NodalFrames<C>> {
    for &(mi, pl) in fault.pairs() {
        let count = [mi, pl]
            .iter()
            .map(|&p| (0..C).filter(|&c| fixed[C * p + c]).count())
            .sum::<usize>();
        if count != 0 && count != 2 * C {
            let p = if (0..C).any(|c| fixed[C * mi + c]) {
                mi
            } else {
                pl
            };
            return Err(invalid(
                "dirichlet",
                format!(
                    "node {p} is a split node of the internal fault `{}` and Dirichlet parts \
                     fix only some components of its two sides; fix every component of both \
                     sides (e.g. each side's far-field motion) or none",
                    fault.sides.name()
                ),
            ));
        }
    }
    if C != D || C == 1 {
        return Ok(NodalFrames::default());
    }
    let mut frames: Vec<(usize, [[f64; C]; C])> = fault
        .pairs()
        .iter()
        .zip(&fault.transform.frames)
        .map(|(&(mi, _), r)| {
            (
                mi,
                std::array::from_fn(|a| std::array::from_fn(|b| r[a][b])),
            )
        })
        .collect();
    frames.sort_by_key(|f| f.0);
    Ok(NodalFrames {
        nodes: frames.iter().map(|f| f.0).collect(),
        rotations: frames.into_iter().map(|f| f.1).collect(),
    })
}

/// `frames` as frames of `C`-component blocks, for `C = D` (where they are the same type).
///
/// # Panics
/// If `C ≠ D` and there are frames (internal invariant: only vector fields have frames).
fn same_block_size<const D: usize, const C: usize>(frames: NodalFrames<D>) -> NodalFrames<C> {
    assert!(C == D || frames.nodes.is_empty(), "frames need C = D");
    NodalFrames {
        nodes: frames.nodes,
        rotations: frames
            .rotations
            .into_iter()
            .map(|q| std::array::from_fn(|r| std::array::from_fn(|c| q[r][c])))
            .collect(),
    }
}

impl<const D: usize, const C: usize> ModelBuilder<D, C> {
    /// The checks of the absorbing parts that need no assembly (before it, so that a
    /// medium the mass matrix would refuse, e.g. of zero density, is named here): inertia,
    /// a finite far-field velocity, the medium's impedances finite and positive.
    fn check_absorbing(&self, material: &dyn Medium<D, C>) -> Result<()> {
        for a in &self.absorbing {
            let name = a.part.name();
            if !self.with_mass {
                return Err(part_error(
                    name,
                    "absorbing parts need inertia (the model is built without_mass)",
                ));
            }
            if a.velocity.iter().any(|w| !w.is_finite()) {
                return Err(part_error(
                    name,
                    format!("far-field velocity {:?} must be finite", a.velocity),
                ));
            }
            // A medium with one impedance for the whole body is checked here; one that
            // varies (material regions) facet by facet at assembly.
            if material.impedances().is_some() {
                absorbing_impedances(material, name, None)?;
            }
        }
        Ok(())
    }

    /// The dashpots of the absorbing parts (Cartesian, unscaled), if any: each part
    /// resolved, checked (inertia, the medium's impedances, no facet of Γ_F, a free dof)
    /// and lumped on the pattern of `stiffness`.
    fn absorbing_parts(
        &self,
        mesh: &SimplexMesh<D>,
        material: &dyn Medium<D, C>,
        gamma_f: &BoundaryPart<D>,
        fixed: &[bool],
        stiffness: &SparseMatrix,
    ) -> Result<Option<AbsorbingBoundary>> {
        if self.absorbing.is_empty() {
            return Ok(None);
        }
        let mut resolved = Vec::with_capacity(self.absorbing.len());
        for a in &self.absorbing {
            let name = a.part.name();
            let part = a.part.resolve(mesh)?;
            let impedances = part
                .facets()
                .iter()
                .map(|&f| {
                    let cell = mesh.cell(mesh.boundary_facet_cell(f));
                    let centroid: [f64; D] = std::array::from_fn(|k| {
                        cell.iter().map(|&p| mesh.vertices()[p][k]).sum::<f64>() / (D + 1) as f64
                    });
                    absorbing_impedances(material, name, Some(&centroid))
                })
                .collect::<Result<Vec<[f64; 2]>>>()?;
            if let Some(f) = part
                .facets()
                .iter()
                .find(|f| gamma_f.facets().binary_search(f).is_ok())
            {
                return Err(part_error(
                    name,
                    format!(
                        "boundary facet {f} is also on the frictional boundary `{}`",
                        gamma_f.name()
                    ),
                ));
            }
            if part
                .nodes()
                .iter()
                .all(|&p| (0..C).all(|c| fixed[C * p + c]))
            {
                return Err(part_error(
                    name,
                    "every dof of its nodes is fixed (Dirichlet): the dashpots would do nothing",
                ));
            }
            resolved.push((part, impedances, a.velocity));
        }
        let parts: Vec<ResolvedPart<'_, D, C>> = resolved
            .iter()
            .map(|(part, impedances, velocity)| ResolvedPart {
                part,
                impedances,
                velocity: *velocity,
            })
            .collect();
        let (damping, far_field_force) = super::absorbing::assemble(mesh, &parts, stiffness)?;
        Ok(Some(AbsorbingBoundary {
            parts: self
                .absorbing
                .iter()
                .map(|a| a.part.name().to_owned())
                .collect(),
            damping,
            far_field_force,
        }))
    }

    /// The nodal frames of the slanted nodes of Γ_F (normal not along a coordinate axis),
    /// in increasing node order; checks corners and degenerate facets at every node.
    /// The [`fault_tangent`](Self::fault_tangent), checked: 3-D only, finite, non-zero.
    fn checked_fault_tangent(&self) -> Result<Option<[f64; D]>> {
        if let Some(t) = self.fault_tangent {
            if D != 3 {
                return Err(invalid(
                    "fault_tangent",
                    format!(
                        "{t:?} given in {D}-D: it orients the 3-D nodal frames only; in \
                         {D}-D the tangent is t = (-n_y, n_x), fixed by the normal (remove \
                         the call)"
                    ),
                ));
            }
            if t.iter().any(|c| !c.is_finite()) || t.iter().all(|&c| c == 0.0) {
                return Err(invalid(
                    "fault_tangent",
                    format!("{t:?} must be finite and non-zero"),
                ));
            }
        }
        Ok(self.fault_tangent)
    }

    fn fault_frames(
        &self,
        mesh: &SimplexMesh<D>,
        gamma_f: &BoundaryPart<D>,
        name: &str,
    ) -> Result<NodalFrames<D>> {
        let limit = self.max_kink_degrees;
        if !(0.0..=180.0).contains(&limit) {
            return Err(invalid(
                "max_fault_kink",
                format!("{limit} must be in [0, 180] degrees"),
            ));
        }
        self.checked_fault_tangent()?;
        let facets = gamma_f.facets();
        let mean = facets
            .iter()
            .map(|&f| mesh.boundary_facet_measure(f))
            .sum::<f64>()
            / facets.len() as f64;
        // Per node: the unit normals of its facets, and their area-weighted sum with the
        // total area (a fold: the sum cancels).
        let mut at_node: Vec<Vec<[f64; D]>> = vec![Vec::new(); mesh.num_vertices()];
        let mut resultant = vec![([0.0; D], 0.0); mesh.num_vertices()];
        for &f in facets {
            let a = mesh.boundary_facet_measure(f);
            let vs = mesh.boundary_facet(f);
            if !(a.is_finite() && a > DEGENERATE_FACET * mean) {
                return Err(Error::DegenerateFaultFacet {
                    part: name.to_owned(),
                    node: vs[0],
                    facet: f,
                    measure: a,
                });
            }
            let nf = mesh.boundary_facet_normal(f);
            for &v in vs {
                at_node[v].push(nf);
                let (sum, total) = &mut resultant[v];
                sum.iter_mut().zip(&nf).for_each(|(s, n)| *s += a * n);
                *total += a;
            }
        }
        for &p in gamma_f.nodes() {
            let ns = &at_node[p];
            let mut worst = 0.0f64;
            for (i, a) in ns.iter().enumerate() {
                for b in &ns[i + 1..] {
                    let dot: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
                    worst = worst.max(dot.clamp(-1.0, 1.0).acos().to_degrees());
                }
            }
            if worst > limit {
                return Err(Error::FaultCorner {
                    part: name.to_owned(),
                    node: p,
                    position: mesh.vertices()[p].to_vec(),
                    angle_degrees: worst,
                    limit_degrees: limit,
                });
            }
            let (sum, total) = &resultant[p];
            if sum.iter().map(|s| s * s).sum::<f64>().sqrt() <= FOLD * total {
                return Err(Error::FaultFoldsBack {
                    part: name.to_owned(),
                    node: p,
                    position: mesh.vertices()[p].to_vec(),
                });
            }
        }
        // Frames at the slanted nodes only (an axis-aligned node keeps the Cartesian basis,
        // whatever the tangent there): a fault tangent (nearly) normal at one of them is
        // an error naming it (rsf_fem::Error::TangentAlongNormal), not another tangent.
        let normals = gamma_f.normals(mesh)?;
        let mut slanted: Vec<(usize, [[f64; D]; D])> = gamma_f
            .nodes()
            .iter()
            .zip(&normals)
            .filter(|(_, n)| normal_axis(n).is_none())
            .map(|(&p, n)| {
                let q = rsf_fem::frame_from_normal(n, self.fault_tangent.as_ref());
                q.map(|q| (p, q))
                    .ok_or_else(|| rsf_fem::Error::TangentAlongNormal {
                        vertex: p,
                        position: mesh.vertices()[p].to_vec(),
                        normal: n.to_vec(),
                        direction: self.fault_tangent.map_or_else(Vec::new, |t| t.to_vec()),
                    })
            })
            .collect::<std::result::Result<_, _>>()?;
        slanted.sort_by_key(|&(p, _)| p);
        Ok(NodalFrames {
            nodes: slanted.iter().map(|&(p, _)| p).collect(),
            rotations: slanted.into_iter().map(|(_, q)| q).collect(),
        })
    }
}

/// `(A + Aᵀ)/2` on the pattern of `A` (structurally symmetric): `Rᵀ A R` of a symmetric `A`
/// is symmetric up to round-off, the solvers demand it exactly.
fn symmetrized(a: &SparseMatrix) -> Result<SparseMatrix> {
    let (cp, ri, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    let mut t = Vec::with_capacity(2 * val.len());
    for j in 0..a.ncols() {
        for k in cp[j]..cp[j + 1] {
            let h = 0.5 * val[k];
            t.push(faer::sparse::Triplet::new(ri[k], j, h));
            t.push(faer::sparse::Triplet::new(j, ri[k], h));
        }
    }
    SparseMatrix::try_new_from_triplets(a.nrows(), a.ncols(), &t)
        .map_err(|e| Error::Fem(rsf_fem::Error::Faer(format!("{e:?}"))))
}

/// The coordinate axis `c` with `|n_c| = 1` (within [`AXIS_TOLERANCE`]), if any.
fn normal_axis<const D: usize>(n: &[f64; D]) -> Option<usize> {
    (0..D).find(|&c| (n[c].abs() - 1.0).abs() <= AXIS_TOLERANCE)
}

/// The medium's impedances `(ρc_p, ρc_s)` for absorbing part `name`, at `x` (m) inside the
/// body or its single ones, finite and positive.
fn absorbing_impedances<const D: usize, const C: usize>(
    material: &dyn Medium<D, C>,
    name: &str,
    x: Option<&[f64; D]>,
) -> Result<[f64; 2]> {
    let at = x.map_or(String::new(), |x| format!(" at {x:?} m"));
    let impedances = match x {
        Some(x) => material.impedances_at(x),
        None => material.impedances(),
    }
    .ok_or_else(|| {
        part_error(
            name,
            format!("the medium gives no impedances{at} (Medium::impedances_at) for its dashpots"),
        )
    })?;
    if impedances.iter().any(|z| !(z.is_finite() && *z > 0.0)) {
        let density = x.map_or(material.density(), |x| material.density_at(x));
        return Err(part_error(
            name,
            format!(
                "the medium's impedances (ρc_p, ρc_s) = {impedances:?} Pa·s/m{at} must be \
                 finite and positive (density ρ = {density} kg/m³)"
            ),
        ));
    }
    Ok(impedances)
}
