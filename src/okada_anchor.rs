//! The 3-D finite-element model against Okada's half-space (issue 55, docs/three-d.md
//! "Against Okada's half-space (issue 55)"), shared by `examples/okada_anchor.rs` and the
//! test `tests/okada_anchor.rs`: uniform slip on a vertical rectangle prescribed as the
//! creep of every split pair of an internal fault, the static problem solved once with the
//! direct solver and no friction (the "velocity" is the displacement of that slip, a
//! linear problem), the surface displacement and the on-fault traction compared with
//! Okada (1992) as `rsf-halfspace` evaluates it (docs/halfspace.md).
//!
//! The model's frame is Okada's: `x` along strike, `z` up, the free surface `z = 0`; the
//! fault is the vertical plane `y = 0`.
//!
//! **The rim.** A rim of the fault inside the body is a shared tip in the model (zero
//! jump at the rim node): the finite-element slip is `s` at the inner nodes and ramps
//! linearly to 0 over the last cell. The model's polygon is therefore Okada's rectangle
//! grown by `h/2` on every inner edge (not along the free surface): the ramp is then
//! centred on Okada's edge, the two slips have the same moment, and their difference
//! (odd about the edge, zero mean) acts at distance `r` as a line of dipoles of strength
//! `O(h²)` — second order, below the discretisation error measured.
//!
//! **Signs.** The polygon's corners go along strike first, then up, so its right-hand
//! normal is `−e_y`: the plus side is `y < 0`, Okada's hanging wall of a vertical fault
//! (docs/halfspace.md §1), and the model's jump `u⁺ − u⁻` is Okada's `U1 e_s + U2 e_d`
//! (`e_d = e_z` at 90° dip), checked on the model's own displacements ([`Errors::jump`]).
//!
//! **Tractions.** At a pair `(p⁻, p⁺)` the residual of the prescribed jump components is
//! `f'_j = Rᵀ f⁺` (the plus copy's force; `f⁺ + f⁻ = 0` at equilibrium, whatever the
//! sharing of the jump), and `f⁺ = ∫ φ σ n⁺_out dS` with the plus side's outward normal
//! `e_y` on the fault: `f⁺ / w ≈ σ e_y`, `w` the node's lumped weight (a third of each
//! adjacent triangle's area). Compared with Okada's `σ e_y` at the nodes at least a
//! quarter of the fault's width from its rim.
//!
//! The builder wants one frictional node: one pair (an inner corner of the fault grid) is
//! left to friction and its jump fixed by hand before the solve.

use rsf::direct::{DirectOptions, DirectSolver};
use rsf::fem::{cuboid_from_coordinates, geometric_grading, SimplexMesh};
use rsf::model::CreepRate;
use rsf::model::InternalFault;
use rsf::nonsmooth::{NoNonlinearity, NonsmoothSolver, Stopping};
use rsf::tnnmg::{Tnnmg, TnnmgOptions};
use rsf::{Material, Model, ModelBuilder, Part};
use rsf_halfspace::{Medium, Okada, Rectangle};

type AnyError = Box<dyn std::error::Error>;

mod modes;
pub use modes::{compare_modes, ModeComparison};

/// Shear modulus μ (Pa).
pub const MU: f64 = 3e10;
/// Poisson's ratio ν.
pub const NU: f64 = 0.25;
/// The slip (m).
pub const SLIP: f64 = 1.0;

/// A vertical rectangle in the plane `y = 0`: `|x| ≤ half_length`, `-bottom ≤ z ≤ -top`.
#[derive(Clone, Copy)]
pub struct Fault {
    /// Half its length along strike `x` (m).
    pub half_length: f64,
    /// Depth of its top edge (m; 0: surface-breaking).
    pub top: f64,
    /// Depth of its bottom edge (m).
    pub bottom: f64,
    /// Okada's `[U1, U2]` (strike, dip) as a Cartesian slip of the hanging wall (y < 0),
    /// m.
    pub slip: [f64; 3],
}

