//! SEAS BP6-QD-A/S/C (fluid injection into a fault in an antiplane whole space;
//! docs/seas-bp6.md): the pore pressure of the description's closed form (or its
//! diffusion solved along the fault) lowers the effective normal stress and drives one
//! aseismic slip transient.
//!
//! ```sh
//! cargo run --release --example seas_bp6 -- --variant a --out out/bp6a          # 10 m, 2 years, BEM
//! cargo run --release --example seas_bp6 -- --variant s --out out/bp6s
//! cargo run --release --example seas_bp6 -- --variant c --out out/bp6c          # implicit, BEM
//! cargo run --release --example seas_bp6 -- --variant c --elastic fe --dz 50 --out out/bp6c_fe
//! cargo run --release --example seas_bp6 -- --variant a --elastic fe --dz 50 --out out/bp6a_fe
//! ```
//!
//! A and S run as a fault ODE (Dormand–Prince 5(4)) with the whole space's
//! boundary-element kernel on `2 l_f/Δz` cells (`--elastic bem`, the default; its product
//! through FFTs, `--bem-product fft`, or stored as `--kernel` says) or the finite-element
//! half space condensed onto the fault (`--elastic fe`, `--domain-km`, `--ratio`). C
//! (constant friction) runs with the implicit scheme (backward Euler, the direct solver:
//! the nonsmooth problem with the bound `f (σ̄₀ − p(t))` solved exactly at every step) on
//! the fault alone with the boundary-element kernel as its dense stiffness (`--elastic
//! bem`, the default: the description's 10 m in 2 min of CPU and 3 GB) or on the
//! finite-element model (`--elastic fe`: 50 m in 36 s and 1.9 GB, finer cells beyond
//! this machine's memory); a fault ODE cannot take it (its steps would be limited to
//! milliseconds by the damping alone, docs/seas-bp6.md).
//!
//! Writes the benchmark's files to `--out` (`rsf_seas::SeasBp6Output`: nine stations,
//! `global.dat`, four profiles). Runs: `--checkpoint-every N`, `--resume FILE`,
//! `--max-steps N`, `--overwrite`, as every SEAS program.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;

use crate::fields::{Fault2d, FaultFields2d, FieldsRun};
use crate::guard::{
    flag_range, in_range, number, refuse, written, AnyError, Folder, Limits, Plan, Prepared,
    Program,
};
use crate::session::Session;
use crate::{cpu_seconds, machine};
use clap::Parser;
use rsf::checkpoint::Fingerprint;
use rsf::pore_pressure::PorePressure;
use rsf::whole_space::WholeSpaceKernel;
use rsf::Stepping;
use rsf_scenes::{
    bp6_ranges, Bp6BemProduct, Bp6Elastic, Bp6Pressure, Bp6Variant, SeasBp6, SeasBp6Grid,
    SeasBp6Run, BP6_C_FIRST_STEP, BP6_DIFFUSION_CELLS, BP6_SECONDS_PER_YEAR,
};
use rsf_seas::{SeasBp6Output, SeasSetup, SEAS_BP6_RESUME_LOG};

/// The elastic kernel.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Elastic {
    /// The whole space's boundary-element kernel on the fault alone.
    Bem,
    /// The finite-element half space condensed onto the fault (C: the implicit scheme).
    Fe,
}

/// How the boundary-element kernel is applied.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum BemProduct {
    /// FFTs of the Toeplitz kernel's circulant embedding: exact up to round-off,
    /// O(n log n) per product.
    Fft,
    /// The kernel stored as `--kernel` says (dense, or an ℋ-matrix).
    Stored,
}

/// The pore pressure.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum PressureArg {
    /// The description's closed form.
    ClosedForm,
    /// The diffusion solved on `--diffusion-cells` cells between no-flux ends at ±l_f.
    Diffusion,
}

