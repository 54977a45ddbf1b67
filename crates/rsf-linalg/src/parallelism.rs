//! The one parallelism parameter of the workspace (docs/design.md, "Parallelism").

use std::num::NonZeroUsize;
use std::sync::OnceLock;

use crate::error::{Error, Result};

/// How many threads the parallel parts of a computation may use: the direct solver's
/// sweeps and dense factorisations (`rsf-tnnmg`), the rows of the integrators'
/// right-hand side (`rsf-time`), and, through `rsf::SolverOptions::parallelism`, every
/// one of them at once.
///
/// As faer's [`Par`](faer::Par) (and convertible to and from it): [`SEQ`](Self::SEQ) runs
/// everything on the calling thread; [`rayon(n)`](Self::rayon) with `n ≥ 2` lets a
/// computation split into at most `n` tasks on rayon's **current** thread pool (the global
/// pool unless the caller `install`s another), so a pool of fewer threads runs them on
/// fewer. Each parallel part still runs sequentially below its own size threshold
/// (`rsf_tnnmg::DENSE_PARALLEL_MIN`, `rsf_time::LOAD_PARALLEL_MIN_ROWS`, …), where a second
/// thread costs more than it saves.
///
/// Results do not depend on it: every split keeps each entry's arithmetic fixed, so
/// [`SEQ`](Self::SEQ) and any thread count give bit-identical output (tested per crate).
///
/// Default: every core of the machine, [`rayon(available_cores())`](Self::available_cores)
/// (`std::thread::available_parallelism`, read once per process). Since the bits do not
/// depend on the threads, the fast choice costs nothing in reproducibility (issue 59;
/// before, the default was a stated two). A computation that splits into short parallel
/// regions (the fault ODE's evaluations) should run on a thread of the pool
/// (`rayon::ThreadPool::install`): entered from outside, each region hands its work to the
/// pool and back, which on small problems costs more than it saves (docs/scaling.md,
/// "From inside the pool"); [`SEQ`](Self::SEQ) is the choice there. (Whether idle pool
/// threads poll between such regions is the fault ODE's own policy,
/// `rsf::fault_ode::FaultOdeOptions::linger`, not part of the thread count.)
///
/// Names (`FromStr`, `Display`): a thread count (`1`, `2`, …), `0` or `pool` for
/// rayon's current pool size (read once, when parsed), `seq` for one thread.
///
/// ```
/// use rsf_linalg::Parallelism;
/// assert_eq!(Parallelism::default(), Parallelism::rayon(Parallelism::available_cores()));
/// assert_eq!(Parallelism::rayon(1), Parallelism::SEQ);
/// assert!(!Parallelism::SEQ.is_parallel());
/// assert_eq!("4".parse::<Parallelism>().unwrap().threads(), 4);
/// assert_eq!(faer::Par::from(Parallelism::SEQ), faer::Par::Seq);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Parallelism {
    threads: NonZeroUsize,
}

impl Parallelism {
    /// One thread: everything on the calling thread.
    pub const SEQ: Self = Self {
        threads: NonZeroUsize::MIN,
    };

