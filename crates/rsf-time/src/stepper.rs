//! One adaptive integrator of `y' = f(t, y)` chosen at run time ([`OdeIntegrator`]): an
//! explicit embedded pair, the stabilised RKC2 ([`Rkc2`]), the linearly implicit
//! ROS34PW2 ([`Rosenbrock`]), or `auto`, which steps with
//! Dormand–Prince 5(4) while its step is set by accuracy and with RKC2 while the step
//! would be set by stability (docs/math.md §12, "Stiff steps").
//!
//! `auto`'s two tests, each on accepted steps:
//! - **Dormand–Prince → RKC2**: DOPRI5's stiffness test (Hairer & Wanner, *Solving ODEs
//!   II*, §IV.2; [`EmbeddedRungeKutta::detect_stiffness`]): `h |λ| > 3.25` (the pair's
//!   stability limit on the negative real axis is ≈ 3.3) in
//!   [`AutoOptions::stiff_steps`] steps in a row (DOPRI5's 15; six steps below it in a row
//!   start the count again). The pair's step is then held by stability, not accuracy.
//! - **RKC2 → Dormand–Prince**: `h ρ ≤` [`AutoOptions::explicit_below`] (default 1.1) in
//!   [`AutoOptions::stiff_steps`] steps in a row, `h` the RKC2 step accuracy allows and
//!   `ρ` its spectral radius estimate: then two RKC2 stages per `h` cost more than the
//!   pair's six per `3.3/ρ`, the largest step stability would let the pair take.
//!
//! Each switch hands over the current point's rate (no evaluation is repeated) and the
//! step the other method proposed.

use crate::rosenbrock::{Rosenbrock, RosenbrockOptions};
use crate::runge_kutta::{
    EmbeddedRungeKutta, OdeSystem, RungeKuttaOptions, RungeKuttaState, RungeKuttaStep,
    BOGACKI_SHAMPINE_32, DORMAND_PRINCE_54,
};
use crate::stabilized::{Rkc2, RkcOptions, RkcState};
use crate::{invalid, Error, Result};

/// The integrator of an ODE system, chosen by name: `auto`, `rkc`, `rosenbrock`,
/// `dormand-prince`, `bogacki-shampine` (`name`, `FromStr`, serde, clap).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum OdeIntegrator {
    /// Dormand–Prince 5(4) while accuracy sets its step, RKC2 while stability would
    /// (module docs).
    Auto,
    /// The stabilised RKC2 ([`Rkc2`]) throughout.
    Rkc,
    /// The Rosenbrock-W method ROS34PW2 ([`Rosenbrock`]: order 3, L-stable, matrix-free
    /// GMRES solves preconditioned by the system's local Jacobian) throughout.
    Rosenbrock,
    /// The Dormand–Prince 5(4) pair ([`DORMAND_PRINCE_54`]) throughout.
    #[default]
    DormandPrince,
    /// The Bogacki–Shampine 3(2) pair ([`BOGACKI_SHAMPINE_32`]) throughout.
    BogackiShampine,
}

impl OdeIntegrator {
    /// Every choice, in declaration order.
    pub const ALL: [OdeIntegrator; 5] = [
        Self::Auto,
        Self::Rkc,
        Self::Rosenbrock,
        Self::DormandPrince,
        Self::BogackiShampine,
    ];

    /// The name: `auto`, `rkc`, `rosenbrock`, `dormand-prince`, `bogacki-shampine`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Rkc => "rkc",
            Self::Rosenbrock => "rosenbrock",
            Self::DormandPrince => "dormand-prince",
            Self::BogackiShampine => "bogacki-shampine",
        }
    }

    /// Whether it uses RKC2 (and so keeps a [`StabilizedMemory`]).
    pub fn stabilized(self) -> bool {
        matches!(self, Self::Auto | Self::Rkc)
    }
}

rsf_numeric::display_and_parse_by_name!(OdeIntegrator, "integrator", Error, OdeIntegrator::ALL);

#[cfg(feature = "clap")]
rsf_numeric::clap_value_enum!(OdeIntegrator, |i| match i {
    OdeIntegrator::Auto => {
        "Dormand–Prince 5(4) where accuracy sets the step, RKC2 where stability would"
    }
    OdeIntegrator::Rkc => "RKC2, stabilised explicit Runge–Kutta–Chebyshev (stiff)",
    OdeIntegrator::Rosenbrock => {
        "ROS34PW2, Rosenbrock-W (order 3, L-stable) with matrix-free GMRES (stiff)"
    }
    OdeIntegrator::DormandPrince => "Dormand–Prince 5(4) explicit pair",
    OdeIntegrator::BogackiShampine => "Bogacki–Shampine 3(2) explicit pair",
});

