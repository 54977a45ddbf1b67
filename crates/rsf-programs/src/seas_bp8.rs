//! SEAS BP8-QD-GS / BP8-QD-PW (fluid injection into a velocity-strengthening square of a
//! planar fault in a whole space; docs/seas-bp8.md): the pore pressure diffusing in the
//! fault plane from a Gaussian source (GS) or a Peaceman well (PW) lowers the effective
//! normal stress and drives one aseismic slip transient.
//!
//! ```sh
//! cargo run --release --example seas_bp8 -- --source gs --out out/bp8gs   # 10 m, 30 days
//! cargo run --release --example seas_bp8 -- --source pw --dx 20 --out out/bp8pw
//! ```
//!
//! The fault ODE (`--integrator`, Dormand–Prince 5(4) while accuracy sets the step) on the
//! `(800 m/Δx)²` square cells of the frictional square, the whole space's boundary-element
//! operator applied by FFTs (`rsf::halfspace_operator::WholeSpaceGrid`: exact up to
//! round-off, the locked exterior contributing nothing); the pressure the diffusion on the
//! square's nodes, exact in time (`rsf::pore_pressure::SurfaceDiffusion`), read at the
//! cells' centres. Where the pressure would reach the normal stress (PW, the cells next to
//! the well) `--overpressure floor` (the default) holds the effective normal stress above
//! `--sigma-min` MPa (`rsf::pore_pressure::EffectiveStressFloor`); `--overpressure refuse`
//! stops the run there with the cell and the time.
//!
//! Writes the benchmark's 20 files to `--out` (`rsf_seas::SeasBp5Output::bp8`: nine
//! stations `fltst_strk±XXXdp±YYY`, `global.dat`, ten profiles on the description's 81
//! positions), `summary.json`. Runs: `--checkpoint-every N`, `--resume FILE`,
//! `--max-steps N`, `--overwrite`, as every SEAS program.

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
use rsf_scenes::{Bp8Overpressure, Bp8Source, SeasBp8, BP8_SECONDS_PER_DAY};
use rsf_seas::{SeasBp5Output, SeasLayout, SeasSampling, SeasSetup, SEAS_BP8_RESUME_LOG};

/// The policy where the pressure would reach the normal stress.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Overpressure {
    /// The effective normal stress held above `--sigma-min` by a smooth floor.
    Floor,
    /// The run stops where the effective normal stress would reach 0.
    Refuse,
}

flag_range!(END_DAYS, END_DAYS_HELP = "End time (days)", [1e-6, 3650]);
flag_range!(
    SIGMA_MIN,
    SIGMA_MIN_HELP = "`--overpressure floor`: the least effective normal stress (MPa; at most half of σ̄₀ = 25 MPa); the floor acts below twice this [default: 1]",
    [1e-3, 12.5]
);
flag_range!(
    STATION_INTERVAL,
    STATION_INTERVAL_HELP = "Seconds between station and `global.dat` rows (0: a row at every accepted step, the default)",
    [0, 1e7]
);
flag_range!(
    PROFILE_INTERVAL,
    PROFILE_INTERVAL_HELP = "Seconds between profile rows (the description's hourly by default)",
    [60, 1e7]
);

