//! Adaptive time steps (docs/math.md §9): attempts with the controller's step until one is
//! accepted, and the local error estimate that decides.

use rsf_friction::FrictionLaw;
use rsf_nonsmooth::ProblemError;
use rsf_state::StateLaw;
use rsf_time::VelocityIntegrator;

use crate::error::{Error, Result};
use crate::model::fault::block_norm;
use crate::report::StepReport;

use super::step::Stepper;
use crate::run::time_slack;

/// Errors after which an adaptive step is retried with a smaller τ: a fixed point or a
/// solver that did not converge, a non-finite solve or state update, and a trial state
/// whose normal stress would be `≤ 0` (an iterate that overshoots; counted apart,
/// [`StepReport::rejected_normal_stress`]).
fn recoverable(e: &Error) -> bool {
    matches!(
        e,
        Error::FixedPointNotConverged { .. }
            | Error::Solver(rsf_tnnmg::Error::NotConverged { .. })
            | Error::Solver(rsf_tnnmg::Error::Problem(ProblemError::NonFinite(_)))
            | Error::Direct(rsf_direct::Error::NotConverged { .. })
            | Error::Direct(rsf_direct::Error::Problem(ProblemError::NonFinite(_)))
            | Error::State(_)
            | Error::NormalStressNotPositive { .. }
    )
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    Stepper<'_, D, L, S, I, C>
{
    /// Attempts with the controller's step until one is accepted (docs/math.md §9). A step
    /// that would pass `t_end` or a breakpoint of the loading
    /// ([`TimeFunction::next_breakpoint`](crate::TimeFunction::next_breakpoint)) is
    /// shortened to end there (off the ladder; the controller keeps its step for later).
    ///
    /// # Panics
    /// Without step control (internal invariant: callers check).
    pub fn adaptive_step(&mut self, t_end: Option<f64>) -> Result<StepReport> {
        let control = *self.method.step_control().expect("adaptive");
        let mut rejected = 0;
        let mut refused = 0;
        let mut rejected_error = 0.0;
        // A breakpoint closer than the round-off allowance is taken as reached (no sliver of
        // a step).
        let tau_now = self.controller().tau();
        let time = self.state.time;
        let breakpoint = self
            .problem
            .model()
            .dirichlet
            .history
            .next_breakpoint(time + time_slack(time, tau_now));
        let stop = match (t_end, breakpoint) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        loop {
            let mut tau = self.controller().tau();
            let mut clipped = false;
            if let Some(stop) = stop {
                let left = stop - self.state.time;
                if left < tau * (1.0 - 1e-9) {
                    tau = left;
                    clipped = true;
                }
            }
            self.set_time_step(tau)?;
            match self.attempt() {
                Ok(mut report) => {
                    let (err, state_change) = self.error_estimate();
                    if err <= 1.0 {
                        if !clipped {
                            control.accept(self.controller_mut(), err, state_change);
                        }
                        report.rejected_attempts = rejected;
                        report.rejected_normal_stress = refused;
                        report.error_estimate = err;
                        report.rejected_error = rejected_error;
                        if control.state_extrapolation && self.problem.uses_state() {
                            self.work
                                .alpha_trial
                                .copy_from_slice(&self.work.alpha_extrapolated);
                        }
                        self.commit(&report);
                        return Ok(report);
                    }
                    rejected_error = if err.is_nan() { f64::INFINITY } else { err };
                    control.reject(self.controller_mut(), err)?;
                }
                Err(e) if recoverable(&e) => {
                    rejected_error = f64::INFINITY;
                    let opens = matches!(e, Error::NormalStressNotPositive { .. });
                    refused += usize::from(opens);
                    if control
                        .reject(self.controller_mut(), f64::INFINITY)
                        .is_err()
                    {
                        return Err(if opens {
                            Error::TrialStateRefused {
                                step: self.state.step + 1,
                                time: self.state.time,
                                tau,
                                refusals: refused,
                                reason: Box::new(e),
                                remedy: "the step control cannot shrink the step below \
                                         tau_min; lower tau_min or the tolerance",
                            }
                        } else {
                            e
                        });
                    }
                }
                Err(e) => return Err(e),
            }
            rejected += 1;
        }
    }

    fn controller(&self) -> &rsf_time::ControllerState {
        self.state.controller.as_ref().expect("adaptive")
    }

    fn controller_mut(&mut self) -> &mut rsf_time::ControllerState {
        self.state.controller.as_mut().expect("adaptive")
    }

    /// The scaled local error of the attempted step (in the workspace's `next`,
    /// `alpha_trial`) and the largest change of the state: the largest of
    /// `rms(e_u) / (atol + tol · rms(u − u₀))` over the free dofs, with the integrator's
    /// estimate `e_u`, of the slip test `(Δ ln(V_p + V_f))² / (12 tol)` at each frictional
    /// node p (if enabled), and the maximum over Γ_F of the state update's estimated local
    /// error over `tol + state_atol/θ` ([`StateIntegrator`](crate::method::StateIntegrator);
    /// backward Euler: `(τ/2)|α̇_n − α̇_{n−1}|`, i.e. `τ²/2 · α̈`, docs/math.md §9; a
    /// non-finite estimate rejects the step). Leaves the locally extrapolated states
    /// (local extrapolation, docs/math.md §9: backward Euler's estimated local error
    /// `(τ/2)(α̇_{n−1} − α̇_n)` added, damped by `1 / (1 + τ ∂²ψ/∂α²)` where the state
    /// equation is stiff; for the exact update at constant slip rate, the mean of the
    /// updates with the step's two slip rates) in `alpha_extrapolated`.
    fn error_estimate(&mut self) -> (f64, f64) {
        let c = *self.method.step_control().expect("adaptive");
        let model = self.problem.model();
        let (state, work) = (&*self.state, &mut *self.work);
        let tau = state.tau;
        let kin = &state.kinematics;
        self.method
            .integrator()
            .displacement_error(tau, kin, &work.next, &mut work.u_err);
        let u0 = &model.initial_displacement;
        // Root mean square over the free dofs (a discrete L² norm on the uniform meshes of
        // this crate's scenes): the displacement error is a property of the whole body.
        let (mut e2, mut d2, mut count) = (0.0, 0.0, 0usize);
        for i in 0..work.u_err.len() {
            if model.fixed[i] {
                continue;
            }
            let d = (kin.u[i] - u0[i]).abs().max((work.next.u[i] - u0[i]).abs());
            e2 += work.u_err[i] * work.u_err[i];
            d2 += d * d;
            count += 1;
        }
        let count = count.max(1) as f64;
        let scale = c.displacement_atol + c.tolerance * (d2 / count).sqrt();
        let mut err = (e2 / count).sqrt() / scale;
        if let Some(v_floor) = c.slip_rate_floor {
            // The relative error of the slip of the step at each frictional node: the
            // trapezoidal slip (τ/2)(V_{n−1} + V_n) of a slip rate exponential in time is
            // off by (Δ ln V)²/12 (docs/math.md §9).
            for &p in &model.frictional_boundary.nodes {
                let v0 = block_norm::<C>(&kin.v, p);
                let v1 = block_norm::<C>(&work.next.v, p);
                let d = ((v1 + v_floor) / (v0 + v_floor)).ln();
                err = err.max(d * d / (12.0 * c.tolerance));
            }
        }
        if err.is_nan() {
            err = f64::INFINITY;
        }
        let mut state_change: f64 = 0.0;
        if self.problem.uses_state() {
            let laws = self.problem.state_laws();
            let integrator = self.method.state_integrator();
            for (k, &p) in model.frictional_boundary.nodes.iter().enumerate() {
                let (a0, a1) = (state.alpha[k], work.alpha_trial[k]);
                let v0 = block_norm::<C>(&kin.v, p);
                let v1 = block_norm::<C>(&work.next.v, p);
                let (e, extrapolated) = integrator.local_error(&laws[k], (a0, v0), (a1, v1), tau);
                work.alpha_extrapolated[k] = extrapolated.unwrap_or(a1);
                // |δθ| ≤ state_atol + tol·θ, i.e. |δα| ≤ tol + state_atol/θ (θ = e^α the
                // larger state of the step); an overflowing 1/θ leaves the absolute part.
                let scale = if c.state_atol > 0.0 {
                    c.tolerance + c.state_atol * (-a0.max(a1)).exp()
                } else {
                    c.tolerance
                };
                err = err.max(if e.is_finite() {
                    e / scale
                } else {
                    f64::INFINITY
                });
                state_change = state_change.max((a1 - a0).abs());
            }
        }
        (err, state_change)
    }
}
