//! A fault ODE's steps: one accepted step, the state written after it (the volume only
//! where observers read it), and the run loop's [`Stepping`] interface.

use std::time::Instant;

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;

use super::rates::Rates;
use super::FaultOde;
use crate::checkpoint::Checkpoint;
use crate::error::{invalid, Result};
use crate::fault_alone::Body;
use crate::method_state::MethodState;
use crate::model::Model;
use crate::observe::FaultTractions;
use crate::report::StepReport;
use crate::run::Stepping;
use crate::simulation_state::SimulationState;
use crate::volume_probe::VolumeProbe;

impl<const D: usize, L: FrictionLaw, S: StateLaw, const C: usize> FaultOde<D, L, S, C> {
    /// The state with the whole field: computes `u` and `v` off Γ_F now (one forward and
    /// one backward sweep each), whatever the last step's observers read. E.g. to hand the
    /// state to a [`Simulation`](crate::Simulation) with inertia at the start of an event
    /// ([`Simulation::restore`](crate::Simulation::restore) of a
    /// [`Checkpoint::new`](crate::Checkpoint::new)).
    ///
    /// # Errors
    /// [`Error::Direct`](crate::Error::Direct) if the extension is not finite.
    pub fn state_with_volume(&mut self) -> Result<&SimulationState> {
        self.fill_state(true)?;
        Ok(&self.state)
    }

    /// Writes the state after a step from `y` and its rate `self.dy`.
    pub(super) fn fill_state(&mut self, volume: bool) -> Result<()> {
        let dy = &self.dy;
        let model = self.problem.model();
        let r = &mut self.rates;
        let m = r.body.dim();
        let t = self.state.time;
        let big_g = r.history.integral(t).unwrap_or(0.0);
        let kin = &mut self.state.kinematics;
        for (i, &dof) in r.body.interface_dofs().iter().enumerate() {
            kin.u[dof] = self.y[i];
            kin.v[dof] = dy[i];
        }
        for (&dof, &f) in model.dirichlet.dofs.iter().zip(&model.dirichlet.factors) {
            kin.u[dof] = model.initial_displacement[dof] + f * big_g;
        }
        for &i in &self.fixed {
            kin.v[i] = 0.0;
        }
        model.dirichlet.impose(t, &mut kin.v);
        if volume {
            if let Body::Condensed { .. } = r.body {
                return Err(invalid(
                    "reads_volume",
                    "the fault ODE was set up without the volume's factor \
                     (build_fault_ode_schur_only): it has the fault and the vertices given to \
                     its set-up, not the whole volume; build it with build_fault_ode to \
                     observe the volume",
                ));
            }
            self.interior_is_nan = false;
            if let Some(cond) = r.body.volume_mut() {
                cond.condense(&model.load, &kin.u, &mut r.r)
                    .and_then(|()| cond.extend(&mut kin.u))?;
                cond.condense(&self.zeros, &kin.v, &mut r.r)
                    .and_then(|()| cond.extend(&mut kin.v))?;
            }
        } else {
            if !self.interior_is_nan {
                for &i in &self.interior {
                    kin.u[i] = f64::NAN;
                    kin.v[i] = f64::NAN;
                }
                self.interior_is_nan = true;
            }
            if let Some(probe) = &self.probe {
                let speed = model.dirichlet.speed(t);
                probe.fill(&self.y[..m], &dy[..m], big_g, speed, &mut kin.u, &mut kin.v);
            }
        }
        self.state.alpha.copy_from_slice(&self.y[m..]);
        if let (Some(normal), Some(tr)) = (&mut r.normal, &mut self.scaled_tractions) {
            // Whole on every rank, not an exchange: a rank may fill its state alone (its
            // observers' vertices, `watch_vertices`, are rank 0's alone in the programs).
            normal.evaluate(t, big_g, &self.y[..m], &mut tr.sigma, r.par)?;
        }
        if let (Some(pr), Some(tr)) = (&mut r.pressure, &mut self.effective_tractions) {
            let base = self.scaled_tractions.as_ref().map(|s| &s.sigma[..]);
            pr.lower(t, base)?;
            tr.sigma.copy_from_slice(&pr.effective);
        }
        Ok(())
    }

