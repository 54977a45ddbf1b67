//! The stiffness of BP7's square fault at the nucleation scale, finite elements against
//! boundary elements (docs/seas-bp7.md, "Why the finite elements' cycle is longer"): for a
//! parabolic slip bump `δ(r) = (1 − r²/R²)₊` along `x₂` centred on the square of BP7
//! (`l_f = 400 m`, whole space, μ = 32.04 GPa, ν = 0.25), the elastic operator's
//! stiffness in two measures:
//!
//! - the energy stiffness `k = δᵀ S δ / Σ_k w_k δ_k²` (Pa/m): twice the strain energy over
//!   the slip's square norm, the measure of a nucleation patch's spring (Rice & Ruina's
//!   `k` against `σ̄(b − a)/L`);
//! - the stress drop at the centre per unit peak slip, `−(S δ)_0 / w_0` (Pa/m), read at the
//!   node at the centre (finite elements) or interpolated from the four cells around it
//!   (boundary elements).
//!
//! The finite elements: the square alone in the box `±3.2 km` clamped on its faces, graded
//! by 1.2 (`rsf_scenes::SquareVolumeGrid::builder`), condensed onto the square's pairs by
//! the Schur-only elimination — the operator `seas_bp7 --kernel fe` steps with, but for
//! the creeping plane outside the square, which a bump inside it does not see (its slip
//! vanishes there). The boundary elements: the square's cells with the whole space's
//! operator (`seas_bp7`'s default kernel). Both operators are applied to the bump sampled
//! at their nodes or cell centres.
//!
//! `--scene bp5` measures BP5's fault the same way (docs/seas-bp5.md, "The 1 km
//! difference"): the finite elements of `seas_bp5 --kernel fe` (the graded box of 400 km,
//! ratio 1.3, condensed by the Schur-only elimination with nested dissection) against
//! Okada's operator of `seas_bp5` (ℋ-matrix of accuracy 1e-8), for the bump over the
//! weakening core — the ellipse of semi-axes 30 km along strike and 6 km down dip centred
//! at `(x₂, x₃) = (0, 10)` km, the scale of BP5's ruptures — and round bumps of the radii
//! centred on the nucleation patch, `(−24, 10)` km; `R` is the bump's semi-axis down dip.
//!
//! ```sh
//! cargo run --release --example nucleation_stiffness              # R = 50, 100, 200 m
//! cargo run --release --example nucleation_stiffness -- --radii 50,100,200,400 \
//!     --fe-dx 40,20 --bem-dx 40,20,10,5 --ratios 1.2,1.1
//! cargo run --release --example nucleation_stiffness -- --scene bp5   # Δx 2, 1 km (FE), 2, 1, 0.5 km (Okada)
//! ```
//!
//! Each line prints the kernel (with the grading ratio), `Δx`, `R`, `Δx/R`, `k`, `kR/μ`,
//! the centre's stress drop (BP7 only) and the operator's set-up time (s).

use std::time::Instant;

use clap::Parser;
use rsf::fault_ode::{InteriorOrdering, SchurOnlySetup};
use rsf::fault_operator::FaultOperator;
use rsf::Parallelism;
use rsf_programs::guard::{in_range, number, AnyError, Limits, Plan, Prepared, Program};
use rsf_scenes::{Bp7Law, SeasBp5, SeasBp5Grid, SeasBp7, SquareVolumeGrid, VolumeElimination};

/// The box of the finite elements (m, its half-width): the bump's support is within
/// 400 m of the centre, the box's clamped faces 3.2 km away.
const DOMAIN: f64 = 3200.0;

/// The fault whose stiffness is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Scene {
    /// BP7's square (whole space, 800 m).
    Bp7,
    /// BP5's rate-and-state region (half-space, 100 × 40 km).
    Bp5,
}

