//! Uniform and smooth slip on a vertical rectangle in the plane `y = 0` (issue 55): the
//! model on a tensor grid of Kuhn tetrahedra (the direct solver's meshes) or on a
//! refinement hierarchy (multigrid), against Okada's field.

use std::rc::Rc;

use rsf_fem::{cuboid_from_coordinates, MeshHierarchy, SimplexMesh};
use rsf_halfspace::Rectangle;

use super::common::{band_and_grading, band_lines, material, Errors, Solver};
use super::dislocation::{held_at, Dislocation};
use super::error::{ComparisonError, Result};
use super::measure::{measure, Windows};
use crate::model::{Model, ModelBuilder, Part, PrescribedSlip};

/// A vertical rectangle in the plane `y = 0`: `|x| ≤ half_length`, `-bottom ≤ z ≤ -top`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fault {
    /// Half its length along strike `x` (m).
    pub half_length: f64,
    /// Depth of its top edge (m; 0: surface-breaking).
    pub top: f64,
    /// Depth of its bottom edge (m).
    pub bottom: f64,
    /// Okada's `[U1, U2]` (strike, dip) as a Cartesian slip of the hanging wall (y < 0),
    /// m: `[U1, 0, U2]`.
    pub slip: [f64; 3],
}

impl Fault {
    /// Okada's rectangle of the fault (dip 90°, reference point at the bottom edge).
    fn rectangle(&self) -> Result<Rectangle> {
        Ok(Rectangle::new(
            self.bottom,
            90.0,
            [-self.half_length, self.half_length],
            [0.0, self.bottom - self.top],
        )?)
    }

    /// The polygon of the rectangle grown by `grow` on its inner edges (not along the free
    /// surface), corners along strike then up: its right-hand normal is `−e_y`, Okada's
    /// normal (the plus side `y < 0` is the hanging wall).
    fn polygon(&self, grow: f64) -> [[f64; 3]; 4] {
        let a = self.half_length + grow;
        let zb = -(self.bottom + grow);
        let zt = if self.top == 0.0 {
            0.0
        } else {
            -(self.top - grow)
        };
        [[-a, 0.0, zb], [a, 0.0, zb], [a, 0.0, zt], [-a, 0.0, zt]]
    }

    /// `self` shrunk by `h/2` on every inner edge (not along the free surface): the
    /// rectangle with the moment of a slip that ramps to 0 over the last cell of `h`.
    fn shrunk(&self, h: f64) -> Self {
        Self {
            half_length: self.half_length - h / 2.0,
            top: if self.top == 0.0 {
                0.0
            } else {
                self.top + h / 2.0
            },
            bottom: self.bottom - h / 2.0,
            slip: self.slip,
        }
    }

    /// The comparison's windows: the surface within `|x|, |y| ≤ L` (`L` the length; a
    /// surface trace's split vertices compared `10⁻⁵ L` off the fault, those within `L/4`
    /// of its ends left out), the fault nodes at least a quarter width from the rim.
    fn compare(&self, model: &Model<3>, d: &Dislocation, far: f64) -> Result<(f64, f64, f64)> {
        let tol = 1e-9 * far;
        let length = 2.0 * self.half_length;
        let (a, top, bottom) = (self.half_length, self.top, self.bottom);
        let width = bottom - top;
        let surface = move |x: &[f64; 3]| {
            let near_end = [-1.0, 1.0]
                .iter()
                .any(|s| (x[0] - s * a).hypot(x[1]) < length / 4.0);
            x[2] >= -tol
                && x[0].abs() <= length
                && x[1].abs() <= length
                && !(top == 0.0 && near_end)
        };
        let inner = move |x: &[f64; 3]| {
            let from_rim = (a - x[0].abs()).min(bottom + x[2]).min(-x[2] - top);
            from_rim >= width / 4.0 - 1e-9 * width
        };
        measure(
            model,
            d,
            &Windows {
                n: [0.0, -1.0, 0.0],
                surface: &surface,
                inner: &inner,
                offset: 1e-5 * length,
            },
        )
    }
}

/// The far faces `|x|, |y| = far`, `z = −far` (within `1e-9 far`).
fn far_faces(far: f64) -> impl Fn(&[f64; 3]) -> bool + Send + Sync + 'static {
    let tol = 1e-9 * far;
    move |x: &[f64; 3]| x[0].abs() > far - tol || x[1].abs() > far - tol || x[2] < -far + tol
}

