//! What used to run silently with wrong physics, or panic, is a typed error naming the
//! problem (issue 11): mismatched state variables, a free normal on Γ_F, non-finite
//! checkpoints, a non-monotone user state law, out-of-range nodes, missing parts.

use rsf::friction::{DieterichRuina, FrictionLaw, StateDependentTresca, StateVariable};
use rsf::method::StateIntegrator;
use rsf::observe::{
    EventThresholds, Every, FileMode, FrictionalProfile, Interval, PointSeries, Recorder,
    SlipEvents,
};
use rsf::state::{Aging, Discontinuous, StateLaw};
use rsf::time::VelocityIntegrator;
use rsf::{Checkpoint, Error, Model, SimulationBuilder};
use rsf_scenes::SliderScene;

fn model() -> Model<2> {
    crate::common::with_level(SliderScene::default(), 1)
        .build_model()
        .unwrap()
}

fn paper_friction() -> DieterichRuina {
    SliderScene::default().friction_law().unwrap()
}

#[test]
fn theta_state_law_with_log_theta_friction_is_refused() {
    let e = SimulationBuilder::new(model())
        .friction(paper_friction())
        .state_law(Discontinuous)
        .initial_state(1.0)
        .time_step(1e-3)
        .build()
        .err()
        .unwrap();
    assert!(
        matches!(
            e,
            Error::StateVariableMismatch {
                node: 0,
                friction: StateVariable::LogTheta,
                state: StateVariable::Theta
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("alpha = ln(theta)"));
    // A friction law declared in θ accepts it.
    let mu = StateDependentTresca::new(|theta: f64| 0.6 + 0.01 * theta, 1e4)
        .unwrap()
        .with_state_variable(StateVariable::Theta);
    assert!(SimulationBuilder::new(model())
        .friction(mu)
        .state_law(Discontinuous)
        .initial_state(1.0)
        .time_step(1e-3)
        .build()
        .is_ok());
}

#[test]
fn a_free_normal_on_the_fault_is_refused() {
    let mut m = model();
    let p = m.frictional_boundary.nodes[3];
    m.fixed[2 * p + 1] = false;
    let e = SimulationBuilder::new(m)
        .friction(paper_friction())
        .state_law(Aging::new(1e-5).unwrap())
        .initial_state(-10.0)
        .time_step(1e-3)
        .build()
        .err()
        .unwrap();
    assert!(matches!(e, Error::FreeNormal { node } if node == p), "{e}");
}

/// `∂ψ/∂α = 100 sin α`: not monotone, seven roots of the update for some inputs.
#[derive(Clone)]
struct Wavy;
impl StateLaw for Wavy {
    fn dpsi_dalpha(&self, alpha: f64, _v: f64) -> f64 {
        100.0 * alpha.sin()
    }
}

/// Aging law written by a user (monotone): passes the probe.
#[derive(Clone)]
struct UserAging(f64);
impl StateLaw for UserAging {
    fn dpsi_dalpha(&self, alpha: f64, v: f64) -> f64 {
        v / self.0 - (-alpha).exp()
    }
}

#[test]
fn a_non_monotone_user_state_law_is_refused() {
    let build = |law| {
        SimulationBuilder::new(model())
            .friction(paper_friction())
            .state_law(law)
            .initial_state(-10.0)
            .time_step(1e-3)
            .build()
    };
    let e = build(Wavy).err().unwrap();
    assert!(
        matches!(
            e,
            Error::StateLaw {
                node: 0,
                source: rsf::state::Error::NotMonotone { .. }
            }
        ),
        "{e}"
    );
    let cause = std::error::Error::source(&e).unwrap().to_string();
    assert!(cause.contains("not nondecreasing"), "{cause}");
    // The message itself carries the cause and says which index space `node` is in.
    let msg = e.to_string();
    assert!(msg.contains(&cause), "{msg}");
    assert!(msg.contains("not nondecreasing"), "{msg}");
    assert!(msg.contains("position on the frictional boundary"), "{msg}");
    let ok = SimulationBuilder::new(model())
        .friction(paper_friction())
        .state_law(UserAging(1e-5))
        .initial_state(-10.0)
        .time_step(1e-3)
        .build();
    assert!(ok.is_ok());
    // The probe alone, on the documented grid.
    assert!(Wavy.check_monotone().is_err());
    assert!(UserAging(1e-5).check_monotone().is_ok());
}

#[test]
fn non_finite_checkpoints_are_refused() {
    let mut sim = SliderScene {
        level: 1,
        ..SliderScene::default()
    }
    .build()
    .unwrap();
    sim.run(2, &mut []).unwrap();
    let good = sim.checkpoint();
    type Edit = fn(&mut Checkpoint);
    let cases: [(Edit, &str, usize); 4] = [
        (|c| c.state.alpha[0] = f64::NAN, "alpha", 0),
        (|c| c.state.kinematics.u[3] = f64::INFINITY, "u", 3),
        (|c| c.state.time = f64::NAN, "time", 0),
        (|c| c.state.tau = -1.0, "time step tau", 0),
    ];
    for (corrupt, name, entry) in cases {
        let mut c = good.clone();
        corrupt(&mut c);
        match sim.restore(&c) {
            Err(Error::CheckpointValue { what, index, .. }) => {
                assert_eq!((what, index), (name, entry))
            }
            other => panic!("{name}: {other:?}"),
        }
    }
    // The failed restores left the simulation as it was.
    assert_eq!(sim.checkpoint(), good);
}

#[test]
fn out_of_range_nodes_and_empty_meshes_are_errors() {
    let m = model();
    let n = m.num_nodes();
    let dir = std::env::temp_dir().join(format!("rsf-consistency-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let e = PointSeries::new(&dir.join("x.csv"), &m, n, FileMode::Create)
        .err()
        .unwrap();
    assert!(matches!(e, Error::NodeOutOfRange { node, nodes, .. } if node == n && nodes == n));
    assert!(Recorder::new(&m, &[0, n + 5]).is_err());
    assert!(SlipEvents::new(EventThresholds::default())
        .unwrap()
        .slip_at(&m, usize::MAX)
        .is_err());
    assert!(SlipEvents::new(EventThresholds {
        onset: 1e-4,
        end: 1e-3
    })
    .is_err());
    assert!(FrictionalProfile::<2>::new(&dir.join("p.csv"), (1.0, 0.0), FileMode::Create).is_err());
    // Sampling every 0 steps (the interval is now `Every`'s, not the profile's).
    let profile =
        FrictionalProfile::<2>::new(&dir.join("p.csv"), (0.0, 1.0), FileMode::Create).unwrap();
    assert!(Every::new(Interval::Steps(0), profile).is_err());
    assert!(rsf::model::nearest_vertex::<2>(&[], &[0.0, 0.0]).is_err());
    assert!(m.nearest_node(&[f64::NAN, 0.0]).is_err());
    std::fs::remove_dir_all(&dir).ok();
}

/// The message of the error `builder` gives when built.
fn refusal<L: FrictionLaw, S: StateLaw, I: VelocityIntegrator>(
    builder: SimulationBuilder<2, L, S, I>,
) -> String {
    builder.build().err().unwrap().to_string()
}

#[test]
fn missing_parts_of_a_simulation_are_named() {
    let aging = || Aging::new(1e-5).unwrap();
    let with_friction = || SimulationBuilder::new(model()).friction(paper_friction());
    let e = refusal(with_friction().state_law(aging()).initial_state(-10.0));
    assert!(e.contains("time_step"), "{e}");
    let e = refusal(with_friction().state_law(aging()).time_step(1e-3));
    assert!(e.contains("initial_state"), "{e}");
    // Friction with state but no state law.
    let e = refusal(with_friction().initial_state(-10.0).time_step(1e-3));
    assert!(e.contains("state_law"), "{e}");
    // τ is named as the simulation's parameter, not a scene's.
    let e = refusal(
        with_friction()
            .state_law(aging())
            .initial_state(-10.0)
            .time_step(f64::NAN),
    );
    assert!(e.contains("`tau`") && !e.contains("scene"), "{e}");
}

#[test]
fn the_constant_slip_rate_update_needs_a_law_with_its_closed_form() {
    let build = |state_integrator| {
        SimulationBuilder::new(model())
            .friction(paper_friction())
            .state_law(UserAging(1e-5))
            .initial_state(-10.0)
            .time_step(1e-3)
            .state_integrator(state_integrator)
            .build()
    };
    let e = build(StateIntegrator::ConstantSlipRate).err().unwrap();
    assert!(
        matches!(&e, Error::InvalidParameter { name, .. } if name == "state_integrator"),
        "{e}"
    );
    assert!(e.to_string().contains("constant_rate_update"), "{e}");
    assert!(build(StateIntegrator::BackwardEuler).is_ok());
    // The built-in law has it, and a scene file names it.
    let ok = SimulationBuilder::new(model())
        .friction(paper_friction())
        .state_law(Aging::new(1e-5).unwrap())
        .initial_state(-10.0)
        .time_step(1e-3)
        .state_integrator(StateIntegrator::ConstantSlipRate)
        .build()
        .unwrap();
    assert_eq!(
        ok.method().state_integrator(),
        StateIntegrator::ConstantSlipRate
    );
    let scene = SliderScene::from_toml("state_integrator = \"constant-slip-rate\"").unwrap();
    assert_eq!(scene.state_integrator, StateIntegrator::ConstantSlipRate);
    assert!(SliderScene::from_toml("state_integrator = \"exact\"").is_err());
}
