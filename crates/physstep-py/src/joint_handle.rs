//! `physstep.JointHandle`, what `add_joint` returns: one joint of one World by the engine's id
//! (`physstep::contact::JointId`, a counter never reused), its parameters as made readable,
//! its motor (`motor_speed`, `max_motor`) and limits (`lower`, `upper`) writable through the
//! World, and its removal (`remove_joint`). The handles of solids, solid springs and forces
//! on solids, and what the four share (`handle_common!`), are in `crate::solid_handles`.

use crate::convert::float;
use crate::handle::World;
use crate::py_err;
use crate::solid_handles::{handle_common, vector, SolidHandle};
use physstep::contact::JointId;
use physstep::world::World as Engine;
use pyo3::prelude::*;

/// A handle to one joint of a World: `id`, `alive`, its parameters as made (`kind`, `a`,
/// `b`, `anchor`, ...), the motor (`motor_speed`, `max_motor`) and limits (`lower`,
/// `upper`) writable.
#[pyclass(module = "physstep._core", frozen, name = "JointHandle")]
pub struct JointHandle {
    world: Py<World>,
    family: u64,
    id: u64,
}

handle_common!(JointHandle, "joint");

impl JointHandle {
    fn row_in(&self, w: &Engine) -> Option<usize> {
        w.joint_row(JointId(self.id))
    }

    /// The joint's parameters as made (and changed since), with `f` on them.
    fn params<T>(&self, f: impl FnOnce(&physstep::contact::JointParams) -> T) -> PyResult<T> {
        let g = self.world.get().lock()?;
        let row = self.row_in(&g.engine).ok_or_else(|| self.gone())?;
        Ok(f(&g.engine.joint_params()[row]))
    }

    /// The handle of solid row `row` of this joint's World.
    fn solid(&self, py: Python<'_>, row: Option<usize>) -> PyResult<Option<SolidHandle>> {
        let g = self.world.get().lock()?;
        let world = self.world.bind(py);
        Ok(row.map(|r| SolidHandle::of_row(world, &g.engine, self.family, r)))
    }

    /// Sets the motor from its parameters as they are, changed by `change`.
    fn set_motor(&self, change: impl FnOnce(&mut (f64, f64))) -> PyResult<()> {
        let mut g = self.world.get().lock()?;
        let w = g.flush()?;
        let row = self.row_in(w).ok_or_else(|| self.gone())?;
        let p = &w.joint_params()[row];
        let mut m = (p.motor_speed, p.max_motor);
        change(&mut m);
        w.set_joint_motor(JointId(self.id), m.0, m.1).map_err(py_err)
    }

    fn set_limits(&self, change: impl FnOnce(&mut (Option<f64>, Option<f64>))) -> PyResult<()> {
        let mut g = self.world.get().lock()?;
        let w = g.flush()?;
        let row = self.row_in(w).ok_or_else(|| self.gone())?;
        let p = &w.joint_params()[row];
        let mut l = (p.lower, p.upper);
        change(&mut l);
        w.set_joint_limits(JointId(self.id), l.0, l.1).map_err(py_err)
    }
}

fn maybe(o: &Bound<'_, PyAny>, field: &str) -> PyResult<Option<f64>> {
    if o.is_none() {
        Ok(None)
    } else {
        float(o, field).map(Some)
    }
}

