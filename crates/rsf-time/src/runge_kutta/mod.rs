//! Explicit embedded Runge–Kutta pairs with adaptive steps for ODE systems `y' = f(t, y)`
//! (docs/math.md §12): the Dormand–Prince 5(4) pair and the Bogacki–Shampine 3(2) pair,
//! both "first same as last", with the PI step-size controller of Hairer, Nørsett & Wanner
//! (Solving Ordinary Differential Equations I, 2nd ed., §II.4 and the code DOPRI5).
//!
//! The system decides what an acceptable error is ([`OdeSystem::scaled_error`], ≤ 1 is
//! accepted), so that mixed absolute/relative tolerances per component stay with the
//! system that knows their units, and which trial points lie outside its domain
//! ([`OdeSystem::outside_domain`]: a stage the rate function refuses, e.g. a normal stress
//! that an overshooting stage drives to zero, rejects the step like a failed error test
//! and retries a smaller one; docs/math.md §12, docs/reliability.md).

use crate::{invalid, Error, Result};

/// A Butcher tableau of an explicit embedded pair with the FSAL property (the last stage
/// is the first of the next step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tableau {
    /// Name for messages ("Dormand–Prince 5(4)").
    pub name: &'static str,
    /// Stages `s` (including the FSAL stage).
    pub stages: usize,
    /// `c_i`, length `s`.
    pub c: &'static [f64],
    /// `a_ij` row by row (row `i` has `i` entries), rows 1..s; the last row is `b`.
    pub a: &'static [&'static [f64]],
    /// `e_i = b_i − b̂_i`: the error estimate is `h Σ e_i k_i`, length `s`.
    pub e: &'static [f64],
    /// Order of the embedded (lower-order) solution `q`: the controller's exponent is
    /// `1/(q + 1)`.
    pub error_order: u32,
}

