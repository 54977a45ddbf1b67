//! The guard every program of the workspace goes through (issue 58, docs/reliability.md):
//! a program is a [`Program`] (its clap flags, its name, its [`Plan`]) run by [`main`],
//! which, before any work:
//!
//! 1. parses the flags (clap names a malformed one as the user wrote it);
//! 2. asks the program for its [`Plan`], judged from the flags alone: each flag is checked
//!    there and named as written (`--end-years -1: …`), the memory and output the run
//!    will take are estimated from the inputs, and the output folders are named;
//! 3. refuses a thread count the machine cannot start ([`check_threads`], naming the
//!    flag), a run estimated above `--max-memory-gb` or `--max-output-gb` ([`Limits`],
//!    on every program);
//! 4. takes every output folder: creates it (an `--out` that is a file is refused naming
//!    the path and the operating system's cause), takes its **exclusive lock** (a second
//!    run into a folder that a run is writing is refused at once), and prepares it
//!    ([`RunFolder::prepare`]: the manifest, another program's or another configuration's
//!    run refused unless `--overwrite`, every output path probed);
//! 5. runs the program's body with the [`Prepared`] folders (their file modes and locks,
//!    held until the body returns), on a pool of the plan's threads if it asks for one.
//!
//! The test `tests/careless_inputs.rs` lists every example binary and runs the same
//! careless inputs against each, so a program added later is covered without anyone
//! editing the test.

use std::error::Error;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use rsf::observe::FileMode;
use rsf::run_folder::RunFolder;

use crate::process::{error_lines, main_on_threads, main_with, on_threads};
pub use crate::ranks::Processes;

/// The error type of the programs.
pub type AnyError = Box<dyn Error>;

/// The bounds every program takes: `--max-memory-gb` and `--max-output-gb`.
#[derive(Debug, Clone, Copy, PartialEq, clap::Args)]
pub struct Limits {
    /// Refuse, before anything is allocated, a run whose memory is estimated above this
    /// many gigabytes (`inf`: no bound; docs/reliability.md lists each program's estimate).
    #[arg(long, default_value_t = 16.0, value_name = "GB", value_parser = gigabytes)]
    pub max_memory_gb: f64,
    /// Refuse, before anything is written, a run whose files are estimated above this many
    /// gigabytes (`inf`: no bound).
    #[arg(long, default_value_t = 10.0, value_name = "GB", value_parser = gigabytes)]
    pub max_output_gb: f64,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_memory_gb: 16.0,
            max_output_gb: 10.0,
        }
    }
}

/// Parses a size limit in gigabytes: a positive number, `inf` for none (a clap value
/// parser: `nan`, 0 and negative values are refused where the flag is read).
///
/// # Errors
/// A message naming the value.
pub fn gigabytes(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x > 0.0 => Ok(x),
        Ok(_) => Err(format!(
            "`{s}` GB must be a positive number (inf: no bound)"
        )),
        Err(e) => Err(format!("`{s}`: {e}")),
    }
}

/// An error naming the flag the user wrote: `--out a_file: cannot create …`.
#[derive(Debug)]
pub struct FlagError {
    /// The flag as written (`--out`) or the scene key.
    pub flag: String,
    /// What is wrong.
    pub source: AnyError,
}

impl std::fmt::Display for FlagError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.flag, self.source)
    }
}

impl Error for FlagError {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        // The wrapped error's own causes (its message is already in ours).
        self.source.source()
    }
}

/// `result`'s error named after `flag` (e.g. `--scene`).
///
/// # Errors
/// The error of `result`, prefixed with `flag`.
pub fn flag<T, E: Into<AnyError>>(flag: &str, result: Result<T, E>) -> Result<T, AnyError> {
    result.map_err(|e| {
        Box::new(FlagError {
            flag: flag.to_owned(),
            source: e.into(),
        }) as AnyError
    })
}

/// The message `--flag value: why` of a refused flag, as an error.
pub fn refuse(flag: &str, value: impl std::fmt::Display, why: &str) -> AnyError {
    format!("{flag} {}: {why}", excerpt(&value.to_string())).into()
}

/// A value as the user wrote it, at most about 100 characters (`1e300`, not 301 digits).
fn excerpt(s: &str) -> String {
    rsf_numeric::excerpt(s)
}

/// A number for a message as a user would write it: `300`, `0.025`, `1e300` (never 301
/// digits), `NaN`.
pub fn number(x: f64) -> String {
    let s = if x != 0.0 && x.is_finite() && !(1e-4..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    };
    // A computed bound (`0.007217090069284064`) with four digits.
    if s.len() > 10 {
        format!("{x:.3e}")
    } else {
        s
    }
}