/// How the far faces are held.
pub(crate) enum Held {
    /// At rest.
    Zero,
    /// At the dislocation's displacement.
    At(Rc<Dislocation>),
}

impl Held {
    /// At `dislocation`'s displacement where `at_okada`, else at rest.
    fn at_okada(dislocation: &Rc<Dislocation>, at_okada: bool) -> Self {
        if at_okada {
            Held::At(dislocation.clone())
        } else {
            Held::Zero
        }
    }
}

/// The model of the Cartesian `slip(x)` prescribed at every split pair of the internal
/// fault `polygon` of `builder`'s mesh, the far faces (distance `far`) held as `held`,
/// its static problem solved by `solver` (the build's equilibrium; not solved with
/// `solve` false: its caller solves other data).
pub(crate) fn slip_model(
    builder: ModelBuilder<3>,
    slip: impl Fn([f64; 3]) -> [f64; 3] + 'static,
    far: f64,
    polygon: [[f64; 3]; 4],
    (held, solver, solve): (Held, Solver, bool),
) -> Result<Model<3>> {
    let builder = if solve {
        builder
    } else {
        builder.without_initial_equilibrium()
    };
    let builder = builder
        .material(material())
        .without_mass()
        .fault_tangent([1.0, 0.0, 0.0])
        .internal_fault_polygon("fault", &polygon)
        .internal_slip_at(move |x| Some(PrescribedSlip::Cartesian(slip(*x))))
        .equilibrium_solver(solver.options());
    let far = Part::predicate("far", far_faces(far));
    match held {
        Held::Zero => Ok(builder.dirichlet(far, [0.0; 3]).build()?),
        Held::At(d) => {
            let (field, error) = held_at(d);
            let model = builder.dirichlet_displacement(far, field).build();
            if let Some(e) = error.borrow_mut().take() {
                return Err(e);
            }
            Ok(model?)
        }
    }
}

/// The model of `fault` with cell size `h0 / 2^level` on the fault (the coarsest mesh's
/// grading from `h0` by `ratio`, each interval split into `2^level`), the far faces at
/// distance `far` from the fault's centre line held at Okada's displacement (`at_okada`) or
/// at rest, solved by the direct solver and compared with Okada.
///
/// The model's polygon is Okada's rectangle grown by `h/2` on every inner edge (not along
/// the free surface): the model's slip ramps to 0 over the last cell, so the ramp is then
/// centred on Okada's edge and the two slips have the same moment.
///
/// # Errors
/// Mesh, model (the static solve included) and half-space kernel errors.
pub fn compare_held(
    fault: Fault,
    (h0, level, ratio): (f64, u32, f64),
    far: f64,
    at_okada: bool,
) -> Result<Errors> {
    let h = h0 / f64::from(1u32 << level);
    let grading = (h0, level, ratio);
    let polygon = fault.polygon(h / 2.0);
    let [[_, _, zb], [a, _, _], [_, _, zt], _] = polygon;
    // x: the fault's lines at spacing h (one more cell each side), graded beyond.
    let xs = band_lines((-a, a), h, grading, (-far, far))?;
    // y: the fault plane y = 0, two cells of h each side, graded beyond.
    let ys = band_lines((-h, h), h, grading, (-far, far))?;
    // z (as depth, downwards): for a buried fault equal cells from the surface to the
    // fault's top, h along the fault and one cell more, graded to the bottom; for a
    // surface-breaking one a first cell of h/2 (the fault's lines are then h/2 + i h).
    let surface_breaking = fault.top == 0.0;
    let mut depths: Vec<f64> = if surface_breaking {
        vec![0.0]
    } else {
        let n_top = (-zt / h).ceil() as usize;
        (0..n_top).map(|i| -zt * i as f64 / n_top as f64).collect()
    };
    let start = if surface_breaking { h / 2.0 } else { -zt };
    let n_f = ((-zb - start) / h).round() as usize + 1;
    depths.extend(band_and_grading(start, h, n_f, grading, far)?);
    let zs: Vec<f64> = depths.iter().rev().map(|d| -d).collect();

    let dislocation = Rc::new(Dislocation::uniform(fault.rectangle()?, fault.slip)?);
    let held = Held::at_okada(&dislocation, at_okada);
    let slip = fault.slip;
    let model = slip_model(
        ModelBuilder::new(cuboid_from_coordinates(&xs, &ys, &zs)?),
        move |_| slip,
        far,
        polygon,
        (held, Solver::Direct, true),
    )?;
    let (jump, surface, traction) = fault.compare(&model, &dislocation, far)?;
    Ok(Errors {
        h,
        vertices: model.num_nodes(),
        surface,
        traction,
        jump,
    })
}

