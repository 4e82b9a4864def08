//! `World`'s methods that build it: particles, the built-in forces, Python forces.

use crate::convert::{array, float, index, text, vector};
use crate::force::PyForce;
use crate::handle::{Inner, World};
use crate::py_err;
use numpy::PyArray1;
use physstep::forces::{Endpoint, Force};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The other end of a spring or rod: a particle index or an anchor point.
pub(crate) fn endpoint(o: &Bound<'_, PyAny>, field: &str, dim: usize) -> PyResult<Endpoint> {
    if o.extract::<i64>().is_ok() && !o.is_instance_of::<pyo3::types::PyBool>() {
        return Ok(Endpoint::Particle(index(o, field)?));
    }
    let p = array(o, field, Some(dim), None)
        .map_err(|_| crate::convert::invalid(field, o, "a particle index or an anchor point"))?;
    let mut out = [0.0; 3];
    out[..dim].copy_from_slice(&p);
    Ok(Endpoint::Anchor(out))
}

#[pymethods]
impl World {
    /// Adds one particle at `position` (dim numbers, m) with `velocity` (m/s, default 0) and
    /// `mass` (kg, default 1; `inf` or `static=True` makes it immovable). Returns its index.
    /// Checked at once (ValueError naming the field); added in a batch before the world is
    /// next read or stepped, so spawn loops cost O(1) per particle.
    #[pyo3(signature = (position, velocity=None, mass=None, r#static=None))]
    fn add_particle(
        &self,
        position: &Bound<'_, PyAny>,
        velocity: Option<&Bound<'_, PyAny>>,
        mass: Option<&Bound<'_, PyAny>>,
        r#static: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let mut g = self.lock()?;
        let d = g.engine.dim();
        let position = vector(position, "position", d)?;
        let velocity = match velocity.filter(|v| !v.is_none()) {
            Some(v) => vector(v, "velocity", d)?,
            None => [0.0; 3],
        };
        let mass = mass.map_or(Ok(1.0), |m| float(m, "mass"))?;
        let fixed = r#static.map_or(Ok(false), |s| crate::convert::flag(s, "static"))?;
        let Inner { engine, pending, .. } = &mut *g;
        let i = pending.push(engine, &position[..d], &velocity[..d], mass, fixed).map_err(py_err)?;
        Ok(i)
    }

