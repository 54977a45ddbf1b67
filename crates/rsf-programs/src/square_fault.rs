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
/// `output` makes, then writes `summary.json`: the program's `keys` (a JSON object) and
/// the run's figures. Returns the output.
///
/// # Errors
/// The session's, the output's and the run's errors; writing the summary.
pub(crate) fn run_square_fault(
    settings: SquareRun<'_>,
    ode: &mut SeasBp8FaultOde,
    output: impl FnOnce() -> Result<SeasBp5Output, AnyError>,
    keys: serde_json::Value,
) -> Result<SeasBp5Output, AnyError> {
    let (clock, cpu0) = settings.started;
    let cells = ode.model().vertices.len();
    println!(
        "{cells} cells ({} slip unknowns); set-up: wall {:.1} s, CPU {:.1} s",
        2 * cells,
        clock.elapsed().as_secs_f64(),
        cpu_seconds() - cpu0
    );
    let session = Session::start(
        settings.run.session_flags(),
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
    let mut output = output()?;
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
