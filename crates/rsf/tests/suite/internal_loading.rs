//! Loading a fault inside the body as SEAS BP3 does (docs/faults-inside.md "Loading"):
//! each side's far boundary moving with its side's rigid motion (Dirichlet parts that fix
//! both copies of a split node), a creeping section with a prescribed slip rate
//! (`ModelBuilder::internal_creep`); uniform slip on a through-going fault is then a rigid
//! motion of the two sides, with no stress change.
use crate::common::plane_x0;
use rsf::direct::{DirectOptions, DirectSolver};
use rsf::fem::{rectangle, Diagonal};
use rsf::nonsmooth::{NoNonlinearity, NonsmoothSolver};
use rsf::{Material, Model, ModelBuilder, Part};

const V: f64 = 1e-3;

/// `[-2, 2] × [-2, 0]` (top free), a fault dipping 45° through it from the surface at the
/// origin to the corner (−2, −2); the fault's direction d = (−1, −1)/√2, the pairs'
/// tangent t = −d = (1, 1)/√2, the plus side x − y > 0 (right, below). The left side (minus)
/// moves with −(V/2) t, the right side and the bottom (plus) with +(V/2) t; the pairs below
/// y = −0.5 creep at V.
fn model(left: [f64; 2]) -> rsf::Result<Model<2>> {
    let h = V / 2.0 / std::f64::consts::SQRT_2;
    let mesh = rectangle([-2.0, -2.0], [4.0, 2.0], 9, 5, Diagonal::Forward)?;
    ModelBuilder::refined(mesh, 1)?
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(Part::predicate("left", |x| x[0] < -2.0 + 1e-9), left)
        .dirichlet(Part::predicate("right", |x| x[0] > 2.0 - 1e-9), [h, h])
        .dirichlet(Part::predicate("bottom", |x| x[1] < -2.0 + 1e-9), [h, h])
        .internal_fault("fault", [0.0, 0.0], [-2.0, -2.0])
        .internal_creep(|x| x[1] < -0.5, V)
        .build()
}

#[test]
fn uniform_creep_on_a_through_going_fault_is_a_rigid_motion_of_the_two_sides() {
    let h = V / 2.0 / std::f64::consts::SQRT_2;
    let model = model([-h, -h]).unwrap();
    let f = model.internal_fault.as_ref().unwrap();
    // Creeping pairs and the corner are not frictional nodes; the pairs above y = −0.5 are.
    let frictional = model.frictional_boundary.len();
    eprintln!("{} pairs, {frictional} frictional", f.pairs().len());
    assert!(frictional > 0 && frictional < f.pairs().len());
    // The static velocity problem with the prescribed data only (no friction: the free
    // pairs follow).
    let mut v = vec![0.0; model.num_dofs()];
    for (&d, &factor) in model.dirichlet.dofs.iter().zip(&model.dirichlet.factors) {
        v[d] = factor;
    }
    DirectSolver::<2>::new(
        model.stiffness.as_ref(),
        &model.fixed,
        DirectOptions::default(),
    )
    .unwrap()
    .solve(&vec![0.0; v.len()], &NoNonlinearity, &mut v)
    .unwrap();
    let cartesian = model.to_cartesian(&v).unwrap();
    let mut worst = 0.0f64;
    for (q, x) in model.vertices.iter().enumerate() {
        let side_plus = match f.pairs().iter().find(|p| p.0 == q || p.1 == q) {
            Some(&(_, pl)) => q == pl,
            None => x[0] - x[1] > 0.0,
        };
        let expected = if side_plus { h } else { -h };
        for c in 0..2 {
            worst = worst.max((cartesian[2 * q + c] - expected).abs());
        }
    }
    // The stress change of a rigid motion: K (T v') vanishes to round-off.
    let mut force = vec![0.0; v.len()];
    rsf::fem::spmv_add(model.stiffness.as_ref(), 1.0, &v, &mut force);
    let scale = model
        .stiffness
        .val()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()))
        * V;
    let largest_force = force.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    eprintln!(
        "largest deviation from the rigid motions {worst:e} m/s (V = {V:e}); largest force \
         {largest_force:e} of the scale {scale:e}"
    );
    assert!(worst < 1e-12 * V, "{worst:e}");
    assert!(largest_force < 1e-12 * scale, "{largest_force:e}");
}

