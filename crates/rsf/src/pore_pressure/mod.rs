//! Pore pressure on a fault (docs/seas-bp6.md): a pressure change `p(x, t)` (Pa) that
//! lowers the effective normal stress of the friction laws to `σ̄_n − p` wherever `σ̄_n`
//! is used — in the fault ODE ([`FaultOde`](crate::FaultOde), at every Runge–Kutta stage,
//! so that the step-size control sees its time dependence) and in the implicit
//! [`Simulation`](crate::Simulation) (at the end of each step) — on any model, 2-D or
//! 3-D, with a fixed normal stress or one that changes with slip.
//!
//! A field is a [`PorePressure`]: the closed form of fluid injected at a point of a
//! fault with flow along it only ([`InjectionPressure`], Lambert & Dunham's SEAS BP6
//! description, eqs. 26–27), the same diffusion solved numerically on a grid along the
//! fault with no-flux ends ([`FaultDiffusion`]), the diffusion in two dimensions over a
//! rectangle of a 3-D model's fault plane (SEAS BP8: [`SurfaceDiffusion`], from a
//! Gaussian source or a Peaceman well, and the unbounded closed forms
//! [`SurfaceInjectionPressure`]; docs/pore-pressure.md), or a user's own (any type
//! implementing the trait, or a closure through [`PressureFn`]). Give it to
//! [`SimulationBuilder::pore_pressure`](crate::SimulationBuilder::pore_pressure).
//!
//! Where `σ̄_n − p ≤ 0` (the fluid would open the fault) a Runge–Kutta stage is outside
//! the problem's domain and the step is retried smaller; at an accepted time, or in the
//! implicit scheme, it is
//! [`Error::NormalStressNotPositive`](crate::Error::NormalStressNotPositive) naming the
//! node and the time — unless the field holds the effective stress above a
//! floor ([`EffectiveStressFloor`], SEAS BP8-PW's policy).

mod closed_form;
mod diffusion;
mod exp_integral;
mod floor;
mod surface;
mod surface_closed_form;
mod surface_diffusion;
mod surface_well;

pub use closed_form::{Injection, InjectionPressure};
pub use diffusion::{FaultDiffusion, MAX_DIFFUSION_CELLS};
pub use floor::EffectiveStressFloor;
pub use surface::{
    FaultPlane, FaultZone, PeacemanWell, SurfaceGrid, SurfaceInjection, SurfaceSource,
};
pub use surface_closed_form::SurfaceInjectionPressure;
pub use surface_diffusion::{SurfaceDiffusion, MAX_SURFACE_CELLS, MAX_WELL_MODES};

use crate::error::{check_normal_stress, Result};
use rsf_friction::{ConvexPotential, FrictionLaw};

/// A pore-pressure change `p(x, t)` on a fault (Pa, positive: it lowers the effective
/// normal stress `σ̄_n − p`), `x` a point of the fault (m, the model's coordinates), `t`
/// the time (s). Implementations are deterministic (the same `x`, `t` give the same
/// bits), finite for finite inputs, and hold no state that a run changes: a checkpoint
/// need not save them.
pub trait PorePressure<const D: usize>: Send + Sync + std::fmt::Debug {
    /// `p(x, t)` (Pa).
    fn pressure(&self, x: &[f64; D], t: f64) -> f64;

    /// `p(xᵢ, t)` at every point into `out` (same length). Default: one
    /// [`pressure`](Self::pressure) per point; a field with shared work per time (a
    /// numerical solution) overrides it. Called at every evaluation: allocate nothing.
    fn pressures(&self, t: f64, points: &[[f64; D]], out: &mut [f64]) {
        for (o, x) in out.iter_mut().zip(points) {
            *o = self.pressure(x, t);
        }
    }

    /// The Darcy velocity `q = −(k/η_f) ∂p/∂s` along the fault at `(x, t)` (m/s; `s` the
    /// fault's coordinate), if the field knows it (for output files). Default `None`.
    fn darcy_velocity(&self, x: &[f64; D], t: f64) -> Option<f64> {
        let _ = (x, t);
        None
    }

    /// The Darcy velocity `q = −(k/η_f) ∇p` at `(x, t)` as a vector of the model's
    /// coordinates (m/s, tangent to the fault), if the field knows it (for output files:
    /// SEAS BP8's `darcy_vel_2`, `darcy_vel_3`). Default `None`.
    fn darcy_velocity_vector(&self, x: &[f64; D], t: f64) -> Option<[f64; D]> {
        let _ = (x, t);
        None
    }

