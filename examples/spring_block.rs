//! The classic one-degree-of-freedom spring–block slider, assembled from the same parts as
//! the paper's slider but without a mesh.
//!
//! A block (dof 0, mass `m` or none) is pulled through a spring of stiffness `k` by a load
//! point (dof 1, fixed, prescribed velocity `V_load`); rate-and-state friction (Dieterich–Ruina
//! with the aging law) acts on the block over a contact area of 1 m². Steady sliding at
//! `V_load` is linearly unstable for `k < k_c = σ̄_n (b − a)/L` (Ruina 1983, quasistatic
//! limit): a small perturbation grows into stick–slip below `k_c` and decays above it.
//!
//! The example sweeps `k/k_c`, prints a table (maximum slip rate, growth of the slip-rate
//! oscillation per period, classification), locates the transition by bisection and writes
//! `out/spring_block/{sweep.csv, bisection.csv, timeseries_k*.csv}`.
//!
//! ```text
//! cargo run --release --example spring_block
//! cargo run --release --example spring_block -- --integrator newmark --mass 1
//! ```
//! Flags: `--integrator quasistatic|newmark|backward-euler` (default quasistatic),
//! `--mass KG` (default 1, dynamic integrators only), `--eta PA_S_PER_M` (radiation damping
//! of the quasistatic integrator, default 5e6), `--steps-per-l N` (τ = (L/V_load)/N,
//! default 100), `--periods N` (length of each run in oscillation periods, default 40),
//! `--out DIR` (default `out/spring_block`), `--overwrite` (a folder holding another run's
//! files is refused, and left untouched, otherwise; docs/reliability.md),
//! `--max-output-gb GB` (default 10: a sweep whose runs would hold more is refused before
//! it starts). The sweep takes
//! seconds and keeps its runs in memory, so it has no `--resume`.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use clap::Parser;
use rsf::faer::sparse::{SparseColMat, SymbolicSparseColMat};
use rsf::fem::SparseMatrix;
use rsf::friction::{DieterichRuina, FrictionLaw, RateStateParams};
use rsf::method::FixedPointOptions;
use rsf::model::{DirichletVelocity, FrictionalBoundary};
use rsf::state::Aging;
use rsf::time::{Quasistatic, VelocityIntegrator};
use rsf::{Integrator, Model, Simulation, SimulationBuilder, SolverKind, TimeFunction};
use rsf_programs::cli::positive_number;
use rsf_programs::guard::{in_range, refuse, AnyError, Folder, Limits, Plan, Prepared, Program};

/// Physical parameters of the spring–block system (SI units, contact area 1 m²).
#[derive(Debug, Clone, Copy)]
struct Block {
    /// Rate-state parameters (σ̄_n in Pa).
    friction: RateStateParams,
    /// Load-point velocity (m/s).
    v_load: f64,
    /// Block mass (kg); `None` for the quasistatic integrator.
    mass: Option<f64>,
    /// Radiation damping η (Pa·s/m) of the quasistatic integrator.
    eta: f64,
    /// Initial perturbation of the state, `α_0 = ln(L/V_load) + dalpha`.
    dalpha: f64,
}

impl Block {
    /// `k_c = σ̄_n (b − a)/L` (N/m for 1 m²).
    fn k_crit(&self) -> f64 {
        let p = &self.friction;
        p.sigma_n * (p.b - p.a) / p.l
    }
    /// Period of the linearised oscillation of steady sliding at `k = k_c` (quasistatic):
    /// `ω = (V_load/L) √((b − a)/a)`.
    fn period_at_kc(&self) -> f64 {
        let p = &self.friction;
        2.0 * std::f64::consts::PI * p.l / self.v_load / ((p.b - p.a) / p.a).sqrt()
    }
}

/// A 2×2 matrix with the full pattern (explicit zeros kept, so all matrices share it).
fn mat2(d00: f64, d01: f64, d11: f64) -> SparseMatrix {
    let sym = SymbolicSparseColMat::new_checked(2, 2, vec![0, 2, 4], None, vec![0, 1, 0, 1]);
    SparseColMat::new(sym, vec![d00, d01, d01, d11])
}

