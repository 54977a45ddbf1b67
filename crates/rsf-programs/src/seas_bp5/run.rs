//! The run of `seas_bp5`: the operator and files of either kernel, the session, the
//! summary.

use std::cell::RefCell;
use std::rc::Rc;
use std::time::Instant;

use crate::guard::{AnyError, Prepared};
use crate::memory::StageMemory;
use crate::seas_args::run_observed;
use crate::{cpu_seconds, machine};
use rsf::direct::{CheckpointPolicy, Progress};
use rsf::fault_ode::{SchurOnlySetup, SetupProgress};
use rsf::observe::{Observer, TimeUnit};
use rsf::run_folder::RunFolder;
use rsf::Stepping;
use rsf_ranks::Processes;
use rsf_scenes::{SeasBp5, SeasBp5Grid};
use rsf_seas::{SeasBp5Output, SeasSetup, SECONDS_PER_YEAR};
use std::ops::ControlFlow;

use super::args::{Args, SETUP_FILE};
use rsf_scenes::{Bp5Condensation as Condensation, Bp5Kernel as Kernel, RunConfig};

/// Removes `path` if it is there.
fn remove_if_present(path: &std::path::Path) -> Result<(), AnyError> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(format!("{}: {e}", path.display()).into())
        }
        _ => Ok(()),
    }
}

/// On a rank other than 0: waits until rank 0 has eliminated (the collective rank 0 enters
/// after its set-up), then the policy that reads its finished elimination from `path` and
/// writes nothing.
///
/// # Errors
/// If `path` is not there after the wait: the run folder is not on a file system this
/// rank sees (every rank must see the same folder).
fn read_rank_0s_setup(
    p: &dyn Processes,
    path: &std::path::Path,
) -> Result<CheckpointPolicy, AnyError> {
    p.barrier();
    if !path.is_file() {
        return Err(format!(
            "rank {} does not see rank 0's set-up {}: the run folder must be on a file \
             system every rank sees",
            p.rank(),
            path.display()
        )
        .into());
    }
    eprintln!(
        "rank {}: the elimination read from rank 0's {}",
        p.rank(),
        path.display()
    );
    Ok(CheckpointPolicy {
        every_fronts: None,
        every_seconds: None,
        ..CheckpointPolicy::new(path)
    })
}

/// A line on standard error at every tenth of the elimination's work (flops), with the
/// fronts done and the wall time.
fn elimination_progress() -> SetupProgress {
    let mut next = 0.1;
    Box::new(move |p: &Progress| {
        let done = if p.flops > 0.0 {
            p.flops_done / p.flops
        } else {
            1.0
        };
        if done >= next {
            eprintln!(
                "set-up: {:.0} % of the elimination ({} of {} fronts, {:.0} s)",
                100.0 * done,
                p.fronts_done,
                p.fronts,
                p.seconds
            );
            while next <= done {
                next += 0.1;
            }
        }
        ControlFlow::Continue(())
    })
}

/// The operator and the files of a run, set up for one kernel.
struct SetUp<'a> {
    args: &'a Args,
    bp5: &'a SeasBp5,
    /// Whether this process writes the files (rank 0, or the one process).
    root: bool,
    options: rsf::fault_ode::FaultOdeOptions,
    half_space: &'a rsf::halfspace_operator::HalfSpaceOptions,
    setup: SeasSetup,
}

/// The fault ODE and, on the process that writes them, its files.
type OdeAndFiles = (rsf_scenes::SeasBp5FaultOde, Option<SeasBp5Output>);

