//! Set-up of a 3-D fault's operator at scale (issue 55, docs/three-d.md "The fault operator
//! at scale"): a vertical strike-slip fault in a half-space as SEAS BP5 has it — the plane
//! `x = 0`, `|y| ≤ --length-km/2`, from the free surface `z = 0` down to `--depth-km` — in
//! a box graded geometrically from the fault's cell size `--dx` to `--domain-km` on every
//! side (far faces held), condensed onto the fault and its operator `S` built as an
//! ℋ-matrix from the factor's entries (no dense `m × m` copy). Per cell size it prints the
//! volume, the factor, the operator's report (stored f64, ranks, error estimate), the
//! set-up time and the peak memory of the process (after the model's assembly and after the
//! whole set-up), and the CPU time per right-hand-side
//! evaluation of the fault ODE; then least-squares exponents against m.
//!
//! ```sh
//! cargo run --release --example fault_setup_3d -- --dx 10,5,2
//! cargo run --release --features metis --example fault_setup_3d -- --dx 10,5,2 --ordering nested-dissection
//! ```

use std::time::Instant;

use clap::Parser;
use rsf::fault_ode::{FaultKernel, FaultOdeOptions, InteriorOrdering};
use rsf::fem::{cuboid_from_coordinates, geometric_grading};
use rsf::friction::{AsinhLaw, RateStateParams};
use rsf::state::Aging;
use rsf::{Material, ModelBuilder, Part, SimulationBuilder, Until};
use rsf_programs::estimates::{fe_3d_box_vertices as box_vertices, fe_3d_memory};
use rsf_programs::guard::{in_range, number, refuse, AnyError, Limits, Plan, Prepared, Program};
use rsf_programs::{cpu_seconds, fit_exponents};
use std::process::ExitCode;

/// The fault operator of a BP5-like 3-D fault at several cell sizes.
#[derive(Parser)]
#[command(version)]
struct Cli {
    /// Cell sizes on the fault (km), comma separated; each must divide the half-length
    /// and the depth (the cells tile the fault).
    #[arg(long, value_delimiter = ',', default_value = "10,5")]
    dx: Vec<f64>,
    /// Length of the fault along strike (km).
    #[arg(long, default_value_t = 100.0)]
    length_km: f64,
    /// Depth of the fault (km).
    #[arg(long, default_value_t = 40.0)]
    depth_km: f64,
    /// Distance from the fault to the far faces (km).
    #[arg(long, default_value_t = 400.0)]
    domain_km: f64,
    /// Growth of the cells away from the fault.
    #[arg(long, default_value_t = 1.3)]
    ratio: f64,
    /// Accuracy ε of the ℋ-matrix.
    #[arg(long, default_value_t = 1e-6)]
    epsilon: f64,
    /// Threads of the fault ODE's evaluations (the set-up's compression is sequential).
    #[arg(long, default_value_t = 1)]
    threads: usize,
    /// Steps of the fault ODE timed after the set-up.
    #[arg(long, default_value_t = 20)]
    steps: usize,
    /// Ordering of the volume's interior in the condensation: `amd` or `nested-dissection`
    /// (METIS; needs `--features metis`).
    #[arg(long, default_value = "amd", value_parser = |s: &str| s.parse::<InteriorOrdering>())]
    ordering: InteriorOrdering,
    #[command(flatten)]
    limits: Limits,
}

impl Program for Cli {
    rsf_programs::name_and_limits!("fault_setup_3d");