/// Builds the simulation for stiffness `k` (N/m) with integrator `I`, started at steady
/// sliding (spring force = steady-state friction + radiation damping at `V_load`,
/// `v = V_load`) with the state perturbed by `dalpha`.
fn build<I: VelocityIntegrator>(
    blk: &Block,
    k: f64,
    integrator: I,
    tau: f64,
) -> Result<Simulation<1, DieterichRuina, Aging, I>, AnyError> {
    let p = blk.friction;
    let stiffness = mat2(k, -k, k);
    // The load point (dof 1) is fixed, so its mass entry is irrelevant: unit diagonal.
    let mass = blk.mass.map(|m| mat2(m, 0.0, 1.0));
    let energy_norm = match blk.mass {
        Some(m) => mat2(k + m, -k, k + 1.0),
        None => mat2(k, -k, k),
    };
    let eta = integrator.radiation_damping();
    let f_ss = p.sigma_n * p.steady_state_friction(blk.v_load) + eta * blk.v_load;
    let model = Model::<1> {
        vertices: vec![[0.0], [1.0]],
        mass,
        stiffness,
        energy_norm,
        load: vec![0.0; 2],
        fixed: vec![false, true],
        dirichlet: DirichletVelocity {
            dofs: vec![1],
            factors: vec![blk.v_load],
            history: TimeFunction::Constant(1.0),
        },
        prolongations: Vec::new(),
        frictional_boundary: FrictionalBoundary::new(&[0], &[1.0])?,
        initial_displacement: vec![0.0, f_ss / k],
        cells: Vec::new(),
        frames: Default::default(),
        absorbing: None,
        internal_fault: None,
        columns: None,
    };
    let alpha_ss = (p.l / blk.v_load).ln();
    let sim = SimulationBuilder::new(model)
        .friction(DieterichRuina::new(p)?)
        .state_law(Aging::new(p.l)?)
        .initial_state(alpha_ss + blk.dalpha)
        .integrator(integrator)
        // Start at v = V_load (the builder starts free dofs at rest otherwise), a = 0.
        .initial_velocity_at(|_| [blk.v_load])
        .time_step(tau)
        .solver(SolverKind::Direct)
        .fixed_point(FixedPointOptions {
            max_iterations: 1000,
            ..FixedPointOptions::default()
        })
        .build()?;
    Ok(sim)
}

/// One sample of a run.
#[derive(Debug, Clone, Copy)]
struct Sample {
    t: f64,
    u_block: f64,
    u_load: f64,
    v: f64,
    alpha: f64,
}

/// Outcome of one run.
#[derive(Debug, Clone)]
struct Outcome {
    max_v: f64,
    /// Geometric mean growth of the peaks of `ln(V/V_load)` per oscillation (> 1: unstable).
    growth_per_period: f64,
    peaks: usize,
    fpi_mean: f64,
    fpi_max: usize,
    /// Time and error of a fixed point failure after the onset of stick–slip.
    aborted: Option<(f64, String)>,
    series: Vec<Sample>,
}

impl Outcome {
    fn unstable(&self) -> bool {
        self.growth_per_period > 1.0
    }
    fn class(&self, v_load: f64) -> &'static str {
        if self.max_v > STICK_SLIP * v_load {
            "stick-slip"
        } else if self.unstable() {
            "growing (-> stick-slip)"
        } else {
            "steady sliding"
        }
    }
}

/// Slip rates above `STICK_SLIP · V_load` count as stick–slip.
const STICK_SLIP: f64 = 100.0;

/// Smallest peak of `ln(V/V_load)` taken as signal (the kick gives about 1e-2).
const PEAK_FLOOR: f64 = 1e-8;