impl SetUp<'_> {
    /// A fault alone with Okada's half-space operator (on ranks, each its rows).
    fn okada(
        self,
        cells: usize,
        processes: Option<&dyn Processes>,
    ) -> Result<OdeAndFiles, AnyError> {
        let (bp5, dx) = (self.bp5, self.args.settings.dx);
        let model = bp5.model(dx)?;
        if self.root {
            println!(
                "BP5-QD, Okada, Δx = {dx} m, {cells} cells ({} slip unknowns); on {}",
                2 * cells,
                machine()
            );
        }
        // On ranks, each builds and holds its rows of the operator.
        let (ode, columns) = bp5.fault_ode_on_ranks(
            model,
            self.options,
            self.half_space,
            &SeasBp5::body_station_points(),
            processes.map(|p| p.group()),
        )?;
        let output = if self.root {
            Some(bp5.output(&self.args.out, dx, columns, self.setup)?)
        } else {
            None
        };
        Ok((ode, output))
    }

    /// The finite-element volume condensed onto the fault (the build's stages with their
    /// memory, docs/three-d.md, "The build's memory"); on ranks, the Schur-only
    /// elimination on rank 0 alone, read by the others from the run folder.
    fn fe(
        self,
        grid: &SeasBp5Grid,
        ratio: f64,
        folder: &RunFolder,
        processes: Option<&dyn Processes>,
    ) -> Result<OdeAndFiles, AnyError> {
        let Self {
            args,
            bp5,
            root,
            options,
            setup,
            ..
        } = self;
        // The build's stages, each with its peak memory (docs/three-d.md, "The build's
        // memory").
        let stages = Rc::new(RefCell::new(StageMemory::start(args.stage_peaks)));
        let builder = bp5
            .fe_model_builder(grid)
            .map_err(|e| format!("--kernel fe: {e}"))?;
        stages.borrow_mut().end("mesh");
        let mesh = builder.mesh();
        let mesh_line = format!(
            "{:?} mesh: {} vertices, {} tetrahedra, smallest dihedral angle {:.2}°, box ±{} km",
            grid.mesh,
            mesh.num_vertices(),
            mesh.num_cells(),
            mesh.min_dihedral_angle().to_degrees(),
            mesh.vertices().iter().map(|x| x[0]).fold(0.0, f64::max) / 1e3
        );
        let watch = Rc::clone(&stages);
        let model = builder
            .on_stage(move |stage| watch.borrow_mut().end(stage.name()))
            .build()
            .map_err(|e| format!("--kernel fe: {e}"))?;
        let m = 2 * model.frictional_boundary.len();
        if root {
            println!(
                "BP5-QD, finite elements, Δx = {} m, ratio {ratio}, {} vertices (the fault's \
                 split), {m} slip unknowns; on {}",
                args.settings.dx,
                model.vertices.len(),
                machine()
            );
            println!("{mesh_line}");
        }
        let options = args.resolved().volume_options(options, m);
        let output = if root {
            Some(bp5.volume_output(&args.out, &model, args.settings.dx, setup)?)
        } else {
            None
        };
        let mut ode = match args.condensation() {
            Condensation::Factor => bp5.fe_fault_ode(model, options)?,
            Condensation::SchurOnly => {
                // The stations' vertices on every rank (the elimination keeps them).
                let watch_vertices = bp5.station_vertices(&model)?;
                let path = folder.path(SETUP_FILE);
                if root && args.run.resume.is_none() {
                    // Another run's elimination is not this one's to continue.
                    remove_if_present(&path)?;
                }
                // On ranks, rank 0 eliminates alone and keeps its result in the run
                // folder; the others wait for it and read it (its checksum of the inputs
                // checked: the same bits), so that one process holds the elimination's
                // memory, not every one (docs/seas-bp5.md, "On MPI ranks").
                let others = processes.filter(|p| p.size() > 1);
                let checkpoint = match others {
                    Some(p) if !root => read_rank_0s_setup(p, &path)?,
                    _ => CheckpointPolicy::new(&path),
                };
                let setup = SchurOnlySetup {
                    watch_vertices,
                    checkpoint: Some(checkpoint),
                    max_bytes: Some(
                        (args.limits.max_memory_gb * 1e9).min(usize::MAX as f64) as usize
                    ),
                    progress: root.then(|| elimination_progress()),
                };
                let ode = bp5
                    .fe_fault_ode_schur_only(model, options, setup)
                    .map_err(|e| {
                        crate::run_folder::kept_setup_hint(e, &path, &args.run.allow_change)
                    })?;
                if let (true, Some(p)) = (root, others) {
                    println!(
                        "set-up: eliminated on rank 0 alone, read from {} by the other ranks \
                         ({})",
                        path.display(),
                        p.size() - 1
                    );
                    p.barrier();
                }
                ode
            }
        };
        stages.borrow_mut().end("condensation and operator");
        if root {
            println!("the set-up's stages (memory of this process):");
            print!("{}", stages.borrow().table());
        }
        if let Some(output) = &output {
            ode.watch_vertices(&output.volume_vertices())?;
            match args.condensation() {
                Condensation::Factor => {
                    println!("volume factor: {} entries", ode.factor_nnz())
                }
                Condensation::SchurOnly => {
                    println!("volume: Schur complement only (no factor kept)")
                }
            }
        }
        Ok((ode, output))
    }
}

