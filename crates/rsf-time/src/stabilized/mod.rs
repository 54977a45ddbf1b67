//! A stabilised explicit Runge–Kutta method for stiff ODE systems `y' = f(t, y)` whose
//! Jacobian has a spectrum near the negative real axis (docs/math.md §12, "Stiff steps"):
//! RKC2, the second-order Runge–Kutta–Chebyshev method of Sommeijer, Shampine & Verwer
//! (1997, "RKC: an explicit solver for parabolic PDEs", J. Comput. Appl. Math. 88) in the
//! form of Verwer, Sommeijer & Hundsdorfer (2004, "RKC time-stepping for
//! advection–diffusion–reaction problems", J. Comput. Phys. 201), damping `ε = 2/13`.
//!
//! A step of `s` stages is stable for `h ρ ≤ β(s) ≈ 0.653 s²` (`ρ` the spectral radius of
//! `∂f/∂y`): the stage count grows with the square root of the stiffness, where an
//! explicit pair's step shrinks with it. Each step takes `s = 1 + ⌊√(1 + 1.54 h ρ)⌋`
//! stages (at least 2; at most [`RkcOptions::max_stages`], the step shortened to fit),
//! `s` evaluations of `f` (the last at the new point is the next step's first, as with
//! the FSAL pairs), the error estimate of the RKC code,
//! `est = 0.8 (yₙ − yₙ₊₁) + 0.4 h (fₙ + fₙ₊₁)`, measured by [`OdeSystem::scaled_error`]
//! and controlled by RKC's step-size rule (exponent 1/3, with the previous step's error).
//!
//! The spectral radius is estimated by a nonlinear power iteration on finite differences
//! of the rate function, `σ ≈ ‖f(t, y + δ) − f(t, y)‖ / ‖δ‖` (RKC's `rkcrho`), in the
//! system's own error norm ([`OdeSystem::scaled_error`]; `‖δ‖ = √ε_mach · max(1, ‖y‖)` in
//! that norm), warm-started from the last estimate's eigenvector, multiplied by the
//! safety factor [`RkcOptions::radius_safety`], and renewed every
//! [`RkcOptions::estimate_every`] accepted steps and after every rejected one. It bounds
//! the spectral radius of the whole Jacobian `∂f/∂y` (every block of it), which the
//! stage count needs; it costs a few evaluations per estimate.

use crate::runge_kutta::{
    after_refusal, check_step, check_step_size, landing_step, rate_or_refusal, OdeSystem,
    RungeKuttaOptions, RungeKuttaStep,
};
use crate::{invalid, Error, Result};

/// Options of [`Rkc2`] beyond the step limits ([`RungeKuttaOptions`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RkcOptions {
    /// Most stages of one step (default 250: stable for `h ρ ≤ 4.1e4`); a step that would
    /// need more is shortened to `h = (s² − 1)/(1.54 ρ)`. At least 2.
    pub max_stages: usize,
    /// The factor the power iteration's estimate is multiplied by (RKC's 1.2; the
    /// iteration approaches the spectral radius from below). At least 1.
    pub radius_safety: f64,
    /// Accepted steps after which the spectral radius is estimated again (RKC's 25); it is
    /// estimated after every rejected step too. At least 1.
    pub estimate_every: usize,
    /// Most iterations of one estimate (RKC's 50); an estimate that has not settled by then
    /// takes the largest value seen (the step's error test still guards the step).
    pub power_iterations: usize,
    /// Relative change between two iterations at which an estimate has settled (RKC's
    /// 0.01). In (0, 1).
    pub power_tolerance: f64,
}

impl Default for RkcOptions {
    fn default() -> Self {
        Self {
            max_stages: 250,
            radius_safety: 1.2,
            estimate_every: 25,
            power_iterations: 50,
            power_tolerance: 0.01,
        }
    }
}

