//! The programs of the `rsf-mpi` crate (its binaries, `crates/rsf-mpi/src/bin/`) as the
//! guard judges them, without MPI: their flags and [`prepare`] —
//! the plan, the limits, the folders — so that the careless-inputs test checks every one of
//! them in the default build, where no MPI library is needed (issue 74). A binary added to
//! the MPI crate must be listed here, or that test fails.

use std::ffi::OsString;

use crate::guard::{parse_from, prepare, AnyError, Program};

/// A program of the MPI crate: its name (its binary's), its clap command and the guard's
/// checks of a command line.
#[derive(Debug, Clone, Copy)]
pub struct RankProgram {
    /// The binary's name.
    pub name: &'static str,
    /// Its flags (for `--help` and the careless-inputs test).
    pub command: fn() -> clap::Command,
    /// Parses `args` (the first the program's name) and [`prepare`]s the run — every
    /// refusal before work, folders created and locked — without running it.
    pub prepare: fn(Vec<OsString>) -> Result<(), AnyError>,
}

fn prepare_only<P: Program>(args: Vec<OsString>) -> Result<(), AnyError> {
    let (program, _) = parse_from::<P, _, _>(args)?;
    prepare(&program).map(drop)
}

fn program<P: Program>(name: &'static str) -> RankProgram {
    RankProgram {
        name,
        command: <P as clap::CommandFactory>::command,
        prepare: prepare_only::<P>,
    }
}

/// Every binary of the MPI crate, by name.
pub fn programs() -> Vec<RankProgram> {
    vec![
        #[cfg(feature = "seas")]
        program::<crate::seas_bp1::Args>("seas_bp1"),
        #[cfg(feature = "seas")]
        program::<crate::seas_bp3::Args>("seas_bp3"),
        #[cfg(feature = "seas")]
        program::<crate::seas_bp5::Args>("seas_bp5"),
        program::<crate::slider_3d::Cli>("slider_3d"),
        program::<crate::distributed_sweep::Args>("distributed_sweep"),
    ]
}
