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

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Bytes of a program's process before its problem: the binary, its libraries, the
/// thread pool's stacks, the font and figure buffers (measured as the peak of the
/// smallest runs of docs/reliability.md's "Memory estimates" table), rounded up. Every
/// plan's memory estimate includes it ([`Plan::memory_bytes`]); re-exported by
/// the module `estimates`.
pub const PROCESS_BYTES: f64 = 64e6;

use rsf::checkpoint::Fingerprint;
use rsf::observe::FileMode;
use rsf::run_folder::RunFolder;

use crate::process::{main_on_threads, main_with};

mod fixed;
mod flags;
mod ranks;

pub use flags::*;
pub use ranks::{agree_on_flags, main_on_ranks, main_on_ranks_supplied};

/// One output folder of a run: the flag that names it, the files the run writes there,
/// whether the run continues an earlier one (`--resume`, `--reuse`) or replaces it
/// (`--overwrite`).
#[derive(Debug, Clone)]
pub struct Folder {
    flag: &'static str,
    dir: PathBuf,
    outputs: Vec<String>,
    resume: bool,
    /// The checkpoint a resume continues from (`--resume FILE`).
    checkpoint: Option<PathBuf>,
    /// The fields of `--allow-change` (they need a checkpoint).
    allow_change: Vec<String>,
    /// The fingerprint of the run's checkpoints, where the plan knows it: a checkpoint is
    /// checked against it before the folder changes.
    fingerprint: Option<Fingerprint>,
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
            checkpoint: None,
            allow_change: Vec::new(),
            fingerprint: None,
            overwrite: false,
        }
    }

    /// Replaces an earlier run's files (`--overwrite`).
    pub fn overwrite(mut self, overwrite: bool) -> Self {
        self.overwrite = overwrite;
        self
    }

    /// Continues the run in the folder without a checkpoint (`--reuse`): its own files
    /// are kept. A program with `--resume FILE` uses [`resume_from`](Self::resume_from)
    /// instead, so that the checkpoint's run is compared with the folder's.
    pub fn reuse(mut self, reuse: bool) -> Self {
        self.resume = reuse;
        self
    }

    /// Continues the run in the folder from `checkpoint` (`--resume FILE`; `None`: a new
    /// run): its files are kept, and a checkpoint of another run than the folder's is
    /// refused unless [`overwrite`](Self::overwrite)
    /// ([`RunFolder::prepare_resume`]).
    pub fn resume_from(mut self, checkpoint: Option<&Path>) -> Self {
        self.resume = checkpoint.is_some();
        self.checkpoint = checkpoint.map(Path::to_path_buf);
        self
    }

    /// The fields a resume may change (`--allow-change`): refused without a checkpoint
    /// to resume (they would be ignored); the fields themselves are checked against the
    /// checkpoint's fingerprint when it is read.
    pub fn allow_change(mut self, fields: &[String]) -> Self {
        self.allow_change = fields.to_vec();
        self
    }

    /// The fingerprint the run's checkpoints carry, where the plan knows it from the flags
    /// (one function for the plan and the run): a resume checks the checkpoint against it
    /// (and `--allow-change`) before the folder changes — with `--overwrite`, before it is
    /// given to the checkpoint's run ([`RunFolder::expecting`]).
    pub fn fingerprint(mut self, fingerprint: Fingerprint) -> Self {
        self.fingerprint = Some(fingerprint);
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
    /// The step cap the plan's output bound needs (an adaptive run whose output would not
    /// fit otherwise), and what it is for.
    step_cap: Option<(u64, String)>,
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
                f.checkpoint = f.checkpoint.take().or(folder.checkpoint);
                f.allow_change.extend(folder.allow_change);
                f.fingerprint = f.fingerprint.take().or(folder.fingerprint);
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

    /// The run stops after `cap` steps in total (across resumes), for `why` (an output
    /// bound of an adaptive run, [`rsf::run_folder::output_plan`]); the smallest of the caps
    /// asked for holds ([`Prepared::step_cap`]).
    pub fn cap_steps(mut self, cap: u64, why: impl Into<String>) -> Self {
        if self.step_cap.as_ref().is_none_or(|(c, _)| cap < *c) {
            self.step_cap = Some((cap, why.into()));
        }
        self
    }

    /// The plan's step cap ([`cap_steps`](Self::cap_steps)), `None` without one.
    pub fn step_cap(&self) -> Option<u64> {
        self.step_cap.as_ref().map(|(cap, _)| *cap)
    }

    /// The run's memory estimate (bytes): the process itself
    /// ([`PROCESS_BYTES`]) and every part of the plan.
    pub fn memory_bytes(&self) -> f64 {
        PROCESS_BYTES + self.memory.iter().map(|e| e.bytes).sum::<f64>()
    }

    /// The run's output estimate (bytes): every part of the plan.
    pub fn output_bytes(&self) -> f64 {
        self.output.iter().map(|e| e.bytes).sum()
    }

    /// Checks the threads and the estimates against `limits`.
    ///
    /// # Errors
    /// The first refused thread count or estimate, naming its flags.
    pub fn check(&self, limits: Limits) -> Result<(), AnyError> {
        if let Some(f) = self
            .folders
            .iter()
            .find(|f| !f.allow_change.is_empty() && f.checkpoint.is_none())
        {
            return Err(format!(
                "--allow-change: needs --resume (the fields a resume may change; a new run into \
                 {} `{}` has nothing to change, it would be ignored)",
                f.flag,
                f.dir.display()
            )
            .into());
        }
        for (flag, n) in &self.threads {
            check_threads(flag, *n)?;
        }
        let output = self.output_bytes();
        for (estimates, sum, limit, name) in [
            (
                &self.memory,
                self.memory_bytes(),
                limits.max_memory_gb,
                "--max-memory-gb",
            ),
            (
                &self.output,
                output,
                limits.max_output_gb,
                "--max-output-gb",
            ),
        ] {
            if !(sum <= limit * 1e9) {
                let kind = if name == "--max-memory-gb" {
                    "memory"
                } else {
                    "output"
                };
                // Name the largest part (or the process itself).
                let (flags, what) = estimates
                    .iter()
                    .max_by(|a, b| a.bytes.total_cmp(&b.bytes))
                    .map_or((name, "the process itself"), |w| {
                        (w.flags.as_str(), w.what.as_str())
                    });
                return Err(format!(
                    "{flags}: {what}: an estimated {} GB of {kind}, above {name} {}: use a \
                     smaller or shorter run, or raise {name} if the machine holds it",
                    gb(sum),
                    written(limit)
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

    /// The program after its flags are parsed, given what clap read (`matches`): a
    /// program with a run configuration reads its `--config` file here, the flags given on
    /// the command line taking precedence over the file's keys
    /// ([`crate::config::ConfigArgs::merged`]). The default keeps the flags as parsed.
    ///
    /// # Errors
    /// The configuration file's (unreadable, malformed, an unknown key).
    fn configure(self, matches: &clap::ArgMatches) -> Result<Self, AnyError>
    where
        Self: Sized,
    {
        let _ = matches;
        Ok(self)
    }
}

/// The two items every [`Program`](crate::guard::Program) writes alike, inside its `impl
/// Program for …` block: `const NAME` (the literal `$name`) and `fn limits`, the
/// arguments' field `limits` ([`Limits`](crate::guard::Limits), flattened into the flags:
/// `--max-memory-gb`, `--max-output-gb`) or the
/// field path given after the name (`output.limits` for a field of a flattened group).
///
/// ```
/// use rsf_programs::guard::{AnyError, Limits, Plan, Program};
///
/// #[derive(clap::Parser)]
/// struct Cli {
///     #[command(flatten)]
///     limits: Limits,
/// }
///
/// impl Program for Cli {
///     rsf_programs::name_and_limits!("toy");
///
///     fn plan(&self) -> Result<Plan, AnyError> {
///         Ok(Plan::new())
///     }
/// }
///
/// assert_eq!(Cli::NAME, "toy");
/// ```
#[macro_export]
macro_rules! name_and_limits {
    ($name:literal) => {
        $crate::name_and_limits!($name, limits);
    };
    ($name:literal, $($field:ident).+) => {
        const NAME: &'static str = $name;

        fn limits(&self) -> $crate::guard::Limits {
            self.$($field).+
        }
    };
}

/// What the guard prepared: the file mode of each folder of the plan (in order) and their
/// locks, held until this is dropped.
#[derive(Debug)]
pub struct Prepared {
    modes: Vec<FileMode>,
    pool: usize,
    /// The plan's memory estimate (bytes), compared with the measured peak at the end.
    memory: f64,
    /// The plan's step cap and what it is for ([`Plan::cap_steps`]).
    step_cap: Option<(u64, String)>,
    _locks: Vec<File>,
}

impl Prepared {
    /// The file mode of the first folder ([`FileMode::Create`], or
    /// [`FileMode::Overwrite`] when an earlier run's files are replaced;
    /// [`FileMode::Create`] on resume, whose files are checked by their writers).
    pub fn mode(&self) -> FileMode {
        self.modes.first().copied().unwrap_or(FileMode::Create)
    }

    /// The run's step cap: the smaller of `max_steps` (`--max-steps`) and the plan's
    /// ([`Plan::cap_steps`]), `None` without either. Where the plan's is the smaller, says
    /// so on standard error (how many steps, what for, how to go on).
    pub fn step_cap(&self, max_steps: Option<u64>) -> Option<u64> {
        match (&self.step_cap, max_steps) {
            (Some((cap, why)), given) if given.is_none_or(|m| *cap < m) => {
                eprintln!(
                    "at most {cap} steps: {why} (the run stops there with a checkpoint; \
                     resume it with a larger --max-steps or --max-output-gb)"
                );
                Some(*cap)
            }
            (_, given) => given,
        }
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
    let command = command_line();
    for f in &plan.folders {
        if f.resume && f.overwrite && f.checkpoint.is_none() {
            return Err(format!(
                "--overwrite: a run that continues the files in {} `{}` (--reuse) cannot \
                 replace them: leave out --overwrite to continue them, or the flag that \
                 continues them to start anew",
                f.flag,
                f.dir.display()
            )
            .into());
        }
        let lock = flag(f.flag, lock(&f.dir))?;
        let outputs: Vec<&str> = f.outputs.iter().map(String::as_str).collect();
        let mut folder = RunFolder::new(&f.dir, P::NAME, &outputs).command(&command);
        if let Some(fingerprint) = &f.fingerprint {
            folder = folder.expecting(fingerprint.clone(), &f.allow_change);
        }
        let mode = match &f.checkpoint {
            // The checkpoint's run against the folder's (issue 74): a resume into another
            // run's folder would cut that run's files and continue another run in them.
            // A checkpoint that cannot be read — of another kind, refused by its type and
            // first bytes (issue 87) — is named by --resume, not by the folder's flag.
            Some(checkpoint) => match folder.prepare_resume(checkpoint, f.overwrite) {
                Err(e @ rsf::Error::InvalidParameter { .. }) => flag("--allow-change", Err(e)),
                Err(
                    e @ (rsf::Error::CheckpointCorrupt { .. }
                    | rsf::Error::CheckpointMismatch { .. }
                    | rsf::Error::File {
                        action: "read the checkpoint",
                        ..
                    }),
                ) => flag("--resume", Err(e)),
                mode => flag(f.flag, mode),
            },
            None => flag(f.flag, folder.prepare(f.resume, f.overwrite)),
        };
        modes.push(mode?);
        locks.push(lock);
    }
    Ok(Prepared {
        modes,
        pool: plan.pool,
        memory: plan.memory_bytes(),
        step_cap: plan.step_cap,
        _locks: locks,
    })
}

/// This process's command line as a run's manifest records it: the program's file name
/// and its arguments, an argument with a space or a quote in single quotes.
fn command_line() -> String {
    let mut args = std::env::args_os();
    let program = args
        .next()
        .map(|p| {
            Path::new(&p)
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
        })
        .unwrap_or_default();
    std::iter::once(program)
        .chain(args.map(|a| {
            let a = a.to_string_lossy().into_owned();
            if a.is_empty() || a.contains(|c: char| c.is_whitespace() || c == '\'' || c == '"') {
                format!("'{}'", a.replace('\'', "'\\''"))
            } else {
                a
            }
        }))
        .collect::<Vec<_>>()
        .join(" ")
}

/// `P`'s command with a negative number taken as a value.
fn command<P: Program>() -> clap::Command {
    P::command().mut_args(|a| {
        if a.get_action().takes_values() {
            a.allow_negative_numbers(true)
        } else {
            a
        }
    })
}

/// `P`'s flags from the command line (a negative number is a value) and the flags as
/// given ([`given_flags`]); exits with clap's message on a parse error or `--help`.
fn parse<P: Program>() -> (Result<P, AnyError>, String) {
    let matches = command::<P>().get_matches();
    let program =
        P::from_arg_matches(&matches).unwrap_or_else(|e| e.format(&mut P::command()).exit());
    (program.configure(&matches), given_flags::<P>(&matches))
}

/// `P`'s flags from `args` (the first is the program's name; a negative number is a
/// value) and the flags as given ([`given_flags`]).
///
/// # Errors
/// clap's error (a malformed or unknown flag, `--help`, `--version`).
pub fn parse_from<P: Program, I, T>(args: I) -> Result<(P, String), clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let matches = command::<P>().try_get_matches_from(args)?;
    let program = P::from_arg_matches(&matches)?
        .configure(&matches)
        .map_err(|e| clap::Error::raw(clap::error::ErrorKind::ValueValidation, format!("{e}\n")))?;
    Ok((program, given_flags::<P>(&matches)))
}

/// The run's flags as the ranks of a job must agree on them ([`agree_on_flags`]): the
/// program's name, then one line per flag given on the command line, as clap read it
/// (`--end-years 5`, whatever the spelling: `--end-years=5` too), in the order of the
/// program's flags. Defaults are not listed: every rank runs the same program, so they
/// agree (but for those that depend on the machine, e.g. `--threads`, which change no
/// bit).
pub fn given_flags<P: Program>(matches: &clap::ArgMatches) -> String {
    let mut lines = vec![format!("the program `{}`", P::NAME)];
    for arg in P::command().get_arguments() {
        let id = arg.get_id().as_str();
        if matches.value_source(id) != Some(clap::parser::ValueSource::CommandLine) {
            continue;
        }
        let name = arg
            .get_long()
            .map_or_else(|| id.to_owned(), |l| format!("--{l}"));
        let values: Vec<String> = match matches.try_get_raw(id) {
            Ok(Some(v)) if arg.get_action().takes_values() => {
                v.map(|x| x.to_string_lossy().into_owned()).collect()
            }
            _ => Vec::new(),
        };
        lines.push(if values.is_empty() {
            name
        } else {
            format!("{name} {}", values.join(","))
        });
    }
    lines.join("\n")
}

/// Runs `P` as a program: parses its flags (a negative number is a value), [`prepare`]s its run and runs `body` (on a
/// pool of the plan's threads if it asks for more than one); prints `error: …` with its
/// causes and exits with code 1 on any error.
pub fn main<P: Program>(body: fn(P, Prepared) -> Result<(), AnyError>) -> ExitCode {
    main_supplied(|_| {}, body)
}

/// [`main`] with `supply` applied to the flags once parsed, before the plan: what the
/// binary supplies beyond the flags (the writers of `--hdf5`,
/// [`FieldArgs::supply`](crate::fields::FieldArgs::supply)).
pub fn main_supplied<P: Program>(
    supply: impl FnOnce(&mut P),
    body: fn(P, Prepared) -> Result<(), AnyError>,
) -> ExitCode {
    // Negative numbers are values (`--end-years -1` is refused with the valid range, not
    // taken for a flag `-1`).
    let (program, _) = parse::<P>();
    let mut program = match program {
        Ok(p) => p,
        Err(e) => return main_with(|| Err(e)),
    };
    supply(&mut program);
    let prepared = match prepare(&program) {
        Ok(p) => p,
        Err(e) => return main_with(|| Err(e)),
    };
    let estimate = prepared.memory;
    let code = match prepared.pool {
        0 | 1 => main_with(|| body(program, prepared)),
        n => main_on_threads(n, move || body(program, prepared)),
    };
    report_memory(P::NAME, estimate, None);
    code
}

/// The process's peak resident memory so far (bytes; Linux's `VmHWM` of
/// `/proc/self/status`, what `/usr/bin/time -v` reports as its maximum resident set),
/// `None` where the system does not say.
pub fn peak_memory_bytes() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

/// The environment variable that makes a program print its memory estimate and its
/// measured peak when it ends (`tests/memory_estimates.rs` reads them).
pub const MEMORY_REPORT: &str = "RSF_MEMORY_REPORT";

/// At the end of a run: with [`MEMORY_REPORT`] set, the line `rsf-memory: program=NAME
/// estimate_bytes=E peak_bytes=P` on standard error; and a warning whenever the measured
/// peak exceeded the plan's estimate (an estimate is a bound: docs/reliability.md,
/// "Memory estimates" — a run above it is worth reporting). `rank`: the rank of a job's
/// process, named in the warning.
fn report_memory(program: &str, estimate: f64, rank: Option<usize>) {
    let Some(peak) = peak_memory_bytes() else {
        return;
    };
    if std::env::var_os(MEMORY_REPORT).is_some() {
        eprintln!(
            "rsf-memory: program={program} estimate_bytes={estimate:.0} peak_bytes={peak:.0}"
        );
    }
    if estimate > 0.0 && peak > estimate {
        eprintln!(
            "warning: {}{program}'s peak memory, {} GB, exceeded its estimate of {} GB (the \
             estimates are bounds, docs/reliability.md \"Memory estimates\": please report \
             the flags of this run)",
            rank.map_or(String::new(), |r| format!("rank {r}: ")),
            gb(peak),
            gb(estimate)
        );
    }
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

#[cfg(test)]
mod tests;
