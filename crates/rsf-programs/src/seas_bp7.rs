//! SEAS BP7-QD-A / BP7-QD-S (nucleation on a velocity-weakening disc of a square fault in
//! a whole space; docs/seas-bp7.md): the fault outside the square creeps at the plate
//! rate, a prescribed shear-stress bump `Δτ₀ G₁(r) G₂(t)` centred at `(−50, −50)` m
//! kicks it at `t = 0`, and the disc ruptures in earthquakes over 10 years.
//!
//! ```sh
//! cargo run --release --example seas_bp7 -- --law aging --out out/bp7a   # 10 m, 10 years
//! cargo run --release --example seas_bp7 -- --law slip --dx 20 --out out/bp7s
//! ```
//!
//! The fault ODE (`--integrator`, Dormand–Prince 5(4) while accuracy sets the step) on the
//! `(800 m/Δx)²` square cells, the whole space's boundary-element operator applied by
//! FFTs (`rsf::halfspace_operator::WholeSpaceGrid`), loaded by back slip at V_p and by
//! the bump (`rsf::fault_ode::LoadChange`, steps ending at its rise time T = 1 s).
//! `--d-rs` (mm) sets D_RS: 0.50 by default, 0.53 in two of the five implementations the
//! restatement read (docs/seas-bp7.md).
//!
//! Writes the benchmark's files to `--out` (`rsf_seas::SeasBp5Output::bp7`: thirteen
//! stations `fltst_strk±XXXdp±YYY`, six `blkst_…`, `global.dat`, slip and shear-stress
//! profiles, `rupture.dat`, `events.csv`), `summary.json`. Runs: `--checkpoint-every N`,
//! `--resume FILE`, `--max-steps N`, `--overwrite`, as every SEAS program.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use crate::guard::{
    flag_range, in_range, number, refuse, written, AnyError, Folder, Limits, Plan, Prepared,
    Program,
};
use crate::square_fault::{run_square_fault, SquareRun};
use crate::square_fault::{DX, DX_HELP, TOLERANCE, TOLERANCE_HELP};
use crate::{cpu_seconds, machine};
use clap::Parser;
use rsf::checkpoint::Fingerprint;
use rsf::observe::TimeUnit;
use rsf_scenes::{Bp7Law, SeasBp7};
use rsf_seas::{
    SeasBp5Output, SeasLayout, SeasSampling, SeasSetup, SEAS_BP7_RESUME_LOG, SECONDS_PER_YEAR,
};

flag_range!(
    END_YEARS,
    END_YEARS_HELP = "End time (years of 365.25 days)",
    [1e-9, 1000]
);
flag_range!(
    D_RS,
    D_RS_HELP = "Characteristic slip distance D_RS (mm; docs/seas-bp7.md: 0.50 or 0.53)",
    [0.01, 100]
);
flag_range!(
    STATION_INTERVAL,
    STATION_INTERVAL_HELP =
        "Station interval between events (s; 0: a station row at every accepted step)",
    [0, 1e7]
);

/// SEAS BP7-QD-A / BP7-QD-S.
#[derive(Parser)]
#[command(version)]
pub(crate) struct Args {
    /// The state law: aging (BP7-QD-A) or slip (BP7-QD-S).
    #[arg(long, default_value = "aging")]
    law: String,
    /// Output folder.
    #[arg(long, default_value = "out/seas_bp7")]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out`.
    #[arg(long)]
    overwrite: bool,
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true, help = END_YEARS_HELP)]
    end_years: f64,
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true, help = DX_HELP)]
    dx: f64,
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true, help = D_RS_HELP)]
    d_rs: f64,
    #[arg(long, default_value_t = 1e-7, allow_negative_numbers = true, help = TOLERANCE_HELP)]
    tolerance: f64,
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, help = STATION_INTERVAL_HELP)]
    station_interval: f64,
    #[command(flatten)]
    integrator: crate::IntegratorArgs,
    /// Threads of each evaluation (the same bits for every value).
    #[arg(long, default_value_t = 1)]
    threads: usize,
    #[command(flatten)]
    header: crate::SeasHeaderArgs,
    #[command(flatten)]
    run: crate::ResumeArgs,
    #[command(flatten)]
    limits: Limits,
}

impl Args {
    /// What a checkpoint continues: the scene, the law, the cell and what changes the
    /// trajectory (the plan's too: a checkpoint is checked against it before the folder
    /// changes).
    ///
    /// # Errors
    /// The law's (`--law`).
    fn fingerprint(&self) -> Result<Fingerprint, AnyError> {
        let fingerprint = Fingerprint::of_serialized(&self.scene())
            .with("law", self.law()?.name())
            .with("dx", self.dx)
            .with("tolerance", self.tolerance)
            .with("end_years", self.end_years)
            .with("station_interval", self.station_interval);
        Ok(self.integrator.fingerprint(fingerprint))
    }

    fn law(&self) -> Result<Bp7Law, AnyError> {
        self.law
            .parse()
            .map_err(|_| refuse("--law", &self.law, "must be aging or slip"))
    }
    fn end_seconds(&self) -> f64 {
        self.end_years * SECONDS_PER_YEAR
    }
    fn scene(&self) -> SeasBp7 {
        SeasBp7 {
            d_rs: self.d_rs * 1e-3,
            ..SeasBp7::default()
        }
    }
}

