//! Set-up, memory and product cost of the boundary-element half-space operator against
//! the number of fault unknowns (issue 55, "a set-up that scales"; docs/seas-bp5.md,
//! "The operator at scale"): SEAS BP5's fault alone (`rsf_scenes::SeasBp5::model`, two
//! slip components per cell) with Okada's operator
//! (`rsf::halfspace_operator::HalfSpaceOperator::fault_alone`) always as an ℋ-matrix, at
//! several cell sizes. For each it prints the set-up's wall and CPU time, what it stored
//! (f64, MB, the table of distinct source–receiver pairs it was built from), the largest
//! rank, the sampled `‖K − K_H‖_F/‖K‖_F`, and the median wall time of one product on one
//! thread over `--products` products; then least-squares exponents against m. Run it
//! under `/usr/bin/time -v` for the peak memory (the largest size's).
//!
//! ```sh
//! cargo run --release --example halfspace_scaling -- --dx 4000,2000,1000,500
//! ```

use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use rsf::fault_operator::FaultOperator;
use rsf::halfspace_operator::{HalfSpaceOperator, HalfSpaceOptions};
use rsf_programs::estimates::operator_bytes;
use rsf_programs::guard::{flag, AnyError, Limits, Plan, Prepared, Program};
use rsf_programs::{cpu_seconds, fit_exponents, machine};

#[path = "common/operator_timing.rs"]
mod operator_timing;
use operator_timing::{block_columns, check_epsilon_and_products, median_product_seconds};
use rsf_scenes::SeasBp5;

/// Set-up and product cost of BP5's half-space operator against m.
#[derive(Parser)]
#[command(version)]
struct Cli {
    /// Cell sizes on the fault (m), comma separated; each must divide 100 km and 40 km.
    #[arg(long, value_delimiter = ',', default_value = "4000,2000,1000,500")]
    dx: Vec<f64>,
    /// Accuracy ε of the ℋ-matrix.
    #[arg(long, default_value_t = 1e-6)]
    epsilon: f64,
    /// Products timed per size (the median is printed).
    #[arg(long, default_value_t = 21)]
    products: usize,
    #[command(flatten)]
    limits: Limits,
}

impl Program for Cli {
    rsf_programs::name_and_limits!("halfspace_scaling");

    fn plan(&self) -> Result<Plan, AnyError> {
        rsf_programs::guard::distinct("--dx", &self.dx)?;
        check_epsilon_and_products(self.epsilon, self.products)?;
        let bp5 = SeasBp5::default();
        let mut largest = 0.0f64;
        for &dx in &self.dx {
            largest = largest.max(flag("--dx", bp5.cells(dx))?.len() as f64);
        }
        // One operator at a time: the largest (its ℋ-matrix, at most the dense size, and
        // the table of distinct pairs, at most `TABLE_MAX_PAIRS` of 48 bytes).
        let m = 2.0 * largest;
        Ok(Plan::new().memory(
            operator_bytes(m, true) + 48.0 * rsf::halfspace::TABLE_MAX_PAIRS as f64,
            "--dx",
            format!("BP5's half-space operator of {m} unknowns"),
        ))
    }
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, _: Prepared) -> Result<(), AnyError> {
    let bp5 = SeasBp5::default();
    println!("on {}", machine());
    println!(
        "| Δx (m) | m | set-up wall (s) | set-up CPU (s) | stored f64 | MB | table MB | dense blocks | low-rank blocks | max rank | ‖K − K_H‖_F/‖K‖_F (sampled) | product (ms, median) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    for &dx in &cli.dx {
        let model = bp5.model(dx)?;
        let options = HalfSpaceOptions {
            // Always the ℋ-matrix, also where BP5 would keep K dense.
            dense_max: 0,
            ..bp5.half_space(cli.epsilon)?
        };
        let (wall, cpu) = (Instant::now(), cpu_seconds());
        let mut op = HalfSpaceOperator::fault_alone(&model, &options)?;
        let (setup_wall, setup_cpu) = (wall.elapsed().as_secs_f64(), cpu_seconds() - cpu);
        let m = op.dim();
        let product = median_product_seconds(&mut op, cli.products)?;
        let report = op.report();
        println!(
            "| {dx} | {m} | {setup_wall:.2} | {setup_cpu:.2} | {} | {:.1} | {:.1} | {} | {:.3} |",
            report.stored_entries,
            report.bytes() as f64 / 1e6,
            report.setup_bytes as f64 / 1e6,
            block_columns(report),
            product * 1e3
        );
        rows.push((
            m as f64,
            [report.stored_entries as f64, product, setup_wall],
        ));
    }
    if rows.len() >= 2 {
        let [stored, product, setup] = fit_exponents(&rows);
        println!(
            "stored f64 ~ m^{stored:.3}, product ~ m^{product:.3}, set-up ~ m^{setup:.3} (least squares on log–log, {} sizes)",
            rows.len()
        );
    }
    Ok(())
}
