//! `World`'s methods that read and set its state: positions, velocities, accelerations,
//! time, energy, snapshots and hashes, the game loop's interpolation and totals.

use crate::convert::{array, bytes, matrix, orientations};
use crate::handle::{raise, World};
use crate::py_err;
use crate::views::{view, Part};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

#[pymethods]
impl World {
    /// Render interpolation factor in [0, 1).
    #[getter]
    fn alpha(&self) -> PyResult<f64> {
        Ok(self.lock()?.engine.alpha())
    }

    /// Totals of the game loop: frames, steps, clamped and dropped time (s).
    #[getter]
    fn clock_stats(&self) -> PyResult<(u64, u64, f64, f64)> {
        let s = self.lock()?.engine.clock().stats();
        Ok((s.frames, s.steps, s.clamped, s.dropped))
    }

    /// Positions to draw (n, dim): previous + alpha (current - previous) over the last step
    /// of the latest `advance()`; a copy.
    fn interpolated_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        matrix(py, w.interpolated_positions(), w.dim())
    }

    /// Solid positions to draw (n, dim), m: as `interpolated_positions()`, between the
    /// solids' poses before the last step of the latest `advance()` and the current ones;
    /// the current ones after a `step()`; a copy.
    fn interpolated_solid_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let g = self.lock()?;
        matrix(py, g.engine.interpolated_solid_positions(), g.engine.dim())
    }

    /// Solid orientations to draw, as `solid_orientations()` gives them (angles (n,) in 2D,
    /// quaternions (n, 4) as (w, x, y, z) in 3D): the angle moved by `alpha` of its change
    /// over the last step, the quaternion slerped.
    fn interpolated_solid_orientations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let g = self.lock()?;
        orientations(py, g.engine.interpolated_solid_orientations(), g.engine.dim())
    }

    /// Positions (n, dim), m: a read-only view of the world's own memory, not a copy (see
    /// docs/views.md); assign an array to move the particles.
    #[getter]
    fn positions<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        view(slf, Part::Positions)
    }

    #[setter(positions)]
    fn set_positions(&self, x: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        let x = array(x, "positions", Some(w.len()), Some(w.dim()))?;
        w.set_positions(&x).map_err(py_err)
    }

    /// Velocities (n, dim), m/s: a read-only view of the world's own memory, not a copy (see
    /// docs/views.md); assign an array to change them.
    #[getter]
    fn velocities<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        view(slf, Part::Velocities)
    }

    #[setter(velocities)]
    fn set_velocities(&self, v: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        let v = array(v, "velocities", Some(w.len()), Some(w.dim()))?;
        w.set_velocities(&v).map_err(py_err)
    }

    /// Accelerations at the current state (n, dim), m/s^2: a copy.
    #[getter]
    fn accelerations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let mut g = self.lock()?;
        let slot = g.slot.clone();
        let w = g.flush()?;
        let dim = w.dim();
        let a = w.accelerations().map_err(|e| raise(&slot, e))?.to_vec();
        matrix(py, a, dim)
    }

    /// Physics time, s.
    #[getter]
    fn time(&self) -> PyResult<f64> {
        Ok(self.lock()?.engine.time())
    }

    /// Steps taken.
    #[getter]
    fn steps(&self) -> PyResult<u64> {
        Ok(self.lock()?.engine.steps())
    }

    /// Force evaluations made.
    #[getter]
    fn evals(&self) -> PyResult<u64> {
        Ok(self.lock()?.engine.evals())
    }

    /// Kinetic energy, J: the dynamic particles', the bodies' and the solids' (translation
    /// and rotation).
    fn kinetic_energy(&self) -> PyResult<f64> {
        Ok(self.lock()?.flush()?.kinetic())
    }

    /// Kinetic plus potential energy, J; None when a user force has no potential.
    fn energy(&self) -> PyResult<Option<f64>> {
        let mut g = self.lock()?;
        let slot = g.slot.clone();
        let w = g.flush()?;
        let e = w.energy();
        if let Some(err) = slot.take() {
            return Err(err);
        }
        let Some(e) = e else { return Ok(None) };
        if !e.is_finite() {
            return Err(py_err(physstep::Error::NonFinite {
                method: w.integrator().info().name.into(),
                quantity: "energy".into(),
                value: e,
                step: w.steps(),
                t: w.time(),
            }));
        }
        Ok(Some(e))
    }

    /// Total momentum of the dynamic particles (dim,), kg m/s.
    fn momentum<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let mut g = self.lock()?;
        Ok(PyArray1::from_vec(py, g.flush()?.momentum()))
    }

    /// The whole dynamic state as checksummed bytes (restore() puts it back bitwise).
    fn snapshot<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let mut g = self.lock()?;
        Ok(PyBytes::new(py, &g.flush()?.snapshot()))
    }

    /// Restores a snapshot() of this world (bytes, bytearray or memoryview); a damaged or
    /// foreign one is a ValueError and the world is unchanged.
    fn restore(&self, data: &Bound<'_, PyAny>) -> PyResult<()> {
        let data = bytes(data, "data")?;
        let mut g = self.lock()?;
        let slot = g.slot.clone();
        g.flush()?.restore(&data).map_err(|e| raise(&slot, e))
    }

    /// A 64-bit hash of the dynamic state: equal for bitwise-equal states.
    fn state_hash(&self) -> PyResult<u64> {
        let mut g = self.lock()?;
        Ok(g.flush()?.state_hash())
    }

    /// The vector the step map acts on: positions and velocities (flat), then the vector
    /// part of the integrator's memory (Verlet's previous positions, leapfrog's half-step
    /// velocities). For linearising a step, as `physstep.lab.stability` does.
    fn phase_state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let mut g = self.lock()?;
        Ok(PyArray1::from_vec(py, g.flush()?.phase()))
    }

    /// Sets what `phase_state()` returns, without restarting the integrator.
    fn set_phase_state(&self, z: &Bound<'_, PyAny>) -> PyResult<()> {
        let z = array(z, "phase", None, None)?;
        let mut g = self.lock()?;
        let slot = g.slot.clone();
        g.flush()?.set_phase(&z).map_err(|e| raise(&slot, e))
    }
}
