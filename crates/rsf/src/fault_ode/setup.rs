//! Setting up a fault ODE: the checks of the model, the condensation onto Γ_F (with the
//! volume's factor, without it, or of a fault alone), the loads and the first rates.

use rsf_direct::Condensation;
use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;
use rsf_time::{Kinematics, OdeStepper, OdeSystem};

use super::rates::{FaultRates, PressureRates};
use super::schur_only;
use super::{FaultOde, FaultOdeOptions};
use crate::error::{invalid, Result};
use crate::fault_alone::{free_fault_dofs, load_rate, Body, Elastic};
use crate::fault_kernel::{condensed_operator, SchurSource};
use crate::fault_operator::FaultOperator;
use crate::model::loading::TimeFunction;
use crate::model::Model;
use crate::normal_stress::{NormalCoupling, NormalStress, ScaledTractions};
use crate::problem::Problem;
use crate::simulation_state::SimulationState;
use crate::volume_probe::VolumeProbe;

/// The elastic body condensed onto Γ_F: the body, its operator `S`, the load
/// `g(t) = g₀ + G(t) g₁` (`G` the history's integral), the normal coupling (with the
/// volume's factor) and the watched vertices' rows (without it).
struct CondensedBody<const C: usize> {
    body: Body<C>,
    operator: Box<dyn FaultOperator>,
    g0: Vec<f64>,
    g1: Vec<f64>,
    history: TimeFunction,
    normal: Option<NormalCoupling>,
    probe: Option<VolumeProbe>,
}

/// Where each frictional node's slip unknowns start (`first`, one past the last at the
/// end) and the prescribed velocity factors of its fixed components.
type FaultLayout<const C: usize> = (Vec<usize>, Vec<[f64; C]>);

impl<const D: usize, L: FrictionLaw, S: StateLaw, const C: usize> FaultOde<D, L, S, C> {
    /// Sets up the run (called by
    /// [`SimulationBuilder::build_fault_ode`](crate::SimulationBuilder::build_fault_ode),
    /// which checks the laws and the model): condenses `K` onto Γ_F, the load and the
    /// Dirichlet velocities, and evaluates the slip rates at `t = 0`. Its stages: the
    /// checks ([`Self::checked_inputs`]), the condensation ([`Self::condense_body`]), the
    /// layout of the slip unknowns ([`Self::fault_layout`]), the rates, the stepper, and
    /// the first evaluation ([`Self::with_first_rates`]).
    pub(crate) fn new(
        problem: Problem<D, L, S, C>,
        alpha0: Vec<f64>,
        dt0: f64,
        options: FaultOdeOptions,
        elastic: Elastic,
    ) -> Result<Self> {
        let (eta, velocity_factor) = Self::checked_inputs(&problem, &options)?;
        let model = problem.model();
        let fb = &model.frictional_boundary;
        let n = model.num_dofs();
        let CondensedBody {
            body,
            operator,
            g0,
            g1,
            history,
            mut normal,
            probe,
        } = Self::condense_body(&problem, &options, &velocity_factor, elastic)?;
        let m = body.dim();
        let normal_kernel_report = match (&mut normal, &body) {
            (Some(n), Body::Volume(cond)) => n.compress(model, cond, options.kernel)?,
            _ => None,
        };
        let scaled_tractions = normal.as_ref().map(|n| ScaledTractions {
            laws: problem.friction_laws().to_vec(),
            sigma0: n.initial().to_vec(),
            sigma: n.initial().to_vec(),
        });
        let zeros = vec![0.0; n];
        let (first, fixed_velocity) = Self::fault_layout(model, &velocity_factor);
        debug_assert_eq!(first[fb.len()], m);
        let mut in_interface = vec![false; n];
        for &dof in body.interface_dofs() {
            in_interface[dof] = true;
        }
        let interior = (0..n)
            .filter(|&i| !model.fixed[i] && !in_interface[i])
            .collect();
        let fixed = (0..n).filter(|&i| model.fixed[i]).collect();
        let mut y = Vec::with_capacity(m + fb.len());
        y.extend(
            body.interface_dofs()
                .iter()
                .map(|&dof| model.initial_displacement[dof]),
        );
        y.extend_from_slice(&alpha0);
        let rates = FaultRates {
            body,
            operator,
            par: options.parallelism,
            linger: options.linger,
            g0,
            g1,
            history,
            first,
            fixed_velocity,
            weights: fb.weights.clone(),
            eta,
            r: vec![0.0; m],
            tolerance: options.tolerance,
            slip_scale: options.slip_scale,
            sigma: normal.as_ref().map_or(Vec::new(), |n| n.initial().to_vec()),
            normal,
            parts: None,
            shared: None,
            diagonal: Vec::new(),
            pressure: Self::pressure_rates(&problem),
            load_change: None,
        };
        let effective_tractions =
            rates
                .pressure
                .as_ref()
                .map(|p| crate::pore_pressure::EffectiveTractions {
                    laws: problem.friction_laws().to_vec(),
                    sigma: p.sigma_laws.clone(),
                });
        let mut kinematics = Kinematics::zeros(n);
        kinematics.u.copy_from_slice(&model.initial_displacement);
        let rk = OdeStepper::new(
            options.integrator,
            (
                options.runge_kutta,
                options.rkc,
                options.auto,
                options.rosenbrock,
            ),
            y.len(),
            dt0,
        )?;
        let state = SimulationState {
            step: 0,
            time: 0.0,
            tau: dt0,
            time_origin: (0, 0.0),
            kinematics,
            alpha: alpha0,
            controller: None,
        };
        Self {
            problem,
            rates,
            rk,
            y,
            state,
            interior,
            fixed,
            interior_is_nan: false,
            zeros,
            dy: Vec::new(),
            options,
            evaluations: 0,
            normal_kernel_report,
            scaled_tractions,
            effective_tractions,
            probe,
        }
        .with_first_rates()
    }

