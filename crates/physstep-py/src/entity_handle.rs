//! `physstep.ParticleHandle`, `ConstraintHandle`, `BodyHandle` and `ParticleHandles`: what
//! `add_particle`, `add_ball`, the `add_*` of constraints, `add_body`, and `add_particles` /
//! `add_balls` return. A handle
//! names one entity of one World by the engine's id (`physstep::world::ParticleId`,
//! `ConstraintId`: a counter never reused), so it stays that entity's while others are
//! removed; `__index__` gives the entity's current row, so `w.positions[h]` and every call
//! that takes an index take a handle too.
//!
//! Like a `ForceHandle`, a handle carries its World's family token (`Inner::family`): the
//! World's copies and pickles take it, another World refuses it in one line. World methods
//! resolve a handle under the lock they hold (`particle`), never through `__index__` (which
//! takes the lock itself).

use crate::errors::{foreign_handle, removed_handle};
use crate::handle::{Inner, World};
use numpy::PyArray1;
use physstep::constraints::Constraint;
use physstep::forces::Endpoint;
use physstep::world::{BodyId, ConstraintId, ParticleId};
use pyo3::exceptions::{PyAttributeError, PyIndexError, PyValueError};
use pyo3::prelude::*;

/// The current row of particle `id` in a World: a row of the engine, or one of the particles
/// waiting in the batch (ids given in order after the engine's counter).
pub(crate) fn particle_row(g: &Inner, id: u64) -> Option<usize> {
    if let Some(r) = g.engine.particle_row(ParticleId(id)) {
        return Some(r);
    }
    let next = g.engine.next_particle_id().0;
    (id >= next && id - next < g.pending.len() as u64).then(|| g.engine.len() + (id - next) as usize)
}

/// A handle to one particle (or ball) of a World: `id`, `alive`, and its current row through
/// `__index__` (`w.positions[h]`, `w.add_spring(h, k, ...)`).
#[pyclass(module = "physstep._core", frozen, name = "ParticleHandle")]
pub struct ParticleHandle {
    pub(crate) world: Py<World>,
    pub(crate) family: u64,
    pub(crate) id: u64,
}

crate::identity::identity!(ParticleHandle, 17);

impl ParticleHandle {
    /// The particle's row in the World whose state `g` is (the handle must be of its family).
    pub(crate) fn row_in(&self, g: &Inner, field: &str) -> PyResult<usize> {
        if self.family != g.family {
            return Err(foreign_handle(field, "particles", &self.text()));
        }
        particle_row(g, self.id).ok_or_else(|| removed_handle(field, &self.text()))
    }
}

#[pymethods]
impl ParticleHandle {
    /// Whether the particle is still in its World.
    #[getter]
    fn alive(&self) -> PyResult<bool> {
        let g = self.world.get().lock()?;
        Ok(particle_row(&g, self.id).is_some())
    }

    /// The particle's current row (its index in `World.positions`); ValueError once removed.
    fn __index__(&self) -> PyResult<usize> {
        let g = self.world.get().lock()?;
        self.row_in(&g, "particle")
    }
}

/// The particles one `add_particles` or `add_balls` call added, as one handle: a sequence of
/// `ParticleHandle`s (their ids are consecutive) that costs O(1) however many there are;
/// `np.asarray(b)` (or `b.rows`) is their current rows.
#[pyclass(module = "physstep._core", frozen, name = "ParticleHandles")]
pub struct ParticleHandles {
    pub(crate) world: Py<World>,
    pub(crate) family: u64,
    pub(crate) first: u64,
    pub(crate) len: u64,
}

impl ParticleHandles {
    fn one(&self, py: Python<'_>, k: u64) -> ParticleHandle {
        ParticleHandle { world: self.world.clone_ref(py), family: self.family, id: self.first + k }
    }