/// Dormand & Prince (1980), the 5(4) pair of DOPRI5 / `ode45`: 7 stages, 6 evaluations per
/// step.
pub const DORMAND_PRINCE_54: Tableau = Tableau {
    name: "Dormand–Prince 5(4)",
    stages: 7,
    c: &[0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0],
    a: &[
        &[0.2],
        &[3.0 / 40.0, 9.0 / 40.0],
        &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
        &[
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
        ],
        &[
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
        ],
        &[
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ],
    e: &[
        71.0 / 57600.0,
        0.0,
        -71.0 / 16695.0,
        71.0 / 1920.0,
        -17253.0 / 339200.0,
        22.0 / 525.0,
        -1.0 / 40.0,
    ],
    error_order: 4,
};

/// Bogacki & Shampine (1989), the 3(2) pair of `ode23`: 4 stages, 3 evaluations per step.
pub const BOGACKI_SHAMPINE_32: Tableau = Tableau {
    name: "Bogacki–Shampine 3(2)",
    stages: 4,
    c: &[0.0, 0.5, 0.75, 1.0],
    a: &[&[0.5], &[0.0, 0.75], &[2.0 / 9.0, 1.0 / 3.0, 4.0 / 9.0]],
    e: &[
        2.0 / 9.0 - 7.0 / 24.0,
        1.0 / 3.0 - 0.25,
        4.0 / 9.0 - 1.0 / 3.0,
        -0.125,
    ],
    error_order: 2,
};

/// An ODE system `y' = f(t, y)` of fixed dimension.
pub trait OdeSystem {
    /// The system's error type (a failed evaluation; its message is the reason of an
    /// [`Error::TrialPointRefused`]).
    type Error: From<Error> + std::fmt::Display;

    /// Evaluates `f(t, y)` into `dy` (same length as `y`). Non-finite values in `dy` make
    /// the integrator reject the step and retry with a smaller one (a step too large for
    /// a stiff stage), so they need no error.
    ///
    /// # Errors
    /// Failures that a smaller step cannot cure, and trial points outside the system's
    /// domain (those for which [`outside_domain`](Self::outside_domain) is `true`: the
    /// integrator rejects the step and retries a smaller one).
    fn rate(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> std::result::Result<(), Self::Error>;

    /// Whether an error of [`rate`](Self::rate) says that its trial point `y` lies outside
    /// the system's domain (e.g. a state in which a normal stress would be ≤ 0), so that a
    /// smaller step, whose stages stay closer to the accepted point, may cure it. Such an
    /// error at a **stage** of a step is a rejection: the step shrinks by
    /// [`RungeKuttaOptions::refusal_shrink`] and is retried, and after
    /// [`RungeKuttaOptions::max_refusals`] refusals in one step (or a step that would fall
    /// below `dt_min`) the integrator gives up with [`Error::TrialPointRefused`] naming the
    /// time, the step and the reason. At the **accepted** point (the first evaluation of
    /// an integration, where no smaller step exists) the error is returned as it is.
    ///
    /// Default: `false` for every error (every error ends the integration).
    fn outside_domain(&self, _error: &Self::Error) -> bool {
        false
    }

    /// The local error estimate `err` of a step from `y` to `y_new` measured against the
    /// system's tolerances: a step with a value ≤ 1 is accepted. Must return a value ≥ 0
    /// (non-finite for non-finite input).
    fn scaled_error(&self, y: &[f64], y_new: &[f64], err: &[f64]) -> f64;

    /// The weights `w_i` of the error norm into `w` (the length of `y`): a
    /// [`scaled_error`](Self::scaled_error) of `max_i w_i |e_i|` (or a norm as strong).
    /// Implicit steps ([`Rosenbrock`](crate::Rosenbrock)) measure their linear solves and
    /// their finite differences in these weights. Returns `false` if the system does not
    /// give them (the default): every component is then weighed alike, by
    /// `scaled_error` of a vector of ones.
    fn error_weights(&self, _y: &[f64], _w: &mut [f64]) -> bool {
        false
    }

    /// An approximation of the Jacobian `∂f/∂y` at `(t, y)` by independent dense blocks
    /// (the cheap, local part of it: e.g. a node's slip and state with the elastic
    /// operator's diagonal), which implicit steps ([`Rosenbrock`](crate::Rosenbrock))
    /// precondition their linear solves with; `f` is `f(t, y)`. On the first call
    /// `blocks` is empty and the system sets its structure
    /// ([`JacobianBlocks::push_block`](crate::JacobianBlocks::push_block)); at every call
    /// it writes the entries. Returns the evaluations of `f` (or their equivalent in
    /// cost) it took, or `None` if the system gives none (the default: the solves go
    /// unpreconditioned).
    ///
    /// # Errors
    /// The system's errors.
    fn local_jacobian(
        &mut self,
        _t: f64,
        _y: &[f64],
        _f: &[f64],
        _blocks: &mut crate::JacobianBlocks,
    ) -> std::result::Result<Option<usize>, Self::Error> {
        Ok(None)
    }
}

/// Options of [`EmbeddedRungeKutta`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RungeKuttaOptions {
    /// Smallest step (s): below it the integrator gives up with [`Error::StepTooSmall`].
    pub dt_min: f64,
    /// Largest step (s).
    pub dt_max: f64,
    /// Safety factor of the controller (DOPRI5's 0.9).
    pub safety: f64,
    /// Largest growth of the step per accepted step (DOPRI5's 10).
    pub max_growth: f64,
    /// Largest shrinking per rejection (DOPRI5's 0.2; a non-finite stage shrinks by 0.1).
    pub max_shrink: f64,
    /// Exponent β of the PI controller's memory (DOPRI5's 0.04; 0 gives the plain
    /// I-controller).
    pub beta: f64,
    /// Factor by which a step shrinks when the rate function refuses one of its stages
    /// ([`OdeSystem::outside_domain`]; default 0.1, the reduction of a non-finite stage).
    /// In (0, 1).
    pub refusal_shrink: f64,
    /// Most refused attempts of one step ([`OdeSystem::outside_domain`]; default 12: the
    /// step may shrink by `refusal_shrink¹²` = 10⁻¹² before the integrator gives up with
    /// [`Error::TrialPointRefused`]). At least 1.
    pub max_refusals: usize,
}

impl Default for RungeKuttaOptions {
    fn default() -> Self {
        Self {
            dt_min: 1e-12,
            dt_max: f64::INFINITY,
            safety: 0.9,
            max_growth: 10.0,
            max_shrink: 0.2,
            beta: 0.04,
            refusal_shrink: 0.1,
            max_refusals: 12,
        }
    }
}

impl RungeKuttaOptions {
    /// Checks the options.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first invalid option.
    pub fn validate(&self) -> Result<()> {
        if !(self.dt_min > 0.0 && self.dt_min.is_finite()) {
            return invalid("dt_min", self.dt_min, "must be positive and finite");
        }
        if !(self.dt_max >= self.dt_min) {
            return invalid("dt_max", self.dt_max, "must be at least dt_min");
        }
        if !(self.safety > 0.0 && self.safety <= 1.0) {
            return invalid("safety", self.safety, "must be in (0, 1]");
        }
        if !(self.max_growth > 1.0 && self.max_growth.is_finite()) {
            return invalid("max_growth", self.max_growth, "must be finite and > 1");
        }
        if !(self.max_shrink > 0.0 && self.max_shrink < 1.0) {
            return invalid("max_shrink", self.max_shrink, "must be in (0, 1)");
        }
        if !(self.beta >= 0.0 && self.beta < 0.2) {
            return invalid("beta", self.beta, "must be in [0, 0.2)");
        }
        if !(self.refusal_shrink > 0.0 && self.refusal_shrink < 1.0) {
            return invalid("refusal_shrink", self.refusal_shrink, "must be in (0, 1)");
        }
        if self.max_refusals == 0 {
            return invalid("max_refusals", 0.0, "must be at least 1");
        }
        Ok(())
    }
}

/// What one accepted step did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RungeKuttaStep {
    /// The step taken (s).
    pub dt: f64,
    /// Attempts rejected before it (for any reason: a failed error test, a non-finite
    /// stage, a refused stage).
    pub rejected: usize,
    /// Of those, the attempts whose stage the rate function refused as outside its domain
    /// ([`OdeSystem::outside_domain`]).
    pub refused: usize,
    /// Its scaled error estimate (≤ 1).
    pub error: f64,
    /// The scaled error estimate of the last attempt rejected before it (∞ for an attempt
    /// without a finite estimate: a non-finite or refused stage; 0 if none was rejected).
    pub rejected_error: f64,
    /// Evaluations of `f` it took (rejected attempts included).
    pub evaluations: usize,
}