/// Runs `steps` steps and measures the growth of the slip-rate oscillation from the peaks
/// of `x = ln(V/V_load)` (the first sample, the response to the initial kick, is skipped).
fn run<I: VelocityIntegrator>(
    blk: &Block,
    k: f64,
    integrator: I,
    tau: f64,
    steps: usize,
    keep: bool,
) -> Result<Outcome, AnyError> {
    let mut sim = build(blk, k, integrator, tau)?;
    let mut xs = Vec::with_capacity(steps);
    let mut series = Vec::new();
    let (mut max_v, mut fpi, mut fpi_max) = (0.0f64, 0usize, 0usize);
    let mut aborted = None;
    for _ in 0..steps {
        let r = match sim.step() {
            Ok(r) => r,
            // Once the run is in stick–slip, an event with τV/L ≫ 1 can exhaust the fixed
            // point budget (docs/spring-block.md); the classification is already decided.
            Err(e) if max_v > STICK_SLIP * blk.v_load => {
                aborted = Some((sim.time(), e.to_string()));
                break;
            }
            Err(e) => return Err(e.into()),
        };
        let kin = sim.kinematics();
        let v = kin.v[0];
        max_v = max_v.max(r.max_slip_rate);
        fpi += r.fixed_point_iterations;
        fpi_max = fpi_max.max(r.fixed_point_iterations);
        xs.push((v.abs().max(1e-300) / blk.v_load).ln());
        if keep {
            series.push(Sample {
                t: r.time,
                u_block: kin.u[0],
                u_load: kin.u[1],
                v,
                alpha: sim.alpha()[0],
            });
        }
    }
    // Peaks below PEAK_FLOOR are round-off once a stable oscillation has died out.
    let peaks: Vec<f64> = (2..xs.len().saturating_sub(1))
        .filter(|&n| xs[n] > xs[n - 1] && xs[n] >= xs[n + 1] && xs[n] > PEAK_FLOOR)
        .map(|n| xs[n])
        .collect();
    let growth_per_period = match peaks.len() {
        0 | 1 => 0.0,
        n => (peaks[n - 1] / peaks[0]).powf(1.0 / (n - 1) as f64),
    };
    Ok(Outcome {
        max_v,
        growth_per_period,
        peaks: peaks.len(),
        fpi_mean: fpi as f64 / xs.len().max(1) as f64,
        fpi_max,
        aborted,
        series,
    })
}

fn write_series(path: &std::path::Path, blk: &Block, k: f64, s: &[Sample]) -> Result<(), AnyError> {
    let law = DieterichRuina::new(blk.friction)?;
    let mut out = String::from(
        "t_s,block_u_m,load_point_u_m,slip_rate_mps,alpha,spring_force_n,friction_coefficient\n",
    );
    for x in s {
        writeln!(
            out,
            "{:.9e},{:.12e},{:.12e},{:.9e},{:.9e},{:.9e},{:.9e}",
            x.t,
            x.u_block,
            x.u_load,
            x.v,
            x.alpha,
            k * (x.u_load - x.u_block),
            law.friction_coefficient(x.v.abs(), x.alpha)
        )?;
    }
    rsf::checkpoint::write_atomically(path, out.as_bytes())?;
    Ok(())
}

/// Spring–block slider: stick–slip below k_c, steady sliding above.
#[derive(Parser)]
#[command(version)]
struct Cli {
    /// Velocity integrator.
    #[arg(long, value_enum, default_value = "quasistatic")]
    integrator: Integrator,
    /// Block mass (kg; dynamic integrators only).
    #[arg(long, default_value_t = 1.0, value_name = "KG", value_parser = positive_number)]
    mass: f64,
    /// Radiation damping η of the quasistatic integrator (Pa·s/m).
    #[arg(long, default_value_t = 5e6, value_name = "PA_S_PER_M")]
    eta: f64,
    /// Steps per L/V_load (τ = (L/V_load)/N).
    #[arg(long, default_value_t = 100.0, value_name = "N")]
    steps_per_l: f64,
    /// Length of each run in oscillation periods.
    #[arg(long, default_value_t = 40.0, value_name = "N")]
    periods: f64,
    /// Output folder.
    #[arg(long, default_value = "out/spring_block")]
    out: PathBuf,
    /// Replace the files of an earlier run in the output folder.
    #[arg(long)]
    overwrite: bool,
    /// `--max-output-gb`: a sweep whose runs would hold more than it (the slip-rate
    /// history of a run in memory, the kept runs' time series on disk) is refused.
    #[command(flatten)]
    limits: Limits,
}