/// The comparison on a refinement hierarchy, solved by [`Solver::Multigrid`] (or, to
/// check it, [`Solver::Direct`] on the finest mesh; at `level` 0, the coarsest mesh alone,
/// by the direct solver whichever is asked): the coarsest mesh has spacing `h0`
/// along `fault` and one cell beyond its rim, then cells graded by `ratio` to the far
/// faces; it is refined `level` times (each tetrahedron into eight), so every level's
/// grid lines are the coarser level's and their midpoints. The model's polygon is
/// `fault`'s rectangle itself at every level (its rim on the coarsest mesh's lines); its
/// slip ramps to 0 over the last cell, so the reference it is compared with is Okada's
/// rectangle with the same moment: `fault` shrunk by `h/2` on every inner edge (not along
/// the free surface), `h = h0 / 2^level`. Errors are relative to that reference; the
/// windows (surface, inner nodes) are taken from it as in [`compare_held`].
///
/// # Errors
/// [`ComparisonError::Setup`] for `fault` not on the coarsest grid (its length, width and
/// a buried top not multiples of `h0`); mesh, model (the static solve included:
/// multigrid's "not converged") and half-space kernel errors.
pub fn compare_refined(
    fault: Fault,
    mesh: (f64, u32, f64),
    far: f64,
    at_okada: bool,
    solver: Solver,
) -> Result<Errors> {
    let h = mesh.0 / f64::from(1u32 << mesh.1);
    let reference = fault.shrunk(h);
    let dislocation = Rc::new(Dislocation::uniform(reference.rectangle()?, fault.slip)?);
    let held = Held::at_okada(&dislocation, at_okada);
    let slip = fault.slip;
    let model = refined_model(fault, mesh, far, (held, solver), move |_| slip, true)?;
    let (jump, surface, traction) = reference.compare(&model, &dislocation, far)?;
    Ok(Errors {
        h,
        vertices: model.num_nodes(),
        surface,
        traction,
        jump,
    })
}

/// A smooth slip on the buried rectangle `fault` against the boundary-element field of the
/// same slip (issue 55: the finite-element and boundary-element operators applied to one
/// slip): the slip `fault.slip · cos(π x / 2a) · cos(π (z − z_c) / W)` (zero on the rim;
/// `a` the half length, `z_c` the centre's height, `W` the width) given to the model on
/// the hierarchy as [`compare_refined`]; the reference is `RectangularFault`'s
/// discretisation of it — square cells of side `h` centred on the inner nodes of the
/// fault grid, each with its node's slip, Okada's fields superposed. Errors as
/// [`Errors`] (surface displacement; tractions at the nodes at least a quarter width from
/// the rim) in the windows of the rectangle the cells cover (`fault` shrunk by `h/2`),
/// the far faces held at the reference's displacement (`far`).
///
/// # Errors
/// [`ComparisonError::Setup`] for a surface-breaking `fault` (its slip would not vanish on
/// the free surface's edge), and those of [`compare_refined`].
pub fn compare_smooth(
    fault: Fault,
    mesh: (f64, u32, f64),
    far: f64,
    solver: Solver,
) -> Result<Errors> {
    if fault.top == 0.0 {
        return Err(ComparisonError::Setup(
            "a smooth slip needs a buried fault".into(),
        ));
    }
    let (a, zc, w) = (
        fault.half_length,
        -(fault.top + fault.bottom) / 2.0,
        fault.bottom - fault.top,
    );
    let direction = fault.slip;
    let slip_at = move |x: [f64; 3]| {
        let m = (std::f64::consts::PI * x[0] / (2.0 * a)).cos()
            * (std::f64::consts::PI * (x[2] - zc) / w).cos();
        direction.map(|d| d * m)
    };
    let h = mesh.0 / f64::from(1u32 << mesh.1);
    let (n_x, n_z) = ((2.0 * a / h).round() as usize, (w / h).round() as usize);
    let mut cells = Vec::with_capacity((n_x - 1) * (n_z - 1));
    for i in 1..n_x {
        for j in 1..n_z {
            let (x, depth) = (-a + i as f64 * h, fault.bottom - j as f64 * h);
            let rect = Rectangle::new(depth + h / 2.0, 90.0, [x - h / 2.0, x + h / 2.0], [0.0, h])?;
            cells.push((rect, slip_at([x, 0.0, -depth])));
        }
    }
    let dislocation = Rc::new(Dislocation::of(cells, Box::new(slip_at))?);
    let model = refined_model(
        fault,
        mesh,
        far,
        (Held::At(dislocation.clone()), solver),
        slip_at,
        true,
    )?;
    let (jump, surface, traction) = fault.shrunk(h).compare(&model, &dislocation, far)?;
    Ok(Errors {
        h,
        vertices: model.num_nodes(),
        surface,
        traction,
        jump,
    })
}

