//! A stepover between two strike-slip strands in map view (plane strain, quasi-dynamic;
//! docs/fault-networks.md): the fault network `rsf_scenes::Stepover` — two parallel
//! strands with SEAS BP1's friction along strike from their tips, loaded by creep beyond
//! their far ends and by the box's plate motion — integrated by the fault ODE over many
//! cycles, with the catalogue of which strand each event ruptured.
//!
//! ```sh
//! cargo run --release --example stepover -- --gap-km 1 --overlap-km 2 --out out/stepover
//! cargo run --release --example stepover -- --gap-km 4 --dx 50 --end-years 1500 --out out/stepover_4km
//! ```
//!
//! Writes to `--out`: a station file per strand and distance from its tip
//! (`{south,north}_sNN.Nkm.csv`: step, time, slip, slip rate, shear traction, state;
//! rsf::observe::FaultStations), the catalogue `catalogue.csv` (every event: onset, end,
//! the strand and place where it nucleated, the strands it ruptured, per strand its peak
//! slip rate, moment and rupture time; rsf::observe::FaultCatalogue), `summary.json` (the
//! scene, the run, the events, how many jumped the step), and the figure `catalogue.png`
//! (each event's strands against time).
//!
//! Runs: `--checkpoint-every N`, `--resume FILE`, `--allow-change`, `--max-steps N` as the
//! SEAS programs (the files and the catalogue continue byte for byte), `--overwrite`.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use crate::estimates::{csv_row_bytes, operator_bytes, FIGURE_BYTES, SEAS_BYTES_PER_NODE};
use crate::guard::{
    flag_range, in_range, number, written, AnyError, Folder, Limits, Plan, Prepared, Program,
};
use crate::{cpu_seconds, machine};
use clap::Parser;
use rsf::checkpoint::Fingerprint;
use rsf_scenes::{SeasBp1, Stepover, StepoverGrid};

flag_range!(END_YEARS, END_YEARS_HELP = "End time (years)", [1e-9, 1e5]);
flag_range!(
    DX,
    DX_HELP = "Element size along the strands and next to them (m); must divide half the gap, half the overlap and the strands' frictional length into whole cells; at most H/8 = 1875 m",
    [1, 1875]
);
flag_range!(
    GAP_KM,
    GAP_KM_HELP = "Distance between the strands across strike (km); half of it at least the \
                   smallest --dx, 1 m",
    [2e-3, 1e3]
);
flag_range!(
    STRAND_KM,
    STRAND_KM_HELP = "Length of each strand's frictional part (km), from its tip: velocity weakening over 15 km, the transition to 18 km, velocity strengthening to this, creep beyond",
    [1, 1e4]
);
flag_range!(
    RATIO,
    RATIO_HELP = "Growth of the elements away from the strands",
    [1, 2]
);

/// A stepover between two strike-slip strands (map view, plane strain).
#[derive(Parser)]
#[command(version)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/stepover")]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out` (without it, a folder holding any
    /// rsf program's run is refused and left untouched).
    #[arg(long)]
    overwrite: bool,
    #[arg(long, default_value_t = 3000.0, allow_negative_numbers = true, help = END_YEARS_HELP)]
    end_years: f64,
    #[arg(long, default_value_t = 25.0, allow_negative_numbers = true, help = DX_HELP)]
    dx: f64,
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true, help = GAP_KM_HELP)]
    gap_km: f64,
    /// Overlap of the strands along strike (km; negative: an underlap, the tips apart);
    /// shorter than 0.9 of a strand either way.
    #[arg(long, default_value_t = 2.0, allow_negative_numbers = true)]
    overlap_km: f64,
    #[arg(long, default_value_t = 25.0, allow_negative_numbers = true, help = STRAND_KM_HELP)]
    strand_km: f64,
    /// How far the box reaches beyond the strands (km), along and across strike: at least
    /// `--strand-km`, at most 1e5.
    #[arg(long, default_value_t = 50.0, allow_negative_numbers = true)]
    domain_km: f64,
    #[arg(long, default_value_t = 1.05, allow_negative_numbers = true, help = RATIO_HELP)]
    ratio: f64,
    /// The normal stress changes with slip (a releasing or restraining step); default the
    /// laws' fixed σ_n.
    #[arg(long)]
    normal_stress_from_slip: bool,
    /// Tolerance of the fault ODE, in (2.220446049250313e-16, 1) (open: from f64::EPSILON
    /// to 1).
    #[arg(long, default_value_t = 1e-6, allow_negative_numbers = true)]
    tolerance: f64,
    #[command(flatten)]
    kernel: crate::KernelArgs,
    #[command(flatten)]
    integrator: crate::IntegratorArgs,
    /// Threads of each evaluation (the same bits for every value). Default: every core.
    #[arg(long, default_value_t = rsf::Parallelism::available_cores())]
    threads: usize,
    /// `--checkpoint-every N`, `--resume FILE`, `--allow-change`, `--max-steps N`.
    #[command(flatten)]
    run: crate::ResumeArgs,
    #[command(flatten)]
    limits: Limits,
}