#[pymethods]
impl JointHandle {
    /// "ball", "revolute", "distance", "weld" or "prismatic".
    #[getter]
    fn kind(&self) -> PyResult<&'static str> {
        self.params(|p| p.kind.name())
    }

    /// The first solid's handle.
    #[getter]
    fn a(&self, py: Python<'_>) -> PyResult<Option<SolidHandle>> {
        let a = self.params(|p| p.a)?;
        self.solid(py, Some(a))
    }

    /// The second solid's handle, or None: the world.
    #[getter]
    fn b(&self, py: Python<'_>) -> PyResult<Option<SolidHandle>> {
        let b = self.params(|p| p.b)?;
        self.solid(py, b)
    }

    /// The anchor as given when the joint was made (world coordinates then), m.
    #[getter]
    fn anchor(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let a = self.params(|p| p.anchor.clone())?;
        Ok(vector(py, &a))
    }

    /// The end on `b` as given (a distance joint's), or None.
    #[getter]
    fn anchor_b(&self, py: Python<'_>) -> PyResult<Option<Py<PyAny>>> {
        Ok(self.params(|p| p.anchor_b.clone())?.map(|a| vector(py, &a)))
    }

    /// The axis as given (a slider's or a 3D hinge's), or None.
    #[getter]
    fn axis(&self, py: Python<'_>) -> PyResult<Option<Py<PyAny>>> {
        Ok(self.params(|p| p.axis.clone())?.map(|a| vector(py, &a)))
    }

    /// A distance joint's length, min_length and max_length as given (None: as made).
    #[getter]
    fn length(&self) -> PyResult<Option<f64>> {
        self.params(|p| p.length)
    }

    #[getter]
    fn min_length(&self) -> PyResult<Option<f64>> {
        self.params(|p| p.min_length)
    }

    #[getter]
    fn max_length(&self) -> PyResult<Option<f64>> {
        self.params(|p| p.max_length)
    }

    /// Softness, Hz (0: rigid), and its damping ratio.
    #[getter]
    fn hertz(&self) -> PyResult<f64> {
        self.params(|p| p.hertz)
    }

    #[getter]
    fn damping_ratio(&self) -> PyResult<f64> {
        self.params(|p| p.damping_ratio)
    }

    /// Whether its two solids still collide.
    #[getter]
    fn collide(&self) -> PyResult<bool> {
        self.params(|p| p.collide)
    }

    /// The lower limit (rad for a hinge, m for a slider; None: none); assign a number or
    /// None (validated as `add_joint`: lower <= upper).
    #[getter]
    fn lower(&self) -> PyResult<Option<f64>> {
        self.params(|p| p.lower)
    }

    #[setter]
    fn set_lower(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = maybe(value, "lower")?;
        self.set_limits(|l| l.0 = v)
    }

    /// The upper limit (None: none); assign a number or None.
    #[getter]
    fn upper(&self) -> PyResult<Option<f64>> {
        self.params(|p| p.upper)
    }

    #[setter]
    fn set_upper(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = maybe(value, "upper")?;
        self.set_limits(|l| l.1 = v)
    }

    /// The motor's speed (rad/s, or m/s for a slider); assign to change it (finite).
    #[getter]
    fn motor_speed(&self) -> PyResult<f64> {
        self.params(|p| p.motor_speed)
    }

    #[setter]
    fn set_motor_speed(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(value, "motor_speed")?;
        self.set_motor(|m| m.0 = v)
    }

    /// The motor's largest torque (N m) or force (N); assign to change it (>= 0; 0: no
    /// motor).
    #[getter]
    fn max_motor(&self) -> PyResult<f64> {
        self.params(|p| p.max_motor)
    }

    #[setter]
    fn set_max_motor(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(value, "max_motor")?;
        self.set_motor(|m| m.1 = v)
    }
}

/// The handle of the joint just added at `row`.
pub(crate) fn joint_handle(world: &Bound<'_, World>, w: &Engine, family: u64, row: usize) -> JointHandle {
    JointHandle { world: world.clone().unbind(), family, id: w.joint_ids()[row].0 }
}

/// `World.remove(h)` for a `JointHandle`: `Ok(true)` when `handle` was one (and is removed),
/// `Ok(false)` when it is of another class (the caller goes on).
pub(crate) fn remove_joint(world: &World, handle: &Bound<'_, PyAny>) -> PyResult<bool> {
    if let Ok(h) = handle.cast::<JointHandle>() {
        let h = h.get();
        let mut g = world.lock()?;
        let id = JointId(h.id_in(g.family)?);
        if g.engine.joint_row(id).is_none() {
            return Err(h.gone());
        }
        g.flush()?.remove_joint(id).map_err(py_err)?;
        return Ok(true);
    }
    Ok(false)
}

#[pymethods]
impl World {
    /// Handles of the joints, in row order.
    #[getter]
    fn joints(slf: &Bound<'_, Self>) -> PyResult<Vec<JointHandle>> {
        let g = slf.get().lock()?;
        Ok((0..g.engine.joint_count()).map(|r| joint_handle(slf, &g.engine, g.family, r)).collect())
    }
}
