//! The paper's slider on a curved base (issue 24): the block's frictional base is a
//! circular arc, read from a Gmsh mesh and refined onto the arc; the model carries nodal
//! frames on every base node but the arc's lowest point (docs/math.md §10.1).

use std::path::Path;

use crate::SliderScene;
use rsf::fem::{read_gmsh, MeshHierarchy, TAG_FRICTIONAL};
use rsf::{Model, ModelBuilder};

use crate::incline::slider_like_model;

/// The Gmsh fixture of the block on the arc (`arc_block.msh` with its `arc_block.geo`,
/// crates/rsf-fem/tests/fixtures): x ∈ [0, 5] m between the arc and y = 1 m, physical
/// groups `frictional` (the arc), `dirichlet` (the top), `neumann` (the sides).
pub const ARC_BLOCK_MESH: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../rsf-fem/tests/fixtures/arc_block.msh"
);

/// Radius of the base arc of [`ARC_BLOCK_MESH`] (m).
pub const ARC_RADIUS_M: f64 = 10.0;

/// Centre of the base arc of [`ARC_BLOCK_MESH`] (m): the arc is the circle's lower branch,
/// through (2.5, 0).
pub const ARC_CENTRE: [f64; 2] = [2.5, ARC_RADIUS_M];

/// The point of the base arc above or below `x` (the projection along y; for
/// |x₀ − 2.5| < R). Refining with it keeps the base nodes of a mesh equally spaced in x
/// equally spaced, so the spacing along the arc varies smoothly on every level (what the
/// nodal normals' second-order accuracy needs).
pub fn onto_arc(x: &[f64; 2]) -> [f64; 2] {
    let u = x[0] - ARC_CENTRE[0];
    [
        x[0],
        ARC_CENTRE[1] - (ARC_RADIUS_M * ARC_RADIUS_M - u * u).sqrt(),
    ]
}

/// The slider's scene on the block of the Gmsh file `mesh` (groups as in
/// [`ARC_BLOCK_MESH`]), refined `scene.level` times with the new base nodes moved onto the
/// arc ([`onto_arc`]): the paper's material, gravity `(0, −g)`, the top moving along x at
/// the loading velocity, the arc frictional with bilateral contact.
///
/// # Errors
/// Reading the file ([`rsf::Error::Fem`]); as [`SliderScene::build_model`].
pub fn arc_block_model(scene: &SliderScene, mesh: &Path) -> rsf::Result<Model<2>> {
    scene.validate()?;
    let coarse = read_gmsh::<2>(mesh)?.mesh;
    let hierarchy =
        MeshHierarchy::try_refine_uniformly_onto(coarse, scene.level, TAG_FRICTIONAL, onto_arc)?;
    slider_like_model(
        ModelBuilder::from_hierarchy(hierarchy),
        scene,
        [0.0, -scene.gravity_m_per_s2],
        [scene.loading_velocity_m_per_s, 0.0],
    )
}