impl RkcOptions {
    /// Checks the options.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first invalid option.
    pub fn validate(&self) -> Result<()> {
        if self.max_stages < 2 || self.max_stages > 10_000 {
            return invalid(
                "max_stages",
                self.max_stages as f64,
                "must be in [2, 10000]",
            );
        }
        if !(self.radius_safety >= 1.0 && self.radius_safety.is_finite()) {
            return invalid(
                "radius_safety",
                self.radius_safety,
                "must be finite and >= 1",
            );
        }
        if self.estimate_every == 0 {
            return invalid("estimate_every", 0.0, "must be at least 1");
        }
        if self.power_iterations < 2 {
            return invalid(
                "power_iterations",
                self.power_iterations as f64,
                "must be at least 2",
            );
        }
        if !(self.power_tolerance > 0.0 && self.power_tolerance < 1.0) {
            return invalid("power_tolerance", self.power_tolerance, "must be in (0, 1)");
        }
        Ok(())
    }
}

/// Stages of an RKC2 step of size `h` for the spectral radius `rho` (RKC's rule
/// `1 + ⌊√(1 + 1.54 h ρ)⌋`, at least 2): stable for `h ρ ≤ (s² − 1)/1.54`.
pub fn rkc_stages(h: f64, rho: f64) -> usize {
    let x = 1.0 + (1.0 + 1.54 * h * rho).max(0.0).sqrt();
    if x.is_finite() && x < 1e9 {
        (x.floor() as usize).max(2)
    } else {
        usize::MAX
    }
}

/// The memory of an [`Rkc2`] integration: what a checkpoint must keep, with `t`, `y` and
/// the rate at `(t, y)`, to continue it bit for bit.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RkcState {
    /// The next step to try (s).
    pub dt: f64,
    /// The last accepted step's scaled error (RKC's `errold`; 0 before the first).
    pub previous_error: f64,
    /// The last accepted step (s; RKC's `hold`; 0 before the first).
    pub previous_dt: f64,
    /// The spectral radius estimate in use, safety factor included (1/s; 0 before the
    /// first estimate).
    pub spectral_radius: f64,
    /// Accepted steps since the last estimate.
    pub since_estimate: usize,
    /// Whether the next step estimates the spectral radius first (the first step, after a
    /// rejection, after [`RkcOptions::estimate_every`] steps).
    pub estimate_due: bool,
    /// The last estimate's eigenvector (the power iteration's warm start); empty before
    /// the first.
    pub eigenvector: Vec<f64>,
}

impl RkcState {
    /// A fresh state whose first step tries `dt` and estimates the spectral radius first.
    pub fn starting(dt: f64) -> Self {
        Self {
            dt,
            previous_error: 0.0,
            previous_dt: 0.0,
            spectral_radius: 0.0,
            since_estimate: 0,
            estimate_due: true,
            eigenvector: Vec::new(),
        }
    }
}

/// What one accepted RKC2 step did beyond [`RungeKuttaStep`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RkcStep {
    /// The step (its `evaluations` include the spectral radius estimates).
    pub step: RungeKuttaStep,
    /// Stages of the accepted attempt.
    pub stages: usize,
    /// The spectral radius it was taken with (safety factor included; 1/s).
    pub spectral_radius: f64,
    /// Spectral radius estimates made for it (0, or 1 and more after rejections).
    pub estimates: usize,
    /// Of its evaluations, those the estimates took.
    pub estimate_evaluations: usize,
}

/// The RKC2 integrator with adaptive steps and stage counts: call [`step`](Self::step)
/// for one accepted step at a time. Allocates its vectors once; a step allocates nothing.
#[derive(Debug, Clone)]
pub struct Rkc2 {
    options: RungeKuttaOptions,
    rkc: RkcOptions,
    state: RkcState,
    /// `f(t, y)` at the current point (valid if `fsal`).
    f0: Vec<f64>,
    f_new: Vec<f64>,
    yjm1: Vec<f64>,
    yjm2: Vec<f64>,
    yj: Vec<f64>,
    fj: Vec<f64>,
    est: Vec<f64>,
    fsal: bool,
}

