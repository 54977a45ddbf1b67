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
use crate::normal_stress::{NormalCoupling, NormalStress, ScaledTractions};
use crate::problem::Problem;
use crate::simulation_state::SimulationState;

impl<const D: usize, L: FrictionLaw, S: StateLaw, const C: usize> FaultOde<D, L, S, C> {
    /// Sets up the run (called by
    /// [`SimulationBuilder::build_fault_ode`](crate::SimulationBuilder::build_fault_ode),
    /// which checks the laws and the model): condenses `K` onto Γ_F, the load and the
    /// Dirichlet velocities, and evaluates the slip rates at `t = 0`.
    pub(crate) fn new(
        problem: Problem<D, L, S, C>,
        alpha0: Vec<f64>,
        dt0: f64,
        options: FaultOdeOptions,
        elastic: Elastic,
    ) -> Result<Self> {
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
        let fb = &model.frictional_boundary;
        let n = model.num_dofs();
        let mut velocity_factor = vec![0.0; n];
        for (&dof, &f) in model.dirichlet.dofs.iter().zip(&model.dirichlet.factors) {
            velocity_factor[dof] = f;
        }
        for (k, &p) in fb.nodes.iter().enumerate() {
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
        // The watched vertices' rows: computed with the set-up without the factor, later
        // (watch_vertices) with it.
        let mut probe = None;
        let (body, operator, g0, g1, history, mut normal) = match elastic {
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
                    &velocity_factor,
                    big_g0,
                )?;
                let mut g0 = vec![0.0; m];
                cond.condense(&model.load, &model.initial_displacement, &mut g0)?;
                let mut g1 = vec![0.0; m];
                cond.condense(&vec![0.0; n], &velocity_factor, &mut g1)?;
                let history = model.dirichlet.history.clone();
                (
                    Body::Volume(Box::new(cond)),
                    operator,
                    g0,
                    g1,
                    history,
                    normal,
                )
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
                let body = schur_only::condense(model, &options, &velocity_factor, setup)?;
                probe = body.probe;
                (
                    Body::Condensed { dofs: body.dofs },
                    Box::new(body.operator) as Box<dyn FaultOperator>,
                    body.g0,
                    body.g1,
                    model.dirichlet.history.clone(),
                    None,
                )
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
                // g(t) = g₀ + t S v_pl: the history's integral is t.
                let history = TimeFunction::Constant(1.0);
                (Body::Alone { dofs }, alone.operator, g0, g1, history, None)
            }
        };
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
        debug_assert_eq!(count, m);
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
            pressure: problem.pore_pressure().map(|at_nodes| {
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
            }),
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
        let mut ode = Self {
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
        };
        // The slip rates at t = 0 (a check that the initial state is admissible).
        let mut dy = vec![0.0; ode.y.len()];
        let y0 = ode.y.clone();
        ode.system().rate(0.0, &y0, &mut dy)?;
        if let Some(i) = dy.iter().position(|x| !x.is_finite()) {
            return Err(invalid(
                "initial_state",
                format!("the rate of unknown {i} at t = 0 is {}", dy[i]),
            ));
        }
        ode.dy = dy;
        ode.fill_state(false)?;
        Ok(ode)
    }
}
