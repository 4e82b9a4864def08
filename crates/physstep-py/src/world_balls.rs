//! `World`'s balls and walls: adding them, reading radii, walls and contact statistics.

use crate::convert::{array, float, vector};
use crate::handle::World;
use crate::py_err;
use numpy::PyArray1;
use physstep::world::World as Engine;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

#[pymethods]
impl World {
    /// Adds a ball: a particle of `radius` (m, default 1) at `position` (dim numbers, m) with
    /// `velocity` (m/s, default 0) and `mass` (kg, default 1; `inf` makes it immovable) that
    /// collides with the other balls and the walls. Returns its handle (a `ParticleHandle`).
    #[pyo3(signature = (position, velocity=None, radius=None, mass=None))]
    fn add_ball(
        slf: &Bound<'_, Self>,
        position: &Bound<'_, PyAny>,
        velocity: Option<&Bound<'_, PyAny>>,
        radius: Option<&Bound<'_, PyAny>>,
        mass: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<crate::entity_handle::ParticleHandle> {
        let mut g = slf.get().lock()?;
        let d = g.flush()?.dim();
        let position = vector(position, "position", d)?;
        let velocity = match velocity.filter(|v| !v.is_none()) {
            Some(v) => vector(v, "velocity", d)?,
            None => [0.0; 3],
        };
        let radius = radius.map_or(Ok(1.0), |r| float(r, "radius"))?;
        let mass = mass.map_or(Ok(1.0), |m| float(m, "mass"))?;
        let w = g.grow()?;
        let id = w.next_particle_id().0;
        w.add_ball(&position[..d], &velocity[..d], radius, mass).map_err(py_err)?;
        Ok(crate::entity_handle::ParticleHandle { world: slf.clone().unbind(), family: g.family, id })
    }

    /// Adds many balls: `positions` (k, dim), `radii` (one number for all, or (k,)),
    /// optional `velocities` (k, dim) and `masses` (k,). Returns their handles as one
    /// `ParticleHandles`.
    #[pyo3(signature = (positions, radii, velocities=None, masses=None))]
    fn add_balls<'py>(
        slf: &Bound<'py, Self>,
        positions: &Bound<'py, PyAny>,
        radii: &Bound<'py, PyAny>,
        velocities: Option<&Bound<'py, PyAny>>,
        masses: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<crate::entity_handle::ParticleHandles> {
        let mut g = slf.get().lock()?;
        let w = g.grow()?;
        let d = w.dim();
        let x = array(positions, "positions", None, Some(d))?;
        let k = x.len() / d;
        let r = match radii.extract::<f64>() {
            Ok(r) if !radii.is_instance_of::<pyo3::types::PyBool>() => vec![r; k],
            _ => array(radii, "radii", Some(k), None)?,
        };
        let v = velocities
            .filter(|v| !v.is_none())
            .map(|v| array(v, "velocities", Some(k), Some(d)))
            .transpose()?;
        let m = masses.filter(|m| !m.is_none()).map(|m| array(m, "masses", Some(k), None)).transpose()?;
        let first = w.next_particle_id().0;
        w.add_balls(&x, v.as_deref(), &r, m.as_deref()).map_err(py_err)?;
        let (world, family, len) = (slf.clone().unbind(), g.family, k as u64);
        Ok(crate::entity_handle::ParticleHandles { world, family, first, len })
    }

    /// Puts the balls in the axis-aligned box `lo`..`hi` (dim numbers each, m), replacing any
    /// walls before.
    fn add_walls(&self, lo: &Bound<'_, PyAny>, hi: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        let d = w.dim();
        let (lo, hi) = (array(lo, "lo", Some(d), None)?, array(hi, "hi", Some(d), None)?);
        w.add_walls(&lo, &hi).map_err(py_err)
    }

    /// Coefficient of restitution of every contact, 0 to 1 (1: elastic, the default).
    #[getter]
    fn restitution(&self) -> PyResult<f64> {
        Ok(self.lock()?.engine.restitution())
    }

    #[setter(restitution)]
    fn set_restitution(&self, e: &Bound<'_, PyAny>) -> PyResult<()> {
        let e = float(e, "restitution")?;
        self.lock()?.engine.set_restitution(e).map_err(py_err)
    }

    /// The radius of every particle (n,), m: 0 for a particle that is not a ball (a copy).
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let mut g = self.lock()?;
        Ok(PyArray1::from_vec(py, g.flush()?.radii()))
    }

    /// The walls as `(lo, hi)` arrays, or None.
    #[getter]
    fn walls<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyTuple>>> {
        let g = self.lock()?;
        let d = g.engine.dim();
        g.engine
            .walls()
            .map(|w| {
                let lo = PyArray1::from_slice(py, &w.lo[..d]);
                let hi = PyArray1::from_slice(py, &w.hi[..d]);
                PyTuple::new(py, [lo.into_any(), hi.into_any()])
            })
            .transpose()
    }

    /// What the contacts came to since the world was built: `count` (contacts resolved),
    /// `max_overlap` (the deepest overlap of two balls, or of a ball past a wall, after any
    /// step, m) and `pair_tests` (pairs the narrow phase tested: grows with N, not N^2).
    #[getter]
    fn collisions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.lock()?.engine.collisions();
        let d = PyDict::new(py);
        d.set_item("count", s.count)?;
        d.set_item("max_overlap", s.max_overlap)?;
        d.set_item("pair_tests", s.pair_tests)?;
        Ok(d)
    }
}

/// The contact statistics of a world with balls (the keys of `World.collisions`), else None.
pub(crate) fn stats<'py>(py: Python<'py>, w: &Engine) -> PyResult<Option<Bound<'py, PyDict>>> {
    if w.ball_count() == 0 {
        return Ok(None);
    }
    let s = w.collisions();
    let d = PyDict::new(py);
    d.set_item("count", s.count)?;
    d.set_item("max_overlap", s.max_overlap)?;
    d.set_item("pair_tests", s.pair_tests)?;
    Ok(Some(d))
}
