//! MPI ranks for rsf (docs/scaling.md, "Past one machine"): [`MpiRanks`], the
//! [`rsf::ranks::RankGroup`] of the processes of `MPI_COMM_WORLD`, with which
//! [`FaultOde::share_evaluations`](rsf::FaultOde::share_evaluations) splits every
//! evaluation of the fault ODE's right-hand side (the rows of the fault operator's product
//! — dense, ℋ or the half-space operator — and their nodes' friction solves) between the
//! ranks and gathers the rates with one `MPI_Allgatherv`. The trajectory has the same bits
//! at every rank count. Binaries: `seas_bp1`, `seas_bp3`, `seas_bp5` (`rsf-programs`'
//! programs), and `slider_3d`, whose velocity solves are TNNMG on the ranks
//! ([`rsf::method::TnnmgOnRanks`] over [`MpiExchange`]; docs/scaling.md, "Phase 5").
//!
//! Every rank runs the whole program (the same scene, options and state); only the
//! evaluations are shared — and `seas_bp5 --kernel fe`'s elimination of the volume, which
//! rank 0 does alone and the other ranks read from the run folder's `setup.bin` (so one
//! process, not every one, holds its memory; the folder must be on a file system every
//! rank sees). A program writes its files on rank 0 ([`MpiRanks::is_root`];
//! `slider_3d`'s VTU frames are the exception: every rank writes its piece)
//! and ends every rank on an error with [`end_all_ranks`] (an error on one rank must not
//! leave the others waiting in a collective).
//!
//! This crate is outside the workspace's default build (it needs an MPI library and
//! clang); `cargo build --release --manifest-path crates/rsf-mpi/Cargo.toml`.
//!
//! The implicit engine's distributed smoother (rsf-ranks' `DistributedSweep`, below
//! rsf-tnnmg's V-cycle and TNNMG on ranks) runs its halo exchanges over MPI through
//! [`MpiExchange`]; the binary `distributed_sweep` runs it on a refined elastic box and
//! measures it (docs/scaling.md, "Phase 2").
#![warn(missing_docs)]

mod halo;

pub use halo::MpiExchange;

use mpi::datatype::PartitionMut;
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::{Communicator, CommunicatorCollectives};
use mpi::Threading;
use rsf_ranks::{HaloMessage, RankGroup};

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

/// The ranks of `MPI_COMM_WORLD` as an [`rsf::ranks::RankGroup`].
///
/// Holds no handle (every call takes the world communicator afresh), so it is `Send`; MPI
/// was initialised with `MPI_THREAD_SERIALIZED`, so the fault ODE may call it from any
/// thread, one call at a time (a fault ODE evaluates on one thread at a time).
#[derive(Debug, Clone)]
pub struct MpiRanks {
    rank: usize,
    size: usize,
    /// `MPI_Allgatherv`'s counts and displacements, in buffers kept between calls: no
    /// allocation per evaluation.
    partition: Partition,
}

/// The counts and displacements of an `MPI_Allgatherv` (MPI's `int`) of a rank-ordered
/// concatenation, in buffers kept between calls (no allocation once they hold the rank
/// count).
#[derive(Debug, Clone, Default)]
pub(crate) struct Partition {
    counts: Vec<i32>,
    displs: Vec<i32>,
}

impl Partition {
    /// `recv` partitioned by `counts`: rank `r`'s `counts[r]` values at
    /// `counts[..r].iter().sum()`.
    ///
    /// # Panics
    /// If a count or displacement does not fit MPI's `int` (more than 2³¹ values), or
    /// `recv` is shorter than the counts' sum.
    pub(crate) fn of<'a>(
        &'a mut self,
        recv: &'a mut [f64],
        counts: &[usize],
    ) -> PartitionMut<'a, [f64], &'a [i32], &'a [i32]> {
        let to_int = |c: usize| i32::try_from(c).unwrap_or_else(|_| panic!("{}", Error::Count(c)));
        self.counts.clear();
        self.displs.clear();
        let mut at = 0usize;
        for &c in counts {
            self.counts.push(to_int(c));
            self.displs.push(to_int(at));
            at += c;
        }
        assert!(recv.len() >= at, "all_gather: the sum of the counts");
        PartitionMut::new(recv, &self.counts[..], &self.displs[..])
    }
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
    let world = universe.world();
    let ranks = MpiRanks {
        rank: usize::try_from(world.rank()).expect("MPI ranks are not negative"),
        size: usize::try_from(world.size()).expect("MPI sizes are positive"),
        partition: Partition::default(),
    };
    Ok((universe, ranks))
}

