//! `World`'s position constraints: adding them, the sweep count and the violation.

use crate::convert::{array, float, index, whole};
use crate::handle::World;
use crate::py_err;
use crate::world_build::endpoint;
use pyo3::prelude::*;

#[pymethods]
impl World {
    /// Adds the constraint |x_i - x_j| = length (m) between particle `i` and particle `j`
    /// (or a fixed point: `j` may be an anchor of dim numbers); `length` defaults to the
    /// current distance. `compliance` (m/N, default 0) 0 is rigid (SHAKE/RATTLE under
    /// velocity-verlet and leapfrog, projection otherwise); above 0 the link is soft (XPBD).
    /// Returns the constraint's index.
    #[pyo3(signature = (i, j, length=None, compliance=None))]
    fn add_distance_constraint(
        &self,
        i: &Bound<'_, PyAny>,
        j: &Bound<'_, PyAny>,
        length: Option<&Bound<'_, PyAny>>,
        compliance: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        let i = index(i, "i")?;
        let j = endpoint(j, "j", w.dim())?;
        let length = length.filter(|l| !l.is_none()).map(|l| float(l, "length")).transpose()?;
        let compliance = compliance.map_or(Ok(0.0), |c| float(c, "compliance"))?;
        w.add_distance_constraint(i, j, length, compliance).map_err(py_err)
    }

    /// Holds particle `i` at `point` (dim numbers, m); other constraints see it as fixed.
    /// Returns the constraint's index.
    fn add_pin(&self, i: &Bound<'_, PyAny>, point: &Bound<'_, PyAny>) -> PyResult<usize> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        let i = index(i, "i")?;
        let point = array(point, "point", Some(w.dim()), None)?;
        w.add_pin(i, &point).map_err(py_err)
    }

    /// A rope of `max_length` (m) from particle `i` to particle (or anchor point) `j`: the
    /// distance may shrink, not grow past it. Returns the constraint's index.
    fn add_rope(
        &self,
        i: &Bound<'_, PyAny>,
        j: &Bound<'_, PyAny>,
        max_length: &Bound<'_, PyAny>,
    ) -> PyResult<usize> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        let i = index(i, "i")?;
        let j = endpoint(j, "j", w.dim())?;
        let max_length = float(max_length, "max_length")?;
        w.add_rope(i, j, max_length).map_err(py_err)
    }

    /// A joint limit: min_length <= |x_i - x_j| <= max_length (m). Returns its index.
    fn add_distance_limit(
        &self,
        i: &Bound<'_, PyAny>,
        j: &Bound<'_, PyAny>,
        min_length: &Bound<'_, PyAny>,
        max_length: &Bound<'_, PyAny>,
    ) -> PyResult<usize> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        let i = index(i, "i")?;
        let j = endpoint(j, "j", w.dim())?;
        let (lo, hi) = (float(min_length, "min_length")?, float(max_length, "max_length")?);
        w.add_distance_limit(i, j, lo, hi).map_err(py_err)
    }

    /// Keeps every particle in the half-space normal . x >= offset (m): a ground (normal
    /// (0, 1), offset 0 is y >= 0) or one wall of a box. `normal` (dim numbers, nonzero)
    /// points into the allowed side and is made unit. Returns the constraint's index.
    #[pyo3(signature = (normal, offset=None))]
    fn add_plane(&self, normal: &Bound<'_, PyAny>, offset: Option<&Bound<'_, PyAny>>) -> PyResult<usize> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        let normal = array(normal, "normal", Some(w.dim()), None)?;
        let offset = offset.map_or(Ok(0.0), |o| float(o, "offset"))?;
        w.add_plane(&normal, offset).map_err(py_err)
    }

    /// Relaxation sweeps per step (default 16): exactly this many for projection, at most
    /// this many for SHAKE/RATTLE, which stop at their tolerance. Assign to change it.
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

    /// The number of constraints.
    #[getter]
    fn constraint_count(&self) -> PyResult<usize> {
        Ok(self.lock()?.engine.constraints().list().len())
    }
}
