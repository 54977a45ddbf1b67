//! What `seas_bp7` and `seas_bp8` share (a square fault in a whole space, SEAS BP7 and
//! BP8): the run of the fault ODE from its set-up line to `summary.json` — the session
//! (checkpoints, resume), the benchmark's files, the progress bar, the last line and the
//! summary's common keys.

use std::path::Path;
use std::time::Instant;

use rsf::checkpoint::Fingerprint;
use rsf::observe::TimeUnit;
use rsf::Stepping;
use rsf_scenes::SeasBp8FaultOde;
use rsf_seas::SeasBp5Output;

use crate::guard::AnyError;
use crate::session::Session;
use crate::{cpu_seconds, machine};

/// A run's settings: its flags, fingerprint, end and the bar's unit.
pub(crate) struct SquareRun<'a> {
    /// `--checkpoint-every`, `--resume`, `--max-steps`.
    pub(crate) run: &'a crate::ResumeArgs,
    /// The run's step cap (`--max-steps`, or the plan's: `Prepared::step_cap`).
    pub(crate) step_cap: Option<u64>,
    /// The program (`seas_bp7`, `seas_bp8`), as `--hdf5`'s refusal names it.
    pub(crate) program: &'static str,
    /// `--hdf5` and the mode of a fresh run's files.
    pub(crate) fields: (&'a crate::fields::FieldArgs, rsf::observe::FileMode),
    /// `--integrator`.
    pub(crate) integrator: &'a crate::IntegratorArgs,
    /// `--threads`.
    pub(crate) threads: usize,
    /// `--out`.
    pub(crate) out: &'a Path,
    /// The checkpoint's fingerprint.
    pub(crate) fingerprint: Fingerprint,
    /// End time (s).
    pub(crate) end: f64,
    /// The progress bar's unit and label.
    pub(crate) unit: (TimeUnit, &'static str),
    /// When the program started (wall, CPU s).
    pub(crate) started: (Instant, f64),
}

/// Runs `ode` (the fault ODE of BP7 or BP8, set up) to `settings.end` into the output
/// `output` makes of `ode`'s model, then writes `summary.json`: the program's `keys` (a JSON object) and
/// the run's figures. Returns the output.
///
/// # Errors
/// The session's, the output's and the run's errors; writing the summary.
pub(crate) fn run_square_fault(
    settings: SquareRun<'_>,
    ode: &mut SeasBp8FaultOde,
    output: impl FnOnce(&rsf::Model<3, 3>) -> Result<SeasBp5Output, AnyError>,
    keys: serde_json::Value,
) -> Result<SeasBp5Output, AnyError> {
    let (clock, cpu0) = settings.started;
    let cells = ode.model().frictional_boundary.len();
    println!(
        "{cells} fault nodes ({} slip unknowns); set-up: wall {:.1} s, CPU {:.1} s",
        2 * cells,
        clock.elapsed().as_secs_f64(),
        cpu_seconds() - cpu0
    );
    let session = Session::start(
        settings.run.session_flags_with_cap(settings.step_cap),
        settings.out.join("checkpoint.bin"),
        settings.fingerprint,
        settings.end,
        ode,
    )?;
    // The fault's fields (`--hdf5 N`): the file proves it holds the checkpoint's run
    // before any file is cut.
    let (field_args, fresh) = settings.fields;
    let mut fields = field_args.observer(
        (settings.program, settings.out),
        crate::fields::FieldsRun::of(&session, fresh, &settings.run.allow_change),
        |w, target| w.fault_3d(target),
    )?;
    let mut output = output(ode.model())?;
    if session.keeps_resume_log() {
        output = output.with_resume_log(settings.run.checkpoint_every);
    }
    match session.resumed() {
        Some(c) => output.resume(c.state.step, c.state.time)?,
        None => output.write_initial_state(ode.model(), ode.state(), ode.fault_tractions()),
    }
    let (unit, label) = settings.unit;
    let progress = rsf::observe::Progress::time_in(ode.state().time, settings.end, unit, label);
    let mut observers: Vec<&mut dyn rsf::Observer<3>> = vec![&mut output];
    if let Some(f) = fields.as_mut() {
        observers.push(f.as_mut());
    }
    let summary = session.run(ode, &mut observers, Some(progress))?;
    drop(observers);
    let wall = clock.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - cpu0;
    println!(
        "{} steps ({} attempts rejected), {} evaluations, {} events; wall {wall:.1} s, CPU \
         {cpu:.1} s; wrote {}",
        summary.steps,
        summary.rejected_attempts,
        ode.evaluations(),
        output.events().len(),
        settings.out.display()
    );
    let mut json = keys;
    let run = serde_json::json!({
        "cells": cells,
        "events": output.events().len(),
        "accepted_steps": ode.state().step,
        "steps_this_invocation": summary.steps,
        "rejected_attempts": summary.rejected_attempts,
        "rate_evaluations": ode.evaluations(),
        "integrator": settings.integrator.summary(Some(ode.integrator_stats())),
        "threads": settings.threads,
        "wall_time_s": wall,
        "cpu_time_s": cpu,
        "machine": machine(),
    });
    if let (Some(json), serde_json::Value::Object(run)) = (json.as_object_mut(), run) {
        json.extend(run);
    }
    rsf::checkpoint::write_atomically(
        &settings.out.join("summary.json"),
        serde_json::to_string_pretty(&json)?.as_bytes(),
    )?;
    Ok(output)
}

/// How a square's `--kernel fe` eliminates its volume here: the fastest ordering built
/// (nested dissection where METIS is), bounded by `--max-memory-gb`.
pub(crate) fn elimination(limits: &crate::guard::Limits) -> rsf_scenes::VolumeElimination {
    rsf_scenes::VolumeElimination {
        max_bytes: Some((limits.max_memory_gb * 1e9).min(usize::MAX as f64) as usize),
        ..Default::default()
    }
}

/// Prints the volume of a square's `--kernel fe` run (`ode` set up on `grid`) and its
/// condensed operator.
pub(crate) fn print_volume(ode: &SeasBp8FaultOde, grid: &rsf_scenes::SquareVolumeGrid) {
    let model = ode.model();
    println!(
        "finite elements in the box ±{} km (ratio {}): {} vertices (the fault's split), {} \
         slip unknowns",
        grid.root_and_far().1 / 1e3,
        grid.ratio,
        model.vertices.len(),
        2 * model.frictional_boundary.len(),
    );
    println!("S: {}", ode.kernel_report());
}

/// The peak memory (bytes) of a square's `--kernel fe` run on `grid` (the box graded
/// towards the square of half-width `half` and `stations`), `pairs` frictional nodes:
/// the Schur-only elimination with nested dissection, `2.5e4 V (V/1e5)^{1/3}` bytes for
/// `V` mesh vertices (counted from the octree, without making the mesh; measured with
/// `/usr/bin/time -v`: BP8-GS at 40 m, 48 272 vertices, 0.70 GB; at 20 m, 93 698
/// vertices, 1.92 GB; BP7-A at 20 m, 114 161 vertices, 2.65 GB — a factor's fill growing
/// like `V^{4/3}`), the condensed operator's dense `S` and two copies (`3 · 8 m²` for
/// `m = 2 pairs` unknowns), 100 MB for the rest. Where `S` and the rest alone exceed
/// `max_bytes` (`--max-memory-gb`), that lower bound, the box not counted (the guard
/// refuses it, unmeshed).
///
/// # Errors
/// The grid's ([`rsf_scenes::SquareVolumeGrid::mesh_vertices`]).
pub fn volume_memory(
    grid: &rsf_scenes::SquareVolumeGrid,
    (half, stations): (f64, &[[f64; 3]]),
    pairs: f64,
    max_bytes: f64,
) -> rsf::Result<f64> {
    let m = 2.0 * pairs;
    let least = 24.0 * m * m + 1e8;
    if least > max_bytes {
        return Ok(least);
    }
    let vertices = grid.mesh_vertices(half, stations)? as f64;
    Ok(2.5e4 * vertices * (vertices / 1e5).cbrt() + least)
}
