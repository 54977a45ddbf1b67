//! The run of `seas_bp1`: the method the flags choose, the session, the summary.

use std::time::Instant;

use crate::guard::{AnyError, Prepared};
use crate::seas_args::run_observed;
use crate::{cpu_seconds, machine};
use rsf::method::{FixedPointOptions, SolverOptions};
use rsf::observe::{Progress, TimeUnit};
use rsf::MethodKind;
use rsf_ranks::Processes;
use rsf_scenes::{
    Bp1Absorbing, Bp1DynamicIntegrator, Bp1Scheme, RunConfig, SeasBp1, SeasBp1Run,
    SEAS_BP1_STATION_DEPTHS,
};
use rsf_seas::{SeasOutput, SeasSetup, SECONDS_PER_YEAR};

use super::args::{Args, Bp1Run};

/// The run the settings ask for on BP1's model (`run` resolved): the implicit scheme,
/// the fault ODE, or the switch between the fault ODE and the dynamic implicit scheme.
fn build_run(run: &SeasBp1Run, threads: usize) -> Result<Bp1Run, AnyError> {
    let (bp1, grid) = (run.scene(), run.grid());
    let absorbing = run.absorbing.unwrap_or(Bp1Absorbing::None);
    // The methods' settings (checked by the plan before any file was touched).
    let mut control = bp1.step_control(run.tolerance)?;
    control.state_change_cap = (run.state_change_cap > 0.0).then_some(run.state_change_cap);
    let model = bp1.model_with_far(
        &grid,
        run.inertia,
        SeasBp1Run::far(absorbing == Bp1Absorbing::All),
    )?;
    // The implicit scheme on `model`, with or without inertia, from τ₀ (s).
    let implicit = |model, inertia, tau0, fixed_point_tolerance| {
        let builder = bp1.simulation_builder(model, inertia, tau0, control)?;
        let builder = match (inertia, run.dynamic_integrator) {
            (true, Bp1DynamicIntegrator::BackwardEuler) => {
                builder.integrator(rsf::Integrator::BackwardEuler)
            }
            _ => builder,
        };
        builder
            .fixed_point(FixedPointOptions {
                tolerance: fixed_point_tolerance,
                ..FixedPointOptions::default()
            })
            .solver_options(SolverOptions {
                setup_per_time_step: run.setup_per_time_step,
                ..SolverOptions::default()
            })
            .build()
    };
    let fault_ode_options = run.fault_ode_options(threads)?;
    let fault_ode = |model| bp1.fault_ode(model, fault_ode_options);
    Ok(match run.method() {
        MethodKind::Implicit => {
            implicit(model, run.inertia, 1e-2, run.fixed_point_tolerance)?.into()
        }
        MethodKind::FaultOde => fault_ode(model)?.into(),
        MethodKind::Switching => {
            let dynamic_tau = run.dynamic_tau.unwrap_or(0.25 * run.crossing_time());
            let dynamic_model = match absorbing {
                Bp1Absorbing::Dynamic => bp1.model_with_far(&grid, true, SeasBp1Run::far(true))?,
                _ => model.clone(),
            };
            let dynamic = implicit(dynamic_model, true, 1.0, run.dynamic_fixed_point_tolerance)?;
            rsf::SwitchingRun::new(
                fault_ode(model)?,
                dynamic,
                rsf::switching::SwitchingOptions {
                    to_dynamic: run.switch_to_dynamic.unwrap_or(1e-2),
                    to_quasi_dynamic: run.switch_to_quasi_dynamic.unwrap_or(1e-3),
                    dynamic_tau,
                    restart_dt: dynamic_tau,
                },
            )?
            .into()
        }
    })
}

