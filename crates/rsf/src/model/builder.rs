//! Building a [`Model`] from a mesh, a material and named boundary parts.

use rsf_fem::{
    body_force_load, traction_load, Assembler, BoundaryPart, ConstrainedSystem, LinearElasticity,
    MeshHierarchy, SimplexMesh,
};

use super::fault::FrictionalBoundary;
use super::loading::{DirichletVelocity, TimeFunction};
use super::Model;
use crate::error::{invalid, Error, Result};

/// Isotropic linear elastic material (SI units; in 2D plane strain, per unit thickness).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Material {
    /// Young's modulus E (Pa), finite and > 0.
    pub youngs_modulus: f64,
    /// Poisson's ratio ν ∈ (−1, ½).
    pub poisson_ratio: f64,
    /// Density ρ (kg/m³; kg/m² per unit thickness in 2D), finite and > 0.
    pub density: f64,
}

impl Material {
    /// Young's modulus E (Pa), Poisson's ratio ν, density ρ (kg/m³; kg/m² in 2D).
    pub const fn new(youngs_modulus: f64, poisson_ratio: f64, density: f64) -> Self {
        Self {
            youngs_modulus,
            poisson_ratio,
            density,
        }
    }

    /// The elasticity tensor: [`LinearElasticity::isotropic`] (plane strain in 2D).
    ///
    /// # Errors
    /// [`rsf_fem::Error::InvalidYoungsModulus`], [`rsf_fem::Error::InvalidPoissonRatio`].
    pub fn elasticity(&self) -> Result<LinearElasticity> {
        Ok(LinearElasticity::isotropic(
            self.youngs_modulus,
            self.poisson_ratio,
        )?)
    }
}

/// A force density or traction as a function of position.
type VectorField<const D: usize> = Box<dyn Fn(&[f64; D]) -> [f64; D]>;

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
struct Dirichlet<const D: usize> {
    part: Part<D>,
    components: Vec<usize>,
    velocity: [f64; D],
}

/// Largest number of cells [`ModelBuilder::refined`] creates (the paper's slider at level 10
/// has 10 · 4¹⁰ ≈ 1.0e7 triangles).
pub const MAX_CELLS: usize = 50_000_000;

/// Tolerance on `|n_c| = 1` for a frictional normal along a coordinate axis.
const AXIS_TOLERANCE: f64 = 1e-9;

/// Builds a validated [`Model`] from a mesh (or a refinement hierarchy), a [`Material`],
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
/// Γ_F must have its outer normal along a coordinate axis at every node (e.g. the bottom
/// of a block): the normal velocity component is then that coordinate, fixed. Slanted or
/// curved frictional boundaries need nodal frames, which [`Model`] does not carry yet;
/// they are rejected with [`Error::BoundaryPart`] naming the part and node.
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
pub struct ModelBuilder<const D: usize> {
    hierarchy: MeshHierarchy<D>,
    material: Option<Material>,
    gravity: Option<[f64; D]>,
    body_force: Option<VectorField<D>>,
    dirichlet: Vec<Dirichlet<D>>,
    neumann: Vec<(Part<D>, VectorField<D>)>,
    frictional_boundary: Option<Part<D>>,
    loading: TimeFunction,
    with_mass: bool,
}

impl<const D: usize> ModelBuilder<D> {
    /// A model on one mesh (no hierarchy: the direct solver, or TNNMG as a smoother only).
    pub fn new(mesh: SimplexMesh<D>) -> Self {
        Self::from_hierarchy(MeshHierarchy::refine_uniformly(mesh, 0))
    }

