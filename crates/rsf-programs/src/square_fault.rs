//! What `seas_bp7` and `seas_bp8` share (a square fault in a whole space, SEAS BP7 and
//! BP8): the run of the fault ODE from its set-up line to `summary.json` — the session
//! (checkpoints, resume), the benchmark's files, the progress bar, the last line and the
//! summary's common keys.

use std::time::Instant;

use rsf::checkpoint::Fingerprint;
use rsf::observe::TimeUnit;
use rsf::Stepping;
use rsf_scenes::SeasBp8FaultOde;
use rsf_seas::SeasBp5Output;

use crate::guard::{AnyError, Prepared};
use crate::seas_args::{run_observed, RunFlags};
use crate::{cpu_seconds, machine};

/// A run's settings: its flags, fingerprint, end and the bar's unit.
pub(crate) struct SquareRun<'a> {
    /// `--out`, `--threads`, the resume flags, `--hdf5`.
    pub(crate) flags: RunFlags<'a>,
    /// The guard's folder: the run's step cap (`--max-steps`, or the plan's) and the mode
    /// of a fresh run's files.
    pub(crate) folder: &'a Prepared,
    /// `--integrator`.
    pub(crate) integrator: rsf::fault_ode::OdeIntegrator,
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
    let (flags, folder) = (settings.flags, settings.folder);
    let step_cap = folder.step_cap(flags.run.max_steps);
    let session = flags.session(step_cap, settings.fingerprint, settings.end, ode)?;
    let mut fields = flags.fields_observer(&session, folder.mode(), |w, t| w.fault_3d(t))?;
    let mut output = output(ode.model())?;
    if session.keeps_resume_log() {
        output = output.with_resume_log(flags.run.checkpoint_every);
    }
    match session.resumed() {
        Some(c) => output.resume(c.state.step, c.state.time)?,
        None => output.write_initial_state(ode.model(), ode.state(), ode.fault_tractions()),
    }
    let (unit, label) = settings.unit;
    let progress = rsf::observe::Progress::time_in(ode.state().time, settings.end, unit, label);
    let files = vec![&mut output as &mut dyn rsf::Observer<3>];
    let summary = run_observed(session, ode, files, &mut fields, progress)?;
    let wall = clock.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - cpu0;
    println!(
        "{} steps ({} attempts rejected), {} evaluations, {} events; wall {wall:.1} s, CPU \
         {cpu:.1} s; wrote {}",
        summary.steps,
        summary.rejected_attempts,
        ode.evaluations(),
        output.events().len(),
        flags.out.display()
    );
    let mut json = keys;
    let run = serde_json::json!({
        "cells": cells,
        "events": output.events().len(),
        "accepted_steps": ode.state().step,
        "steps_this_invocation": summary.steps,
        "rejected_attempts": summary.rejected_attempts,
        "rate_evaluations": ode.evaluations(),
        "integrator": crate::IntegratorArgs {
            integrator: settings.integrator,
        }
        .summary(Some(ode.integrator_stats())),
        "threads": flags.threads,
        "wall_time_s": wall,
        "cpu_time_s": cpu,
        "machine": machine(),
    });
    if let (Some(json), serde_json::Value::Object(run)) = (json.as_object_mut(), run) {
        json.extend(run);
    }
    rsf::checkpoint::write_atomically(
        &flags.out.join("summary.json"),
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