/// Options of `auto` ([`OdeIntegrator::Auto`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct AutoOptions {
    /// Accepted steps in a row that a test must pass before the method changes (DOPRI5's
    /// 15). At least 1.
    pub stiff_steps: u32,
    /// `h |λ|` above which a Dormand–Prince step counts as held by stability (DOPRI5's
    /// 3.25). Positive.
    pub stiff_above: f64,
    /// `h ρ` at or below which an RKC2 step counts as not held by stability (default 1.1:
    /// two stages per `h` then cost at least the pair's six per `3.3/ρ`). Positive.
    pub explicit_below: f64,
}

impl Default for AutoOptions {
    fn default() -> Self {
        Self {
            stiff_steps: 15,
            stiff_above: 3.25,
            explicit_below: 1.1,
        }
    }
}

impl AutoOptions {
    /// Checks the options.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first invalid option.
    pub fn validate(&self) -> Result<()> {
        if self.stiff_steps == 0 {
            return invalid("stiff_steps", 0.0, "must be at least 1");
        }
        for (name, value) in [
            ("stiff_above", self.stiff_above),
            ("explicit_below", self.explicit_below),
        ] {
            if !(value > 0.0 && value.is_finite()) {
                return invalid(name, value, "must be positive and finite");
            }
        }
        Ok(())
    }
}

/// Which method an [`OdeStepper`] steps with now.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum StepperMode {
    /// The explicit pair.
    #[default]
    Explicit,
    /// RKC2.
    Stabilized,
    /// ROS34PW2.
    Implicit,
}

/// The memory of the RKC2 part of an [`OdeStepper`] (`rkc` and `auto`): with the explicit
/// pair's [`RungeKuttaState`], `t`, `y` and the current rate, what continues it bit for
/// bit.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StabilizedMemory {
    /// The method in use.
    pub mode: StepperMode,
    /// `auto`'s count of steps in a row that passed the test of leaving the mode.
    pub streak: u32,
    /// `auto`'s count of Dormand–Prince steps in a row below the stiffness limit (six
    /// start the stiff count again, as in DOPRI5).
    pub calm: u32,
    /// RKC2's memory.
    pub rkc: RkcState,
}

/// What an [`OdeStepper`] did in this process (not saved in checkpoints).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepperStats {
    /// Accepted steps of the explicit pair.
    pub explicit_steps: usize,
    /// Accepted steps of RKC2.
    pub stabilized_steps: usize,
    /// Simulated time stepped by the explicit pair (s).
    pub explicit_time: f64,
    /// Simulated time stepped by RKC2 (s).
    pub stabilized_time: f64,
    /// Evaluations of the explicit pair's steps.
    pub explicit_evaluations: usize,
    /// Evaluations of RKC2's steps (estimates included).
    pub stabilized_evaluations: usize,
    /// Changes of method (`auto`).
    pub switches: usize,
    /// Spectral radius estimates.
    pub estimates: usize,
    /// Evaluations the estimates took.
    pub estimate_evaluations: usize,
    /// Most stages of an accepted RKC2 step.
    pub max_stages: usize,
    /// The last spectral radius estimate (safety factor included; 1/s; 0 if none).
    pub spectral_radius: f64,
    /// The largest spectral radius estimate (1/s).
    pub max_spectral_radius: f64,
    /// Accepted steps of ROS34PW2.
    pub implicit_steps: usize,
    /// Simulated time stepped by ROS34PW2 (s).
    pub implicit_time: f64,
    /// Evaluations of ROS34PW2's steps (GMRES iterations included).
    pub implicit_evaluations: usize,
    /// GMRES iterations of ROS34PW2's steps.
    pub krylov_iterations: usize,
    /// ROS34PW2's attempts rejected for a linear solve that did not converge.
    pub linear_failures: usize,
    /// Simulated time of the explicit pair's steps that ran DOPRI5's stiffness test
    /// (`auto`; s).
    pub tested_time: f64,
    /// `∫ h|λ| dt` over those steps (s): divided by `tested_time`, the time-weighted mean
    /// of `h|λ|`, whose ratio to the pair's stability limit ≈ 3.3 says how close to it the
    /// steps that take the simulated time ran.
    pub stiffness_integral: f64,
    /// Simulated time of the tested steps with `h|λ|` above `stiff_above` (3.25: held by
    /// stability; s).
    pub held_time: f64,
}