pub(super) fn run(
    args: Args,
    prepared: Prepared,
    processes: Option<&dyn Processes>,
) -> Result<(), AnyError> {
    // Rank 0 (or the one process) writes the files and tells.
    let root = processes.is_none_or(|p| p.rank() == 0);
    let bp5 = args.scene()?;
    let (_, ratio) = args.box_size();
    // Checked before any file is touched.
    let cells = bp5
        .cells(args.settings.dx)
        .map_err(|e| format!("--dx: {e}"))?
        .len();
    let grid = args.grid(&bp5);
    let options = args
        .resolved()
        .fault_ode_options(&bp5, args.threads)
        .map_err(|e| format!("--tolerance: {e}"))?;
    let half_space = bp5
        .half_space(args.settings.epsilon)
        .map_err(|e| format!("--epsilon: {e}"))?;
    // A folder of another run (unless --overwrite), one that cannot be written: refused
    // by the guard before anything was computed.
    let folder = RunFolder::new(&args.out, "seas_bp5", &[]);
    let fingerprint = args.fingerprint(&bp5);
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let setup = args.resolved().seas_setup(
        &bp5,
        args.header.modeler.clone(),
        args.header.date_or_today(),
    );
    let set_up = SetUp {
        args: &args,
        bp5: &bp5,
        root,
        options,
        half_space: &half_space,
        setup,
    };
    let (mut ode, output) = match args.settings.kernel {
        Kernel::Okada => set_up.okada(cells, processes)?,
        Kernel::Fe => set_up.fe(&grid, ratio, &folder, processes)?,
    };
    if let Some(p) = processes {
        ode.share_evaluations(p.group())?;
    }
    let setup_s = clock.elapsed().as_secs_f64();
    // The checkpoint is checked and restored (on every rank) before any file is touched.
    let flags = args.flags();
    let end = args.settings.end_years * SECONDS_PER_YEAR;
    let step_cap = prepared.step_cap(args.run.max_steps);
    let session = flags.session(step_cap, fingerprint, end, &mut ode)?;
    let Some(mut output) = output else {
        // The other ranks: the same steps as rank 0, no files (no observer here ends a
        // run).
        session.follow(&mut ode, &mut [])?;
        return Ok(());
    };
    println!("S: {}", ode.kernel_report());
    if let Some(p) = processes {
        println!("{} MPI ranks share every evaluation", p.size());
    }
    println!(
        "set-up: wall {setup_s:.1} s, CPU {:.1} s",
        cpu_seconds() - cpu0
    );
    let mut fields = flags.fields_observer(&session, prepared.mode(), |w, t| w.fault_3d(t))?;
    if session.keeps_resume_log() {
        output = output.with_resume_log(args.run.checkpoint_every);
    }
    match session.resumed() {
        Some(c) => output.resume(c.state.step, c.state.time)?,
        None => output.write_initial_state(
            ode.model(),
            ode.state(),
            rsf::Stepping::fault_tractions(&ode),
        ),
    }
    let year = TimeUnit::year(SECONDS_PER_YEAR);
    let progress = rsf::observe::Progress::time_in(ode.state().time, end, year, "BP5");
    let files = vec![&mut output as &mut dyn Observer<3>];
    let summary = run_observed(session, &mut ode, files, &mut fields, progress)?;
    let times = (setup_s, clock.elapsed().as_secs_f64(), cpu_seconds() - cpu0);
    report(&args, &ode, &output, &summary, cells, times)?;
    Ok(())
}

