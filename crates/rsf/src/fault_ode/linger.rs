//! Bounded polling of idle pool threads between the fault ODE's evaluations, which follow
//! each other within microseconds ([`FaultOdeOptions::linger`](super::FaultOdeOptions)).
//! An idle rayon thread yields to the operating system for a few dozen rounds —
//! microseconds — and then sleeps on a futex; waking it again costs a system call on both
//! sides and, on a virtual machine, an interprocessor interrupt. The lingering task keeps
//! one thread in rayon's own work loop instead ([`rayon::yield_now`] runs what it finds),
//! the way OpenMP runtimes spin for a "block time" before they sleep.
//!
//! Only the fault ODE lingers (its evaluations come every ~15 µs of sequential
//! Runge–Kutta work), so the policy lives here, next to it, and not in the workspace's
//! thread count (`rsf_linalg::Parallelism`, which held it until issue 59).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use rsf_linalg::Parallelism;

/// How long a lingering thread polls after the last work it found by default
/// ([`FaultOdeOptions::linger`](super::FaultOdeOptions) `None`): longer than the
/// sequential work between two fault-ODE evaluations (about 15 µs on SEAS BP1 at
/// Δz = 25 m; docs/scaling.md, "Idle threads that poll"), short against anything a user
/// would notice as a busy core.
pub const LINGER: Duration = Duration::from_micros(200);

thread_local! {
    /// Lingering tasks running or queued that this thread started. Never more than a
    /// linger's `threads − 1` of them: a lingering task that ran another inside its
    /// polling would nest them without bound. One counter per calling thread, so two runs
    /// in one process — on two pools, or on two threads of one pool — neither share nor
    /// spend each other's lingering (a thread of a pool belongs to that pool only).
    static LINGERING: Arc<AtomicUsize> = Arc::new(AtomicUsize::new(0));
}

/// How long [`linger`] polls when called now with the setting `idle`: `idle` when set,
/// else [`LINGER`] — or zero (off) when rayon's current pool has more threads than the
/// machine has cores ([`Parallelism::available_cores`]), where a polling thread would
/// take a core from a thread with work.
pub(super) fn linger_time(idle: Option<Duration>) -> Duration {
    match idle {
        Some(idle) => idle,
        None if rayon::current_num_threads() > Parallelism::available_cores() => Duration::ZERO,
        None => LINGER,
    }
}

/// After a parallel region on `par`'s threads when the next one follows within
/// microseconds: unless `threads − 1` tasks started by this thread are lingering already,
/// a task on rayon's current pool that polls the pool, running whatever work it finds (the
/// next regions' tasks), until none has come for [`linger_time`]`(idle)`. Only the timing
/// changes — which tasks exist and what they compute stay the same, so results keep their
/// bits. Does nothing for one thread, when the linger time is zero, or when called outside
/// a rayon pool (a region entered from outside is handed to the pool and back anyway). A
/// lingering task that the calling thread itself picks up later returns at once. Returns
/// whether it started a task.
pub(super) fn linger(par: Parallelism, idle: Option<Duration>) -> bool {
    let Some(caller) = rayon::current_thread_index() else {
        return false;
    };
    let wanted = par.threads() - 1;
    if wanted == 0 {
        return false;
    }
    let idle = linger_time(idle);
    if idle.is_zero() {
        return false;
    }
    let count = LINGERING.with(Arc::clone);
    let claimed = count.fetch_update(Ordering::AcqRel, Ordering::Acquire, |n| {
        (n < wanted).then_some(n + 1)
    });
    if claimed.is_err() {
        return false;
    }
    rayon::spawn(move || {
        if rayon::current_thread_index() != Some(caller) {
            poll(idle);
        }
        count.fetch_sub(1, Ordering::AcqRel);
    });
    true
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

    /// The lingering tasks this thread started and not yet ended.
    fn lingering_here() -> Arc<AtomicUsize> {
        LINGERING.with(Arc::clone)
    }

    /// Waits until no lingering task of `count` is left; panics after 10 s.
    fn wait_until_none(count: &AtomicUsize) -> Duration {
        let start = Instant::now();
        while count.load(Ordering::Acquire) != 0 {
            assert!(
                start.elapsed() < Duration::from_secs(10),
                "a lingering task did not end"
            );
            std::thread::sleep(Duration::from_millis(1));
        }
        start.elapsed()
    }

    /// What lingering could break, asserted: it starts a task after a region when on, at
    /// most `threads − 1` at a time, and the tasks end on their own once the pool is idle
    /// (none left — a task that never stopped polling would spin a core for ever);
    /// configured off (`Some(ZERO)`), with one thread, or outside a pool it starts none; a
    /// second caller's lingering does not stop the first's (one count per calling thread,
    /// not per process).
    #[test]
    fn lingering_starts_when_on_never_stacks_and_ends() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        // Long enough that a task is still polling when the next call comes.
        let p = Parallelism::rayon(2);
        let long = Some(Duration::from_millis(50));
        assert_eq!(linger_time(long), Duration::from_millis(50));
        let count = pool.install(|| {
            let count = lingering_here();
            assert!(linger(p, long), "on: a lingering task");
            for _ in 0..100 {
                p.join(|| (), || ());
                linger(p, long);
                assert!(count.load(Ordering::Acquire) <= 1, "more than threads − 1");
            }
            count
        });
        wait_until_none(&count);
        // Off: no task, however often called.
        let off = Some(Duration::ZERO);
        pool.install(|| {
            let count = lingering_here();
            for _ in 0..100 {
                assert!(!linger(p, off));
                assert!(!linger(Parallelism::SEQ, long));
                assert_eq!(count.load(Ordering::Acquire), 0);
            }
        });
        assert!(!linger(p, None), "outside any pool");
        // Two callers on two pools: each starts its own task while the other's polls.
        let other = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let (a, b) = pool.install(|| {
            let a = lingering_here();
            assert!(linger(p, long));
            let b = other.install(|| {
                let b = lingering_here();
                assert!(linger(p, long), "the other pool's caller lingers too");
                b
            });
            (a, b)
        });
        wait_until_none(&a);
        wait_until_none(&b);
    }

    /// The default: [`LINGER`] on a pool no larger than the machine, off on one whose
    /// threads outnumber its cores.
    #[test]
    fn lingering_is_off_by_default_on_an_oversubscribed_pool() {
        let cores = Parallelism::available_cores();
        let fits = rayon::ThreadPoolBuilder::new()
            .num_threads(cores.max(2))
            .build()
            .unwrap();
        let p = Parallelism::rayon(2);
        let on = fits.install(|| linger_time(None));
        if cores >= 2 {
            assert_eq!(on, LINGER);
        }
        let over = rayon::ThreadPoolBuilder::new()
            .num_threads(cores + 1)
            .build()
            .unwrap();
        let count = over.install(|| {
            assert_eq!(linger_time(None), Duration::ZERO);
            let count = lingering_here();
            assert!(!linger(p, None), "oversubscribed: no lingering by default");
            assert_eq!(count.load(Ordering::Acquire), 0);
            // Set explicitly, it lingers even there, and ends.
            assert!(linger(p, Some(LINGER)));
            count
        });
        wait_until_none(&count);
    }
}
