//! The stages of [`ModelBuilder::build`](crate::ModelBuilder::build), in the order it runs
//! them, each a function of typed inputs to a typed output (none of them sees the builder):
//!
//! 1. [`domain`]: the mesh the model lives on — the hierarchy's finest level, or a copy cut
//!    open along a fault inside the body ([`Domain`](domain::Domain) and the
//!    [`InternalFault`](crate::model::InternalFault)).
//! 2. [`inputs`]: the settings that need no mesh data — the medium, the slip factor, which
//!    part is Γ_F, the loading history, gravity ([`Inputs`](inputs::Inputs)).
//! 3. [`constraints`]: Dirichlet parts resolved, Γ_F resolved, the nodal frames of its
//!    slanted nodes ([`frames`]), bilateral contact
//!    ([`Constraints`](constraints::Constraints): fixed dofs, prescribed velocities).
//! 4. [`matrices`]: `K`, `M`, the energy norm and the dashpots of absorbing parts
//!    ([`absorbing`]), Cartesian ([`Matrices`](matrices::Matrices)).
//! 5. [`loads`]: body forces and tractions, Cartesian; with the matrices a
//!    [`System`](matrices::System).
//! 6. [`scaling`]: an antisymmetric fault's unknown `s·u` (`K/s²`, `F/s`, …).
//! 7. [`pairs`]: an internal fault's jump shared by the sides' stiffness and its prescribed
//!    pairs (both sides clamped, or creeping).
//! 8. [`variables`]: the change of variables — the system in the model's unknowns through
//!    one [`DofTransform`](rsf_fem::DofTransform) (nodal frames `RᵀAR`, or mean and jump
//!    `TᵀAT`), the Dirichlet data in them.
//! 9. [`fault_order`]: Γ_F's nodes in order with their lumped weights
//!    ([`FrictionalBoundary`](crate::model::FrictionalBoundary)).
//! 10. [`prolongations`]: the hierarchy's prolongations, the finest onto the model's
//!     unknowns (`T⁻¹P`).
//!
//! Then the initial equilibrium `K u₀ = F` (`model/equilibrium.rs`). The order is the
//! order of the checks: a builder with several mistakes reports the first stage's.

pub(crate) mod absorbing;
pub(crate) mod constraints;
pub(crate) mod domain;
pub(crate) mod fault_order;
pub(crate) mod frames;
pub(crate) mod inputs;
pub(crate) mod loads;
pub(crate) mod matrices;
pub(crate) mod pairs;
pub(crate) mod prolongations;
pub(crate) mod scaling;
pub(crate) mod variables;

#[cfg(test)]
mod tests;
