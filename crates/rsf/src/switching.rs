//! Fully dynamic events in quasi-dynamic cycles: a run that switches between a
//! [`FaultOde`] (no inertia, radiation damping, explicit adaptive steps) while the fault
//! creeps and a [`Simulation`] with inertia (e.g. Newmark, no radiation damping, fixed
//! steps) while it slips fast — the approach of the fully dynamic codes of the SEAS
//! benchmark BP1-FD (Erickson et al. 2023, BSSA), docs/math.md §12.

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::VelocityIntegrator;

use crate::checkpoint::Checkpoint;
use crate::error::{invalid, Result};
use crate::fault_ode::FaultOde;
use crate::observe::{Flow, Observer, StepView};
use crate::simulation::run::{
    check_end_time, observed_run, time_reached, RunError, RunSummary, Termination,
};
use crate::simulation::Simulation;

/// When and how a [`SwitchingRun`] changes between its two methods.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwitchingOptions {
    /// The quasi-dynamic run hands over to the dynamic one after the first step whose
    /// largest slip rate on Γ_F is at least this (m/s). Default 1e-3 m/s (the SEAS event
    /// threshold).
    pub to_dynamic: f64,
    /// The dynamic run hands back after the first step whose largest slip rate is below
    /// this (m/s), at most `to_dynamic` (hysteresis against switching back and forth).
    /// Default 1e-4 m/s.
    pub to_quasi_dynamic: f64,
    /// The time step of the dynamic phases (s), fixed; e.g. a fraction of the time a shear
    /// wave takes to cross an element on the fault.
    pub dynamic_tau: f64,
    /// The first trial step of a quasi-dynamic phase (s); its step control takes over.
    pub restart_dt: f64,
}

/// What a [`SwitchingRun`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SwitchingStats {
    /// Dynamic phases started.
    pub dynamic_phases: usize,
    /// Steps taken in dynamic phases.
    pub dynamic_steps: usize,
    /// Steps taken in quasi-dynamic phases.
    pub quasi_dynamic_steps: usize,
    /// Time spent in dynamic phases (s of simulated time).
    pub dynamic_time: f64,
}

/// Which method runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    QuasiDynamic,
    Dynamic,
}

/// A run that is quasi-dynamic while the fault creeps and fully dynamic while it slips
/// fast. Both methods must work on the same model (the dynamic one's with a mass matrix):
/// at a switch to the dynamic phase the whole field `(u, v)` of the quasi-dynamic state
/// (its equilibrium, [`FaultOde::state_with_volume`]), α and the time become the dynamic
/// run's state with zero acceleration; at a switch back the displacement on Γ_F and α
/// become the quasi-dynamic state ([`FaultOde::restart_from`]; the waves of the volume are
/// dropped, as in any quasi-dynamic model). Observers see every step of both, in order,
/// and are finished once at the end.
pub struct SwitchingRun<
    const D: usize,
    L: FrictionLaw,
    S: StateLaw,
    I: VelocityIntegrator,
    const C: usize = D,
