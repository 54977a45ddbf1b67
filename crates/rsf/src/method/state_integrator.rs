//! How a time step advances the state on Γ_F (docs/friction-state.md, "Exact update at
//! constant slip rate").

use crate::error::{invalid, Result};
use rsf_state::StateLaw;

/// The update of the state `α` over one step, given the slip rate `V_n` of the step's
/// fixed point iterate.
///
/// Both are first order in τ for a slip rate that changes within the step; they differ
/// where it does not: in stick and steady creep [`ConstantSlipRate`](Self::ConstantSlipRate)
/// is exact (the aging law's healing `θ(t) = θ₀ + t`, for instance), backward Euler in
/// `α = ln θ` is not (its local error is `τ²/2 · |α̈|`, `α̈ = −1/θ²` in stick).
///
/// Names (`name`, `FromStr`, serde, clap): `backward-euler`, `constant-slip-rate`.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum StateIntegrator {
    /// Backward Euler, the paper's update (3.5): `α_n = prox_{τψ(·, V_n)}(α_{n−1})`
    /// ([`StateLaw::update`]). The default.
    #[default]
    BackwardEuler,
    /// The exact solution of the state equation over the step with the slip rate held at
    /// `V_n` ([`StateLaw::constant_rate_update`]; beyond the paper). Needs a law with that
    /// closed form (the built-in aging, slip and discontinuous laws).
    ConstantSlipRate,
}

rsf_numeric::display_and_parse_by_name!(
    StateIntegrator,
    "state integrator",
    crate::Error,
    [
        StateIntegrator::BackwardEuler,
        StateIntegrator::ConstantSlipRate
    ]
);

impl StateIntegrator {
    /// Name as in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::BackwardEuler => "backward-euler",
            Self::ConstantSlipRate => "constant-slip-rate",
        }
    }

    /// Checks that `law` supports this update.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `state_integrator` if `ConstantSlipRate` is asked of
    /// a law without [`StateLaw::constant_rate_update`].
    pub(crate) fn check<S: StateLaw>(self, law: &S) -> Result<()> {
        if self == Self::ConstantSlipRate && law.constant_rate_update(0.0, 0.0, 0.0).is_none() {
            return Err(invalid(
                "state_integrator",
                "constant-slip-rate needs a state law with a closed-form update at constant \
                 slip rate (StateLaw::constant_rate_update)",
            ));
        }
        Ok(())
    }

    /// `α_n` from `α_{n−1}` with slip rate `v` (m/s) over `tau` (s).
    pub(crate) fn update<S: StateLaw>(
        self,
        law: &S,
        alpha_prev: f64,
        v: f64,
        tau: f64,
    ) -> rsf_state::Result<f64> {
        match self {
            Self::BackwardEuler => law.update(alpha_prev, v, tau),
            // Checked at construction; a law that has the update only for some inputs gets
            // an error, not a panic.
            Self::ConstantSlipRate => law.constant_rate_update(alpha_prev, v, tau).unwrap_or(Err(
                rsf_state::Error::InvalidInput {
                    name: "v",
                    value: v,
                    requirement: "a slip rate for which the law's constant_rate_update is Some",
                },
            )),
        }
    }

    /// Error estimate and local extrapolation of the accepted update `a1 = S(a0, v1)` of a
    /// step from `(a0, v0)` (docs/math.md §9): `(e, extrapolated)`, `extrapolated` `None` if
    /// it is not finite or the law lacks what it needs. Backward Euler: `e = (τ/2)|Δα̇|`,
    /// extrapolated towards the trapezoidal rule (damped by `1/(1 + τ ∂²ψ/∂α²)`). At constant
    /// slip rate: the update is exact up to the change of `V` within the step, whose effect
    /// is estimated by the update with the step's other end, `ŝ = S(a0, v0)`:
    /// `e = |a1 − ŝ|/2`, extrapolated to the mean `(a1 + ŝ)/2` (slip rate averaged over the
    /// step, second order for a slip rate linear in time).
    pub(crate) fn local_error<S: StateLaw>(
        self,
        law: &S,
        (a0, v0): (f64, f64),
        (a1, v1): (f64, f64),
        tau: f64,
    ) -> (f64, Option<f64>) {
        match self {
            Self::BackwardEuler => {
                let rate_change = law.dpsi_dalpha(a1, v1) - law.dpsi_dalpha(a0, v0);
                if !rate_change.is_finite() {
                    return ((a1 - a0).abs(), None);
                }
                let corrected = law.d2psi_dalpha2(a1, v1).and_then(|curvature| {
                    let c = 0.5 * tau * rate_change / (1.0 + tau * curvature.max(0.0));
                    c.is_finite().then_some(a1 + c)
                });
                (0.5 * tau * rate_change.abs(), corrected)
            }
            Self::ConstantSlipRate => match self.update(law, a0, v0, tau) {
                Ok(other) => (0.5 * (a1 - other).abs(), Some(0.5 * (a1 + other))),
                Err(_) => ((a1 - a0).abs(), None),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsf_state::{Aging, Slip};

    /// At a constant slip rate the exact update has no error to estimate (healing in stick,
    /// a step towards steady state at any `V`); backward Euler's estimate is that of its
    /// truncation error, `(τ/2)|Δα̇| ≈ τ²/2 · |α̈|`.
    #[test]
    fn local_error_vanishes_at_constant_slip_rate_only_for_the_exact_update() {
        let (l, tau) = (1e-5, 1e-3);
        let aging = Aging::new(l).unwrap();
        for v in [0.0, 1e-9, 1e-6, 1e-3] {
            let a0 = -10.0;
            let csr = StateIntegrator::ConstantSlipRate;
            let a1 = csr.update(&aging, a0, v, tau).unwrap();
            let (e, extrapolated) = csr.local_error(&aging, (a0, v), (a1, v), tau);
            assert_eq!(e, 0.0, "V = {v}");
            assert_eq!(extrapolated, Some(a1));
            let be = StateIntegrator::BackwardEuler;
            let b1 = be.update(&aging, a0, v, tau).unwrap();
            let (e_be, _) = be.local_error(&aging, (a0, v), (b1, v), tau);
            assert!(e_be > 0.1, "V = {v}: {e_be}");
        }
        // A slip-rate change within the step is what the exact update's estimate sees:
        // half the difference of the updates with the two ends' slip rates.
        let slip = Slip::new(l).unwrap();
        let csr = StateIntegrator::ConstantSlipRate;
        let (a0, v0, v1) = (3.0, 1e-6, 1e-4);
        let a1 = csr.update(&slip, a0, v1, tau).unwrap();
        let other = csr.update(&slip, a0, v0, tau).unwrap();
        let (e, extrapolated) = csr.local_error(&slip, (a0, v0), (a1, v1), tau);
        assert_eq!(e, 0.5 * (a1 - other).abs());
        assert!(e > 0.0);
        assert_eq!(extrapolated, Some(0.5 * (a1 + other)));
    }
}
