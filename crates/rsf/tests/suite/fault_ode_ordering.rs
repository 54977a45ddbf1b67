//! `FaultOdeOptions::ordering` reaches the fault ODE's condensation: METIS's nested
//! dissection (feature `metis`) gives a short run of AMD's to round-off with another
//! factor; without the feature it is a typed error.

use crate::common::plane_x0;
use rsf::fault_ode::{FaultOdeOptions, InteriorOrdering};
use rsf::fem::cuboid_from_coordinates;
use rsf::friction::{AsinhLaw, RateStateParams};
use rsf::state::Aging;
use rsf::{Material, ModelBuilder, Part, SimulationBuilder};

/// Velocity of the faces `x = ±4 km` along the fault (m/s), `±V`.
const V: f64 = 1e-2;

/// A vertical strike-slip fault 4 km × 2 km at `x = 0` from the free surface down, in a
/// box ±4 km × ±4 km × 3 km of 0.5 km cells sheared by its faces `x = ±4 km` (moving at
/// `±V` along the fault; the other faces free), condensed onto the fault.
fn fault_ode(ordering: InteriorOrdering) -> rsf::Result<rsf::FaultOde<3, AsinhLaw, Aging>> {
    let h = 500.0;
    let line = |lo: f64, hi: f64| -> Vec<f64> {
        let k = ((hi - lo) / h).round() as usize;
        (0..=k).map(|i| lo + h * i as f64).collect()
    };
    let mesh = cuboid_from_coordinates(&line(-4e3, 4e3), &line(-4e3, 4e3), &line(-3e3, 0.0))?;
    let (mu, c_s) = (32.04e9, 3464.0);
    let model = ModelBuilder::new(mesh)
        .material(Material::new(2.5 * mu, 0.25, 2670.0))
        .without_mass()
        .dirichlet(
            Part::predicate("plus face", |x| x[0] > 4e3 - 1.0),
            [0.0, V, 0.0],
        )
        .dirichlet(
            Part::predicate("minus face", |x| x[0] < -4e3 + 1.0),
            [0.0, -V, 0.0],
        )
        .fault_tangent([0.0, 1.0, 0.0])
        .internal_fault_polygon("fault", &plane_x0(2e3, (-2e3, 0.0)))
        .build()?;
    let params = RateStateParams {
        mu0: 0.6,
        a: 0.004,
        b: 0.03,
        v0: 1e-6,
        l: 0.14,
        sigma_n: 25e6,
    };
    SimulationBuilder::new(model)
        .friction(AsinhLaw::new(params)?)
        .state_law(Aging::new(params.l)?)
        .initial_state((params.l / 1e-9f64).ln())
        .integrator(rsf::time::Quasistatic::new())
        .radiation_damping(mu / (2.0 * c_s))
        .time_step(1e-3)
        .build_fault_ode(FaultOdeOptions {
            ordering,
            slip_scale: params.l,
            ..FaultOdeOptions::default()
        })
}

#[cfg(not(feature = "metis"))]
#[test]
fn nested_dissection_without_the_feature_is_a_typed_error() {
    let e = fault_ode(InteriorOrdering::NestedDissection).err().unwrap();
    assert!(
        matches!(
            e,
            rsf::Error::Direct(rsf_direct::Error::FeatureDisabled {
                feature: "metis",
                ..
            })
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("feature `metis`"), "{e}");
}

/// After ten steps the rates (slip rates and state rates) and the displacement agree to
/// 1e-10 relative; the factors differ (the ordering was used).
#[cfg(feature = "metis")]
#[test]
fn nested_dissection_gives_amds_fault_ode_to_round_off() {
    let mut amd = fault_ode(InteriorOrdering::Amd).unwrap();
    let mut nd = fault_ode(InteriorOrdering::NestedDissection).unwrap();
    assert_eq!(nd.options().ordering, InteriorOrdering::NestedDissection);
    assert_ne!(amd.factor_nnz(), nd.factor_nnz());
    let rel = |p: &[f64], q: &[f64]| {
        let scale = p.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
        let diff = p
            .iter()
            .zip(q)
            .fold(0.0_f64, |s, (x, y)| s.max((x - y).abs()));
        assert!(scale > 0.0);
        diff / scale
    };
    for ode in [&mut amd, &mut nd] {
        ode.run_until(rsf::Until::Steps(10), &mut []).unwrap();
    }
    let (r_amd, r_nd) = (amd.fault_ode_state().rate, nd.fault_ode_state().rate);
    let slip_rates = amd.condensed_dim();
    let rates = rel(&r_amd[..slip_rates], &r_nd[..slip_rates]);
    assert!(rates <= 1e-10, "slip rates differ by {rates:e}");
    let states = rel(&r_amd[slip_rates..], &r_nd[slip_rates..]);
    assert!(states <= 1e-10, "state rates differ by {states:e}");
    let u = rel(&amd.state().kinematics.u, &nd.state().kinematics.u);
    assert!(u <= 1e-10, "displacements differ by {u:e}");
    println!(
        "factor entries AMD {} / nested dissection {}; slip rates {rates:e}, state rates \
         {states:e}, u {u:e} (relative)",
        amd.factor_nnz(),
        nd.factor_nnz()
    );
}
