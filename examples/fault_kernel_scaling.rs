//! Memory and cost of the fault ODE's operator against the number of fault unknowns
//! (issue 37, docs/scaling.md "Compressed fault operator"): SEAS BP1 condensed onto the
//! fault (`rsf::fault_ode::FaultOde`) at several element sizes, with the dense and the
//! hierarchical kernel. For each it prints the kernel report (stored f64, compression
//! ratio, measured `‖S − S_H‖_F/‖S‖_F`) and the CPU time per right-hand-side evaluation
//! (one product with the operator and one friction solve per node) over the first
//! `--steps` steps from t = 0 (CPU and wall time, at each `--threads` count), then
//! least-squares exponents of storage and cost (one thread) against m.
//!
//! ```sh
//! cargo run --release --example fault_kernel_scaling -- --dz 200,100,50,25,12.5 --domain-km 100
//! ```

use clap::Parser;
use rsf::fault_ode::{FaultKernel, FaultOdeOptions};
use rsf::Until;
use rsf_programs::cli::for_flag;
use rsf_programs::guard::{in_range, AnyError, Limits, Plan, Prepared, Program};
use rsf_programs::{cpu_seconds, fit_exponents};
use rsf_scenes::{SeasBp1, SeasBp1Grid};
use std::process::ExitCode;

/// Storage and cost of the dense and hierarchical fault operators of BP1.
#[derive(Parser)]
#[command(version)]
struct Cli {
    /// Element sizes on the fault (m), comma separated.
    #[arg(long, value_delimiter = ',', default_value = "200,100,50,25,12.5")]
    dz: Vec<f64>,
    /// Side of the square domain (km).
    #[arg(long, default_value_t = 100.0)]
    domain_km: f64,
    /// Accuracy ε of the hierarchical kernel.
    #[arg(long, default_value_t = 1e-6)]
    epsilon: f64,
    /// Steps timed from t = 0 (creep: the same steps for both kernels up to round-off).
    #[arg(long, default_value_t = 400)]
    steps: usize,
    /// Thread counts of the evaluations (comma separated; `FaultOdeOptions::parallelism`,
    /// the run on a pool of that many threads): each size and kernel is timed at each.
    #[arg(long, value_delimiter = ',', default_value = "1")]
    threads: Vec<usize>,
    /// Run from the main thread, outside the pool (rayon's global pool; each parallel
    /// region then hands over to the pool and back).
    #[arg(long)]
    outside_pool: bool,
    /// Skip the dense kernel above this many unknowns (its m² storage).
    #[arg(long, default_value_t = 10_000)]
    dense_max: usize,
    #[command(flatten)]
    limits: Limits,
}

impl Program for Cli {
    rsf_programs::name_and_limits!("fault_kernel_scaling");

    fn plan(&self) -> Result<Plan, AnyError> {
        rsf_programs::guard::distinct("--dz", &self.dz)?;
        let bp1 = SeasBp1::default();
        in_range(
            "--epsilon",
            self.epsilon,
            (f64::EPSILON, 0.5),
            "a relative accuracy",
        )?;
        in_range(
            "--steps",
            self.steps as f64,
            (1.0, 1e6),
            "steps timed from t = 0",
        )?;
        let mut plan = Plan::new();
        for &n in &self.threads {
            plan = plan.threads("--threads", n);
        }
        // One model and kernel at a time: the largest (BP1's estimate: the nodes and two
        // dense fault operators, an upper bound of the hierarchical kernel's).
        let mut worst = 0.0f64;
        for &dz in &self.dz {
            let grid = SeasBp1Grid {
                dz,
                domain: self.domain_km * 1e3,
                ..SeasBp1Grid::default()
            };
            let size = for_flag(
                "--domain-km",
                "domain",
                for_flag("--dz", "dz", bp1.estimate(&grid)),
            )?;
            if size.bytes > worst {
                worst = size.bytes;
                plan = plan.memory(
                    size.bytes,
                    "--dz, --domain-km",
                    format!(
                        "BP1 on dz = {dz:e} m: about {:.3e} nodes ({:.3e} on the fault)",
                        size.nodes, size.fault_nodes
                    ),
                );
            }
        }
        Ok(plan)
    }
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, _: Prepared) -> Result<(), AnyError> {
    let bp1 = SeasBp1::default();
    println!(
        "| Δz (m) | m | kernel | stored f64 | MB | compression | ‖S − S_H‖_F/‖S‖_F | compress (s) | threads | evaluations | CPU per evaluation (µs) | wall per evaluation (µs) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut rows: Vec<(&str, f64, f64, f64)> = Vec::new();
    for &dz in &cli.dz {
        let grid = SeasBp1Grid {
            dz,
            domain: cli.domain_km * 1e3,
            ..SeasBp1Grid::default()
        };
        for (kernel, &threads) in [FaultKernel::Dense, FaultKernel::hierarchical(cli.epsilon)]
            .into_iter()
            .flat_map(|k| cli.threads.iter().map(move |t| (k, t)))
        {
            let model = bp1.model(&grid, false)?;
            if kernel == FaultKernel::Dense && model.condensed_unknowns() > cli.dense_max {
                continue;
            }
            let options = FaultOdeOptions {
                kernel,
                parallelism: rsf::Parallelism::rayon(threads),
                ..bp1.fault_ode_options(1e-6)?
            };
            let mut ode = bp1.fault_ode(model, options)?;
            let report = ode.kernel_report().clone();
            let (cpu, wall) = (cpu_seconds(), std::time::Instant::now());
            let before = ode.evaluations();
            // On a pool of `threads` threads, as the SEAS examples run (docs/scaling.md,
            // "From inside the pool"); `--outside-pool` times the calls from this thread.
            if cli.outside_pool || threads == 1 {
                ode.run_until(Until::Steps(cli.steps), &mut [])
            } else {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()?
                    .install(|| ode.run_until(Until::Steps(cli.steps), &mut []))
            }
            .map_err(|e| e.error)?;
            let evaluations = (ode.evaluations() - before).max(1) as f64;
            let per_eval = (cpu_seconds() - cpu) / evaluations;
            let wall_per_eval = wall.elapsed().as_secs_f64() / evaluations;
            println!(
                "| {dz} | {} | {} | {} | {:.2} | {:.1} | {:.2e} | {:.2} | {threads} | {} | {:.1} | {:.1} |",
                report.dim,
                kernel.name(),
                report.stored_entries,
                report.bytes() as f64 / 1e6,
                report.compression_ratio(),
                report.relative_error,
                report.setup_seconds,
                ode.evaluations() - before,
                per_eval * 1e6,
                wall_per_eval * 1e6
            );
            if threads != 1 {
                continue;
            }
            rows.push((
                kernel.name(),
                report.dim as f64,
                report.stored_entries as f64,
                per_eval,
            ));
        }
    }
    for name in ["dense", "hierarchical"] {
        let sizes: Vec<(f64, [f64; 2])> = rows
            .iter()
            .filter(|r| r.0 == name)
            .map(|r| (r.1, [r.2, r.3]))
            .collect();
        if sizes.len() >= 2 {
            let [stored, cost] = fit_exponents(&sizes);
            println!(
                "{name}: stored f64 ~ m^{stored:.3}, CPU per evaluation ~ m^{cost:.3} (least squares on log–log, {} sizes)",
                sizes.len()
            );
        }
    }
    Ok(())
}