/// The controller's memory: what a checkpoint of an integration must keep to continue it
/// bit for bit (with the state `y` and the time `t`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RungeKuttaState {
    /// The next step to try (s).
    pub dt: f64,
    /// The previous accepted step's error (the PI controller's memory).
    pub previous_error: f64,
}

/// An explicit embedded Runge–Kutta integrator with adaptive steps: call
/// [`step`](Self::step) for one accepted step at a time. Allocates its stages once; a step
/// allocates nothing.
#[derive(Debug, Clone)]
pub struct EmbeddedRungeKutta {
    tableau: Tableau,
    options: RungeKuttaOptions,
    k: Vec<Vec<f64>>,
    stage: Vec<f64>,
    y_new: Vec<f64>,
    err: Vec<f64>,
    /// Whether `k[0]` holds `f(t, y)` of the current point (FSAL).
    fsal: bool,
    state: RungeKuttaState,
    /// The stiffness test's copy of the second-last stage's point (empty when off).
    ysti: Vec<f64>,
    /// `h |λ|` of the last accepted step by the stiffness test (NaN when off).
    stiffness: f64,
}

impl EmbeddedRungeKutta {
    /// An integrator for systems of dimension `n` with the first step `dt0` (s).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid options or `dt0` outside
    /// `[dt_min, dt_max]`.
    pub fn new(tableau: Tableau, options: RungeKuttaOptions, n: usize, dt0: f64) -> Result<Self> {
        options.validate()?;
        if !(dt0 >= options.dt_min && dt0 <= options.dt_max) {
            return Err(Error::InvalidParameter {
                name: "dt0",
                value: dt0,
                requirement: "must be in [dt_min, dt_max]",
            });
        }
        Ok(Self {
            tableau,
            options,
            k: vec![vec![0.0; n]; tableau.stages],
            stage: vec![0.0; n],
            y_new: vec![0.0; n],
            err: vec![0.0; n],
            fsal: false,
            state: RungeKuttaState {
                dt: dt0,
                previous_error: 1e-4,
            },
            ysti: Vec::new(),
            stiffness: f64::NAN,
        })
    }