/// Both kernels' stiffness of a SEAS fault at the nucleation scale.
#[derive(Parser)]
#[command(version)]
struct Cli {
    /// The fault: `bp7` (the square of BP7, whole space) or `bp5` (BP5's fault in its
    /// half-space, the weakening core's bump beside the round ones).
    #[arg(long, value_enum, default_value_t = Scene::Bp7)]
    scene: Scene,
    /// The bumps' radii R (m, comma-separated): BP7's in [10, 400], default 50,100,200;
    /// BP5's in [500, 6000] (round bumps on the nucleation patch), default 3000,6000.
    #[arg(long, value_delimiter = ',')]
    radii: Option<Vec<f64>>,
    /// The finite elements' cell sizes on the fault (m, comma-separated): BP7's divide
    /// 800 m into 2 to 160 cells, default 40,20; BP5's are `seas_bp5 --kernel fe --dx`'s
    /// (500 m needs `--max-memory-gb 18`), default 2000,1000.
    #[arg(long, value_delimiter = ',')]
    fe_dx: Option<Vec<f64>>,
    /// The boundary elements' cell sizes (m, comma-separated): BP7's divide 800 m into 2 to
    /// 160 cells, default 40,20,10,5; BP5's are `seas_bp5 --dx`'s, default 2000,1000,500.
    #[arg(long, value_delimiter = ',')]
    bem_dx: Option<Vec<f64>>,
    /// The finite elements' grading ratios (comma-separated, each in [1.01, 2]): cells
    /// `Δx + (ratio − 1) d` at distance `d` from the fault (BP7: default 1.2; BP5: default
    /// 1.3, `seas_bp5 --ratio`'s).
    #[arg(long, value_delimiter = ',')]
    ratios: Option<Vec<f64>>,
    #[command(flatten)]
    limits: Limits,
}

impl Cli {
    /// A list flag's values, or the scene's default.
    fn list(given: &Option<Vec<f64>>, bp7: &[f64], bp5: &[f64], scene: Scene) -> Vec<f64> {
        given.clone().unwrap_or_else(|| {
            match scene {
                Scene::Bp7 => bp7,
                Scene::Bp5 => bp5,
            }
            .to_vec()
        })
    }
    fn radii(&self) -> Vec<f64> {
        Self::list(&self.radii, &[50.0, 100.0, 200.0], &[3e3, 6e3], self.scene)
    }
    fn fe_dx(&self) -> Vec<f64> {
        Self::list(&self.fe_dx, &[40.0, 20.0], &[2e3, 1e3], self.scene)
    }
    fn bem_dx(&self) -> Vec<f64> {
        Self::list(
            &self.bem_dx,
            &[40.0, 20.0, 10.0, 5.0],
            &[2e3, 1e3, 500.0],
            self.scene,
        )
    }
    fn ratios(&self) -> Vec<f64> {
        Self::list(&self.ratios, &[1.2], &[1.3], self.scene)
    }

    /// `grid(dx, ratio)` of every cell size with every ratio (the ratios inner).
    fn each_dx_and_ratio<G>(&self, grid: impl Fn(f64, f64) -> G) -> Vec<G> {
        let (ratios, grid) = (self.ratios(), &grid);
        self.fe_dx()
            .into_iter()
            .flat_map(|dx| ratios.iter().map(move |&ratio| grid(dx, ratio)))
            .collect()
    }

    /// BP7's finite-element grids, every cell size with every ratio.
    fn grids(&self) -> Vec<SquareVolumeGrid> {
        self.each_dx_and_ratio(|dx, ratio| SquareVolumeGrid {
            dx,
            domain: DOMAIN,
            ratio,
        })
    }

    /// BP5's finite-element grids (`seas_bp5 --kernel fe`'s box), every cell size with
    /// every ratio.
    fn bp5_grids(&self) -> Vec<SeasBp5Grid> {
        self.each_dx_and_ratio(|dx, ratio| SeasBp5Grid {
            dx,
            ratio,
            ..SeasBp5Grid::default()
        })
    }

