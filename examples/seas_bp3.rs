//! A coarse SEAS BP3-QD (a thrust or normal fault dipping under a free surface, plane
//! strain, quasi-dynamic; docs/seas-bp3.md): the fault inside the body
//! (`ModelBuilder::internal_fault`), its normal stress changing with slip
//! (`NormalStress::FromSlip`), loaded by creep below W_f (`internal_creep`) and by each
//! side's rigid motion on the far boundaries, integrated by the fault ODE.
//!
//! ```sh
//! cargo run --release --example seas_bp3 -- --dip 60 --out out/bp3_60 --end-years 300
//! cargo run --release --example seas_bp3 -- --dip 30 --dx 250 --out out/bp3_30
//! ```
//!
//! The scene is `rsf_scenes::SeasBp3` (the mesh: a graded structured mesh sheared along
//! the dip, `SeasBp3::mesh`; the parameters: BP1's table, which BP3 shares, with the depth
//! replaced by the down-dip distance x_d).
//!
//! Writes the benchmark's files to `--out` (`SeasBp3::seas_setup`: the twelve on-fault
//! stations `fltst_dpXXX` with six columns — slip, log10 V, shear and normal stress,
//! log10 θ — the eight surface stations `srfst_fn…` with displacement and velocity, the
//! profiles `slip.dat`, `shear_stress.dat` and `normal_stress.dat`, the event catalogue
//! `events.csv`), the figure `overview.png` (slip profiles, maximum slip rate against
//! time), and prints the events.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use rsf::observe::{FileMode, SeasOutput, SeasSampling, SeasSetup, SECONDS_PER_YEAR};
use rsf::Stepping;
use rsf_examples::{cpu_seconds, machine};
use rsf_scenes::{SeasBp3, SeasBp3Grid};

/// A coarse SEAS BP3-QD.
#[derive(Parser)]
#[command(version)]
struct Args {
    /// Dip ψ (degrees): 60 (thrust) or 30 (normal).
    #[arg(long, default_value_t = 60.0)]
    dip: f64,
    /// Output folder.
    #[arg(long, default_value = "out/seas_bp3")]
    out: PathBuf,
    /// End time (years).
    #[arg(long, default_value_t = 300.0)]
    end_years: f64,
    /// Element size along the fault (m).
    #[arg(long, default_value_t = 500.0)]
    dx: f64,
    /// Half-width L of the box across the fault (km); its depth is L sin ψ. The default
    /// moves the first event by < 0.1 yr against a box twice as large (docs/seas-bp3.md).
    #[arg(long, default_value_t = 1600.0)]
    domain_km: f64,
    /// Growth of the elements away from the fault and below W_f. The default is within
    /// 0.2 yr of a ratio of 1.0125 in the first event; 1.1 puts the normal fault's 2.9 yr
    /// early (docs/seas-bp3.md, "Mesh grading").
    #[arg(long, default_value_t = 1.025)]
    ratio: f64,
    /// Tolerance of the fault ODE.
    #[arg(long, default_value_t = 1e-7)]
    tolerance: f64,
    #[command(flatten)]
    kernel: rsf_examples::KernelArgs,
    /// Threads of each evaluation (the operator products and the per-node friction
    /// solves; the same bits for every value). Default: every core of the machine.
    #[arg(long, default_value_t = rsf::Parallelism::available_cores())]
    threads: usize,
    /// Modeler's name for the files' headers.
    #[arg(long, default_value = "rsf")]
    modeler: String,
}

fn main() -> ExitCode {
    let args = Args::parse();
    // With threads, the whole run on the pool (no hand-over per parallel region).
    rsf_examples::main_on_threads(args.threads, || run(args))
}

fn run(args: Args) -> Result<(), Box<dyn std::error::Error>> {
    if !(args.end_years > 0.0 && args.end_years <= 1e5) {
        return Err(format!("--end-years {}: must be in (0, 1e5]", args.end_years).into());
    }
    if !(args.dip > 0.0 && args.dip < 90.0) {
        return Err(format!("--dip {}: must be in (0, 90) degrees", args.dip).into());
    }
    let bp3 = SeasBp3 {
        dip_degrees: args.dip,
        ..if args.dip < 45.0 {
            SeasBp3::normal()
        } else {
            SeasBp3::thrust()
        }
    };
    let grid = SeasBp3Grid {
        dx: args.dx,
        domain: args.domain_km * 1e3,
        ratio: args.ratio,
    };
    std::fs::create_dir_all(&args.out)?;
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let model = bp3.model(&grid)?;
    let fb = &model.frictional_boundary;
    println!(
        "BP3-QD, dip {}° ({}), Δx = {} m, box ±{} km, {} nodes, {} frictional nodes; on {}",
        args.dip,
        if bp3.normal_faulting {
            "normal"
        } else {
            "thrust"
        },
        args.dx,
        args.domain_km,
        model.vertices.len(),
        fb.len(),
        machine()
    );
    if args.threads == 0 {
        return Err("--threads must be at least 1".into());
    }
    let mut options = bp3.params.fault_ode_options(args.tolerance)?;
    options.runge_kutta.dt_min = 1e-8;
    options.kernel = args.kernel.kernel(args.tolerance)?;
    options.parallelism = rsf::Parallelism::rayon(args.threads);
    let mut ode = bp3.fault_ode(model, options)?;
    println!("S: {}", ode.kernel_report());
    if let Some(r) = ode.normal_kernel_report() {
        println!("S_N: {r}");
    }
    println!(
        "set-up: wall {:.1} s, CPU {:.1} s",
        clock.elapsed().as_secs_f64(),
        cpu_seconds() - cpu0
    );
    let setup = SeasSetup {
        modeler: args.modeler.clone(),
        ..bp3.seas_setup(args.dx, SeasSampling::default())
    };
    let mut output = SeasOutput::new(
        &args.out,
        ode.model(),
        ode.problem().friction_laws(),
        setup,
        FileMode::Overwrite,
    )?;
    // The fault ODE computes the surface stations' vertices (not the whole field) after
    // every step; their initial row needs them now.
    ode.watch_vertices(&output.surface_vertices())?;
    output.write_initial_state(ode.model(), ode.state())?;
    let summary = ode.run_until(
        rsf::Until::Time(args.end_years * SECONDS_PER_YEAR),
        &mut [&mut output],
    )?;
    let wall = clock.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - cpu0;
    for e in output.events() {
        println!(
            "event at {:.3} yr: peak slip rate {:.3e} m/s, hypocentre x_d = {:.2} km",
            e.t_start / SECONDS_PER_YEAR,
            e.peak_slip_rate,
            e.hypocentre_depth / 1e3
        );
    }
    println!(
        "{} steps ({} attempts rejected, {} of them for σ̄_n ≤ 0 at a stage), {} evaluations; \
         wall {wall:.1} s, CPU {cpu:.1} s; wrote {}",
        summary.steps,
        summary.rejected_attempts,
        summary.rejected_normal_stress,
        ode.evaluations(),
        args.out.display()
    );
    rsf_examples::seas_overview(
        &args.out,
        "slip.dat",
        "down-dip distance (km)",
        output.events().len(),
    )?;
    println!("wrote {}", args.out.join("overview.png").display());
    Ok(())
}
