//! Handles of the contact side (docs/contact.md, "Handles and removal"): what `add_solid`,
//! `add_solid_spring` and `add_solid_force` return (`add_joint`'s: `crate::joint_handle`), each naming one thing of
//! one World by the engine's id (a counter of its kind never reused: `physstep::contact::
//! SolidId` and the rest), so it stays that thing's while others are added or removed.
//!
//! A `SolidHandle` is also the solid's view (`w.solids[i]` returns it): `position`,
//! `velocity`, `angle` (2D) or `orientation` (3D), `angular_velocity`, read and written
//! through the World, each write validated as `add_solid` and applied at once. Its
//! `__index__` is the solid's row now, so every call and array that takes a solid index
//! takes the handle. `World.remove(h)` removes the thing (`remove_solid_like`); a removed
//! thing's handle is not `alive`, and using it is one ValueError naming it.
//!
//! A handle is bound to the World it came from by the World's family token, as a
//! `ForceHandle` is: a copy or a pickle of a World carries its ids and family, so
//! `copy.remove(h)` reaches the same thing in the copy.

use crate::convert::{array, float};
use crate::handle::World;
use crate::py_err;
use numpy::PyArray1;
use physstep::contact::{SolidForceId, SolidId, SolidMotion, SolidSpringId};
use physstep::world::World as Engine;
use pyo3::exceptions::{PyAttributeError, PyIndexError};
use pyo3::prelude::*;

/// What the four handles share (this file's three and `crate::joint_handle`'s): the World, its family, the id, a name for messages.
macro_rules! handle_common {
    ($ty:ident, $what:literal) => {
        crate::identity::identity!($ty, 17);

        impl $ty {
            fn gone(&self) -> PyErr {
                crate::errors::removed_handle($what, &self.text())
            }

            /// The id, checked to be of the World of family `family`.
            fn id_in(&self, family: u64) -> PyResult<u64> {
                if self.family != family {
                    return Err(crate::errors::foreign_handle($what, concat!($what, "s"), &self.text()));
                }
                Ok(self.id)
            }
        }

        #[pymethods]
        impl $ty {
            /// Whether it is still in its World.
            #[getter]
            fn alive(&self) -> PyResult<bool> {
                let g = self.world.get().lock()?;
                Ok(self.row_in(&g.engine).is_some())
            }

            /// Its row now among its kind (the order they were added in, the removed ones
            /// taken out); ValueError once removed.
            #[getter]
            fn row(&self) -> PyResult<usize> {
                let g = self.world.get().lock()?;
                self.row_in(&g.engine).ok_or_else(|| self.gone())
            }
        }
    };
}
pub(crate) use handle_common;

/// A handle to one solid of a World, and its view: `id`, `alive`, `row`, `kind`, `shape`,
/// and `position`, `velocity`, `angle` (2D) or `orientation` (3D), `angular_velocity`,
/// readable and writable. `int(h)` and `operator.index(h)` give its row now.
#[pyclass(module = "physstep._core", frozen, name = "SolidHandle")]
pub struct SolidHandle {
    world: Py<World>,
    family: u64,
    id: u64,
}

/// A handle to one spring between solids: `id`, `alive`, `a`, `b`, `point_a`, `point_b`,
/// and `stiffness`, `rest_length`, `damping` writable.
#[pyclass(module = "physstep._core", frozen, name = "SolidSpringHandle")]
pub struct SolidSpringHandle {
    world: Py<World>,
    family: u64,
    id: u64,
}

/// A handle to one force from Python on a solid (`add_solid_force`): `id`, `alive`,
/// `solid`, `name`.
#[pyclass(module = "physstep._core", frozen, name = "SolidForceHandle")]
pub struct SolidForceHandle {
    world: Py<World>,
    family: u64,
    id: u64,
    name: String,
}

handle_common!(SolidHandle, "solid");
handle_common!(SolidSpringHandle, "spring");
handle_common!(SolidForceHandle, "force");

impl SolidHandle {
    fn row_in(&self, w: &Engine) -> Option<usize> {
        w.solid_row(SolidId(self.id))
    }

