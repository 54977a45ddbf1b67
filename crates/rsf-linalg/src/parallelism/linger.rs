//! Bounded polling of idle pool threads between parallel regions that follow each other
//! closely ([`Parallelism::linger`]). An idle rayon thread yields to the operating system
//! for a few dozen rounds — microseconds — and then sleeps on a futex; waking it again
//! costs a system call on both sides and, on a virtual machine, an interprocessor
//! interrupt. The lingering task keeps one thread in rayon's own work loop instead
//! ([`rayon::yield_now`] runs what it finds), the way OpenMP runtimes spin for a "block
//! time" before they sleep.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use super::Parallelism;

/// Lingering tasks running or queued, of all pools. Never more than a linger's
/// `threads − 1` of them: a lingering task that ran another inside its polling would
/// nest them without bound.
static LINGERING: AtomicUsize = AtomicUsize::new(0);

impl Parallelism {
    /// How long a lingering thread polls after the last work it found
    /// ([`linger`](Self::linger)): longer than the sequential work between two
    /// fault-ODE evaluations (about 15 µs on SEAS BP1 at Δz = 25 m; docs/scaling.md,
    /// "Idle threads that poll"), short against anything a user would notice as a busy
    /// core.
    pub const LINGER: Duration = Duration::from_micros(200);

    /// After a parallel region when the next one follows within microseconds: unless
    /// `threads − 1` tasks are lingering already, a task on rayon's current pool that
    /// polls the pool, running whatever work it finds (the next regions' tasks), until
    /// none has come for [`LINGER`](Self::LINGER). Only the timing changes — which tasks
    /// exist and what they compute stay the same, so results keep their bits. Does
    /// nothing for [`SEQ`](Self::SEQ) or when called outside a rayon pool (a region
    /// entered from outside is handed to the pool and back anyway). A lingering task
    /// that the calling thread itself picks up later returns at once.
    pub fn linger(self) {
        let Some(caller) = rayon::current_thread_index() else {
            return;
        };
        let wanted = self.threads() - 1;
        let claimed = LINGERING.fetch_update(Ordering::AcqRel, Ordering::Acquire, |n| {
            (n < wanted).then_some(n + 1)
        });
        if claimed.is_err() {
            return;
        }
        rayon::spawn(move || {
            if rayon::current_thread_index() != Some(caller) {
                poll(Self::LINGER);
            }
            LINGERING.fetch_sub(1, Ordering::AcqRel);
        });
    }
}

/// Runs the pool's pending work until none has come for `idle`.
fn poll(idle: Duration) {
    let mut since = Instant::now();
    loop {
        if rayon::yield_now() == Some(rayon::Yield::Executed) {
            since = Instant::now();
        } else if since.elapsed() >= idle {
            return;
        }
        for _ in 0..32 {
            std::hint::spin_loop();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lingering leaves results and their bits alone, comes back on its own and never
    /// stacks up: a thousand regions with a linger after each on a two-thread pool give
    /// the sums of the sequential run, and once the pool is idle for longer than
    /// `LINGER` no lingering task is left.
    #[test]
    fn lingering_changes_no_result_and_ends() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let data: Vec<f64> = (0..4096).map(|i| (i as f64 * 0.37).sin()).collect();
        let (lo, hi) = data.split_at(2048);
        let seq = (lo.iter().sum::<f64>(), hi.iter().sum::<f64>());
        let p = Parallelism::rayon(2);
        pool.install(|| {
            for _ in 0..1000 {
                let sums = p.join(|| lo.iter().sum::<f64>(), || hi.iter().sum::<f64>());
                assert_eq!(sums.0.to_bits(), seq.0.to_bits());
                assert_eq!(sums.1.to_bits(), seq.1.to_bits());
                p.linger();
                assert!(LINGERING.load(Ordering::Acquire) <= 1);
            }
        });
        let start = Instant::now();
        while LINGERING.load(Ordering::Acquire) != 0 {
            assert!(
                start.elapsed() < Duration::from_secs(10),
                "a lingering task did not end"
            );
            std::thread::sleep(Duration::from_millis(1));
        }
        Parallelism::SEQ.linger();
        Parallelism::rayon(2).linger(); // outside any pool: nothing
        assert_eq!(LINGERING.load(Ordering::Acquire), 0);
    }
}
