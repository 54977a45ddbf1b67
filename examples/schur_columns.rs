//! The fault's Schur complement `S` three ways (issue 70, item 3; docs/three-d.md, "Columns
//! of S by solves"): the multifrontal elimination that keeps no factor column
//! (`rsf_direct::SchurOnly`, what `seas_bp5 --kernel fe` uses), and one static solve per
//! column (`rsf::model::SchurColumns`) by the sparse Cholesky factor of the interior or by
//! multigrid on the refinement hierarchy (memory linear in the dofs). The model: a 2 m cube
//! of 4³ boxes refined `--levels` times, its bottom clamped, a buried square fault
//! `|y|, |z| ≤ 0.5 m` in the plane `x = 0`. Per level it prints the dofs, the slip unknowns
//! `m`, each way's set-up and time per column, multigrid's iterations, and the largest
//! difference from the elimination's `S` (relative to its largest diagonal entry); then the
//! exponents of the times against the dofs.
//!
//! ```sh
//! cargo run --release --example schur_columns -- --levels 1,2,3
//! ```

use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use rsf::direct::{InteriorOrdering, SchurOnly, SchurOnlyOptions};
use rsf::fem::cuboid;
use rsf::model::{SchurColumns, StaticMethod, StaticOptions};
use rsf::nonsmooth::Stopping;
use rsf::{Material, Model, ModelBuilder, Parallelism, Part};
use rsf_programs::estimates::fe_3d_memory;
use rsf_programs::guard::{in_range, refuse, AnyError, Limits, Plan, Prepared, Program};
use rsf_programs::{cpu_seconds, fit_exponents};

/// `S` by elimination, by Cholesky solves and by multigrid solves.
#[derive(Parser)]
#[command(version)]
struct Cli {
    /// Refinements of the 4³ cube (comma separated, each 0 to 3; 3 has 108 486 dofs).
    #[arg(long, value_delimiter = ',', default_value = "1,2,3")]
    levels: Vec<usize>,
    /// Multigrid's stopping test: the energy norm of the last correction at most this
    /// multiple of the solution's.
    #[arg(long, default_value_t = 1e-10)]
    tolerance: f64,
    /// Threads of multigrid's smoothing (the iterates do not depend on them).
    #[arg(long, default_value_t = 1)]
    threads: usize,
    /// Columns timed by each solve-based way (evenly spread; all of them if larger than
    /// `m`); the difference from the elimination is over these columns.
    #[arg(long, default_value_t = 64)]
    columns: usize,
    #[command(flatten)]
    limits: Limits,
}

/// The largest level: 4 would be 840 000 dofs, whose Cholesky factor of a uniform cube
/// does not fit this machine (level 3: 2.48 GB).
const MAX_LEVEL: usize = 3;

/// The uniform cube fills its factors more than the graded box
/// [`fe_3d_memory`] was fitted to: `schur_columns --levels 1,2,3` peaked at 2.48 GB
/// (the Cholesky factor of level 3) against that estimate's 1.51 GB (AMD EPYC).
const UNIFORM_CUBE_FILL: f64 = 2.5;

impl Program for Cli {
    rsf_programs::name_and_limits!("schur_columns");

