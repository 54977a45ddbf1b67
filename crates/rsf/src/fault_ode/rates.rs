//! The right-hand side of a fault ODE: the load, the product with the elastic operator
//! and the node-by-node friction solves, as an [`OdeSystem`].

use std::time::Duration;

use rsf_friction::FrictionLaw;
use rsf_linalg::Parallelism;
use rsf_state::StateLaw;
use rsf_time::{JacobianBlocks, OdeSystem};

use crate::error::{Error, Result};
use crate::fault_alone::Body;
use crate::fault_operator::FaultOperator;
use crate::model::loading::TimeFunction;
use crate::node_solves::{Loading, NodeSolves, PartNodes, RatesOut, PARALLEL_NODES_MIN};
use crate::normal_stress::NormalCoupling;
use crate::ranks::SharedEvaluation;

use super::linger::linger;

/// The nodes' solves of the rates `$rates` ([`Rates`]) with its data `$d`
/// ([`FaultRates`]) at the loading rate `$speed` and the states `$alpha`: at the normal
/// stresses and pore pressures of the evaluation. A macro, so that the fields of `$d` it
/// does not borrow stay free to borrow mutably.
macro_rules! node_solves {
    ($rates:expr, $d:expr, $speed:expr, $alpha:expr) => {
        NodeSolves {
            friction: $rates.friction,
            state_laws: $rates.state_laws,
            uses_state: $rates.uses_state,
            first: &$d.first,
            weights: &$d.weights,
            fixed_velocity: &$d.fixed_velocity,
            eta: &$d.eta,
            speed: $speed,
            alpha: $alpha,
            scale: $d.normal.as_ref().map(|n| (&$d.sigma[..], n.initial())),
            effective: $d.pressure.as_ref().map(|p| &p.effective[..]),
        }
    };
}

/// What the right-hand side needs besides the laws.
pub(super) struct FaultRates<const C: usize> {
    pub(super) body: Body<C>,
    pub(super) operator: Box<dyn FaultOperator>,
    pub(super) par: Parallelism,
    /// The polling of idle threads after an evaluation ([`super::FaultOdeOptions::linger`]).
    pub(super) linger: Option<Duration>,
    pub(super) g0: Vec<f64>,
    pub(super) g1: Vec<f64>,
    pub(super) history: TimeFunction,
    /// Free components of frictional node `k`: `first[k]..first[k + 1]`.
    pub(super) first: Vec<usize>,
    /// Dirichlet velocity factor of every component of each frictional node (0 where free
    /// or at rest).
    pub(super) fixed_velocity: Vec<[f64; C]>,
    pub(super) weights: Vec<f64>,
    /// η of every frictional node (Pa·s/m).
    pub(super) eta: Vec<f64>,
    pub(super) r: Vec<f64>,
    pub(super) tolerance: f64,
    pub(super) slip_scale: f64,
    /// A normal stress that changes with slip, and its values (scratch, one per node).
    pub(super) normal: Option<NormalCoupling>,
    pub(super) sigma: Vec<f64>,
    /// The nodes of each part of the ℋ-product, made at the first parallel evaluation.
    pub(super) parts: Option<PartNodes>,
    /// The ranks that share the evaluations, if shared
    /// ([`FaultOde::share_evaluations`](super::FaultOde::share_evaluations)).
    pub(super) shared: Option<SharedEvaluation>,
    /// A pore pressure: the field at the nodes, the laws' own `σ̄_n`, the effective normal
    /// stress `σ̄_n − p` of the evaluation and scratch (one per node each).
    pub(super) pressure: Option<PressureRates>,
    /// The diagonal of `S` (N/m; empty until the first local Jacobian asks for it).
    pub(super) diagonal: Vec<f64>,
    /// A prescribed change of the load in time ([`super::LoadChange`]).
    pub(super) load_change: Option<super::load_change::LoadChangeRates>,
}

/// A pore pressure in the fault ODE's evaluations.
pub(super) struct PressureRates {
    pub(super) at_nodes: std::sync::Arc<dyn crate::pore_pressure::NodePressures>,
    pub(super) sigma_laws: Vec<f64>,
    pub(super) effective: Vec<f64>,
    pub(super) scratch: Vec<f64>,
}

impl PressureRates {
    /// `σ̄_n − p(t)` into `effective` from `base` (the normal stress from slip) or the
    /// laws' own.
    ///
    /// # Errors
    /// [`Error::NormalStressNotPositive`] where it is `≤ 0` (a stage outside the domain).
    pub(super) fn lower(&mut self, t: f64, base: Option<&[f64]>) -> Result<()> {
        self.effective
            .copy_from_slice(base.unwrap_or(self.sigma_laws.as_slice()));
        self.at_nodes
            .lower(t, &mut self.effective, &mut self.scratch)
    }
}