/// The grid lines `[x, y, z]` of the coarsest mesh of [`compare_refined`]: spacing `h0`
/// along `fault` and one cell beyond its rim, graded by `ratio` to the far faces.
fn coarse_lines(fault: Fault, (h0, ratio): (f64, f64), far: f64) -> Result<[Vec<f64>; 3]> {
    let a = fault.half_length;
    let xs = band_lines((-a, a), h0, (h0, 0, ratio), (-far, far))?;
    let ys = band_lines((-h0, h0), h0, (h0, 0, ratio), (-far, far))?;
    // Depths: equal cells from the surface to the fault's top (none if it breaks the
    // surface), h0 along the fault and one cell more, graded to the bottom.
    let n_top = (fault.top / h0).ceil() as usize;
    let mut depths: Vec<f64> = (0..n_top)
        .map(|i| fault.top * i as f64 / n_top as f64)
        .collect();
    let n_f = ((fault.bottom - fault.top) / h0).round() as usize + 1;
    depths.extend(band_and_grading(fault.top, h0, n_f, (h0, 0, ratio), far)?);
    let zs: Vec<f64> = depths.iter().rev().map(|d| -d).collect();
    Ok([xs, ys, zs])
}

/// The vertices of the model of [`compare_refined`] and [`compare_smooth`] before the
/// fault is split: `(n − 1) 2^level + 1` lines along each axis of the coarsest mesh's `n`.
///
/// # Errors
/// As the coarsest mesh's lines ([`compare_refined`]).
pub fn hierarchy_vertices(
    fault: Fault,
    (h0, level, ratio): (f64, u32, f64),
    far: f64,
) -> Result<f64> {
    let lines = coarse_lines(fault, (h0, ratio), far)?;
    let k = 2f64.powi(level as i32);
    Ok(lines
        .iter()
        .map(|l| (l.len() as f64 - 1.0) * k + 1.0)
        .product())
}

/// The model of `fault` on the hierarchy of [`compare_refined`], its pairs slipping
/// `slip(x)`, the far faces held as `held`, solved by `solver` (if `solve`).
pub(crate) fn refined_model(
    fault: Fault,
    (h0, level, ratio): (f64, u32, f64),
    far: f64,
    (held, solver): (Held, Solver),
    slip: impl Fn([f64; 3]) -> [f64; 3] + 'static,
    solve: bool,
) -> Result<Model<3>> {
    let on_grid = |len: f64| ((len / h0).round() * h0 - len).abs() < 1e-9 * h0;
    if !on_grid(2.0 * fault.half_length) || !on_grid(fault.bottom - fault.top) {
        return Err(ComparisonError::Setup(format!(
            "the fault's length {} and width {} must be multiples of h0 = {h0}",
            2.0 * fault.half_length,
            fault.bottom - fault.top
        )));
    }
    let [xs, ys, zs] = coarse_lines(fault, (h0, ratio), far)?;
    let coarse = cuboid_from_coordinates(&xs, &ys, &zs)?;
    // Level 0 is the coarsest mesh alone: no hierarchy for multigrid, a direct solve.
    let solver = if level == 0 { Solver::Direct } else { solver };
    let builder = match solver {
        Solver::Multigrid => ModelBuilder::refined(coarse, level as usize)?,
        Solver::Direct => ModelBuilder::new(refine(coarse, level)?),
    };
    slip_model(
        builder,
        slip,
        far,
        fault.polygon(0.0),
        (held, solver, solve),
    )
}

/// `mesh` refined `level` times uniformly (the finest mesh of [`ModelBuilder::refined`]).
fn refine(mesh: SimplexMesh<3>, level: u32) -> Result<SimplexMesh<3>> {
    Ok(MeshHierarchy::try_refine_uniformly(mesh, level as usize)?
        .finest()
        .clone())
}