    /// The checks of the inputs a condensed run needs: valid options, radiation damping
    /// `η > 0` at every frictional node, a loading history with a closed-form integral,
    /// and no frictional node partly prescribed at a non-zero velocity. Returns `η` per
    /// frictional node and the prescribed velocity factor of every dof (0 where free).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
    /// `radiation_damping`, `loading` or `dirichlet`; the options' own.
    fn checked_inputs(
        problem: &Problem<D, L, S, C>,
        options: &FaultOdeOptions,
    ) -> Result<(Vec<f64>, Vec<f64>)> {
        options.validate()?;
        let model = problem.model();
        let eta = problem.radiation_damping().to_vec();
        if let Some((k, e)) = eta
            .iter()
            .enumerate()
            .find(|(_, e)| !(**e > 0.0 && e.is_finite()))
        {
            return Err(invalid(
                "radiation_damping",
                format!(
                    "η = {e} Pa·s/m at frictional node {k}: a run condensed onto the fault \
                     needs radiation damping η > 0 at every node (quasi-dynamic, \
                     SimulationBuilder::radiation_damping)"
                ),
            ));
        }
        if model.dirichlet.history.integral(0.0).is_none() {
            return Err(invalid(
                "loading",
                "a custom loading history has no closed-form integral; use a constant, ramp \
                 or piecewise-linear history",
            ));
        }
        let mut velocity_factor = vec![0.0; model.num_dofs()];
        for (&dof, &f) in model.dirichlet.dofs.iter().zip(&model.dirichlet.factors) {
            velocity_factor[dof] = f;
        }
        for (k, &p) in model.frictional_boundary.nodes.iter().enumerate() {
            let comps = C * p..C * p + C;
            let some_fixed = comps.clone().any(|i| model.fixed[i]);
            let all_fixed = comps.clone().all(|i| model.fixed[i]);
            if some_fixed && !all_fixed && comps.clone().any(|i| velocity_factor[i] != 0.0) {
                return Err(invalid(
                    "dirichlet",
                    format!(
                        "frictional node {k} (vertex {p}) has some components prescribed with a \
                         non-zero velocity; a run condensed onto the fault needs them at rest \
                         or the whole node prescribed"
                    ),
                ));
            }
        }
        Ok((eta, velocity_factor))
    }

