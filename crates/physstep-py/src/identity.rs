//! What a handle of one thing of a World is, whatever the thing (a particle, constraint or
//! body, a body spring or force, a solid, solid spring, force on a solid or joint): its World,
//! that World's family token (`Inner::family`: its copies and pickles share it) and the
//! engine's id of the thing. [`identity!`] gives each handle class its name in messages and
//! repr (`BodyHandle(id=3)`), its `id` and `world`, and its equality and hash (the same thing
//! of the same World family). `ForceHandle` is not one of them: its repr carries the kind.

/// `identity!(HandleType, rotation)`: the handle's `text` and its `id`, `world`, `__repr__`,
/// `__eq__` and `__hash__` (`id ^ family.rotate_left(rotation)`: each kind its own, so the
/// same id of different kinds hashes apart). The type has fields `world: Py<World>`,
/// `family: u64` and `id: u64`.
macro_rules! identity {
    ($ty:ident, $rotation:literal) => {
        impl $ty {
            /// `Type(id=N)`: the handle in messages and its repr.
            fn text(&self) -> String {
                format!(concat!(stringify!($ty), "(id={})"), self.id)
            }
        }

        #[pymethods]
        impl $ty {
            /// The id in its World: never given to another of its kind in that World.
            #[getter]
            fn id(&self) -> u64 {
                self.id
            }

            /// The World the handle came from.
            #[getter]
            fn world(&self, py: Python<'_>) -> Py<crate::handle::World> {
                self.world.clone_ref(py)
            }

            fn __repr__(&self) -> String {
                self.text()
            }

            /// Equal handles name the same one of the same World family.
            fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
                other.cast::<$ty>().is_ok_and(|o| {
                    let o = o.get();
                    o.id == self.id && o.family == self.family
                })
            }

            fn __hash__(&self) -> u64 {
                self.id ^ self.family.rotate_left($rotation)
            }
        }
    };
}
pub(crate) use identity;
