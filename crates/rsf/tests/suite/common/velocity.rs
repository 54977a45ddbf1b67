//! The Newmark velocity problems of the sliders (`velocity_solvers`, `slider_3d`): a
//! module of `rsf`'s suite's `common`, and of the bench `benches/velocity_solvers.rs`,
//! which includes this file by `#[path]`.

use rsf::fem::SparseMatrix;
use rsf::friction::FrictionLaw;
use rsf::time::{Kinematics, VelocityIntegrator};
use rsf_scenes::SliderScene;

/// The matrix `A = (2/τ)M + (τ/2)K` of `model`'s Newmark velocity problems at step `tau`
/// (s).
pub fn newmark_velocity_matrix<const D: usize>(model: &rsf::Model<D>, tau: f64) -> SparseMatrix {
    rsf::fem::combine(
        2.0 / tau,
        model.mass.as_ref().expect("Newmark has mass"),
        tau / 2.0,
        &model.stiffness,
    )
    .expect("A = (2/τ)M + (τ/2)K")
}

/// The paper's slider at refinement level `level` with N = 10⁴ steps (τ = 1.5 ms), its
/// model and the matrix A of its Newmark velocity problems
/// ([`newmark_velocity_matrix`]).
pub fn slider_velocity_problem(level: usize) -> (SliderScene, rsf::Model<2>, SparseMatrix) {
    let scene = SliderScene {
        level,
        steps: 10_000,
        ..SliderScene::default()
    };
    let model = scene.build_model().expect("slider model");
    let a = newmark_velocity_matrix(&model, scene.tau());
    (scene, model, a)
}

/// The Newmark right-hand side ℓ of `model` at step `tau` (s) from `(u, v, 0)`.
pub fn newmark_rhs<const D: usize>(
    model: &rsf::Model<D>,
    tau: f64,
    u: Vec<f64>,
    v: Vec<f64>,
) -> Vec<f64> {
    let n = v.len();
    let kin = Kinematics {
        u,
        v,
        a: vec![0.0; n],
    };
    let mut b = vec![0.0; n];
    rsf::time::Newmark
        .right_hand_side(
            tau,
            rsf::time::SystemMatrices::new(model.mass.as_ref(), &model.stiffness),
            &model.load,
            &kin,
            &mut b,
        )
        .expect("Newmark right-hand side");
    b
}

/// A warm start: `v` with the Dirichlet values on `model`'s fixed dofs, `v_top` (m/s) on
/// the first component of the `top` dofs and 0 elsewhere.
pub fn with_dirichlet_values<const D: usize>(
    model: &rsf::Model<D>,
    top: &[bool],
    v_top: f64,
    mut v: Vec<f64>,
) -> Vec<f64> {
    for (i, &f) in model.fixed.iter().enumerate() {
        if f {
            v[i] = if top[i] && i % D == 0 { v_top } else { 0.0 };
        }
    }
    v
}

/// `law` at state `alpha` at every node of `model`'s frictional boundary.
pub fn uniform_friction<L: FrictionLaw + Clone, const D: usize>(
    model: &rsf::Model<D>,
    law: L,
    alpha: f64,
) -> rsf::method::FrictionBlocks<L> {
    let f = &model.frictional_boundary;
    rsf::method::FrictionBlocks::new(
        f.nodes.clone(),
        f.weights.clone(),
        vec![law; f.nodes.len()],
        &vec![alpha; f.nodes.len()],
    )
}

/// TNNMG for the matrix `a` on `model`'s hierarchy, stopping norm `K + M`.
pub fn tnnmg_on<const D: usize>(
    a: &SparseMatrix,
    model: &rsf::Model<D>,
    opts: rsf::tnnmg::TnnmgOptions,
) -> rsf::tnnmg::Tnnmg<D> {
    rsf::tnnmg::Tnnmg::<D>::new(
        a.as_ref(),
        &model.fixed,
        &model.prolongations,
        Some(model.energy_norm.as_ref()),
        opts,
    )
    .unwrap()
}

/// The shear strain γ of a prestress whose elastic traction on the slider's fault balances
/// steady-state friction at slip rate `v_slide` (m/s): `G γ = μ_ss(V) σ̄_n`, G the shear
/// modulus of `scene`'s body.
pub fn steady_shear_strain(scene: &SliderScene, v_slide: f64) -> f64 {
    let g = scene.youngs_modulus_pa / (2.0 * (1.0 + scene.poisson_ratio));
    scene.rate_state_params().steady_state_friction(v_slide) * scene.sigma_n_pa / g
}