    fn plan(&self) -> Result<Plan, AnyError> {
        rsf_programs::guard::distinct("--levels", &self.levels)?;
        if let Some(&l) = self.levels.iter().find(|&&l| l > MAX_LEVEL) {
            return Err(refuse(
                "--levels",
                l,
                &format!("at most {MAX_LEVEL} (each level has 8× the dofs)"),
            ));
        }
        in_range(
            "--tolerance",
            self.tolerance,
            (1e-15, 0.5),
            "a relative tolerance",
        )?;
        in_range(
            "--columns",
            self.columns as f64,
            (1.0, 1e6),
            "columns timed per way",
        )?;
        let worst = self.levels.iter().copied().max().unwrap_or(0);
        let vertices = (4.0 * 2f64.powi(worst as i32) + 1.0).powi(3);
        Ok(Plan::new().threads("--threads", self.threads).memory(
            UNIFORM_CUBE_FILL * fe_3d_memory(vertices),
            "--levels",
            format!("the cube refined {worst} times: {vertices:.3e} vertices"),
        ))
    }
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

/// The cube refined `level` times with its fault.
fn model(level: usize) -> Result<Model<3>, AnyError> {
    Ok(
        ModelBuilder::refined(cuboid([-1.0; 3], [2.0; 3], [5; 3])?, level)?
            .material(Material::new(1e10, 0.25, 2700.0))
            .without_mass()
            .without_initial_equilibrium()
            .dirichlet(Part::predicate("bottom", |x| x[2] < -1.0 + 1e-9), [0.0; 3])
            .internal_fault_polygon(
                "fault",
                &[
                    [0.0, -0.5, -0.5],
                    [0.0, 0.5, -0.5],
                    [0.0, 0.5, 0.5],
                    [0.0, -0.5, 0.5],
                ],
            )
            .build()?,
    )
}

/// One solve-based way's timings on `cols`: set-up (s), CPU per column (s), iterations
/// per column, largest difference from `s_ref` over the columns.
fn by_solves(
    model: &Model<3>,
    options: StaticOptions,
    cols: &[usize],
    s_ref: &impl Fn(usize, usize) -> f64,
) -> Result<(f64, f64, f64, f64), AnyError> {
    let clock = Instant::now();
    let columns = SchurColumns::new(model, options)?;
    let setup = clock.elapsed().as_secs_f64();
    let m = columns.dim();
    let mut out = faer::Mat::zeros(m, cols.len());
    let cpu = cpu_seconds();
    columns.columns(cols, out.as_mut())?;
    let per_column = (cpu_seconds() - cpu) / cols.len() as f64;
    let scale = (0..m).map(|i| s_ref(i, i)).fold(0.0f64, f64::max);
    let mut diff = 0.0f64;
    for (k, &j) in cols.iter().enumerate() {
        for i in 0..m {
            diff = diff.max((out[(i, k)] - s_ref(i, j)).abs());
        }
    }
    let iterations = columns.report().iterations as f64 / cols.len() as f64;
    Ok((setup, per_column, iterations, diff / scale))
}

fn run(cli: Cli, _: Prepared) -> Result<(), AnyError> {
    let mut levels = cli.levels.clone();
    levels.sort_unstable();
    println!(
        "multigrid: relative tolerance {:e}, {} thread(s); times are CPU seconds",
        cli.tolerance, cli.threads
    );
    println!(
        "| level | dofs | m | elimination (s) | elimination per column (s) | Cholesky set-up (s) | Cholesky per column (s) | Cholesky diff | multigrid set-up (s) | multigrid per column (s) | iterations per column | multigrid diff |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    for level in levels {
        let model = model(level)?;
        let dofs = model.num_dofs();
        let cpu = cpu_seconds();
        let elimination = SchurOnly::<3>::new(
            model.stiffness.as_ref(),
            &model.fixed,
            &model.frictional_boundary.nodes,
            &[],
            InteriorOrdering::Amd,
        )?;
        let kept = elimination.eliminate(&[], &SchurOnlyOptions::default())?;
        drop(elimination);
        let eliminate = cpu_seconds() - cpu;
        let m = kept.dim();
        let s = kept.schur();
        let s_ref = |i: usize, j: usize| s.entry(i, j);
        let k = cli.columns.min(m);
        let cols: Vec<usize> = (0..k).map(|c| c * m / k).collect();
        let chol = by_solves(
            &model,
            StaticOptions::method(StaticMethod::Direct),
            &cols,
            &s_ref,
        )?;
        let mg_options = StaticOptions::method(StaticMethod::Multigrid)
            .with_stopping(Stopping {
                absolute: 0.0,
                relative: cli.tolerance,
                max_iterations: 500,
            })
            .with_parallelism(Parallelism::rayon(cli.threads));
        let mg = by_solves(&model, mg_options, &cols, &s_ref)?;
        println!(
            "| {level} | {dofs} | {m} | {eliminate:.2} | {:.2e} | {:.2} | {:.2e} | {:.1e} | {:.2} | {:.2e} | {:.1} | {:.1e} |",
            eliminate / m as f64,
            chol.0,
            chol.1,
            chol.3,
            mg.0,
            mg.1,
            mg.2,
            mg.3,
        );
        rows.push((dofs as f64, [eliminate, chol.1 * m as f64, mg.1 * m as f64]));
    }
    if rows.len() >= 2 {
        let [elimination, cholesky, multigrid] = fit_exponents(&rows);
        println!(
            "the whole S (m columns) against the dofs n: elimination ~ n^{elimination:.2}, Cholesky solves ~ n^{cholesky:.2}, multigrid solves ~ n^{multigrid:.2} (least squares on log–log, {} levels)",
            rows.len()
        );
    }
    Ok(())
}