/// Checks that `x` (the value of `flag`) lies in `[lo, hi]` (NaN is refused).
///
/// # Errors
/// `--flag x: must be in [lo, hi] (why)`.
pub fn in_range(flag: &str, x: f64, (lo, hi): (f64, f64), why: &str) -> Result<f64, AnyError> {
    if x >= lo && x <= hi {
        Ok(x)
    } else {
        Err(refuse(
            flag,
            number(x),
            &format!("must be in [{}, {}] ({why})", number(lo), number(hi)),
        ))
    }
}

/// One output folder of a run: the flag that names it, the files the run writes there,
/// whether the run continues an earlier one (`--resume`, `--reuse`) or replaces it
/// (`--overwrite`).
#[derive(Debug, Clone)]
pub struct Folder {
    flag: &'static str,
    dir: PathBuf,
    outputs: Vec<String>,
    resume: bool,
    overwrite: bool,
}

impl Folder {
    /// The folder `dir` named by `flag` (e.g. `--out`) where the run writes `outputs`
    /// (paths inside it).
    pub fn new(flag: &'static str, dir: &Path, outputs: &[&str]) -> Self {
        Self {
            flag,
            dir: dir.to_path_buf(),
            outputs: outputs.iter().map(|s| (*s).to_owned()).collect(),
            resume: false,
            overwrite: false,
        }
    }

    /// Replaces an earlier run's files (`--overwrite`).
    pub fn overwrite(mut self, overwrite: bool) -> Self {
        self.overwrite = overwrite;
        self
    }

    /// Continues the run in the folder (`--resume`, `--reuse`): its own files are kept.
    pub fn resume(mut self, resume: bool) -> Self {
        self.resume = resume;
        self
    }
}

/// A run's memory or output, estimated from its inputs.
#[derive(Debug, Clone)]
struct Estimate {
    bytes: f64,
    flags: String,
    what: String,
}

/// What a run needs, judged from its flags alone before any work: its output folders, its
/// thread counts, its memory and output estimated from the inputs.
#[derive(Debug, Clone, Default)]
pub struct Plan {
    folders: Vec<Folder>,
    threads: Vec<(String, usize)>,
    pool: usize,
    memory: Vec<Estimate>,
    output: Vec<Estimate>,
}

impl Plan {
    /// An empty plan: no folder, no threads, no estimate.
    pub fn new() -> Self {
        Self::default()
    }

    /// The run writes into `folder`.
    pub fn folder(mut self, folder: Folder) -> Self {
        // One folder named twice (`--out X --figures X`) is one folder with one lock.
        match self.folders.iter_mut().find(|f| f.dir == folder.dir) {
            Some(f) => {
                f.outputs.extend(folder.outputs);
                f.overwrite |= folder.overwrite;
                f.resume |= folder.resume;
            }
            None => self.folders.push(folder),
        }
        self
    }

    /// The run starts `n` threads as `flag` (e.g. `--threads`) asks.
    pub fn threads(mut self, flag: &str, n: usize) -> Self {
        self.threads.push((flag.to_owned(), n));
        self
    }

    /// The run's body runs on a pool of `n` threads (`--threads`; one: on the calling
    /// thread).
    pub fn pool(mut self, n: usize) -> Self {
        self.pool = n;
        self.threads("--threads", n)
    }

    /// The run holds about `bytes` of memory; `flags` set it (named if it is refused),
    /// `what` says how it was estimated (e.g. `BP3 on dx = 1 m: 6.7e9 nodes`).
    pub fn memory(mut self, bytes: f64, flags: &str, what: impl Into<String>) -> Self {
        self.memory.push(Estimate {
            bytes,
            flags: flags.to_owned(),
            what: what.into(),
        });
        self
    }

    /// The run writes about `bytes` of files; `flags` set it, `what` says how.
    pub fn output(mut self, bytes: f64, flags: &str, what: impl Into<String>) -> Self {
        self.output.push(Estimate {
            bytes,
            flags: flags.to_owned(),
            what: what.into(),
        });
        self
    }

    /// Checks the threads and the estimates against `limits`.
    ///
    /// # Errors
    /// The first refused thread count or estimate, naming its flags.
    pub fn check(&self, limits: Limits) -> Result<(), AnyError> {
        for (flag, n) in &self.threads {
            check_threads(flag, *n)?;
        }
        let total = |e: &[Estimate]| e.iter().map(|e| e.bytes).sum::<f64>();
        for (estimates, limit, name) in [
            (&self.memory, limits.max_memory_gb, "--max-memory-gb"),
            (&self.output, limits.max_output_gb, "--max-output-gb"),
        ] {
            let sum = total(estimates);
            if !(sum <= limit * 1e9) {
                // Name the largest part.
                let worst = estimates
                    .iter()
                    .max_by(|a, b| a.bytes.total_cmp(&b.bytes))
                    .expect("a sum above a positive limit has a part");
                let kind = if name == "--max-memory-gb" {
                    "memory"
                } else {
                    "output"
                };
                return Err(format!(
                    "{}: {}: an estimated {} GB of {kind}, above {name} {limit}: use a smaller \
                     or shorter run, or raise {name} if the machine holds it",
                    worst.flags,
                    worst.what,
                    gb(worst.bytes)
                )
                .into());
            }
        }
        Ok(())
    }
}

