//! The guard on the processes of a job (MPI ranks): the ranks agree on their flags
//! ([`agree_on_flags`]) and run a program with rank 0 preparing the folders
//! ([`main_on_ranks`]).

use std::process::ExitCode;

use super::flags::excerpt;
use super::{parse, prepare, report_memory, AnyError, Prepared, Program};
use crate::process::{error_lines, on_threads};
use rsf::observe::FileMode;
use rsf_ranks::{Processes, RankGroup};

/// Compares every rank's `flags` ([`given_flags`](super::given_flags)) before any work (issue 74): ranks
/// started with different flags (an MPMD launch `mpirun -n 1 P --end-years 5 : -n 1 P
/// --end-years 50`, a different `--dx`, another program) would compute different runs
/// and wait for each other in a collective that never matches — a hang or a crash. Two
/// all-gathers of the group (each rank's length, then its text, a byte per value), so
/// every rank sees every rank's flags and reaches the same verdict.
///
/// # Errors
/// On every rank the same message: the ranks whose flags differ from rank 0's and the
/// first differing flag, as the users wrote it on each.
pub fn agree_on_flags(group: &mut dyn RankGroup, flags: &str) -> Result<(), String> {
    let size = group.size();
    if size <= 1 {
        return Ok(());
    }
    let own: Vec<f64> = flags.bytes().map(f64::from).collect();
    let mut lengths = vec![0.0; size];
    group.all_gather(&[own.len() as f64], &vec![1; size], &mut lengths);
    let counts: Vec<usize> = lengths.iter().map(|&l| l as usize).collect();
    let mut all = vec![0.0; counts.iter().sum()];
    group.all_gather(&own, &counts, &mut all);
    let mut texts = Vec::with_capacity(size);
    let mut at = 0;
    for &c in &counts {
        let bytes: Vec<u8> = all[at..at + c].iter().map(|&b| b as u8).collect();
        texts.push(String::from_utf8_lossy(&bytes).into_owned());
        at += c;
    }
    let differ: Vec<usize> = (1..size).filter(|&r| texts[r] != texts[0]).collect();
    let Some(&first) = differ.first() else {
        return Ok(());
    };
    let lines = |t: &str| t.lines().map(str::to_owned).collect::<Vec<_>>();
    let (root, other) = (lines(&texts[0]), lines(&texts[first]));
    let only = |a: &[String], b: &[String]| {
        a.iter()
            .filter(|l| !b.contains(l))
            .map(|l| format!("`{}`", excerpt(l)))
            .collect::<Vec<_>>()
    };
    let (theirs, ours) = (only(&other, &root), only(&root, &other));
    let show = |v: &[String]| {
        if v.is_empty() {
            "nothing else".to_owned()
        } else {
            v.join(", ")
        }
    };
    let ranks = differ
        .iter()
        .take(8)
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join(", ");
    let more = if differ.len() > 8 { ", …" } else { "" };
    Err(format!(
        "the ranks were started with different flags (rank{} {ranks}{more} of {size} differ \
         from rank 0): rank {first} has {} where rank 0 has {}; start every rank with the \
         same program and flags",
        if differ.len() > 1 { "s" } else { "" },
        show(&theirs),
        show(&ours),
    ))
}

/// [`main`](super::main) on the processes of a job (MPI ranks, `processes`): every rank parses the
/// flags, and the ranks compare them ([`agree_on_flags`]: ranks started with different
/// flags end, every one, with one error naming the flag, before any work); every rank
/// checks the flags and plans the run; rank 0 alone prepares the folders (creates, locks,
/// checks them) — the others get a [`Prepared`] without folders, and a body writes its
/// files on rank 0 only. `body` gets the processes. Any rank's error (its refusal, the
/// body's error) is printed with the rank and ends every rank
/// ([`Processes::end_all`]): a rank that returned would leave the others waiting. The
/// exceptions are the differing flags and the stop at `--max-steps`, which every rank
/// reaches alike: each rank returns failure, rank 0 printing the message.
pub fn main_on_ranks<P: Program>(
    processes: &dyn Processes,
    body: fn(P, Prepared, &dyn Processes) -> Result<(), AnyError>,
) -> ExitCode {
    main_on_ranks_supplied(processes, |_| {}, body)
}