    /// The rows of the particles in the World whose state `g` is.
    pub(crate) fn rows_in(&self, g: &Inner) -> PyResult<Vec<usize>> {
        let text = || format!("ParticleHandles(ids {}..{})", self.first, self.first + self.len);
        if self.family != g.family {
            return Err(foreign_handle("particle", "particles", &text()));
        }
        (self.first..self.first + self.len)
            .map(|id| {
                particle_row(g, id).ok_or_else(|| {
                    PyValueError::new_err(format!(
                        "invalid particle = ParticleHandle(id={id}) (of {}): it was removed from its World",
                        text()
                    ))
                })
            })
            .collect()
    }
}

#[pymethods]
impl ParticleHandles {
    fn __len__(&self) -> usize {
        self.len as usize
    }

    fn __getitem__(&self, py: Python<'_>, k: &Bound<'_, PyAny>) -> PyResult<ParticleHandle> {
        let k = crate::convert::whole(k, "index", i64::MIN, i64::MAX)?;
        let at = if k < 0 { k + self.len as i64 } else { k };
        if at < 0 || at >= self.len as i64 {
            return Err(PyIndexError::new_err(format!("index {k} out of range: {} particles", self.len)));
        }
        Ok(self.one(py, at as u64))
    }

    fn __iter__(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let all: Vec<ParticleHandle> = (0..self.len).map(|k| self.one(py, k)).collect();
        Ok(pyo3::types::PyList::new(py, all)?.try_iter()?.into_any().unbind())
    }

    /// The particles' ids (consecutive), int64.
    #[getter]
    fn ids<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_vec(py, (self.first as i64..(self.first + self.len) as i64).collect())
    }

    /// The particles' current rows, int64 (ValueError naming the first removed one).
    #[getter]
    fn rows<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let g = self.world.get().lock()?;
        let rows = self.rows_in(&g)?;
        Ok(PyArray1::from_vec(py, rows.into_iter().map(|r| r as i64).collect()))
    }

    /// `np.asarray(handles)`: the current rows.
    #[pyo3(signature = (dtype=None, copy=None))]
    fn __array__<'py>(
        &self,
        py: Python<'py>,
        dtype: Option<&Bound<'py, PyAny>>,
        copy: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let _ = copy;
        let rows = self.rows(py)?.into_any();
        match dtype.filter(|d| !d.is_none()) {
            Some(d) => rows.call_method1("astype", (d,)),
            None => Ok(rows),
        }
    }

    /// Whether every one of the particles is still in its World.
    #[getter]
    fn alive(&self) -> PyResult<bool> {
        let g = self.world.get().lock()?;
        Ok((self.first..self.first + self.len).all(|id| particle_row(&g, id).is_some()))
    }

    /// The World the handles came from.
    #[getter]
    fn world(&self, py: Python<'_>) -> Py<World> {
        self.world.clone_ref(py)
    }

    fn __repr__(&self) -> String {
        format!("ParticleHandles(ids {}..{}, {} particles)", self.first, self.first + self.len, self.len)
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<ParticleHandles>().is_ok_and(|o| {
            let o = o.get();
            (o.family, o.first, o.len) == (self.family, self.first, self.len)
        })
    }

    fn __hash__(&self) -> u64 {
        self.first ^ self.len.rotate_left(32) ^ self.family.rotate_left(17)
    }
}

/// A particle argument (`field`): a `ParticleHandle` of this World (its current row) or an
/// index, resolved under the lock the caller holds.
pub(crate) fn particle(o: &Bound<'_, PyAny>, field: &str, g: &Inner) -> PyResult<usize> {
    match o.cast::<ParticleHandle>() {
        Ok(h) => h.get().row_in(g, field),
        // Another kind's handle is not a particle, whatever its row.
        Err(_) if is_handle(o) => {
            Err(crate::convert::invalid(field, o, "a particle index or a ParticleHandle"))
        }
        Err(_) => crate::convert::index(o, field),
    }
}

/// A body argument (`field`): a `BodyHandle` of this World (its current row) or an index
/// (the engine checks it against the count), resolved under the lock the caller holds.
/// Another kind's handle is refused, whatever its row.
pub(crate) fn body(o: &Bound<'_, PyAny>, field: &str, g: &Inner) -> PyResult<usize> {
    match o.cast::<BodyHandle>() {
        Ok(h) => h.get().row_in(g, field),
        Err(_) if is_handle(o) => Err(crate::convert::invalid(field, o, "a body index or a BodyHandle")),
        Err(_) => crate::convert::whole(o, field, 0, i64::MAX)
            .map(|v| v as usize)
            .map_err(|_| crate::convert::invalid(field, o, "a body index >= 0")),
    }
}

