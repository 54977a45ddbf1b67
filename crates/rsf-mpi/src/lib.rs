//! MPI ranks for rsf (docs/scaling.md, "Past one machine"): [`MpiRanks`], one MPI
//! communicator — `MPI_COMM_WORLD` ([`initialize`], [`MpiRanks::world`]) or a duplicate of
//! one ([`MpiRanks::duplicate`]) — as the workspace's transport
//! ([`rsf_ranks::RankGroup`]: halo exchanges by nonblocking point-to-point messages,
//! all-gathers by `MPI_Allgatherv`) and as the processes of a job
//! ([`rsf_ranks::Processes`]: the groups of a program's collectives and its solvers'
//! transports, each a duplicate of the communicator; a barrier; `MPI_Abort` for an error).
//! With it [`FaultOde::share_evaluations`](rsf::FaultOde::share_evaluations) splits every
//! evaluation of the fault ODE's right-hand side (the rows of the fault operator's product
//! — dense, ℋ or the half-space operator — and their nodes' friction solves) between the
//! ranks and gathers the rates with one `MPI_Allgatherv`. The trajectory has the same bits
//! at every rank count. Binaries: `seas_bp1`, `seas_bp3`, `seas_bp5` (`rsf-programs`'
//! programs), and `slider_3d`, whose velocity solves are TNNMG on the ranks
//! ([`rsf::method::TnnmgOnRanks`]; docs/scaling.md, "Phase 5").
//!
//! Every rank runs the whole program (the same scene, options and state); only the
//! evaluations are shared — and `seas_bp5 --kernel fe`'s elimination of the volume, which
//! rank 0 does alone and the other ranks read from the run folder's `setup.bin` (so one
//! process, not every one, holds its memory; the folder must be on a file system every
//! rank sees). A program writes its files on rank 0 (`slider_3d`'s VTU frames are the
//! exception: every rank writes its piece) and ends every rank on an error with
//! [`Processes::end_all`](rsf_ranks::Processes::end_all) (an error on one rank must not
//! leave the others waiting in a collective).
//!
//! This crate is outside the workspace's default build (it needs an MPI library and
//! clang); `cargo build --release --manifest-path crates/rsf-mpi/Cargo.toml`.
//!
//! The implicit engine's distributed smoother (rsf-ranks' `DistributedSweep`, below
//! rsf-tnnmg's V-cycle and TNNMG on ranks) runs its halo exchanges over MPI through
//! [`MpiRanks`]; the binary `distributed_sweep` runs it on a refined elastic box and
//! measures it (docs/scaling.md, "Phase 2").
#![warn(missing_docs)]

mod halo;
mod ranks;

pub use ranks::MpiRanks;

use mpi::environment::Universe;
use mpi::Threading;
use rsf_ranks::Processes;

/// What can go wrong when MPI starts.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// `MPI_Init_thread` was already called (MPI starts once per process).
    #[error("MPI is already initialised in this process")]
    AlreadyInitialised,
    /// The MPI library gives less than `MPI_THREAD_SERIALIZED`: the fault ODE calls MPI
    /// from the thread that runs it, which need not be the main thread.
    #[error(
        "the MPI library gives thread support {0:?}; rsf needs Serialized (calls from any \
         thread, one at a time)"
    )]
    ThreadSupport(Threading),
    /// More ranks or values than MPI's `int` counts hold.
    #[error("{0} does not fit MPI's int counts")]
    Count(usize),
}

/// Starts MPI (`MPI_Init_thread` with `MPI_THREAD_SERIALIZED`): the universe (MPI ends
/// when it is dropped, at the end of the program) and the world's ranks.
///
/// # Errors
/// [`Error::AlreadyInitialised`]; [`Error::ThreadSupport`] if the library gives less than
/// serialised calls from several threads.
pub fn initialize() -> Result<(Universe, MpiRanks), Error> {
    let (universe, threading) =
        mpi::initialize_with_threading(Threading::Serialized).ok_or(Error::AlreadyInitialised)?;
    if matches!(threading, Threading::Single | Threading::Funneled) {
        return Err(Error::ThreadSupport(threading));
    }
    Ok((universe, MpiRanks::world()))
}

/// The writers of `--hdf5 N` for the SEAS programs on ranks: crates/rsf-hdf5's with this
/// crate's feature `hdf5` (rank 0 writes the fault's fields), none without it (the programs'
/// plans then refuse `--hdf5 N`, naming the feature).
pub fn field_writers() -> rsf_programs::fields::Writers {
    #[cfg(feature = "hdf5")]
    {
        Some(rsf_hdf5::programs::Hdf5Writers::shared())
    }
    #[cfg(not(feature = "hdf5"))]
    {
        None
    }
}

/// Starts MPI and runs a program of `rsf-programs` on the world's ranks ([`MpiRanks::world`])
/// (`program`: e.g. `rsf_programs::seas_bp1::main_on_ranks`); MPI ends when the program
/// returns. A failure to start MPI is printed as `error: …` with exit code 1.
pub fn main_on_ranks(
    program: impl FnOnce(&dyn Processes) -> std::process::ExitCode,
) -> std::process::ExitCode {
    match initialize() {
        // The world's handle and every duplicate made from it are dropped (freed) before
        // the universe ends MPI.
        Ok((_universe, ranks)) => program(&ranks),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
