//! What the programs of fault networks share (`stepover`, `bp5_pair`;
//! docs/fault-networks.md): the catalogue's statistics, its lines on the terminal and its
//! figure (each event's faults against time).

use std::path::Path;

use plotters::prelude::*;
use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::OdeIntegrator;
use rsf::friction::FrictionLaw;
use rsf::observe::{
    EventThresholds, FaultCatalogue, FaultStation, FaultStations, FileMode, NetworkEvent, Progress,
    TimeUnit, SECONDS_PER_YEAR,
};
use rsf::state::StateLaw;
use rsf::{FaultOde, RunSummary, Stepping};

use crate::fields::{FieldArgs, FieldWriters, FieldsRun, FieldsTarget};
use crate::guard::{AnyError, Prepared};
use crate::seas_args::{run_observed, RunFlags};
use crate::session::Session;

/// The catalogue's resume log in a run folder.
pub const CATALOGUE_LOG: &str = "catalogue_resume.csv";

/// The files every network run writes besides its stations.
pub const NETWORK_FILES: [&str; 5] = [
    "catalogue.csv",
    CATALOGUE_LOG,
    "summary.json",
    "catalogue.png",
    "checkpoint.bin",
];

/// The files a network run writes into its folder: a station file `{fault}_{label}.csv` for
/// each of `stations`, then [`NETWORK_FILES`].
pub(crate) fn network_outputs<const D: usize>(stations: &[FaultStation<D>]) -> Vec<String> {
    let mut names: Vec<String> = stations
        .iter()
        .map(|s| format!("{}_{}.csv", s.fault, s.label))
        .collect();
    names.extend(NETWORK_FILES.map(String::from));
    names
}

/// How a network program runs: its folder, end, resume flags and the catalogue's rigidity.
pub struct NetworkRun<'a> {
    /// The run folder.
    pub out: &'a Path,
    /// The folder's mode for a fresh run (the guard's).
    pub fresh: FileMode,
    /// End time (years).
    pub end_years: f64,
    /// `--checkpoint-every`, `--resume`, `--allow-change`, `--max-steps`.
    pub resume: &'a crate::ResumeArgs,
    /// The run's step cap (`--max-steps`, or the plan's: `Prepared::step_cap`).
    pub step_cap: Option<u64>,
    /// The progress bar's label and the figure's caption; the program's name.
    pub label: &'a str,
    /// The shear modulus of the catalogue's moments (Pa).
    pub rigidity: f64,
    /// `--hdf5 N`: the faults' fields.
    pub fields: &'a FieldArgs,
}

impl<'a> NetworkRun<'a> {
    /// The run of a network program's `flags` into the guard's `folder` (its step cap and a
    /// fresh run's mode) to `end_years`, the catalogue's moments of `rigidity` (Pa); the
    /// program's name its label.
    pub(crate) fn of(
        flags: RunFlags<'a>,
        folder: &Prepared,
        end_years: f64,
        rigidity: f64,
    ) -> Self {
        Self {
            out: flags.out,
            fresh: folder.mode(),
            end_years,
            resume: flags.run,
            step_cap: folder.step_cap(flags.run.max_steps),
            label: flags.program,
            rigidity,
            fields: flags.fields,
        }
    }
}