    /// BP5's plan: the cell sizes checked, the largest operator's memory.
    fn plan_bp5(&self) -> Result<Plan, AnyError> {
        let bp5 = SeasBp5::default();
        for r in self.radii() {
            in_range("--radii", r, (500.0, 6000.0), "m")?;
        }
        let max = self.limits.max_memory_gb * 1e9;
        let mut bytes: f64 = 1e8;
        for dx in self.bem_dx() {
            let cells = bp5
                .cells(dx)
                .map_err(|e| format!("--bem-dx {}: {e}", number(dx)))?;
            let m = 2.0 * cells.len() as f64;
            bytes = bytes.max(3.0 * rsf_programs::estimates::operator_bytes(m, true));
        }
        for grid in self.bp5_grids() {
            let vertices = bp5
                .fe_mesh_vertices(&grid)
                .map_err(|e| format!("--fe-dx {}: {e}", number(grid.dx)))?;
            // The Schur-only elimination's peak with nested dissection, the fault's
            // nodes kept (seas_bp5's own estimate), and the dense operator of its pairs.
            let nodes = (bp5.l_f / grid.dx + 1.0) * (bp5.w_f / grid.dx + 1.0);
            let peak =
                rsf_programs::seas_bp5::graded_schur_only_nd_peak(vertices as f64, 2.0 * nodes);
            bytes = bytes.max(peak + rsf_programs::estimates::operator_bytes(2.0 * nodes, false));
            if bytes > max {
                break;
            }
        }
        Ok(Plan::new().memory(bytes, "--fe-dx, --bem-dx", "the largest operator"))
    }
}

impl Program for Cli {
    rsf_programs::name_and_limits!("nucleation_stiffness");

    fn plan(&self) -> Result<Plan, AnyError> {
        for ratio in self.ratios() {
            in_range("--ratios", ratio, (1.01, 2.0), "the grading ratio")?;
        }
        if self.scene == Scene::Bp5 {
            return self.plan_bp5();
        }
        let bp7 = SeasBp7::default();
        for r in self.radii() {
            in_range("--radii", r, (10.0, bp7.l_f), "m")?;
        }
        for (flag, cells) in [("--bem-dx", self.bem_dx()), ("--fe-dx", self.fe_dx())] {
            for dx in cells {
                bp7.cells(dx)
                    .map_err(|e| format!("{flag} {}: {e}", number(dx)))?;
            }
        }
        // The runs one after another: the largest finite-element volume bounds the peak.
        let mut bytes: f64 = 1e8;
        for grid in self.grids() {
            let pairs = (2.0 * bp7.l_f / grid.dx - 1.0).powi(2);
            let max = self.limits.max_memory_gb * 1e9;
            bytes = bytes.max(rsf_programs::volume_memory(
                &grid,
                (bp7.l_f, &[]),
                pairs,
                max,
            )?);
        }
        Ok(Plan::new().memory(
            bytes,
            "--fe-dx, --ratios",
            "the largest finite-element volume",
        ))
    }
}

/// `(k, centre stress drop)` (Pa/m) of the operator `op` for the slip bump `bump` (its
/// value at `(x₂, x₃)`, m); `nodes` one entry per frictional node in the operator's order:
/// its position `(x₂, x₃)` (m), weight `w` (m²) and the components of a unit slip along
/// `x₂` in its two slip unknowns; `centre` the nodes and weights that read the centre (none:
/// the drop is not read, NaN).
fn stiffness(
    op: &mut dyn FaultOperator,
    nodes: &[Node],
    bump: &dyn Fn([f64; 2]) -> f64,
    centre: &[(usize, f64)],
) -> Result<(f64, f64), AnyError> {
    let x: Vec<f64> = nodes
        .iter()
        .flat_map(|&(p, _, along)| [bump(p) * along[0], bump(p) * along[1]])
        .collect();
    let mut sx = vec![0.0; x.len()];
    op.subtract_product(&x, &mut sx, Parallelism::SEQ)?;
    // sx = −S δ.
    let energy: f64 = -x.iter().zip(&sx).map(|(a, b)| a * b).sum::<f64>();
    let norm: f64 = nodes.iter().map(|&(p, w, _)| w * bump(p).powi(2)).sum();
    let drop_at = |k: usize| {
        let (_, w, along) = nodes[k];
        (sx[2 * k] * along[0] + sx[2 * k + 1] * along[1]) / w
    };
    let drop: f64 = if centre.is_empty() {
        f64::NAN
    } else {
        centre.iter().map(|&(k, c)| c * drop_at(k)).sum()
    };
    Ok((energy / norm, drop))
}

/// A frictional node as [`stiffness`] takes it: its position `(x₂, x₃)` (m), weight `w` (m²)
/// and the components of a unit slip along `x₂` in its two slip unknowns.
type Node = ([f64; 2], f64, [f64; 2]);

