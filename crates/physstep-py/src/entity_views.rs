//! Per-entity views, in the style of REBOUND's `sim.particles[i]` and pymunk's bodies:
//! `w.particles[i].position = ...`, `w.bodies[b].velocity`, read and written through the
//! World (each read a copy, each write validated as the add call and applied at once).
//!
//! A particle view taken by handle (`w.particles[h]`, `h` a `ParticleHandle`) carries the
//! particle's id and looks its row up at each use: it stays that particle's while others are
//! removed, and refuses in one line once it is removed itself. A view taken by an int names
//! the row (after a removal, the particle that moved into it). Body views likewise.

use crate::convert::{array, whole};
use crate::handle::World;
use crate::py_err;
use crate::world_bodies::per_body;
use numpy::{PyArray1, PyArray2};
use physstep::world::World as Engine;
use pyo3::exceptions::PyIndexError;
use pyo3::prelude::*;

/// `i` as an index of a sequence of `n` (negative from the end), or `IndexError`.
fn position_of(i: &Bound<'_, PyAny>, n: usize, what: &str) -> PyResult<usize> {
    let k = whole(i, "index", i64::MIN, i64::MAX)?;
    let at = if k < 0 { k + n as i64 } else { k };
    if at < 0 || at >= n as i64 {
        return Err(PyIndexError::new_err(format!(
            "{what} index {k} out of range: the World has {n} {what}s"
        )));
    }
    Ok(at as usize)
}

/// The particles of a World as a sequence: `len(w.particles)`, `w.particles[i]` (a
/// `Particle` view), iteration.
#[pyclass(module = "physstep._core", frozen, name = "Particles")]
pub struct Particles {
    pub(crate) world: Py<World>,
}

/// One particle of a World: `position`, `velocity`, `mass`, readable and writable.
#[pyclass(module = "physstep._core", frozen, name = "Particle")]
pub struct Particle {
    world: Py<World>,
    index: usize,
    /// The particle's id when the view was taken by handle (then `index` is unused).
    id: Option<u64>,
}

#[pymethods]
impl Particles {
    fn __len__(&self) -> PyResult<usize> {
        Ok(self.world.get().lock()?.count())
    }

    fn __getitem__(&self, py: Python<'_>, i: &Bound<'_, PyAny>) -> PyResult<Particle> {
        if let Ok(h) = i.cast::<crate::entity_handle::ParticleHandle>() {
            // Checked now (another World's, or removed: one line), looked up at each use.
            let g = self.world.get().lock()?;
            h.get().row_in(&g, "particle")?;
            return Ok(Particle { world: self.world.clone_ref(py), index: 0, id: Some(h.get().id) });
        }
        if crate::entity_handle::is_handle(i) {
            return Err(crate::convert::invalid("index", i, "a particle index or a ParticleHandle"));
        }
        let n = self.world.get().lock()?.count();
        let index = position_of(i, n, "particle")?;
        Ok(Particle { world: self.world.clone_ref(py), index, id: None })
    }

    fn __iter__(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let n = self.world.get().lock()?.count();
        let views: Vec<Particle> =
            (0..n).map(|index| Particle { world: self.world.clone_ref(py), index, id: None }).collect();
        Ok(pyo3::types::PyList::new(py, views)?.try_iter()?.into_any().unbind())
    }

    fn __repr__(&self) -> PyResult<String> {
        Ok(format!("<{} particles>", self.__len__()?))
    }
}

impl Particle {
    /// The particle's row in the flushed World `g`: its id's row for a view taken by handle.
    fn row(&self, g: &mut crate::handle::Inner) -> PyResult<usize> {
        g.flush()?;
        match self.id {
            // Rows move up after a removal: a view by index past the end says so.
            None if self.index >= g.engine.len() => Err(pyo3::exceptions::PyValueError::new_err(format!(
                "invalid particle = {}: must be an index below {}",
                self.index,
                g.engine.len()
            ))),
            None => Ok(self.index),
            Some(id) => crate::entity_handle::particle_row(g, id).ok_or_else(|| {
                pyo3::exceptions::PyValueError::new_err(format!(
                    "invalid particle = ParticleHandle(id={id}): it was removed from its World"
                ))
            }),
        }
    }

    /// `read(engine, i, dim)` on the flushed engine.
    fn read<T>(&self, read: impl FnOnce(&Engine, usize, usize) -> T) -> PyResult<T> {
        let mut g = self.world.get().lock()?;
        let i = self.row(&mut g)?;
        let w = &g.engine;
        Ok(read(w, i, w.dim()))
    }
}

#[pymethods]
impl Particle {
    /// The particle's index in the World (the row of `World.positions`; for a view taken by
    /// handle, its current row).
    #[getter]
    fn index(&self) -> PyResult<usize> {
        let mut g = self.world.get().lock()?;
        self.row(&mut g)
    }