/// The files a run writes into `--out`.
fn outputs() -> Vec<String> {
    let mut names = SeasBp5Output::bp7_file_names();
    names.extend(["checkpoint.bin", SEAS_BP7_RESUME_LOG, "summary.json"].map(String::from));
    names
}

impl Program for Args {
    const NAME: &'static str = "seas_bp7";

    fn limits(&self) -> Limits {
        self.limits
    }

    fn plan(&self) -> Result<Plan, AnyError> {
        self.law()?;
        in_range("--end-years", self.end_years, END_YEARS, "years")?;
        in_range("--d-rs", self.d_rs, D_RS, "mm")?;
        let bp7 = self.scene();
        in_range("--dx", self.dx, DX, "m")?;
        let cells = bp7
            .cells(self.dx)
            .map_err(|_| refuse("--dx", written(self.dx), "must divide 2 l_f = 800 m"))?
            .len() as f64;
        in_range("--tolerance", self.tolerance, TOLERANCE, "")?;
        in_range(
            "--station-interval",
            self.station_interval,
            STATION_INTERVAL,
            "s",
        )?;
        self.header.check()?;
        // Station rows (19 files of 8 columns and global.dat, 130 B a row each) at most
        // one per accepted step, the steps bounded by 10 000 a year for this estimate
        // (measured at 20 m: 1 318 a year with the aging law, 3 459 with the slip law;
        // docs/seas-bp7.md; fewer with `--station-interval`); profile rows (4 files of
        // 83 columns) one per second of events, 2 000 a year.
        let years = self.end_years;
        let rows = years * 1e4;
        let output = rows * 20.0 * 130.0 + years * 2000.0 * 4.0 * 83.0 * 15.0;
        // The fault ODE's vectors and the FFT operator's circulant, 2 kB per cell as BP8
        // (docs/seas-bp8.md), the six off-fault stations' displacement columns (3 × 2
        // values a cell each) 300 B per cell; the rows, kept in memory until the files
        // are written; 100 MB for the rest.
        let memory = 2300.0 * cells + output + 1e8;
        let names = outputs();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        Ok(Plan::new()
            .pool(self.threads)
            .memory(
                memory,
                "--dx",
                format!("BP7 on Δx = {} m: {cells} cells", number(self.dx)),
            )
            .output(
                output,
                "--end-years",
                format!("{} years of stations and profiles", written(self.end_years)),
            )
            .folder(
                self.run
                    .folder(Folder::new("--out", &self.out, &names).overwrite(self.overwrite))
                    .fingerprint(self.fingerprint()?),
            ))
    }
}

/// The program `seas_bp7`.
pub fn main() -> ExitCode {
    crate::guard::main(run)
}

fn run(args: Args, folder: Prepared) -> Result<(), AnyError> {
    let law = args.law()?;
    let bp7 = args.scene();
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let sampling = if args.station_interval == 0.0 {
        SeasSampling {
            every_step: true,
            ..SeasSampling::default()
        }
    } else {
        SeasSampling {
            station_quiet: args.station_interval,
            ..SeasSampling::default()
        }
    };
    let setup = SeasSetup {
        problem: format!("SEAS Benchmark BP7-QD-{}", law.name()),
        modeler: args.header.modeler.clone(),
        date: args.header.date_or_today(),
        element_size: args.dx,
        stations: Vec::new(),
        depth_axis: 2,
        depth_down: true,
        sigma_n: bp7.sigma_n,
        profile_spacing: args.dx,
        sampling,
        layout: SeasLayout::default(),
        surface_stations: Vec::new(),
    };
    let fingerprint = args.fingerprint()?;
    println!(
        "BP7-QD-{}, Δx = {} m, D_RS = {} mm, whole space (FFT boundary elements); on {}",
        law.name(),
        args.dx,
        args.d_rs,
        machine()
    );
    let mut options = bp7.fault_ode_options(args.tolerance)?;
    options.parallelism = rsf::Parallelism::rayon(args.threads);
    options.integrator = args.integrator.integrator;
    let (mut ode, body_columns) = bp7.fault_ode(args.dx, law, options)?;
    // The folder's lock is held until the run ends.
    let _folder = &folder;
    let settings = SquareRun {
        run: &args.run,
        integrator: &args.integrator,
        threads: args.threads,
        out: &args.out,
        fingerprint,
        end: args.end_seconds(),
        unit: (
            TimeUnit {
                seconds: SECONDS_PER_YEAR,
                symbol: "yr",
            },
            "BP7",
        ),
        started: (clock, cpu0),
    };
    let output = || Ok(bp7.output(&args.out, args.dx, body_columns, setup)?);
    let keys = serde_json::json!({
        "problem": format!("BP7-QD-{}", law.name()),
        "dx_m": args.dx,
        "d_rs_mm": args.d_rs,
        "end_years": args.end_years,
        "tolerance": args.tolerance,
    });
    run_square_fault(settings, &mut ode, output, keys)?;
    Ok(())
}

#[cfg(test)]
mod flag_tests {
    /// `--dx`'s upper bound is the scene's `l_f` (the flag's range is written as a
    /// literal, for `--help`).
    #[test]
    fn the_dx_bound_is_the_half_width() {
        assert_eq!(super::DX.1, rsf_scenes::SeasBp7::default().l_f);
    }
}