impl StepperStats {
    /// Counts an accepted step of `mode` that advanced the time by `dt` (s) with
    /// `evaluations` evaluations.
    fn count(&mut self, mode: StepperMode, dt: f64, evaluations: usize) {
        let (steps, time, evals) = match mode {
            StepperMode::Explicit => (
                &mut self.explicit_steps,
                &mut self.explicit_time,
                &mut self.explicit_evaluations,
            ),
            StepperMode::Stabilized => (
                &mut self.stabilized_steps,
                &mut self.stabilized_time,
                &mut self.stabilized_evaluations,
            ),
            StepperMode::Implicit => (
                &mut self.implicit_steps,
                &mut self.implicit_time,
                &mut self.implicit_evaluations,
            ),
        };
        *steps += 1;
        *time += dt;
        *evals += evaluations;
    }
}

/// What one accepted step of an [`OdeStepper`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct OdeStep {
    /// The step, its rejections and evaluations (estimates included).
    pub step: RungeKuttaStep,
    /// The method that took it.
    pub mode: StepperMode,
    /// RKC2's stages (0 for the explicit pair).
    pub stages: usize,
}

/// The adaptive integrator an [`OdeIntegrator`] names, with one interface: one accepted
/// step at a time, the current rate (FSAL), the memory to checkpoint.
#[derive(Debug, Clone)]
pub struct OdeStepper {
    choice: OdeIntegrator,
    auto: AutoOptions,
    explicit: EmbeddedRungeKutta,
    rkc: Option<Rkc2>,
    rosenbrock: Option<Rosenbrock>,
    mode: StepperMode,
    streak: u32,
    calm: u32,
    stats: StepperStats,
}

impl OdeStepper {
    /// The integrator `choice` for systems of dimension `n`, first step `dt0` (s); the
    /// options of the pairs' steps, RKC2's, `auto`'s and ROS34PW2's linear solves.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid options or a `dt0` outside
    /// `[dt_min, dt_max]`.
    pub fn new(
        choice: OdeIntegrator,
        options: (
            RungeKuttaOptions,
            RkcOptions,
            AutoOptions,
            RosenbrockOptions,
        ),
        n: usize,
        dt0: f64,
    ) -> Result<Self> {
        let (rk, rkc, auto, ros) = options;
        auto.validate()?;
        ros.validate()?;
        let tableau = match choice {
            OdeIntegrator::BogackiShampine => BOGACKI_SHAMPINE_32,
            _ => DORMAND_PRINCE_54,
        };
        let mut explicit = EmbeddedRungeKutta::new(tableau, rk, n, dt0)?;
        if choice == OdeIntegrator::Auto {
            explicit.detect_stiffness()?;
        }
        let rkc = match choice.stabilized() {
            true => Some(Rkc2::new(rk, rkc, n, dt0)?),
            false => None,
        };
        let rosenbrock = match choice {
            OdeIntegrator::Rosenbrock => Some(Rosenbrock::new(rk, ros, n, dt0)?),
            _ => None,
        };
        Ok(Self {
            choice,
            auto,
            explicit,
            rkc,
            rosenbrock,
            mode: Self::first_mode(choice),
            streak: 0,
            calm: 0,
            stats: StepperStats::default(),
        })
    }

    /// The choice it was made with.
    pub fn choice(&self) -> OdeIntegrator {
        self.choice
    }

    /// The method in use.
    pub fn mode(&self) -> StepperMode {
        self.mode
    }

    /// What it did in this process.
    pub fn stats(&self) -> StepperStats {
        self.stats
    }

    /// The method a run of `choice` starts with.
    fn first_mode(choice: OdeIntegrator) -> StepperMode {
        match choice {
            OdeIntegrator::Rkc => StepperMode::Stabilized,
            OdeIntegrator::Rosenbrock => StepperMode::Implicit,
            _ => StepperMode::Explicit,
        }
    }

    /// The step controller's state of the method in use: the next step (s) and its last
    /// error (RKC2's `previous_error` where it has none yet: 1e-4, as the pair's start).
    pub fn controller(&self) -> RungeKuttaState {
        if let Some(r) = &self.rosenbrock {
            return r.state();
        }
        match (self.mode, &self.rkc) {
            (StepperMode::Stabilized, Some(r)) => RungeKuttaState {
                dt: r.state().dt,
                previous_error: if r.state().previous_error > 0.0 {
                    r.state().previous_error
                } else {
                    1e-4
                },
            },
            _ => self.explicit.state(),
        }
    }