flag_range!(
    END_YEARS,
    END_YEARS_HELP = "End time (years of 365 days)",
    [1e-9, 100]
);
flag_range!(
    DZ,
    DZ_HELP = "Cell (BEM) or element (FE) size along the fault (m), dividing 2 l_f = 40 km \
               into whole cells; at most l_f/2",
    [0.4, 10e3]
);
flag_range!(
    DOMAIN_KM,
    DOMAIN_KM_HELP = "FE: the truncation of the half space, 0 ≤ x ≤ L, |z| ≤ L (km)",
    [30, 1e5]
);
flag_range!(
    RATIO,
    RATIO_HELP = "FE: growth of the elements away from the fault",
    [1, 2]
);
flag_range!(
    TOLERANCE,
    TOLERANCE_HELP = "Tolerance: of the fault ODE (a, s), of the implicit steps' slip error \
                      relative to D_RS (c)",
    [1e-12, 0.1]
);
flag_range!(
    STATION_INTERVAL,
    STATION_INTERVAL_HELP = "Seconds between station and `global.dat` rows (0: a row at every \
                             accepted step, the default — a transient of the slip law lasts \
                             minutes, D_RS/V)",
    [0, 1e7]
);
flag_range!(
    PROFILE_INTERVAL,
    PROFILE_INTERVAL_HELP = "Seconds between profile rows",
    [60, 1e7]
);
flag_range!(
    DIFFUSION_CELLS,
    DIFFUSION_CELLS_HELP = "Cells of the diffusion along 2 l_f (`--pressure diffusion`) \
                            [default: 800]; at most rsf::pore_pressure::MAX_DIFFUSION_CELLS",
    [2, 20000]
);

/// SEAS BP6-QD-A/S/C.
#[derive(Parser)]
#[command(version)]
pub(crate) struct Args {
    /// The variant: a (aging law), s (slip law), c (constant friction).
    #[arg(long, default_value = "a")]
    variant: String,
    /// Output folder.
    #[arg(long, default_value = "out/seas_bp6")]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out`.
    #[arg(long)]
    overwrite: bool,
    #[arg(long, default_value_t = SeasBp6Run::default().end_years, allow_negative_numbers = true, help = END_YEARS_HELP)]
    end_years: f64,
    #[arg(long, default_value_t = SeasBp6Run::default().dz, allow_negative_numbers = true, help = DZ_HELP)]
    dz: f64,
    /// The elastic kernel [default: bem; for c too, whose finite-element model at the
    /// default 10 m would need about 50 GB].
    #[arg(long, value_enum)]
    elastic: Option<Elastic>,
    /// BEM: how the kernel's products are computed [default: fft].
    #[arg(long, value_enum)]
    bem_product: Option<BemProduct>,
    #[arg(long, default_value_t = SeasBp6Run::default().domain_km, allow_negative_numbers = true, help = DOMAIN_KM_HELP)]
    domain_km: f64,
    #[arg(long, default_value_t = SeasBp6Run::default().ratio, allow_negative_numbers = true, help = RATIO_HELP)]
    ratio: f64,
    #[arg(long, allow_negative_numbers = true, help = TOLERANCE_HELP)]
    tolerance: Option<f64>,
    /// The pore pressure.
    #[arg(long, value_enum, default_value = "closed-form")]
    pressure: PressureArg,
    #[arg(long, default_value_t = SeasBp6Run::default().station_interval, allow_negative_numbers = true, help = STATION_INTERVAL_HELP)]
    station_interval: f64,
    #[arg(long, default_value_t = SeasBp6Run::default().profile_interval, allow_negative_numbers = true, help = PROFILE_INTERVAL_HELP)]
    profile_interval: f64,
    #[arg(long, help = DIFFUSION_CELLS_HELP)]
    diffusion_cells: Option<usize>,
    #[command(flatten)]
    kernel: crate::KernelArgs,
    #[command(flatten)]
    integrator: crate::IntegratorArgs,
    /// Threads of each evaluation (the same bits for every value).
    #[arg(long, default_value_t = 1)]
    threads: usize,
    #[command(flatten)]
    header: crate::SeasHeaderArgs,
    #[command(flatten)]
    run: crate::ResumeArgs,
    /// `--hdf5 N`: the fault's fields (crates/rsf-hdf5's `seas_bp6`).
    #[command(flatten)]
    pub(crate) fields: crate::fields::FieldArgs,
    #[command(flatten)]
    limits: Limits,
}