pub(super) fn run(
    args: Args,
    prepared: Prepared,
    processes: Option<&dyn Processes>,
) -> Result<(), AnyError> {
    // Rank 0 (or the one process) writes the files and tells.
    let root = processes.is_none_or(|p| p.rank() == 0);
    let settings = args.settings.resolved();
    let bp1 = settings.scene();
    let stations: Vec<(String, f64)> = SEAS_BP1_STATION_DEPTHS
        .iter()
        .map(|&d| (SeasBp1::station_name(d), d))
        .collect();
    // The folder was refused before anything was computed if it holds another run (of
    // this or of any other rsf program, unless --overwrite) or cannot be written.
    let step_cap = args.step_cap();
    if let (Some(cap), None) = (step_cap, args.job.run.max_steps) {
        eprintln!(
            "--every-step: at most {cap} steps (station rows within --max-output-gb {})",
            args.job.limits.max_output_gb
        );
    }
    let t_setup = Instant::now();
    let mut sim = build_run(&settings, args.threads)?;
    let model = rsf::Stepping::model(&sim);
    let (nodes, fault_nodes) = (model.num_nodes(), model.frictional_boundary.len());
    if let Some(p) = processes {
        match &mut sim {
            rsf::Run::FaultOde(ode) => ode.share_evaluations(p.group())?,
            _ => {
                return Err("MPI ranks share the Runge–Kutta run of BP1-QD (--scheme \
                            runge-kutta without --inertia)"
                    .into())
            }
        }
    }
    let setup_s = t_setup.elapsed().as_secs_f64();
    if root {
        if let Some(r) = kernel_report(&sim) {
            eprintln!("{r}");
        }
        if let Some(p) = processes {
            eprintln!("{} MPI ranks share every evaluation", p.size());
        }
        eprintln!(
            "BP1{} ({:?}): dz = {} m, domain {} km, {nodes} nodes, {fault_nodes} on the fault; \
             set-up {setup_s:.1} s",
            if settings.inertia { "-FD" } else { "-QD" },
            settings.scheme,
            settings.dz,
            settings.domain_km
        );
    }
    let sampling = settings.sampling();
    let fingerprint = settings.fingerprint();
    let setup = SeasSetup {
        modeler: args.header.modeler.clone(),
        date: args.header.date_or_today(),
        stations,
        ..bp1.seas_setup(settings.dz, settings.inertia, sampling)
    };
    // The checkpoint is checked and restored before any file is touched, then the files'
    // rows up to its step.
    let t_end = settings.end_years * SECONDS_PER_YEAR;
    let flags = args.flags();
    let session = flags.session(prepared.step_cap(step_cap), fingerprint, t_end, &mut sim)?;
    if !root {
        // The same steps as rank 0, no files (no observer here ends a run).
        session.follow(&mut sim, &mut [])?;
        return Ok(());
    }
    let mut fields =
        flags.fields_observer(&session, prepared.mode(), |w, t| w.fault_antiplane(t))?;
    let mut output = rsf_seas::SeasOutput::for_session(
        &session,
        &args.out,
        rsf::Stepping::model(&sim),
        sim.problem().friction_laws(),
        setup,
        prepared.mode(),
    )?;
    if session.resumed().is_none() {
        // The benchmark's first row: the initial state at t = 0.
        output.write_initial_state(rsf::Stepping::model(&sim), rsf::Stepping::state(&sim))?;
    }
    let t0 = rsf::Stepping::state(&sim).time;
    let progress = Progress::time_in(t0, t_end, TimeUnit::year(SECONDS_PER_YEAR), "BP1");
    let (wall, cpu) = (Instant::now(), cpu_seconds());
    let files = vec![&mut output as &mut dyn rsf::Observer<2, 1>];
    let summary = run_observed(session, &mut sim, files, &mut fields, progress)?;
    let facts = Facts {
        nodes,
        fault_nodes,
        setup_s,
        wall_s: wall.elapsed().as_secs_f64(),
        cpu_s: cpu_seconds() - cpu,
    };
    let done = report(&args, &sim, &output, &summary, facts)?;
    crate::seas_overview(&args.out, "devol.dat", "depth (km)", done)?;
    Ok(())
}

/// The model's size and the set-up and this invocation's run times (s).
#[derive(Clone, Copy)]
struct Facts {
    nodes: usize,
    fault_nodes: usize,
    setup_s: f64,
    wall_s: f64,
    cpu_s: f64,
}

/// The kernel of the fault ODE (the Runge–Kutta runs; `None` for the implicit scheme).
fn kernel_report(sim: &Bp1Run) -> Option<&rsf::fault_ode::KernelReport> {
    match sim {
        rsf::Run::Implicit(_) => None,
        rsf::Run::FaultOde(s) => Some(s.kernel_report()),
        rsf::Run::Switching(s) => Some(s.quasi_dynamic().kernel_report()),
    }
}

