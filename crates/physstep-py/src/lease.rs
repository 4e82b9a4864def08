//! The lease under which a World lends its state's buffers to zero-copy views (`crate::views`
//! says how the views use it): a World's side, which knows nothing of the views themselves.

use physstep::world::World as Engine;
use std::sync::{Arc, OnceLock};

/// The buffers lent out since the last detach, once they have been retired.
#[derive(Debug, Default)]
pub(crate) struct Lease {
    /// The engine's `[y, f]` of the time the views were made, after a reallocating call.
    pub(crate) retired: OnceLock<[Vec<f64>; 2]>,
}

/// A World's side of its views: the lease its current buffers are lent under.
#[derive(Debug, Default)]
pub(crate) struct Views {
    pub(crate) current: Arc<Lease>,
}

impl Views {
    /// Before a call that may reallocate the engine's state: when views of the current
    /// buffers are alive, the engine gets copies and the buffers are kept for the views.
    pub(crate) fn detach(&mut self, engine: &mut Engine) {
        if Arc::strong_count(&self.current) > 1 {
            let old = engine.detach_state();
            // A lease is current until it is retired, and retired once: `set` finds it empty.
            let _ = self.current.retired.set(old);
            self.current = Arc::default();
        }
    }
}