/// Gigabytes of `bytes` for a message (`1.234e3`, never 301 digits).
fn gb(bytes: f64) -> String {
    let g = bytes / 1e9;
    if g.is_finite() && g < 1e4 {
        format!("{g:.3}")
    } else {
        format!("{g:.3e}")
    }
}

/// The most threads one run may ask for, and why: the machine's limits on threads
/// (`/proc/sys/kernel/threads-max`, the process limit `RLIMIT_NPROC` from
/// `/proc/self/limits`, half of `/proc/sys/vm/max_map_count` — a thread's stack takes
/// two mappings — and a cgroup's `pids.max` less its `pids.current`) and 4096, beyond
/// which no part of rsf gains anything (its parallel parts split into at most a few
/// tasks per node block) and a count is far more likely a typo.
pub fn max_threads() -> (usize, String) {
    let read = |path: &str| -> Option<usize> {
        std::fs::read_to_string(path)
            .ok()
            .and_then(|s| s.trim().parse().ok())
    };
    let mut best = (4096usize, "rsf's cap on one run's threads".to_owned());
    let mut take = |n: Option<usize>, why: &str| {
        if let Some(n) = n.filter(|&n| n < best.0) {
            best = (n, why.to_owned());
        }
    };
    take(read("/proc/sys/kernel/threads-max"), "kernel.threads-max");
    take(
        read("/proc/sys/vm/max_map_count").map(|m| m / 2),
        "vm.max_map_count / 2",
    );
    let nproc = std::fs::read_to_string("/proc/self/limits")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("Max processes"))
                .and_then(|l| l.split_whitespace().nth(2)?.parse().ok())
        });
    take(nproc, "the process limit RLIMIT_NPROC");
    for dir in ["/sys/fs/cgroup", "/sys/fs/cgroup/pids"] {
        let max = read(&format!("{dir}/pids.max"));
        let used = read(&format!("{dir}/pids.current")).unwrap_or(0);
        take(max.map(|m| m.saturating_sub(used)), "the cgroup's pids.max");
    }
    best
}

/// Checks a thread count `n` given by `flag`: at least 1 and at most [`max_threads`].
///
/// # Errors
/// A message naming the flag, the count, the limit and where it comes from.
pub fn check_threads(flag: &str, n: usize) -> Result<(), AnyError> {
    if n == 0 {
        return Err(refuse(flag, n, "must be at least 1"));
    }
    let (max, why) = max_threads();
    if n > max {
        return Err(refuse(
            flag,
            n,
            &format!(
                "above the {max} threads one run may start on this machine ({why}; it has {} \
                 cores)",
                rsf::Parallelism::available_cores()
            ),
        ));
    }
    Ok(())
}

/// A program of the workspace: its flags (clap), its name (in its folders' manifests) and
/// its [`Plan`].
pub trait Program: clap::Parser + Send + 'static {
    /// The program's name, as its run folders' manifests name it.
    const NAME: &'static str;

    /// `--max-memory-gb` and `--max-output-gb` as given.
    fn limits(&self) -> Limits;

    /// What the run needs, from the flags alone (no work: no model built, no file
    /// touched). Every flag is checked here and named as the user wrote it.
    ///
    /// # Errors
    /// The first refused flag.
    fn plan(&self) -> Result<Plan, AnyError>;
}

/// What the guard prepared: the file mode of each folder of the plan (in order) and their
/// locks, held until this is dropped.
#[derive(Debug)]
pub struct Prepared {
    modes: Vec<FileMode>,
    pool: usize,
    _locks: Vec<File>,
}

impl Prepared {
    /// The file mode of the first folder ([`FileMode::Create`], or
    /// [`FileMode::Overwrite`] when an earlier run's files are replaced;
    /// [`FileMode::Create`] on resume, whose files are checked by their writers).
    pub fn mode(&self) -> FileMode {
        self.modes.first().copied().unwrap_or(FileMode::Create)
    }

    /// The file modes of the folders, in the plan's order.
    pub fn modes(&self) -> &[FileMode] {
        &self.modes
    }
}