/// [`linger`] when dropped: at the end of an evaluation however it ends (a few
/// microseconds of Runge–Kutta arithmetic come before the next).
pub(super) struct LingerAfter(Parallelism, Option<Duration>);

impl Drop for LingerAfter {
    fn drop(&mut self) {
        linger(self.0, self.1);
    }
}

/// The ODE system of one step: the rates with the laws borrowed.
pub(super) struct Rates<'a, L, S, const C: usize> {
    pub(super) friction: &'a [L],
    pub(super) state_laws: &'a [S],
    pub(super) uses_state: bool,
    pub(super) data: &'a mut FaultRates<C>,
}

impl<L: FrictionLaw, S: StateLaw, const C: usize> OdeSystem for Rates<'_, L, S, C> {
    type Error = Error;

    fn rate(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
        let d = &mut *self.data;
        let m = d.first[d.first.len() - 1];
        let big_g = d
            .history
            .integral(t)
            .expect("checked at construction: a loading history with a closed-form integral");
        let speed = d.history.value(t);
        if let Some(change) = &d.load_change {
            change.apply(t, &mut d.g0);
        }
        let (u, alpha) = y.split_at(m);
        let (dyu, dya) = dy.split_at_mut(m);
        let pieces = if d.par.is_parallel() && self.friction.len() >= PARALLEL_NODES_MIN {
            d.par.threads()
        } else {
            1
        };
        // Shared by ranks: each rank its part of the operator's rows and their nodes,
        // then one exchange; a normal stress from slip first, each rank its rows of `S_N`
        // and one exchange (the same numbers as alone). A non-finite `u` (the same on
        // every rank) takes the sequential path below on every rank.
        let shared_path = d.shared.is_some() && u.iter().all(|v| v.is_finite());
        // The normal stress first: from slip (alone or shared), then less a pore
        // pressure (independent of the product below: the same bits in either order).
        if let Some(normal) = &mut d.normal {
            match (&mut d.shared, shared_path) {
                (Some(shared), true) => {
                    shared.normal_stress(normal, (t, big_g), u, &mut d.sigma, d.par)?;
                }
                _ => normal.evaluate(t, big_g, u, &mut d.sigma, d.par)?,
            }
        }
        if let Some(pr) = &mut d.pressure {
            pr.lower(t, d.normal.as_ref().map(|_| &d.sigma[..]))?;
        }
        let solves = node_solves!(self, d, speed, alpha);
        if let (Some(shared), true) = (&mut d.shared, shared_path) {
            let load = Loading {
                g0: &d.g0,
                g1: &d.g1,
                big_g,
            };
            return shared.evaluate(&mut *d.operator, u, &solves, load, RatesOut { dyu, dya });
        }
        // Between the parallel evaluations the pool's other threads poll for work.
        let _linger = (pieces > 1).then_some(LingerAfter(d.par, d.linger));
        // With threads, an ℋ-kernel and a fixed normal stress: one parallel region, each
        // thread its rows of the product and their nodes' solves (same bits).
        if let (true, None, Some(h)) = (pieces > 1, &d.normal, d.operator.hierarchical_mut()) {
            let parts = d
                .parts
                .get_or_insert_with(|| PartNodes::new(h, pieces, solves.first));
            let load = Loading {
                g0: &d.g0,
                g1: &d.g1,
                big_g,
            };
            match parts.evaluate(h, u, &solves, load, RatesOut { dyu, dya }) {
                Err(rsf_hmatrix::Error::NonFiniteInput(_)) => {} // as below: a NaN residual
                other => return other.map_err(Error::from),
            }
        }
        for ((r, g0), g1) in d.r.iter_mut().zip(&d.g0).zip(&d.g1) {
            *r = g0 + big_g * g1;
        }
        d.operator.subtract_product(u, &mut d.r, d.par)?;
        solves.solve((0, self.friction.len()), pieces, &d.r, dyu, dya);
        Ok(())
    }

    /// A stage whose normal stress would be `≤ 0` or not finite
    /// ([`Error::NormalStressNotPositive`]) is outside the domain: the step is rejected
    /// and retried smaller (docs/reliability.md, "Trial points outside the domain").
    fn outside_domain(&self, error: &Error) -> bool {
        matches!(error, Error::NormalStressNotPositive { .. })
    }

    /// Slip components `1/(tolerance · slip_scale)`, states `1/tolerance`: the weights of
    /// [`scaled_error`](Self::scaled_error)'s maximum.
    fn error_weights(&self, _y: &[f64], w: &mut [f64]) -> bool {
        let d = &*self.data;
        let m = d.first[d.first.len() - 1];
        let (slip, state) = (1.0 / (d.tolerance * d.slip_scale), 1.0 / d.tolerance);
        for (i, wi) in w.iter_mut().enumerate() {
            *wi = if i < m { slip } else { state };
        }
        true
    }

    /// Node by node, the Jacobian of the node's slip rates and state rate with respect to
    /// its slip and state, with `S` replaced by its diagonal (docs/math.md §12, "Implicit
    /// steps"): forward differences of the node's own solve (its traction moved by
    /// `S_ii δu_i`, its state by `δα`), at `g(t) − S u_F` of one product. The first call
    /// also takes `S`'s diagonal ([`FaultOperator::diagonal`]). The normal stress's
    /// dependence on slip and the pore pressure's on time are left out (the blocks only
    /// precondition).
    fn local_jacobian(
        &mut self,
        t: f64,
        y: &[f64],
        _f: &[f64],
        blocks: &mut JacobianBlocks,
    ) -> Result<Option<usize>> {
        let d = &mut *self.data;
        let nodes = d.first.len() - 1;
        let m = d.first[nodes];
        if d.diagonal.len() != m {
            d.diagonal.resize(m, 0.0);
            d.operator.diagonal(&mut d.diagonal)?;
        }
        if blocks.is_empty() {
            let mut comps = Vec::with_capacity(C + 1);
            for k in 0..nodes {
                comps.clear();
                comps.extend(d.first[k]..d.first[k + 1]);
                comps.push(m + k);
                blocks.push_block(&comps);
            }
        }
        let big_g = d
            .history
            .integral(t)
            .expect("checked at construction: a loading history with a closed-form integral");
        let (u, alpha) = y.split_at(m);
        if let Some(normal) = &mut d.normal {
            normal.evaluate(t, big_g, u, &mut d.sigma, d.par)?;
        }
        if let Some(pr) = &mut d.pressure {
            pr.lower(t, d.normal.as_ref().map(|_| &d.sigma[..]))?;
        }
        for ((r, g0), g1) in d.r.iter_mut().zip(&d.g0).zip(&d.g1) {
            *r = g0 + big_g * g1;
        }
        d.operator.subtract_product(u, &mut d.r, d.par)?;
        let solves = node_solves!(self, d, d.history.value(t), alpha);
        let root = f64::EPSILON.sqrt();
        for k in 0..nodes {
            let (a, b) = (d.first[k], d.first[k + 1]);
            let nc = b - a;
            let width = nc + 1;
            let block = blocks.block_mut(k);
            let (mut v0, mut v1, mut rr) = ([0.0; C], [0.0; C], [0.0; C]);
            let a0 = solves.solve_node_at(k, alpha[k], &d.r[a..b], &mut v0[..nc]);
            for i in 0..nc {
                let du = root * u[a + i].abs().max(d.slip_scale);
                rr[..nc].copy_from_slice(&d.r[a..b]);
                rr[i] -= d.diagonal[a + i] * du;
                let a1 = solves.solve_node_at(k, alpha[k], &rr[..nc], &mut v1[..nc]);
                for j in 0..nc {
                    block[j * width + i] = (v1[j] - v0[j]) / du;
                }
                block[nc * width + i] = (a1 - a0) / du;
            }
            let da = root * alpha[k].abs().max(1.0);
            let a1 = solves.solve_node_at(k, alpha[k] + da, &d.r[a..b], &mut v1[..nc]);
            for j in 0..nc {
                block[j * width + nc] = (v1[j] - v0[j]) / da;
            }
            block[nc * width + nc] = (a1 - a0) / da;
        }
        Ok(Some(1))
    }

    fn scaled_error(&self, _y: &[f64], _y_new: &[f64], err: &[f64]) -> f64 {
        let d = &*self.data;
        let m = d.first[d.first.len() - 1];
        let slip = 1.0 / (d.tolerance * d.slip_scale);
        let state = 1.0 / d.tolerance;
        let mut worst = 0.0_f64;
        for (i, e) in err.iter().enumerate() {
            let x = e.abs() * if i < m { slip } else { state };
            if x.is_nan() {
                return f64::INFINITY;
            }
            worst = worst.max(x);
        }
        worst
    }
}