/// The cells of a fault alone (boundary elements) of `model`, in the operator's order: each
/// cell's position (`at` of its centre, m), area (m²) and its first slip unknown along `x₂`
/// (the elements' strike).
fn cell_nodes(model: &rsf::Model<3, 3>, at: impl Fn([f64; 3]) -> [f64; 2]) -> Vec<Node> {
    let fb = &model.frictional_boundary;
    fb.nodes
        .iter()
        .zip(&fb.weights)
        .map(|(&p, &w)| (at(model.vertices[p]), w, [1.0, 0.0]))
        .collect()
}

/// The frictional pairs of a fault inside the body of `model`, in the operator's order: each
/// pair's position on the fault (`at` of its vertex, m), weight (m²) and a unit Cartesian
/// slip along `x₂` in the pair's frame (`Qᵀ e₂`).
fn pair_nodes(
    model: &rsf::Model<3, 3>,
    at: impl Fn([f64; 3]) -> [f64; 2],
) -> Result<Vec<Node>, AnyError> {
    let fault = model
        .internal_fault
        .as_ref()
        .ok_or("no fault inside the body")?;
    let fb = &model.frictional_boundary;
    let mut nodes = Vec::with_capacity(fb.len());
    for (&p, &w) in fb.nodes.iter().zip(&fb.weights) {
        let i = fault
            .pair_index(p)
            .ok_or("a frictional node that is not a pair")?;
        let q = fault.transform.frames[i];
        nodes.push((at(model.vertices[p]), w, [q[1][0], q[1][1]]));
    }
    Ok(nodes)
}

/// The parabolic bump `(1 − (Δx₂/a)² − (Δx₃/b)²)₊` centred at `c` with semi-axes `(a, b)`.
fn bump(c: [f64; 2], (a, b): (f64, f64)) -> impl Fn([f64; 2]) -> f64 {
    move |p: [f64; 2]| {
        let (u, v) = ((p[0] - c[0]) / a, (p[1] - c[1]) / b);
        (1.0 - u * u - v * v).max(0.0)
    }
}

/// One line per bump of the operator `op` (`kernel`, cell size `dx`, set-up seconds):
/// `bumps` the bumps' names and sizes `R` (m), `run` the stiffness of the `k`-th.
fn report(
    (kernel, dx, setup): (&str, f64, f64),
    bumps: &[(String, f64)],
    mu: f64,
    mut run: impl FnMut(usize) -> Result<(f64, f64), AnyError>,
) -> Result<(), AnyError> {
    for (i, (name, r)) in bumps.iter().enumerate() {
        let (k, drop) = run(i)?;
        println!(
            "{kernel:>9} dx {dx:>5} m  {name:>10} R {r:>5} m  dx/R {:.4}  k {k:.5e} Pa/m  kR/mu {:.6}  centre drop {drop:.5e} Pa/m  set-up {setup:.1} s",
            dx / r,
            k * r / mu
        );
    }
    Ok(())
}

fn main() -> std::process::ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, _: Prepared) -> Result<(), AnyError> {
    match cli.scene {
        Scene::Bp7 => run_bp7(&cli),
        Scene::Bp5 => run_bp5(&cli),
    }
}

