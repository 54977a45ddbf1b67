//! What the direct solver would hold for the paper's slider (2-D) or the 3-D slider at a
//! refinement level, and what the `auto` solver choice makes of it under a memory budget
//! (issue 25, docs/scaling.md). Runs the fill-reducing ordering and the symbolic
//! factorisation only: seconds even where the factorisation itself would not fit.
//!
//! ```sh
//! cargo run --release --example solver_memory -- --dim 2 --levels 4,5,6,7,8
//! cargo run --release --example solver_memory -- --dim 3 --levels 2,3,4,5 --memory-budget-gib 8
//! ```
//!
//! Prints one row per level: dofs, condensed unknowns, the estimate by part
//! (`rsf::direct::DirectMemory`: sparse factor, dense matrices on Γ_F, the set-up's harmonic
//! extension; MiB), the time the estimate took (s) and the choice of `auto`. Writes no
//! files.

use std::process::ExitCode;

use clap::Parser;
use rsf::direct::{DirectMemory, DirectOptions};
use rsf::method::SolverOptions;
use rsf::{Model, SolverKind};
use rsf_programs::estimates::slider_nodes;
use rsf_programs::guard::{AnyError, Limits, Plan, Prepared, Program};
use rsf_scenes::{Slider3dScene, SliderScene};

/// The direct solver's memory estimate and the `auto` choice per refinement level.
#[derive(Parser)]
#[command(version)]
struct Cli {
    /// Spatial dimension: 2 (the paper's slider) or 3 (the 3-D slider, W = 1 m).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(2..=3))]
    dim: u8,
    /// Refinement levels, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [4usize, 5, 6])]
    levels: Vec<usize>,
    /// The budget (GiB) of the `auto` choice. Default: `rsf::method::DEFAULT_MEMORY_BUDGET_BYTES`.
    #[arg(long)]
    memory_budget_gib: Option<f64>,
    #[command(flatten)]
    limits: Limits,
}

/// Bytes per node of a model with its stiffness matrix and the symbolic factorisation
/// (no factor): assumed a sixth of a 2-D slider run's 30 kB and a third of a 3-D one's
/// 35 kB (the factor and the solver's work are most of a run).
const MODEL_BYTES_PER_NODE: [f64; 2] = [5e3, 12e3];

impl Program for Cli {
    rsf_programs::name_and_limits!("solver_memory");

    fn plan(&self) -> Result<Plan, AnyError> {
        if let Some(gib) = self.memory_budget_gib {
            rsf_programs::memory_budget_bytes("--memory-budget-gib", gib)?;
        }
        rsf_programs::guard::distinct("--levels", &self.levels)?;
        let k = self.levels.iter().copied().max().unwrap_or(0);
        let nodes = if self.dim == 2 {
            slider_nodes(k)
        } else {
            let mut scene = Slider3dScene::default();
            scene.slider.level = k;
            scene.estimated_bytes().0
        };
        let bytes = nodes * MODEL_BYTES_PER_NODE[usize::from(self.dim == 3)];
        Ok(Plan::new().memory(
            bytes,
            "--levels",
            format!("the {}-D slider at level {k}: {nodes:.3e} nodes", self.dim),
        ))
    }
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

fn mib(bytes: usize) -> f64 {
    bytes as f64 / (1u64 << 20) as f64
}

/// One row of the table for `model`.
fn row<const D: usize, const C: usize>(
    level: usize,
    model: &Model<D, C>,
    options: &SolverOptions,
) -> Result<(), Box<dyn std::error::Error>> {
    let start = std::time::Instant::now();
    let est = DirectMemory::estimate::<C>(
        model.stiffness.as_ref(),
        &model.fixed,
        &model.frictional_boundary.nodes,
        true,
        &DirectOptions::default(),
    )?;
    let seconds = start.elapsed().as_secs_f64();
    let condensed = model.condensed_unknowns();
    let choice = match SolverKind::Auto.resolve_within(model, &model.stiffness, options) {
        Ok(kind) => kind.to_string(),
        Err(e) => format!("error: {e}"),
    };
    println!(
        "| {level} | {} | {condensed} | {:.0} | {:.0} | {:.0} | {:.0} | {seconds:.2} | {choice} |",
        model.fixed.len(),
        mib(est.factor_bytes),
        mib(est.dense_bytes),
        mib(est.extension_bytes),
        mib(est.total_bytes()),
    );
    Ok(())
}

fn run(cli: Cli, _: Prepared) -> Result<(), AnyError> {
    let mut options = SolverOptions::default();
    if let Some(gib) = cli.memory_budget_gib {
        options.memory_budget_bytes =
            rsf_programs::memory_budget_bytes("--memory-budget-gib", gib)?;
    }
    println!(
        "{}-D slider, budget {:.1} GiB",
        cli.dim,
        options.memory_budget_bytes as f64 / (1u64 << 30) as f64
    );
    println!(
        "| level | dofs | condensed | factor (MiB) | dense (MiB) | extension (MiB) | total (MiB) | estimate (s) | auto |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for &level in &cli.levels {
        if cli.dim == 2 {
            let scene = SliderScene {
                level,
                ..SliderScene::default()
            };
            row(level, &scene.build_model()?, &options)?;
        } else {
            let mut scene = Slider3dScene::default();
            scene.slider.level = level;
            row(level, &scene.build_model()?, &options)?;
        }
    }
    Ok(())
}