    /// The controller state a checkpoint keeps: the explicit pair's, or ROS34PW2's for
    /// [`OdeIntegrator::Rosenbrock`] (its whole memory: [`Rosenbrock`]).
    pub fn explicit_state(&self) -> RungeKuttaState {
        match &self.rosenbrock {
            Some(r) => r.state(),
            None => self.explicit.state(),
        }
    }

    /// RKC2's memory and `auto`'s (for checkpoints; `None` for an explicit pair alone).
    pub fn stabilized_memory(&self) -> Option<StabilizedMemory> {
        self.rkc.as_ref().map(|r| StabilizedMemory {
            mode: self.mode,
            streak: self.streak,
            calm: self.calm,
            rkc: r.state().clone(),
        })
    }

    /// `f(t, y)` of the current point, if known.
    pub fn current_rate(&self) -> Option<&[f64]> {
        if let Some(r) = &self.rosenbrock {
            return r.current_rate();
        }
        match (self.mode, &self.rkc) {
            (StepperMode::Stabilized, Some(r)) => r.current_rate(),
            _ => self.explicit.current_rate(),
        }
    }

    /// Continues from saved memories and the rate `f(t, y)` of the current point:
    /// bit-identical to the integration that saved them. Without a `stabilized` memory
    /// (a checkpoint of an explicit pair) RKC2 starts afresh from the pair's step; with
    /// one and an explicit pair alone, the memory is ignored: the run goes on with the
    /// pair (a change of integrator, which continues the trajectory, not its bits).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for a rate or eigenvector of another length;
    /// [`Error::InvalidParameter`] for a step outside `[dt_min, dt_max]`.
    pub fn restore(
        &mut self,
        explicit: RungeKuttaState,
        stabilized: Option<&StabilizedMemory>,
        rate: &[f64],
    ) -> Result<()> {
        self.explicit.restore(explicit, rate)?;
        self.streak = 0;
        self.calm = 0;
        if let Some(r) = &mut self.rosenbrock {
            r.restore(explicit, rate)?;
            self.mode = StepperMode::Implicit;
            return Ok(());
        }
        let Some(rkc) = &mut self.rkc else {
            self.mode = StepperMode::Explicit;
            return Ok(());
        };
        match stabilized {
            Some(m) => {
                rkc.restore(m.rkc.clone(), rate)?;
                self.mode = m.mode;
                self.streak = m.streak;
                self.calm = m.calm;
            }
            None => rkc.restore(RkcState::starting(explicit.dt), rate)?,
        }
        match self.choice {
            OdeIntegrator::Rkc => self.mode = StepperMode::Stabilized,
            OdeIntegrator::Auto => {}
            _ => self.mode = StepperMode::Explicit,
        }
        Ok(())
    }

    /// Starts afresh from a new point (the rate evaluated at the next step) with the first
    /// step `dt`: the explicit pair's memory, RKC2's (the spectral radius estimated again)
    /// and `auto`'s test counts reset; `auto` starts with the explicit pair.
    pub fn restart(&mut self, dt: f64) {
        self.explicit.set_state(RungeKuttaState {
            dt,
            previous_error: 1e-4,
        });
        if let Some(r) = &mut self.rkc {
            r.set_state(RkcState::starting(dt));
        }
        if let Some(r) = &mut self.rosenbrock {
            r.set_state(RungeKuttaState {
                dt,
                previous_error: 1e-4,
            });
        }
        self.streak = 0;
        self.calm = 0;
        self.mode = Self::first_mode(self.choice);
    }