/// SEAS BP8-QD-GS / BP8-QD-PW.
#[derive(Parser)]
#[command(version)]
pub(crate) struct Args {
    /// The injection's source: gs (a Gaussian) or pw (a Peaceman well).
    #[arg(long, default_value = "gs")]
    source: String,
    /// Output folder.
    #[arg(long, default_value = "out/seas_bp8")]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out`.
    #[arg(long)]
    overwrite: bool,
    #[arg(long, default_value_t = 30.0, allow_negative_numbers = true, help = END_DAYS_HELP)]
    end_days: f64,
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true, help = DX_HELP)]
    dx: f64,
    #[arg(long, default_value_t = 1e-7, allow_negative_numbers = true, help = TOLERANCE_HELP)]
    tolerance: f64,
    /// Where the pressure would reach the normal stress (docs/seas-bp8.md).
    #[arg(long, value_enum, default_value_t = Overpressure::Floor)]
    overpressure: Overpressure,
    #[arg(long, allow_negative_numbers = true, help = SIGMA_MIN_HELP)]
    sigma_min: Option<f64>,
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, help = STATION_INTERVAL_HELP)]
    station_interval: f64,
    #[arg(long, default_value_t = 3600.0, allow_negative_numbers = true, help = PROFILE_INTERVAL_HELP)]
    profile_interval: f64,
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
    /// What a checkpoint continues: the scene, the source, the cell and what changes the
    /// trajectory (the plan's too: a checkpoint is checked against it before the folder
    /// changes).
    ///
    /// # Errors
    /// The source's (`--source`).
    fn fingerprint(&self) -> Result<Fingerprint, AnyError> {
        let fingerprint = Fingerprint::of_serialized(&SeasBp8::default())
            .with("source", self.source()?.name())
            .with("dx", self.dx)
            .with("tolerance", self.tolerance)
            .with("overpressure", format!("{:?}", self.overpressure()))
            .with("end_days", self.end_days)
            .with("station_interval", self.station_interval)
            .with("profile_interval", self.profile_interval);
        Ok(self.integrator.fingerprint(fingerprint))
    }

    fn source(&self) -> Result<Bp8Source, AnyError> {
        self.source
            .parse()
            .map_err(|_| refuse("--source", &self.source, "must be gs or pw"))
    }
    /// The policy (σ_min in Pa).
    fn overpressure(&self) -> Bp8Overpressure {
        match self.overpressure {
            Overpressure::Refuse => Bp8Overpressure::Refuse,
            Overpressure::Floor => Bp8Overpressure::Floor {
                sigma_min: self.sigma_min.unwrap_or(1.0) * 1e6,
            },
        }
    }
    fn end_seconds(&self) -> f64 {
        self.end_days * BP8_SECONDS_PER_DAY
    }
}

/// The files a run writes into `--out`.
fn outputs() -> Vec<String> {
    let mut names = SeasBp5Output::bp8_file_names();
    names.extend(["checkpoint.bin", SEAS_BP8_RESUME_LOG, "summary.json"].map(String::from));
    names
}

impl Program for Args {
    const NAME: &'static str = "seas_bp8";

    fn limits(&self) -> Limits {
        self.limits
    }

    fn plan(&self) -> Result<Plan, AnyError> {
        self.source()?;
        in_range("--end-days", self.end_days, END_DAYS, "days")?;
        let bp8 = SeasBp8::default();
        in_range("--dx", self.dx, DX, "m")?;
        let cells = bp8
            .cells(self.dx)
            .map_err(|_| refuse("--dx", written(self.dx), "must divide 2 l_f = 800 m"))?
            .len() as f64;
        in_range("--tolerance", self.tolerance, TOLERANCE, "")?;
        match (self.overpressure, self.sigma_min) {
            (Overpressure::Refuse, Some(s)) => {
                return Err(refuse(
                    "--sigma-min",
                    written(s),
                    "a setting of `--overpressure floor`: with `refuse` it would be ignored",
                ))
            }
            (Overpressure::Floor, Some(s)) => {
                in_range("--sigma-min", s, SIGMA_MIN, "MPa, at most half of σ̄₀")?;
            }
            _ => {}
        }
        in_range(
            "--station-interval",
            self.station_interval,
            STATION_INTERVAL,
            "s",
        )?;
        in_range(
            "--profile-interval",
            self.profile_interval,
            PROFILE_INTERVAL,
            "s",
        )?;
        self.header.check()?;
        // The fault ODE's vectors, the FFT operator's circulant (4 times the cells, a
        // 2 × 2 block of complex entries each) and the pressure's nodes: 2 kB per cell
        // (measured: 27 MB of max RSS for GS at 10 m, 6 400 cells); PW's modal system of
        // the well, dense in its D directions (one per distinct eigenvalue of the cosine
        // modes: D = 3 283 at 5 m, docs/pore-pressure.md; estimated here as
        // (n/2 + 1)(n/2 + 2)/2 for n cells a side, 3 321 at 5 m), its
        // eigendecomposition's copies counted four times (PW at 5 m: 419 MB of max RSS,
        // this estimate 504 MB); 100 MB for the rest.
        let n = cells.sqrt();
        let modes = (0.5 * n + 1.0) * (0.5 * n + 2.0) / 2.0;
        let well = if self.source()? == Bp8Source::Well {
            4.0 * 8.0 * modes * modes
        } else {
            0.0
        };
        let memory = 2000.0 * cells + well + 1e8;
        // Station rows (9 files of 11 columns and global.dat) at most one per step, the
        // steps bounded by one per minute for this estimate (30 days at 10 m take a few
        // thousand); 10 profiles of 83 columns.
        let seconds = self.end_seconds();
        let rows = seconds / self.station_interval.max(60.0);
        let output = rows * (10.0 * 170.0) + seconds / self.profile_interval * 10.0 * 83.0 * 15.0;
        let names = outputs();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        Ok(Plan::new()
            .pool(self.threads)
            .memory(
                memory,
                "--dx",
                format!("BP8 on Δx = {} m: {cells} cells", number(self.dx)),
            )
            .output(
                output,
                "--end-days",
                format!("{} days of stations and profiles", written(self.end_days)),
            )
            .folder(
                self.run
                    .folder(Folder::new("--out", &self.out, &names).overwrite(self.overwrite))
                    .fingerprint(self.fingerprint()?),
            ))
    }
}