/// `n` intervals of `spacing` each from `start` upwards, then graded intervals (the
/// grading by `ratio` of the coarsest mesh from `h0`, each interval split into `2^level`)
/// to `end`.
fn band_and_grading(
    start: f64,
    spacing: f64,
    n: usize,
    (h0, level, ratio): (f64, u32, f64),
    end: f64,
) -> Result<Vec<f64>, AnyError> {
    let mut c: Vec<f64> = (0..=n).map(|i| start + i as f64 * spacing).collect();
    let last = c[n];
    if end - last > 1e-9 * h0 {
        let graded = geometric_grading(h0, 0.0, ratio, end - last)?;
        let parts = 1usize << level;
        for w in graded.windows(2) {
            for k in 1..=parts {
                c.push(last + w[0] + (w[1] - w[0]) * k as f64 / parts as f64);
            }
        }
    }
    Ok(c)
}

/// The comparison of one mesh.
pub struct Errors {
    /// The cell size on the fault (m).
    pub h: f64,
    /// Vertices of the model.
    pub vertices: usize,
    /// max over the surface window of `|u_FE − u_Okada|`, relative to max `|u_Okada|` there.
    pub surface: f64,
    /// max over the inner fault nodes of `|t_FE − σ e_y|`, relative to max `|σ e_y|` there.
    pub traction: f64,
    /// max deviation of the model's jump from the prescribed slip (m).
    pub jump: f64,
}

/// The model of `fault` with cell size `h0 / 2^level` on the fault (the coarsest mesh's
/// grading from `h0` by `ratio`, each interval split into `2^level`), the far faces at
/// distance `far` from the fault's centre line held at Okada's displacement (`at_okada`) or
/// at 0, solved and compared with Okada.
///
/// # Errors
/// Mesh, model, solver and Okada errors.
pub fn compare_held(
    fault: Fault,
    (h0, level, ratio): (f64, u32, f64),
    far: f64,
    at_okada: bool,
) -> Result<Errors, AnyError> {
    let h = h0 / f64::from(1u32 << level);
    let surface_breaking = fault.top == 0.0;
    // The model's polygon: Okada's rectangle grown by h/2 on the inner edges.
    let a = fault.half_length + h / 2.0;
    let zb = -(fault.bottom + h / 2.0);
    let zt = if surface_breaking {
        0.0
    } else {
        -(fault.top - h / 2.0)
    };
    // x: the fault's lines at spacing h (one more cell each side), graded beyond.
    let n_x = ((2.0 * a) / h).round() as usize + 2;
    let right = band_and_grading(-a - h, h, n_x, (h0, level, ratio), far)?;
    let mut xs: Vec<f64> = right.iter().rev().map(|x| -x).collect();
    xs.retain(|&x| x < -a - h - 1e-9 * h);
    xs.extend(&right);
    // y: the fault plane y = 0, two cells of h each side, graded beyond.
    let half_y = band_and_grading(0.0, h, 2, (h0, level, ratio), far)?;
    let mut ys: Vec<f64> = half_y.iter().rev().map(|y| -y).collect();
    ys.extend(&half_y[1..]);
    // z (as depth, downwards): for a buried fault equal cells from the surface to the
    // fault's top, h along the fault and one cell more, graded to the bottom; for a
    // surface-breaking one a first cell of h/2 (the fault's lines are then h/2 + i h).
    let mut depths: Vec<f64> = if surface_breaking {
        vec![0.0]
    } else {
        let n_top = (-zt / h).ceil() as usize;
        (0..n_top).map(|i| -zt * i as f64 / n_top as f64).collect()
    };
    let start = if surface_breaking { h / 2.0 } else { -zt };
    let n_f = ((-zb - start) / h).round() as usize + 1;
    depths.extend(band_and_grading(start, h, n_f, (h0, level, ratio), far)?);
    let zs: Vec<f64> = depths.iter().rev().map(|d| -d).collect();

    let mesh = cuboid_from_coordinates(&xs, &ys, &zs)?;
    let probe = [-a + h, 0.0, zb + h];
    let slip = fault.slip;
    let model = slip_model(
        ModelBuilder::new(mesh),
        move |_| slip,
        far,
        [[-a, 0.0, zb], [a, 0.0, zb], [a, 0.0, zt], [-a, 0.0, zt]],
        (probe, h),
    )?;
    solve_and_compare(
        &model,
        fault,
        (probe, h),
        (far, at_okada),
        Solver::Direct,
        &Dislocation::uniform(fault)?,
    )
}