    /// The handle of the solid in row `row` of `world`.
    pub(crate) fn of_row(world: &Bound<'_, World>, w: &Engine, family: u64, row: usize) -> Self {
        Self { world: world.clone().unbind(), family, id: w.solid_ids()[row].0 }
    }

    /// `read(engine, row, dim)` for the solid, or the error naming it once removed.
    fn read<T>(&self, read: impl FnOnce(&Engine, usize, usize) -> T) -> PyResult<T> {
        let g = self.world.get().lock()?;
        let row = self.row_in(&g.engine).ok_or_else(|| self.gone())?;
        Ok(read(&g.engine, row, g.engine.dim()))
    }

    /// Sets the parts of the motion given (`value` converted by `part` with the World's
    /// dimension).
    fn write(
        &self,
        value: &Bound<'_, PyAny>,
        part: impl FnOnce(Vec<f64>) -> SolidMotion,
        field: &str,
    ) -> PyResult<()> {
        let x = numbers(value, field)?;
        let mut g = self.world.get().lock()?;
        let w = g.flush()?;
        if self.row_in(w).is_none() {
            return Err(self.gone());
        }
        w.set_solid_motion(SolidId(self.id), &part(x)).map_err(py_err)
    }
}

/// A number or an array-like as numbers (one number: a vector of one).
fn numbers(o: &Bound<'_, PyAny>, field: &str) -> PyResult<Vec<f64>> {
    if !o.is_instance_of::<pyo3::types::PyBool>() {
        if let Ok(x) = o.extract::<f64>() {
            return Ok(vec![x]);
        }
    }
    array(o, field, None, None)
}

pub(crate) fn vector(py: Python<'_>, v: &[f64]) -> Py<PyAny> {
    PyArray1::from_slice(py, v).into_any().unbind()
}

#[pymethods]
impl SolidHandle {
    /// The solid's row now: `w.solid_positions()[h]` and every call that takes a solid
    /// index take the handle. ValueError once the solid was removed.
    fn __index__(&self) -> PyResult<usize> {
        self.row()
    }

    fn __int__(&self) -> PyResult<usize> {
        self.row()
    }