/// Writes `summary.json` and prints the run's line; returns the number of finished events.
fn report(
    args: &Args,
    sim: &Bp1Run,
    output: &SeasOutput<rsf::friction::AsinhLaw>,
    summary: &rsf::RunSummary,
    facts: Facts,
) -> Result<usize, AnyError> {
    let events = output.events();
    let done: Vec<_> = events.iter().filter(|e| e.t_end.is_finite()).collect();
    let intervals: Vec<f64> = done
        .windows(2)
        .map(|w| (w[1].t_start - w[0].t_start) / SECONDS_PER_YEAR)
        .collect();
    let later: Vec<f64> = intervals.iter().skip(3).copied().collect();
    let mean_recurrence = if later.is_empty() {
        f64::NAN
    } else {
        later.iter().sum::<f64>() / later.len() as f64
    };
    let (tau_min, tau_max, _) = output.time_steps();
    let runge_kutta = args.settings.scheme == Bp1Scheme::RungeKutta;
    let json = serde_json::json!({
        "problem": if args.settings.inertia { "BP1-FD" } else { "BP1-QD" },
        // Every setting as the run resolved it (rsf_scenes::SeasBp1Run).
        "settings": args.settings.summary(),
        "event_start_years": events.iter().map(|e| e.t_start / SECONDS_PER_YEAR).collect::<Vec<_>>(),
        "nodes": facts.nodes,
        "fault_nodes": facts.fault_nodes,
        // Steps of the whole run (across resumes); the counts and times below are this
        // invocation's.
        "accepted_steps": rsf::Stepping::state(sim).step,
        "steps_this_invocation": summary.steps,
        "rejected_attempts": summary.rejected_attempts,
        "accepted_by_controller": match sim {
            rsf::Run::Implicit(s) => s.state().controller.as_ref().map(|c| c.accepted()),
            rsf::Run::FaultOde(_) | rsf::Run::Switching(_) => None,
        },
        "integrator": runge_kutta.then(|| crate::IntegratorArgs { integrator: args.settings.integrator }.summary(match sim {
            rsf::Run::Implicit(_) => None,
            rsf::Run::FaultOde(s) => Some(s.integrator_stats()),
            rsf::Run::Switching(s) => Some(s.quasi_dynamic().integrator_stats()),
        })),
        "rate_evaluations": match sim {
            rsf::Run::Implicit(_) => None,
            rsf::Run::FaultOde(s) => Some(s.evaluations()),
            rsf::Run::Switching(s) => Some(s.quasi_dynamic().evaluations()),
        },
        "kernel": kernel_report(sim).map(|r| serde_json::json!({
            "kernel": r.kernel.to_string(),
            "dim": r.dim,
            "relative_error_frobenius": r.relative_error,
            "stored_entries": r.stored_entries,
            "compression_ratio": r.compression_ratio(),
            "dense_blocks": r.dense_blocks,
            "low_rank_blocks": r.low_rank_blocks,
            "max_rank": r.max_rank,
            "setup_s": r.setup_seconds,
        })),
        "threads": args.threads,
        // On MPI ranks: the processes and what they exchanged (counted by the code).
        "ranks": match sim {
            rsf::Run::FaultOde(s) => s.exchanges(),
            _ => None,
        }.map(|e| serde_json::json!({
            "ranks": e.ranks,
            "all_gathers": e.all_gathers,
            "values_per_all_gather": e.values as f64 / e.all_gathers.max(1) as f64,
            "bytes_received_per_rank": 8 * e.values,
        })),
        "switching": switching_json(sim),
        "tau_min_s": tau_min,
        "tau_max_s": tau_max,
        "fixed_point_iterations_mean": summary.fpi_mean,
        "setup_s": facts.setup_s,
        "wall_time_s": facts.wall_s,
        "cpu_time_s": facts.cpu_s,
        "machine": machine(),
        "events": events.len(),
        "first_event_years": events.first().map(|e| e.t_start / SECONDS_PER_YEAR),
        "recurrence_intervals_years": intervals,
        "mean_recurrence_from_4th_interval_years": mean_recurrence,
        "peak_slip_rate_mps": done.iter().map(|e| e.peak_slip_rate).fold(0.0, f64::max),
        "hypocentre_depths_m": done.iter().map(|e| e.hypocentre_depth).collect::<Vec<_>>(),
        "surface_slip_m": done.iter().map(|e| e.surface_slip).collect::<Vec<_>>(),
        "durations_s": done.iter().map(|e| e.t_end - e.t_start).collect::<Vec<_>>(),
    });
    let path = args.out.join("summary.json");
    rsf::checkpoint::write_atomically(&path, serde_json::to_string_pretty(&json)?.as_bytes())?;
    eprintln!(
        "{} steps ({} rejected), {} events, mean recurrence (4th interval on) {mean_recurrence:.1} yr, \
         wall {:.1} s, cpu {:.1} s",
        summary.steps,
        summary.rejected_attempts,
        events.len(),
        facts.wall_s,
        facts.cpu_s
    );
    Ok(done.len())
}

/// The dynamic phases of a switching run (`None` for the other methods).
fn switching_json(sim: &Bp1Run) -> Option<serde_json::Value> {
    let rsf::Run::Switching(s) = sim else {
        return None;
    };
    let st = s.stats();
    Some(serde_json::json!({
        "dynamic_phases": st.dynamic_phases,
        "dynamic_steps": st.dynamic_steps,
        "quasi_dynamic_steps": st.quasi_dynamic_steps,
        "dynamic_time_s": st.dynamic_time,
        "dynamic_tau_s": s.dynamic().tau(),
    }))
}
