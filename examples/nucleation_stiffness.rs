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
//! ```sh
//! cargo run --release --example nucleation_stiffness              # R = 50, 100, 200 m
//! cargo run --release --example nucleation_stiffness -- --radii 50,100,200,400 \
//!     --fe-dx 40,20 --bem-dx 40,20,10,5 --ratios 1.2,1.1
//! ```
//!
//! Each line prints the kernel (with the grading ratio), `Δx`, `R`, `Δx/R`, `k`, `kR/μ`,
//! the centre's stress drop and the operator's set-up time (s).

use std::time::Instant;

use clap::Parser;
use rsf::fault_operator::FaultOperator;
use rsf::Parallelism;
use rsf_programs::guard::{in_range, number, AnyError, Limits, Plan, Prepared, Program};
use rsf_scenes::{Bp7Law, SeasBp7, SquareVolumeGrid, VolumeElimination};

/// The box of the finite elements (m, its half-width): the bump's support is within
/// 400 m of the centre, the box's clamped faces 3.2 km away.
const DOMAIN: f64 = 3200.0;

/// Both kernels' stiffness of BP7's square at the nucleation scale.
#[derive(Parser)]
#[command(version)]
struct Cli {
    /// The bumps' radii R (m, comma-separated), each in [10, 400].
    #[arg(long, value_delimiter = ',', default_values_t = [50.0, 100.0, 200.0])]
    radii: Vec<f64>,
    /// The finite elements' cell sizes on the square (m, comma-separated; each divides
    /// 800 m into 2 to 160 cells).
    #[arg(long, value_delimiter = ',', default_values_t = [40.0, 20.0])]
    fe_dx: Vec<f64>,
    /// The boundary elements' cell sizes (m, comma-separated; each divides 800 m into 2 to
    /// 160 cells).
    #[arg(long, value_delimiter = ',', default_values_t = [40.0, 20.0, 10.0, 5.0])]
    bem_dx: Vec<f64>,
    /// The finite elements' grading ratios (comma-separated, each in [1.01, 2]): cells
    /// `Δx + (ratio − 1) d` at distance `d` from the square.
    #[arg(long, value_delimiter = ',', default_values_t = [1.2])]
    ratios: Vec<f64>,
    #[command(flatten)]
    limits: Limits,
}

impl Cli {
    /// The finite elements' grids, every cell size with every ratio.
    fn grids(&self) -> Vec<SquareVolumeGrid> {
        self.fe_dx
            .iter()
            .flat_map(|&dx| {
                self.ratios.iter().map(move |&ratio| SquareVolumeGrid {
                    dx,
                    domain: DOMAIN,
                    ratio,
                })
            })
            .collect()
    }
}

impl Program for Cli {
    const NAME: &'static str = "nucleation_stiffness";

    fn limits(&self) -> Limits {
        self.limits
    }

    fn plan(&self) -> Result<Plan, AnyError> {
        let bp7 = SeasBp7::default();
        for &r in &self.radii {
            in_range("--radii", r, (10.0, bp7.l_f), "m")?;
        }
        for &ratio in &self.ratios {
            in_range("--ratios", ratio, (1.01, 2.0), "the grading ratio")?;
        }
        for (flag, cells) in [("--bem-dx", &self.bem_dx), ("--fe-dx", &self.fe_dx)] {
            for &dx in cells {
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

/// `(k, centre stress drop)` (Pa/m) of the operator `op` for the bump of radius `r` (m);
/// `nodes` one entry per frictional node in the operator's order: its position
/// `(x₂, x₃)` (m), weight `w` (m²) and the components of a unit slip along `x₂` in its two
/// slip unknowns; `centre` the nodes and weights that read the centre.
fn stiffness(
    op: &mut dyn FaultOperator,
    nodes: &[([f64; 2], f64, [f64; 2])],
    r: f64,
    centre: &[(usize, f64)],
) -> Result<(f64, f64), AnyError> {
    let bump = |p: [f64; 2]| (1.0 - (p[0] * p[0] + p[1] * p[1]) / (r * r)).max(0.0);
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
    let drop: f64 = centre.iter().map(|&(k, c)| c * drop_at(k)).sum();
    Ok((energy / norm, drop))
}

/// One line per radius of the operator `op` (`kernel`, cell size `dx`, set-up seconds).
fn report(
    (kernel, dx, setup): (&str, f64, f64),
    radii: &[f64],
    mu: f64,
    mut run: impl FnMut(f64) -> Result<(f64, f64), AnyError>,
) -> Result<(), AnyError> {
    for &r in radii {
        let (k, drop) = run(r)?;
        println!(
            "{kernel:>9} dx {dx:>5} m  R {r:>5} m  dx/R {:.4}  k {k:.5e} Pa/m  kR/mu {:.6}  centre drop {drop:.5e} Pa/m  set-up {setup:.1} s",
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
    let bp7 = SeasBp7::default();
    let mu = bp7.shear_modulus();
    println!(
        "BP7's square (l_f {} m), parabolic slip bumps; mu {mu:.4e} Pa",
        bp7.l_f
    );
    for &dx in &cli.bem_dx {
        let clock = Instant::now();
        let (mut ode, _) = bp7.fault_ode(dx, Bp7Law::Aging, bp7.fault_ode_options(1e-7)?)?;
        let setup = clock.elapsed().as_secs_f64();
        let model = ode.model();
        let fb = &model.frictional_boundary;
        let nodes: Vec<([f64; 2], f64, [f64; 2])> = fb
            .nodes
            .iter()
            .zip(&fb.weights)
            .map(|(&p, &w)| {
                let x = model.vertices[p];
                ([x[1], x[2]], w, [1.0, 0.0])
            })
            .collect();
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
        report(("bem", dx, setup), &cli.radii, mu, |r| {
            stiffness(op, &nodes, r, &centre)
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
        let model = ode.model();
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
            let x = model.vertices[p];
            // A unit Cartesian slip along x₂ in the pair's frame: Qᵀ e₂.
            nodes.push(([x[1], x[2]], w, [q[1][0], q[1][1]]));
        }
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
        report((&kernel, grid.dx, setup), &cli.radii, mu, |r| {
            stiffness(op, &nodes, r, &centre)
        })?;
    }
    Ok(())
}
