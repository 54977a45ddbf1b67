//! A prescribed change of a fault ODE's load in time, `h(t) f` on its slip unknowns: a
//! traction perturbation given as a function of position and time, as SEAS BP7's
//! nucleating stress bump `Δτ₀ G₁(r) G₂(t)` (docs/seas-bp7.md).

use std::sync::Arc;

use crate::error::{invalid, Result};

/// A change `h(t) f` of the load of a [`FaultOde`](super::FaultOde)'s slip unknowns
/// ([`FaultOde::with_load_change`](super::FaultOde::with_load_change)): the balance of
/// every node becomes `g(t) + h(t) f − S u_F = w (τ(V, α) + η V)`.
///
/// `f` is a force per slip unknown (N: the traction change at `h = 1`, Pa, times the
/// node's weight, m², in the unknown's own component — a fault alone's Cartesian free
/// axes, a fault inside the body's pair frame); `h` a dimensionless function of time
/// (s), finite for every `t ≥ 0`. It is physics, not state: a checkpoint holds none of
/// it, and a resumed run must be given the same change (the programs put it in their
/// fingerprint).
#[derive(Clone)]
pub struct LoadChange {
    /// `f` (N), one per slip unknown (the fault ODE's `condensed_dim`), finite.
    pub forces: Vec<f64>,
    /// `h(t)` (dimensionless).
    pub history: Arc<dyn Fn(f64) -> f64 + Send + Sync>,
    /// Times (s) where `h` is not smooth (a ramp's end): a step ends there rather than
    /// step over it.
    pub breakpoints: Vec<f64>,
}

impl std::fmt::Debug for LoadChange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LoadChange")
            .field("forces", &self.forces.len())
            .field("breakpoints", &self.breakpoints)
            .finish_non_exhaustive()
    }
}

/// A load change in the fault ODE's evaluations: the load without it, and the change.
pub(super) struct LoadChangeRates {
    /// `g₀` without the change.
    pub(super) base: Vec<f64>,
    pub(super) change: LoadChange,
}

impl LoadChangeRates {
    /// Checks `change` against `base` (the load `g₀`, one entry per slip unknown) at the
    /// time `t`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
    /// `load_change.forces` for another length or a non-finite force,
    /// `load_change.history` for a non-finite `h(t)`, `load_change.breakpoints` for a
    /// non-finite one.
    pub(super) fn new(base: Vec<f64>, mut change: LoadChange, t: f64) -> Result<Self> {
        if change.forces.len() != base.len() {
            return Err(invalid(
                "load_change.forces",
                format!(
                    "{} forces for {} slip unknowns",
                    change.forces.len(),
                    base.len()
                ),
            ));
        }
        if let Some(i) = change.forces.iter().position(|f| !f.is_finite()) {
            return Err(invalid(
                "load_change.forces",
                format!("force {i} is {}", change.forces[i]),
            ));
        }
        let h = (change.history)(t);
        if !h.is_finite() {
            return Err(invalid(
                "load_change.history",
                format!("h({t}) = {h} must be finite"),
            ));
        }
        if change.breakpoints.iter().any(|b| !b.is_finite()) {
            return Err(invalid(
                "load_change.breakpoints",
                "must be finite times (s)",
            ));
        }
        change.breakpoints.sort_by(f64::total_cmp);
        Ok(Self { base, change })
    }

    /// Adds `forces` to the load without the change (`FaultOde::with_load_added`).
    pub(super) fn add_to_base(&mut self, forces: &[f64]) {
        for (b, f) in self.base.iter_mut().zip(forces) {
            *b += f;
        }
    }

    /// `g₀ + h(t) f` into `g0`.
    pub(super) fn apply(&self, t: f64, g0: &mut [f64]) {
        let h = (self.change.history)(t);
        for ((g, b), f) in g0.iter_mut().zip(&self.base).zip(&self.change.forces) {
            *g = b + h * f;
        }
    }

    /// The first breakpoint after `t`, if any.
    pub(super) fn next_breakpoint(&self, t: f64) -> Option<f64> {
        self.change.breakpoints.iter().copied().find(|&b| b > t)
    }
}
