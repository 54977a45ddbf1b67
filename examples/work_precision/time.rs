//! The time-step studies: error against τ for each integrator and solver, and adaptive
//! steps against uniform N.

use std::fmt::Write as _;

use rsf::{Integrator, SolverKind};
use rsf_scenes::SliderScene;

use crate::common::{base, log, window, Ctx, Res};
use crate::errors::{errors, opt, row, traced, Errors, ROW_HEAD};
use crate::plot::plot_panels;
use crate::trace::{timed_trace, trace, Trace};

/// CPU seconds the repeats of one configuration of the adaptive study add up to at least,
/// over all its passes (see [`timed_trace`]).
const MIN_CPU_S: f64 = 1.5;
/// Passes over all configurations of the adaptive study (see `adaptive_study`).
const PASSES: usize = 5;

pub(crate) fn time_study(c: &Ctx) -> Res<()> {
    let mut ns: Vec<usize> = vec![1_000, 2_000, 5_000, 10_000, 20_000, 50_000, 100_000];
    let mut ref_n = c.ref_n;
    if c.big {
        ns.extend([200_000, 500_000, 1_000_000]);
        ref_n = ref_n.max(2_000_000);
    }
    let mut rs = base(c.level, ref_n);
    rs.solver = SolverKind::Direct;
    let (tmin, tmax) = window(&rs);
    log(&format!("time study: reference Newmark direct N = {ref_n}"));
    let reference = trace(&rs, tmin, tmax, true)?;
    log(&format!(
        "  reference: {:.1} s, t_slip = {}",
        reference.seconds(),
        opt(reference.first_slip(rs.ramp_fraction * rs.end_time_s))
    ));
    let mut csv = format!("integrator,solver,level,N,tau_s,{ROW_HEAD}\n");
    let _ = writeln!(
        csv,
        "newmark,direct-reference,{},{ref_n},{:.6e},{}",
        c.level,
        rs.tau(),
        row(&reference, &Errors::default())
    );
    let mut points = Vec::new();
    for integrator in [Integrator::Newmark, Integrator::BackwardEuler] {
        if !c.integrators.contains(&integrator) {
            continue;
        }
        for solver in [SolverKind::Tnnmg, SolverKind::Direct] {
            if !c.solvers.contains(&solver) {
                continue;
            }
            for &n in &ns {
                let mut s = base(c.level, n);
                s.integrator = integrator;
                s.solver = solver;
                s.state_integrator = c.state_integrator;
                let Some((tr, e)) = traced(&s, (tmin, tmax), &reference, format_args!("N = {n}"))
                else {
                    continue;
                };
                log(&format!(
                    "  {} {} N = {n}: {:.2} s, {}",
                    integrator.name(),
                    solver.name(),
                    tr.seconds(),
                    e.describe(&tr)
                ));
                let _ = writeln!(
                    csv,
                    "{},{},{},{n},{:.6e},{}",
                    integrator.name(),
                    solver.name(),
                    c.level,
                    s.tau(),
                    row(&tr, &e)
                );
                std::fs::write(c.out.join("time_step.csv"), &csv)?;
                points.push(e.point(format!("{} {}", integrator.name(), solver.name()), &tr));
            }
        }
    }
    plot_panels(
        &c.figures.join("work_precision_time_step.png"),
        &format!(
            "Time step: N = {}…{}, j = {}, error vs N = {ref_n} Newmark",
            ns[0],
            ns[ns.len() - 1],
            c.level
        ),
        &points,
        None,
    )?;
    Ok(())
}

