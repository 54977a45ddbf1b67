//! A body of several materials (`MaterialRegions`): the assembly per cell against the
//! homogeneous one, a layered column against its closed form, gravity with the regions'
//! densities, and the paper's block on an elastic base converging to the rigid base as
//! the base stiffens.
use rsf::fem::{rectangle, Diagonal};
use rsf::model::{MaterialRegions, Medium};
use rsf::{Material, Model, ModelBuilder, Part};

fn max_abs_diff(a: &rsf::fem::SparseMatrix, b: &rsf::fem::SparseMatrix) -> (f64, f64) {
    let (va, vb) = (a.val(), b.val());
    assert_eq!(va.len(), vb.len());
    let d = va
        .iter()
        .zip(vb)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    (d, va.iter().fold(0.0f64, |m, x| m.max(x.abs())))
}

/// Regions all of one material assemble exactly what the material assembles.
#[test]
fn regions_of_one_material_assemble_what_the_material_assembles() {
    let mesh = rectangle([0.0, -1.0], [2.0, 2.0], 5, 5, Diagonal::Forward).unwrap();
    let m = Material::new(3e9, 0.27, 2600.0);
    let regions = MaterialRegions::new(m)
        .region("lower", |x| x[1] < 0.0, m)
        .region("left", |x| x[0] < 1.0, m);
    let a = <Material as Medium<2, 2>>::assemble(&m, &mesh, true).unwrap();
    let b = regions.assemble(&mesh, true).unwrap();
    for (x, y) in [
        (&a.stiffness, &b.stiffness),
        (a.mass.as_ref().unwrap(), b.mass.as_ref().unwrap()),
        (&a.energy_norm, &b.energy_norm),
    ] {
        let (d, scale) = max_abs_diff(x, y);
        assert!(d <= 1e-15 * scale, "{d:e} of {scale:e}");
    }
}

/// A column [0, 1] × [−1, 1] of two layers (E₁ above y = 0, E₂ below, ν = 0), its bottom
/// fixed, its top pressed by p: uniaxial stress, u_y = −p (y + 1)/E₂ below and
/// −p (1/E₂ + y/E₁) above, which P1 elements reproduce exactly (piecewise linear); the
/// same with half the interface a fault inside the body (no shear: it does not slip).
#[test]
fn a_layered_column_compresses_by_the_sum_of_its_layers() {
    let (e1, e2, p) = (2e9, 7e10, 3e6);
    let exact = |y: f64| {
        if y <= 0.0 {
            -p * (y + 1.0) / e2
        } else {
            -p * (1.0 / e2 + y / e1)
        }
    };
    for with_fault in [false, true] {
        let mesh = rectangle([0.0, -1.0], [1.0, 2.0], 3, 5, Diagonal::Forward).unwrap();
        let medium = MaterialRegions::new(Material::new(e1, 0.0, 2700.0)).region(
            "base",
            |x| x[1] < 0.0,
            Material::new(e2, 0.0, 2700.0),
        );
        let builder = ModelBuilder::refined(mesh, 2)
            .unwrap()
            .material(medium)
            .without_mass()
            .dirichlet(
                Part::predicate("bottom", |x| x[1] < -1.0 + 1e-9),
                [0.0, 0.0],
            )
            .neumann(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), move |_| {
                [0.0, -p]
            });
        let model = if with_fault {
            // Half the interface (a tip at x = 0.5 m): the block cannot slide off.
            builder.internal_fault("interface", [0.0, 0.0], [0.5, 0.0])
        } else {
            builder.frictional_boundary(Part::predicate("right", |x| x[0] > 1.0 - 1e-9))
        }
        .build()
        .unwrap();
        let mut worst = 0.0f64;
        for (q, x) in model.vertices.iter().enumerate() {
            let u = model.vertex_value(q, &model.initial_displacement);
            worst = worst.max((u[1] - exact(x[1])).abs()).max(u[0].abs());
        }
        let scale = exact(1.0).abs();
        eprintln!("fault {with_fault}: largest error {worst:e} of {scale:e} m");
        assert!(worst < 1e-10 * scale, "{worst:e}");
    }
}