    /// "dynamic", "static" or "kinematic".
    #[getter]
    fn kind(&self) -> PyResult<&'static str> {
        self.read(|w, i, _| w.solid_params()[i].kind.name())
    }

    /// The shape as added (read-only; its `kind` names it).
    #[getter]
    fn shape(&self) -> PyResult<crate::shapes::SolidShape> {
        self.read(|w, i, _| crate::shapes::SolidShape(w.solid_params()[i].shape.clone()))
    }

    /// Origin of the shape (dim,), m (a copy); assign to move the solid (validated as
    /// `add_solid`; its contacts' warm starts and render interpolation's previous pose are
    /// forgotten).
    #[getter]
    fn position(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let x = self.read(|w, i, d| w.solid_positions()[i * d..(i + 1) * d].to_vec())?;
        Ok(vector(py, &x))
    }

    #[setter]
    fn set_position(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.write(value, |x| SolidMotion { position: Some(x), ..Default::default() }, "position")
    }

    /// Velocity of the centre of mass (dim,), m/s; assign to set it (a static solid's stays
    /// zero: a nonzero one is refused; make it kinematic to move it).
    #[getter]
    fn velocity(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let v = self.read(|w, i, d| w.solid_velocities()[i * d..(i + 1) * d].to_vec())?;
        Ok(vector(py, &v))
    }

    #[setter]
    fn set_velocity(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.write(value, |v| SolidMotion { velocity: Some(v), ..Default::default() }, "velocity")
    }

    /// Angle, rad (2D worlds); assign to turn the solid about its shape's origin.
    #[getter]
    fn angle(&self) -> PyResult<f64> {
        let (dim, q) = self.read(|w, i, d| (d, if d == 2 { w.solid_orientations()[i] } else { 0.0 }))?;
        if dim != 2 {
            return Err(PyAttributeError::new_err("a solid of a 3D world has no angle: use orientation"));
        }
        Ok(q)
    }

    #[setter]
    fn set_angle(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        if self.read(|_, _, d| d)? != 2 {
            return Err(PyAttributeError::new_err("a solid of a 3D world has no angle: use orientation"));
        }
        let a = float(value, "angle")?;
        self.write(
            &value.clone(),
            |_| SolidMotion { orientation: Some(vec![a]), ..Default::default() },
            "angle",
        )
    }

    /// Orientation: the angle (2D, rad) or a unit quaternion (4,) as (w, x, y, z) (3D);
    /// assign to turn the solid about its shape's origin (a quaternion is normalised; a zero
    /// one is refused).
    #[getter]
    fn orientation(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let (dim, q) = self.read(|w, i, d| {
            let r = if d == 2 { 1 } else { 4 };
            (d, w.solid_orientations()[i * r..(i + 1) * r].to_vec())
        })?;
        Ok(if dim == 2 { q[0].into_pyobject(py)?.into_any().unbind() } else { vector(py, &q) })
    }

    #[setter]
    fn set_orientation(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.write(value, |q| SolidMotion { orientation: Some(q), ..Default::default() }, "orientation")
    }

    /// Angular velocity, rad/s: a number in 2D, (3,) world frame in 3D; assign to set it.
    #[getter]
    fn angular_velocity(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let (dim, w) = self.read(|w, i, d| {
            let a = if d == 2 { 1 } else { 3 };
            (d, w.solid_angular_velocities()[i * a..(i + 1) * a].to_vec())
        })?;
        Ok(if dim == 2 { w[0].into_pyobject(py)?.into_any().unbind() } else { vector(py, &w) })
    }

    #[setter]
    fn set_angular_velocity(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.write(
            value,
            |w| SolidMotion { angular_velocity: Some(w), ..Default::default() },
            "angular_velocity",
        )
    }
}

impl SolidSpringHandle {
    fn row_in(&self, w: &Engine) -> Option<usize> {
        w.solid_spring_row(SolidSpringId(self.id))
    }

    fn params<T>(&self, f: impl FnOnce(&physstep::contact::SolidSpring) -> T) -> PyResult<T> {
        let g = self.world.get().lock()?;
        let row = self.row_in(&g.engine).ok_or_else(|| self.gone())?;
        Ok(f(&g.engine.solid_springs()[row]))
    }

    /// Sets (stiffness, rest length, damping) from the spring's as they are, changed.
    fn set(&self, change: impl FnOnce(&mut [f64; 3])) -> PyResult<()> {
        let mut g = self.world.get().lock()?;
        let w = g.flush()?;
        let row = self.row_in(w).ok_or_else(|| self.gone())?;
        let p = &w.solid_springs()[row];
        let mut k = [p.stiffness, p.rest_length.unwrap_or(0.0), p.damping];
        change(&mut k);
        w.set_solid_spring(SolidSpringId(self.id), k[0], k[1], k[2]).map_err(py_err)
    }
}

#[pymethods]
impl SolidSpringHandle {
    /// The first solid's handle.
    #[getter]
    fn a(&self, py: Python<'_>) -> PyResult<SolidHandle> {
        let g = self.world.get().lock()?;
        let row = self.row_in(&g.engine).ok_or_else(|| self.gone())?;
        let a = g.engine.solid_springs()[row].a;
        Ok(SolidHandle::of_row(self.world.bind(py), &g.engine, self.family, a))
    }

    /// The second solid's handle, or None: a fixed point of the world.
    #[getter]
    fn b(&self, py: Python<'_>) -> PyResult<Option<SolidHandle>> {
        let g = self.world.get().lock()?;
        let row = self.row_in(&g.engine).ok_or_else(|| self.gone())?;
        let b = g.engine.solid_springs()[row].b;
        Ok(b.map(|b| SolidHandle::of_row(self.world.bind(py), &g.engine, self.family, b)))
    }

    /// The end on `a`, in its frame, m.
    #[getter]
    fn point_a(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let p = self.params(|p| p.point_a.clone())?;
        Ok(vector(py, &p))
    }

