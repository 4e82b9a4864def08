//! `physstep.BodySpringHandle` and `BodyForceHandle`: what `add_body_spring` and
//! `add_body_force` return. Links between entities (a spring from a body point to a particle
//! or another body, a Python force at a body point) rather than entities with a row of state:
//! an id, `alive` (a link goes with its body, or with the particle a body spring ends on), its
//! place among its kind by `__index__`, and a body spring's parameters read and written through
//! it. Bound to their World's family as the entities' handles are (`entity_handle.rs`; the errors of both in `errors.rs`).

use crate::errors::{foreign_handle, removed_handle};
use crate::handle::{Inner, World};
use pyo3::prelude::*;

/// A handle of a body link (a body spring or a Python force at a body point): id, alive,
/// its place among its kind by `__index__`.
macro_rules! link_handle {
    ($(#[$doc:meta])* $name:ident, $what:literal, $row:ident, $id:ident) => {
        $(#[$doc])*
        #[pyclass(module = "physstep._core", frozen)]
        pub struct $name {
            pub(crate) world: Py<World>,
            pub(crate) family: u64,
            pub(crate) id: u64,
        }

        crate::identity::identity!($name, 31);

        impl $name {
            /// The id, checked to be of the World whose state `g` is.
            pub(crate) fn id_in(&self, g: &Inner) -> PyResult<physstep::world::$id> {
                if self.family != g.family {
                    return Err(foreign_handle($what, concat!($what, "s"), &self.text()));
                }
                Ok(physstep::world::$id(self.id))
            }
        }

        #[pymethods]
        impl $name {
            /// Whether it is still in its World (it goes with its body, or with the
            /// particle a body spring ends on).
            #[getter]
            fn alive(&self) -> PyResult<bool> {
                let g = self.world.get().lock()?;
                Ok(g.engine.$row(physstep::world::$id(self.id)).is_some())
            }

            /// Its place among its kind in the World; ValueError once removed.
            fn __index__(&self) -> PyResult<usize> {
                let g = self.world.get().lock()?;
                g.engine.$row(physstep::world::$id(self.id)).ok_or_else(|| removed_handle($what, &self.text()))
            }
        }
    };
}

link_handle!(
    /// A handle to one body spring (what `add_body_spring` returns); `World.remove(h)`
    /// removes it.
    BodySpringHandle,
    "body_spring",
    body_spring_row,
    BodySpringId
);
link_handle!(
    /// A handle to one Python force at a body point (what `add_body_force` returns);
    /// `World.remove(h)` removes it.
    BodyForceHandle,
    "body_force",
    body_force_row,
    BodyForceId
);

/// A body spring's parameters through its handle, read and written as `add_body_spring`
/// takes them (a write is checked the same way; the next step sees it).
#[pymethods]
impl BodySpringHandle {
    /// Stiffness, N/m.
    #[getter]
    fn stiffness(&self) -> PyResult<f64> {
        Ok(self.spring()?.stiffness)
    }

    #[setter]
    fn set_stiffness(&self, value: f64) -> PyResult<()> {
        self.set(Some(value), None, None)
    }

    /// Rest length, m.
    #[getter]
    fn rest_length(&self) -> PyResult<f64> {
        Ok(self.spring()?.rest_length)
    }

    #[setter]
    fn set_rest_length(&self, value: f64) -> PyResult<()> {
        self.set(None, Some(value), None)
    }

    /// Damping along the spring, N s/m.
    #[getter]
    fn damping(&self) -> PyResult<f64> {
        Ok(self.spring()?.damping)
    }

    #[setter]
    fn set_damping(&self, value: f64) -> PyResult<()> {
        self.set(None, None, Some(value))
    }
}

impl BodySpringHandle {
    /// The spring as the World holds it, or the one-line error of a removed or foreign one.
    fn spring(&self) -> PyResult<physstep::rigid::body::BodySpring> {
        let g = self.world.get().lock()?;
        let id = self.id_in(&g)?;
        g.engine.body_spring(id).ok_or_else(|| removed_handle("body_spring", &self.text()))
    }

    fn set(&self, stiffness: Option<f64>, rest: Option<f64>, damping: Option<f64>) -> PyResult<()> {
        let mut g = self.world.get().lock()?;
        let id = self.id_in(&g)?;
        g.flush()?.set_body_spring(id, stiffness, rest, damping).map_err(crate::py_err)
    }
}