/// A handle to one position constraint of a World: `id`, `alive`, `kind` and its parameters
/// (read-only: remove it and add another to change it); `__index__` is its place among the
/// World's constraints (the sweep order).
#[pyclass(module = "physstep._core", frozen, name = "ConstraintHandle")]
pub struct ConstraintHandle {
    pub(crate) world: Py<World>,
    pub(crate) family: u64,
    pub(crate) id: u64,
}

crate::identity::identity!(ConstraintHandle, 23);

impl ConstraintHandle {
    /// The constraint's id, checked to be of the World whose state `g` is.
    pub(crate) fn id_in(&self, g: &Inner) -> PyResult<ConstraintId> {
        if self.family != g.family {
            return Err(foreign_handle("constraint", "constraints", &self.text()));
        }
        Ok(ConstraintId(self.id))
    }

    fn get(&self) -> PyResult<(Constraint, usize)> {
        let g = self.world.get().lock()?;
        let c = g
            .engine
            .constraint(ConstraintId(self.id))
            .ok_or_else(|| removed_handle("constraint", &self.text()))?;
        Ok((c, g.engine.dim()))
    }

    fn none(&self, kind: &str, what: &str) -> PyErr {
        PyAttributeError::new_err(format!("a {kind} constraint has no {what}"))
    }
}

fn kind_of(c: &Constraint) -> &'static str {
    match c {
        Constraint::Distance { .. } => "distance",
        Constraint::Limit { .. } => "limit",
        Constraint::Pin { .. } => "pin",
        Constraint::Plane { .. } => "plane",
    }
}

fn vec_out(py: Python<'_>, v: [f64; 3], dim: usize) -> Py<PyAny> {
    PyArray1::from_slice(py, &v[..dim]).into_any().unbind()
}

#[pymethods]
impl ConstraintHandle {
    /// Whether the constraint is still in its World.
    #[getter]
    fn alive(&self) -> PyResult<bool> {
        Ok(self.world.get().lock()?.engine.constraint(ConstraintId(self.id)).is_some())
    }