    /// The end on `b` in its frame, or the world point, m.
    #[getter]
    fn point_b(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let p = self.params(|p| p.point_b.clone())?;
        Ok(vector(py, &p))
    }

    /// Stiffness, N/m; assign to change it (in [0, 1e12]).
    #[getter]
    fn stiffness(&self) -> PyResult<f64> {
        self.params(|p| p.stiffness)
    }

    #[setter]
    fn set_stiffness(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(value, "stiffness")?;
        self.set(|k| k[0] = v)
    }

    /// Rest length, m; assign to change it (in [0, 1e12]).
    #[getter]
    fn rest_length(&self) -> PyResult<f64> {
        self.params(|p| p.rest_length.unwrap_or(0.0))
    }

    #[setter]
    fn set_rest_length(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(value, "rest_length")?;
        self.set(|k| k[1] = v)
    }

    /// Damping along the spring, N s/m; assign to change it (in [0, 1e12]).
    #[getter]
    fn damping(&self) -> PyResult<f64> {
        self.params(|p| p.damping)
    }

    #[setter]
    fn set_damping(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(value, "damping")?;
        self.set(|k| k[2] = v)
    }
}

impl SolidForceHandle {
    fn row_in(&self, w: &Engine) -> Option<usize> {
        w.solid_force_row(SolidForceId(self.id))
    }
}

#[pymethods]
impl SolidForceHandle {
    /// The force's name (in errors).
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// The handle of the solid it acts on.
    #[getter]
    fn solid(&self, py: Python<'_>) -> PyResult<SolidHandle> {
        let g = self.world.get().lock()?;
        let row = self.row_in(&g.engine).ok_or_else(|| self.gone())?;
        let solid = g.solid_forces[row].0;
        Ok(SolidHandle::of_row(self.world.bind(py), &g.engine, self.family, solid))
    }
}

/// A solid argument of a call on `world`: a `SolidHandle` of its family (its row there now;
/// ValueError naming it once removed) or a row index >= 0 (the engine checks the count).
pub(crate) fn solid_arg(world: &World, o: &Bound<'_, PyAny>, field: &str) -> PyResult<usize> {
    if let Ok(h) = o.cast::<SolidHandle>() {
        let h = h.get();
        let g = world.lock()?;
        let id = h.id_in(g.family)?;
        return g.engine.solid_row(SolidId(id)).ok_or_else(|| h.gone());
    }
    // Another kind's handle is not a solid, whatever its row.
    if crate::entity_handle::is_handle(o) {
        return Err(crate::convert::invalid(field, o, "a solid index or a SolidHandle"));
    }
    crate::convert::whole(o, field, 0, i64::MAX)
        .map(|v| v as usize)
        .map_err(|_| crate::convert::invalid(field, o, "a solid index >= 0 or a SolidHandle"))
}

/// The handle of the spring or force just added at `row`.
pub(crate) fn spring_handle(
    world: &Bound<'_, World>,
    w: &Engine,
    family: u64,
    row: usize,
) -> SolidSpringHandle {
    SolidSpringHandle { world: world.clone().unbind(), family, id: w.solid_spring_ids()[row].0 }
}

pub(crate) fn force_handle(
    world: &Bound<'_, World>,
    w: &Engine,
    family: u64,
    row: usize,
    name: String,
) -> SolidForceHandle {
    SolidForceHandle { world: world.clone().unbind(), family, id: w.solid_force_ids()[row].0, name }
}