/// Everything before the work of a run of `program`: its plan, the threads, the
/// estimates, the folders (created, locked, prepared).
///
/// # Errors
/// The first refusal, naming the flag, the key or the path.
pub fn prepare<P: Program>(program: &P) -> Result<Prepared, AnyError> {
    let plan = program.plan()?;
    plan.check(program.limits())?;
    let mut modes = Vec::new();
    let mut locks = Vec::new();
    for f in &plan.folders {
        if f.resume && f.overwrite {
            return Err(format!(
                "--overwrite: a run that continues the files in {} `{}` (--resume, --reuse) \
                 cannot replace them: leave out --overwrite to continue them, or the flag \
                 that continues them to start anew",
                f.flag,
                f.dir.display()
            )
            .into());
        }
        let lock = flag(f.flag, lock(&f.dir))?;
        let outputs: Vec<&str> = f.outputs.iter().map(String::as_str).collect();
        let folder = RunFolder::new(&f.dir, P::NAME, &outputs);
        modes.push(flag(f.flag, folder.prepare(f.resume, f.overwrite))?);
        locks.push(lock);
    }
    Ok(Prepared {
        modes,
        pool: plan.pool,
        _locks: locks,
    })
}

/// `P`'s flags from the command line (a negative number is a value); exits with clap's
/// message on a parse error or `--help`.
fn parse<P: Program>() -> P {
    let command = P::command().mut_args(|a| {
        if a.get_action().takes_values() {
            a.allow_negative_numbers(true)
        } else {
            a
        }
    });
    P::from_arg_matches(&command.get_matches())
        .unwrap_or_else(|e| e.format(&mut P::command()).exit())
}

/// Runs `P` as a program: parses its flags (a negative number is a value), [`prepare`]s its run and runs `body` (on a
/// pool of the plan's threads if it asks for more than one); prints `error: …` with its
/// causes and exits with code 1 on any error.
pub fn main<P: Program>(body: fn(P, Prepared) -> Result<(), AnyError>) -> ExitCode {
    // Negative numbers are values (`--end-years -1` is refused with the valid range, not
    // taken for a flag `-1`).
    let program = parse::<P>();
    let prepared = match prepare(&program) {
        Ok(p) => p,
        Err(e) => return main_with(|| Err(e)),
    };
    match prepared.pool {
        0 | 1 => main_with(|| body(program, prepared)),
        n => main_on_threads(n, move || body(program, prepared)),
    }
}

/// [`main`] on the processes of a job (MPI ranks, `processes`): every rank parses and
/// checks the flags and plans the run; rank 0 alone prepares the folders (creates, locks,
/// checks them) — the others get a [`Prepared`] without folders, and a body writes its
/// files on rank 0 only. `body` gets the processes. Any rank's error (its refusal, the
/// body's error) is printed with the rank and ends every rank
/// ([`Processes::end_all`]): a rank that returned would leave the others waiting. The one
/// exception is the stop at `--max-steps`, which every rank reaches at the same step: each
/// rank returns failure, rank 0 printing the message.
pub fn main_on_ranks<P: Program>(
    processes: &dyn Processes,
    body: fn(P, Prepared, &dyn Processes) -> Result<(), AnyError>,
) -> ExitCode {
    let program = parse::<P>();
    let prepared = if processes.rank() == 0 {
        prepare(&program)
    } else {
        plan_only(&program)
    };
    let step_cap = std::sync::atomic::AtomicBool::new(false);
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
        Some(rsf::Error::InvalidParameter { name, .. }) if name == "max_steps"
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
        _locks: Vec::new(),
    })
}

/// Creates the folder `dir` and takes its exclusive lock (held while the returned file is
/// open: a second run into the folder is refused at once; the lock ends with the process,
/// also when it is killed). On Unix the lock is the folder's own (`flock` on the folder),
/// elsewhere a file `rsf-run.lock` inside it.
///
/// # Errors
/// The folder cannot be created (the path and the operating system's cause), or another
/// run holds its lock.
pub fn lock(dir: &Path) -> Result<File, AnyError> {
    let shown = dir.display();
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("cannot create the output folder `{shown}`: {e}"))?;
    #[cfg(unix)]
    let file = File::open(dir);
    #[cfg(not(unix))]
    let file = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(dir.join("rsf-run.lock"));
    let file = file.map_err(|e| format!("cannot open the output folder `{shown}`: {e}"))?;
    match file.try_lock() {
        Ok(()) => Ok(file),
        Err(std::fs::TryLockError::WouldBlock) => Err(format!(
            "another run is writing into `{shown}` (it holds the folder's lock): wait for it \
             to end, or choose another folder"
        )
        .into()),
        Err(std::fs::TryLockError::Error(e)) => {
            Err(format!("cannot lock the output folder `{shown}`: {e}").into())
        }
    }
}
