//! What the SEAS programs and the fault networks (`seas_bp1` … `seas_bp8`, `stepover`,
//! `bp5_pair`) share in their flags and plans: the [`Program`](crate::guard::Program)
//! of arguments with a run configuration ([`configured_program!`]) and the last lines of
//! every plan — the thread pool, the run folder `--out` and the fault's fields `--hdf5`
//! ([`RunFlags::plan`]) — and what their runs share: the session, the fields' observer and
//! the run with its observers ([`RunFlags::session`], [`RunFlags::fields_observer`],
//! [`run_observed`]). Built with the feature `seas`.

#![cfg(feature = "seas")]

use std::path::Path;

use rsf::checkpoint::Fingerprint;
use rsf::observe::{FileMode, Progress};
use rsf::{Observer, RunSummary, Stepping};

use crate::cli::ResumeArgs;
use crate::fields::{FaultSize, FieldArgs, FieldWriters, FieldsRun, FieldsTarget};
use crate::guard::{AnyError, Folder, Limits, Plan};
use crate::session::Session;

/// The flags a SEAS program or fault network ends with (in one group, flattened into its
/// arguments as the field `job`): how the run resumes ([`ResumeArgs`]: `--checkpoint-every`,
/// `--resume`, `--allow-change`, `--max-steps`), the fault's fields ([`FieldArgs`]: `--hdf5
/// N`) and the bounds ([`Limits`]: `--max-memory-gb`, `--max-output-gb`).
#[derive(Debug, Clone, clap::Args)]
pub(crate) struct JobArgs {
    /// `--checkpoint-every N`, `--resume FILE`, `--allow-change`, `--max-steps N`.
    #[command(flatten)]
    pub run: ResumeArgs,
    /// `--hdf5 N`: the fault's fields (the binaries of crates/rsf-hdf5).
    #[command(flatten)]
    pub fields: FieldArgs,
    /// `--max-memory-gb`, `--max-output-gb`.
    #[command(flatten)]
    pub limits: Limits,
}

/// The flags of a run beside its settings, borrowed from a program's arguments
/// (`flags()`, made by [`configured_program!`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct RunFlags<'a> {
    /// The program's name (as `--hdf5`'s refusal names it).
    pub(crate) program: &'static str,
    /// `--out`.
    pub(crate) out: &'a Path,
    /// `--overwrite`.
    pub(crate) overwrite: bool,
    /// `--threads`.
    pub(crate) threads: usize,
    /// `--checkpoint-every`, `--resume`, `--allow-change`, `--max-steps`.
    pub(crate) run: &'a ResumeArgs,
    /// `--hdf5`.
    pub(crate) fields: &'a FieldArgs,
    /// `--max-memory-gb`, `--max-output-gb`.
    pub limits: Limits,
}

