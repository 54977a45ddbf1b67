//! What a simulation solves: the model and the laws on its frictional boundary
//! (docs/design.md, "Problem, method, state").

use crate::normal_stress::NormalStress;
use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;

use crate::model::Model;

/// The problem of a simulation: the discrete [`Model`], per frictional node (in
/// `model.frictional_boundary.nodes` order) a friction law `L` and a state law `S` (none if no
/// friction law uses the state), and the radiation damping η on Γ_F — physics, whatever
/// the method. Immutable once the simulation is built.
#[derive(Debug, Clone)]
pub struct Problem<const D: usize, L, S, const C: usize = D> {
    model: Model<D, C>,
    friction_laws: Vec<L>,
    state_laws: Vec<S>,
    uses_state: bool,
    radiation_damping: Vec<f64>,
    normal_stress: NormalStress,
    /// The pore pressure at the frictional nodes, if any.
    pore_pressure: Option<std::sync::Arc<dyn crate::pore_pressure::NodePressures>>,
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, const C: usize> Problem<D, L, S, C> {
    /// The parts, checked by the simulation builder (`checks.rs`) before this is called.
    pub(crate) fn new(
        model: Model<D, C>,
        friction_laws: Vec<L>,
        state_laws: Vec<S>,
        radiation_damping: Vec<f64>,
    ) -> Self {
        let uses_state = friction_laws.iter().any(FrictionLaw::uses_state);
        Self {
            model,
            friction_laws,
            state_laws,
            uses_state,
            radiation_damping,
            normal_stress: NormalStress::Fixed,
            pore_pressure: None,
        }
    }

    /// The problem with the pore pressure `field` lowering the laws' normal stress
    /// (none: unchanged).
    ///
    /// # Errors
    /// As [`PressureAtNodes::new`](crate::pore_pressure::PressureAtNodes::new).
    pub(crate) fn with_pore_pressure(
        mut self,
        field: Option<std::sync::Arc<dyn crate::pore_pressure::PorePressure<D>>>,
    ) -> crate::Result<Self> {
        if let Some(field) = field {
            let points = self
                .model
                .frictional_boundary
                .nodes
                .iter()
                .map(|&p| self.model.vertices[p])
                .collect();
            let at =
                crate::pore_pressure::PressureAtNodes::new(field, points, &self.friction_laws)?;
            self.pore_pressure = Some(std::sync::Arc::new(at));
        }
        Ok(self)
    }

    /// The pore pressure at the frictional nodes, if any.
    pub(crate) fn pore_pressure(
        &self,
    ) -> Option<&std::sync::Arc<dyn crate::pore_pressure::NodePressures>> {
        self.pore_pressure.as_ref()
    }

    /// Whether the problem has a pore pressure
    /// ([`SimulationBuilder::pore_pressure`](crate::SimulationBuilder::pore_pressure)).
    pub fn has_pore_pressure(&self) -> bool {
        self.pore_pressure.is_some()
    }

    /// The problem with the fault's normal stress found as `choice` says.
    pub(crate) fn with_normal_stress(mut self, choice: NormalStress) -> Self {
        self.normal_stress = choice;
        self
    }

    /// How the fault's normal stress is found
    /// ([`SimulationBuilder::normal_stress`](crate::SimulationBuilder::normal_stress)).
    pub fn normal_stress(&self) -> NormalStress {
        self.normal_stress
    }

    /// The radiation damping η of every frictional node (Pa·s/m, in
    /// `model.frictional_boundary.nodes` order; 0 for none): the shear traction `−η V` of
    /// waves radiated from the fault in a quasi-dynamic model (Rice 1993; docs/math.md
    /// §11), per unit fault area — `μ/(2c_s)` of the material at the node for the usual
    /// choice.
    pub fn radiation_damping(&self) -> &[f64] {
        &self.radiation_damping
    }

    /// The model.
    pub fn model(&self) -> &Model<D, C> {
        &self.model
    }

    /// The friction law of each frictional node.
    pub fn friction_laws(&self) -> &[L] {
        &self.friction_laws
    }

    /// The friction laws as the tractions observers see.
    pub(crate) fn fault_tractions(&self) -> &dyn crate::observe::FaultTractions {
        &self.friction_laws
    }

    /// The state law of each frictional node (empty if no friction law uses the state).
    pub fn state_laws(&self) -> &[S] {
        &self.state_laws
    }

    /// Whether any friction law depends on the state (else the state never changes and
    /// no state update is computed).
    pub fn uses_state(&self) -> bool {
        self.uses_state
    }
}

/// A placeholder state law for friction laws without state (plain Tresca): α never changes
/// and no state update is ever computed.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NoState;

impl StateLaw for NoState {
    fn dpsi_dalpha(&self, _alpha: f64, _v: f64) -> f64 {
        0.0
    }
    fn update(&self, alpha_prev: f64, _v: f64, _tau: f64) -> rsf_state::Result<f64> {
        Ok(alpha_prev)
    }
}