impl Args {
    /// What a checkpoint continues: the scene, the variant, the cell and what changes the
    /// trajectory (the plan's too: a checkpoint is checked against it before the folder
    /// changes).
    ///
    /// # Errors
    /// The variant's and the kernel's (as the plan names them).
    fn fingerprint(&self) -> Result<Fingerprint, AnyError> {
        // The scene's fingerprint of the run's settings (the integrator of the fault ODE
        // runs only), which the Python package's `rsf.seas_bp6` computes too.
        Ok(self.settings()?.fingerprint(&SeasBp6::default()))
    }

    fn variant(&self) -> Result<Bp6Variant, AnyError> {
        self.variant
            .parse()
            .map_err(|_| refuse("--variant", &self.variant, "must be a, s or c"))
    }
    fn elastic(&self) -> Elastic {
        self.elastic.unwrap_or(Elastic::Bem)
    }
    fn tolerance(&self, v: Bp6Variant) -> f64 {
        self.tolerance.unwrap_or(v.default_tolerance())
    }
    fn grid(&self) -> SeasBp6Grid {
        SeasBp6Grid {
            dz: self.dz,
            domain: self.domain_km * 1e3,
            ratio: self.ratio,
        }
    }
    /// The boundary-element kernel's product.
    fn bem_kernel(&self, tol: f64) -> Result<WholeSpaceKernel, AnyError> {
        Ok(match self.bem_product() {
            BemProduct::Fft => WholeSpaceKernel::Fft,
            BemProduct::Stored => WholeSpaceKernel::Stored(self.kernel.kernel(tol.min(1e-2))?),
        })
    }
    /// `--bem-product`, or its default.
    fn bem_product(&self) -> BemProduct {
        self.bem_product.unwrap_or(BemProduct::Fft)
    }
    /// `--diffusion-cells`, or its default.
    fn diffusion_cells(&self) -> usize {
        self.diffusion_cells.unwrap_or(BP6_DIFFUSION_CELLS)
    }
    /// The run's settings as the scene states them (its fingerprint's source, shared with
    /// the Python package's `rsf.seas_bp6`).
    fn settings(&self) -> Result<SeasBp6Run, AnyError> {
        let variant = self.variant()?;
        let tolerance = self.tolerance(variant);
        Ok(SeasBp6Run {
            variant,
            dz: self.dz,
            elastic: match self.elastic() {
                Elastic::Bem => Bp6Elastic::Bem,
                Elastic::Fe => Bp6Elastic::Fe,
            },
            bem_product: match self.bem_product() {
                BemProduct::Fft => Bp6BemProduct::Fft,
                BemProduct::Stored => Bp6BemProduct::Stored,
            },
            domain_km: self.domain_km,
            ratio: self.ratio,
            tolerance,
            pressure: self.pressure_choice(),
            kernel: self.kernel.kernel(tolerance.min(1e-2))?,
            integrator: self.integrator.integrator,
            end_years: self.end_years,
            station_interval: self.station_interval,
            profile_interval: self.profile_interval,
        })
    }
    fn pressure_choice(&self) -> Bp6Pressure {
        match self.pressure {
            PressureArg::ClosedForm => Bp6Pressure::ClosedForm,
            PressureArg::Diffusion => Bp6Pressure::Diffusion {
                cells: self.diffusion_cells(),
            },
        }
    }
}

/// The files a run writes into `--out`.
fn outputs() -> Vec<String> {
    let mut names = SeasBp6Output::file_names();
    names.extend(["checkpoint.bin", SEAS_BP6_RESUME_LOG, "summary.json"].map(String::from));
    names.extend(crate::fields::FIELD_OUTPUTS.map(String::from));
    names
}