#[test]
fn loading_that_would_open_the_fault_or_fix_part_of_a_split_node_is_refused() {
    let h = V / 2.0 / std::f64::consts::SQRT_2;
    // The left side moving across the fault: the corner pair would open.
    match model([-h, h]) {
        Err(rsf::Error::InvalidParameter { name, reason }) => {
            assert_eq!(name, "dirichlet");
            assert!(reason.contains("open"), "{reason}");
        }
        other => panic!("{:?}", other.map(|_| ())),
    }
    // Only one side of the surface pair fixed.
    let mesh = rectangle([-2.0, -2.0], [4.0, 2.0], 9, 5, Diagonal::Forward).unwrap();
    let e = ModelBuilder::refined(mesh, 1)
        .unwrap()
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(
            Part::predicate("bottom", |x| x[1] < -2.0 + 1e-9),
            [0.0, 0.0],
        )
        .dirichlet(
            Part::predicate("top right", |x| x[1] > -1e-9 && x[0] > 0.0),
            [0.0, 0.0],
        )
        .internal_fault("fault", [0.0, 0.0], [0.0, -1.0])
        .build()
        .expect_err("refused");
    assert!(
        matches!(e, rsf::Error::InvalidParameter { ref name, .. } if name == "dirichlet"),
        "{e}"
    );
    // A creeping section without an internal fault.
    let mesh = rectangle([0.0, 0.0], [1.0, 1.0], 3, 3, Diagonal::Forward).unwrap();
    let e = ModelBuilder::new(mesh)
        .material(Material::new(1e10, 0.25, 2700.0))
        .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [0.0, 0.0])
        .frictional_boundary(Part::predicate("bottom", |x| x[1] < 1e-9))
        .internal_creep(|_| true, 1e-9)
        .build()
        .expect_err("refused");
    assert!(
        matches!(e, rsf::Error::InvalidParameter { ref name, .. } if name == "internal_creep"),
        "{e}"
    );
}

/// The cube `[-1, 1]³` (5 × 5 × 5 coarse vertices, refined once) cut through by the fault
/// `x = 0` (t₁ = e_y, t₂ = e_z, n = e_x), the face `x = −1` held, `x = +1` free; the pairs
/// above `z = 0.4` creep at `V` along the rake 30° from t₁ towards t₂, given as a
/// Cartesian vector; the rest of the fault is locked by Tresca friction far above the
/// stress the creep makes. Eight quasistatic steps.
fn creeping_cube(rake_degrees: f64) -> (Model<3>, Vec<Vec<[f64; 3]>>) {
    let r = rake_degrees.to_radians();
    let direction = [0.0, r.cos(), r.sin()];
    let mesh = rsf::fem::cuboid([-1.0; 3], [2.0; 3], [5, 5, 5]).unwrap();
    let model = ModelBuilder::refined(mesh, 1)
        .unwrap()
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(Part::predicate("held", |x| x[0] < -1.0 + 1e-9), [0.0; 3])
        .fault_tangent([0.0, 1.0, 0.0])
        .internal_fault_polygon("fault", &plane_x0(1.0, (-1.0, 1.0)))
        .internal_creep_at(move |x| {
            (x[2] > 0.4).then_some(rsf::model::CreepRate::Cartesian(direction.map(|d| V * d)))
        })
        .build()
        .unwrap();
    let mut sim = rsf::SimulationBuilder::new(model.clone())
        .friction(rsf::friction::Tresca::new(10.0, 1e9).unwrap())
        .state_law(rsf::simulation::NoState)
        .initial_state(0.0)
        .integrator(rsf::time::Quasistatic::new())
        .time_step(0.5)
        .solver(rsf::SolverKind::Direct)
        .build()
        .unwrap();
    struct Jumps(Vec<Vec<[f64; 3]>>);
    impl rsf::Observer<3> for Jumps {
        fn observe(&mut self, s: &rsf::StepView<'_, 3, 3>) -> rsf::Result<rsf::Flow> {
            let f = s.model.internal_fault.as_ref().expect("an internal fault");
            let v = s.model.to_cartesian(&s.state.kinematics.v)?;
            self.0.push(
                f.pairs()
                    .iter()
                    .map(|&(mi, pl)| std::array::from_fn(|c| v[3 * pl + c] - v[3 * mi + c]))
                    .collect(),
            );
            Ok(rsf::Flow::Continue(()))
        }
    }
    let mut jumps = Jumps(Vec::new());
    sim.run(8, &mut [&mut jumps]).unwrap();
    (model, jumps.0)
}

