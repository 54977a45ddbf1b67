//! The box with two faults of the Green's function tests: a module of `greens` in `rsf`'s
//! suite, and of `crates/rsf-hdf5/tests/greens.rs`, which includes this file by `#[path]`.

use rsf::fault_ode::{FaultKernel, FaultOdeOptions};
use rsf::fem::{rectangle, Diagonal};
use rsf::friction::{AsinhLaw, RateStateParams};
use rsf::state::Aging;
use rsf::time::Quasistatic;
use rsf::{FaultOde, Material, Model, ModelBuilder, Part, SimulationBuilder};

/// The fault ODE of the tests.
pub type Ode = FaultOde<2, AsinhLaw, Aging>;

/// A `2 half × 2 half` m box in cells of `1/per_m` m, top and bottom held, with two
/// vertical faults 1 m long at `x = ∓d/2`, "west" and "east".
pub fn box_with_faults(d: f64, half: f64, per_m: f64) -> Model<2> {
    let n = (2.0 * per_m * half).round() as usize + 1;
    let mesh = rectangle(
        [-half, -half],
        [2.0 * half, 2.0 * half],
        n,
        n,
        Diagonal::Forward,
    )
    .unwrap();
    ModelBuilder::new(mesh)
        .material(Material::new(3e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(
            Part::predicate("top", move |x| x[1] > half - 1e-9),
            [1e-9, 0.0],
        )
        .dirichlet(
            Part::predicate("bottom", move |x| x[1] < -half + 1e-9),
            [-1e-9, 0.0],
        )
        .internal_fault("west", [-d / 2.0, -0.5], [-d / 2.0, 0.5])
        .internal_fault("east", [d / 2.0, -0.5], [d / 2.0, 0.5])
        .build()
        .unwrap()
}

/// The quasistatic fault ODE of `model` with `kernel`: BP1-like rate and state (a = 0.015,
/// b = 0.01, L = 0.1 mm, σ̄_n = 5 MPa), aging, started at θ = L/(1 nm/s).
pub fn fault_ode(model: Model<2>, kernel: FaultKernel) -> Ode {
    let p = RateStateParams {
        mu0: 0.6,
        a: 0.015,
        b: 0.01,
        v0: 1e-6,
        l: 1e-4,
        sigma_n: 5e6,
    };
    SimulationBuilder::new(model)
        .friction(AsinhLaw::new(p).unwrap())
        .state_law(Aging::new(p.l).unwrap())
        .initial_state((p.l / 1e-9f64).ln())
        .integrator(Quasistatic::new())
        .radiation_damping(5e6)
        .time_step(1.0)
        .build_fault_ode(FaultOdeOptions {
            kernel,
            ..Default::default()
        })
        .unwrap()
}
