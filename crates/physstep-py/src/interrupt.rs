//! Ctrl-C inside a long step (Unix).
//!
//! Python looks at signals only between calls: a step of n-body gravity on 20,000 bodies
//! would hear Ctrl-C after it. While a long call runs, a [`Watch`] puts a
//! SIGINT handler of its own in front of Python's: one atomic store asking the engine to stop
//! inside the step (`physstep::interrupt`, async-signal-safe), then Python's handler, which
//! raises KeyboardInterrupt when the call looks ([`stopped`]). The step under way is rolled
//! back; the steps before it stay taken. Python's handler is put back when the call ends.

use pyo3::prelude::*;

/// Whether an engine answer is a stop asked by Ctrl-C: the request withdrawn, then the
/// exception a user callback raised meanwhile (the KeyboardInterrupt Python raised inside
/// it) or Python's handler run (KeyboardInterrupt, as a rule); when that handler does not
/// raise the call goes on (the step is taken again).
pub(crate) fn stopped(
    py: Python<'_>,
    e: &physstep::Error,
    slot: Option<&crate::slot::Slot>,
) -> PyResult<bool> {
    if !matches!(e, physstep::Error::Interrupted { .. }) {
        return Ok(false);
    }
    physstep::interrupt::clear();
    if let Some(kept) = slot.and_then(|s| s.take()) {
        return Err(kept);
    }
    py.check_signals()?;
    Ok(true)
}

/// While it lives (in front of a Python handler), SIGINT also asks the engine to stop. Not nested: an inner call inside a callback leaves the outer one's.
pub(crate) struct Watch {
    #[cfg(unix)]
    previous: Option<libc::sigaction>,
}

#[cfg(unix)]
mod unix {
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

    /// Python's handler, called after the request.
    pub(super) static PYTHON: AtomicUsize = AtomicUsize::new(0);
    /// Whether a Watch holds SIGINT.
    pub(super) static HELD: AtomicBool = AtomicBool::new(false);

    pub(super) extern "C" fn on_sigint(signal: libc::c_int) {
        physstep::interrupt::request();
        let previous = PYTHON.load(Ordering::Relaxed);
        if previous != 0 {
            // SAFETY: a plain handler (not SIG_DFL or SIG_IGN, no SA_SIGINFO) read from
            // sigaction when the Watch began: a function of one int.
            let f: extern "C" fn(libc::c_int) = unsafe { std::mem::transmute(previous) };
            f(signal);
        }
    }
}

impl Watch {
    /// A watch over the current call; does nothing where Python ignores SIGINT or leaves it
    /// to the system, or while another watch holds it. A call on another thread than the
    /// main one may hold it: Ctrl-C then rolls its step back and takes it again (its thread
    /// does not handle signals), while the main thread gets KeyboardInterrupt.
    pub(crate) fn new() -> Self {
        #[cfg(unix)]
        {
            Self { previous: Self::install() }
        }
        #[cfg(not(unix))]
        {
            Self {}
        }
    }

    #[cfg(unix)]
    fn install() -> Option<libc::sigaction> {
        use std::sync::atomic::Ordering;
        // No Python code runs here: a signal already pending would be handled by it, and
        // its KeyboardInterrupt lost.
        if unix::HELD.swap(true, Ordering::AcqRel) {
            return None;
        }
        // SAFETY: sigaction with valid pointers; the new handler only does an atomic store
        // and calls the handler it replaces.
        unsafe {
            let mut old: libc::sigaction = std::mem::zeroed();
            if libc::sigaction(libc::SIGINT, std::ptr::null(), &mut old) != 0
                || old.sa_sigaction == libc::SIG_DFL
                || old.sa_sigaction == libc::SIG_IGN
                || old.sa_flags & libc::SA_SIGINFO != 0
            {
                unix::HELD.store(false, Ordering::Release);
                return None;
            }
            unix::PYTHON.store(old.sa_sigaction, Ordering::Relaxed);
            let mut new = old;
            new.sa_sigaction = unix::on_sigint as extern "C" fn(libc::c_int) as usize;
            if libc::sigaction(libc::SIGINT, &new, std::ptr::null_mut()) != 0 {
                unix::HELD.store(false, Ordering::Release);
                return None;
            }
            Some(old)
        }
    }
}

impl Drop for Watch {
    fn drop(&mut self) {
        #[cfg(unix)]
        if let Some(old) = self.previous.take() {
            use std::sync::atomic::Ordering;
            // SAFETY: as in `install`. Python's handler goes back only if ours is still there
            // (a callback may have set another meanwhile).
            unsafe {
                let mut current: libc::sigaction = std::mem::zeroed();
                if libc::sigaction(libc::SIGINT, std::ptr::null(), &mut current) == 0
                    && current.sa_sigaction == unix::on_sigint as extern "C" fn(libc::c_int) as usize
                {
                    libc::sigaction(libc::SIGINT, &old, std::ptr::null_mut());
                }
            }
            physstep::interrupt::clear();
            unix::HELD.store(false, Ordering::Release);
        }
    }
}
