//! Zero-copy reads: `World.positions` and `World.velocities` are read-only numpy arrays over
//! the engine's own state, not copies.
//!
//! Why the memory behind a view is alive for as long as the view is (docs/views.md):
//!
//! * The array's base is a [`StateView`], which holds a strong reference to the `World` and
//!   a share of the World's current [`Lease`]. The World owns the engine, and the engine owns
//!   the buffers the view points into, so they live as long as the view does, whatever the
//!   Python side drops.
//! * The engine writes those buffers in place, except when a call changes the state's layout
//!   (adding particles or bodies), which reallocates them (`World::detach_state` says so, and
//!   a test in `physstep::world::state` pins it for every method). Every such call in this
//!   crate goes through [`crate::handle::Inner::flush`] or [`crate::handle::Inner::grow`], and
//!   both call [`crate::lease::Views::detach`] first: when views of the current buffers are alive, the
//!   engine is given copies and the buffers themselves move, unchanged (moving a `Vec` does
//!   not move its heap memory), into the current lease, where they stay until the last view
//!   holding that lease is gone. A view kept across the change shows the values it had then.
//! * "Views alive" is `Arc::strong_count(lease) > 1`. A new view takes its share under the
//!   World's lock, the same lock `detach` runs under, so none can appear during the check; a
//!   view dropped meanwhile only makes `detach` keep buffers it no longer needed to.

use crate::handle::World;
use crate::lease::Lease;
use numpy::ndarray::ArrayView2;
use numpy::{npyffi, PyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::sync::Arc;

/// The base object of a `World.positions` / `World.velocities` view: it keeps the World and
/// the memory the view reads alive.
#[pyclass(module = "physstep._core", frozen)]
pub(crate) struct StateView {
    _world: Py<World>,
    _lease: Arc<Lease>,
}

#[pymethods]
impl StateView {
    fn __repr__(&self) -> &'static str {
        "<the memory of a physstep World's positions or velocities>"
    }
}

/// Which part of the state a view shows.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Part {
    Positions,
    Velocities,
}

/// A read-only `(n, dim)` float64 array over the engine's positions or velocities.
pub(crate) fn view<'py>(world: &Bound<'py, World>, part: Part) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let py = world.py();
    let mut g = world.get().lock()?;
    g.flush()?;
    let lease = Arc::clone(&g.views.current);
    let w = &g.engine;
    let data = match part {
        Part::Positions => w.positions(),
        Part::Velocities => w.velocities(),
    };
    let base = StateView::new(world.clone().unbind(), lease);
    borrow(py, data, w.dim(), base)
}

impl StateView {
    /// The base object of views of the state of `world`, lent under `lease`.
    pub(crate) fn new(world: Py<World>, lease: Arc<Lease>) -> Self {
        Self { _world: world, _lease: lease }
    }
}

/// A read-only `(rows, dim)` float64 array over `data`, a part of the state of the World that
/// `base` holds, lent under the lease `base` holds: the World's current one.
pub(crate) fn borrow<'py>(
    py: Python<'py>,
    data: &[f64],
    dim: usize,
    base: StateView,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let rows = data.len() / dim;
    let a = ArrayView2::from_shape((rows, dim), &data[..rows * dim])
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let base = Bound::new(py, base)?;
    // SAFETY: `borrow_from_array` asks that the memory of `a` stay valid, and not be
    // reallocated, until `base` is dropped. `a` is a slice of the engine's `state.y` or
    // `state.f`. `base` owns the World (so the engine and its buffers are not dropped) and a
    // share of the current lease; the engine reallocates those buffers only in calls that
    // change the state's layout, and each runs `Views::detach` first (under the World's lock,
    // which the caller holds), which, the lease being shared, moves the buffers into the lease
    // unchanged rather than let them be freed. So the memory lives until `base`, the array's
    // base object, is gone. Writes by the engine later (steps) are in place, and numpy reads
    // them as plain f64.
    let arr = unsafe { PyArray2::borrow_from_array(&a, base.into_any()) };
    // SAFETY: `arr` was just made here and no other reference to it exists; clearing the
    // WRITEABLE bit of its flags is what `PyArray_CLEARFLAGS` does. Its base is not an array
    // and has no buffer interface, so numpy refuses to set the bit again (`setflags`).
    unsafe {
        (*npyffi::objects::_PyArray_GET_ITEM_DATA(arr.as_array_ptr())).flags &= !npyffi::NPY_ARRAY_WRITEABLE;
    }
    Ok(arr)
}
