//! `World`'s position constraints: adding them, the sweep count and the violation.

use crate::convert::{array, float, whole};
use crate::entity_handle::{particle, ConstraintHandle};
use crate::handle::World;
use crate::py_err;
use crate::world_build::endpoint;
use pyo3::prelude::*;

/// After constraint `k` was added: the World unlocked, then a `ConstraintWarning` for each
/// conflict it makes (the constraint stays). Returns its handle.
fn added(slf: &Bound<'_, World>, g: crate::handle::Guard<'_>, k: usize) -> PyResult<ConstraintHandle> {
    let conflicts = g.engine.constraint_conflicts_of(k);
    let id = g.engine.constraint_id(k).map_or(u64::MAX, |id| id.0);
    let family = g.family;
    drop(g);
    if !conflicts.is_empty() {
        Python::attach(|py| crate::errors::warn_conflicts(py, conflicts))?;
    }
    Ok(ConstraintHandle { world: slf.clone().unbind(), family, id })
}

#[pymethods]
impl World {
    /// Adds the constraint |x_i - x_j| = length (m) between particle `i` and particle `j`
    /// (or a fixed point: `j` may be an anchor of dim numbers); `length` defaults to the
    /// current distance. `compliance` (m/N, default 0) 0 is rigid (SHAKE/RATTLE under
    /// velocity-verlet and leapfrog, projection otherwise); above 0 the link is soft (XPBD).
    /// Returns its handle (a `ConstraintHandle`).
    #[pyo3(signature = (i, j, length=None, compliance=None))]
    fn add_distance_constraint(
        slf: &Bound<'_, Self>,
        i: &Bound<'_, PyAny>,
        j: &Bound<'_, PyAny>,
        length: Option<&Bound<'_, PyAny>>,
        compliance: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<ConstraintHandle> {
        let mut g = slf.get().lock()?;
        g.flush()?;
        let i = particle(i, "i", &g)?;
        let j = endpoint(j, "j", &g)?;
        let w = &mut g.engine;
        let length = length.filter(|l| !l.is_none()).map(|l| float(l, "length")).transpose()?;
        let compliance = compliance.map_or(Ok(0.0), |c| float(c, "compliance"))?;
        let k = w.add_distance_constraint(i, j, length, compliance).map_err(py_err)?;
        added(slf, g, k)
    }

    /// Holds particle `i` at `point` (dim numbers, m); other constraints see it as fixed.
    /// Returns its handle (a `ConstraintHandle`).
    fn add_pin(
        slf: &Bound<'_, Self>,
        i: &Bound<'_, PyAny>,
        point: &Bound<'_, PyAny>,
    ) -> PyResult<ConstraintHandle> {
        let mut g = slf.get().lock()?;
        g.flush()?;
        let i = particle(i, "i", &g)?;
        let w = &mut g.engine;
        let point = array(point, "point", Some(w.dim()), None)?;
        let k = w.add_pin(i, &point).map_err(py_err)?;
        added(slf, g, k)
    }

    /// A rope of `max_length` (m) from particle `i` to particle (or anchor point) `j`: the
    /// distance may shrink, not grow past it. Returns its handle (a `ConstraintHandle`).
    fn add_rope(
        slf: &Bound<'_, Self>,
        i: &Bound<'_, PyAny>,
        j: &Bound<'_, PyAny>,
        max_length: &Bound<'_, PyAny>,
    ) -> PyResult<ConstraintHandle> {
        let mut g = slf.get().lock()?;
        g.flush()?;
        let i = particle(i, "i", &g)?;
        let j = endpoint(j, "j", &g)?;
        let w = &mut g.engine;
        let max_length = float(max_length, "max_length")?;
        let k = w.add_rope(i, j, max_length).map_err(py_err)?;
        added(slf, g, k)
    }

    /// A joint limit: min_length <= |x_i - x_j| <= max_length (m). Returns its handle.
    fn add_distance_limit(
        slf: &Bound<'_, Self>,
        i: &Bound<'_, PyAny>,
        j: &Bound<'_, PyAny>,
        min_length: &Bound<'_, PyAny>,
        max_length: &Bound<'_, PyAny>,
    ) -> PyResult<ConstraintHandle> {
        let mut g = slf.get().lock()?;
        g.flush()?;
        let i = particle(i, "i", &g)?;
        let j = endpoint(j, "j", &g)?;
        let w = &mut g.engine;
        let (lo, hi) = (float(min_length, "min_length")?, float(max_length, "max_length")?);
        let k = w.add_distance_limit(i, j, lo, hi).map_err(py_err)?;
        added(slf, g, k)
    }

    /// Keeps every particle in the half-space normal . x >= offset (m): a ground (normal
    /// (0, 1), offset 0 is y >= 0) or one wall of a box. `normal` (dim numbers, nonzero)
    /// points into the allowed side and is made unit. Returns its handle (a `ConstraintHandle`).
    #[pyo3(signature = (normal, offset=None))]
    fn add_plane(
        slf: &Bound<'_, Self>,
        normal: &Bound<'_, PyAny>,
        offset: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<ConstraintHandle> {
        let mut g = slf.get().lock()?;
        let w = g.flush()?;
        let normal = array(normal, "normal", Some(w.dim()), None)?;
        let offset = offset.map_or(Ok(0.0), |o| float(o, "offset"))?;
        let k = w.add_plane(&normal, offset).map_err(py_err)?;
        added(slf, g, k)
    }

    /// Relaxation sweeps per step (default 16), at most: the sweeps stop once every
    /// constraint is within 1e-13 (relative); `constraint_stats` counts the steps that
    /// reached this cap first. Assign to change it.
    #[getter]
    fn constraint_iterations(&self) -> PyResult<u32> {
        Ok(self.lock()?.engine.constraint_iterations())
    }

    #[setter]
    fn set_constraint_iterations(&self, n: &Bound<'_, PyAny>) -> PyResult<()> {
        let max = i64::from(physstep::constraints::MAX_ITERATIONS);
        let n = whole(n, "constraint_iterations", 1, max)? as u32;
        self.lock()?.engine.set_constraint_iterations(n).map_err(py_err)
    }

    /// The largest violation of any constraint at the current positions, m (0.0 without
    /// constraints).
    fn constraint_violation(&self) -> PyResult<f64> {
        let mut g = self.lock()?;
        Ok(g.flush()?.constraint_violation())
    }

    /// What the relaxation sweeps did: {"last_sweeps": the last step's sweeps,
    /// "capped_steps": steps whose sweeps ended at constraint_iterations with a constraint
    /// still off by more than 1e-13 (relative), "capped_violation": the largest violation,
    /// m, such a step left (0.0 when none)}. A diagnostic over the world's steps, not state.
    #[getter]
    fn constraint_stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let s = self.lock()?.engine.constraint_stats();
        let d = pyo3::types::PyDict::new(py);
        d.set_item("last_sweeps", s.last_sweeps)?;
        d.set_item("capped_steps", s.capped_steps)?;
        d.set_item("capped_violation", s.capped_violation)?;
        Ok(d)
    }

    /// What in the constraints cannot be met whatever the sweeps, one line each (empty when
    /// nothing is seen): a particle pinned to two points, two pinned balls closer than their
    /// radii, opposite planes with no point between them, a pinned particle behind a plane,
    /// held ends at a distance a constraint forbids, a distance whose ends coincide. Adding
    /// such a constraint warns (`ConstraintWarning`); the check is of pairs, not a proof.
    fn constraint_conflicts(&self) -> PyResult<Vec<String>> {
        Ok(self.lock()?.engine.constraint_conflicts())
    }

    /// The number of constraints.
    #[getter]
    fn constraint_count(&self) -> PyResult<usize> {
        Ok(self.lock()?.engine.constraints().list().len())
    }
}