    /// Adds many particles: `positions` (k, dim), optional `velocities` (k, dim) and
    /// `masses` (k,). Returns their indices.
    #[pyo3(signature = (positions, velocities=None, masses=None, r#static=None))]
    fn add_particles<'py>(
        &self,
        py: Python<'py>,
        positions: &Bound<'py, PyAny>,
        velocities: Option<&Bound<'py, PyAny>>,
        masses: Option<&Bound<'py, PyAny>>,
        r#static: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let mut g = self.lock()?;
        let w = g.grow()?;
        let d = w.dim();
        let fixed = r#static.map_or(Ok(false), |s| crate::convert::flag(s, "static"))?;
        let x = array(positions, "positions", None, Some(d))?;
        let k = x.len() / d;
        let v = velocities
            .filter(|v| !v.is_none())
            .map(|v| array(v, "velocities", Some(k), Some(d)))
            .transpose()?;
        let m = masses.filter(|m| !m.is_none()).map(|m| array(m, "masses", Some(k), None)).transpose()?;
        let first = w.add_particles(&x, v.as_deref(), m.as_deref(), fixed).map_err(py_err)?;
        Ok(PyArray1::from_vec(py, (first as i64..(first + k) as i64).collect()))
    }

    /// Adds uniform gravity `g` (dim numbers, m/s^2) on every dynamic particle.
    fn add_gravity(&self, g: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut guard = self.lock()?;
        let w = guard.flush()?;
        let g = vector(g, "g", w.dim())?;
        w.add_force(Force::Gravity { g }).map(|_| ()).map_err(py_err)
    }

    /// Adds a damped spring (`stiffness` N/m, `damping` N s/m) from particle `i` to particle
    /// `j_or_anchor` or to a fixed anchor point; `rest_length` (m) defaults to the current
    /// distance. A zero rest length makes the linear spring F = -k d - c w.
    #[pyo3(signature = (i, j_or_anchor, stiffness, rest_length=None, damping=None))]
    fn add_spring(
        &self,
        i: &Bound<'_, PyAny>,
        j_or_anchor: &Bound<'_, PyAny>,
        stiffness: &Bound<'_, PyAny>,
        rest_length: Option<&Bound<'_, PyAny>>,
        damping: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let mut guard = self.lock()?;
        let w = guard.flush()?;
        let i = index(i, "i")?;
        let j = endpoint(j_or_anchor, "j_or_anchor", w.dim())?;
        let stiffness = float(stiffness, "stiffness")?;
        let rest_length =
            rest_length.filter(|r| !r.is_none()).map(|r| float(r, "rest_length")).transpose()?;
        let damping = damping.map_or(Ok(0.0), |c| float(c, "damping"))?;
        w.add_spring(i, j, stiffness, rest_length, damping).map(|_| ()).map_err(py_err)
    }

    /// Adds drag F = -(linear + quadratic |v|) v on every particle (N s/m, N s^2/m^2).
    #[pyo3(signature = (linear=None, quadratic=None))]
    fn add_drag(
        &self,
        linear: Option<&Bound<'_, PyAny>>,
        quadratic: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let linear = linear.map_or(Ok(0.0), |c| float(c, "linear"))?;
        let quadratic = quadratic.map_or(Ok(0.0), |c| float(c, "quadratic"))?;
        let mut g = self.lock()?;
        g.flush()?.add_force(Force::Drag { linear, quadratic }).map(|_| ()).map_err(py_err)
    }

    /// Adds gravity towards a fixed `center` with parameter `gm` (m^3/s^2): a = -gm r / |r|^3.
    fn add_central_gravity(&self, center: &Bound<'_, PyAny>, gm: &Bound<'_, PyAny>) -> PyResult<()> {
        let gm = float(gm, "gm")?;
        let mut g = self.lock()?;
        let w = g.flush()?;
        let center = vector(center, "center", w.dim())?;
        w.add_force(Force::CentralGravity { center, gm }).map(|_| ()).map_err(py_err)
    }

    /// Adds mutual gravity between all particles (constant `g`, `softening` length m).
    #[pyo3(signature = (g=None, softening=None))]
    fn add_nbody_gravity(
        &self,
        g: Option<&Bound<'_, PyAny>>,
        softening: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let gval = g.map_or(Ok(1.0), |g| float(g, "g"))?;
        let softening = softening.map_or(Ok(0.0), |s| float(s, "softening"))?;
        let mut guard = self.lock()?;
        guard.flush()?.add_force(Force::NBody { g: gval, softening }).map(|_| ()).map_err(py_err)
    }

    /// Adds the notes' force-based rod from particle `i` to `j_or_anchor` (a particle or an
    /// anchor point); it holds the current distance (`length`, when given, must equal it).
    #[pyo3(signature = (i, j_or_anchor, length=None))]
    fn add_rod(
        &self,
        i: &Bound<'_, PyAny>,
        j_or_anchor: &Bound<'_, PyAny>,
        length: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let mut guard = self.lock()?;
        let w = guard.flush()?;
        let i = index(i, "i")?;
        let j = endpoint(j_or_anchor, "j_or_anchor", w.dim())?;
        let length = length.filter(|l| !l.is_none()).map(|l| float(l, "length")).transpose()?;
        w.add_rod(i, j, length).map(|_| ()).map_err(py_err)
    }

    /// Adds a force written in Python: `func(t, x, v)` gets the time and the positions and
    /// velocities of all particles as read-only (n, dim) arrays and returns the forces
    /// (n, dim), N; with `inplace=True` it is `func(t, x, v, out)` and writes the forces into
    /// `out` (n, dim, zeroed), returning None. It is called once per force evaluation; the
    /// arrays are reused between calls, not allocated (one kept past its call is left to
    /// the caller, unchanged, and replaced). `potential(x)` (J) makes the energy known;
    /// `jacobian(t, x, v)` returns (dF/dx, dF/dv), each (n dim, n dim), for the implicit
    /// methods; `velocity_dependent=False` saves re-evaluations when the force ignores v.
    /// An exception raised inside propagates unchanged, with the step rolled back. Returns
    /// the force's index among the user forces.
    #[pyo3(signature = (func, *, potential=None, jacobian=None, velocity_dependent=None, name=None, inplace=None))]
    #[allow(clippy::too_many_arguments)]
    fn add_force(
        &self,
        py: Python<'_>,
        func: &Bound<'_, PyAny>,
        potential: Option<&Bound<'_, PyAny>>,
        jacobian: Option<&Bound<'_, PyAny>>,
        velocity_dependent: Option<&Bound<'_, PyAny>>,
        name: Option<&Bound<'_, PyAny>>,
        inplace: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let callable = |o: Option<&Bound<'_, PyAny>>, field: &str| -> PyResult<Option<Py<PyAny>>> {
            match o.filter(|o| !o.is_none()) {
                Some(o) if o.is_callable() => Ok(Some(o.clone().unbind())),
                Some(o) => Err(crate::convert::invalid(field, o, "callable")),
                None => Ok(None),
            }
        };
        let func = callable(Some(func), "func")?
            .ok_or_else(|| PyValueError::new_err("invalid func = None: must be callable"))?;
        let potential = callable(potential, "potential")?;
        let jacobian = callable(jacobian, "jacobian")?;
        let velocity_dependent =
            velocity_dependent.map_or(Ok(true), |v| crate::convert::flag(v, "velocity_dependent"))?;
        let inplace = inplace.map_or(Ok(false), |v| crate::convert::flag(v, "inplace"))?;
        let mut g = self.lock()?;
        let k = g.engine.model().user_forces();
        let name = match name {
            Some(n) => text(n, "name")?,
            None => func
                .bind(py)
                .getattr("__name__")
                .and_then(|n| n.extract::<String>())
                .unwrap_or_else(|_| format!("force {k}")),
        };
        let slot = g.slot.clone();
        let w = g.flush()?;
        let force = PyForce::new(name, w.dim(), func, potential, jacobian, velocity_dependent, inplace, slot);
        let spec = force.spec(py)?.unbind();
        let id = w.add_force_generator(std::sync::Arc::new(force)).map_err(py_err)?;
        let k = w.user_force_index(id).unwrap_or_default();
        g.user.push(spec);
        Ok(k)
    }
}
