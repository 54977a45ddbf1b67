//! Uniform slip on a rectangle dipping at 45° (issue 70): the plane `y − z = depth` of
//! Okada's frame, which a Kuhn grid of cubes resolves (its cells' faces include the
//! diagonal planes `x_i − x_j = const`, not `x_i + x_j = const`), so the fault is a surface
//! of mesh faces without a mesh generator.

use std::f64::consts::SQRT_2;
use std::rc::Rc;

use rsf_fem::{cuboid_from_coordinates, MeshHierarchy};
use rsf_halfspace::Rectangle;

use super::common::{band_lines, material, Errors, Solver};
use super::dislocation::{held_at, Dislocation};
use super::error::{ComparisonError, Result};
use super::measure::{measure, Windows};
use crate::model::{ModelBuilder, Part, PrescribedSlip};

/// A rectangle dipping at 45° in Okada's frame (`x` along strike, `z` up, the free surface
/// `z = 0`; docs/halfspace.md §1): its bottom edge at depth `depth` in the plane `y = 0`,
/// its points `(ξ, η/√2, −depth + η/√2)` for `|ξ| ≤ half_length`, `0 ≤ η ≤ width` — the
/// plane `y − z = depth`, dipping towards `−y`; the hanging wall is the side `y − z <
/// depth` (above the fault), Okada's normal `n = (0, −1, 1)/√2` points into it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DippingFault {
    /// Half its length along strike `x` (m).
    pub half_length: f64,
    /// Depth of its bottom edge (m).
    pub depth: f64,
    /// Its width along dip (m): it rises `width/√2`; the top edge at depth
    /// `depth − width/√2 > 0` (buried).
    pub width: f64,
    /// Okada's `[U1, U2]`: the hanging wall's motion relative to the footwall along
    /// strike and up dip (m; `U2 > 0` reverse).
    pub slip: [f64; 2],
}

impl DippingFault {
    /// The Cartesian slip `U1 e_s + U2 e_d`, `e_d = (0, 1, 1)/√2`.
    fn cartesian_slip(&self) -> [f64; 3] {
        let [u1, u2] = self.slip;
        [u1, u2 / SQRT_2, u2 / SQRT_2]
    }

    /// Okada's rectangle of the part `ξ ∈ [−a + s, a − s]`, `η ∈ [t, W − t]`.
    fn rectangle(&self, s: f64, t: f64) -> Result<Rectangle> {
        let a = self.half_length;
        Ok(Rectangle::new(
            self.depth,
            45.0,
            [-a + s, a - s],
            [t, self.width - t],
        )?)
    }

    /// The polygon of the whole rectangle, corners along strike then up dip: its
    /// right-hand normal is Okada's `n`, so the model's plus side is the hanging wall.
    fn polygon(&self) -> [[f64; 3]; 4] {
        let (a, rise) = (self.half_length, self.width / SQRT_2);
        let (zb, zt) = (-self.depth, -self.depth + rise);
        [[-a, 0.0, zb], [a, 0.0, zb], [a, rise, zt], [-a, rise, zt]]
    }
}