/// The scene and grid of the flags.
fn scene(args: &Args) -> (Stepover, StepoverGrid) {
    let stepover = Stepover {
        params: SeasBp1 {
            w_f: args.strand_km * 1e3,
            ..SeasBp1::default()
        },
        gap: args.gap_km * 1e3,
        overlap: args.overlap_km * 1e3,
        normal_stress_from_slip: args.normal_stress_from_slip,
    };
    let grid = StepoverGrid {
        dx: args.dx,
        domain: args.domain_km * 1e3,
        ratio: args.ratio,
    };
    (stepover, grid)
}

/// The files a run writes into `--out`.
fn outputs(stepover: &Stepover) -> Vec<String> {
    let mut names: Vec<String> = stepover
        .stations()
        .iter()
        .map(|s| format!("{}_{}.csv", s.fault, s.label))
        .collect();
    names.extend(crate::network::NETWORK_FILES.map(String::from));
    names
}

/// Bytes per station row (step, time, slip, slip rate, traction, state).
fn station_row_bytes() -> f64 {
    csv_row_bytes(6)
}

impl Args {
    /// What a checkpoint continues: the two strands, the grid and what changes the
    /// trajectory (the plan's too: a checkpoint is checked against it before the folder
    /// changes).
    ///
    /// # Errors
    /// The kernel's (`--kernel-epsilon`).
    fn fingerprint(&self) -> Result<Fingerprint, AnyError> {
        let (stepover, _) = scene(self);
        Ok(self.integrator.fingerprint(
            crate::cli::with_box_and_end(
                Fingerprint::of_serialized(&stepover),
                (self.dx, self.domain_km, self.ratio),
                self.end_years,
                self.tolerance,
            )
            .with("kernel", self.kernel.kernel(self.tolerance)?),
        ))
    }
}

impl Program for Args {
    const NAME: &'static str = "stepover";

    fn limits(&self) -> Limits {
        self.limits
    }

