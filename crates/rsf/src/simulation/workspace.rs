//! Scratch space of a simulation's step: everything a step overwrites before it reads it,
//! allocated once at construction (no allocation per step or iteration).

use rsf_friction::FrictionLaw;
use rsf_time::Kinematics;

use crate::friction_blocks::{evaluate_potentials, FrictionView};
use crate::method::fixed_point::{Accelerator, FixedPointOptions};
use crate::model::fault::FrictionalBoundary;
use crate::normal_stress::{NormalReactions, ScaledTractions};

/// The fixed point history's capacity allocated up front (it grows beyond, if ever).
const HISTORY_CAPACITY: usize = 1000;

/// The buffers of a step, sized for `n` dofs and `nf` frictional nodes.
pub(crate) struct Workspace<L: FrictionLaw> {
    /// The friction potentials at the state of the current fixed point iterate.
    pub potentials: Vec<L::Potential>,
    /// The attempted step's `(u, v, a)`.
    pub next: Kinematics,
    /// Coefficient vectors of the right-hand side `ℓ = F + M w_M − K w_K`.
    pub w_mass: Vec<f64>,
    pub w_stiffness: Vec<f64>,
    /// The right-hand side `ℓ_n`.
    pub rhs: Vec<f64>,
    /// The velocity iterate (predictor, then `v_n`).
    pub v: Vec<f64>,
    /// State iterate `α^ν`, its update `S(α_{n−1}, |v^ν|)`, and the locally extrapolated
    /// update of adaptive steps.
    pub alpha_iter: Vec<f64>,
    pub alpha_trial: Vec<f64>,
    pub alpha_extrapolated: Vec<f64>,
    /// Slip rates on Γ_F of the current iterate.
    pub slip: Vec<f64>,
    /// Fixed point corrections of the current step.
    pub history: Vec<f64>,
    /// Displacement error estimate of an adaptive step.
    pub u_err: Vec<f64>,
    /// Acceleration of the fixed point iteration.
    pub accelerator: Accelerator,
    /// A normal stress from slip: its reactions and buffers (`None`: the laws' own).
    pub normal: Option<NormalWork<L>>,
    /// A pore pressure: the effective normal stress and its tractions (`None`: none).
    pub pressure: Option<crate::pore_pressure::PressureWork<L>>,
}

/// The buffers of a normal stress from slip in the implicit scheme.
pub(crate) struct NormalWork<L: FrictionLaw> {
    /// The reactions at the tied normal jumps.
    pub reactions: NormalReactions,
    /// `σ̄_n` of the current iterate and the friction weights scaled by it.
    pub sigma: Vec<f64>,
    pub weights: Vec<f64>,
    /// The current iterate's whole velocity and kinematics.
    pub v: Vec<f64>,
    pub next: Kinematics,
    /// What observers see: the laws scaled by `σ̄_n` of the last committed step.
    pub tractions: ScaledTractions<L>,
}

impl<L: FrictionLaw> NormalWork<L> {
    /// Buffers for `n` dofs and the laws `laws`.
    pub fn new(reactions: NormalReactions, n: usize, laws: &[L], weights: &[f64]) -> Self {
        let sigma0 = reactions.initial().to_vec();
        Self {
            sigma: sigma0.clone(),
            weights: weights.to_vec(),
            v: vec![0.0; n],
            next: Kinematics::zeros(n),
            tractions: ScaledTractions {
                laws: laws.to_vec(),
                sigma: sigma0.clone(),
                sigma0,
            },
            reactions,
        }
    }
}

impl<L: FrictionLaw> Workspace<L> {
    /// The friction of Γ_F (`fb`, its `laws`) at the state iterate `alpha_iter`: with a
    /// pore pressure the laws at `σ̄_n − p(t)` (`σ̄_n` the laws' or the iterate's from
    /// slip), the weights unscaled; with a normal stress from slip the iterate's scaled
    /// weights; otherwise the laws' potentials with `fb`'s weights.
    ///
    /// # Errors
    /// The pressure's at `t`.
    pub fn friction_view<'a>(
        &'a mut self,
        laws: &[L],
        fb: &'a FrictionalBoundary,
        t: f64,
    ) -> crate::error::Result<FrictionView<'a, L>> {
        if let Some(pw) = &mut self.pressure {
            pw.lower_from(t, self.normal.as_ref().map(|n| &n.sigma[..]))?;
            crate::pore_pressure::potentials_at(
                laws,
                &self.alpha_iter,
                &pw.sigma,
                &mut self.potentials,
            );
            return Ok(FrictionView::<L>::new(fb, &self.potentials));
        }
        evaluate_potentials(laws, &self.alpha_iter, &mut self.potentials);
        Ok(match &self.normal {
            None => FrictionView::<L>::new(fb, &self.potentials),
            Some(normal) => FrictionView::<L> {
                nodes: &fb.nodes,
                weights: &normal.weights,
                potentials: &self.potentials,
            },
        })
    }

    /// Buffers for `n` dofs, the frictional nodes' `laws` at state `alpha` and weights
    /// `weights` (of the accelerator's norm).
    pub fn new(
        n: usize,
        laws: &[L],
        alpha: &[f64],
        weights: &[f64],
        fixed_point: &FixedPointOptions,
    ) -> Self {
        let nf = laws.len();
        let mut potentials = Vec::with_capacity(nf);
        evaluate_potentials(laws, alpha, &mut potentials);
        Self {
            potentials,
            next: Kinematics::zeros(n),
            w_mass: vec![0.0; n],
            w_stiffness: vec![0.0; n],
            rhs: vec![0.0; n],
            v: vec![0.0; n],
            alpha_iter: vec![0.0; nf],
            alpha_trial: vec![0.0; nf],
            alpha_extrapolated: vec![0.0; nf],
            slip: vec![0.0; nf],
            // Room for the iterations a step takes in practice (the paper's steps take
            // ≤ 30); a larger user bound (up to `usize::MAX`) is not allocated up front.
            history: Vec::with_capacity(fixed_point.max_iterations.min(HISTORY_CAPACITY)),
            u_err: vec![0.0; n],
            accelerator: Accelerator::new(fixed_point.acceleration, weights),
            normal: None,
            pressure: None,
        }
    }
}
