//! The `World` handle: the engine world behind a mutex with the parts only Python can hold
//! (its forces' callables, the particles waiting to be added, the lease of the buffers its
//! views read). The modules that give `physstep.World` its methods (`world`, `world_*`,
//! `pickle`, `record`, `views`) import it; it imports none of them.
//!
//! Threading: a World is used by one thread at a time. Its state sits behind a mutex; a call
//! that finds it taken (another thread is stepping it, or a callback inside its own step
//! touched it) raises `WorldBusyError` at once rather than wait or corrupt anything.

use crate::errors::WorldBusyError;
use crate::lease::Views;
use crate::py_err;
use crate::slot::{Lend, Slot};
use physstep::world::{ParticleBatch, World as Engine};
use pyo3::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, TryLockError};

/// A Python force at a body point as added: body, point (shape frame), and the force's spec
/// `(func, potential, None, velocity_dependent, name, inplace)`: the callables the engine
/// cannot hold, for pickles and copies.
pub(crate) type BodyForceSpec = (usize, [f64; 3], std::sync::Arc<Py<PyAny>>);

/// A Python force at a solid's point as added: solid, point (its frame, `dim` numbers), and
/// the force's spec as [`BodyForceSpec`]'s.
pub(crate) type SolidForceSpec = (usize, Vec<f64>, std::sync::Arc<Py<PyAny>>);

/// Particles, forces, an integrator and a fixed-timestep game loop.
///
/// World(dim, method="symplectic-euler", dt=1/120, max_steps_per_frame=8,
/// max_frame_time=0.1, loop="accumulator", substeps=1). A World serves one thread at a time
/// (WorldBusyError otherwise); step() and the recording release the GIL and see Ctrl-C.
#[pyclass(module = "physstep._core", frozen)]
pub struct World {
    inner: Mutex<Inner>,
    /// The thread holding `inner` ([`thread_tag`]), 0 when no one does: a call that finds
    /// the World taken by its own thread is a callback inside the World's own step.
    holder: AtomicUsize,
}

/// A new family token: random (std's per-process random keys, advanced for every hasher),
/// so the Worlds of two processes, or a pickle from another process, do not share one.
fn new_family() -> u64 {
    use std::hash::{BuildHasher, Hasher};
    static COUNT: AtomicUsize = AtomicUsize::new(0);
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_usize(COUNT.fetch_add(1, Ordering::Relaxed));
    h.write_u32(std::process::id());
    h.finish()
}

/// A number for the current thread, never 0 (the address of a thread-local).
fn thread_tag() -> usize {
    thread_local!(static TAG: u8 = const { 0 });
    TAG.with(|t| std::ptr::from_ref(t) as usize)
}

/// The World's state while one call holds it; the holder is forgotten when it drops.
pub(crate) struct Guard<'a> {
    guard: MutexGuard<'a, Inner>,
    holder: &'a AtomicUsize,
}

impl std::ops::Deref for Guard<'_> {
    type Target = Inner;
    fn deref(&self) -> &Inner {
        &self.guard
    }
}

impl std::ops::DerefMut for Guard<'_> {
    fn deref_mut(&mut self) -> &mut Inner {
        &mut self.guard
    }
}

impl Drop for Guard<'_> {
    fn drop(&mut self) {
        // (Before the mutex is released: the field drops after this.)
        self.holder.store(0, Ordering::Release);
    }
}

pub(crate) struct Inner {
    pub(crate) engine: Engine,
    /// A Python exception raised inside a step by a user force, to re-raise unchanged.
    pub(crate) slot: Slot,
    /// The Python forces as added: `(func, potential, jacobian, velocity_dependent, name,
    /// inplace)`: the callables the engine cannot hold, for pickling (the rest of a pickle is
    /// the engine's scene text and snapshot, `crate::pickle`).
    pub(crate) user: Vec<Py<PyAny>>,
    /// A Python flow as made: `(func, jacobian, name, n)`, for pickling.
    pub(crate) flow: Option<Py<PyAny>>,
    /// Particles from `add_particle`, validated and waiting to be added in one batch:
    /// growing the engine's `[x; v]` state one particle at a time moves the velocity half
    /// every time, which is quadratic in a spawn loop. Every method that reads or steps the
    /// state flushes them first.
    pub(crate) pending: ParticleBatch,
    /// The Python forces at body points as added, for pickling.
    pub(crate) body_forces: Vec<BodyForceSpec>,
    /// The Python forces at solids' points as added, for pickling.
    pub(crate) solid_forces: Vec<SolidForceSpec>,
    /// The zero-copy views lent out (`crate::views`): detached before the state reallocates.
    pub(crate) views: Views,
    /// This World's family: a random number, kept by its copies and pickles, that the
    /// handles of its forces carry (`crate::force_handle`): a World takes the handles of its
    /// own family and refuses another's.
    pub(crate) family: u64,
}

