//! The paper's slider on an inclined base (issue 24): the whole scene turned so that its
//! frictional base dips by an angle in the loading direction, gravity kept vertical. The
//! model carries nodal frames on the slanted base (docs/math.md §10).

use crate::{SliderScene, SLIDER_CENTRE};
use rsf::fem::{pipping_slider_coarse, SimplexMesh, TAG_DIRICHLET, TAG_FRICTIONAL, TAG_NEUMANN};
use rsf::time::VelocityIntegrator;
use rsf::{Model, ModelBuilder};

/// `x` rotated clockwise by `dip` (rad) about the origin (the slider's bottom-left corner):
/// the paper's `+x` axis then points down a slope of `dip`.
pub fn dip_point(dip: f64, x: [f64; 2]) -> [f64; 2] {
    let (s, c) = (-dip).sin_cos();
    [c * x[0] - s * x[1], s * x[0] + c * x[1]]
}

/// x0 of the inclined slider: the paper's `SLIDER_CENTRE` (2.5, 0) turned with the block.
pub fn inclined_centre(dip: f64) -> [f64; 2] {
    dip_point(dip, SLIDER_CENTRE)
}

/// The model of `scene` on a base dipping by `dip` (rad, positive: the base descends in the
/// loading direction; the weight's down-slope part is carried by the clamped top in the
/// initial equilibrium `u₀`, see examples/inclined_block.rs):
/// the coarse mesh turned, tags as the paper's (top Γ_D, sides Γ_N, base Γ_F), gravity
/// `(0, −g)`, the top moving along the slope at the loading velocity. `dip = 0` is
/// [`SliderScene::build_model`] itself (no frames, the paper's model bit for bit).
///
/// # Errors
/// As [`SliderScene::build_model`]; [`rsf::Error::InvalidParameter`] named `dip` for a
/// non-finite angle or one of 90° or more.
pub fn inclined_slider_model(scene: &SliderScene, dip: f64) -> rsf::Result<Model<2>> {
    if !(dip.is_finite() && dip.abs() < std::f64::consts::FRAC_PI_2) {
        return Err(rsf::Error::InvalidParameter {
            name: "dip".into(),
            reason: format!(
                "{} degrees must be finite and below 90 in size",
                dip.to_degrees()
            ),
        });
    }
    if dip == 0.0 {
        return scene.build_model();
    }
    scene.validate()?;
    let flat = pipping_slider_coarse(scene.diagonal);
    let vertices = flat.vertices().iter().map(|&x| dip_point(dip, x)).collect();
    let mut mesh = SimplexMesh::new(vertices, flat.cells().to_vec())?;
    let back = |x: &[f64; 2]| dip_point(-dip, *x);
    mesh.tag_boundary(TAG_NEUMANN, |x| {
        let y = back(x);
        y[0] < 1e-9 || y[0] > 5.0 - 1e-9
    });
    mesh.tag_boundary(TAG_DIRICHLET, |x| back(x)[1] > 1.0 - 1e-9);
    mesh.tag_boundary(TAG_FRICTIONAL, |x| back(x)[1] < 1e-9);
    slider_like_model(
        ModelBuilder::refined(mesh, scene.level)?,
        scene,
        [0.0, -scene.gravity_m_per_s2],
        dip_point(dip, [scene.loading_velocity_m_per_s, 0.0]),
    )
}

/// The slider's scene on the mesh (hierarchy) of `builder`, whose boundary carries the
/// paper's tags: the paper's material, `gravity` (m/s²), the part [`TAG_DIRICHLET`] moving
/// at `top_velocity` (m/s) times the scene's loading ramp, [`TAG_FRICTIONAL`] the fault;
/// no mass matrix for an integrator without inertia.
///
/// # Errors
/// As [`ModelBuilder::build`].
pub(crate) fn slider_like_model(
    builder: ModelBuilder<2>,
    scene: &SliderScene,
    gravity: [f64; 2],
    top_velocity: [f64; 2],
) -> rsf::Result<Model<2>> {
    let builder = builder
        .material(scene.material())
        .gravity(gravity)
        .dirichlet(TAG_DIRICHLET, top_velocity)
        .frictional_boundary(TAG_FRICTIONAL)
        .loading(scene.loading());
    if scene.integrator.uses_mass() {
        builder.build()
    } else {
        builder.without_mass().build()
    }
}