    /// Turns on the stiffness test of DOPRI5 (Hairer & Wanner, *Solving Ordinary
    /// Differential Equations II*, §IV.2): after every accepted step
    /// `h |λ| ≈ h ‖k_s − k_{s−1}‖ / ‖y_{n+1} − g_{s−1}‖` from the last two stages, which
    /// share `c = 1` (`g` a stage's point), read by [`stiffness`](Self::stiffness). Costs a
    /// copy of one stage per attempt.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `tableau` for a pair whose last two stages do not
    /// share `c = 1` (Bogacki–Shampine 3(2)).
    pub fn detect_stiffness(&mut self) -> Result<()> {
        let c = self.tableau.c;
        let s = self.tableau.stages;
        if !(s >= 2 && c[s - 1] == 1.0 && c[s - 2] == 1.0) {
            return Err(Error::InvalidParameter {
                name: "tableau",
                value: s as f64,
                requirement: "the stiffness test needs the last two stages at c = 1 \
                              (Dormand–Prince 5(4))",
            });
        }
        self.ysti = vec![0.0; self.stage.len()];
        Ok(())
    }

    /// `h |λ|` of the last accepted step by the stiffness test (DOPRI5's `HLAMB`: its pair
    /// is stable on the negative real axis up to about 3.3); NaN unless
    /// [`detect_stiffness`](Self::detect_stiffness) is on or before the first step.
    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// The pair in use.
    pub fn tableau(&self) -> &Tableau {
        &self.tableau
    }

    /// The controller's state (for checkpoints).
    pub fn state(&self) -> RungeKuttaState {
        self.state
    }

    /// Continues from a saved controller state; the next step evaluates `f` afresh at its
    /// start (`f(t, y)` is a function of `t` and `y`, so the result does not change).
    pub fn set_state(&mut self, state: RungeKuttaState) {
        self.state = state;
        self.fsal = false;
    }

    /// Continues from a saved controller state and the saved rate `f(t, y)` of the current
    /// point (the first stage of the next step, as [`current_rate`](Self::current_rate)
    /// gave it): bit-identical to the integration that saved them, also after a step that
    /// landed on an end time (whose rate was evaluated at `t + (t_end − t)`, which may
    /// differ from `t_end` in the last bit).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for a rate of another length than the state.
    pub fn restore(&mut self, state: RungeKuttaState, rate: &[f64]) -> Result<()> {
        let n = self.stage.len();
        if rate.len() != n {
            return Err(Error::DimensionMismatch {
                what: "saved rate",
                expected: n,
                got: rate.len(),
            });
        }
        self.state = state;
        self.k[0].copy_from_slice(rate);
        self.fsal = true;
        Ok(())
    }

    /// `f(t, y)` of the current point, if known (after a step: the FSAL stage).
    pub fn current_rate(&self) -> Option<&[f64]> {
        self.fsal.then_some(self.k[0].as_slice())
    }