/// The friction of the sweep (σ̄_n in Pa; contact area 1 m²).
const FRICTION: RateStateParams = RateStateParams {
    mu0: 0.6,
    a: 0.010,
    b: 0.015,
    v0: 1e-6,
    l: 1e-5,
    sigma_n: 1e6,
};

/// The load-point velocity (m/s).
const V_LOAD: f64 = 1e-6;

impl Cli {
    /// Steps of each run: `--periods` periods of the oscillation at k_c, τ = (L/V_load) /
    /// `--steps-per-l`.
    fn steps(&self) -> Result<f64, AnyError> {
        let steps_per_l = positive("--steps-per-l", self.steps_per_l)?;
        let periods = positive("--periods", self.periods)?;
        let probe = Block {
            friction: FRICTION,
            v_load: V_LOAD,
            mass: None,
            eta: 0.0,
            dalpha: 0.0,
        };
        let tau = FRICTION.l / V_LOAD / steps_per_l;
        Ok((periods * probe.period_at_kc() / tau).ceil())
    }
}

impl Program for Cli {
    rsf_programs::name_and_limits!("spring_block");

    fn plan(&self) -> Result<Plan, AnyError> {
        let steps = self.steps()?;
        in_range("--eta", self.eta, (0.0, 1e15), "Pa·s/m")?;
        let bytes = steps * STEP_BYTES;
        let what = format!("{steps:.3e} steps per run");
        Ok(Plan::new()
            // A run's history in memory, the kept runs' series on disk.
            .memory(bytes, "--steps-per-l, --periods", what.clone())
            .output(bytes, "--steps-per-l, --periods", what)
            .folder(Folder::new("--out", &self.out, &OUTPUTS).overwrite(self.overwrite)))
    }
}

/// Bytes per step of a run, rounded up: its slip-rate history in memory and, for the
/// two kept runs, a time series row (≈ 60 bytes) and its text before the atomic write.
const STEP_BYTES: f64 = 150.0;

/// `x` finite and > 0, else an error naming the flag `name`.
fn positive(name: &str, x: f64) -> Result<f64, AnyError> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(refuse(
            name,
            rsf_programs::guard::number(x),
            "must be positive and finite",
        ))
    }
}

/// The files a run writes into its folder.
const OUTPUTS: [&str; 4] = [
    "sweep.csv",
    "bisection.csv",
    "timeseries_k0.80.csv",
    "timeseries_k1.20.csv",
];

fn main() -> std::process::ExitCode {
    rsf_programs::guard::main(run_cli)
}

