//! The processes of a job as a program sees them ([`Processes`]: its rank, its groups, how
//! an error ends them all), and their test double on threads of one process
//! ([`ThreadProcess`]).

use std::sync::Arc;

use crate::transport::on_threads;
use crate::{RankGroup, ThreadGroups, TransportFactory};

/// The processes of a job (MPI ranks in the `rsf-mpi` crate, threads of one process in
/// the tests: [`ThreadProcess`]) as a program sees them: its rank, the groups its
/// collectives run on, and how an error on one rank ends them all. The programs of
/// `rsf-programs` take any implementation (`rsf_programs::guard::main_on_ranks`).
pub trait Processes: Sync {
    /// This process's rank, in `0..size()`; rank 0 writes a program's files.
    fn rank(&self) -> usize;

    /// The number of processes (≥ 1).
    fn size(&self) -> usize;

    /// A group of all the processes for the collectives of the program's own thread, in
    /// program order: the fault ODE's shared evaluations (`rsf::FaultOde::share_evaluations`),
    /// VTU frames written in pieces (`rsf::observe::VtuFrames::pieces`), the agreement on
    /// the flags, [`barrier`](Self::barrier). Collective: every rank makes its calls in the
    /// same order.
    fn group(&self) -> Box<dyn RankGroup + Send>;

    /// The transports of solvers on these processes (`rsf::method::TnnmgOnRanks`): each call
    /// of the factory (collective: every rank builds its solvers in the same order) gives
    /// this rank's end of a fresh group of all the processes, whose messages never meet
    /// another group's (over MPI: a duplicate of the world communicator).
    fn transports(&self) -> TransportFactory;

    /// Prints `message` (with this rank) and ends every process of the job with a failure
    /// code: an error on one rank must not leave the others waiting in a collective.
    fn end_all(&self, message: &str) -> !;

    /// Returns when every process has called it: a collective, called once by every
    /// process at the same point of the program. What one process wrote before it (rank
    /// 0's set-up in the run folder) is there for the others after it.
    ///
    /// The default is one all-gather of one value per rank on a [`group`](Self::group),
    /// which no process can finish before every other has contributed; a transport with a
    /// barrier of its own (MPI's `MPI_Barrier`) overrides it.
    fn barrier(&self) {
        let size = self.size();
        let counts = vec![1; size];
        let mut all = vec![0.0; size];
        self.group().all_gather(&[1.0], &counts, &mut all);
    }
}

/// One rank of a job whose ranks are threads of this process: its ends of fresh groups of
/// the same [`ThreadGroups`], one per [`group`](Processes::group) call and per call of its
/// [`transports`](Processes::transports)' factory (every rank calls in the same order).
/// [`end_all`](Processes::end_all) panics: the other ranks' threads end when their
/// partner's channels close. The test double of an MPI job.
#[derive(Debug, Clone)]
pub struct ThreadProcess {
    rank: usize,
    groups: Arc<ThreadGroups>,
}

impl ThreadProcess {
    /// The ranks of a new job of `size` thread ranks, in rank order: give each to its own
    /// thread.
    ///
    /// # Panics
    /// If `size == 0`.
    pub fn job(size: usize) -> Vec<Self> {
        let groups = ThreadGroups::new(size);
        (0..size)
            .map(|rank| Self {
                rank,
                groups: Arc::clone(&groups),
            })
            .collect()
    }

    /// Runs `run` on every rank of a new job of `size` ([`job`](Self::job)), each rank on a
    /// scoped thread of its own, and returns the results in rank order.
    ///
    /// # Panics
    /// If `size == 0`; with the panic of a rank whose `run` panicked (the lowest such rank).
    pub fn run<T: Send>(size: usize, run: impl Fn(Self) -> T + Sync) -> Vec<T> {
        on_threads(Self::job(size), run)
    }
}

impl Processes for ThreadProcess {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.groups.size()
    }

    fn group(&self) -> Box<dyn RankGroup + Send> {
        Box::new(self.groups.take(self.rank))
    }

    fn transports(&self) -> TransportFactory {
        self.groups.factory(self.rank)
    }

    fn end_all(&self, message: &str) -> ! {
        panic!("rank {} of {}: {message}", self.rank, self.size())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three thread ranks: rank 0 writes before the barrier, every rank reads after it;
    /// each group and each transport of a rank meets the same call of the other ranks.
    #[test]
    fn a_thread_job_meets_in_its_barrier_groups_and_transports() {
        let written = std::sync::Mutex::new(None);
        let seen = ThreadProcess::run(3, |p| {
            if p.rank() == 0 {
                *written.lock().unwrap() = Some(7.0);
            }
            p.barrier();
            let before = written
                .lock()
                .unwrap()
                .expect("rank 0 wrote before the barrier");
            let mut all = [0.0; 3];
            p.group()
                .all_gather(&[p.rank() as f64], &[1, 1, 1], &mut all);
            let transports = p.transports();
            let mut t = transports();
            let mut sums = [0.0; 3];
            t.all_gather(&[10.0 * p.rank() as f64], &[1, 1, 1], &mut sums);
            (before, all, sums)
        });
        for s in seen {
            assert_eq!(s, (7.0, [0.0, 1.0, 2.0], [0.0, 10.0, 20.0]));
        }
    }
}