> {
    quasi_dynamic: FaultOde<D, L, S, C>,
    dynamic: Simulation<D, L, S, I, C>,
    options: SwitchingOptions,
    phase: Phase,
    stats: SwitchingStats,
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, I: VelocityIntegrator, const C: usize>
    SwitchingRun<D, L, S, I, C>
{
    /// A switching run starting in the quasi-dynamic phase at the state of
    /// `quasi_dynamic`. `dynamic` is switched to fixed steps of `options.dynamic_tau`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `dynamic` if its
    /// integrator has no inertia or its model's dofs or frictional nodes differ, or
    /// naming the first invalid option (thresholds positive and ordered, steps positive
    /// and finite).
    pub fn new(
        quasi_dynamic: FaultOde<D, L, S, C>,
        mut dynamic: Simulation<D, L, S, I, C>,
        options: SwitchingOptions,
    ) -> Result<Self> {
        let o = options;
        if !(o.to_dynamic > 0.0 && o.to_dynamic.is_finite()) {
            return Err(invalid("to_dynamic", format!("{} m/s", o.to_dynamic)));
        }
        if !(o.to_quasi_dynamic > 0.0 && o.to_quasi_dynamic <= o.to_dynamic) {
            return Err(invalid(
                "to_quasi_dynamic",
                format!("{} m/s must be in (0, to_dynamic]", o.to_quasi_dynamic),
            ));
        }
        for (name, x) in [("dynamic_tau", o.dynamic_tau), ("restart_dt", o.restart_dt)] {
            if !(x > 0.0 && x.is_finite()) {
                return Err(invalid(name, format!("{x} s must be positive and finite")));
            }
        }
        if !dynamic.method().integrator().uses_mass() {
            return Err(invalid(
                "dynamic",
                "its integrator has no inertia (use Newmark or backward Euler)",
            ));
        }
        let (a, b) = (quasi_dynamic.model(), dynamic.model());
        if a.num_dofs() != b.num_dofs()
            || a.frictional_boundary.nodes != b.frictional_boundary.nodes
        {
            return Err(invalid(
                "dynamic",
                "its model differs from the quasi-dynamic one (dofs or frictional nodes)",
            ));
        }
        dynamic.set_step_control(None)?;
        dynamic.set_time_step(o.dynamic_tau)?;
        Ok(Self {
            quasi_dynamic,
            dynamic,
            options,
            phase: Phase::QuasiDynamic,
            stats: SwitchingStats::default(),
        })
    }

    /// The quasi-dynamic method.
    pub fn quasi_dynamic(&self) -> &FaultOde<D, L, S, C> {
        &self.quasi_dynamic
    }

    /// The dynamic method.
    pub fn dynamic(&self) -> &Simulation<D, L, S, I, C> {
        &self.dynamic
    }

    /// What the run did so far.
    pub fn stats(&self) -> SwitchingStats {
        self.stats
    }

    /// The time of the current state (s).
    pub fn time(&self) -> f64 {
        match self.phase {
            Phase::QuasiDynamic => self.quasi_dynamic.state().time,
            Phase::Dynamic => self.dynamic.time(),
        }
    }

    /// Runs until the time `t_end` (s), switching as the options say.
    ///
    /// # Errors
    /// A [`RunError`] with the first error of a step, an observer or a switch, and the
    /// summary of the steps before it.
    pub fn run_until(
        &mut self,
        t_end: f64,
        observers: &mut [&mut dyn Observer<D, C>],
    ) -> std::result::Result<RunSummary, RunError> {
        observed_run(observers, |observers, summary| {
            self.run_loop(t_end, observers, summary)
        })
    }

    fn run_loop(
        &mut self,
        t_end: f64,
        observers: &mut [&mut dyn Observer<D, C>],
        summary: &mut RunSummary,
    ) -> Result<()> {
        check_end_time(t_end)?;
        let mut fpi_total = 0.0;
        loop {
            if time_reached(self.time(), t_end, self.options.dynamic_tau) {
                summary.termination = Termination::EndTime;
                return Ok(());
            }
            let t0 = self.time();
            let mut switch = SwitchWhen {
                threshold: match self.phase {
                    Phase::QuasiDynamic => self.options.to_dynamic,
                    Phase::Dynamic => self.options.to_quasi_dynamic,
                },
                above: self.phase == Phase::QuasiDynamic,
            };
            let switch_index = observers.len();
            let mut forwards: Vec<Forward<'_, '_, D, C>> =
                observers.iter_mut().map(|o| Forward(&mut **o)).collect();
            let mut list: Vec<&mut dyn Observer<D, C>> = forwards
                .iter_mut()
                .map(|f| f as &mut dyn Observer<D, C>)
                .collect();
            list.push(&mut switch);
            let until = crate::Until::Time(t_end);
            let run = match self.phase {
                Phase::QuasiDynamic => self.quasi_dynamic.run_until(until, &mut list),
                Phase::Dynamic => self.dynamic.run_until(until, &mut list),
            };
            let part = match run {
                Ok(s) => s,
                Err(e) => {
                    add(summary, &e.summary, &mut fpi_total);
                    return Err(e.error);
                }
            };
            add(summary, &part, &mut fpi_total);
            match self.phase {
                Phase::QuasiDynamic => self.stats.quasi_dynamic_steps += part.steps,
                Phase::Dynamic => {
                    self.stats.dynamic_steps += part.steps;
                    self.stats.dynamic_time += self.time() - t0;
                }
            }
            match part.termination {
                Termination::Observer { index, .. } if index == switch_index => {
                    self.switch()?;
                }
                other => {
                    summary.termination = other;
                    return Ok(());
                }
            }
        }
    }

    /// Hands the state over to the other method.
    fn switch(&mut self) -> Result<()> {
        match self.phase {
            Phase::QuasiDynamic => {
                let mut state = self.quasi_dynamic.state_with_volume()?.clone();
                state.tau = self.options.dynamic_tau;
                state.kinematics.a.fill(0.0);
                state.controller = None;
                state.time_origin = (state.step, state.time);
                self.dynamic.restore(&Checkpoint::new(D, state))?;
                self.phase = Phase::Dynamic;
                self.stats.dynamic_phases += 1;
            }
            Phase::Dynamic => {
                self.quasi_dynamic
                    .restart_from(self.dynamic.state(), self.options.restart_dt)?;
                self.phase = Phase::QuasiDynamic;
            }
        }
        Ok(())
    }
}

/// Adds a phase's summary to the run's.
fn add(total: &mut RunSummary, part: &RunSummary, fpi_total: &mut f64) {
    *fpi_total += part.fpi_mean * part.steps as f64;
    total.steps += part.steps;
    total.fpi_max = total.fpi_max.max(part.fpi_max);
    total.solver_iterations += part.solver_iterations;
    total.relaxed_steps += part.relaxed_steps;
    total.rejected_attempts += part.rejected_attempts;
    total.fpi_mean = if total.steps > 0 {
        *fpi_total / total.steps as f64
    } else {
        0.0
    };
}

/// An observer shown every step of a phase but finished only once, at the end of the
/// whole run.
struct Forward<'a, 'b, const D: usize, const C: usize>(&'a mut (dyn Observer<D, C> + 'b));

impl<const D: usize, const C: usize> Observer<D, C> for Forward<'_, '_, D, C> {
    fn observe(&mut self, step: &StepView<'_, D, C>) -> Result<Flow> {
        self.0.observe(step)
    }
    fn name(&self) -> String {
        self.0.name()
    }
    fn reads_volume(&self) -> bool {
        self.0.reads_volume()
    }
}

/// Ends a phase after the first step whose largest slip rate is at least (`above`) or
/// below the threshold.
struct SwitchWhen {
    threshold: f64,
    above: bool,
}

impl<const D: usize, const C: usize> Observer<D, C> for SwitchWhen {
    fn observe(&mut self, step: &StepView<'_, D, C>) -> Result<Flow> {
        let v = step.report.max_slip_rate;
        let switch = if self.above {
            v >= self.threshold
        } else {
            v < self.threshold
        };
        Ok(if switch {
            Flow::Break(())
        } else {
            Flow::Continue(())
        })
    }
    fn name(&self) -> String {
        "switch between quasi-dynamic and dynamic".into()
    }
    fn reads_volume(&self) -> bool {
        false
    }
}