    fn plan(&self) -> Result<Plan, AnyError> {
        rsf_programs::guard::distinct("--dx", &self.dx)?;
        let (length, depth, far) = (
            self.length_km * 1e3,
            self.depth_km * 1e3,
            self.domain_km * 1e3,
        );
        if !(length > 0.0 && depth > 0.0 && far > length && far > depth && far <= 1e7) {
            return Err(format!(
                "--length-km {}, --depth-km {}, --domain-km {}: positive, the first two \
                 below --domain-km, at most 1e4 km",
                number(self.length_km),
                number(self.depth_km),
                number(self.domain_km)
            )
            .into());
        }
        in_range("--ratio", self.ratio, (1.0, 2.0), "the growth of the cells")?;
        in_range(
            "--epsilon",
            self.epsilon,
            (f64::EPSILON, 0.5),
            "a relative accuracy",
        )?;
        in_range(
            "--steps",
            self.steps as f64,
            (0.0, 1e6),
            "steps timed after the set-up",
        )?;
        if self.ordering == InteriorOrdering::NestedDissection && !rsf_metis::is_available() {
            return Err(refuse(
                "--ordering",
                "nested-dissection",
                "needs METIS, which this build lacks: build with `--features metis`",
            ));
        }
        // The sizes run one after the other: the largest one's estimate bounds the run.
        let mut worst: Option<(f64, String)> = None;
        for &dx_km in &self.dx {
            let h = dx_km * 1e3;
            if !(h > 0.0 && h <= depth) {
                return Err(refuse(
                    "--dx",
                    number(dx_km),
                    "must be positive and at most --depth-km",
                ));
            }
            // The cells must tile the fault: its half-length and its depth whole multiples
            // of the cell size (else the mesh has no faces on the fault's edges).
            let whole = |x: f64| (x / h - (x / h).round()).abs() <= 1e-9 * (x / h);
            if !(whole(length / 2.0) && whole(depth)) {
                return Err(refuse(
                    "--dx",
                    number(dx_km),
                    &format!(
                        "must divide the half-length --length-km/2 = {} km and the depth \
                         --depth-km = {} km into whole cells (the cells tile the fault)",
                        number(self.length_km / 2.0),
                        number(self.depth_km)
                    ),
                ));
            }
            let vertices = box_vertices(h, length, depth, self.ratio, far);
            let bytes = fe_3d_memory(vertices);
            if worst.as_ref().is_none_or(|w| bytes > w.0) {
                let what = format!(
                    "the box at dx = {} km: {vertices:.3e} vertices",
                    number(dx_km)
                );
                worst = Some((bytes, what));
            }
        }
        let mut plan = Plan::new().threads("--threads", self.threads);
        if let Some((bytes, what)) = worst {
            plan = plan.memory(bytes, "--dx, --domain-km, --ratio", what);
        }
        Ok(plan)
    }
}

/// Coordinates `-far … -uniform … uniform … far` (m): spacing `h` over `[-uniform,
/// uniform]`, growing by `ratio` beyond.
fn symmetric(h: f64, uniform: f64, ratio: f64, far: f64) -> Result<Vec<f64>, AnyError> {
    let half = geometric_grading(h, uniform, ratio, far)?;
    let mut c: Vec<f64> = half.iter().rev().map(|x| -x).collect();
    c.extend_from_slice(&half[1..]);
    Ok(c)
}