/// Slip is a vector on a creeping 3-D fault: with the rake 30°, both tangential
/// components of every creeping pair's slip rate are the prescribed ones (the second
/// component is fixed too, not a free frictionless unknown), the fault never opens, and the
/// locked part does not slip in either direction.
#[test]
fn a_creeping_3d_fault_slips_along_the_prescribed_vector_and_the_locked_part_does_not() {
    let rake = 30f64.to_radians();
    let (model, jumps) = creeping_cube(30.0);
    let f = model.internal_fault.as_ref().unwrap();
    let creeping: Vec<bool> = f
        .pairs()
        .iter()
        .map(|&(mi, _)| model.vertices[mi][2] > 0.4)
        .collect();
    let n_creep = creeping.iter().filter(|&&c| c).count();
    assert!(n_creep > 0 && n_creep < creeping.len());
    assert_eq!(model.frictional_boundary.len(), creeping.len() - n_creep);
    let expected = [0.0, V * rake.cos(), V * rake.sin()];
    let (mut worst_creep, mut worst_locked) = (0.0f64, 0.0f64);
    for step in &jumps {
        for (jump, &creeps) in step.iter().zip(&creeping) {
            if creeps {
                for c in 0..3 {
                    worst_creep = worst_creep.max((jump[c] - expected[c]).abs());
                }
            } else {
                worst_locked = worst_locked.max(jump.iter().fold(0.0f64, |m, x| m.max(x.abs())));
            }
        }
    }
    eprintln!(
        "{n_creep} creeping pairs: largest deviation from the prescribed vector {worst_creep:e} \
         m/s; largest slip rate of a locked pair {worst_locked:e} m/s (V = {V:e})"
    );
    assert!(worst_creep < 1e-12 * V, "{worst_creep:e}");
    assert!(worst_locked < 1e-12 * V, "{worst_locked:e}");
}

/// A creep vector that would open the fault, and a second tangential component on a 2-D
/// fault, are refused naming `internal_creep`.
#[test]
fn a_creep_rate_off_the_fault_plane_is_refused() {
    let mesh = rsf::fem::cuboid([-1.0; 3], [2.0; 3], [3, 3, 3]).unwrap();
    let e = ModelBuilder::refined(mesh, 1)
        .unwrap()
        .material(Material::new(1e10, 0.25, 2700.0))
        .dirichlet(Part::predicate("held", |x| x[0] < -1.0 + 1e-9), [0.0; 3])
        .internal_fault_polygon("fault", &plane_x0(1.0, (-1.0, 1.0)))
        .internal_creep_at(|_| Some(rsf::model::CreepRate::Cartesian([1e-9, 1e-9, 0.0])))
        .build()
        .expect_err("refused");
    assert!(
        matches!(e, rsf::Error::InvalidParameter { ref name, ref reason } if name == "internal_creep" && reason.contains("normal part")),
        "{e}"
    );
    let h = V / 2.0 / std::f64::consts::SQRT_2;
    let mesh = rectangle([-2.0, -2.0], [4.0, 2.0], 9, 5, Diagonal::Forward).unwrap();
    let e = ModelBuilder::refined(mesh, 1)
        .unwrap()
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(Part::predicate("right", |x| x[0] > 2.0 - 1e-9), [h, h])
        .internal_fault("fault", [0.0, 0.0], [-2.0, -2.0])
        .internal_creep_at(|x| (x[1] < -0.5).then_some(rsf::model::CreepRate::rake(V, 30.0)))
        .build()
        .expect_err("refused");
    assert!(
        matches!(e, rsf::Error::InvalidParameter { ref name, .. } if name == "internal_creep"),
        "{e}"
    );
}