fn run_cli(cli: Cli, _prepared: Prepared) -> Result<(), AnyError> {
    // The steps and the folder: checked by the guard before anything was computed.
    let steps = cli.steps()? as usize;
    let steps_per_l = cli.steps_per_l;
    let (mass, out_dir) = (cli.mass, cli.out);
    let integ_name = cli.integrator.name();
    let integ = match cli.integrator {
        Integrator::Quasistatic(_) => {
            Integrator::Quasistatic(Quasistatic::with_radiation_damping(cli.eta)?)
        }
        other => other,
    };
    let blk = Block {
        friction: FRICTION,
        v_load: V_LOAD,
        mass: match integ {
            Integrator::Quasistatic(_) => None,
            _ => Some(mass),
        },
        eta: integ.radiation_damping(),
        dalpha: -0.01,
    };
    let p = blk.friction;
    let kc = blk.k_crit();
    let t_l = p.l / blk.v_load;
    let tau = t_l / steps_per_l;
    let period = blk.period_at_kc();

    // Expected shifts of the discrete threshold (docs/spring-block.md):
    // backward Euler ~ τ V_load / L, radiation damping η V_load / (σ̄_n (b − a)),
    // inertia + m V_load² / (σ̄_n a L).
    let shift_be = tau * blk.v_load / p.l;
    let shift_eta = blk.eta * blk.v_load / (p.sigma_n * (p.b - p.a));
    let shift_m = blk.mass.unwrap_or(0.0) * blk.v_load.powi(2) / (p.sigma_n * p.a * p.l);
    println!("spring–block slider, {integ_name} integrator");
    println!(
        "  σ̄_n = {:.3e} Pa, a = {}, b = {}, L = {:.1e} m, V0 = {:.1e} m/s, μ0 = {}",
        p.sigma_n, p.a, p.b, p.l, p.v0, p.mu0
    );
    println!(
        "  V_load = {:.1e} m/s, mass = {}, η = {:.2e} Pa·s/m, α0 = ln(L/V_load) {:+}",
        blk.v_load,
        blk.mass.map_or("none".into(), |m| format!("{m} kg")),
        blk.eta,
        blk.dalpha
    );
    println!(
        "  k_c = σ̄_n(b−a)/L = {kc:.4e} N/m, period at k_c = {period:.2} s, τ = {tau:.3e} s, \
         {steps} steps per run"
    );
    println!(
        "  predicted threshold k*/k_c ≈ 1 − {shift_be:.1e} (backward Euler) − {shift_eta:.1e} (η) \
         + {shift_m:.1e} (inertia)\n"
    );

    let start = Instant::now();
    let ratios = [
        0.5, 0.7, 0.8, 0.9, 0.95, 0.98, 1.02, 1.05, 1.1, 1.2, 1.5, 2.0,
    ];
    let mut sweep = String::from(
        "k_over_kc,max_slip_rate_mps,max_slip_rate_over_vload,growth_per_period,peaks,fpi_mean,fpi_max,class\n",
    );
    println!(
        "{:>7} {:>14} {:>10} {:>10} {:>6} {:>9}  classification",
        "k/k_c", "max V (m/s)", "max V/V_L", "growth/T", "peaks", "FPI mean"
    );
    for &r in &ratios {
        let keep = r == 0.8 || r == 1.2;
        let o = run(&blk, r * kc, integ, tau, steps, keep)?;
        println!(
            "{:>7.3} {:>14.4e} {:>10.3e} {:>10.4} {:>6} {:>9.2}  {}",
            r,
            o.max_v,
            o.max_v / blk.v_load,
            o.growth_per_period,
            o.peaks,
            o.fpi_mean,
            o.class(blk.v_load)
        );
        if let Some((t, e)) = &o.aborted {
            let e: String = e.chars().take(60).collect();
            println!("        (stopped at t = {t:.1} s in stick–slip: {e}…)");
        }
        writeln!(
            sweep,
            "{r},{:.6e},{:.6e},{:.6},{},{:.4},{},{}",
            o.max_v,
            o.max_v / blk.v_load,
            o.growth_per_period,
            o.peaks,
            o.fpi_mean,
            o.fpi_max,
            o.class(blk.v_load)
        )?;
        if keep {
            let path = out_dir.join(format!("timeseries_k{r:.2}.csv"));
            write_series(&path, &blk, r * kc, &o.series)?;
        }
    }
    rsf::checkpoint::write_atomically(&out_dir.join("sweep.csv"), sweep.as_bytes())?;

    // Bisection on k/k_c for the change of sign of the growth of the oscillation.
    let (mut lo, mut hi) = (0.5, 1.5);
    let mut bis = String::from("k_over_kc,growth_per_period,unstable\n");
    for _ in 0..10 {
        let mid = 0.5 * (lo + hi);
        let o = run(&blk, mid * kc, integ, tau, steps, false)?;
        if let Some((t, _)) = &o.aborted {
            println!("bisection k/k_c = {mid:.4}: stopped at t = {t:.1} s in stick–slip");
        }
        writeln!(bis, "{mid},{:.8},{}", o.growth_per_period, o.unstable())?;
        if o.unstable() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    rsf::checkpoint::write_atomically(&out_dir.join("bisection.csv"), bis.as_bytes())?;
    let k_star = 0.5 * (lo + hi);
    println!(
        "\ntransition (bisection, 10 halvings of [0.5, 1.5]): k*/k_c = {k_star:.4} ± {:.4} \
         ({:+.2}% from k_c)",
        0.5 * (hi - lo),
        100.0 * (k_star - 1.0)
    );
    println!(
        "wall time {:.2} s; wrote {}/{{sweep,bisection,timeseries_k0.80,timeseries_k1.20}}.csv",
        start.elapsed().as_secs_f64(),
        out_dir.display()
    );
    Ok(())
}