    /// A model on the finest level of `hierarchy`, with its prolongations for TNNMG.
    pub fn from_hierarchy(hierarchy: MeshHierarchy<D>) -> Self {
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
        }
    }

    /// A model on `coarse` refined `levels` times uniformly (red refinement: `2^D`
    /// children per cell and level).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `levels` if the finest mesh would have more than
    /// [`MAX_CELLS`] cells; refinement errors of [`MeshHierarchy::try_refine_uniformly`].
    pub fn refined(coarse: SimplexMesh<D>, levels: usize) -> Result<Self> {
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
        Ok(Self::from_hierarchy(MeshHierarchy::try_refine_uniformly(
            coarse, levels,
        )?))
    }

    /// The finest mesh (where parts are selected).
    pub fn mesh(&self) -> &SimplexMesh<D> {
        self.hierarchy.finest()
    }

    /// The material (required).
    pub fn material(mut self, material: Material) -> Self {
        self.material = Some(material);
        self
    }

    /// Gravitational acceleration `g` (m/s²): body force density `ρ g`.
    pub fn gravity(mut self, g: [f64; D]) -> Self {
        self.gravity = Some(g);
        self
    }

    /// A body force density `f(x)` (N/m³; N/m² per unit thickness in 2D), added to gravity.
    pub fn body_force(mut self, f: impl Fn(&[f64; D]) -> [f64; D] + 'static) -> Self {
        self.body_force = Some(Box::new(f));
        self
    }

    /// A Dirichlet part whose nodes move with velocity `velocity · g(t)` (m/s; `g` the
    /// [`loading`](Self::loading) history), all components fixed. `[0.0; D]` clamps.
    pub fn dirichlet(self, part: impl Into<Part<D>>, velocity: [f64; D]) -> Self {
        self.dirichlet_components(part, &(0..D).collect::<Vec<_>>(), velocity)
    }

    /// A Dirichlet part fixing only the listed components (e.g. a roller: the normal
    /// component only); component `c` moves with `velocity[c] · g(t)`.
    pub fn dirichlet_components(
        mut self,
        part: impl Into<Part<D>>,
        components: &[usize],
        velocity: [f64; D],
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
        traction: impl Fn(&[f64; D]) -> [f64; D] + 'static,
    ) -> Self {
        self.neumann.push((part.into(), Box::new(traction)));
        self
    }

    /// The frictional boundary Γ_F (required), with bilateral contact: the normal
    /// velocity component of its nodes is fixed.
    pub fn frictional_boundary(mut self, part: impl Into<Part<D>>) -> Self {
        self.frictional_boundary = Some(part.into());
        self
    }

    /// The loading history `g(t)` scaling every Dirichlet velocity (default `g ≡ 1`).
    pub fn loading(mut self, history: TimeFunction) -> Self {
        self.loading = history;
        self
    }

    /// No mass matrix (quasistatic problems); the energy norm is then `K`.
    pub fn without_mass(mut self) -> Self {
        self.with_mass = false;
        self
    }

    /// Assembles and validates the model.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a missing material or frictional part, non-finite
    /// velocities or gravity, a component ≥ D, two Dirichlet parts prescribing different
    /// velocities to one dof; [`Error::BoundaryPart`] for a part that selects nothing, was
    /// built on another mesh, or (Γ_F) has a normal not along a coordinate axis;
    /// [`Error::Equilibrium`] if `K u₀ = F` is singular under the constraints; material
    /// and assembly errors ([`Error::Fem`]), e.g. a non-finite force or traction.
    pub fn build(self) -> Result<Model<D>> {
        let mesh = self.hierarchy.finest();
        let n = D * mesh.num_vertices();
        let material = self
            .material
            .ok_or_else(|| invalid("material", "not set"))?;
        let elasticity = material.elasticity()?;
        let fpart = self.frictional_boundary.as_ref().ok_or_else(|| {
            invalid(
                "frictional_boundary",
                "not set (ModelBuilder::frictional_boundary)",
            )
        })?;
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
            if d.components.is_empty() || d.components.iter().any(|&c| c >= D) {
                return Err(invalid(
                    "dirichlet",
                    format!(
                        "part `{name}`: components {:?} must be in 0..{D}",
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
                    let i = D * p + c;
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
        let normals = gamma_f.normals(mesh)?;
        for (&p, nrm) in gamma_f.nodes().iter().zip(&normals) {
            let c = normal_axis(nrm).ok_or_else(|| {
                part_error(
                    fpart.name(),
                    format!(
                        "the outer normal {nrm:?} at node {p} is not along a coordinate axis; \
                         slanted or curved frictional boundaries need nodal frames, which \
                         models do not support yet"
                    ),
                )
            })?;
            fixed[D * p + c] = true;
        }
        let (dofs, factors): (Vec<usize>, Vec<f64>) = velocity
            .iter()
            .enumerate()
            .filter_map(|(i, w)| w.filter(|w| *w != 0.0).map(|w| (i, w)))
            .unzip();

        // Matrices.
        let assembler = Assembler::new(mesh)?;
        let stiffness = assembler.stiffness(mesh, &elasticity)?;
        let (mass, energy_norm) = if self.with_mass {
            (
                Some(assembler.mass(mesh, material.density)?),
                assembler.energy(mesh, material.density, &elasticity)?,
            )
        } else {
            (None, stiffness.clone())
        };

        // Loads.
        let rho = material.density;
        let mut load = match (self.gravity, &self.body_force) {
            (None, None) => vec![0.0; n],
            (Some(g), None) => body_force_load(mesh, |_| g.map(|gc| rho * gc))?,
            (None, Some(f)) => body_force_load(mesh, f)?,
            (Some(g), Some(f)) => body_force_load(mesh, |x| {
                let mut v = f(x);
                for (vc, gc) in v.iter_mut().zip(g) {
                    *vc += rho * gc;
                }
                v
            })?,
        };
        for (part, traction) in &self.neumann {
            let t = traction_load(mesh, &part.resolve(mesh)?, traction)?;
            for (l, ti) in load.iter_mut().zip(t) {
                *l += ti;
            }
        }

        // Γ_F in increasing node order; `along` by coordinates (lexicographic).
        let weights = gamma_f.weights(mesh)?;
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
        let nodes_along: Vec<usize> = order.iter().map(|&k| gamma_f.nodes()[k]).collect();
        let weights_along: Vec<f64> = order.iter().map(|&k| weights[k]).collect();
        let frictional_boundary = FrictionalBoundary::new(&nodes_along, &weights_along)?;

        // Initial equilibrium.
        let mut u0 = vec![0.0; n];
        ConstrainedSystem::new(stiffness.as_ref(), &fixed)
            .and_then(|mut s| s.solve(&load, &mut u0))
            .map_err(|e| match e {
                rsf_fem::Error::NotPositiveDefinite { .. } => Error::Equilibrium(e),
                e => Error::Fem(e),
            })?;

        let prolongations = (1..self.hierarchy.num_levels())
            .map(|j| self.hierarchy.vector_prolongation(j).clone())
            .collect();
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
        };
        // Consistent by construction; a simulation built on it validates it (once).
        debug_assert!(model.validate().is_ok(), "{:?}", model.validate());
        Ok(model)
    }
}

/// The coordinate axis `c` with `|n_c| = 1` (within [`AXIS_TOLERANCE`]), if any.
fn normal_axis<const D: usize>(n: &[f64; D]) -> Option<usize> {
    (0..D).find(|&c| (n[c].abs() - 1.0).abs() <= AXIS_TOLERANCE)
}