impl MpiRanks {
    /// Whether this is rank 0, the one that writes a program's files.
    pub fn is_root(&self) -> bool {
        self.rank == 0
    }

    /// Waits until every rank is here (`MPI_Barrier`).
    pub fn barrier(&self) {
        SimpleCommunicator::world().barrier();
    }
}

impl RankGroup for MpiRanks {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.size
    }

    /// Point-to-point messages over `MPI_COMM_WORLD` ([`halo::exchange_on`]).
    ///
    /// # Panics
    /// As [`MpiExchange`]'s.
    fn exchange(
        &mut self,
        sends: &[HaloMessage],
        send: &[f64],
        recvs: &[HaloMessage],
        recv: &mut [f64],
    ) {
        let world = SimpleCommunicator::world();
        halo::exchange_on(&world, (self.rank, self.size), sends, send, recvs, recv);
    }

    /// `MPI_Allgatherv` over `MPI_COMM_WORLD`.
    ///
    /// # Panics
    /// If a count does not fit MPI's `int` (more than 2³¹ values per rank: far beyond a
    /// fault an evaluation can hold), or `own` is not `counts[rank]` long.
    fn all_gather(&mut self, own: &[f64], counts: &[usize], all: &mut [f64]) {
        assert_eq!(own.len(), counts[self.rank], "this rank's share");
        let mut partition = self.partition.of(all, counts);
        SimpleCommunicator::world().all_gather_varcount_into(own, &mut partition);
    }
}

/// Ends every rank: writes `message` (prefixed with this rank) to standard error and calls
/// `MPI_Abort` with exit code 1, which ends every process of the job — where returning
/// would leave the other ranks waiting in their next collective.
pub fn end_all_ranks(ranks: &MpiRanks, message: &dyn std::fmt::Display) -> ! {
    // One write of the whole line: `eprintln!` writes its pieces one by one, and the
    // launcher's abort banner (another process on the same stderr) can land between them.
    let line = format!("rank {} of {}: {message}\n", ranks.rank, ranks.size);
    let _ = std::io::Write::write_all(&mut std::io::stderr().lock(), line.as_bytes());
    SimpleCommunicator::world().abort(1)
}

/// The ranks of `MPI_COMM_WORLD` as the processes of a program of `rsf-programs`
/// ([`rsf_programs::ranks::Processes`]): what `rsf_programs::seas_bp1::main_on_ranks` runs on.
#[derive(Debug, Clone)]
pub struct Job(pub MpiRanks);

impl rsf_programs::ranks::Processes for Job {
    fn rank(&self) -> usize {
        self.0.rank
    }

    fn size(&self) -> usize {
        self.0.size
    }

    fn group(&self) -> Box<dyn rsf::ranks::RankGroup + Send> {
        Box::new(self.0.clone())
    }

    /// A new [`MpiExchange::world`] (a duplicate of the world communicator) per call.
    fn transports(&self) -> rsf::method::TransportFactory {
        std::sync::Arc::new(|| -> Box<dyn RankGroup> { Box::new(MpiExchange::world()) })
    }

    fn end_all(&self, message: &str) -> ! {
        end_all_ranks(&self.0, &message)
    }
}

/// Starts MPI and runs a program of `rsf-programs` on the world's ranks
/// (`program`: e.g. `rsf_programs::seas_bp1::main_on_ranks`); MPI ends when the program
/// returns. A failure to start MPI is printed as `error: …` with exit code 1.
pub fn main_on_ranks(
    program: fn(&dyn rsf_programs::ranks::Processes) -> std::process::ExitCode,
) -> std::process::ExitCode {
    match initialize() {
        Ok((_universe, ranks)) => program(&Job(ranks)),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