    /// One accepted step (at most up to `t_end`); `volume`: whether to compute the field
    /// off Γ_F after it.
    fn advance_step(&mut self, t_end: Option<f64>, volume: bool) -> Result<StepReport> {
        let clock = Instant::now();
        let mut t = self.state.time;
        let taken = {
            let mut sys = Rates {
                friction: self.problem.friction_laws(),
                state_laws: self.problem.state_laws(),
                uses_state: self.problem.uses_state(),
                data: &mut self.rates,
            };
            // A step ends at the pore pressure's next breakpoint (a shut-in) and at the
            // load change's rather than step over them.
            let earliest = |a: Option<f64>, b: Option<f64>| match (a, b) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
            let pressure = sys
                .data
                .pressure
                .as_ref()
                .and_then(|p| p.at_nodes.next_breakpoint(t));
            let change = sys
                .data
                .load_change
                .as_ref()
                .and_then(|c| c.next_breakpoint(t));
            let t_end = earliest(t_end, earliest(pressure, change));
            self.rk.step(&mut sys, &mut t, &mut self.y, t_end)?.step
        };
        self.dy
            .copy_from_slice(self.rk.current_rate().expect("set by an accepted step"));
        self.evaluations += taken.evaluations;
        self.state.time = t;
        self.state.step += 1;
        self.state.tau = self.rk.controller().dt;
        self.fill_state(volume)?;
        let fb = &self.problem.model().frictional_boundary;
        let max_slip_rate = fb
            .nodes
            .iter()
            .map(|&p| crate::model::fault::block_norm::<C>(&self.state.kinematics.v, p))
            .fold(0.0, f64::max);
        Ok(StepReport {
            step: self.state.step,
            time: t,
            tau: taken.dt,
            evaluations: taken.evaluations,
            max_slip_rate,
            rejected_attempts: taken.rejected,
            rejected_normal_stress: taken.refused,
            error_estimate: taken.error,
            rejected_error: taken.rejected_error,
            seconds: clock.elapsed().as_secs_f64(),
            ..StepReport::default()
        })
    }
}

impl<const D: usize, L: FrictionLaw, S: StateLaw, const C: usize> Stepping<D, C>
    for FaultOde<D, L, S, C>
{
    fn advance(&mut self, t_end: Option<f64>, reads_volume: bool) -> Result<StepReport> {
        self.advance_step(t_end, reads_volume)
    }
    /// The Runge–Kutta control's `dt_min`.
    fn step_floor(&self) -> Option<f64> {
        Some(self.options.runge_kutta.dt_min)
    }
    /// Precomputes the extension operator's rows at the vertices' dofs (one forward sweep
    /// per dof, kept while the same vertices are asked for) and fills them in the current
    /// state. Set up without the factor ([`SchurOnlySetup`]), the set-up's vertices (or
    /// some of them) are accepted and any other is refused.
    ///
    /// [`SchurOnlySetup`]: super::SchurOnlySetup
    fn watch_vertices(&mut self, vertices: &[usize]) -> Result<()> {
        if let Body::Condensed { .. } = self.rates.body {
            // Set up without the factor: the probe of the set-up's vertices stays (it
            // cannot be made again); any of its vertices may be read.
            let watched = self.probe.as_ref().map_or(&[][..], |p| p.vertices());
            if vertices.iter().all(|v| watched.binary_search(v).is_ok()) {
                return Ok(());
            }
        }
        if vertices.is_empty() {
            self.probe = None;
            return Ok(());
        }
        if self.probe.as_ref().is_some_and(|p| p.watches(vertices)) {
            return Ok(());
        }
        let model = self.problem.model();
        let mut velocity_factor = vec![0.0; model.num_dofs()];
        for (&dof, &f) in model.dirichlet.dofs.iter().zip(&model.dirichlet.factors) {
            velocity_factor[dof] = f;
        }
        if let Body::Condensed { .. } = self.rates.body {
            return Err(invalid(
                "volume_vertices",
                format!(
                    "the fault ODE was set up without the volume's factor: it reads the \
                     vertices given to its set-up (SchurOnlySetup::watch_vertices{}), not \
                     {vertices:?}",
                    match &self.probe {
                        Some(p) => format!(": {:?}", p.vertices()),
                        None => ", none".to_string(),
                    }
                ),
            ));
        }
        let Some(cond) = self.rates.body.volume_mut() else {
            return Err(invalid(
                "volume_vertices",
                "a fault alone (FaultAlone) has no volume: an observer cannot read vertices \
                 off the fault",
            ));
        };
        self.probe = Some(VolumeProbe::new(model, cond, vertices, &velocity_factor)?);
        // Another probe's vertices are NaN again.
        self.interior_is_nan = false;
        self.fill_state(false)
    }
    fn model(&self) -> &Model<D, C> {
        self.problem.model()
    }
    fn state(&self) -> &SimulationState {
        &self.state
    }
    fn fault_tractions(&self) -> &dyn FaultTractions {
        if let Some(t) = &self.effective_tractions {
            return t;
        }
        match &self.scaled_tractions {
            Some(t) => t,
            None => self.problem.fault_tractions(),
        }
    }
    fn method_state(&self) -> MethodState {
        MethodState::FaultOde(self.fault_ode_state())
    }
    fn restore(&mut self, checkpoint: &Checkpoint) -> Result<()> {
        FaultOde::restore(self, checkpoint)
    }
}