/// Adaptive steps (docs/math.md §9) against uniform N, both Newmark with the direct
/// solver, measured in one process against the time study's reference; prints the cost
/// ratio at 1 % and 0.1 % error in both (a) and (b).
pub(crate) fn adaptive_study(c: &Ctx) -> Res<()> {
    let mut rs = base(c.level, c.ref_n);
    rs.solver = SolverKind::Direct;
    let (tmin, tmax) = window(&rs);
    log(&format!(
        "adaptive study: reference Newmark direct N = {}",
        c.ref_n
    ));
    let reference = trace(&rs, tmin, tmax, true)?;
    let mut csv = format!("method,level,N_or_tol,tau0_s,rejected,repeats,{ROW_HEAD}\n");
    let _ = writeln!(
        csv,
        "reference,{},{},{:.6e},0,1,{}",
        c.level,
        c.ref_n,
        rs.tau(),
        row(&reference, &Errors::default())
    );
    // Every configuration: (method, N or tolerance, scene).
    let mut configs: Vec<(&'static str, String, SliderScene)> = Vec::new();
    for &n in &c.uniform {
        let mut s = base(c.level, n);
        s.solver = SolverKind::Direct;
        s.state_integrator = c.state_integrator;
        configs.push(("uniform", n.to_string(), s));
    }
    for &tol in &c.tolerances {
        let mut s = base(c.level, 10_000);
        s.solver = SolverKind::Direct;
        s.time_step = rsf_scenes::TimeStep::Adaptive(rsf_scenes::AdaptiveTimeStep::new(tol));
        s.state_integrator = c.state_integrator;
        configs.push(("adaptive", format!("{tol:e}"), s));
    }
    // Pass 1 records every trajectory and its errors; the other passes only time the runs
    // again (they are deterministic). Interleaving the repeats of all configurations over
    // several passes, minutes apart, keeps a burst of load from other jobs out of the
    // fastest repeat of any one configuration.
    let mut runs: Vec<Option<(Trace, usize, Errors)>> = Vec::new();
    for pass in 1..=PASSES {
        log(&format!("  pass {pass} of {PASSES}"));
        for (k, (method, key, s)) in configs.iter().enumerate() {
            if pass > 1 && runs[k].is_none() {
                continue;
            }
            let (tr, repeats) = match timed_trace(s, tmin, tmax, true, MIN_CPU_S / PASSES as f64) {
                Ok(t) => t,
                Err(e) => {
                    log(&format!("  {method} {key}: {e}"));
                    runs.push(None);
                    continue;
                }
            };
            if pass == 1 {
                let e = errors(&tr, &reference, s);
                runs.push(Some((tr, repeats, e)));
            } else if let Some((best, count, _)) = &mut runs[k] {
                *count += repeats;
                best.keep_faster_timing(&tr);
            }
        }
    }
    // Every run that reached the end: (method, N or tolerance, fastest CPU time, errors).
    let mut results: Vec<(&str, &str, f64, Errors)> = Vec::new();
    let mut points = Vec::new();
    for ((method, key, s), run) in configs.iter().zip(&runs) {
        let Some((tr, repeats, e)) = run else {
            continue;
        };
        log(&format!(
            "  {method} {key}: {} steps, cpu {:.4} s (fastest of {repeats}), {}",
            tr.steps(),
            tr.cpu_s,
            e.describe(tr)
        ));
        let _ = writeln!(
            csv,
            "{method},{},{key},{:.6e},{},{repeats},{}",
            c.level,
            s.initial_tau(),
            tr.rejected,
            row(tr, e)
        );
        if tr.failure.is_none() {
            results.push((method, key, tr.cpu_s, *e));
        }
        points.push(e.point(method.to_string(), tr));
    }
    std::fs::write(c.out.join("adaptive.csv"), &csv)?;
    for target in [1e-2, 1e-3, 1e-4] {
        let cheapest = |method: &str| {
            results
                .iter()
                .filter(|r| r.0 == method)
                .filter(|r| {
                    r.3.u.is_some_and(|e| e <= target) && r.3.ts.is_some_and(|e| e <= target)
                })
                .min_by(|x, y| x.2.total_cmp(&y.2))
        };
        let (u, a) = (cheapest("uniform"), cheapest("adaptive"));
        let describe = |r: Option<&(&str, &str, f64, Errors)>| {
            r.map_or("none".to_string(), |r| {
                format!("{} ({} s CPU)", r.1, opt(Some(r.2)))
            })
        };
        log(&format!(
            "error ≤ {target:e} in (a) and (b): cheapest uniform N = {}, adaptive tol = {}, \
             ratio {}",
            describe(u),
            describe(a),
            opt(u.zip(a).map(|(u, a)| u.2 / a.2))
        ));
    }
    plot_panels(
        &c.figures.join("work_precision_adaptive.png"),
        &format!(
            "Adaptive τ (tolerance {:e}…{:e}) and uniform N, j = {}, Newmark direct",
            c.tolerances.iter().copied().fold(0.0, f64::max),
            c.tolerances.iter().copied().fold(f64::INFINITY, f64::min),
            c.level
        ),
        &points,
        None,
    )
}