/// How the static problem is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// The direct solver on the finest mesh (its factor's memory grows like the vertices
    /// to the power 4/3 and more: the limit of [`compare_held`]).
    Direct,
    /// TNNMG on the refinement hierarchy (no nonlinearity: one Gauss–Seidel sweep and
    /// conjugate gradients preconditioned by multigrid V-cycles per iteration, to a
    /// relative correction of 1e-10 in the energy norm): memory linear in the vertices.
    Multigrid,
}

/// The relative energy-norm correction at which [`Solver::Multigrid`] stops.
pub const MULTIGRID_TOLERANCE: f64 = 1e-10;

/// [`Solver::Multigrid`] for `model`'s stiffness with the dofs `fixed` held: TNNMG on the
/// model's hierarchy, no nonlinearity, to [`MULTIGRID_TOLERANCE`], on the default threads.
fn multigrid(model: &Model<3>, fixed: &[bool]) -> Result<Tnnmg<3>, AnyError> {
    let options = TnnmgOptions {
        stopping: Stopping {
            absolute: 0.0,
            relative: MULTIGRID_TOLERANCE,
            max_iterations: 500,
        },
        ..TnnmgOptions::default()
    };
    Ok(Tnnmg::<3>::new(
        model.stiffness.as_ref(),
        fixed,
        &model.prolongations,
        None,
        options,
    )?
    .with_parallelism(rsf::Parallelism::default()))
}

/// The comparison on a refinement hierarchy, solved by [`Solver::Multigrid`] (or, to
/// check it, [`Solver::Direct`] on the finest mesh): the coarsest mesh has spacing `h0`
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
/// `fault` not on the coarsest grid (its length, width and a buried top not multiples of
/// `h0`), mesh, model, solver (including TNNMG's "not converged") and Okada errors.
pub fn compare_refined(
    fault: Fault,
    mesh: (f64, u32, f64),
    far: f64,
    at_okada: bool,
    solver: Solver,
) -> Result<Errors, AnyError> {
    let slip = fault.slip;
    let (model, probe, h) = refined_model(fault, mesh, far, solver, move |_| slip)?;
    let reference = shrunk(fault, h);
    solve_and_compare(
        &model,
        reference,
        (probe, h),
        (far, at_okada),
        solver,
        &Dislocation::uniform(reference)?,
    )
}

