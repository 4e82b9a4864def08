//! What a World shares with its Python forces: the slot where an exception raised inside a
//! step waits to be re-raised, and the state the World lends them while it steps.
//!
//! Lending: during `World.step`, `advance` and `record` (the calls that step), a World with
//! Python forces lends them its positions and velocities ([`Lend`]). A force the engine hands
//! exactly those slices (the method evaluates at the state itself: the Euler methods, Verlet's
//! drifted positions) gives its callable a read-only view of them, made once a call of steps
//! and reused, instead of a copy: the memory is the engine's `state.y`, kept alive and in place
//! under the World's current lease exactly as `World.positions` is (`crate::views` says why).
//! Anything else (a method's stage buffers, a body's point) is copied into arrays the force
//! owns (`crate::force`). The lending ends with the call: nothing it made outlives it unless
//! the callable kept it, which the force reports as an error (`crate::force`).

use crate::handle::World;
use crate::lease::Lease;
use numpy::PyArray2;
use physstep::world::World as Engine;
use pyo3::prelude::*;
use std::sync::{Arc, Mutex, PoisonError};

/// A World's positions and velocities lent to its Python forces for one call of steps.
struct Lending {
    /// Which [`Lend`] made it.
    id: u64,
    world: Py<World>,
    lease: Arc<Lease>,
    dim: usize,
    /// Address and length of the positions, then of the velocities.
    parts: [(usize, usize); 2],
    /// The view of each part, once made: reused call after call while no one else holds it.
    views: [Option<Py<PyArray2<f64>>>; 2],
}

/// What a World and its Python forces share (a copy of the World shares it too, as it
/// shares the forces).
#[derive(Default)]
pub(crate) struct Shared {
    error: Mutex<Option<PyErr>>,
    /// The lendings in force, the latest last (a callable may step a copy of its World, and
    /// a copy may step in another thread while this one records).
    lending: Mutex<Vec<Lending>>,
    /// The id of the next lending.
    next: std::sync::atomic::AtomicU64,
}

/// A World's [`Shared`] part, as its forces hold it.
#[derive(Clone, Default)]
pub(crate) struct Slot(Arc<Shared>);

impl Slot {
    /// Keeps `e` (the first one wins) for the caller of the step.
    pub(crate) fn keep(&self, e: PyErr) {
        let mut slot = self.0.error.lock().unwrap_or_else(PoisonError::into_inner);
        if slot.is_none() {
            *slot = Some(e);
        }
    }

    /// The exception kept since the last take, if any.
    pub(crate) fn take(&self) -> Option<PyErr> {
        self.0.error.lock().unwrap_or_else(PoisonError::into_inner).take()
    }

    fn lending(&self) -> std::sync::MutexGuard<'_, Vec<Lending>> {
        self.0.lending.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// A read-only `(rows, dim)` view of `data` when it is a part of a lent state (`part` 0:
    /// positions, 1: velocities), else `None`.
    pub(crate) fn view<'py>(
        &self,
        py: Python<'py>,
        part: usize,
        data: &[f64],
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        let key = (data.as_ptr() as usize, data.len());
        // (What Python does, allocating, runs after the lock is let go.)
        let found = self
            .lending()
            .iter_mut()
            .rev()
            .find(|l| l.parts[part] == key)
            .map(|l| (l.views[part].take(), l.world.clone_ref(py), Arc::clone(&l.lease), l.dim));
        let Some((kept, world, lease, dim)) = found else { return Ok(None) };
        if let Some(v) = kept {
            return Ok(Some(v.into_bound(py)));
        }
        crate::views::borrow(py, data, dim, crate::views::StateView::new(world, lease)).map(Some)
    }

    /// After a call: the view of `data` made by [`Slot::view`] is kept for the next call
    /// (`arr` unchanged: it was not kept by the callable, nor reshaped).
    pub(crate) fn give_back(&self, part: usize, data: &[f64], arr: Bound<'_, PyArray2<f64>>) {
        let key = (data.as_ptr() as usize, data.len());
        let mut arr = Some(arr.unbind());
        if let Some(l) = self.lending().iter_mut().rev().find(|l| l.parts[part] == key) {
            if l.views[part].is_none() {
                l.views[part] = arr.take();
            }
        }
        drop(arr);
    }
}

/// While alive, the World's positions and velocities are lent to its Python forces.
pub(crate) struct Lend {
    slot: Slot,
    id: u64,
}

impl Lend {
    /// Lends `engine`'s state (the engine of `world`, its views under `lease`) to the forces
    /// sharing `slot` until the returned value is dropped. The state must not be reallocated
    /// meanwhile: the calls that step never do (adding particles or bodies does, through
    /// `Inner::grow`, which a callable cannot reach: the World is busy).
    pub(crate) fn new(slot: &Slot, world: Py<World>, lease: Arc<Lease>, engine: &Engine) -> Self {
        let key = |s: &[f64]| (s.as_ptr() as usize, s.len());
        let parts = [key(engine.positions()), key(engine.velocities())];
        let dim = engine.dim();
        let id = slot.0.next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        slot.lending().push(Lending { id, world, lease, dim, parts, views: [None, None] });
        Self { slot: slot.clone(), id }
    }
}

impl Drop for Lend {
    fn drop(&mut self) {
        // (Its views, if still here, are dropped with it once the lock is let go.)
        let ended = {
            let mut lendings = self.slot.lending();
            lendings.iter().rposition(|l| l.id == self.id).map(|i| lendings.remove(i))
        };
        drop(ended);
    }
}