impl Rkc2 {
    /// An integrator for systems of dimension `n` with the first step `dt0` (s).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid options or `dt0` outside
    /// `[dt_min, dt_max]`.
    pub fn new(options: RungeKuttaOptions, rkc: RkcOptions, n: usize, dt0: f64) -> Result<Self> {
        options.validate()?;
        rkc.validate()?;
        if !(dt0 >= options.dt_min && dt0 <= options.dt_max) {
            return Err(Error::InvalidParameter {
                name: "dt0",
                value: dt0,
                requirement: "must be in [dt_min, dt_max]",
            });
        }
        let z = || vec![0.0; n];
        Ok(Self {
            options,
            rkc,
            state: RkcState::starting(dt0),
            f0: z(),
            f_new: z(),
            yjm1: z(),
            yjm2: z(),
            yj: z(),
            fj: z(),
            est: z(),
            fsal: false,
        })
    }

    /// The memory (for checkpoints).
    pub fn state(&self) -> &RkcState {
        &self.state
    }

    /// The options of the stage count and the estimates.
    pub fn rkc_options(&self) -> &RkcOptions {
        &self.rkc
    }

    /// Continues from a saved memory; the next step evaluates `f` afresh at its start.
    pub fn set_state(&mut self, state: RkcState) {
        self.state = state;
        self.fsal = false;
    }

    /// `f(t, y)` of the current point, if known (after a step: its last evaluation).
    pub fn current_rate(&self) -> Option<&[f64]> {
        self.fsal.then_some(self.f0.as_slice())
    }

    /// Continues from a saved memory and the saved rate `f(t, y)` of the current point
    /// (bit-identical to the integration that saved them).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for a rate or an eigenvector (if not empty) of another
    /// length than the state; [`Error::InvalidParameter`] named `dt` for a step outside
    /// `[dt_min, dt_max]`.
    pub fn restore(&mut self, state: RkcState, rate: &[f64]) -> Result<()> {
        let n = self.f0.len();
        for (what, got) in [
            ("saved rate", rate.len()),
            ("saved eigenvector", state.eigenvector.len()),
        ] {
            if got != n && !(what == "saved eigenvector" && got == 0) {
                return Err(Error::DimensionMismatch {
                    what,
                    expected: n,
                    got,
                });
            }
        }
        let o = self.options;
        if !(state.dt >= o.dt_min && state.dt <= o.dt_max) {
            return Err(Error::InvalidParameter {
                name: "dt",
                value: state.dt,
                requirement: "must be in [dt_min, dt_max]",
            });
        }
        self.state = state;
        self.f0.copy_from_slice(rate);
        self.fsal = true;
        Ok(())
    }

