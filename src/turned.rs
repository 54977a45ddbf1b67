//! The 3-D slider turned about a skew axis (issue 24): mesh, gravity and loading rotated,
//! so that its fault has a nodal frame at every node (docs/math.md §10.1). The same
//! discrete problem as the unturned slider in other coordinates; used to measure what the
//! frames cost (examples/frames_cost.rs, docs/performance.md).

use rsf::fem::{SimplexMesh, TAG_DIRICHLET, TAG_FRICTIONAL, TAG_NEUMANN};
use rsf::time::VelocityIntegrator;
use rsf::{slider_3d_coarse, LateralBoundary, Model, ModelBuilder, Slider3dScene, TAG_LATERAL};

/// `x` rotated by `phi` (rad) about the unit axis `(1, 2, 3)/√14` (Rodrigues' formula):
/// aligned with no coordinate axis or plane.
pub fn skew_rotation(phi: f64, x: [f64; 3]) -> [f64; 3] {
    let l = 14f64.sqrt();
    let k = [1.0 / l, 2.0 / l, 3.0 / l];
    let (s, c) = phi.sin_cos();
    let kx = [
        k[1] * x[2] - k[2] * x[1],
        k[2] * x[0] - k[0] * x[2],
        k[0] * x[1] - k[1] * x[0],
    ];
    let kdx = k[0] * x[0] + k[1] * x[1] + k[2] * x[2];
    std::array::from_fn(|r| x[r] * c + kx[r] * s + k[r] * kdx * (1.0 - c))
}

/// The model of the 3-D slider `scene` turned by `phi` (rad) about [`skew_rotation`]'s
/// axis: the coarse mesh's vertices, gravity and the top's velocity rotated, the faces
/// tagged as [`slider_3d_coarse`]'s, and the fault's reference tangent
/// ([`ModelBuilder::fault_tangent`]) the rotated `e_x`, so that the slip along the first
/// tangent is the unturned slider's slip along x. The coarse cells are Kuhn paths, whose
/// refinement order is increasing vertex index: the turned hierarchy is the unturned one,
/// rotated. `phi = 0` is [`Slider3dScene::build_model`] itself.
///
/// # Errors
/// As [`Slider3dScene::build_model`]; [`rsf::Error::InvalidParameter`] named `lateral`
/// for plane-strain lateral faces (a constraint on Cartesian `u_z`, not turned here) and
/// named `angle` for a non-finite angle.
pub fn turned_slider_3d_model(scene: &Slider3dScene, phi: f64) -> rsf::Result<Model<3>> {
    let invalid = |name: &str, reason: String| rsf::Error::InvalidParameter {
        name: name.into(),
        reason,
    };
    if !phi.is_finite() {
        return Err(invalid("angle", format!("{phi} rad must be finite")));
    }
    if phi == 0.0 {
        return scene.build_model();
    }
    if scene.lateral != LateralBoundary::Free {
        return Err(invalid(
            "lateral",
            "the turned 3-D slider has free lateral faces only".into(),
        ));
    }
    scene.validate()?;
    let flat = slider_3d_coarse(scene.width_m)?;
    let vertices = flat
        .vertices()
        .iter()
        .map(|&x| skew_rotation(phi, x))
        .collect();
    let cells = flat
        .cells()
        .chunks_exact(4)
        .flat_map(|c| {
            let mut c = [c[0], c[1], c[2], c[3]];
            c.sort_unstable();
            c
        })
        .collect();
    let mut coarse = SimplexMesh::from_ordered_cells(vertices, cells)?;
    let w = scene.width_m;
    let back = |x: &[f64; 3]| skew_rotation(-phi, *x);
    coarse.tag_boundary(TAG_NEUMANN, |x| {
        let y = back(x);
        y[0] < 1e-9 || y[0] > 5.0 - 1e-9
    });
    coarse.tag_boundary(TAG_LATERAL, |x| {
        let y = back(x);
        y[2] < 1e-9 * w || y[2] > w * (1.0 - 1e-9)
    });
    coarse.tag_boundary(TAG_DIRICHLET, |x| back(x)[1] > 1.0 - 1e-9);
    coarse.tag_boundary(TAG_FRICTIONAL, |x| back(x)[1] < 1e-9);
    let s = &scene.slider;
    let builder = ModelBuilder::refined(coarse, s.level)?
        .material(s.material())
        .gravity(skew_rotation(phi, [0.0, -s.gravity_m_per_s2, 0.0]))
        .dirichlet(
            TAG_DIRICHLET,
            skew_rotation(phi, [s.loading_velocity_m_per_s, 0.0, 0.0]),
        )
        .frictional_boundary(TAG_FRICTIONAL)
        .fault_tangent(skew_rotation(phi, [1.0, 0.0, 0.0]))
        .loading(s.loading());
    if s.integrator.uses_mass() {
        builder.build()
    } else {
        builder.without_mass().build()
    }
}