    /// One accepted step from `(t, y)`, at most up to `t_end`, by the method in use; then
    /// `auto`'s tests.
    ///
    /// # Errors
    /// Those of [`EmbeddedRungeKutta::step`], [`Rkc2::step`] and [`Rosenbrock::step`].
    pub fn step<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: &mut f64,
        y: &mut [f64],
        t_end: Option<f64>,
    ) -> std::result::Result<OdeStep, S::Error> {
        let t0 = *t;
        if let Some(ros) = &mut self.rosenbrock {
            let r = ros.step(sys, t, y, t_end)?;
            let st = &mut self.stats;
            st.count(StepperMode::Implicit, *t - t0, r.step.evaluations);
            st.krylov_iterations += r.krylov_iterations;
            st.linear_failures += r.linear_failures;
            return Ok(OdeStep {
                step: r.step,
                mode: StepperMode::Implicit,
                stages: 0,
            });
        }
        let taken = match (self.mode, &mut self.rkc) {
            (StepperMode::Stabilized, Some(rkc)) => {
                let r = rkc.step(sys, t, y, t_end)?;
                let st = &mut self.stats;
                st.count(StepperMode::Stabilized, *t - t0, r.step.evaluations);
                st.estimates += r.estimates;
                st.estimate_evaluations += r.estimate_evaluations;
                st.max_stages = st.max_stages.max(r.stages);
                st.spectral_radius = r.spectral_radius;
                st.max_spectral_radius = st.max_spectral_radius.max(r.spectral_radius);
                OdeStep {
                    step: r.step,
                    mode: StepperMode::Stabilized,
                    stages: r.stages,
                }
            }
            _ => {
                let r = self.explicit.step(sys, t, y, t_end)?;
                let st = &mut self.stats;
                st.count(StepperMode::Explicit, *t - t0, r.evaluations);
                let h_lambda = self.explicit.stiffness();
                if h_lambda.is_finite() {
                    st.tested_time += *t - t0;
                    st.stiffness_integral += h_lambda * (*t - t0);
                    if h_lambda > self.auto.stiff_above {
                        st.held_time += *t - t0;
                    }
                }
                OdeStep {
                    step: r,
                    mode: StepperMode::Explicit,
                    stages: 0,
                }
            }
        };
        if self.choice == OdeIntegrator::Auto {
            self.switch_if_due(&taken);
        }
        Ok(taken)
    }

    /// `auto`'s tests after an accepted step (module docs).
    fn switch_if_due(&mut self, taken: &OdeStep) {
        let Some(rkc) = &mut self.rkc else {
            return;
        };
        let a = self.auto;
        match self.mode {
            StepperMode::Explicit => {
                let h_lambda = self.explicit.stiffness();
                if h_lambda > a.stiff_above {
                    self.calm = 0;
                    self.streak += 1;
                } else {
                    self.calm += 1;
                    if self.calm >= 6 {
                        self.streak = 0;
                    }
                }
                if self.streak >= a.stiff_steps {
                    let rate = self
                        .explicit
                        .current_rate()
                        .expect("set by an accepted step");
                    // RKC2 from the pair's step; its spectral radius estimated first.
                    let mut memory = rkc.state().clone();
                    memory.dt = self.explicit.state().dt;
                    memory.previous_error = 0.0;
                    memory.previous_dt = 0.0;
                    memory.estimate_due = true;
                    rkc.restore(memory, rate)
                        .expect("the same dimension and step limits");
                    self.mode = StepperMode::Stabilized;
                    self.streak = 0;
                    self.calm = 0;
                    self.stats.switches += 1;
                }
            }
            StepperMode::Implicit => {}
            StepperMode::Stabilized => {
                let st = rkc.state();
                let h_rho = taken.step.dt * st.spectral_radius;
                if h_rho <= a.explicit_below {
                    self.streak += 1;
                } else {
                    self.streak = 0;
                }
                if self.streak >= a.stiff_steps {
                    let rate = rkc.current_rate().expect("set by an accepted step");
                    let dt = st.dt;
                    self.explicit
                        .restore(
                            RungeKuttaState {
                                dt,
                                previous_error: 1e-4,
                            },
                            rate,
                        )
                        .expect("the same dimension");
                    self.mode = StepperMode::Explicit;
                    self.streak = 0;
                    self.calm = 0;
                    self.stats.switches += 1;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `y' = −λ (y − cos t) − sin t` per component, `λ_i` over `[1, λ_max]`; with `kick`
    /// a transient `y(0) = 1 + kick` that decays at every `λ_i`.
    struct Relaxation {
        lambda: Vec<f64>,
    }

    impl OdeSystem for Relaxation {
        type Error = Error;
        fn rate(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
            for ((d, &yi), &l) in dy.iter_mut().zip(y).zip(&self.lambda) {
                *d = -l * (yi - t.cos()) - t.sin();
            }
            Ok(())
        }
        fn scaled_error(&self, _y: &[f64], _y_new: &[f64], err: &[f64]) -> f64 {
            err.iter().fold(0.0_f64, |m, e| m.max(e.abs())) / 1e-7
        }
    }

    fn run(choice: OdeIntegrator, lambda_max: f64, t_end: f64) -> (Vec<u64>, OdeStepper, usize) {
        let n = 6;
        let lambda = (0..n)
            .map(|i| lambda_max.powf(i as f64 / (n - 1) as f64))
            .collect();
        let mut sys = Relaxation { lambda };
        let options = (
            RungeKuttaOptions::default(),
            RkcOptions::default(),
            AutoOptions::default(),
            RosenbrockOptions::default(),
        );
        let mut stepper = OdeStepper::new(choice, options, n, 1e-4).unwrap();
        let (mut t, mut y) = (0.0, vec![1.5; n]);
        let mut steps = 0;
        while t < t_end {
            stepper.step(&mut sys, &mut t, &mut y, Some(t_end)).unwrap();
            steps += 1;
        }
        let bits = y.iter().map(|v| v.to_bits()).collect();
        (bits, stepper, steps)
    }

    /// On a problem that never gets stiff for the pair, `auto` is the pair to the bit.
    #[test]
    fn auto_is_the_pair_where_the_pair_is_not_held_by_stability() {
        let (auto, stepper, _) = run(OdeIntegrator::Auto, 1.0, 5.0);
        let (pair, _, _) = run(OdeIntegrator::DormandPrince, 1.0, 5.0);
        assert_eq!(auto, pair);
        assert_eq!(stepper.stats().switches, 0);
        assert_eq!(stepper.stats().stabilized_steps, 0);
    }

    /// On a stiff problem whose transient ends early `auto` changes to RKC2 once the
    /// pair's steps are held by stability and takes far fewer steps than the pair; its
    /// answer agrees with the pair's within the tolerance's reach.
    #[test]
    fn auto_changes_to_rkc_where_the_pair_is_held_by_stability() {
        let (auto, stepper, n_auto) = run(OdeIntegrator::Auto, 1e5, 3.0);
        let (pair, _, n_pair) = run(OdeIntegrator::DormandPrince, 1e5, 3.0);
        let st = stepper.stats();
        println!("auto: {n_auto} steps ({st:?}); Dormand–Prince {n_pair} steps");
        assert!(st.switches >= 1 && st.stabilized_steps > 0, "{st:?}");
        assert!(10 * n_auto < n_pair, "{n_auto} against {n_pair}");
        for (a, p) in auto.iter().zip(&pair) {
            let (a, p) = (f64::from_bits(*a), f64::from_bits(*p));
            assert!((a - p).abs() < 1e-4, "{a} against {p}");
        }
    }

    /// A stepper restored from another's memory (mode, tests' counts, RKC2's memory, the
    /// rate) continues bit for bit, in either mode.
    #[test]
    fn restore_continues_bit_for_bit_in_either_mode() {
        let n = 6;
        let lambda: Vec<f64> = (0..n).map(|i| 1e5f64.powf(i as f64 / 5.0)).collect();
        let options = (
            RungeKuttaOptions::default(),
            RkcOptions::default(),
            AutoOptions::default(),
            RosenbrockOptions::default(),
        );
        let go = |split: Option<usize>| {
            let mut sys = Relaxation {
                lambda: lambda.clone(),
            };
            let mut s = OdeStepper::new(OdeIntegrator::Auto, options, n, 1e-4).unwrap();
            let (mut t, mut y) = (0.0, vec![1.5; n]);
            let mut modes = Vec::new();
            for k in 0..400 {
                if Some(k) == split {
                    let (e, m, r) = (
                        s.explicit_state(),
                        s.stabilized_memory(),
                        s.current_rate().unwrap().to_vec(),
                    );
                    s = OdeStepper::new(OdeIntegrator::Auto, options, n, 1.0).unwrap();
                    s.restore(e, m.as_ref(), &r).unwrap();
                }
                modes.push(s.step(&mut sys, &mut t, &mut y, None).unwrap().mode);
            }
            (
                t.to_bits(),
                y.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                modes,
            )
        };
        let whole = go(None);
        assert!(whole.2.contains(&StepperMode::Explicit));
        assert!(whole.2.contains(&StepperMode::Stabilized));
        let first_stiff = whole
            .2
            .iter()
            .position(|m| *m == StepperMode::Stabilized)
            .unwrap();
        for split in [first_stiff / 2, first_stiff + 3, 350] {
            assert_eq!(go(Some(split)), whole, "split at {split}");
        }
    }

    #[test]
    fn names_round_trip() {
        for i in OdeIntegrator::ALL {
            assert_eq!(i.name().parse::<OdeIntegrator>().unwrap(), i);
        }
        assert!("rk45".parse::<OdeIntegrator>().is_err());
    }
}