    /// Position (dim,), m (a copy); assign to move the particle (validated as
    /// `add_particle`; a teleport restarts a method's memory, as assigning
    /// `World.positions` does).
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = self.read(|w, i, d| w.positions()[i * d..(i + 1) * d].to_vec())?;
        Ok(PyArray1::from_vec(py, x))
    }

    #[setter]
    fn set_position(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut g = self.world.get().lock()?;
        let i = self.row(&mut g)?;
        let x = array(value, "position", Some(g.engine.dim()), None)?;
        g.engine.set_particle(i, Some(&x), None).map_err(py_err)
    }

    /// Velocity (dim,), m/s (a copy); assign to set it (validated as `add_particle`; a
    /// static particle's stays zero: a nonzero one is refused).
    #[getter]
    fn velocity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let v = self.read(|w, i, d| w.velocities()[i * d..(i + 1) * d].to_vec())?;
        Ok(PyArray1::from_vec(py, v))
    }

    #[setter]
    fn set_velocity(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut g = self.world.get().lock()?;
        let i = self.row(&mut g)?;
        let v = array(value, "velocity", Some(g.engine.dim()), None)?;
        g.engine.set_particle(i, None, Some(&v)).map_err(py_err)
    }

    /// Mass, kg (inf for a particle added with mass inf); assign to change it (validated as
    /// `add_particle`; the velocity is kept; a dynamic particle takes a finite mass, a static
    /// one stays static).
    #[getter]
    fn mass(&self) -> PyResult<f64> {
        self.read(|w, i, _| w.model().mass()[i])
    }

    #[setter]
    fn set_mass(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let m = crate::convert::float(value, "mass")?;
        let mut g = self.world.get().lock()?;
        let i = self.row(&mut g)?;
        g.engine.set_mass(i, m).map_err(py_err)
    }

    /// Whether the particle is static (immovable).
    #[getter]
    fn r#static(&self) -> PyResult<bool> {
        self.read(|w, i, _| w.model().inv_mass()[i] == 0.0)
    }

    fn __repr__(&self) -> String {
        match self.id {
            None => format!("<particle {}>", self.index),
            Some(id) => format!("<particle id={id}>"),
        }
    }
}

/// The rigid bodies of a World as a sequence: `len(w.bodies)`, `w.bodies[b]` (a `Body`
/// view), iteration, and their state as arrays (`positions`, `velocities`, `orientations`,
/// `angular_velocities`: copies, one row per body in the order they were added).
#[pyclass(module = "physstep._core", frozen, name = "Bodies")]
pub struct Bodies {
    pub(crate) world: Py<World>,
}

/// One rigid body of a World: `position`, `velocity`, `orientation`, `angular_velocity`,
/// readable and writable.
#[pyclass(module = "physstep._core", frozen, name = "Body")]
pub struct Body {
    world: Py<World>,
    index: usize,
    /// The body's id when the view was taken by handle (then `index` is unused).
    id: Option<u64>,
}

#[pymethods]
impl Bodies {
    fn __len__(&self) -> PyResult<usize> {
        Ok(self.world.get().lock()?.engine.bodies().len())
    }

    fn __getitem__(&self, py: Python<'_>, i: &Bound<'_, PyAny>) -> PyResult<Body> {
        if let Ok(h) = i.cast::<crate::entity_handle::BodyHandle>() {
            let g = self.world.get().lock()?;
            h.get().row_in(&g, "body")?;
            return Ok(Body { world: self.world.clone_ref(py), index: 0, id: Some(h.get().id) });
        }
        if crate::entity_handle::is_handle(i) {
            return Err(crate::convert::invalid("index", i, "a body index or a BodyHandle"));
        }
        let n = self.__len__()?;
        let index = position_of(i, n, "body")?;
        Ok(Body { world: self.world.clone_ref(py), index, id: None })
    }

    fn __iter__(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let n = self.__len__()?;
        let views: Vec<Body> =
            (0..n).map(|index| Body { world: self.world.clone_ref(py), index, id: None }).collect();
        Ok(pyo3::types::PyList::new(py, views)?.try_iter()?.into_any().unbind())
    }

    fn __repr__(&self) -> PyResult<String> {
        Ok(format!("<{} bodies>", self.__len__()?))
    }

    /// Centres of mass (nb, 3), m.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        per_body(py, &self.world.get().lock()?.engine, Engine::body_position)
    }

    /// Velocities of the centres of mass (nb, 3), m/s.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        per_body(py, &self.world.get().lock()?.engine, Engine::body_velocity)
    }

    /// Orientations of the shape frames (nb, 4), unit quaternions (w, x, y, z).
    #[getter]
    fn orientations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        per_body(py, &self.world.get().lock()?.engine, Engine::body_orientation)
    }

    /// Angular velocities (nb, 3), rad/s, world frame.
    #[getter]
    fn angular_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        per_body(py, &self.world.get().lock()?.engine, Engine::body_angular_velocity)
    }
}