/// The writer of a network's fault fields in `D` dimensions
/// ([`FieldWriters::fault_2d`] or [`FieldWriters::fault_3d`]).
pub type FaultFieldsMaker<const D: usize> =
    fn(&dyn FieldWriters, &FieldsTarget<'_>) -> rsf::Result<Box<dyn rsf::Observer<D>>>;

/// What a network run ends with.
pub struct NetworkOutcome {
    /// The run's summary.
    pub summary: RunSummary,
    /// The faults' names.
    pub names: Vec<String>,
    /// The catalogue.
    pub events: Vec<NetworkEvent>,
}

/// Runs `method` (a fault network's fault ODE) as its program does: the session (a
/// checkpoint checked and restored before any file is touched), the station files of
/// `stations` and the catalogue (with its resume log where the run can stop before its
/// end), with `--hdf5 N` the faults' fields (`fault_fields` the writer's method), the
/// progress in years; then writes `catalogue.csv` and `catalogue.png` and prints the
/// events.
///
/// # Errors
/// The session's, the files', the run's.
pub fn run_network<const D: usize, M: Stepping<D, D> + ?Sized>(
    method: &mut M,
    stations: &[FaultStation<D>],
    fingerprint: Fingerprint,
    run: NetworkRun<'_>,
    fault_fields: FaultFieldsMaker<D>,
) -> Result<NetworkOutcome, AnyError> {
    let end = run.end_years * SECONDS_PER_YEAR;
    let session = Session::start(
        run.resume.session_flags_with_cap(run.step_cap),
        run.out.join("checkpoint.bin"),
        fingerprint,
        end,
        method,
    )?;
    let mode = session.mode(run.fresh);
    let model = method.model();
    let mu = run.rigidity;
    let mut catalogue = FaultCatalogue::new(model, EventThresholds::default(), |_| mu)?;
    if let Some(c) = session.resumed() {
        // The folder's files are the checkpoint's run's (its manifest may be missing):
        // proven by the catalogue's state of the step before any file is cut.
        catalogue.check_checkpoint_state(&run.out.join(CATALOGUE_LOG), model, c)?;
    }
    // The faults' fields (`--hdf5 N`): the file proves it holds the checkpoint's run
    // before any file is cut.
    let mut fields = run.fields.observer(
        (run.label, run.out),
        FieldsRun::of(&session, run.fresh, &run.resume.allow_change),
        fault_fields,
    )?;
    let mut files = FaultStations::new(run.out, model, stations, mode)?;
    if session.keeps_resume_log() {
        catalogue = catalogue.with_resume_log(
            &run.out.join(CATALOGUE_LOG),
            run.resume.checkpoint_every,
            run.resume.max_steps.map(|s| s as usize),
            mode,
        )?;
    }
    let year = TimeUnit::year(SECONDS_PER_YEAR);
    let progress = Progress::time_in(method.state().time, end, year, run.label);
    let observers: Vec<&mut dyn rsf::Observer<D>> = vec![&mut files, &mut catalogue];
    let summary = run_observed(session, method, observers, &mut fields, progress)?;
    catalogue.write_csv(&run.out.join("catalogue.csv"))?;
    let names = catalogue.fault_names().to_vec();
    let events = catalogue.events().to_vec();
    print_events(&names, &events);
    catalogue_figure(
        &run.out.join("catalogue.png"),
        &format!("{}: events by fault", run.label),
        &names,
        &events,
    )?;
    Ok(NetworkOutcome {
        summary,
        names,
        events,
    })
}

/// Prints every event of a network's catalogue: its onset (years), the fault and place
/// where it nucleated, the faults it ruptured and each fault's peak slip rate.
pub fn print_events(names: &[String], events: &[NetworkEvent]) {
    for e in events {
        let at: Vec<String> = e
            .nucleation_x
            .iter()
            .map(|x| format!("{:.2}", x / 1e3))
            .collect();
        println!(
            "event at {:.3} yr: nucleated on {} at ({}) km, ruptured {}, peak slip rate {} m/s",
            e.onset_s / SECONDS_PER_YEAR,
            names[e.nucleation_fault],
            at.join(", "),
            e.ruptured_names(names),
            e.peak_slip_rate
                .iter()
                .map(|v| format!("{v:.2e}"))
                .collect::<Vec<_>>()
                .join("/")
        );
    }
}

/// The catalogue's statistics for `summary.json`: the number of events, how many
/// ruptured every fault (and more than one), and per fault how many nucleated on it and
/// how many it took part in.
pub fn catalogue_stats(names: &[String], events: &[NetworkEvent]) -> serde_json::Value {
    let per_fault = |count: &dyn Fn(usize, &NetworkEvent) -> bool| {
        names
            .iter()
            .enumerate()
            .map(|(f, name)| (name.clone(), events.iter().filter(|e| count(f, e)).count()))
            .collect::<std::collections::BTreeMap<_, _>>()
    };
    serde_json::json!({
        "events": events.len(),
        "ruptured_every_fault": events.iter().filter(|e| e.ruptured.iter().all(|&r| r)).count(),
        "ruptured_several_faults": events
            .iter()
            .filter(|e| e.ruptured.iter().filter(|&&r| r).count() > 1)
            .count(),
        "nucleated_on": per_fault(&|f, e| e.nucleation_fault == f),
        "ruptured": per_fault(&|f, e| e.ruptured[f]),
    })
}

/// The catalogue's figure (PNG, 1000 × 400, caption `title`): one row per fault, every
/// event a mark at its onset (years) on each fault it ruptured — filled on the fault where
/// it nucleated — the marks of one event joined by a line when it ruptured more than one.
///
/// # Errors
/// Drawing or file errors.
pub fn catalogue_figure(
    path: &Path,
    title: &str,
    names: &[String],
    events: &[NetworkEvent],
) -> Result<(), Box<dyn std::error::Error>> {
    crate::init_fonts();
    let t_end = events
        .iter()
        .map(|e| e.onset_s / SECONDS_PER_YEAR)
        .fold(1.0f64, f64::max);
    let rows = names.len() as f64;
    crate::draw_png(path, (1000, 400), |root| {
        let mut chart = crate::titled_chart(root, title, 0.0..1.05 * t_end, -0.5..rows - 0.5)?;
        let labels = names.to_vec();
        chart
            .configure_mesh()
            .x_desc("onset (years)")
            .y_desc("fault")
            .y_labels(names.len())
            .y_label_formatter(&move |y| {
                labels.get(y.round() as usize).cloned().unwrap_or_default()
            })
            .label_style(("sans-serif", 15))
            .draw()?;
        let blue = RGBColor(31, 119, 180);
        for e in events {
            let t = e.onset_s / SECONDS_PER_YEAR;
            let hit: Vec<f64> = (0..names.len())
                .filter(|&f| e.ruptured[f])
                .map(|f| f as f64)
                .collect();
            if hit.len() > 1 {
                chart.draw_series(LineSeries::new(
                    [(t, hit[0]), (t, hit[hit.len() - 1])],
                    blue.stroke_width(1),
                ))?;
            }
            for &f in &hit {
                let nucleated = f as usize == e.nucleation_fault;
                let style = if nucleated {
                    blue.filled()
                } else {
                    blue.stroke_width(2)
                };
                chart.draw_series(std::iter::once(Circle::new((t, f), 5, style)))?;
            }
        }
        Ok(())
    })
}

/// What a network program's run ended with, for its last line and `summary.json`
/// ([`finish`]).
pub struct NetworkEnd<'a> {
    /// The run folder.
    pub out: &'a Path,
    /// The run's outcome.
    pub outcome: &'a NetworkOutcome,
    /// The fault ODE's rate evaluations.
    pub evaluations: usize,
    /// The integrator's summary (`IntegratorArgs::summary`).
    pub integrator: serde_json::Value,
    /// The wall clock and the CPU seconds at the program's start.
    pub started: (std::time::Instant, f64),
}