    fn plan(&self) -> Result<Plan, AnyError> {
        in_range("--end-years", self.end_years, END_YEARS, "years")?;
        in_range("--strand-km", self.strand_km, STRAND_KM, "km")?;
        in_range("--gap-km", self.gap_km, GAP_KM, "km")?;
        in_range(
            "--overlap-km",
            self.overlap_km,
            (-0.9 * self.strand_km, 0.9 * self.strand_km),
            "km: shorter than a strand either way",
        )?;
        in_range("--dx", self.dx, DX, "m: at most H/8")?;
        in_range(
            "--domain-km",
            self.domain_km,
            (self.strand_km, 1e5),
            "km: at least a strand's length",
        )?;
        in_range("--ratio", self.ratio, RATIO, "the growth of the elements")?;
        let (stepover, grid) = scene(self);
        stepover
            .check_grid(&grid)
            .map_err(|e| format!("--dx {}: {e}", written(self.dx)))?;
        crate::cli::for_flag(
            "--tolerance",
            "tolerance",
            stepover.params.fault_ode_options(self.tolerance),
        )?;
        self.kernel.kernel(self.tolerance)?;
        // The graded mesh in closed form (as Stepover::mesh grades it).
        let [x_half, _] = stepover.box_half(&grid);
        let reach = x_half - grid.domain;
        let len = rsf::fem::geometric_grading_len;
        let nx = 2.0 * len(grid.dx, reach, grid.ratio, x_half) - 1.0;
        let g = 0.5 * stepover.gap;
        let ny = 2.0 * len(grid.dx, 2.0 * grid.dx, grid.ratio, grid.domain)
            + 2.0 * len(grid.dx, (2.0 * grid.dx).min(g), grid.ratio, g)
            - 3.0;
        let nodes = nx * ny;
        // Both strands' slip nodes across the box.
        let fault_nodes = 2.0 * (x_half + x_half) / grid.dx;
        let hierarchical = self.kernel.kernel == crate::KernelArg::Hierarchical;
        let memory = nodes * SEAS_BYTES_PER_NODE + 2.0 * operator_bytes(fault_nodes, hierarchical);
        // Rows: every step, a few hundred steps per year with events (the BP1 programs'
        // rate is an upper bound for the stations written at every step).
        let stations = stepover.stations().len() as f64;
        let rows = self.end_years * 400.0 + 1e4;
        let names = outputs(&stepover);
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        Ok(Plan::new()
            .pool(self.threads)
            .memory(
                memory,
                "--dx, --domain-km, --ratio, --strand-km",
                format!(
                    "the stepover on dx = {} m: about {nodes:.3e} nodes, {fault_nodes:.3e} on \
                     the strands",
                    number(self.dx)
                ),
            )
            .output(
                stations * rows * station_row_bytes() + FIGURE_BYTES + 1e7,
                "--end-years",
                format!(
                    "{} years of {stations} station files",
                    written(self.end_years)
                ),
            )
            .folder(
                self.run
                    .folder(Folder::new("--out", &self.out, &names).overwrite(self.overwrite))
                    .fingerprint(self.fingerprint()?),
            ))
    }
}

/// The program `stepover` (`cargo run --release --example stepover -- --out DIR …`).
pub fn main() -> ExitCode {
    crate::guard::main(run)
}

fn run(args: Args, folder: Prepared) -> Result<(), AnyError> {
    let (stepover, grid) = scene(&args);
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let model = stepover.model(&grid)?;
    println!(
        "stepover: gap {} km, overlap {} km, strands {} km, Δx = {} m, {} nodes, {} frictional \
         nodes ({} on the south strand); on {}",
        args.gap_km,
        args.overlap_km,
        args.strand_km,
        args.dx,
        model.vertices.len(),
        model.frictional_boundary.len(),
        model.frictional_boundary.along_fault(0).len(),
        machine()
    );
    let mut options = stepover.params.fault_ode_options(args.tolerance)?;
    options.kernel = args.kernel.kernel(args.tolerance)?;
    options.integrator = args.integrator.integrator;
    options.parallelism = rsf::Parallelism::rayon(args.threads);
    let mut ode = stepover.fault_ode(model, options)?;
    println!("S: {}", ode.kernel_report());
    println!(
        "set-up: wall {:.1} s, CPU {:.1} s",
        clock.elapsed().as_secs_f64(),
        cpu_seconds() - cpu0
    );
    let fingerprint = args.fingerprint()?;
    let outcome = crate::network::run_network(
        &mut ode,
        &stepover.stations(),
        fingerprint,
        crate::network::NetworkRun {
            out: &args.out,
            fresh: folder.mode(),
            end_years: args.end_years,
            resume: &args.run,
            label: "stepover",
            rigidity: stepover.params.shear_modulus(),
        },
    )?;
    crate::network::finish(
        crate::network::NetworkEnd {
            out: &args.out,
            outcome: &outcome,
            evaluations: ode.evaluations(),
            integrator: args.integrator.summary(Some(ode.integrator_stats())),
            started: (clock, cpu0),
        },
        serde_json::json!({ "program": "stepover", "scene": stepover, "grid": grid }),
        serde_json::json!({ "end_years": args.end_years, "tolerance": args.tolerance }),
    )
}

#[cfg(test)]
mod flag_tests {
    /// `--dx`'s upper bound is H/8 of the scene's `H` (the flag's range is written as a
    /// literal, for `--help`).
    #[test]
    fn the_dx_bound_is_an_eighth_of_h() {
        assert_eq!(super::DX.1, rsf_scenes::SeasBp1::default().h_top / 8.0);
    }
}
