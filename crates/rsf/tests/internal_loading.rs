//! Loading a fault inside the body as SEAS BP3 does (docs/faults-inside.md "Loading"):
//! each side's far boundary moving with its side's rigid motion (Dirichlet parts that fix
//! both copies of a split node), a creeping section with a prescribed slip rate
//! (`ModelBuilder::internal_creep`); uniform slip on a through-going fault is then a rigid
//! motion of the two sides, with no stress change.
use rsf::fem::{rectangle, Diagonal};
use rsf::tnnmg::{DirectOptions, DirectSolver, NoNonlinearity, NonsmoothSolver};
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
