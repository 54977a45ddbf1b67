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
//! Writes to `--out`: `events.csv` (start time, peak slip rate, hypocentre x_d) and
//! `stations.csv` (at the BP3 stations' down-dip distances, every `--every` accepted
//! steps: time, slip, log10 V, shear and normal stress, log10 θ), and prints the events.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use rsf::observe::SECONDS_PER_YEAR;
use rsf::{Flow, Observer, StepView};
use rsf_examples::{cpu_seconds, machine};
use rsf_scenes::{SeasBp3, SeasBp3Grid, SEAS_BP3_STATION_DISTANCES};

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
    /// Half-width L of the box across the fault (km); its depth is L sin ψ.
    #[arg(long, default_value_t = 100.0)]
    domain_km: f64,
    /// Growth of the elements away from the fault and below W_f.
    #[arg(long, default_value_t = 1.1)]
    ratio: f64,
    /// Tolerance of the fault ODE.
    #[arg(long, default_value_t = 1e-7)]
    tolerance: f64,
    /// A station row every this many accepted steps.
    #[arg(long, default_value_t = 10)]
    every: usize,
}

/// Per accepted step: the event catalogue and the station rows.
struct Output {
    bp3: SeasBp3,
    stations: Vec<usize>,
    u0: Vec<f64>,
    every: usize,
    steps: usize,
    rows: String,
    /// (start time, peak slip rate, hypocentre x_d); the last is open while slipping.
    events: Vec<(f64, f64, f64)>,
    slipping: bool,
}

impl Observer<2> for Output {
    fn observe(&mut self, s: &StepView<'_, 2, 2>) -> rsf::Result<Flow> {
        let fb = &s.model.frictional_boundary;
        let (k_max, v_max) = (0..fb.len())
            .map(|k| (k, s.slip_rate(k)))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        let t = s.state.time;
        if v_max >= 1e-3 {
            if !self.slipping {
                let x = s.model.vertices[fb.nodes[k_max]];
                self.events.push((t, v_max, self.bp3.x_d(&x)));
            }
            let e = self.events.last_mut().expect("an open event");
            e.1 = e.1.max(v_max);
        }
        self.slipping = v_max >= 1e-3;
        if self.steps % self.every == 0 {
            write!(self.rows, "{t:.13e}").expect("string");
            for &k in &self.stations {
                let p = fb.nodes[k];
                let slip = s.state.kinematics.u[2 * p] - self.u0[2 * p];
                let v = s.slip_rate(k);
                let alpha = s.state.alpha[k];
                write!(
                    self.rows,
                    ",{slip:.6e},{:.6e},{:.6e},{:.6e},{:.6e}",
                    v.log10(),
                    s.shear_traction(k) / 1e6,
                    s.normal_traction(k).unwrap_or(f64::NAN) / 1e6,
                    alpha / std::f64::consts::LN_10
                )
                .expect("string");
            }
            self.rows.push('\n');
        }
        self.steps += 1;
        Ok(Flow::Continue(()))
    }
}

fn main() -> ExitCode {
    rsf_examples::main_with(|| run(Args::parse()))
}

fn run(args: Args) -> Result<(), Box<dyn std::error::Error>> {
    if !(args.dip > 0.0 && args.dip < 90.0) {
        return Err(format!("--dip {}: must be in (0, 90) degrees", args.dip).into());
    }
    if args.every == 0 {
        return Err("--every must be at least 1".into());
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
    let stations = SEAS_BP3_STATION_DISTANCES
        .iter()
        .map(|&xd| {
            (0..fb.len())
                .min_by(|&a, &b| {
                    let d = |k: usize| (bp3.x_d(&model.vertices[fb.nodes[k]]) - xd).abs();
                    d(a).total_cmp(&d(b))
                })
                .expect("frictional nodes")
        })
        .collect();
    let mut options = bp3.params.fault_ode_options(args.tolerance)?;
    options.runge_kutta.dt_min = 1e-8;
    let u0 = model.initial_displacement.clone();
    let mut ode = bp3.fault_ode(model, options)?;
    let mut output = Output {
        bp3: bp3.clone(),
        stations,
        u0,
        every: args.every,
        steps: 0,
        rows: String::from("t"),
        events: Vec::new(),
        slipping: false,
    };
    for xd in SEAS_BP3_STATION_DISTANCES {
        write!(
            output.rows,
            ",slip_{xd},log10V_{xd},shear_MPa_{xd},normal_MPa_{xd},log10theta_{xd}"
        )?;
    }
    output.rows.push('\n');
    let summary = ode.run_until(
        rsf::Until::Time(args.end_years * SECONDS_PER_YEAR),
        &mut [&mut output],
    )?;
    let wall = clock.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - cpu0;
    std::fs::write(args.out.join("stations.csv"), &output.rows)?;
    let mut events = String::from("t_start_yr,peak_slip_rate_m_per_s,hypocentre_x_d_m\n");
    for e in &output.events {
        writeln!(
            events,
            "{:.6},{:.6e},{:.1}",
            e.0 / SECONDS_PER_YEAR,
            e.1,
            e.2
        )?;
        println!(
            "event at {:.3} yr: peak slip rate {:.3e} m/s, hypocentre x_d = {:.1} km",
            e.0 / SECONDS_PER_YEAR,
            e.1,
            e.2 / 1e3
        );
    }
    std::fs::write(args.out.join("events.csv"), events)?;
    println!(
        "{} steps, {} evaluations; wall {wall:.1} s, CPU {cpu:.1} s; wrote {}",
        summary.steps,
        ode.evaluations(),
        args.out.display()
    );
    Ok(())
}