    /// One accepted step from `(t, y)`, updating both; at most up to `t_end` (the step is
    /// shortened to land on it, and the controller's proposal is kept for the next one).
    /// A stage outside the system's domain ([`OdeSystem::outside_domain`]) rejects the
    /// attempt and shrinks the step by `refusal_shrink`.
    ///
    /// # Errors
    /// [`Error::StepTooSmall`] (as `S::Error`) when the step would fall below `dt_min`;
    /// [`Error::TrialPointRefused`] after `max_refusals` refused attempts of this step or
    /// when a refusal would take the step below `dt_min`; [`Error::DimensionMismatch`] for
    /// a `y` of another length; the system's errors (also a refusal at the current point,
    /// the first evaluation of an integration).
    pub fn step<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: &mut f64,
        y: &mut [f64],
        t_end: Option<f64>,
    ) -> std::result::Result<RungeKuttaStep, S::Error> {
        let n = self.stage.len();
        check_step(n, y, *t, t_end)?;
        let tab = self.tableau;
        let o = self.options;
        let mut evaluations = 0;
        if !self.fsal {
            sys.rate(*t, y, &mut self.k[0])?;
            evaluations += 1;
            self.fsal = true;
        }
        let mut rejected = 0;
        let mut refused = 0;
        let mut rejected_error = 0.0;
        loop {
            let (dt, landing) = next_attempt(&o, *t, self.state.dt, t_end)?;
            // Stages 2..s; the last stage's argument is the new solution (FSAL).
            let mut finite = true;
            let mut refusal = None;
            for i in 1..tab.stages {
                if i == tab.stages - 1 && !self.ysti.is_empty() {
                    self.ysti.copy_from_slice(&self.stage);
                }
                combine(&mut self.stage, tab.a[i - 1], &self.k);
                for (s, &yj) in self.stage.iter_mut().zip(y.iter()) {
                    *s = yj + dt * *s;
                }
                refusal = rate_or_refusal(sys, *t + tab.c[i] * dt, &self.stage, &mut self.k[i])?;
                evaluations += 1;
                if refusal.is_some() {
                    break;
                }
                if self.k[i].iter().any(|x| !x.is_finite()) {
                    finite = false;
                    break;
                }
            }
            if let Some(e) = refusal {
                // Outside the domain: a strong reduction, a typed error after too many.
                rejected += 1;
                refused += 1;
                rejected_error = f64::INFINITY;
                self.state.dt = after_refusal(&o, (*t, dt), refused, &e)?;
                continue;
            }
            let error = if finite {
                self.y_new.copy_from_slice(&self.stage);
                combine(&mut self.err, tab.e, &self.k);
                for e in &mut self.err {
                    *e *= dt;
                }
                sys.scaled_error(y, &self.y_new, &self.err)
            } else {
                f64::INFINITY
            };
            if error <= 1.0 {
                let next = accepted_next(&o, &mut self.state, (dt, error), tab.error_order);
                if !landing || next < self.state.dt {
                    self.state.dt = next;
                }
                y.copy_from_slice(&self.y_new);
                *t = if landing {
                    t_end.unwrap_or(*t + dt)
                } else {
                    *t + dt
                };
                let last = tab.stages - 1;
                if !self.ysti.is_empty() {
                    let (mut num, mut den) = (0.0, 0.0);
                    for i in 0..n {
                        num += (self.k[last][i] - self.k[last - 1][i]).powi(2);
                        den += (self.y_new[i] - self.ysti[i]).powi(2);
                    }
                    self.stiffness = if den > 0.0 {
                        dt * (num / den).sqrt()
                    } else {
                        0.0
                    };
                }
                self.k.swap(0, last);
                return Ok(RungeKuttaStep {
                    dt,
                    rejected,
                    refused,
                    error,
                    rejected_error,
                    evaluations,
                });
            }
            rejected += 1;
            rejected_error = if error.is_nan() { f64::INFINITY } else { error };
            self.state.dt = rejected_next(&o, dt, error, tab.error_order);
            if self.state.dt < o.dt_min {
                return Err(Error::StepTooSmall {
                    tau: self.state.dt,
                    tau_min: o.dt_min,
                }
                .into());
            }
        }
    }
}

/// The next step after an accepted one of `dt` with scaled error `error` (DOPRI5's PI
/// controller, exponents from the embedded solution's order `error_order`); updates the
/// controller's memory.
pub(crate) fn accepted_next(
    o: &RungeKuttaOptions,
    state: &mut RungeKuttaState,
    (dt, error): (f64, f64),
    error_order: u32,
) -> f64 {
    let exponent = 1.0 / f64::from(error_order + 1) - 0.75 * o.beta;
    let fac = error.max(1e-300).powf(exponent) / state.previous_error.powf(o.beta);
    let fac = (fac / o.safety).clamp(1.0 / o.max_growth, 1.0 / o.max_shrink);
    state.previous_error = error.max(1e-4);
    (dt / fac).min(o.dt_max)
}

/// The step after a rejected attempt of `dt` with scaled error `error` (∞ or NaN for a
/// failed attempt: a tenth).
pub(crate) fn rejected_next(o: &RungeKuttaOptions, dt: f64, error: f64, error_order: u32) -> f64 {
    let shrink = if error.is_finite() {
        (error.powf(1.0 / f64::from(error_order + 1)) / o.safety).clamp(1.0, 1.0 / o.max_shrink)
    } else {
        10.0
    };
    dt / shrink
}