impl Inner {
    /// The engine, with the particles waiting in the batch added.
    pub(crate) fn flush(&mut self) -> PyResult<&mut Engine> {
        if !self.pending.is_empty() {
            self.views.detach(&mut self.engine);
            self.pending.commit(&mut self.engine).map_err(py_err)?;
        }
        Ok(&mut self.engine)
    }

    /// The engine, flushed, for a call that steps: its positions and velocities lent to its
    /// Python forces (`crate::slot`) while the returned [`Lend`] lives, when it has any.
    pub(crate) fn stepping(&mut self, world: &Bound<'_, World>) -> PyResult<(&mut Engine, Option<Lend>)> {
        self.flush()?;
        let forces = self.engine.model().user_forces() > 0;
        let lend = forces.then(|| {
            let lease = std::sync::Arc::clone(&self.views.current);
            Lend::new(&self.slot, world.clone().unbind(), lease, &self.engine)
        });
        Ok((&mut self.engine, lend))
    }

    /// The engine for a call that adds particles or bodies (which reallocates its state):
    /// flushed, and the zero-copy views lent out detached first.
    pub(crate) fn grow(&mut self) -> PyResult<&mut Engine> {
        self.flush()?;
        self.views.detach(&mut self.engine);
        Ok(&mut self.engine)
    }

    /// Particles in the world, waiting ones included.
    pub(crate) fn count(&self) -> usize {
        self.engine.len() + self.pending.len()
    }
}

/// The engine's error as a Python exception; an exception a user force raised during the
/// call comes first, unchanged.
pub(crate) fn raise(slot: &Slot, e: physstep::Error) -> PyErr {
    let kept = slot.take();
    kept.unwrap_or_else(|| py_err(e))
}

impl World {
    /// The state, or `WorldBusyError` when another thread holds it, or when a callback of
    /// this world's own step (a force, potential or Jacobian) asks for it: the step holds
    /// the state, and the callback is handed what it may read (`t`, `x`, `v`).
    pub(crate) fn lock(&self) -> PyResult<Guard<'_>> {
        let guard = match self.inner.try_lock() {
            Ok(g) => g,
            Err(TryLockError::WouldBlock) if self.holder.load(Ordering::Acquire) == thread_tag() => {
                return Err(WorldBusyError::new_err(
                    "this World is in use by the call that ran this callback (its own force, \
                     potential or jacobian): a callback cannot use the World it belongs to; \
                     read the t, x and v it is handed instead",
                ))
            }
            Err(TryLockError::WouldBlock) => {
                return Err(WorldBusyError::new_err(
                    "this World is in use by another thread (a World serves one thread at a time: \
                     give each thread its own World, or guard it with a lock)",
                ))
            }
            // A panic cannot happen inside (every engine call returns a Result); were it to,
            // the data is still whole, so go on with it.
            Err(TryLockError::Poisoned(p)) => p.into_inner(),
        };
        self.holder.store(thread_tag(), Ordering::Release);
        Ok(Guard { guard, holder: &self.holder })
    }

    /// A World around an engine world with no Python parts (a scene, a loaded scene file).
    pub(crate) fn wrap(engine: Engine) -> Self {
        Self::with_parts(engine, Slot::default(), Vec::new(), None)
    }

    pub(crate) fn with_parts(
        engine: Engine,
        slot: Slot,
        user: Vec<Py<PyAny>>,
        flow: Option<Py<PyAny>>,
    ) -> Self {
        let (pending, body_forces) = (ParticleBatch::default(), Vec::new());
        let views = Views::default();
        let solid_forces = Vec::new();
        let family = new_family();
        let inner =
            Mutex::new(Inner { engine, slot, user, flow, pending, body_forces, solid_forces, views, family });
        Self { inner, holder: AtomicUsize::new(0) }
    }
}