/// `World.remove(h)` for the handles of solids, solid springs and forces on solids: `Ok(true)`
/// when `handle` was one (and is removed), `Ok(false)` when it is of another class (the
/// caller goes on; a joint's is `crate::joint_handle::remove_joint`'s). A solid's removal
/// takes its joints, springs and Python forces with it.
pub(crate) fn remove_solid_like(world: &World, handle: &Bound<'_, PyAny>) -> PyResult<bool> {
    if let Ok(h) = handle.cast::<SolidHandle>() {
        let h = h.get();
        let mut g = world.lock()?;
        let id = SolidId(h.id_in(g.family)?);
        let row = g.engine.solid_row(id).ok_or_else(|| h.gone())?;
        g.grow()?.remove_solid(id).map_err(py_err)?;
        // The Python forces' specs follow the engine's user forces: those on it go.
        g.solid_forces.retain(|f| f.0 != row);
        for f in &mut g.solid_forces {
            if f.0 > row {
                f.0 -= 1;
            }
        }
        return Ok(true);
    }
    if let Ok(h) = handle.cast::<SolidSpringHandle>() {
        let h = h.get();
        let mut g = world.lock()?;
        let id = SolidSpringId(h.id_in(g.family)?);
        if g.engine.solid_spring_row(id).is_none() {
            return Err(h.gone());
        }
        g.flush()?.remove_solid_spring(id).map_err(py_err)?;
        return Ok(true);
    }
    if let Ok(h) = handle.cast::<SolidForceHandle>() {
        let h = h.get();
        let mut g = world.lock()?;
        let id = SolidForceId(h.id_in(g.family)?);
        if g.engine.solid_force_row(id).is_none() {
            return Err(h.gone());
        }
        let row = g.flush()?.remove_solid_force(id).map_err(py_err)?;
        g.solid_forces.remove(row);
        return Ok(true);
    }
    Ok(false)
}

/// The solids of a World as a sequence: `len(w.solids)`, `w.solids[i]` or `w.solids[h]` (a
/// `SolidHandle`, which is also the solid's view), iteration in row order.
#[pyclass(module = "physstep._core", frozen, name = "Solids")]
pub struct Solids {
    world: Py<World>,
}

#[pymethods]
impl Solids {
    fn __len__(&self) -> PyResult<usize> {
        Ok(self.world.get().lock()?.engine.solid_count())
    }

    fn __getitem__(&self, py: Python<'_>, i: &Bound<'_, PyAny>) -> PyResult<SolidHandle> {
        let g = self.world.get().lock()?;
        if let Ok(h) = i.cast::<SolidHandle>() {
            let h = h.get();
            let id = h.id_in(g.family)?;
            h.row_in(&g.engine).ok_or_else(|| h.gone())?;
            return Ok(SolidHandle { world: self.world.clone_ref(py), family: g.family, id });
        }
        let n = g.engine.solid_count();
        let k = crate::convert::whole(i, "index", i64::MIN, i64::MAX)?;
        let at = if k < 0 { k + n as i64 } else { k };
        if at < 0 || at >= n as i64 {
            return Err(PyIndexError::new_err(format!(
                "solid index {k} out of range: the World has {n} solids"
            )));
        }
        Ok(SolidHandle::of_row(self.world.bind(py), &g.engine, g.family, at as usize))
    }

    fn __iter__(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let g = self.world.get().lock()?;
        let world = self.world.bind(py);
        let views: Vec<SolidHandle> =
            (0..g.engine.solid_count()).map(|r| SolidHandle::of_row(world, &g.engine, g.family, r)).collect();
        drop(g);
        Ok(pyo3::types::PyList::new(py, views)?.try_iter()?.into_any().unbind())
    }

    fn __repr__(&self) -> PyResult<String> {
        Ok(format!("<{} solids>", self.__len__()?))
    }
}

#[pymethods]
impl World {
    /// The solids as a sequence of handles, each also the solid's view
    /// (`w.solids[i].velocity = ...`), in row order: the order they were added, the removed
    /// ones taken out.
    #[getter]
    fn solids(slf: &Bound<'_, Self>) -> Solids {
        Solids { world: slf.clone().unbind() }
    }

    /// Handles of the solid springs, in row order.
    #[getter]
    fn solid_springs(slf: &Bound<'_, Self>) -> PyResult<Vec<SolidSpringHandle>> {
        let g = slf.get().lock()?;
        Ok((0..g.engine.solid_springs().len()).map(|r| spring_handle(slf, &g.engine, g.family, r)).collect())
    }
}