/// `fault`'s rectangle shrunk by `h/2` on every inner edge (not along the free surface):
/// the rectangle with the moment of a slip that ramps to 0 over the last cell of `h`.
fn shrunk(fault: Fault, h: f64) -> Fault {
    Fault {
        half_length: fault.half_length - h / 2.0,
        top: if fault.top == 0.0 {
            0.0
        } else {
            fault.top + h / 2.0
        },
        bottom: fault.bottom - h / 2.0,
        slip: fault.slip,
    }
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
/// A surface-breaking `fault` (its slip would not vanish on the free surface's edge), and
/// those of [`compare_refined`].
pub fn compare_smooth(
    fault: Fault,
    mesh: (f64, u32, f64),
    far: f64,
    solver: Solver,
) -> Result<Errors, AnyError> {
    if fault.top == 0.0 {
        return Err("a smooth slip needs a buried fault".into());
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
    let (model, probe, h) = refined_model(fault, mesh, far, solver, slip_at)?;
    let (n_x, n_z) = ((2.0 * a / h).round() as usize, (w / h).round() as usize);
    let mut cells = Vec::with_capacity((n_x - 1) * (n_z - 1));
    for i in 1..n_x {
        for j in 1..n_z {
            let (x, depth) = (-a + i as f64 * h, fault.bottom - j as f64 * h);
            let rect = Rectangle::new(depth + h / 2.0, 90.0, [x - h / 2.0, x + h / 2.0], [0.0, h])?;
            cells.push((rect, slip_at([x, 0.0, -depth])));
        }
    }
    let dislocation = Dislocation::of(cells, Box::new(slip_at))?;
    solve_and_compare(
        &model,
        shrunk(fault, h),
        (probe, h),
        (far, true),
        solver,
        &dislocation,
    )
}

/// The grid lines `[x, y, z]` of the coarsest mesh of [`compare_refined`]: spacing `h0`
/// along `fault` and one cell beyond its rim, graded by `ratio` to the far faces.
fn coarse_lines(
    fault: Fault,
    (h0, ratio): (f64, f64),
    far: f64,
) -> Result<[Vec<f64>; 3], AnyError> {
    let a = fault.half_length;
    let n_x = ((2.0 * a) / h0).round() as usize + 2;
    let right = band_and_grading(-a - h0, h0, n_x, (h0, 0, ratio), far)?;
    let mut xs: Vec<f64> = right.iter().rev().map(|x| -x).collect();
    xs.retain(|&x| x < -a - h0 - 1e-9 * h0);
    xs.extend(&right);
    let half_y = band_and_grading(0.0, h0, 2, (h0, 0, ratio), far)?;
    let mut ys: Vec<f64> = half_y.iter().rev().map(|y| -y).collect();
    ys.extend(&half_y[1..]);
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
) -> Result<f64, AnyError> {
    let lines = coarse_lines(fault, (h0, ratio), far)?;
    let k = 2f64.powi(level as i32);
    Ok(lines
        .iter()
        .map(|l| (l.len() as f64 - 1.0) * k + 1.0)
        .product())
}

/// The model of `fault` on the hierarchy of [`compare_refined`], its pairs slipping
/// `slip(x)`: the model, the position of the pair left to friction (set by hand) and `h`.
fn refined_model(
    fault: Fault,
    (h0, level, ratio): (f64, u32, f64),
    far: f64,
    solver: Solver,
    slip: impl Fn([f64; 3]) -> [f64; 3] + 'static,
) -> Result<(Model<3>, [f64; 3], f64), AnyError> {
    let on_grid = |len: f64| ((len / h0).round() * h0 - len).abs() < 1e-9 * h0;
    if !on_grid(2.0 * fault.half_length) || !on_grid(fault.bottom - fault.top) {
        return Err(format!(
            "the fault's length {} and width {} must be multiples of h0 = {h0}",
            2.0 * fault.half_length,
            fault.bottom - fault.top
        )
        .into());
    }
    let a = fault.half_length;
    let [xs, ys, zs] = coarse_lines(fault, (h0, ratio), far)?;
    let coarse = cuboid_from_coordinates(&xs, &ys, &zs)?;

    let h = h0 / f64::from(1u32 << level);
    let (zb, zt) = (-fault.bottom, -fault.top);
    let probe = [-a + h, 0.0, zb + h];
    let builder = match solver {
        Solver::Multigrid => ModelBuilder::refined(coarse, level as usize)?,
        Solver::Direct => ModelBuilder::new(refine(coarse, level)?),
    };
    let model = slip_model(
        builder,
        slip,
        far,
        [[-a, 0.0, zb], [a, 0.0, zb], [a, 0.0, zt], [-a, 0.0, zt]],
        (probe, h),
    )?;
    Ok((model, probe, h))
}

/// `mesh` refined `level` times uniformly (the finest mesh of [`ModelBuilder::refined`]).
fn refine(mesh: SimplexMesh<3>, level: u32) -> Result<SimplexMesh<3>, AnyError> {
    Ok(
        rsf::fem::MeshHierarchy::refine_uniformly(mesh, level as usize)
            .finest()
            .clone(),
    )
}

/// The model of the Cartesian `slip(x)` on the internal fault `polygon` of `builder`'s
/// mesh: the far faces (distance `far`) held (at 0; the caller may overwrite the values),
/// every split pair creeping at its `slip` but the one at `probe` (within `1e-9 h`), which
/// the builder wants as a frictional node.
fn slip_model(
    builder: ModelBuilder<3>,
    slip: impl Fn([f64; 3]) -> [f64; 3] + 'static,
    far: f64,
    polygon: [[f64; 3]; 4],
    (probe, h): ([f64; 3], f64),
) -> Result<Model<3>, AnyError> {
    let e = 2.0 * MU * (1.0 + NU);
    let tol = 1e-9 * far;
    Ok(builder
        .material(Material::new(e, NU, 2700.0))
        .without_mass()
        .dirichlet(
            Part::predicate("far", move |x| {
                x[0].abs() > far - tol || x[1].abs() > far - tol || x[2] < -far + tol
            }),
            [0.0; 3],
        )
        .fault_tangent([1.0, 0.0, 0.0])
        .internal_fault_polygon("fault", &polygon)
        .internal_creep_at(move |x| {
            let at_probe = (0..3).all(|c| (x[c] - probe[c]).abs() < 1e-9 * h);
            (!at_probe).then_some(CreepRate::Cartesian(slip(*x)))
        })
        .build()?)
}

/// A slip imposed on the fault and its field in the half-space: Okada's rectangles, each
/// with its uniform slip (Cartesian, hanging wall `y < 0`), superposed, and the slip the
/// model's split pairs are given at a point.
struct Dislocation {
    medium: Medium,
    /// Each rectangle with Okada's `[U1, U2, 0]`.
    parts: Vec<(Okada, [f64; 3])>,
    slip_at: Box<dyn Fn([f64; 3]) -> [f64; 3]>,
}

impl Dislocation {
    /// Uniform `fault.slip` on `fault`'s rectangle.
    fn uniform(fault: Fault) -> Result<Self, AnyError> {
        let rect = Rectangle::new(
            fault.bottom,
            90.0,
            [-fault.half_length, fault.half_length],
            [0.0, fault.bottom - fault.top],
        )?;
        let slip = fault.slip;
        Self::of(vec![(rect, slip)], Box::new(move |_| slip))
    }

    /// The rectangles `parts` with their Cartesian slips; the model's pairs slip `slip_at`.
    fn of(
        parts: Vec<(Rectangle, [f64; 3])>,
        slip_at: Box<dyn Fn([f64; 3]) -> [f64; 3]>,
    ) -> Result<Self, AnyError> {
        let medium = Medium::from_shear_poisson(MU, NU)?;
        let parts = parts
            .into_iter()
            .map(|(rect, s)| Ok((Okada::new(medium.alpha(), rect)?, [s[0], s[2], 0.0])))
            .collect::<Result<Vec<_>, AnyError>>()?;
        Ok(Self {
            medium,
            parts,
            slip_at,
        })
    }

    /// The displacement and its gradient at `x`: the rectangles' fields summed in order.
    fn at(&self, x: [f64; 3]) -> Result<rsf_halfspace::Deformation, AnyError> {
        let mut parts = self.parts.iter();
        let (okada, u) = parts.next().ok_or("a dislocation without a rectangle")?;
        let mut sum = okada.deformation(x, *u)?;
        for (okada, u) in parts {
            sum = sum.add_scaled(1.0, &okada.deformation(x, *u)?);
        }
        Ok(sum)
    }
}

/// Per vertex, its lumped weight (m²) on the fault: a third of the area of every fault
/// triangle of the minus side it is a corner of (0 off the fault). A fault triangle of the
/// minus side is a face of a cell whose three corners are fault nodes — minus vertices of
/// split pairs or the rim's shared tips, all in the fault's plane — at least one of them a
/// minus vertex (only the minus side's cells hold those; a face of three tips, at a
/// corner of the rim, is left out: its weight is not used).
fn fault_weights(model: &Model<3>, f: &InternalFault<3>) -> Vec<f64> {
    let mut w = vec![0.0; model.num_nodes()];
    let (mut on_fault, mut minus) = (vec![false; w.len()], vec![false; w.len()]);
    for &(m, p) in f.sides.nodes() {
        on_fault[m] = true;
        minus[m] = m != p;
    }
    for cell in model.cells.chunks_exact(4) {
        let corners: Vec<usize> = cell.iter().copied().filter(|&q| on_fault[q]).collect();
        if !corners.iter().any(|&q| minus[q]) {
            continue;
        }
        if let [p, q, r] = corners[..] {
            let (x, y, z) = (model.vertices[p], model.vertices[q], model.vertices[r]);
            let d1: [f64; 3] = std::array::from_fn(|c| y[c] - x[c]);
            let d2: [f64; 3] = std::array::from_fn(|c| z[c] - x[c]);
            let n = [
                d1[1] * d2[2] - d1[2] * d2[1],
                d1[2] * d2[0] - d1[0] * d2[2],
                d1[0] * d2[1] - d1[1] * d2[0],
            ];
            let third = 0.5 * n.iter().map(|c| c * c).sum::<f64>().sqrt() / 3.0;
            for v in [p, q, r] {
                w[v] += third;
            }
        }
    }
    w
}

/// Solves `model` (its pairs slipping as `dislocation` says, the one at `probe` set by
/// hand) and compares it with `dislocation`'s field in the windows of `fault`.
fn solve_and_compare(
    model: &Model<3>,
    fault: Fault,
    (probe, h): ([f64; 3], f64),
    (far, at_okada): (f64, bool),
    solver: Solver,
    dislocation: &Dislocation,
) -> Result<Errors, AnyError> {
    let medium = &dislocation.medium;
    let f = model
        .internal_fault
        .as_ref()
        .ok_or("the model has no internal fault")?;
    let tol = 1e-9 * far;
    let mut v = vec![0.0; model.num_dofs()];
    for (&d, &factor) in model.dirichlet.dofs.iter().zip(&model.dirichlet.factors) {
        v[d] = factor;
    }
    // The far faces at Okada's displacement (Cartesian unknowns: no frame there).
    for (q, x) in model.vertices.iter().enumerate() {
        let on_far_face = x[0].abs() > far - tol || x[1].abs() > far - tol || x[2] < -far + tol;
        if at_okada && on_far_face {
            assert!(f.pair_of(q).is_none());
            let u = dislocation.at(*x)?.u;
            for c in 0..3 {
                assert!(model.fixed[3 * q + c]);
                v[3 * q + c] = u[c];
            }
        }
    }
    // The probe pair's jump: the slip in its frame (the normal component is tied already).
    let mut fixed = model.fixed.clone();
    let mut probes = 0;
    for (k, &(mi, _)) in f.pairs().iter().enumerate() {
        let x = model.vertices[mi];
        if (0..3).all(|c| (x[c] - probe[c]).abs() < 1e-9 * h) {
            let r = f.transform.frames[k];
            let slip = (dislocation.slip_at)(x);
            let j: [f64; 3] = std::array::from_fn(|a| (0..3).map(|b| r[b][a] * slip[b]).sum());
            assert!(fixed[3 * mi + 2] && j[2].abs() < 1e-12);
            assert!(!fixed[3 * mi] && !fixed[3 * mi + 1]);
            for c in 0..2 {
                fixed[3 * mi + c] = true;
                v[3 * mi + c] = j[c];
            }
            probes += 1;
        }
    }
    assert_eq!(probes, 1);
    let zero = vec![0.0; v.len()];
    match solver {
        Solver::Direct => {
            DirectSolver::<3>::new(model.stiffness.as_ref(), &fixed, DirectOptions::default())?
                .solve(&zero, &NoNonlinearity, &mut v)?;
        }
        Solver::Multigrid => {
            multigrid(model, &fixed)?.solve(&zero, &NoNonlinearity, &mut v)?;
        }
    }
    let u = model.to_cartesian(&v)?;

    // The jump u⁺ − u⁻ of every pair is the prescribed slip (plus side y < 0).
    let mut jump = 0.0f64;
    for &(mi, pl) in f.pairs() {
        let slip = (dislocation.slip_at)(model.vertices[mi]);
        for c in 0..3 {
            jump = jump.max((u[3 * pl + c] - u[3 * mi + c] - slip[c]).abs());
        }
    }

    // Surface displacement: every surface vertex with |x|, |y| ≤ L (L the fault's
    // length) and at least L/4 from the ends of a surface trace; a vertex on the trace
    // (a split pair) compared with Okada's limit from its own side.
    let length = 2.0 * fault.half_length;
    let window = length;
    let (mut err, mut scale) = (0.0f64, 0.0f64);
    for (q, x) in model.vertices.iter().enumerate() {
        if x[2] < -tol || x[0].abs() > window || x[1].abs() > window {
            continue;
        }
        let near_end = [-1.0, 1.0]
            .iter()
            .any(|s| (x[0] - s * fault.half_length).hypot(x[1]) < length / 4.0);
        if fault.top == 0.0 && near_end {
            continue;
        }
        let mut point = *x;
        if let Some((_, pl)) = f.pair_of(q) {
            point[1] = if q == pl {
                -1e-5 * length
            } else {
                1e-5 * length
            };
        }
        let uo = dislocation.at(point)?.u;
        let e = (0..3).fold(0.0f64, |m, c| m.hypot(u[3 * q + c] - uo[c]));
        err = err.max(e);
        scale = scale.max(uo.iter().fold(0.0f64, |m, c| m.hypot(*c)));
    }
    let surface = err / scale;

    // On-fault traction: f' = K' v' at the jump dofs, f⁺ = R f'_j, f⁺/h² against σ e_y.
    let mut force = vec![0.0; v.len()];
    rsf::fem::spmv_add(model.stiffness.as_ref(), 1.0, &v, &mut force);
    let width = fault.bottom - fault.top;
    let weights = fault_weights(model, f);
    let (mut terr, mut tscale) = (0.0f64, 0.0f64);
    let mut inner = 0;
    for (k, &(mi, _)) in f.pairs().iter().enumerate() {
        let x = model.vertices[mi];
        let from_rim_x = fault.half_length - x[0].abs();
        let from_bottom = fault.bottom + x[2];
        let from_top = -x[2] - fault.top;
        if from_rim_x.min(from_bottom).min(from_top) < width / 4.0 - 1e-9 * width {
            continue;
        }
        inner += 1;
        let r = f.transform.frames[k];
        let w = weights[mi];
        let fj = [force[3 * mi], force[3 * mi + 1], force[3 * mi + 2]];
        let t_fe: [f64; 3] =
            std::array::from_fn(|i| (0..3).map(|a| r[i][a] * fj[a]).sum::<f64>() / w);
        let grad = dislocation.at(x)?.grad;
        let sigma = medium.stress(&grad);
        let t_ok = rsf_halfspace::traction(&sigma, &[0.0, 1.0, 0.0]);
        let e = (0..3).fold(0.0f64, |m, c| m.hypot(t_fe[c] - t_ok[c]));
        terr = terr.max(e);
        tscale = tscale.max(t_ok.iter().fold(0.0f64, |m, c| m.hypot(*c)));
    }
    assert!(inner > 0);
    Ok(Errors {
        h,
        vertices: model.num_nodes(),
        surface,
        traction: terr / tscale,
        jump,
    })
}
