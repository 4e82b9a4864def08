//! `physstep.ForceHandle`: what every `add_*` of a force returns. It names one force of one
//! World by the engine's id (a counter never reused, `physstep::forces::ForceId`), so it
//! stays that force's while others are added or removed; its parameters read and write
//! through it (`h.stiffness = 2e3`), validated as the add was.
//!
//! A handle is bound to the World it came from. A World's copies and pickles carry its
//! forces' ids and its family token (`Inner::family`), so `copy.force(h)` and
//! `copy.remove(h)` reach the same force in the copy; a World of another family refuses the
//! handle in one line.

use crate::convert::{float, vector};
use crate::handle::World;
use crate::py_err;
use numpy::PyArray1;
use physstep::forces::{Endpoint, Force, ForceId};
use pyo3::exceptions::{PyAttributeError, PyValueError};
use pyo3::prelude::*;

/// A handle to one force of a World: `kind`, `id`, and the force's parameters as
/// properties, readable and writable (validated as the `add_*` call).
#[pyclass(module = "physstep._core", frozen, name = "ForceHandle")]
pub struct ForceHandle {
    world: Py<World>,
    family: u64,
    id: u64,
    kind: &'static str,
}

/// The kind a Python force's handle reports.
pub(crate) const PYTHON: &str = "python";

impl ForceHandle {
    /// The handle of force `id` of `world`.
    pub(crate) fn new(world: &Bound<'_, World>, family: u64, id: ForceId, kind: &'static str) -> Self {
        Self { world: world.clone().unbind(), family, id: id.0, kind }
    }

    /// `(family, id)`, checked to be a force of the World of family `family`.
    pub(crate) fn id_in(&self, family: u64) -> PyResult<ForceId> {
        if self.family != family {
            return Err(crate::errors::foreign_handle("force", "forces", &self.text()));
        }
        Ok(ForceId(self.id))
    }

    pub(crate) fn kind_name(&self) -> &'static str {
        self.kind
    }

    fn text(&self) -> String {
        format!("ForceHandle(id={}, kind='{}')", self.id, self.kind)
    }

    /// The force as its World holds it now.
    fn get(&self, name: &str) -> PyResult<Force> {
        if self.kind == PYTHON {
            return Err(self.none(name));
        }
        let g = self.world.get().lock()?;
        g.engine.force(ForceId(self.id)).ok_or_else(|| self.gone())
    }

    /// The force changed by `change` (handed the force as it is), validated and put in place.
    fn set(&self, name: &str, change: impl FnOnce(Force, usize) -> PyResult<Force>) -> PyResult<()> {
        if self.kind == PYTHON {
            return Err(self.none(name));
        }
        let mut g = self.world.get().lock()?;
        let w = g.flush()?;
        let Some(old) = w.force(ForceId(self.id)) else {
            return Err(self.gone());
        };
        let new = change(old, w.dim())?;
        w.set_force(ForceId(self.id), new).map_err(py_err)
    }

    fn gone(&self) -> PyErr {
        crate::errors::removed_handle("force", &self.text())
    }

    /// `AttributeError`: this kind of force has no parameter `what`.
    fn none(&self, what: &str) -> PyErr {
        PyAttributeError::new_err(format!("a {} force has no {what}", self.kind))
    }

    fn dim(&self) -> PyResult<usize> {
        Ok(self.world.get().lock()?.engine.dim())
    }
}

fn vec_out(py: Python<'_>, v: [f64; 3], dim: usize) -> Py<PyAny> {
    PyArray1::from_slice(py, &v[..dim]).into_any().unbind()
}

/// Replaces a spring's parameter (stiffness, rest length, damping: `k`).
fn spring_param(f: Force, k: usize, value: f64, h: &ForceHandle, name: &str) -> PyResult<Force> {
    match f {
        Force::Spring { i, j, stiffness, rest_length, damping } => {
            let mut p = [stiffness, rest_length, damping];
            p[k] = value;
            Ok(Force::Spring { i, j, stiffness: p[0], rest_length: p[1], damping: p[2] })
        }
        _ => Err(h.none(name)),
    }
}

#[pymethods]
impl ForceHandle {
    /// The force's id in its World: never given to another force of that World.
    #[getter]
    fn id(&self) -> u64 {
        self.id
    }