    /// `distance`, `limit` (a rope or distance limit), `pin` or `plane`.
    #[getter]
    fn kind(&self) -> PyResult<&'static str> {
        Ok(kind_of(&self.get()?.0))
    }

    /// The constraint's place among the World's constraints; ValueError once removed.
    fn __index__(&self) -> PyResult<usize> {
        let g = self.world.get().lock()?;
        g.engine
            .constraint_row(ConstraintId(self.id))
            .ok_or_else(|| removed_handle("constraint", &self.text()))
    }

    /// The (first) particle's current row (distance, limit, pin).
    #[getter]
    fn i(&self) -> PyResult<usize> {
        match self.get()?.0 {
            Constraint::Distance { i, .. } | Constraint::Limit { i, .. } | Constraint::Pin { i, .. } => Ok(i),
            c => Err(self.none(kind_of(&c), "i")),
        }
    }

    /// The other particle's current row, or None when the other end is a fixed point.
    #[getter]
    fn j(&self) -> PyResult<Option<usize>> {
        match self.get()?.0 {
            Constraint::Distance { j, .. } | Constraint::Limit { j, .. } => {
                Ok(if let Endpoint::Particle(j) = j { Some(j) } else { None })
            }
            c => Err(self.none(kind_of(&c), "j")),
        }
    }

    /// The fixed point (dim,) the constraint holds its particle to, m, or None when the other
    /// end is a particle.
    #[getter]
    fn anchor(&self, py: Python<'_>) -> PyResult<Option<Py<PyAny>>> {
        let (c, d) = self.get()?;
        match c {
            Constraint::Distance { j, .. } | Constraint::Limit { j, .. } => {
                Ok(if let Endpoint::Anchor(a) = j { Some(vec_out(py, a, d)) } else { None })
            }
            c => Err(self.none(kind_of(&c), "anchor")),
        }
    }

    /// A distance constraint's length, m.
    #[getter]
    fn length(&self) -> PyResult<f64> {
        match self.get()?.0 {
            Constraint::Distance { length, .. } => Ok(length),
            c => Err(self.none(kind_of(&c), "length")),
        }
    }

    /// A distance constraint's compliance, m/N (0: rigid).
    #[getter]
    fn compliance(&self) -> PyResult<f64> {
        match self.get()?.0 {
            Constraint::Distance { compliance, .. } => Ok(compliance),
            c => Err(self.none(kind_of(&c), "compliance")),
        }
    }

    /// A limit's (rope's) shortest distance, m (0 for a rope).
    #[getter]
    fn min_length(&self) -> PyResult<f64> {
        match self.get()?.0 {
            Constraint::Limit { min, .. } => Ok(min),
            c => Err(self.none(kind_of(&c), "min_length")),
        }
    }

    /// A limit's (rope's) longest distance, m.
    #[getter]
    fn max_length(&self) -> PyResult<f64> {
        match self.get()?.0 {
            Constraint::Limit { max, .. } => Ok(max),
            c => Err(self.none(kind_of(&c), "max_length")),
        }
    }

    /// A pin's point (dim,), m.
    #[getter]
    fn point(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        match self.get()? {
            (Constraint::Pin { point, .. }, d) => Ok(vec_out(py, point, d)),
            (c, _) => Err(self.none(kind_of(&c), "point")),
        }
    }

    /// A plane's unit normal (dim,).
    #[getter]
    fn normal(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        match self.get()? {
            (Constraint::Plane { normal, .. }, d) => Ok(vec_out(py, normal, d)),
            (c, _) => Err(self.none(kind_of(&c), "normal")),
        }
    }

    /// A plane's offset along its normal, m.
    #[getter]
    fn offset(&self) -> PyResult<f64> {
        match self.get()?.0 {
            Constraint::Plane { offset, .. } => Ok(offset),
            c => Err(self.none(kind_of(&c), "offset")),
        }
    }
}

/// A handle to one rigid body of a World (what `add_body` returns): `id`, `alive`, and its
/// current row through `__index__` (`w.bodies[h]`, `w.apply_force(h, ...)`).
#[pyclass(module = "physstep._core", frozen, name = "BodyHandle")]
pub struct BodyHandle {
    pub(crate) world: Py<World>,
    pub(crate) family: u64,
    pub(crate) id: u64,
}

crate::identity::identity!(BodyHandle, 29);

impl BodyHandle {
    /// The body's row in the World whose state `g` is (the handle must be of its family).
    pub(crate) fn row_in(&self, g: &Inner, field: &str) -> PyResult<usize> {
        if self.family != g.family {
            return Err(foreign_handle(field, "bodies", &self.text()));
        }
        g.engine.body_row(BodyId(self.id)).ok_or_else(|| removed_handle(field, &self.text()))
    }
}

#[pymethods]
impl BodyHandle {
    /// Whether the body is still in its World.
    #[getter]
    fn alive(&self) -> PyResult<bool> {
        Ok(self.world.get().lock()?.engine.body_row(BodyId(self.id)).is_some())
    }

    /// The body's current row (its index in `World.bodies`); ValueError once removed.
    fn __index__(&self) -> PyResult<usize> {
        let g = self.world.get().lock()?;
        self.row_in(&g, "body")
    }
}

/// Whether `o` is a handle whose `__index__` is an entity's row (of any kind: an argument
/// that wants one kind refuses the others instead of taking their row as its index).
pub(crate) fn is_handle(o: &Bound<'_, PyAny>) -> bool {
    o.is_instance_of::<ParticleHandle>()
        || o.is_instance_of::<BodyHandle>()
        || o.is_instance_of::<ConstraintHandle>()
        || o.is_instance_of::<crate::body_link_handle::BodySpringHandle>()
        || o.is_instance_of::<crate::body_link_handle::BodyForceHandle>()
        || o.is_instance_of::<crate::solid_handles::SolidHandle>()
}