impl RunFlags<'_> {
    /// `plan` (the run's estimates) on a pool of `--threads`, its folder `--out` holding
    /// `outputs` (the files the run writes there) and the fields' files of `--hdf5`
    /// ([`FIELD_OUTPUTS`](crate::fields::FIELD_OUTPUTS)), `--overwrite`, the resume flags
    /// and the run's `fingerprint` judged by the guard.
    pub(crate) fn folder(
        &self,
        plan: Plan,
        outputs: Vec<String>,
        fingerprint: Fingerprint,
    ) -> Plan {
        let mut names: Vec<&str> = outputs.iter().map(String::as_str).collect();
        names.extend(crate::fields::FIELD_OUTPUTS);
        let folder = Folder::new("--out", self.out, &names).overwrite(self.overwrite);
        plan.pool(self.threads)
            .folder(self.run.folder(folder).fingerprint(fingerprint))
    }

    /// [`folder`](Self::folder)'s plan with the fields of a fault of `fault`'s size
    /// (`--hdf5`: [`FieldArgs::adaptive_output`], bounded by `--max-steps` and what
    /// `--max-output-gb` leaves).
    ///
    /// # Errors
    /// The fields' output bound, naming `--hdf5` and `--max-steps` or `--max-output-gb`.
    pub(crate) fn plan(
        &self,
        plan: Plan,
        outputs: Vec<String>,
        fingerprint: Fingerprint,
        fault: FaultSize,
    ) -> Result<Plan, AnyError> {
        let plan = self.folder(plan, outputs, fingerprint);
        self.fields
            .adaptive_output(plan, fault, self.run.max_steps, self.limits)
    }

    /// The run's session ([`Session::start`]: `--resume`, `--allow-change`,
    /// `--checkpoint-every`) with its checkpoint `OUT/checkpoint.bin` of `fingerprint`, to
    /// the time `end` (s) or the step cap `step_cap` (`--max-steps`, or the plan's:
    /// [`Prepared::step_cap`](crate::guard::Prepared::step_cap)): the checkpoint it
    /// continues checked and `method` restored from it before any file is touched.
    ///
    /// # Errors
    /// The checkpoint's (unreadable, of another run, after `end`).
    pub(crate) fn session<const D: usize, const C: usize, M: Stepping<D, C> + ?Sized>(
        &self,
        step_cap: Option<u64>,
        fingerprint: Fingerprint,
        end: f64,
        method: &mut M,
    ) -> Result<Session, AnyError> {
        let flags = self.run.session_flags_with_cap(step_cap);
        let checkpoint = self.out.join("checkpoint.bin");
        Ok(Session::start(flags, checkpoint, fingerprint, end, method)?)
    }

    /// The observer of the fields (`--hdf5 N`, made by `make`: [`FieldArgs::observer`];
    /// `None` without the flag) of the run of `session`, a new run's file in the mode
    /// `fresh`: the file proves it holds the checkpoint's run before any file is cut.
    ///
    /// # Errors
    /// The writer's, named `--hdf5`.
    pub(crate) fn fields_observer<O: ?Sized>(
        &self,
        session: &Session,
        fresh: FileMode,
        make: impl FnOnce(&dyn FieldWriters, &FieldsTarget<'_>) -> rsf::Result<Box<O>>,
    ) -> Result<Option<Box<O>>, AnyError> {
        let run = FieldsRun::of(session, fresh, &self.run.allow_change);
        self.fields.observer((self.program, self.out), run, make)
    }
}

/// Runs `session` on `method` to its end ([`Session::run`]) with the observers `files`,
/// then the fields' observer `fields` if there is one ([`RunFlags::fields_observer`]),
/// showing `progress`.
///
/// # Errors
/// The run's ([`Session::run`]).
pub(crate) fn run_observed<'a, const D: usize, const C: usize, M: Stepping<D, C> + ?Sized>(
    session: Session,
    method: &mut M,
    mut files: Vec<&'a mut dyn Observer<D, C>>,
    fields: &'a mut Option<Box<dyn Observer<D, C>>>,
    progress: Progress,
) -> Result<RunSummary, AnyError> {
    if let Some(f) = fields {
        files.push(f.as_mut());
    }
    Ok(session.run(method, &mut files, Some(progress))?)
}

/// `impl Program for $args`, the arguments of a program with a run configuration and the
/// fields `settings` (its settings), `config` (`--config`, [`ConfigArgs`]), `out`,
/// `overwrite`, `threads`, `run` ([`ResumeArgs`]), `fields` ([`FieldArgs`]) and `limits`
/// ([`Limits`]), the last three those of the field `$group` ([`JobArgs`]) where it is
/// named: its name `$name`, its limits, `--config`'s file read into the settings
/// (the flags given win: [`ConfigArgs::merged`]), and its plan — the settings checked
/// ([`ConfigArgs::validate`]), `--hdf5` refused by a build without writers
/// ([`FieldArgs::check`]), then the plan of `$args`'s own `fn planned(&self)`. Also
/// `$args::flags`, the [`RunFlags`] of the arguments.
///
/// [`ConfigArgs`]: crate::config::ConfigArgs
/// [`ConfigArgs::merged`]: crate::config::ConfigArgs::merged
/// [`ConfigArgs::validate`]: crate::config::ConfigArgs::validate
macro_rules! configured_program {
    ($args:ty, $name:literal $(, $group:ident)?) => {
        impl $crate::guard::Program for $args {
            $crate::name_and_limits!($name, $($group.)? limits);

            fn configure(
                mut self,
                matches: &clap::ArgMatches,
            ) -> Result<Self, $crate::guard::AnyError> {
                self.settings = self.config.merged(self.settings, matches)?;
                Ok(self)
            }

            fn plan(&self) -> Result<$crate::guard::Plan, $crate::guard::AnyError> {
                self.config.validate(&self.settings)?;
                self$(.$group)?.fields.check($name)?;
                self.planned()
            }
        }

        impl $args {
            /// The flags of the run beside its settings.
            pub(crate) fn flags(&self) -> $crate::seas_args::RunFlags<'_> {
                $crate::seas_args::RunFlags {
                    program: $name,
                    out: &self.out,
                    overwrite: self.overwrite,
                    threads: self.threads,
                    run: &self$(.$group)?.run,
                    fields: &self$(.$group)?.fields,
                    limits: self$(.$group)?.limits,
                }
            }
        }
    };
}