impl<'a> NetworkEnd<'a> {
    /// The end of the run of `ode` (its evaluations; the summary of `integrator`, the
    /// method it was given, with what it did) into `out` with `outcome`, started at
    /// `started` (the wall clock, the CPU seconds).
    pub(crate) fn of<const D: usize, L: FrictionLaw, S: StateLaw, const C: usize>(
        out: &'a Path,
        outcome: &'a NetworkOutcome,
        ode: &FaultOde<D, L, S, C>,
        integrator: OdeIntegrator,
        started: (std::time::Instant, f64),
    ) -> Self {
        NetworkEnd {
            out,
            outcome,
            evaluations: ode.evaluations(),
            integrator: crate::IntegratorArgs { integrator }.summary(Some(ode.integrator_stats())),
            started,
        }
    }
}

/// Prints a network run's last lines and writes its `summary.json`: the program's own keys
/// `head` (an object: program, scene, grid, …), then `run` — `run_keys` (an object: the
/// program's flags and set-up figures) with the steps, rejected attempts, evaluations,
/// wall and CPU seconds, machine and integrator added — and the faults' names, the events
/// and their statistics ([`catalogue_stats`]).
///
/// # Errors
/// Writing the file.
pub fn finish(
    end: NetworkEnd<'_>,
    head: serde_json::Value,
    run_keys: serde_json::Value,
) -> Result<(), AnyError> {
    let wall = end.started.0.elapsed().as_secs_f64();
    let cpu = crate::cpu_seconds() - end.started.1;
    let (summary, names, events) = (
        &end.outcome.summary,
        &end.outcome.names,
        &end.outcome.events,
    );
    let every = events
        .iter()
        .filter(|e| e.ruptured.iter().all(|&r| r))
        .count();
    println!(
        "{} events, {every} of them ruptured every fault; {} steps ({} rejected), {} \
         evaluations; wall {wall:.1} s, CPU {cpu:.1} s; wrote {}",
        events.len(),
        summary.steps,
        summary.rejected_attempts,
        end.evaluations,
        end.out.display()
    );
    let mut run = run_keys;
    let keys = serde_json::json!({
        "steps": summary.steps,
        "rejected_attempts": summary.rejected_attempts,
        "evaluations": end.evaluations,
        "wall_seconds": wall,
        "cpu_seconds": cpu,
        "machine": crate::machine(),
        "integrator": end.integrator,
    });
    let mut json = head;
    if let (Some(run), Some(keys), Some(json)) =
        (run.as_object_mut(), keys.as_object(), json.as_object_mut())
    {
        run.extend(keys.clone());
        json.insert("run".into(), serde_json::Value::Object(run.clone()));
        json.insert("faults".into(), serde_json::json!(names));
        json.insert("events".into(), serde_json::json!(events));
        json.insert("stats".into(), catalogue_stats(names, events));
    } else {
        return Err("summary.json: the program's keys must be objects".into());
    }
    rsf::checkpoint::write_atomically(
        &end.out.join("summary.json"),
        serde_json::to_string_pretty(&json)?.as_bytes(),
    )?;
    println!("wrote {}", end.out.join("catalogue.png").display());
    Ok(())
}