/// [`main_on_ranks`] with `supply` applied to every rank's flags once parsed, before the
/// plan: what the binary supplies beyond the flags (the writers of `--hdf5`,
/// [`FieldArgs::supply`](crate::fields::FieldArgs::supply); rank 0 writes the file).
pub fn main_on_ranks_supplied<P: Program>(
    processes: &dyn Processes,
    supply: impl FnOnce(&mut P),
    body: fn(P, Prepared, &dyn Processes) -> Result<(), AnyError>,
) -> ExitCode {
    let (program, flags) = parse::<P>();
    // Before any work: ranks with different flags would run different runs (issue 74).
    // Every rank reaches the same verdict, so each ends normally (rank 0 printing it):
    // none is left waiting.
    if let Err(e) = agree_on_flags(&mut *processes.group(), &flags) {
        if processes.rank() == 0 {
            eprintln!("rank 0 of {}: error: {e}", processes.size());
        }
        return ExitCode::FAILURE;
    }
    // A `--config` file every rank reads (the same file on a shared disk: each reaches the
    // same verdict).
    let mut program = match program {
        Ok(p) => p,
        Err(e) => {
            if processes.rank() == 0 {
                eprintln!("rank 0 of {}: error: {e}", processes.size());
            }
            return ExitCode::FAILURE;
        }
    };
    supply(&mut program);
    let prepared = if processes.rank() == 0 {
        prepare(&program)
    } else {
        plan_only(&program)
    };
    let step_cap = std::sync::atomic::AtomicBool::new(false);
    let estimate = prepared.as_ref().map_or(0.0, |p| p.memory);
    let outcome = match prepared {
        Ok(prepared) => on_threads(prepared.pool, || {
            body(program, prepared, processes).inspect_err(|e| {
                if is_step_cap(&**e) {
                    step_cap.store(true, std::sync::atomic::Ordering::Relaxed);
                }
            })
        }),
        Err(e) => Err(error_lines(&*e)),
    };
    report_memory(P::NAME, estimate, Some(processes.rank()));
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        // Every rank stops at the step cap at the same step (the time stepping is the same
        // on every rank, and rank 0 wrote the checkpoint before): no rank is left waiting,
        // so each ends normally, rank 0 with the message. Ending the job from every rank
        // at once (`end_all`, MPI_Abort) could leave Open MPI's launcher hanging.
        Err(lines) if step_cap.load(std::sync::atomic::Ordering::Relaxed) => {
            if processes.rank() == 0 {
                eprintln!("rank 0 of {}: {}", processes.size(), lines.join("\n"));
            }
            ExitCode::FAILURE
        }
        Err(lines) => processes.end_all(&lines.join("\n")),
    }
}

/// Whether `e` is a run's stop at its step cap (`--max-steps`:
/// [`step_cap_error`](rsf::run_folder::step_cap_error)'s error).
fn is_step_cap(e: &(dyn std::error::Error + 'static)) -> bool {
    matches!(
        e.downcast_ref::<rsf::Error>(),
        Some(rsf::Error::StepCapReached { .. })
    )
}

/// The checks of [`prepare`] that touch no file: the plan and the estimates (the
/// processes of a job other than rank 0, which prepares the folders).
fn plan_only<P: Program>(program: &P) -> Result<Prepared, AnyError> {
    let plan = program.plan()?;
    plan.check(program.limits())?;
    Ok(Prepared {
        modes: vec![FileMode::Create; plan.folders.len()],
        pool: plan.pool,
        memory: plan.memory_bytes(),
        step_cap: plan.step_cap,
        _locks: Vec::new(),
    })
}
