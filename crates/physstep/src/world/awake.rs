//! The thread pool kept awake across a user force's call.
//!
//! A user force (a Python callable above all) runs on the calling thread while the pool's
//! workers have nothing to do: after a few rounds of looking for work they go to sleep, and
//! the parallel passes that read the forces then start without them (on a virtual machine a
//! sleeping processor takes long to come back). As OpenMP runtimes do by default, the workers
//! wait awake instead, for a bounded time: each runs any pool work there is (a force that runs
//! parallel work of its own gets it done) and otherwise yields its processor to any other
//! thread, until the call ends or [`AWAKE_AT_MOST`] has passed. One worker fewer than the pool
//! has waits: the calling thread holds a processor of its own. A force whose previous call
//! outlasted the bound is not waited for (the passes after it are small beside it), nor one
//! called from a worker of the pool (worlds stepped in parallel: the pool has work).
//!
//! Measured at 1e5 particles under a Python force taking 0.6 ms (`bench/bench_user_force.py`,
//! 2 processors, ten runs interleaved with the build before): the force's own cost in a step
//! went from 1.64-2.06x to 1.33-1.79x the bare numpy expression. What runs is unchanged: the
//! waiting workers touch no data.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How long the workers wait awake at most.
pub(super) const AWAKE_AT_MOST: Duration = Duration::from_millis(2);

/// The pool's workers kept awake during a call, until [`Awake::end`] (or drop).
#[must_use]
pub(super) struct Awake {
    done: Option<Arc<AtomicBool>>,
    start: Instant,
    /// Whether the call outlasted [`AWAKE_AT_MOST`], once it ended.
    outlasted: Option<bool>,
}

impl Awake {
    /// Keeps the pool's workers awake for a call after which parallel passes run over
    /// `particles` particles: not when those passes are not parallel, or when the force's
    /// previous call was `slow` (it outlasted the bound).
    pub(super) fn during(particles: usize, slow: bool) -> Self {
        let start = Instant::now();
        let threads = rayon::current_num_threads();
        if !wanted(particles, slow, threads, rayon::current_thread_index().is_some()) {
            return Self { done: None, start, outlasted: None };
        }
        let done = Arc::new(AtomicBool::new(false));
        for _ in 1..threads {
            let done = Arc::clone(&done);
            rayon::spawn(move || {
                while !done.load(Ordering::Acquire) && start.elapsed() < AWAKE_AT_MOST {
                    if rayon::yield_now() != Some(rayon::Yield::Executed) {
                        std::thread::yield_now();
                    }
                }
            });
        }
        Self { done: Some(done), start, outlasted: None }
    }

    /// Whether workers were woken to wait.
    #[cfg(test)]
    fn waiting(&self) -> bool {
        self.done.is_some()
    }

    /// The call ended (the first call of this counts): the workers stop waiting; whether it
    /// outlasted [`AWAKE_AT_MOST`].
    pub(super) fn end(&mut self) -> bool {
        if let Some(done) = self.done.take() {
            done.store(true, Ordering::Release);
        }
        *self.outlasted.get_or_insert_with(|| self.start.elapsed() > AWAKE_AT_MOST)
    }
}

/// Whether the workers wait awake through a call after which parallel passes run over
/// `particles` particles, the force's previous call `slow`, with `threads` in the pool, called
/// `on_worker` (from a worker of the pool).
fn wanted(particles: usize, slow: bool, threads: usize, on_worker: bool) -> bool {
    !slow && !on_worker && threads >= 2 && particles >= super::tiles::PARALLEL_MIN
}

impl Drop for Awake {
    fn drop(&mut self) {
        self.end();
    }
}

#[cfg(test)]
mod tests {
    use super::{wanted, Awake, AWAKE_AT_MOST};
    use crate::world::tiles::PARALLEL_MIN;

    #[test]
    fn workers_wait_only_where_parallel_passes_follow_from_outside_the_pool_after_a_short_call() {
        assert!(wanted(PARALLEL_MIN, false, 2, false));
        assert!(!wanted(PARALLEL_MIN - 1, false, 2, false), "a serial pass follows");
        assert!(!wanted(PARALLEL_MIN, true, 2, false), "the last call was slow");
        assert!(!wanted(PARALLEL_MIN, false, 1, false), "no other worker");
        assert!(!wanted(PARALLEL_MIN, false, 8, true), "called from a worker of the pool");
        // From a worker: nothing spawned.
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        pool.install(|| assert!(!Awake::during(PARALLEL_MIN, false).waiting()));
        // From outside (this test's thread), as the pool allows.
        let mut awake = Awake::during(PARALLEL_MIN, false);
        assert_eq!(awake.waiting(), rayon::current_num_threads() >= 2);
        awake.end();
        assert!(!awake.waiting(), "ended");
    }

    #[test]
    fn a_call_longer_than_the_bound_is_slow_and_the_first_end_counts() {
        let mut awake = Awake::during(PARALLEL_MIN, false);
        std::thread::sleep(AWAKE_AT_MOST + AWAKE_AT_MOST / 2);
        assert!(awake.end());
        assert!(awake.end(), "the first end is the one that counts");
    }

    #[test]
    fn pool_work_asked_for_during_the_call_is_done_by_the_waiting_workers() {
        use rayon::prelude::*;
        // The call itself runs parallel work (a force that uses the pool): it completes, with
        // the sum a serial loop gives (each item is its own, the sum of integers exact).
        for _ in 0..20 {
            let mut awake = Awake::during(PARALLEL_MIN, false);
            let got: u64 = (0..200_000u64).into_par_iter().map(|i| i % 7).sum();
            awake.end();
            assert_eq!(got, (0..200_000u64).map(|i| i % 7).sum::<u64>());
        }
    }
}
