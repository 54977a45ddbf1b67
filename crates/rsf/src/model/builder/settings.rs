//! What a [`ModelBuilder`](crate::ModelBuilder) has been told, grouped by concern: the body
//! ([`Body`]: medium, forces, inertia), its boundary conditions ([`Boundary`]) and its fault
//! ([`Faults`]). The setters fill these (`material.rs`, `boundary.rs`, `faults.rs`); the
//! stages of [`build`](crate::ModelBuilder::build) read them (`stages/`).

use super::part::Part;
use crate::model::creep::{CreepField, SlipField};
use crate::model::equilibrium::StaticOptions;
use crate::model::internal::{FaultCut, NetworkSplit};
use crate::model::loading::TimeFunction;
use crate::model::medium::Medium;

/// A force density or traction (`C` components) as a function of position (m).
pub(crate) type VectorField<const D: usize, const C: usize> = Box<dyn Fn(&[f64; D]) -> [f64; C]>;

/// Default of [`ModelBuilder::max_fault_kink`](crate::ModelBuilder::max_fault_kink): the
/// largest angle (degrees) between the outer normals of two frictional facets meeting at a
/// node.
pub const DEFAULT_MAX_FAULT_KINK_DEGREES: f64 = 30.0;

/// The body: what it is made of and what acts on it inside.
pub(crate) struct Body<const D: usize, const C: usize> {
    /// The medium (required at `build`).
    pub material: Option<Box<dyn Medium<D, C>>>,
    /// Gravitational acceleration `g` (m/s²): body force `ρ g`.
    pub gravity: Option<[f64; D]>,
    /// A body force density (N/m³; N/m² per unit thickness in 2-D), added to gravity.
    pub body_force: Option<VectorField<D, C>>,
    /// Assemble the mass matrix (default); `false` for quasistatic problems.
    pub with_mass: bool,
    /// Solve the initial equilibrium `K u₀ = F` (default); `false`: `u₀ = 0`.
    pub equilibrium: bool,
    /// How the initial equilibrium is solved (default [`StaticOptions::default`]).
    pub equilibrium_solver: StaticOptions,
}

/// A Dirichlet part: the listed components of its nodes move with `velocity · g(t)`.
pub(crate) struct Dirichlet<const D: usize, const C: usize> {
    /// The facets whose nodes are constrained.
    pub part: Part<D>,
    /// The constrained components (each `< C`).
    pub components: Vec<usize>,
    /// The velocity factors `w` (m/s): component `c` moves with `w[c] · g(t)`.
    pub velocity: [f64; C],
    /// The displacement (m) the part's nodes are held at in the initial equilibrium, by
    /// position ([`dirichlet_displacement`](crate::ModelBuilder::dirichlet_displacement));
    /// `None`: 0.
    pub displacement: Option<VectorField<D, C>>,
}

/// An absorbing part: dashpots against the motion relative to `velocity · g(t)`.
pub(crate) struct Absorbing<const D: usize, const C: usize> {
    /// The facets carrying dashpots.
    pub part: Part<D>,
    /// The far field's velocity factors (m/s).
    pub velocity: [f64; C],
}

/// The boundary conditions other than the fault's, and the loading history.
pub(crate) struct Boundary<const D: usize, const C: usize> {
    /// Dirichlet parts, in the order given (a later part may not contradict an earlier one).
    pub dirichlet: Vec<Dirichlet<D, C>>,
    /// Neumann parts with their traction (Pa; N/m per unit thickness in 2-D).
    pub neumann: Vec<(Part<D>, VectorField<D, C>)>,
    /// Absorbing parts.
    pub absorbing: Vec<Absorbing<D, C>>,
    /// The loading history `g(t)` of every prescribed velocity.
    pub loading: TimeFunction,
}

/// The fault: on the boundary (Γ_F, bilateral contact, nodal frames where slanted) or
/// inside the body (split, mean and jump).
pub(crate) struct Faults<const D: usize> {
    /// The frictional boundary Γ_F (a fault on the boundary).
    pub frictional_boundary: Option<Part<D>>,
    /// The antisymmetry factor `s` (slip `s·u`; 1 for a body on a rigid surface).
    pub slip_factor: f64,
    /// The largest kink (degrees) between facets of Γ_F at a node.
    pub max_kink_degrees: f64,
    /// The reference direction of the first tangent of 3-D frames.
    pub tangent: Option<[f64; D]>,
    /// The faults inside the body, in the order given (a network if several).
    pub internal: Vec<FaultCut<D>>,
    /// How to cut the hierarchy open along them (set with the first).
    pub network_split: Option<NetworkSplit<D>>,
    /// The creeping section of a fault inside the body: its slip rate (m/s, times `g(t)`)
    /// by a pair's position, `None` where the pair slips by friction.
    pub creep: Option<CreepField<D>>,
    /// The prescribed slip (m) of a fault inside the body's pairs by position, `None` where
    /// a pair's slip is not prescribed
    /// ([`internal_slip_at`](crate::ModelBuilder::internal_slip_at)).
    pub slip: Option<SlipField<D>>,
}

impl<const D: usize, const C: usize> Default for Body<D, C> {
    fn default() -> Self {
        Self {
            material: None,
            gravity: None,
            body_force: None,
            with_mass: true,
            equilibrium: true,
            equilibrium_solver: StaticOptions::default(),
        }
    }
}

impl<const D: usize, const C: usize> Default for Boundary<D, C> {
    fn default() -> Self {
        Self {
            dirichlet: Vec::new(),
            neumann: Vec::new(),
            absorbing: Vec::new(),
            loading: TimeFunction::Constant(1.0),
        }
    }
}

impl<const D: usize> Default for Faults<D> {
    fn default() -> Self {
        Self {
            frictional_boundary: None,
            slip_factor: 1.0,
            max_kink_degrees: DEFAULT_MAX_FAULT_KINK_DEGREES,
            tangent: None,
            internal: Vec::new(),
            network_split: None,
            creep: None,
            slip: None,
        }
    }
}
