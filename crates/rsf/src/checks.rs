//! Consistency checks of a simulation's parts, run when it is constructed (before any
//! assembly): what would otherwise run silently with wrong physics is a typed error.

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;

use crate::error::{invalid, Error, Result};
use crate::model::Model;

/// Checks τ, the model ([`Model::validate`], including the fixed normal on Γ_F), the
/// number of laws, that each node's friction law and state law agree on the state
/// variable, and the monotonicity probe of each state law ([`StateLaw::check_monotone`]).
/// State laws are only checked at nodes whose friction law uses the state.
///
/// # Errors
/// [`Error::InvalidParameter`] (`tau`, `friction_laws`, `state_laws`), the errors of
/// [`Model::validate`], [`Error::StateVariableMismatch`], [`Error::StateLaw`].
pub(crate) fn check_construction<const D: usize, L: FrictionLaw, S: StateLaw>(
    model: &Model<D>,
    friction_laws: &[L],
    state_laws: &[S],
    tau: f64,
) -> Result<()> {
    if !(tau.is_finite() && tau > 0.0) {
        return Err(invalid(
            "tau",
            format!("τ = {tau} s must be finite and > 0"),
        ));
    }
    model.validate()?;
    let nf = model.frictional.len();
    if friction_laws.len() != nf {
        return Err(invalid(
            "friction_laws",
            format!("{} laws for {nf} frictional nodes", friction_laws.len()),
        ));
    }
    if !state_laws.is_empty() && state_laws.len() != nf {
        return Err(invalid(
            "state_laws",
            format!("{} laws for {nf} frictional nodes", state_laws.len()),
        ));
    }
    for (k, (f, s)) in friction_laws.iter().zip(state_laws).enumerate() {
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
    }
    Ok(())
}