/// The checks at the start of an adaptive step of either integrator: `y` of length `n`,
/// `t_end` (if any) after `t`.
pub(crate) fn check_step(n: usize, y: &[f64], t: f64, t_end: Option<f64>) -> Result<()> {
    if y.len() != n {
        return Err(Error::DimensionMismatch {
            what: "ODE state",
            expected: n,
            got: y.len(),
        });
    }
    if let Some(te) = t_end {
        if !(te > t) {
            return Err(Error::InvalidParameter {
                name: "t_end",
                value: te,
                requirement: "must be after the current time",
            });
        }
    }
    Ok(())
}

/// The step to try from `t` with the controller's `proposal`, and whether it lands on
/// `t_end` (a proposal within 1e-12 of it is stretched to land).
pub(crate) fn landing_step(t: f64, proposal: f64, t_end: Option<f64>) -> (f64, bool) {
    match t_end {
        Some(te) if t + proposal >= te - 1e-12 * proposal => (te - t, true),
        _ => (proposal, false),
    }
}

/// The step to attempt from `t`: the controller's `proposal` capped at `dt_max` and
/// [`landing_step`]'s, with whether it lands on `t_end`.
///
/// # Errors
/// [`Error::StepTooSmall`] for a step below `dt_min` that does not land on `t_end`.
pub(crate) fn next_attempt(
    o: &RungeKuttaOptions,
    t: f64,
    proposal: f64,
    t_end: Option<f64>,
) -> Result<(f64, bool)> {
    let (dt, landing) = landing_step(t, proposal.min(o.dt_max), t_end);
    check_step_size(o, dt, landing)?;
    Ok((dt, landing))
}

/// [`Error::StepTooSmall`] for a step `dt` below `dt_min` that does not land on `t_end`.
pub(crate) fn check_step_size(o: &RungeKuttaOptions, dt: f64, landing: bool) -> Result<()> {
    if !(dt >= o.dt_min) && !landing {
        return Err(Error::StepTooSmall {
            tau: dt,
            tau_min: o.dt_min,
        });
    }
    Ok(())
}

/// `f(t, y)` into `dy`: `Ok(None)` when evaluated, `Ok(Some(e))` when the system refuses
/// the point as outside its domain ([`OdeSystem::outside_domain`]), `Err` for its other
/// errors.
pub(crate) fn rate_or_refusal<S: OdeSystem>(
    sys: &mut S,
    t: f64,
    y: &[f64],
    dy: &mut [f64],
) -> std::result::Result<Option<S::Error>, S::Error> {
    match sys.rate(t, y, dy) {
        Ok(()) => Ok(None),
        Err(e) if sys.outside_domain(&e) => Ok(Some(e)),
        Err(e) => Err(e),
    }
}

/// The next step after the `refused`-th refused attempt of a step `dt` from `time`
/// (`refusal_shrink`), or [`Error::TrialPointRefused`] after `max_refusals` or below
/// `dt_min`.
pub(crate) fn after_refusal(
    o: &RungeKuttaOptions,
    (time, dt): (f64, f64),
    refused: usize,
    reason: &dyn std::fmt::Display,
) -> Result<f64> {
    let next = dt * o.refusal_shrink;
    if refused >= o.max_refusals || next < o.dt_min {
        return Err(Error::TrialPointRefused {
            time,
            dt,
            refusals: refused,
            reason: reason.to_string(),
        });
    }
    Ok(next)
}

/// `out = Σ_l c_l k_l` over the nonzero `c_l`, summed in the order of `l` from `0.0`
/// (entry by entry the same additions as a scalar loop over `l`, so the same bits), one
/// vectorisable pass per nonzero coefficient.
fn combine(out: &mut [f64], c: &[f64], k: &[Vec<f64>]) {
    out.fill(0.0);
    for (&cl, kl) in c.iter().zip(k) {
        if cl != 0.0 {
            for (o, &x) in out.iter_mut().zip(kl) {
                *o += cl * x;
            }
        }
    }
}

#[cfg(test)]
mod tests;