pub(crate) use configured_program;

/// The three entry points of a program that runs in one process or on the processes of a
/// job (`seas_bp1`, `seas_bp3`, `seas_bp5`), each documented by the attributes before its
/// name: `main()` (one process: [`guard::main`](crate::guard::main)),
/// `main_with_fields(writers)` (one process with `writers` of the fault's fields, `--hdf5
/// N`: the binaries of crates/rsf-hdf5) and `main_on_ranks(processes, writers)` (MPI
/// ranks, with the writers if the build has them:
/// [`guard::main_on_ranks_supplied`](crate::guard::main_on_ranks_supplied)). Each runs the
/// body `$run(args: $args, prepared, processes)`, `processes` `None` in one process (with
/// threads, the whole run on the pool: no hand-over per parallel region). The writers go to
/// the arguments' field `fields`, or to `$group.fields` ([`JobArgs`]) where `$group` is named.
macro_rules! ranked_entry_points {
    (
        $args:ty, $run:path $(, $group:ident)?;
        $(#[$main:meta])* main,
        $(#[$fields:meta])* main_with_fields,
        $(#[$ranks:meta])* main_on_ranks $(,)?
    ) => {
        $(#[$main])*
        pub fn main() -> std::process::ExitCode {
            $crate::guard::main(|args, prepared| $run(args, prepared, None))
        }

        $(#[$fields])*
        pub fn main_with_fields(
            writers: std::sync::Arc<dyn $crate::fields::FieldWriters>,
        ) -> std::process::ExitCode {
            $crate::guard::main_supplied(
                |args: &mut $args| args$(.$group)?.fields.supply(writers),
                |args, prepared| $run(args, prepared, None),
            )
        }

        $(#[$ranks])*
        pub fn main_on_ranks(
            processes: &dyn rsf_ranks::Processes,
            writers: $crate::fields::Writers,
        ) -> std::process::ExitCode {
            let supply = |args: &mut $args| args$(.$group)?.fields.supply_if(writers);
            $crate::guard::main_on_ranks_supplied(processes, supply, |a, f, p| {
                $run(a, f, Some(p))
            })
        }
    };
}

pub(crate) use ranked_entry_points;

/// The two entry points of a program that runs in one process (`seas_bp6`, `seas_bp7`,
/// `seas_bp8`, `stepover`, `bp5_pair`), named `$name` in their documentation: `main()`
/// ([`guard::main`](crate::guard::main)) and `main_with_fields(writers)` (with `writers`
/// of the fault's fields supplied to `--hdf5 N`, [`JobArgs`]' field `fields`: the binaries
/// of crates/rsf-hdf5, whose writer `crate::fields::$writer` the run calls). Each runs
/// `$run(args: $args, prepared)`.
macro_rules! entry_points {
    ($args:ty, $run:path, $name:literal, $writer:literal) => {
        #[doc = concat!("The program `", $name, "`.")]
        pub fn main() -> std::process::ExitCode {
            $crate::guard::main($run)
        }

        #[doc = concat!(
            "The program `", $name, "` with `writers` of the fields (`--hdf5 N`, [`", $writer,
            "`](crate::fields::", $writer, "); the binary `", $name, "` of crates/rsf-hdf5)."
        )]
        pub fn main_with_fields(
            writers: std::sync::Arc<dyn $crate::fields::FieldWriters>,
        ) -> std::process::ExitCode {
            $crate::guard::main_supplied(|args: &mut $args| args.job.fields.supply(writers), $run)
        }
    };
}

pub(crate) use entry_points;
