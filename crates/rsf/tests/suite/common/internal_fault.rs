//! The runs of the internal faults' tests (`internal_fault`, `internal_fault_3d`,
//! `fault_network`, `normal_stress`): the quasi-dynamic builder, the last slip, the
//! implicit scheme and the fault ODE against each other, their observed orders.

use rsf::fault_ode::{FaultOde, FaultOdeOptions};
use rsf::friction::{AsinhLaw, RateStateParams};
use rsf::state::Aging;
use rsf::time::Quasistatic;
use rsf::{Model, Observer, Simulation, SimulationBuilder, SolverKind, StepView};

use super::largest_difference;

/// The quasi-dynamic builder of the internal-fault tests (`normal_stress::quasi_dynamic`).
pub type QuasiDynamic<const D: usize> = rsf::SimulationBuilder<
    D,
    rsf::friction::AsinhLaw,
    rsf::state::Aging,
    rsf::time::Quasistatic,
    D,
>;

/// The quasi-dynamic problem on `model`: the regularised law of `params`, the aging law at
/// steady state for the slip rate `v_init` (m/s), radiation damping μ/(2c_s) of the shear
/// modulus `mu` (Pa) and the density 2700 kg/m³.
///
/// # Panics
/// If `params` are refused.
pub fn quasi_dynamic_of<const D: usize>(
    model: Model<D>,
    params: RateStateParams,
    v_init: f64,
    mu: f64,
) -> QuasiDynamic<D> {
    let c_s = (mu / 2700.0f64).sqrt();
    SimulationBuilder::new(model)
        .friction(AsinhLaw::new(params).unwrap())
        .state_law(Aging::new(params.l).unwrap())
        .initial_state((params.l / v_init).ln())
        .integrator(Quasistatic::new())
        .radiation_damping(mu / (2.0 * c_s))
}

/// The last step's slip length (m) of every frictional node: the hypotenuse of its slip
/// components, taken one component at a time.
#[derive(Default)]
pub struct LastSlip(pub Vec<f64>);

impl<const D: usize> Observer<D> for LastSlip {
    fn observe(&mut self, s: &StepView<'_, D, D>) -> rsf::Result<rsf::Flow> {
        self.0 = (0..s.model.frictional_boundary.len())
            .map(|k| s.slip(k).iter().fold(0.0f64, |h, &c| h.hypot(c)))
            .collect();
        Ok(rsf::Flow::Continue(()))
    }
}

/// `builder`'s implicit scheme (its integrator, the direct solver) at the fixed step
/// `t_end / steps`.
pub fn implicit_scheme<const D: usize>(
    builder: QuasiDynamic<D>,
    t_end: f64,
    steps: usize,
) -> Simulation<D, AsinhLaw, Aging, Quasistatic, D> {
    builder
        .time_step(t_end / steps as f64)
        .solver(SolverKind::Direct)
        .build()
        .unwrap()
}

/// The last slip lengths ([`LastSlip`]) of [`implicit_scheme`] run to `t_end` in `steps`
/// fixed steps.
pub fn implicit_last_slip<const D: usize>(
    builder: QuasiDynamic<D>,
    t_end: f64,
    steps: usize,
) -> Vec<f64> {
    let mut sim = implicit_scheme(builder, t_end, steps);
    let mut last = LastSlip::default();
    sim.run(steps, &mut [&mut last]).unwrap();
    last.0
}

/// [`implicit_last_slip`] of `builder()` for each number of steps of `steps`: its largest
/// distance from `reference`, relative to `reference`'s largest slip, one per count.
pub fn implicit_slip_errors<const D: usize>(
    builder: impl Fn() -> QuasiDynamic<D>,
    t_end: f64,
    steps: &[usize],
    reference: &[f64],
) -> Vec<f64> {
    let scale = reference.iter().fold(0.0f64, |m, &x| m.max(x));
    assert!(scale > 0.0);
    steps
        .iter()
        .map(|&steps| {
            let slip = implicit_last_slip(builder(), t_end, steps);
            let e = largest_difference(&slip, reference) / scale;
            eprintln!(
                "τ = T/{steps}: implicit against the fault ODE {e:e} of the largest slip {scale:e} m"
            );
            e
        })
        .collect()
}

/// Asserts that `errors`, one per halving of τ, fall at an observed order above 0.8.
pub fn assert_first_order(errors: &[f64]) {
    for w in errors.windows(2) {
        let rate = (w[0] / w[1]).log2();
        eprintln!("rate {rate:.3}");
        assert!(rate > 0.8, "{errors:?}");
    }
}

/// `builder`'s fault ODE: first step 1e-3 s, tolerance 1e-9.
pub fn tight_fault_ode<const D: usize>(
    builder: QuasiDynamic<D>,
) -> FaultOde<D, AsinhLaw, Aging, D> {
    builder
        .time_step(1e-3)
        .build_fault_ode(FaultOdeOptions {
            tolerance: 1e-9,
            ..Default::default()
        })
        .unwrap()
}

/// The last slip lengths ([`LastSlip`]) of [`tight_fault_ode`] of `builder` run until
/// `until`, and its number of steps.
pub fn fault_ode_last_slip<const D: usize>(
    builder: QuasiDynamic<D>,
    until: rsf::Until,
) -> (Vec<f64>, usize) {
    let mut ode = tight_fault_ode(builder);
    let mut last = LastSlip::default();
    let steps = rsf::run_until(&mut ode, until, &mut [&mut last])
        .unwrap()
        .steps;
    (last.0, steps)
}

/// Asserts that `errors` (slip, normal stress), one pair per halving of τ, both fall at an
/// observed order above 0.8.
pub fn assert_first_order_with_normal_stress(errors: &[(f64, f64)]) {
    for w in errors.windows(2) {
        let rates = ((w[0].0 / w[1].0).log2(), (w[0].1 / w[1].1).log2());
        eprintln!(
            "rates {:.3} (slip), {:.3} (normal stress)",
            rates.0, rates.1
        );
        assert!(rates.0 > 0.8 && rates.1 > 0.8, "{errors:?}");
    }
}