type BodyState = (Option<[f64; 3]>, Option<[f64; 3]>, Option<[f64; 4]>, Option<[f64; 3]>);

impl Body {
    /// The body's row: its id's row for a view taken by handle.
    fn row(&self, g: &crate::handle::Inner) -> PyResult<usize> {
        match self.id {
            None => Ok(self.index),
            Some(id) => g.engine.body_row(physstep::world::BodyId(id)).ok_or_else(|| {
                pyo3::exceptions::PyValueError::new_err(format!(
                    "invalid body = BodyHandle(id={id}): it was removed from its World"
                ))
            }),
        }
    }

    fn read<const N: usize>(
        &self,
        py: Python<'_>,
        read: fn(&Engine, usize) -> physstep::Result<[f64; N]>,
    ) -> PyResult<Py<PyArray1<f64>>> {
        let g = self.world.get().lock()?;
        let v = read(&g.engine, self.row(&g)?).map_err(py_err)?;
        Ok(PyArray1::from_slice(py, &v).unbind())
    }

    fn write(&self, state: BodyState) -> PyResult<()> {
        let (x, v, q, w) = state;
        let mut g = self.world.get().lock()?;
        let b = self.row(&g)?;
        g.flush()?.set_body_state(b, x, v, q, w).map_err(py_err)
    }
}

/// A 3-vector argument named `field` (validated for finiteness by the engine).
fn three(value: &Bound<'_, PyAny>, field: &str) -> PyResult<[f64; 3]> {
    let a = array(value, field, Some(3), None)?;
    Ok([a[0], a[1], a[2]])
}

#[pymethods]
impl Body {
    /// The body's index in the World (the row of `World.bodies.positions`; for a view taken
    /// by handle, its current row).
    #[getter]
    fn index(&self) -> PyResult<usize> {
        let g = self.world.get().lock()?;
        self.row(&g)
    }

    /// Centre of mass (3,), m (a copy); assign to move the body (validated as `add_body`;
    /// refused for a pinned body; a teleport restarts a method's memory).
    #[getter]
    fn position(&self, py: Python<'_>) -> PyResult<Py<PyArray1<f64>>> {
        self.read(py, Engine::body_position)
    }

    #[setter]
    fn set_position(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.write((Some(three(value, "position")?), None, None, None))
    }

    /// Velocity of the centre of mass (3,), m/s; assign to set it (a pinned body's must be
    /// zero).
    #[getter]
    fn velocity(&self, py: Python<'_>) -> PyResult<Py<PyArray1<f64>>> {
        self.read(py, Engine::body_velocity)
    }

    #[setter]
    fn set_velocity(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.write((None, Some(three(value, "velocity")?), None, None))
    }

    /// Orientation of the shape frame (4,), a unit quaternion (w, x, y, z); assign any
    /// quaternion of length >= 1e-12: it is normalised, as `add_body` does (a shorter one,
    /// or one not finite, is refused). The angular velocity is kept.
    #[getter]
    fn orientation(&self, py: Python<'_>) -> PyResult<Py<PyArray1<f64>>> {
        self.read(py, Engine::body_orientation)
    }

    #[setter]
    fn set_orientation(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let a = array(value, "orientation", Some(4), None)?;
        self.write((None, None, Some([a[0], a[1], a[2], a[3]]), None))
    }

    /// Angular velocity (3,), rad/s, world frame; assign to set it.
    #[getter]
    fn angular_velocity(&self, py: Python<'_>) -> PyResult<Py<PyArray1<f64>>> {
        self.read(py, Engine::body_angular_velocity)
    }

    #[setter]
    fn set_angular_velocity(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.write((None, None, None, Some(three(value, "angular_velocity")?)))
    }

    /// Mass, kg.
    #[getter]
    fn mass(&self) -> PyResult<f64> {
        let g = self.world.get().lock()?;
        let (b, n) = (self.row(&g)?, g.engine.bodies().len());
        g.engine.bodies().mass().get(b).copied().ok_or_else(|| {
            pyo3::exceptions::PyValueError::new_err(format!("invalid body = {b}: must be an index below {n}"))
        })
    }

    fn __repr__(&self) -> String {
        match self.id {
            None => format!("<body {}>", self.index),
            Some(id) => format!("<body id={id}>"),
        }
    }
}

#[pymethods]
impl World {
    /// The particles as a sequence of views: `w.particles[i].position = ...`.
    #[getter]
    fn particles(slf: &Bound<'_, Self>) -> Particles {
        Particles { world: slf.clone().unbind() }
    }

    /// The rigid bodies as a sequence of views (`w.bodies[b].velocity = ...`) with their
    /// state as arrays (`w.bodies.positions`).
    #[getter]
    fn bodies(slf: &Bound<'_, Self>) -> Bodies {
        Bodies { world: slf.clone().unbind() }
    }
}