    /// The elastic body condensed onto Γ_F as `elastic` asks: with the volume's factor
    /// (the operator given or built from it, the normal coupling), without it (the
    /// Schur-only elimination's), or a fault alone (its operator, the load rate
    /// `S v_pl`).
    ///
    /// # Errors
    /// An operator of another size than the fault's slip unknowns; a normal stress from
    /// slip without the volume's factor; the condensation's and the kernel's errors.
    fn condense_body(
        problem: &Problem<D, L, S, C>,
        options: &FaultOdeOptions,
        velocity_factor: &[f64],
        elastic: Elastic,
    ) -> Result<CondensedBody<C>> {
        let model = problem.model();
        let fb = &model.frictional_boundary;
        match elastic {
            Elastic::Condensed(operator) => {
                let mut cond = Condensation::<C>::with_ordering(
                    model.stiffness.as_ref(),
                    &model.fixed,
                    &fb.nodes,
                    options.ordering,
                )?;
                let m = cond.dim();
                let operator: Box<dyn FaultOperator> = match operator {
                    Some(op) if op.dim() != m => {
                        return Err(invalid(
                            "fault_operator",
                            format!(
                                "an operator of {} unknowns for a fault of {m} slip unknowns",
                                op.dim()
                            ),
                        ))
                    }
                    Some(op) => op,
                    None => Box::new(condensed_operator(
                        model,
                        &SchurSource::Factor(&cond),
                        options.kernel,
                    )?),
                };
                let big_g0 = model.dirichlet.history.integral(0.0).unwrap_or(0.0);
                let normal = NormalCoupling::new(
                    problem.normal_stress(),
                    model,
                    &mut cond,
                    problem.friction_laws(),
                    velocity_factor,
                    big_g0,
                )?;
                let mut g0 = vec![0.0; m];
                cond.condense(&model.load, &model.initial_displacement, &mut g0)?;
                let mut g1 = vec![0.0; m];
                cond.condense(&vec![0.0; model.num_dofs()], velocity_factor, &mut g1)?;
                Ok(CondensedBody {
                    body: Body::Volume(Box::new(cond)),
                    operator,
                    g0,
                    g1,
                    history: model.dirichlet.history.clone(),
                    normal,
                    probe: None,
                })
            }
            Elastic::SchurOnly(setup) => {
                if problem.normal_stress() != NormalStress::Fixed {
                    return Err(invalid(
                        "normal_stress",
                        "a normal stress from slip needs the volume's factor (its extension \
                         onto the fault's normal dofs): build the fault ODE with \
                         build_fault_ode, not without the factor",
                    ));
                }
                let body = schur_only::condense(model, options, velocity_factor, setup)?;
                Ok(CondensedBody {
                    body: Body::Condensed { dofs: body.dofs },
                    operator: Box::new(body.operator),
                    g0: body.g0,
                    g1: body.g1,
                    history: model.dirichlet.history.clone(),
                    normal: None,
                    probe: body.probe,
                })
            }
            Elastic::Alone(mut alone) => {
                if problem.normal_stress() != NormalStress::Fixed {
                    return Err(invalid(
                        "normal_stress",
                        "a fault alone has no volume to take a normal stress from slip from: \
                         use NormalStress::Fixed",
                    ));
                }
                let g1 = load_rate(model, &mut alone, options.parallelism)?;
                let dofs = free_fault_dofs(model);
                let g0 = dofs.iter().map(|&i| model.load[i]).collect();
                Ok(CondensedBody {
                    body: Body::Alone { dofs },
                    operator: alone.operator,
                    g0,
                    g1,
                    // g(t) = g₀ + t S v_pl: the history's integral is t.
                    history: TimeFunction::Constant(1.0),
                    normal: None,
                    probe: None,
                })
            }
        }
    }

    /// Where each frictional node's slip unknowns start among the free components of
    /// Γ_F (`first`, `n_F + 1` entries) and the velocity factors of its prescribed
    /// components (0 for the free ones).
    fn fault_layout(model: &Model<D, C>, velocity_factor: &[f64]) -> FaultLayout<C> {
        let fb = &model.frictional_boundary;
        let mut first = Vec::with_capacity(fb.len() + 1);
        let mut fixed_velocity = Vec::with_capacity(fb.len());
        let mut count = 0;
        for &p in &fb.nodes {
            first.push(count);
            let mut f = [0.0; C];
            for (c, fc) in f.iter_mut().enumerate() {
                if model.fixed[C * p + c] {
                    *fc = velocity_factor[C * p + c];
                } else {
                    count += 1;
                }
            }
            fixed_velocity.push(f);
        }
        first.push(count);
        (first, fixed_velocity)
    }

    /// The pore pressure's part of the rates, if the problem has a pressure: the laws'
    /// normal stresses and room for the effective ones.
    fn pressure_rates(problem: &Problem<D, L, S, C>) -> Option<PressureRates> {
        problem.pore_pressure().map(|at_nodes| {
            let sigma_laws: Vec<f64> = problem
                .friction_laws()
                .iter()
                .map(|l| l.normal_stress().unwrap_or(f64::NAN))
                .collect();
            PressureRates {
                at_nodes: at_nodes.clone(),
                effective: sigma_laws.clone(),
                scratch: vec![0.0; sigma_laws.len()],
                sigma_laws,
            }
        })
    }

    /// The run with its slip rates at `t = 0` evaluated (a check that the initial state
    /// is admissible) and its state filled from them.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `initial_state`
    /// for a rate that is not finite; the rates' own errors.
    fn with_first_rates(mut self) -> Result<Self> {
        let mut dy = vec![0.0; self.y.len()];
        let y0 = self.y.clone();
        self.system().rate(0.0, &y0, &mut dy)?;
        if let Some(i) = dy.iter().position(|x| !x.is_finite()) {
            return Err(invalid(
                "initial_state",
                format!("the rate of unknown {i} at t = 0 is {}", dy[i]),
            ));
        }
        self.dy = dy;
        self.fill_state(false)?;
        Ok(self)
    }
}