    /// Times (s, increasing) where `p` is not smooth in time (the start and end of an
    /// injection): the fault ODE ends a step there rather than step over them. Default
    /// none.
    fn breakpoints(&self) -> Vec<f64> {
        Vec::new()
    }
}

/// A field shared with its readers (a run and its output files).
impl<const D: usize, P: PorePressure<D> + ?Sized> PorePressure<D> for std::sync::Arc<P> {
    fn pressure(&self, x: &[f64; D], t: f64) -> f64 {
        (**self).pressure(x, t)
    }
    fn pressures(&self, t: f64, points: &[[f64; D]], out: &mut [f64]) {
        (**self).pressures(t, points, out);
    }
    fn darcy_velocity(&self, x: &[f64; D], t: f64) -> Option<f64> {
        (**self).darcy_velocity(x, t)
    }
    fn darcy_velocity_vector(&self, x: &[f64; D], t: f64) -> Option<[f64; D]> {
        (**self).darcy_velocity_vector(x, t)
    }
    fn breakpoints(&self) -> Vec<f64> {
        (**self).breakpoints()
    }
}

/// A user's pressure field from a closure `|x, t| p` (Pa), with no Darcy velocity and no
/// breakpoints.
#[derive(Clone)]
pub struct PressureFn<F>(pub F);

impl<F> std::fmt::Debug for PressureFn<F> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("PressureFn")
    }
}

impl<const D: usize, F: Fn(&[f64; D], f64) -> f64 + Send + Sync> PorePressure<D> for PressureFn<F> {
    fn pressure(&self, x: &[f64; D], t: f64) -> f64 {
        (self.0)(x, t)
    }
}

/// The pore pressure at a run's frictional nodes, whatever the dimension: what the
/// methods call.
pub(crate) trait NodePressures: Send + Sync + std::fmt::Debug {
    /// `σ_k − p(x_k, t)` into `sigma` (which holds `σ_k`), checked in node order
    /// ([`PressureAtNodes::lower`]).
    fn lower(&self, t: f64, sigma: &mut [f64], scratch: &mut [f64]) -> Result<()>;
    /// The first breakpoint after `t` (s), if any.
    fn next_breakpoint(&self, t: f64) -> Option<f64>;
}

/// The pore pressure of a run: the field and the frictional nodes' coordinates.
#[derive(Debug, Clone)]
pub(crate) struct PressureAtNodes<const D: usize> {
    field: std::sync::Arc<dyn PorePressure<D>>,
    points: Vec<[f64; D]>,
    breakpoints: Vec<f64>,
}

impl<const D: usize> PressureAtNodes<D> {
    /// `field` at the frictional nodes `points`, for laws that build their potential at
    /// another normal stress ([`FrictionLaw::potential_at_normal_stress`]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `pore_pressure`
    /// for a law without a normal stress, or one that cannot take another.
    pub(crate) fn new<L: FrictionLaw>(
        field: std::sync::Arc<dyn PorePressure<D>>,
        points: Vec<[f64; D]>,
        laws: &[L],
    ) -> Result<Self> {
        for (k, law) in laws.iter().enumerate() {
            let ok = matches!(law.normal_stress(), Some(s) if s > 0.0 && s.is_finite())
                && law.potential_at_normal_stress(0.0, 1.0).is_some();
            if !ok {
                return Err(crate::error::invalid(
                    "pore_pressure",
                    format!(
                        "the law of frictional node {k} has no positive normal stress or \
                         cannot take another (FrictionLaw::normal_stress, \
                         FrictionLaw::potential_at_normal_stress)"
                    ),
                ));
            }
        }
        let mut breakpoints = field.breakpoints();
        breakpoints.retain(|t| t.is_finite());
        breakpoints.sort_by(f64::total_cmp);
        Ok(Self {
            field,
            points,
            breakpoints,
        })
    }
}

impl<const D: usize> NodePressures for PressureAtNodes<D> {
    fn next_breakpoint(&self, t: f64) -> Option<f64> {
        self.breakpoints.iter().copied().find(|&b| b > t)
    }

