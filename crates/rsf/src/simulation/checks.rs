//! The checks of a simulation's parts, all in one place and each run once: by
//! [`SimulationBuilder::build`](crate::SimulationBuilder::build) before anything is
//! assembled, and (for τ) by [`Simulation::set_time_step`](crate::Simulation::set_time_step).
//! What would otherwise run silently with wrong physics is a typed error naming the part
//! as the builder calls it.

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::VelocityIntegrator;

use crate::error::{invalid, Error, Result};
use crate::method::MethodOptions;
use crate::model::Model;

/// Checks the time step τ (s).
///
/// # Errors
/// [`Error::InvalidParameter`] named `tau` unless τ is finite and > 0.
pub(crate) fn time_step(tau: f64) -> Result<()> {
    if tau.is_finite() && tau > 0.0 {
        Ok(())
    } else {
        Err(invalid(
            "tau",
            format!("τ = {tau} s must be finite and > 0"),
        ))
    }
}

/// The parts of a simulation as the builder collected them.
pub(crate) struct Parts<'a, const D: usize, L, S, I, const C: usize> {
    pub model: &'a Model<D, C>,
    pub friction_laws: &'a [L],
    pub state_laws: &'a [S],
    pub alpha0: Option<&'a [f64]>,
    pub v0: Option<&'a [f64]>,
    pub tau: Option<f64>,
    pub method: &'a MethodOptions<I>,
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    Parts<'_, D, L, S, I, C>
{
    /// Checks every part and returns τ: τ set and valid (named `tau`), the model
    /// ([`Model::validate`], including the fixed normal on Γ_F; at least one frictional
    /// node, [`Error::NoFrictionalNode`]), a mass matrix for an
    /// integrator with inertia, a finite initial velocity, the initial state (set and finite where the friction uses
    /// the state), a state law where the friction uses the state, per node that friction
    /// law and state law agree on the state variable and the state law's monotonicity
    /// probe ([`StateLaw::check_monotone`]), the fixed point options, the step control and
    /// the state integrator's needs.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] (`tau`, `mass`, `initial_velocity`, `initial_state`, `state_law`,
    /// `fixed_point.*`, `state_integrator`), the errors of [`Model::validate`],
    /// [`Error::StateVariableMismatch`], [`Error::StateLaw`], the step control's
    /// [`Error::Time`].
    pub fn check(&self) -> Result<f64> {
        let tau = self
            .tau
            .ok_or_else(|| invalid("tau", "not set (SimulationBuilder::time_step)"))?;
        time_step(tau)?;
        let model = self.model;
        model.validate()?;
        if model.frictional_boundary.is_empty() {
            return Err(Error::NoFrictionalNode {
                what: "a simulation (SimulationBuilder::build, build_fault_ode)",
            });
        }
        let method = self.method;
        if method.integrator.uses_mass() && model.mass.is_none() {
            return Err(invalid(
                "mass",
                format!("{} needs the mass matrix", method.integrator.name()),
            ));
        }
        if let Some(v0) = self.v0 {
            if v0.iter().any(|v| !v.is_finite()) {
                return Err(invalid("initial_velocity", "must be finite at every node"));
            }
        }
        let uses_state = self.friction_laws.iter().any(FrictionLaw::uses_state);
        if let Some(alpha0) = self.alpha0 {
            if alpha0.iter().any(|a| !a.is_finite()) {
                return Err(invalid("initial_state", "must be finite at every node"));
            }
        } else if uses_state {
            return Err(invalid(
                "initial_state",
                "not set, and the friction law uses the state",
            ));
        }
        if uses_state && self.state_laws.is_empty() {
            return Err(invalid(
                "state_law",
                "not set, and the friction law uses the state",
            ));
        }
        for (k, (f, s)) in self.friction_laws.iter().zip(self.state_laws).enumerate() {
            if !f.uses_state() {
                continue;
            }
            if f.state_variable() != s.state_variable() {
                return Err(Error::StateVariableMismatch {
                    node: k,
                    friction: f.state_variable(),
                    state: s.state_variable(),
                });
            }
            s.check_monotone()
                .map_err(|source| Error::StateLaw { node: k, source })?;
            method.state_integrator.check(s)?;
        }
        method.fixed_point.validate()?;
        if let Some(control) = &method.step_control {
            control.start(tau)?;
        }
        Ok(tau)
    }
}