    /// `gravity`, `spring`, `drag`, `central-gravity`, `nbody`, `rod` or `python`.
    #[getter]
    fn kind(&self) -> &'static str {
        self.kind
    }

    /// The World the handle came from.
    #[getter]
    fn world(&self, py: Python<'_>) -> Py<World> {
        self.world.clone_ref(py)
    }

    /// Whether the force is still in its World.
    #[getter]
    fn alive(&self) -> PyResult<bool> {
        let g = self.world.get().lock()?;
        let id = ForceId(self.id);
        Ok(g.engine.force(id).is_some() || g.engine.is_user_force(id))
    }

    fn __repr__(&self) -> String {
        self.text()
    }

    /// Equal handles name the same force of the same World.
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<ForceHandle>().is_ok_and(|o| {
            let o = o.get();
            o.id == self.id && o.world.as_ptr() == self.world.as_ptr()
        })
    }

    fn __hash__(&self) -> u64 {
        self.id ^ (self.world.as_ptr() as u64).rotate_left(17)
    }

    /// A spring's stiffness, N/m (>= 0).
    #[getter]
    fn stiffness(&self) -> PyResult<f64> {
        match self.get("stiffness")? {
            Force::Spring { stiffness, .. } => Ok(stiffness),
            _ => Err(self.none("stiffness")),
        }
    }

    #[setter]
    fn set_stiffness(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(value, "stiffness")?;
        self.set("stiffness", |f, _| spring_param(f, 0, v, self, "stiffness"))
    }

    /// A spring's rest length, m (>= 0).
    #[getter]
    fn rest_length(&self) -> PyResult<f64> {
        match self.get("rest_length")? {
            Force::Spring { rest_length, .. } => Ok(rest_length),
            _ => Err(self.none("rest_length")),
        }
    }

    #[setter]
    fn set_rest_length(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(value, "rest_length")?;
        self.set("rest_length", |f, _| spring_param(f, 1, v, self, "rest_length"))
    }

    /// A spring's damping along it, N s/m (>= 0).
    #[getter]
    fn damping(&self) -> PyResult<f64> {
        match self.get("damping")? {
            Force::Spring { damping, .. } => Ok(damping),
            _ => Err(self.none("damping")),
        }
    }

    #[setter]
    fn set_damping(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(value, "damping")?;
        self.set("damping", |f, _| spring_param(f, 2, v, self, "damping"))
    }

    /// The first particle of a spring or rod (the lower index of a pair: the World stores a
    /// pair as `i < j`). Read-only: remove the force and add another to change its ends.
    #[getter]
    fn i(&self) -> PyResult<usize> {
        match self.get("i")? {
            Force::Spring { i, .. } | Force::Rod { i, .. } => Ok(i),
            _ => Err(self.none("i")),
        }
    }

    /// The other particle of a spring or rod, or None when its other end is an anchor.
    /// Read-only.
    #[getter]
    fn j(&self) -> PyResult<Option<usize>> {
        match self.get("j")? {
            Force::Spring { j, .. } | Force::Rod { j, .. } => {
                Ok(if let Endpoint::Particle(j) = j { Some(j) } else { None })
            }
            _ => Err(self.none("j")),
        }
    }

    /// The anchor point (dim,) of a spring or rod to a fixed point, m, or None when its
    /// other end is a particle. Writable for a spring to an anchor (a mouse spring that
    /// follows the cursor); a rod's anchor must keep the rod's length.
    #[getter]
    fn anchor(&self, py: Python<'_>) -> PyResult<Option<Py<PyAny>>> {
        let d = self.dim()?;
        match self.get("anchor")? {
            Force::Spring { j, .. } | Force::Rod { j, .. } => {
                Ok(if let Endpoint::Anchor(a) = j { Some(vec_out(py, a, d)) } else { None })
            }
            _ => Err(self.none("anchor")),
        }
    }

    #[setter]
    fn set_anchor(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set("anchor", |f, d| {
            let at = Endpoint::Anchor(vector(value, "anchor", d)?);
            match f {
                Force::Spring { i, j: Endpoint::Anchor(_), stiffness, rest_length, damping } => {
                    Ok(Force::Spring { i, j: at, stiffness, rest_length, damping })
                }
                Force::Rod { i, j: Endpoint::Anchor(_), length } => Ok(Force::Rod { i, j: at, length }),
                Force::Spring { .. } | Force::Rod { .. } => Err(PyValueError::new_err(format!(
                    "invalid anchor: {} joins two particles, it has no anchor to move",
                    self.text()
                ))),
                _ => Err(self.none("anchor")),
            }
        })
    }

    /// A rod's length, m (read-only: a rod holds the length its ends have).
    #[getter]
    fn length(&self) -> PyResult<f64> {
        match self.get("length")? {
            Force::Rod { length, .. } => Ok(length),
            _ => Err(self.none("length")),
        }
    }

    /// Uniform gravity's acceleration (dim,), m/s^2; n-body gravity's constant G (a
    /// number).
    #[getter]
    fn g(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let d = self.dim()?;
        match self.get("g")? {
            Force::Gravity { g } => Ok(vec_out(py, g, d)),
            Force::NBody { g, .. } => Ok(g.into_pyobject(py)?.into_any().unbind()),
            _ => Err(self.none("g")),
        }
    }

    #[setter]
    fn set_g(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set("g", |f, d| match f {
            Force::Gravity { .. } => Ok(Force::Gravity { g: vector(value, "g", d)? }),
            Force::NBody { softening, .. } => Ok(Force::NBody { g: float(value, "g")?, softening }),
            _ => Err(self.none("g")),
        })
    }

    /// N-body gravity's softening length, m (>= 0).
    #[getter]
    fn softening(&self) -> PyResult<f64> {
        match self.get("softening")? {
            Force::NBody { softening, .. } => Ok(softening),
            _ => Err(self.none("softening")),
        }
    }

    #[setter]
    fn set_softening(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(value, "softening")?;
        self.set("softening", |f, _| match f {
            Force::NBody { g, .. } => Ok(Force::NBody { g, softening: v }),
            _ => Err(self.none("softening")),
        })
    }

    /// Drag's linear coefficient, N s/m (>= 0).
    #[getter]
    fn linear(&self) -> PyResult<f64> {
        match self.get("linear")? {
            Force::Drag { linear, .. } => Ok(linear),
            _ => Err(self.none("linear")),
        }
    }

    #[setter]
    fn set_linear(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(value, "linear")?;
        self.set("linear", |f, _| match f {
            Force::Drag { quadratic, .. } => Ok(Force::Drag { linear: v, quadratic }),
            _ => Err(self.none("linear")),
        })
    }

    /// Drag's quadratic coefficient, N s^2/m^2 (>= 0).
    #[getter]
    fn quadratic(&self) -> PyResult<f64> {
        match self.get("quadratic")? {
            Force::Drag { quadratic, .. } => Ok(quadratic),
            _ => Err(self.none("quadratic")),
        }
    }

    #[setter]
    fn set_quadratic(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(value, "quadratic")?;
        self.set("quadratic", |f, _| match f {
            Force::Drag { linear, .. } => Ok(Force::Drag { linear, quadratic: v }),
            _ => Err(self.none("quadratic")),
        })
    }

    /// Central gravity's centre (dim,), m.
    #[getter]
    fn center(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let d = self.dim()?;
        match self.get("center")? {
            Force::CentralGravity { center, .. } => Ok(vec_out(py, center, d)),
            _ => Err(self.none("center")),
        }
    }

    #[setter]
    fn set_center(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set("center", |f, d| match f {
            Force::CentralGravity { gm, .. } => {
                Ok(Force::CentralGravity { center: vector(value, "center", d)?, gm })
            }
            _ => Err(self.none("center")),
        })
    }

    /// Central gravity's parameter G M, m^3/s^2.
    #[getter]
    fn gm(&self) -> PyResult<f64> {
        match self.get("gm")? {
            Force::CentralGravity { gm, .. } => Ok(gm),
            _ => Err(self.none("gm")),
        }
    }

    #[setter]
    fn set_gm(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(value, "gm")?;
        self.set("gm", |f, _| match f {
            Force::CentralGravity { center, .. } => Ok(Force::CentralGravity { center, gm: v }),
            _ => Err(self.none("gm")),
        })
    }
}