/// Gravity's body force uses each region's density: the load's vertical components sum
/// to −g (ρ₁ A₁ + ρ₂ A₂).
#[test]
fn gravity_weighs_each_region_with_its_density() {
    let (rho1, rho2, g) = (2000.0, 3300.0, 9.81);
    let mesh = rectangle([0.0, -1.0], [3.0, 2.0], 7, 5, Diagonal::Backward).unwrap();
    let medium = MaterialRegions::new(Material::new(1e10, 0.25, rho1)).region(
        "base",
        |x| x[1] < 0.0,
        Material::new(1e10, 0.25, rho2),
    );
    let model = ModelBuilder::new(mesh)
        .material(medium)
        .gravity([0.0, -g])
        .dirichlet(
            Part::predicate("bottom", |x| x[1] < -1.0 + 1e-9),
            [0.0, 0.0],
        )
        .frictional_boundary(Part::predicate("top", |x| x[1] > 1.0 - 1e-9))
        .build()
        .unwrap();
    let total: f64 = model.load.iter().skip(1).step_by(2).sum();
    let expected = -g * (3.0 * rho1 + 3.0 * rho2);
    assert!(
        (total - expected).abs() < 1e-12 * expected.abs(),
        "{total} vs {expected}"
    );
}

/// The paper's block ([0, 5] × [0, 1] m, E = 5e7 Pa, gravity, the top held) on a base
/// [0, 5] × [−1, 0] m whose bottom is fixed, the interface a fault inside the body: its
/// initial equilibrium tends to the rigid base's (the block alone, its bottom's normal
/// fixed) as the base's E grows, at first order in E_block/E_base.
#[test]
fn the_block_on_an_elastic_base_tends_to_the_rigid_base() {
    let block = Material::new(5e7, 0.3, 5e3);
    let g = [0.0, -9.81];
    let top = || Part::predicate("top", |x| x[1] > 1.0 - 1e-9);
    let rigid = ModelBuilder::refined(
        rectangle([0.0, 0.0], [5.0, 1.0], 6, 2, Diagonal::Forward).unwrap(),
        2,
    )
    .unwrap()
    .material(block)
    .gravity(g)
    .dirichlet(top(), [1e-4, 0.0])
    .frictional_boundary(Part::predicate("bottom", |x| x[1] < 1e-9))
    .build()
    .unwrap();
    let elastic = |ratio: f64| -> Model<2> {
        let base = Material {
            youngs_modulus: ratio * block.youngs_modulus,
            ..block
        };
        ModelBuilder::refined(
            rectangle([0.0, -1.0], [5.0, 2.0], 6, 3, Diagonal::Forward).unwrap(),
            2,
        )
        .unwrap()
        .material(MaterialRegions::new(block).region("base", |x| x[1] < 0.0, base))
        .gravity(g)
        .dirichlet(top(), [1e-4, 0.0])
        .dirichlet(
            Part::predicate("bottom", |x| x[1] < -1.0 + 1e-9),
            [0.0, 0.0],
        )
        .internal_fault("interface", [0.0, 0.0], [5.0, 0.0])
        .build()
        .unwrap()
    };
    let scale = rigid
        .initial_displacement
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let mut errors = Vec::new();
    for ratio in [1e2, 1e4] {
        let m = elastic(ratio);
        let f = m.internal_fault.as_ref().unwrap();
        // The block's vertices: on the interface the plus copies (the plus side is y > 0).
        let plus_of = |q: usize| f.pairs().iter().find(|p| p.0 == q).map_or(q, |p| p.1);
        let mut worst = 0.0f64;
        for (q, x) in rigid.vertices.iter().enumerate() {
            let r = m
                .vertices
                .iter()
                .position(|y| (y[0] - x[0]).abs() + (y[1] - x[1]).abs() < 1e-12)
                .expect("the block's vertices are vertices of the two-body mesh");
            let a = rigid.vertex_value(q, &rigid.initial_displacement);
            let b = m.vertex_value(plus_of(r), &m.initial_displacement);
            worst = worst.max((a[0] - b[0]).hypot(a[1] - b[1]));
        }
        eprintln!("E_base/E_block = {ratio:e}: largest difference {worst:e} of {scale:e} m");
        errors.push(worst);
    }
    let rate = (errors[0] / errors[1]).log10() / 2.0;
    eprintln!("order in E_block/E_base: {rate:.3}");
    assert!(errors[0] < 0.1 * scale, "{errors:?}");
    assert!((rate - 1.0).abs() < 0.1, "rate {rate}");
}
