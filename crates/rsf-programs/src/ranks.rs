//! The processes of a job (MPI ranks) as a program sees them: its rank, the group that
//! shares its fault ODE's evaluations ([`rsf::ranks::RankGroup`]), the transports of TNNMG's
//! solves on ranks, and how an error ends them all. The MPI implementation lives in the `rsf-mpi` crate (outside the default build);
//! this package's programs take any implementation ([`guard::main_on_ranks`](crate::guard::main_on_ranks)).

/// The processes of a job.
pub trait Processes: Sync {
    /// This process's rank, in `0..size()`; rank 0 writes the files.
    fn rank(&self) -> usize;

    /// The number of processes (≥ 1).
    fn size(&self) -> usize;

    /// The group that shares a fault ODE's evaluations
    /// ([`rsf::FaultOde::share_evaluations`]), or that writes VTU frames in pieces
    /// ([`rsf::observe::VtuFrames::pieces`]: one all-gather per frame).
    fn group(&self) -> Box<dyn rsf::ranks::RankGroup + Send>;

    /// The transports of TNNMG's solves on these processes
    /// ([`rsf::method::TnnmgOnRanks::transport`]): each call of the factory (collective:
    /// every rank builds its solvers in the same order) gives this rank's end of a fresh
    /// group of all the processes (over MPI: a duplicate of the world communicator).
    fn transports(&self) -> rsf::method::TransportFactory;

    /// Prints `message` (with this rank) and ends every process of the job with a failure
    /// code: an error on one rank must not leave the others waiting in a collective.
    fn end_all(&self, message: &str) -> !;

    /// Returns when every process has called it: a collective, called once by every
    /// process at the same point of the program (one value each through
    /// [`group`](Self::group)'s `all_gather`, which no process can finish before every
    /// other has contributed). What one process wrote before it (rank 0's set-up in the
    /// run folder) is there for the others after it.
    fn barrier(&self) {
        let size = self.size();
        let counts = vec![1; size];
        let mut all = vec![0.0; size];
        self.group().all_gather(&[1.0], &counts, &mut all);
    }
}