/// The program `seas_bp8`.
pub fn main() -> ExitCode {
    crate::guard::main(run)
}

fn run(args: Args, folder: Prepared) -> Result<(), AnyError> {
    let source = args.source()?;
    let policy = args.overpressure();
    let bp8 = SeasBp8::default();
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let field = bp8.pressure(source, args.dx)?;
    let friction_pressure = bp8.friction_pressure(field.clone(), policy)?;
    let setup = SeasSetup {
        problem: format!("SEAS Benchmark BP8-QD-{}", source.name()),
        modeler: args.header.modeler.clone(),
        date: args.header.date_or_today(),
        element_size: args.dx,
        stations: Vec::new(),
        depth_axis: 2,
        depth_down: true,
        sigma_n: bp8.sigma_n,
        profile_spacing: args.dx,
        sampling: SeasSampling {
            every_step: args.station_interval == 0.0,
            station_quiet: args.station_interval,
            station_event: args.station_interval,
            profile_quiet: args.profile_interval,
            profile_event: args.profile_interval,
            ..SeasSampling::default()
        },
        layout: SeasLayout::default(),
        surface_stations: Vec::new(),
    };
    let fingerprint = args.fingerprint()?;
    println!(
        "BP8-QD-{}, Δx = {} m, whole space (FFT boundary elements), {policy:?}; on {}",
        source.name(),
        args.dx,
        machine()
    );
    let mut options = bp8.fault_ode_options(args.tolerance)?;
    options.parallelism = rsf::Parallelism::rayon(args.threads);
    options.integrator = args.integrator.integrator;
    let mut ode = bp8.fault_ode(args.dx, options, friction_pressure)?;
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
                seconds: BP8_SECONDS_PER_DAY,
                symbol: "d",
            },
            "BP8",
        ),
        started: (clock, cpu0),
    };
    let output = || Ok(bp8.output(&args.out, args.dx, field, setup)?);
    let keys = serde_json::json!({
        "problem": format!("BP8-QD-{}", source.name()),
        "dx_m": args.dx,
        "end_days": args.end_days,
        "tolerance": args.tolerance,
        "overpressure": format!("{policy:?}"),
    });
    run_square_fault(settings, &mut ode, output, keys)?;
    Ok(())
}

#[cfg(test)]
mod flag_tests {
    /// `--dx`'s and `--sigma-min`'s upper bounds are the scene's `l_f` and half its
    /// `σ̄₀` (the flags' ranges are written as literals, for `--help`).
    #[test]
    fn the_bounds_are_the_scenes() {
        let bp8 = rsf_scenes::SeasBp8::default();
        assert_eq!(super::DX.1, bp8.l_f);
        assert_eq!(super::SIGMA_MIN.1, 0.5 * bp8.sigma_n / 1e6);
    }
}