/// Prints the ruptures and the run's line, writes `summary.json` and the overview figure.
/// `times`: the set-up's wall time, this invocation's wall and CPU times (s).
fn report(
    args: &Args,
    ode: &rsf_scenes::SeasBp5FaultOde,
    output: &SeasBp5Output,
    summary: &rsf::RunSummary,
    cells: usize,
    times: (f64, f64, f64),
) -> Result<(), AnyError> {
    let (setup_s, wall, cpu) = times;
    let (domain_km, ratio) = args.box_size();
    // Events with a peak above 0.1 m/s: the ruptures (the catalogue also holds the
    // shallow afterslip that crosses 1 mm/s after some).
    let ruptures: Vec<_> = output
        .events()
        .iter()
        .filter(|e| e.peak_slip_rate >= 0.1)
        .collect();
    let mut previous: Option<f64> = None;
    let mut intervals = Vec::new();
    for e in &ruptures {
        let years = e.t_start / SECONDS_PER_YEAR;
        let interval = previous.map_or(String::new(), |p| {
            intervals.push(years - p);
            format!(", {:.3} yr after the previous", years - p)
        });
        println!(
            "rupture at {years:.4} yr ({:.1} s): peak slip rate {:.3e} m/s at x₂ = {:.1} km, \
             x₃ = {:.1} km, {:.1} s above 1 mm/s{interval}",
            e.t_start,
            e.peak_slip_rate,
            e.hypocentre[0] / 1e3,
            e.hypocentre[1] / 1e3,
            e.t_end.map_or(f64::NAN, |t| t - e.t_start),
        );
        previous = Some(years);
    }
    println!(
        "{} steps ({} attempts rejected), {} evaluations; wall {wall:.1} s, CPU {cpu:.1} s; \
         wrote {}",
        summary.steps,
        summary.rejected_attempts,
        ode.evaluations(),
        args.out.display()
    );
    let json = serde_json::json!({
        "problem": "BP5-QD",
        "kernel": format!("{:?}", args.settings.kernel),
        "domain_km": (args.settings.kernel == Kernel::Fe).then_some(domain_km),
        "ratio": (args.settings.kernel == Kernel::Fe).then_some(ratio),
        "dx_m": args.settings.dx,
        "cells": cells,
        "end_years": args.settings.end_years,
        "tolerance": args.settings.tolerance,
        "epsilon": args.settings.epsilon,
        "operator": ode.kernel_report().to_string(),
        "volume_factor_entries": ode.factor_nnz(),
        "accepted_steps": ode.state().step,
        "steps_this_invocation": summary.steps,
        "rejected_attempts": summary.rejected_attempts,
        "rate_evaluations": ode.evaluations(),
        "integrator": crate::IntegratorArgs {
            integrator: args.settings.integrator,
        }
        .summary(Some(ode.integrator_stats())),
        "threads": args.threads,
        "setup_s": setup_s,
        "wall_time_s": wall,
        "cpu_time_s": cpu,
        "machine": machine(),
        "settings": args.resolved().summary(),
        "rupture_start_years": ruptures.iter().map(|e| e.t_start / SECONDS_PER_YEAR).collect::<Vec<_>>(),
        "recurrence_intervals_years": intervals,
        "peak_slip_rates_mps": ruptures.iter().map(|e| e.peak_slip_rate).collect::<Vec<_>>(),
        "catalogue_events": output.events().len(),
    });
    rsf::checkpoint::write_atomically(
        &args.out.join("summary.json"),
        serde_json::to_string_pretty(&json)?.as_bytes(),
    )?;
    // Slip₂ along dip at x₂ = 0 and the maximum slip rate against time.
    crate::seas_overview(&args.out, "slip_2_depth.dat", "depth (km)", ruptures.len())?;
    println!("wrote {}", args.out.join("overview.png").display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsf_ranks::ThreadProcess;

    /// Two thread ranks: rank 0 writes `written` and enters the barrier; rank 1 enters it
    /// and asks for `wanted`. Returns rank 1's answer.
    fn rank_1_reads(written: &std::path::Path, wanted: &std::path::Path) -> Result<(), String> {
        let answers = ThreadProcess::run(2, |p| {
            if p.rank() == 0 {
                std::fs::write(written, b"rank 0's set-up").expect("writable");
                p.barrier();
                Ok(())
            } else {
                read_rank_0s_setup(&p, wanted)
                    .map(|policy| {
                        assert_eq!(policy.path, wanted);
                        assert_eq!((policy.every_fronts, policy.every_seconds), (None, None));
                    })
                    .map_err(|e| e.to_string())
            }
        });
        answers.into_iter().nth(1).expect("two ranks")
    }

    /// A rank that does not see rank 0's set-up after the barrier (its run folder on
    /// another file system: here, another folder) fails with an error that names the file
    /// and the rank, instead of eliminating again or waiting; where it sees the file, it
    /// gets a policy that only reads.
    #[test]
    fn a_rank_that_does_not_see_rank_0s_setup_says_which_file() {
        let dir = std::env::temp_dir().join(format!("rsf-rank-0-setup-{}", std::process::id()));
        let (ours, theirs) = (dir.join("rank0"), dir.join("rank1"));
        std::fs::create_dir_all(&ours).unwrap();
        std::fs::create_dir_all(&theirs).unwrap();
        let written = ours.join(SETUP_FILE);
        assert_eq!(rank_1_reads(&written, &written), Ok(()));
        let elsewhere = theirs.join(SETUP_FILE);
        let e = rank_1_reads(&written, &elsewhere).expect_err("not on rank 1's file system");
        assert!(e.contains("rank 1 does not see rank 0's set-up"), "{e}");
        assert!(e.contains(&elsewhere.display().to_string()), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