    /// The machine's cores as the process may use them (`std::thread::available_parallelism`,
    /// read at the first call and kept; 1 if it cannot be read): the threads of
    /// [`Default`].
    pub fn available_cores() -> usize {
        static CORES: OnceLock<usize> = OnceLock::new();
        *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, NonZeroUsize::get))
    }

    /// At most `threads` threads of rayon's current pool; `0` means the size of that pool,
    /// read now (as faer's `Par::rayon(0)`), so the value is fixed where it is given.
    /// `1` is [`SEQ`](Self::SEQ).
    pub fn rayon(threads: usize) -> Self {
        let threads = NonZeroUsize::new(threads).unwrap_or_else(|| {
            NonZeroUsize::new(rayon::current_num_threads()).unwrap_or(NonZeroUsize::MIN)
        });
        Self { threads }
    }

    /// The largest number of threads (≥ 1).
    pub fn threads(self) -> usize {
        self.threads.get()
    }

    /// Whether more than one thread may be used.
    pub fn is_parallel(self) -> bool {
        self.threads() > 1
    }

    /// faer's parallelism for the same threads (`Par::Seq` for one).
    pub fn faer(self) -> faer::Par {
        if self.is_parallel() {
            faer::Par::Rayon(self.threads)
        } else {
            faer::Par::Seq
        }
    }

    /// Runs both closures and returns their results: on two threads (rayon's `join`) when
    /// [`is_parallel`](Self::is_parallel), else one after the other on the calling thread.
    /// The split of a computation into `a` and `b` is the caller's and fixed, so the
    /// results do not depend on the threads.
    pub fn join<A, B, RA, RB>(self, a: A, b: B) -> (RA, RB)
    where
        A: FnOnce() -> RA + Send,
        B: FnOnce() -> RB + Send,
        RA: Send,
        RB: Send,
    {
        if self.is_parallel() {
            rayon::join(a, b)
        } else {
            (a(), b())
        }
    }
}

impl Default for Parallelism {
    /// Every core: [`rayon(available_cores())`](Self::available_cores).
    fn default() -> Self {
        Self::rayon(Self::available_cores())
    }
}

impl From<faer::Par> for Parallelism {
    fn from(par: faer::Par) -> Self {
        match par {
            faer::Par::Seq => Self::SEQ,
            faer::Par::Rayon(threads) => Self { threads },
        }
    }
}

impl From<Parallelism> for faer::Par {
    fn from(par: Parallelism) -> Self {
        par.faer()
    }
}

impl std::fmt::Display for Parallelism {
    /// The thread count.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.threads)
    }
}

impl std::str::FromStr for Parallelism {
    type Err = Error;

    /// A thread count, `0` or `pool` (rayon's current pool size), or `seq` (one thread).
    fn from_str(s: &str) -> Result<Self> {
        match s.trim() {
            "seq" => Ok(Self::SEQ),
            "pool" => Ok(Self::rayon(0)),
            t => t
                .parse::<usize>()
                .map(Self::rayon)
                .map_err(|_| Error::InvalidParallelism(s.to_owned())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_conversions() {
        assert_eq!("seq".parse::<Parallelism>().unwrap(), Parallelism::SEQ);
        assert_eq!("1".parse::<Parallelism>().unwrap(), Parallelism::SEQ);
        assert_eq!(" 3 ".parse::<Parallelism>().unwrap().threads(), 3);
        let pool = rayon::current_num_threads();
        assert_eq!("0".parse::<Parallelism>().unwrap().threads(), pool);
        assert_eq!("pool".parse::<Parallelism>().unwrap().threads(), pool);
        for bad in ["", "-1", "two", "1.5"] {
            assert_eq!(
                bad.parse::<Parallelism>(),
                Err(Error::InvalidParallelism(bad.into()))
            );
        }
        for p in [
            Parallelism::SEQ,
            Parallelism::rayon(2),
            Parallelism::rayon(7),
        ] {
            assert_eq!(p.to_string().parse::<Parallelism>().unwrap(), p);
            assert_eq!(Parallelism::from(faer::Par::from(p)), p);
        }
        assert_eq!(Parallelism::from(faer::Par::rayon(1)), Parallelism::SEQ);
        assert_eq!(Parallelism::rayon(3).faer(), faer::Par::rayon(3));
        assert_eq!(
            Parallelism::default().threads(),
            std::thread::available_parallelism().unwrap().get()
        );
    }

    #[test]
    fn join_returns_both_results_on_any_threads() {
        for p in [
            Parallelism::SEQ,
            Parallelism::rayon(2),
            Parallelism::rayon(4),
        ] {
            let data: Vec<u64> = (0..1000).collect();
            let (lo, hi) = data.split_at(500);
            let (a, b) = p.join(|| lo.iter().sum::<u64>(), || hi.iter().sum::<u64>());
            assert_eq!((a, b), (124_750, 374_750));
        }
    }
}