/// BP7's square: round bumps of the radii at its centre.
fn run_bp7(cli: &Cli) -> Result<(), AnyError> {
    let bp7 = SeasBp7::default();
    let radii = cli.radii();
    let bumps: Vec<(String, f64)> = radii.iter().map(|&r| ("round".into(), r)).collect();
    let shape = |i: usize| bump([0.0, 0.0], (radii[i], radii[i]));
    let mu = bp7.shear_modulus();
    println!(
        "BP7's square (l_f {} m), parabolic slip bumps; mu {mu:.4e} Pa",
        bp7.l_f
    );
    for dx in cli.bem_dx() {
        let clock = Instant::now();
        let (mut ode, _) = bp7.fault_ode(dx, Bp7Law::Aging, bp7.fault_ode_options(1e-7)?)?;
        let setup = clock.elapsed().as_secs_f64();
        let nodes = cell_nodes(ode.model(), |x| [x[1], x[2]]);
        // The four cells around the centre, a quarter each.
        let near = |c: f64| (c.abs() - 0.5 * dx).abs() < 1e-6 * dx;
        let centre: Vec<(usize, f64)> = nodes
            .iter()
            .enumerate()
            .filter(|(_, (p, ..))| near(p[0]) && near(p[1]))
            .map(|(k, _)| (k, 0.25))
            .collect();
        if centre.len() != 4 {
            return Err(format!(
                "Δx = {dx} m: {} cells around the centre, not 4",
                centre.len()
            )
            .into());
        }
        let op = ode.fault_operator_mut();
        report(("bem", dx, setup), &bumps, mu, |i| {
            stiffness(op, &nodes, &shape(i), &centre)
        })?;
    }
    for grid in cli.grids() {
        let clock = Instant::now();
        let model = grid.builder(bp7.l_f, bp7.material())?.build()?;
        println!(
            "finite elements, dx {} m, ratio {}: {} vertices",
            grid.dx,
            grid.ratio,
            model.vertices.len()
        );
        let mut options = bp7.fault_ode_options(1e-7)?;
        let pairs = model.frictional_boundary.len();
        let setup = VolumeElimination::default().options(&mut options, pairs, Vec::new());
        let mut ode = bp7
            .problem_builder(model, Bp7Law::Aging)?
            .build_fault_ode_schur_only(options, setup)?;
        let setup = clock.elapsed().as_secs_f64();
        let nodes = pair_nodes(ode.model(), |x| [x[1], x[2]])?;
        let centre: Vec<(usize, f64)> = nodes
            .iter()
            .enumerate()
            .filter(|(_, (p, ..))| p[0].abs() < 1e-6 * grid.dx && p[1].abs() < 1e-6 * grid.dx)
            .map(|(k, _)| (k, 1.0))
            .collect();
        if centre.len() != 1 {
            return Err(format!(
                "Δx = {} m: {} nodes at the centre, not 1",
                grid.dx,
                centre.len()
            )
            .into());
        }
        let op = ode.fault_operator_mut();
        let kernel = format!("fe ({})", grid.ratio);
        report((&kernel, grid.dx, setup), &bumps, mu, |i| {
            stiffness(op, &nodes, &shape(i), &centre)
        })?;
    }
    Ok(())
}

/// BP5's fault: the weakening core's bump and round bumps of the radii on the nucleation
/// patch, Okada's operator against the finite elements'.
fn run_bp5(cli: &Cli) -> Result<(), AnyError> {
    let bp5 = SeasBp5::default();
    let mu = bp5.shear_modulus();
    println!("BP5's fault (half-space), parabolic slip bumps along strike; mu {mu:.4e} Pa");
    let mut bumps = vec![("core".to_string(), 6e3)];
    let mut shapes: Vec<Box<dyn Fn([f64; 2]) -> f64>> =
        vec![Box::new(bump([0.0, 10e3], (30e3, 6e3)))];
    for r in cli.radii() {
        bumps.push(("patch".into(), r));
        shapes.push(Box::new(bump([-24e3, 10e3], (r, r))));
    }
    let options = || -> Result<_, AnyError> { Ok(bp5.fault_ode_options(1e-6)?) };
    for dx in cli.bem_dx() {
        let clock = Instant::now();
        let mut ode = bp5.fault_ode(bp5.model(dx)?, options()?, &bp5.half_space(1e-8)?)?;
        let setup = clock.elapsed().as_secs_f64();
        // Cell centres at (0, x₂, −x₃).
        let nodes = cell_nodes(ode.model(), |x| [x[1], -x[2]]);
        let op = ode.fault_operator_mut();
        report(("okada", dx, setup), &bumps, mu, |i| {
            stiffness(op, &nodes, &shapes[i], &[])
        })?;
    }
    for grid in cli.bp5_grids() {
        let clock = Instant::now();
        let model = bp5.fe_model(&grid)?;
        println!(
            "finite elements, dx {} m, ratio {}: {} vertices",
            grid.dx,
            grid.ratio,
            model.vertices.len()
        );
        let mut options = options()?;
        options.ordering = InteriorOrdering::NestedDissection;
        let mut ode = bp5.fe_fault_ode_schur_only(model, options, SchurOnlySetup::default())?;
        let setup = clock.elapsed().as_secs_f64();
        // Depth x₃ = −z.
        let nodes = pair_nodes(ode.model(), |x| [x[1], -x[2]])?;
        let op = ode.fault_operator_mut();
        let kernel = format!("fe ({})", grid.ratio);
        report((&kernel, grid.dx, setup), &bumps, mu, |i| {
            stiffness(op, &nodes, &shapes[i], &[])
        })?;
    }
    Ok(())
}