    /// The spectral radius estimate of the Jacobian at `(t, y)` (`f0` its rate), safety
    /// factor included, into the state; returns the evaluations it took.
    fn estimate<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
    ) -> std::result::Result<usize, S::Error> {
        let sqrtu = f64::EPSILON.sqrt();
        let norm = |sys: &S, v: &[f64]| sys.scaled_error(y, y, v);
        // The direction: the last eigenvector, else the rate, else every component.
        let v = &mut self.yj;
        if self.state.eigenvector.len() == y.len() {
            v.copy_from_slice(&self.state.eigenvector);
        } else {
            v.copy_from_slice(&self.f0);
        }
        let mut vnrm = norm(sys, v);
        if !(vnrm > 0.0 && vnrm.is_finite()) {
            v.fill(1.0);
            vnrm = norm(sys, v);
        }
        let ynrm = norm(sys, y);
        let dynrm = sqrtu * if ynrm.is_finite() { ynrm.max(1.0) } else { 1.0 };
        let point = &mut self.yjm1;
        for ((p, &yi), &vi) in point.iter_mut().zip(y).zip(v.iter()) {
            *p = yi + vi * (dynrm / vnrm);
        }
        let (mut sigma, mut largest) = (0.0_f64, 0.0_f64);
        let mut evaluations = 0;
        let mut settled = false;
        for it in 1..=self.rkc.power_iterations {
            let refusal = rate_or_refusal(sys, t, &self.yjm1, &mut self.fj)?;
            evaluations += 1;
            if refusal.is_some() {
                // A perturbed point outside the domain: keep what was found so far.
                break;
            }
            for (d, &f) in self.fj.iter_mut().zip(&self.f0) {
                *d -= f;
            }
            let dfnrm = norm(sys, &self.fj);
            if !dfnrm.is_finite() {
                break;
            }
            let previous = sigma;
            sigma = dfnrm / dynrm;
            largest = largest.max(sigma);
            if it >= 2 && (sigma - previous).abs() <= self.rkc.power_tolerance * sigma {
                settled = true;
                break;
            }
            if sigma == 0.0 && previous == 0.0 && it >= 2 {
                settled = true;
                break;
            }
            if dfnrm > 0.0 {
                for ((p, &yi), &d) in self.yjm1.iter_mut().zip(y).zip(&self.fj) {
                    *p = yi + d * (dynrm / dfnrm);
                }
            } else {
                // No response in this direction: turn another component's sign.
                let i = it % y.len().max(1);
                if let (Some(p), Some(&yi)) = (self.yjm1.get_mut(i), y.get(i)) {
                    *p = yi - (*p - yi);
                }
            }
        }
        let found = if settled { sigma } else { largest };
        let rho = self.rkc.radius_safety * found;
        // An estimate is only kept if finite: a non-finite one keeps the previous one
        // (and the step's error test guards the step).
        if rho.is_finite() {
            self.state.spectral_radius = rho;
        }
        self.state.eigenvector.resize(y.len(), 0.0);
        for ((e, &p), &yi) in self.state.eigenvector.iter_mut().zip(&self.yjm1).zip(y) {
            *e = p - yi;
        }
        self.state.since_estimate = 0;
        self.state.estimate_due = false;
        Ok(evaluations)
    }

    /// One accepted step from `(t, y)`, updating both; at most up to `t_end` (the step is
    /// shortened to land on it, and the controller's proposal is kept for the next one).
    /// Estimates the spectral radius first when due. A stage outside the system's domain
    /// ([`OdeSystem::outside_domain`]) rejects the attempt and shrinks the step by
    /// `refusal_shrink`; a non-finite stage by 10.
    ///
    /// # Errors
    /// As [`EmbeddedRungeKutta::step`](crate::EmbeddedRungeKutta::step):
    /// [`Error::StepTooSmall`], [`Error::TrialPointRefused`],
    /// [`Error::DimensionMismatch`], [`Error::InvalidParameter`] for a `t_end` not after
    /// `t`, and the system's errors.
    pub fn step<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: &mut f64,
        y: &mut [f64],
        t_end: Option<f64>,
    ) -> std::result::Result<RkcStep, S::Error> {
        check_step(self.f0.len(), y, *t, t_end)?;
        let o = self.options;
        let mut evaluations = 0;
        if !self.fsal {
            sys.rate(*t, y, &mut self.f0)?;
            evaluations += 1;
            self.fsal = true;
        }
        let (mut rejected, mut refused) = (0, 0);
        let mut rejected_error = 0.0;
        let (mut estimates, mut estimate_evaluations) = (0, 0);
        loop {
            if self.state.estimate_due || self.state.since_estimate >= self.rkc.estimate_every {
                let e = self.estimate(sys, *t, y)?;
                evaluations += e;
                estimate_evaluations += e;
                estimates += 1;
            }
            let rho = self.state.spectral_radius;
            let proposal = self.state.dt.min(o.dt_max);
            let (mut dt, mut landing) = landing_step(*t, proposal, t_end);
            let mut s = rkc_stages(dt, rho);
            if s > self.rkc.max_stages {
                s = self.rkc.max_stages;
                dt = ((s * s - 1) as f64 / (1.54 * rho)).min(dt);
                landing = false;
            }
            check_step_size(&o, dt, landing)?;
            let outcome = self.stages(sys, (*t, dt), y, s)?;
            evaluations += outcome.evaluations;
            if let Some(e) = outcome.refusal {
                rejected += 1;
                refused += 1;
                rejected_error = f64::INFINITY;
                self.state.dt = after_refusal(&o, (*t, dt), refused, &e)?;
                self.state.estimate_due = true;
                continue;
            }
            let error = if outcome.finite {
                for (((e, &yn), &y1), (&f0, &f1)) in self
                    .est
                    .iter_mut()
                    .zip(y.iter())
                    .zip(&self.yj)
                    .zip(self.f0.iter().zip(&self.f_new))
                {
                    *e = 0.8 * (yn - y1) + 0.4 * dt * (f0 + f1);
                }
                sys.scaled_error(y, &self.yj, &self.est)
            } else {
                f64::INFINITY
            };
            if error <= 1.0 {
                // RKC's controller: with the previous step's error where there is one.
                let mut fac: f64 = 10.0;
                let st = &self.state;
                if st.previous_dt > 0.0 && st.previous_error > 0.0 {
                    let num = 0.8 * dt * st.previous_error.cbrt();
                    let den = st.previous_dt * error.powf(2.0 / 3.0);
                    if num < fac * den {
                        fac = num / den;
                    }
                } else {
                    let den = error.cbrt();
                    if 0.8 < fac * den {
                        fac = 0.8 / den;
                    }
                }
                let mut next = (dt * fac.max(0.1)).min(o.dt_max);
                if rejected > 0 {
                    next = next.min(dt);
                }
                let next = next.max(o.dt_min);
                self.state.previous_error = error.max(1e-10);
                self.state.previous_dt = dt;
                if !landing || next < self.state.dt {
                    self.state.dt = next;
                }
                self.state.since_estimate += 1;
                y.copy_from_slice(&self.yj);
                *t = if landing {
                    t_end.unwrap_or(*t + dt)
                } else {
                    *t + dt
                };
                std::mem::swap(&mut self.f0, &mut self.f_new);
                return Ok(RkcStep {
                    step: RungeKuttaStep {
                        dt,
                        rejected,
                        refused,
                        error,
                        rejected_error,
                        evaluations,
                    },
                    stages: s,
                    spectral_radius: rho,
                    estimates,
                    estimate_evaluations,
                });
            }
            rejected += 1;
            rejected_error = if error.is_nan() { f64::INFINITY } else { error };
            let shrink = if error.is_finite() {
                (0.8 / error.cbrt()).max(0.1)
            } else {
                0.1
            };
            self.state.dt = dt * shrink;
            self.state.estimate_due = true;
            if self.state.dt < o.dt_min {
                return Err(Error::StepTooSmall {
                    tau: self.state.dt,
                    tau_min: o.dt_min,
                }
                .into());
            }
        }
    }

    /// The `s` stages of a step of `dt` from `(t, y)` into `yj`, and `f(t + dt, yj)` into
    /// `f_new` (Verwer, Sommeijer & Hundsdorfer 2004, eqs. (2.3)–(2.6); the recursion of
    /// the RKC code).
    fn stages<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        (t, dt): (f64, f64),
        y: &[f64],
        s: usize,
    ) -> std::result::Result<Stages<S::Error>, S::Error> {
        let sf = s as f64;
        let w0 = 1.0 + 2.0 / (13.0 * sf * sf);
        let temp1 = w0 * w0 - 1.0;
        let temp2 = temp1.sqrt();
        let arg = sf * (w0 + temp2).ln();
        let w1 = arg.sinh() * temp1 / (arg.cosh() * sf * temp2 - w0 * arg.sinh());
        let mut bjm1 = 1.0 / (2.0 * w0).powi(2);
        let mut bjm2 = bjm1;
        // Stage 1.
        let mus = w1 * bjm1;
        self.yjm2.copy_from_slice(y);
        for ((a, &yi), &f) in self.yjm1.iter_mut().zip(y).zip(&self.f0) {
            *a = yi + dt * mus * f;
        }
        let (mut thjm2, mut thjm1) = (0.0, mus);
        let (mut zjm1, mut zjm2) = (w0, 1.0);
        let (mut dzjm1, mut dzjm2) = (1.0, 0.0);
        let (mut d2zjm1, mut d2zjm2) = (0.0, 0.0);
        let mut evaluations = 0;
        for _j in 2..=s {
            let zj = 2.0 * w0 * zjm1 - zjm2;
            let dzj = 2.0 * w0 * dzjm1 - dzjm2 + 2.0 * zjm1;
            let d2zj = 2.0 * w0 * d2zjm1 - d2zjm2 + 4.0 * dzjm1;
            let bj = d2zj / (dzj * dzj);
            let ajm1 = 1.0 - zjm1 * bjm1;
            let mu = 2.0 * w0 * bj / bjm1;
            let nu = -bj / bjm2;
            let mus = mu * w1 / w0;
            let refusal = rate_or_refusal(sys, t + dt * thjm1, &self.yjm1, &mut self.fj)?;
            evaluations += 1;
            if let Some(e) = refusal {
                return Ok(Stages::refused(evaluations, e));
            }
            if self.fj.iter().any(|x| !x.is_finite()) {
                return Ok(Stages {
                    evaluations,
                    finite: false,
                    refusal: None,
                });
            }
            let c0 = 1.0 - mu - nu;
            for (i, yj) in self.yj.iter_mut().enumerate() {
                *yj = mu * self.yjm1[i]
                    + nu * self.yjm2[i]
                    + c0 * y[i]
                    + dt * mus * (self.fj[i] - ajm1 * self.f0[i]);
            }
            let thj = mu * thjm1 + nu * thjm2 + mus * (1.0 - ajm1);
            std::mem::swap(&mut self.yjm2, &mut self.yjm1);
            std::mem::swap(&mut self.yjm1, &mut self.yj);
            (thjm2, thjm1) = (thjm1, thj);
            (bjm2, bjm1) = (bjm1, bj);
            (zjm2, zjm1) = (zjm1, zj);
            (dzjm2, dzjm1) = (dzjm1, dzj);
            (d2zjm2, d2zjm1) = (d2zjm1, d2zj);
        }
        // The new solution is the last stage (now in `yjm1`).
        std::mem::swap(&mut self.yj, &mut self.yjm1);
        let refusal = rate_or_refusal(sys, t + dt, &self.yj, &mut self.f_new)?;
        evaluations += 1;
        if let Some(e) = refusal {
            return Ok(Stages::refused(evaluations, e));
        }
        let finite = self.f_new.iter().chain(&self.yj).all(|x| x.is_finite());
        Ok(Stages {
            evaluations,
            finite,
            refusal: None,
        })
    }
}

/// What the stages of one attempt gave.
struct Stages<E> {
    evaluations: usize,
    /// Whether every stage and the new point's rate are finite.
    finite: bool,
    /// A stage's refusal ([`OdeSystem::outside_domain`]).
    refusal: Option<E>,
}

impl<E> Stages<E> {
    /// The stages of an attempt a stage's refusal `e` ended after `evaluations`.
    fn refused(evaluations: usize, e: E) -> Self {
        Self {
            evaluations,
            finite: false,
            refusal: Some(e),
        }
    }
}

#[cfg(test)]
mod tests;
