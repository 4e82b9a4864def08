//! A request to stop long work (Ctrl-C), seen inside a step.
//!
//! [`request`] is one atomic store, safe to call from a signal handler: the bindings' SIGINT
//! handler calls it while a long call runs. The step looks at it where one step can take long
//! (between the pair blocks of n-body gravity, between Newton and CG iterations, and after
//! each pass of the step loop); a step that sees it is rolled back, bitwise, and the call
//! answers [`crate::Error::Interrupted`], the steps before it taken. The request stays until
//! [`clear`]. A replay of good steps (after a divergence, `World::run`) is never
//! interrupted: it must give the same bits as the run it replays.

use std::cell::Cell;
use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

thread_local! {
    /// Replays under way on this thread: their steps do not look at the request.
    static MASKED: Cell<u32> = const { Cell::new(0) };
}

/// Asks the steps under way (on any thread) to stop: one atomic store, async-signal-safe.
pub fn request() {
    REQUESTED.store(true, Ordering::Relaxed);
}

/// Withdraws the request; returns whether there was one.
pub fn clear() -> bool {
    REQUESTED.swap(false, Ordering::Relaxed)
}

/// Whether a stop was requested (and not cleared).
#[must_use]
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// Whether the step under way on this thread should stop: a request, outside a replay.
#[inline]
#[must_use]
pub(crate) fn stop() -> bool {
    watching() && requested()
}

/// Whether the steps on this thread look at the request (not inside a replay).
#[inline]
#[must_use]
pub(crate) fn watching() -> bool {
    MASKED.with(Cell::get) == 0
}

/// While it lives, the steps on this thread do not look at the request.
pub(crate) struct Masked(());

impl Masked {
    pub(crate) fn new() -> Self {
        MASKED.with(|m| m.set(m.get() + 1));
        Self(())
    }
}

impl Drop for Masked {
    fn drop(&mut self) {
        MASKED.with(|m| m.set(m.get() - 1));
    }
}