/// Peak resident memory of the process (GB), from `/proc/self/status` (0 elsewhere).
fn peak_gb() -> f64 {
    // Linux counts kB: the peak over 1e6 kB.
    rsf_programs::memory::peak_bytes().map_or(0.0, |b| (b / 1024) as f64 / 1e6)
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, _: Prepared) -> Result<(), AnyError> {
    let (length, depth, far) = (cli.length_km * 1e3, cli.depth_km * 1e3, cli.domain_km * 1e3);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(cli.threads)
        .build()?;
    println!("ordering of the interior: {}", cli.ordering);
    println!(
        "| Δx (km) | vertices | dofs | m | factor nnz | stored f64 | MB | max rank | error (sampled) | factor rows MB | operator (s) | set-up (s) | peak GB (model) | peak GB | CPU per evaluation (ms) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    for &dx_km in &cli.dx {
        let h = dx_km * 1e3;
        if !(h > 0.0 && h <= depth) {
            return Err(format!("--dx {dx_km}: positive and at most --depth-km").into());
        }
        let clock = Instant::now();
        let xs = symmetric(h, h, cli.ratio, far)?;
        let ys = symmetric(h, length / 2.0, cli.ratio, far)?;
        let mut zs: Vec<f64> = geometric_grading(h, depth, cli.ratio, far)?
            .iter()
            .rev()
            .map(|z| -z)
            .collect();
        *zs.last_mut().expect("non-empty") = 0.0;
        let mesh = cuboid_from_coordinates(&xs, &ys, &zs)?;
        let vertices = mesh.num_vertices();
        let eps = 1e-6 * far;
        let (mu, c_s) = (32.04e9, 3464.0);
        // No loads and the far faces held at rest: u₀ = 0 without solving for it.
        let model = ModelBuilder::new(mesh)
            .material(Material::new(2.5 * mu, 0.25, 2670.0))
            .without_mass()
            .without_initial_equilibrium()
            .dirichlet(
                Part::predicate("far", move |x| {
                    x[0].abs() > far - eps || x[1].abs() > far - eps || x[2] < -far + eps
                }),
                [0.0; 3],
            )
            .fault_tangent([0.0, 1.0, 0.0])
            .internal_fault_polygon(
                "fault",
                &[
                    [0.0, -length / 2.0, -depth],
                    [0.0, length / 2.0, -depth],
                    [0.0, length / 2.0, 0.0],
                    [0.0, -length / 2.0, 0.0],
                ],
            )
            .build()?;
        let dofs = model.num_dofs();
        // The peak so far: the mesh and the finite-element assembly (before the condensation).
        let model_peak = peak_gb();
        let params = RateStateParams {
            mu0: 0.6,
            a: 0.004,
            b: 0.03,
            v0: 1e-6,
            l: 0.14,
            sigma_n: 25e6,
        };
        let options = FaultOdeOptions {
            kernel: FaultKernel::hierarchical(cli.epsilon),
            parallelism: rsf::Parallelism::rayon(cli.threads),
            tolerance: 1e-6,
            slip_scale: params.l,
            ordering: cli.ordering,
            ..FaultOdeOptions::default()
        };
        let mut ode = SimulationBuilder::new(model)
            .friction(AsinhLaw::new(params)?)
            .state_law(Aging::new(params.l)?)
            .initial_state((params.l / 1e-9f64).ln())
            .integrator(rsf::time::Quasistatic::new())
            .radiation_damping(mu / (2.0 * c_s))
            .time_step(1e-3)
            .build_fault_ode(options)?;
        let setup = clock.elapsed().as_secs_f64();
        let report = ode.kernel_report().clone();
        let peak = peak_gb();
        let (cpu, before) = (cpu_seconds(), ode.evaluations());
        pool.install(|| ode.run_until(Until::Steps(cli.steps), &mut []))
            .map_err(|e| e.error)?;
        let per_eval = (cpu_seconds() - cpu) / (ode.evaluations() - before).max(1) as f64;
        println!(
            "| {dx_km} | {vertices} | {dofs} | {} | {} | {} | {:.1} | {} | {:.1e} | {:.1} | {:.1} | {setup:.1} | {model_peak:.2} | {peak:.2} | {:.2} |",
            report.dim,
            ode.factor_nnz(),
            report.stored_entries,
            report.bytes() as f64 / 1e6,
            report.max_rank,
            report.relative_error,
            report.setup_bytes as f64 / 1e6,
            report.setup_seconds,
            per_eval * 1e3,
        );
        rows.push((report.dim as f64, [report.stored_entries as f64, per_eval]));
    }
    if rows.len() >= 2 {
        let [stored, cost] = fit_exponents(&rows);
        println!(
            "stored f64 ~ m^{stored:.3}, CPU per evaluation ~ m^{cost:.3} (least squares on log–log, {} sizes)",
            rows.len()
        );
    }
    Ok(())
}
