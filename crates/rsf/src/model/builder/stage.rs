//! The stages of [`ModelBuilder::build`](crate::ModelBuilder::build) as a caller sees them:
//! [`BuildStage`], reported to the observer of
//! [`ModelBuilder::on_stage`](crate::ModelBuilder::on_stage) as each stage ends (to measure
//! a stage's time or memory: docs/three-d.md, "The build's memory").

use std::fmt;

/// A stage of [`ModelBuilder::build`](crate::ModelBuilder::build), in the order the
/// builder runs them (its docs, and `model/builder/stages/`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BuildStage {
    /// The mesh the model lives on, cut open along a fault inside the body.
    Domain,
    /// The constraints: Dirichlet parts, Γ_F, its frames, bilateral contact.
    Constraints,
    /// `K`, `M`, the energy norm and the dashpots, Cartesian.
    Matrices,
    /// The load: body forces and tractions.
    Load,
    /// An antisymmetric fault's scaling and an internal fault's shared jump and
    /// prescribed pairs.
    Pairs,
    /// The change of variables (nodal frames or mean and jump).
    Variables,
    /// Γ_F in order with its lumped weights.
    FaultOrder,
    /// The hierarchy's prolongations.
    Prolongations,
    /// The initial equilibrium `K u₀ = F` (or `u₀ = 0` without it,
    /// [`ModelBuilder::without_initial_equilibrium`](crate::ModelBuilder::without_initial_equilibrium)).
    Equilibrium,
}

impl BuildStage {
    /// Every stage, in the order the builder runs them.
    pub const ALL: [BuildStage; 9] = [
        BuildStage::Domain,
        BuildStage::Constraints,
        BuildStage::Matrices,
        BuildStage::Load,
        BuildStage::Pairs,
        BuildStage::Variables,
        BuildStage::FaultOrder,
        BuildStage::Prolongations,
        BuildStage::Equilibrium,
    ];

    /// A short lower-case name (`"matrices"`, `"fault order"`, …).
    pub fn name(self) -> &'static str {
        match self {
            BuildStage::Domain => "domain",
            BuildStage::Constraints => "constraints",
            BuildStage::Matrices => "matrices",
            BuildStage::Load => "load",
            BuildStage::Pairs => "pairs",
            BuildStage::Variables => "variables",
            BuildStage::FaultOrder => "fault order",
            BuildStage::Prolongations => "prolongations",
            BuildStage::Equilibrium => "equilibrium",
        }
    }
}

impl fmt::Display for BuildStage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The observer of [`ModelBuilder::on_stage`](crate::ModelBuilder::on_stage).
pub(crate) type StageObserver = Box<dyn FnMut(BuildStage)>;