/// The dipping rectangle `fault` with uniform slip, built through the public API — the
/// fault a polygon of the mesh (`internal_fault_polygon`), its every pair slipped by
/// `internal_slip_at` (no frictional node), the far faces held at Okada's displacement
/// by `dirichlet_displacement`, the static problem the build's equilibrium — and compared
/// with Okada's half-space.
///
/// The mesh: the coarsest is a tensor grid of Kuhn tetrahedra (`cuboid_from_coordinates`)
/// of cubes of side `h0` in the band around the fault (one cell beyond its rim), graded by
/// `ratio` per cell beyond it to the far faces `x = ±far`, `y = y_c ± far`, `z = z_c −
/// far` (`(0, y_c, z_c)` the fault's centre), equal cells of about `h0` from the band up
/// to the free surface; refined `level` times (each tetrahedron into eight: the fault's
/// plane stays resolved), `h = h0/2^level`. The model's slip ramps to 0 over the last
/// cell before the rim — `h` along strike, `h√2` along dip (the fault grid's spacing) —
/// so the reference is Okada's rectangle with the model's moment, shrunk by `h/2` along
/// strike and `h/√2` along dip on every edge. Measured ([`Errors`]): the surface
/// displacement within `|x|, |y − y_c| ≤ L` (`L` the length), the traction at the pairs at
/// least a quarter of the reference's smaller side from its rim (docs/faults-inside.md,
/// "A prescribed slip").
///
/// # Errors
/// [`ComparisonError::Setup`] for a fault whose length, rise `width/√2` or depth is not a
/// whole number of `h0`, or whose top is not at least `h0` deep; mesh, model (the static
/// solve) and half-space kernel errors.
pub fn compare_dipping(
    fault: DippingFault,
    (h0, level, ratio): (f64, u32, f64),
    far: f64,
    solver: Solver,
) -> Result<Errors> {
    let (a, rise) = (fault.half_length, fault.width / SQRT_2);
    let top = fault.depth - rise;
    let whole = |len: f64| len > 0.0 && ((len / h0).round() * h0 - len).abs() < 1e-9 * h0;
    if !(whole(2.0 * a) && whole(rise) && whole(fault.depth) && top >= h0 * (1.0 - 1e-9)) {
        return Err(ComparisonError::Setup(format!(
            "the dipping fault's length {}, rise {rise} and depth {} must be whole numbers \
             of h0 = {h0} and its top at least h0 deep",
            2.0 * a,
            fault.depth
        )));
    }
    let h = h0 / f64::from(1u32 << level);
    let (yc, zc) = (rise / 2.0, -fault.depth + rise / 2.0);
    let grading = (h0, 0, ratio);
    let xs = band_lines((-a, a), h0, grading, (-far, far))?;
    let ys = band_lines((0.0, rise), h0, grading, (yc - far, yc + far))?;
    // z: the band from one cell below the bottom edge to one above the top edge, graded
    // down to z_c − far; equal cells of about h0 from the band's top to the surface.
    let band = band_lines((-fault.depth, -top), h0, grading, (zc - far, -top + h0))?;
    let band_top = -top + h0;
    let mut zs = band;
    if band_top < -1e-9 * h0 {
        let n_top = (-band_top / h0).round().max(1.0) as usize;
        zs.extend((1..=n_top).map(|i| band_top - band_top * i as f64 / n_top as f64));
    }
    let coarse = cuboid_from_coordinates(&xs, &ys, &zs)?;
    // Level 0 is the coarsest mesh alone: no hierarchy for multigrid, a direct solve.
    let solver = if level == 0 { Solver::Direct } else { solver };
    let builder = match solver {
        Solver::Multigrid => ModelBuilder::refined(coarse, level as usize)?,
        Solver::Direct => ModelBuilder::new(
            MeshHierarchy::try_refine_uniformly(coarse, level as usize)?
                .finest()
                .clone(),
        ),
    };

    let reference = fault.rectangle(h / 2.0, h / SQRT_2)?;
    let slip = fault.cartesian_slip();
    let dislocation = Rc::new(Dislocation::uniform(reference, slip)?);
    let tol = 1e-9 * far;
    let far_faces = move |x: &[f64; 3]| {
        x[0].abs() > far - tol || (x[1] - yc).abs() > far - tol || x[2] < zc - far + tol
    };
    let (field, error) = held_at(dislocation.clone());
    let model = builder
        .material(material())
        .without_mass()
        .dirichlet_displacement(Part::predicate("far", far_faces), field)
        .fault_tangent([1.0, 0.0, 0.0])
        .internal_fault_polygon("fault", &fault.polygon())
        .internal_slip_at(move |_| Some(PrescribedSlip::Cartesian(slip)))
        .equilibrium_solver(solver.options())
        .build();
    if let Some(e) = error.borrow_mut().take() {
        return Err(e);
    }
    let model = model?;

    // The windows of the reference rectangle.
    let length = 2.0 * a;
    let (a_ref, w_ref) = (a - h / 2.0, fault.width - 2.0 * h / SQRT_2);
    let eta0 = h / SQRT_2;
    let depth = fault.depth;
    let surface =
        move |x: &[f64; 3]| x[2] >= -tol && x[0].abs() <= length && (x[1] - yc).abs() <= length;
    let inner = move |x: &[f64; 3]| {
        let eta = (x[2] + depth) * SQRT_2 - eta0;
        let from_rim = (a_ref - x[0].abs()).min(eta).min(w_ref - eta);
        from_rim >= w_ref.min(2.0 * a_ref) / 4.0 - 1e-9 * w_ref
    };
    let (jump, surface, traction) = measure(
        &model,
        &dislocation,
        &Windows {
            n: [0.0, -1.0 / SQRT_2, 1.0 / SQRT_2],
            surface: &surface,
            inner: &inner,
            offset: 1e-5 * length,
        },
    )?;
    Ok(Errors {
        h,
        vertices: model.num_nodes(),
        surface,
        traction,
        jump,
    })
}