    /// `σ_k − p(x_k, t)` into `sigma` (which holds `σ_k`, the normal stress without the
    /// pressure), checked in node order.
    ///
    /// # Errors
    /// [`Error::NormalStressNotPositive`](crate::Error::NormalStressNotPositive) at the first
    /// node where the effective normal stress is `≤ 0` or not finite.
    fn lower(&self, t: f64, sigma: &mut [f64], scratch: &mut [f64]) -> Result<()> {
        self.field.pressures(t, &self.points, scratch);
        for (k, (s, p)) in sigma.iter_mut().zip(scratch.iter()).enumerate() {
            *s -= p;
            check_normal_stress(k, t, *s)?;
        }
        Ok(())
    }
}

/// The laws at the effective normal stresses of the last accepted step: what observers
/// see as the fault's tractions with a pore pressure.
#[derive(Debug, Clone)]
pub(crate) struct EffectiveTractions<L> {
    pub(crate) laws: Vec<L>,
    /// `σ̄_n − p` (Pa) of every frictional node.
    pub(crate) sigma: Vec<f64>,
}

impl<L: FrictionLaw> crate::observe::FaultTractions for EffectiveTractions<L> {
    fn shear_traction(&self, k: usize, slip_rate: f64, alpha: f64) -> f64 {
        match self.laws[k].potential_at_normal_stress(alpha, self.sigma[k]) {
            Some(p) => p.slope(slip_rate),
            None => self.laws[k].potential(alpha).slope(slip_rate),
        }
    }
    fn normal_traction(&self, k: usize) -> Option<f64> {
        Some(self.sigma[k])
    }
}

/// What a method keeps of a run's pore pressure: the pressure at the nodes, the laws'
/// normal stresses, scratch, and the tractions observers see.
#[derive(Debug, Clone)]
pub(crate) struct PressureWork<L> {
    pub(crate) at_nodes: std::sync::Arc<dyn NodePressures>,
    /// The laws' own `σ̄_n` (Pa).
    pub(crate) sigma_laws: Vec<f64>,
    /// `σ̄_n − p` of the current evaluation (Pa).
    pub(crate) sigma: Vec<f64>,
    pub(crate) scratch: Vec<f64>,
    /// The laws at `σ̄_n − p` of the last accepted step.
    pub(crate) tractions: EffectiveTractions<L>,
}

impl<L: FrictionLaw> PressureWork<L> {
    /// For `laws` (each with a normal stress, checked by [`PressureAtNodes::new`]).
    pub(crate) fn new(at_nodes: std::sync::Arc<dyn NodePressures>, laws: &[L]) -> Self {
        let sigma_laws: Vec<f64> = laws
            .iter()
            .map(|l| l.normal_stress().unwrap_or(f64::NAN))
            .collect();
        Self {
            at_nodes,
            sigma: sigma_laws.clone(),
            scratch: vec![0.0; laws.len()],
            tractions: EffectiveTractions {
                laws: laws.to_vec(),
                sigma: sigma_laws.clone(),
            },
            sigma_laws,
        }
    }

    /// `σ̄_n − p(t)` into [`sigma`](Self::sigma) from `base` (the normal stress without
    /// the pressure: the laws' own, or one from slip).
    ///
    /// # Errors
    /// [`Error::NormalStressNotPositive`](crate::Error::NormalStressNotPositive) as
    /// [`NodePressures::lower`].
    pub(crate) fn lower_from(&mut self, t: f64, base: Option<&[f64]>) -> Result<()> {
        self.sigma
            .copy_from_slice(base.unwrap_or(self.sigma_laws.as_slice()));
        self.at_nodes.lower(t, &mut self.sigma, &mut self.scratch)
    }
}

/// `potentials[k]` = law `k`'s potential at `alpha[k]` and the normal stress `sigma[k]`.
pub(crate) fn potentials_at<L: FrictionLaw>(
    laws: &[L],
    alpha: &[f64],
    sigma: &[f64],
    potentials: &mut Vec<L::Potential>,
) {
    let at = |(l, (&a, &s)): (&L, (&f64, &f64))| {
        l.potential_at_normal_stress(a, s)
            .unwrap_or_else(|| l.potential(a))
    };
    if potentials.len() == laws.len() {
        for (p, x) in potentials
            .iter_mut()
            .zip(laws.iter().zip(alpha.iter().zip(sigma)))
        {
            *p = at(x);
        }
    } else {
        potentials.clear();
        potentials.extend(laws.iter().zip(alpha.iter().zip(sigma)).map(at));
    }
}

#[cfg(test)]
mod surface_tests;
#[cfg(test)]
mod tests;