impl Args {
    /// Refuses the settings the chosen kernel `elastic` would ignore (careless inputs):
    /// `--bem-product` with the finite elements, `--kernel` or `--kernel-epsilon` with the
    /// boundary elements' FFT product.
    ///
    /// # Errors
    /// The first such flag, named.
    fn check_ignored_by(&self, elastic: Elastic) -> Result<(), AnyError> {
        match elastic {
            Elastic::Fe => {
                if let Some(product) = self.bem_product {
                    return Err(refuse(
                        "--bem-product",
                        format!("{product:?}").to_lowercase(),
                        "a setting of `--elastic bem`: the finite-element model would ignore it",
                    ));
                }
            }
            Elastic::Bem => {
                let stored = self.kernel.kernel != crate::KernelArg::Hierarchical
                    || self.kernel.kernel_epsilon.is_some();
                if stored && self.bem_product() == BemProduct::Fft {
                    return Err(refuse(
                        "--kernel",
                        format!("{:?}", self.kernel.kernel).to_lowercase(),
                        "`--kernel` and `--kernel-epsilon` set the stored kernel of \
                         `--bem-product stored`: the FFT product (the default) would ignore \
                         them",
                    ));
                }
            }
        }
        Ok(())
    }
}

impl Program for Args {
    const NAME: &'static str = "seas_bp6";

    fn limits(&self) -> Limits {
        self.limits
    }

    fn plan(&self) -> Result<Plan, AnyError> {
        let variant = self.variant()?;
        in_range("--end-years", self.end_years, END_YEARS, "years")?;
        self.fields.check(Self::NAME)?;
        let bp6 = SeasBp6::default();
        in_range("--dz", self.dz, DZ, "m")?;
        let cells = 2.0 * bp6.l_f / self.dz;
        if (cells - cells.round()).abs() > 1e-9 * cells {
            return Err(refuse(
                "--dz",
                written(self.dz),
                "must divide 2 l_f = 40 km",
            ));
        }
        let elastic = self.elastic();
        if variant == Bp6Variant::C
            && elastic == Elastic::Bem
            && cells > bp6_ranges::C_BEM_MAX_CELLS
        {
            return Err(refuse(
                "--dz",
                written(self.dz),
                "BP6-C on the boundary-element kernel forms its stiffness densely: at most \
                 20 000 cells (Δz ≥ 2 m)",
            ));
        }
        self.check_ignored_by(elastic)?;
        // The finite-element flags are checked whatever the kernel: a value that would be
        // refused with `--elastic fe` is a careless input with the default kernel too.
        in_range(
            "--domain-km",
            self.domain_km,
            DOMAIN_KM,
            "km: beyond 1.5 l_f",
        )?;
        in_range("--ratio", self.ratio, RATIO, "the growth of the elements")?;
        let tol = self.tolerance(variant);
        in_range("--tolerance", tol, TOLERANCE, "")?;
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
        if self.pressure != PressureArg::Diffusion {
            if let Some(cells) = self.diffusion_cells {
                return Err(refuse(
                    "--diffusion-cells",
                    cells.to_string(),
                    "a setting of `--pressure diffusion`: with the closed form it would be \
                     ignored",
                ));
            }
        } else {
            in_range(
                "--diffusion-cells",
                self.diffusion_cells() as f64,
                DIFFUSION_CELLS,
                "cells",
            )?;
        }
        self.kernel.kernel(tol.min(1e-2))?;
        self.header.check()?;
        let hierarchical = self.kernel.kernel == crate::KernelArg::Hierarchical;
        let (nodes, memory) = match elastic {
            // C: the dense stiffness as a sparse matrix (16 bytes an entry), its energy
            // norm, the direct solver's copies and dense matrices: measured 180 to 190
            // bytes per entry of S (max RSS at 800, 2000 and 4000 cells), bounded by 256.
            Elastic::Bem if variant == Bp6Variant::C => (cells, 256.0 * cells * cells + 1e8),
            Elastic::Bem => (
                cells,
                match self.bem_product() {
                    BemProduct::Fft => 64.0 * cells,
                    BemProduct::Stored => crate::estimates::operator_bytes(cells, hierarchical),
                } + 1e8,
            ),
            Elastic::Fe => {
                let g = self.grid();
                let nx = rsf::fem::geometric_grading_len(g.dz, 0.0, g.ratio, g.domain);
                let nz = 2.0 * rsf::fem::geometric_grading_len(g.dz, bp6.l_f, g.ratio, g.domain);
                let n = nx * nz;
                if variant == Bp6Variant::C {
                    // C: the implicit scheme's direct solver on the volume, whose fault
                    // block is dense: fitted to the measured peaks (max RSS of 2-year runs,
                    // `--domain-km` 400: 229, 624 and 1 941 MB at Δz = 200, 100, 50 m, for
                    // 36 860, 67 140 and 128 400 nodes and 200, 400, 800 cells) as
                    // 3 636 B a node + 2 375 B per (cell)², with a margin of 1.25.
                    (n, 1.25 * (3636.0 * n + 2375.0 * cells * cells))
                } else {
                    (
                        n,
                        n * crate::estimates::SEAS_BYTES_PER_NODE
                            + 3.0 * crate::estimates::operator_bytes(cells, hierarchical),
                    )
                }
            }
        };
        // Station rows (9 files of 7 columns, global.dat): at most one per step, the
        // steps bounded by one per 10 minutes for this estimate (2 years of BP6-S at 10 m
        // take about 10⁴); 4 profiles of 202 columns.
        let seconds = self.end_years * BP6_SECONDS_PER_YEAR;
        let rows = seconds / self.station_interval.max(600.0);
        let output = rows * (10.0 * 110.0) + seconds / self.profile_interval * 4.0 * 202.0 * 15.0;
        let names = outputs();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        Ok(Plan::new()
            .pool(self.threads)
            .memory(
                memory,
                "--dz, --elastic, --domain-km, --ratio",
                format!("BP6 on Δz = {} m: about {nodes:.3e} nodes", number(self.dz)),
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

/// The program `seas_bp6`.
pub fn main() -> ExitCode {
    crate::guard::main(run)
}

/// The program `seas_bp6` with `writers` of the fault's fields (`--hdf5 N`,
/// [`Fault2d`]: antiplane or in-plane as the run's model; the binary
/// `seas_bp6` of crates/rsf-hdf5).
pub fn main_with_fields(writers: std::sync::Arc<dyn crate::fields::FieldWriters>) -> ExitCode {
    crate::guard::main_supplied(|args: &mut Args| args.fields.supply(writers), run)
}

fn run(args: Args, folder: Prepared) -> Result<(), AnyError> {
    let variant = args.variant()?;
    let elastic = args.elastic();
    let tol = args.tolerance(variant);
    let bp6 = SeasBp6::default();
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let pressure = bp6.pressure(args.pressure_choice())?;
    let setup = SeasSetup {
        problem: format!("SEAS Benchmark BP6-QD-{}", variant.name()),
        modeler: args.header.modeler.clone(),
        date: args.header.date_or_today(),
        element_size: args.dz,
        ..bp6.seas_setup(variant, args.dz)
    };
    let fingerprint = args.fingerprint()?;
    let common = Common {
        args: &args,
        folder,
        setup,
        fingerprint,
        pressure: pressure.clone(),
        clock,
        cpu0,
    };
    println!(
        "BP6-QD-{}, Δz = {} m, {:?} kernel, {:?} pore pressure; on {}",
        variant.name(),
        args.dz,
        elastic,
        args.pressure_choice(),
        machine()
    );
    match (variant, elastic) {
        (Bp6Variant::C, Elastic::Bem) => {
            let model = bp6.bem_constant_friction_model(args.dz, args.bem_kernel(tol)?)?;
            let fault = bp6.output_fault(&model, variant);
            println!(
                "{} cells, the kernel as a dense stiffness (set-up CPU {:.1} s)",
                fault.positions.len(),
                cpu_seconds() - cpu0
            );
            let mut sim =
                bp6.constant_friction(model, pressure, BP6_C_FIRST_STEP, bp6.step_control(tol)?)?;
            common.drive(&mut sim, fault, |s| (s.step_count_text(), None))
        }
        (Bp6Variant::C, Elastic::Fe) => {
            let model = bp6.fe_model(&args.grid(), variant)?;
            let fault = bp6.output_fault(&model, variant);
            println!(
                "{} nodes, {} on the fault",
                model.vertices.len(),
                fault.positions.len()
            );
            let mut sim =
                bp6.constant_friction(model, pressure, BP6_C_FIRST_STEP, bp6.step_control(tol)?)?;
            common.drive(&mut sim, fault, |s| (s.step_count_text(), None))
        }
        (_, Elastic::Bem) => {
            let mut options = bp6.fault_ode_options(tol)?;
            options.parallelism = rsf::Parallelism::rayon(args.threads);
            options.integrator = args.integrator.integrator;
            let kernel = args.bem_kernel(tol)?;
            let mut ode = bp6.bem_fault_ode(args.dz, variant, kernel, options, pressure)?;
            match kernel {
                WholeSpaceKernel::Fft => println!(
                    "S: the FFT product of the Toeplitz kernel, m = {}",
                    ode.kernel_report().dim
                ),
                WholeSpaceKernel::Stored(_) => println!("S: {}", ode.kernel_report()),
            }
            let fault = bp6.output_fault(ode.model(), variant);
            common.drive(&mut ode, fault, |o| {
                (o.evaluations_text(), Some(o.integrator_stats()))
            })
        }
        (_, Elastic::Fe) => {
            let model = bp6.fe_model(&args.grid(), variant)?;
            println!("{} nodes", model.vertices.len());
            let mut options = bp6.fault_ode_options(tol)?;
            options.parallelism = rsf::Parallelism::rayon(args.threads);
            options.integrator = args.integrator.integrator;
            options.kernel = args.kernel.kernel(tol.min(1e-2))?;
            let mut ode = bp6.fe_fault_ode(model, variant, options, pressure)?;
            println!("S: {}", ode.kernel_report());
            let fault = bp6.output_fault(ode.model(), variant);
            common.drive(&mut ode, fault, |o| {
                (o.evaluations_text(), Some(o.integrator_stats()))
            })
        }
    }
}

/// What every run of the program shares.
struct Common<'a> {
    args: &'a Args,
    folder: Prepared,
    setup: SeasSetup,
    fingerprint: Fingerprint,
    pressure: Arc<dyn PorePressure<2>>,
    clock: Instant,
    cpu0: f64,
}

/// A line of what a method counted.
trait Counts {
    fn evaluations_text(&self) -> String {
        String::new()
    }
    fn step_count_text(&self) -> String {
        String::new()
    }
}

impl<L: rsf::friction::FrictionLaw, S: rsf::state::StateLaw, const C: usize> Counts
    for rsf::FaultOde<2, L, S, C>
{
    fn evaluations_text(&self) -> String {
        format!("{} evaluations", self.evaluations())
    }
}

impl<const C: usize> Counts for rsf_scenes::SeasBp6Implicit<C> {}

impl Common<'_> {
    fn drive<const C: usize, R: Stepping<2, C>>(
        self,
        run: &mut R,
        fault: rsf_seas::Bp6Fault,
        counts: impl Fn(&R) -> (String, Option<rsf::fault_ode::StepperStats>),
    ) -> Result<(), AnyError>
    where
        Fault2d<C>: FaultFields2d<C>,
    {
        let args = self.args;
        println!(
            "set-up: wall {:.1} s, CPU {:.1} s",
            self.clock.elapsed().as_secs_f64(),
            cpu_seconds() - self.cpu0
        );
        // The folder's lock is held until the run ends.
        let _folder = &self.folder;
        let session = Session::start(
            args.run.session_flags(),
            args.out.join("checkpoint.bin"),
            self.fingerprint,
            args.end_years * BP6_SECONDS_PER_YEAR,
            run,
        )?;
        // The fault's fields (`--hdf5 N`): the file proves it holds the checkpoint's run
        // before any file is cut.
        let mut fields = args.fields.observer(
            ("seas_bp6", &args.out),
            FieldsRun::of(&session, self.folder.mode(), &args.run.allow_change),
            Fault2d::<C>::make,
        )?;
        let mut output = SeasBp6Output::new(&args.out, fault, self.pressure.clone(), self.setup)?
            .with_intervals(args.station_interval, args.profile_interval);
        if session.keeps_resume_log() {
            output = output.with_resume_log(args.run.checkpoint_every);
        }
        match session.resumed() {
            Some(c) => output.resume(c.state.step, c.state.time)?,
            None => output.write_initial_state(run.model(), run.state(), run.fault_tractions()),
        }
        let progress = rsf::observe::Progress::time_in(
            run.state().time,
            args.end_years * BP6_SECONDS_PER_YEAR,
            rsf::observe::TimeUnit::year(BP6_SECONDS_PER_YEAR),
            "BP6",
        );
        let mut peak = Peak::default();
        let mut observers: Vec<&mut dyn rsf::Observer<2, C>> = vec![&mut output, &mut peak];
        if let Some(f) = fields.as_mut() {
            observers.push(f.as_mut());
        }
        let summary = session.run(run, &mut observers, Some(progress))?;
        drop(observers);
        let wall = self.clock.elapsed().as_secs_f64();
        let cpu = cpu_seconds() - self.cpu0;
        let (counts, integrator) = counts(run);
        println!(
            "{} steps ({} attempts rejected){}{counts}; wall {wall:.1} s, CPU {cpu:.1} s; \
             wrote {}",
            summary.steps,
            summary.rejected_attempts,
            if counts.is_empty() { "" } else { ", " },
            args.out.display()
        );
        let json = serde_json::json!({
            "steps": summary.steps,
            "rejected_attempts": summary.rejected_attempts,
            "wall_s": wall,
            "cpu_s": cpu,
            "machine": machine(),
            "integrator": integrator.map(|st| args.integrator.summary(Some(st))),
            // For the integrators' work–precision study (docs/work-precision.md): the run's
            // (this invocation's) largest fault-wide slip rate at an accepted step and its
            // time, the steps and the evaluations of this invocation.
            "peak_slip_rate_mps": peak.rate,
            "peak_time_years": peak.time / BP6_SECONDS_PER_YEAR,
            "accepted_steps": run.state().step,
            "rate_evaluations": integrator.map(|st| {
                st.explicit_evaluations + st.stabilized_evaluations + st.implicit_evaluations
            }),
            "cpu_time_s": cpu,
        });
        std::fs::write(args.out.join("summary.json"), json.to_string())?;
        Ok(())
    }
}

/// The fault's largest slip rate at an accepted step and its time (s).
#[derive(Debug, Default)]
struct Peak {
    rate: f64,
    time: f64,
}

impl<const C: usize> rsf::Observer<2, C> for Peak {
    fn observe(&mut self, step: &rsf::StepView<'_, 2, C>) -> rsf::Result<rsf::Flow> {
        if step.report.max_slip_rate > self.rate {
            self.rate = step.report.max_slip_rate;
            self.time = step.state.time;
        }
        Ok(rsf::Flow::Continue(()))
    }
    fn reads_volume(&self) -> bool {
        false
    }
}

const _: () = assert!(DIFFUSION_CELLS.1 == rsf::pore_pressure::MAX_DIFFUSION_CELLS as f64);
// The flags' ranges (written as literals for `--help`) are the scene's, which the Python
// keywords of the same names check.
const _: () = {
    let pairs = [
        (END_YEARS, bp6_ranges::END_YEARS),
        (DZ, bp6_ranges::DZ),
        (DOMAIN_KM, bp6_ranges::DOMAIN_KM),
        (RATIO, bp6_ranges::RATIO),
        (TOLERANCE, bp6_ranges::TOLERANCE),
        (STATION_INTERVAL, bp6_ranges::STATION_INTERVAL),
        (PROFILE_INTERVAL, bp6_ranges::PROFILE_INTERVAL),
        (DIFFUSION_CELLS, bp6_ranges::DIFFUSION_CELLS),
    ];
    let mut i = 0;
    while i < pairs.len() {
        assert!(pairs[i].0 .0 == pairs[i].1 .0 && pairs[i].0 .1 == pairs[i].1 .1);
        i += 1;
    }
};

#[cfg(test)]
mod tests {
    /// `--dz`'s upper bound is the scene's `l_f/2` (the flag's range is written as a
    /// literal, for `--help`).
    #[test]
    fn the_dz_bound_is_half_the_fault() {
        assert_eq!(super::DZ.1, rsf_scenes::SeasBp6::default().l_f / 2.0);
    }
}
