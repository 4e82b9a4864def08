//! `World`'s rigid bodies: adding them and their springs, reading their state, loads for the
//! next step, the orientation rule and the angular form. (A pickle holds them through the
//! engine's scene text, `crate::pickle`; only Python forces at body points are kept here.)

use crate::convert::{array, float, matrix, text, vector};
use crate::handle::{BodyForceSpec, World};
use crate::py_err;
use numpy::{PyArray1, PyArray2};
use physstep::rigid::body::{AngularForm, FORMS};
use physstep::rigid::orientation::{Rule, RULES};
use physstep::world::{BodyParams, World as Engine};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Adds a Python force at a body point to `w` (from its spec) and keeps its spec in `kept`.
pub(crate) fn add_force(
    py: Python<'_>,
    w: &mut Engine,
    kept: &mut Vec<BodyForceSpec>,
    body: usize,
    point: [f64; 3],
    spec: Py<PyAny>,
    slot: &crate::slot::Slot,
) -> PyResult<usize> {
    let force = crate::force::PyForce::from_spec(spec.bind(py), 3, slot)?;
    let k = w.add_body_force(body, point, std::sync::Arc::new(force)).map_err(py_err)?;
    kept.push((body, point, std::sync::Arc::new(spec)));
    Ok(k)
}

/// `[w, x, y, z]` from a 4-vector argument (the engine checks finiteness and length).
fn quaternion(o: &Bound<'_, PyAny>, field: &str) -> PyResult<[f64; 4]> {
    let q = array(o, field, Some(4), None)?;
    Ok([q[0], q[1], q[2], q[3]])
}

/// A 3-vector argument, `default` when absent or None.
fn vec3(o: Option<&Bound<'_, PyAny>>, field: &str, default: [f64; 3]) -> PyResult<[f64; 3]> {
    o.filter(|o| !o.is_none()).map_or(Ok(default), |o| vector(o, field, 3))
}

/// One `(nb, k)` array of a per-body reading.
pub(crate) fn per_body<'py, const N: usize>(
    py: Python<'py>,
    w: &Engine,
    read: impl Fn(&Engine, usize) -> physstep::Result<[f64; N]>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = w.bodies().len();
    let mut data = Vec::with_capacity(n * N);
    for b in 0..n {
        data.extend_from_slice(&read(w, b).map_err(py_err)?);
    }
    matrix(py, data, N)
}

#[pymethods]
impl World {
    /// Adds a force written in Python acting at `point` of body `body` (shape frame, m; the
    /// default is the shape's origin): `func(t, x, v)` gets the point's world position and
    /// velocity as (1, 3) arrays and returns the force on it (1, 3), N, which also turns the
    /// body. `potential(x)` (J) keeps the energy known; `velocity_dependent=False` saves
    /// re-evaluations. An exception raised inside propagates unchanged, with the step rolled
    /// back. Returns its handle (a `BodyForceHandle`: `w.remove(h)`).
    #[pyo3(signature = (body, func, *, point=None, potential=None, velocity_dependent=None, name=None))]
    #[allow(clippy::too_many_arguments)]
    fn add_body_force(
        slf: &Bound<'_, Self>,
        py: Python<'_>,
        body: &Bound<'_, PyAny>,
        func: &Bound<'_, PyAny>,
        point: Option<&Bound<'_, PyAny>>,
        potential: Option<&Bound<'_, PyAny>>,
        velocity_dependent: Option<&Bound<'_, PyAny>>,
        name: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<crate::body_link_handle::BodyForceHandle> {
        // Resolved before the callable's name is read (Python code), under a lock of its own.
        let body = crate::entity_handle::body(body, "body", &*slf.get().lock()?)?;
        if !func.is_callable() {
            return Err(crate::convert::invalid("func", func, "callable"));
        }
        let potential = match potential.filter(|p| !p.is_none()) {
            Some(p) if p.is_callable() => Some(p.clone().unbind()),
            Some(p) => return Err(crate::convert::invalid("potential", p, "callable")),
            None => None,
        };
        let velocity_dependent =
            velocity_dependent.map_or(Ok(true), |v| crate::convert::flag(v, "velocity_dependent"))?;
        let point = vec3(point, "point", [0.0; 3])?;
        let name = match name {
            Some(n) => text(n, "name")?,
            None => func
                .getattr("__name__")
                .and_then(|n| n.extract::<String>())
                .unwrap_or_else(|_| "body force".into()),
        };
        let spec =
            (func, potential.as_ref().map(|p| p.bind(py)), py.None(), velocity_dependent, &name, false)
                .into_pyobject(py)?
                .into_any()
                .unbind();
        let mut g = slf.get().lock()?;
        g.flush()?;
        let id = g.engine.next_body_link_ids()[1];
        let crate::handle::Inner { engine, body_forces, slot, .. } = &mut *g;
        add_force(py, engine, body_forces, body, point, spec, slot)?;
        Ok(crate::body_link_handle::BodyForceHandle { world: slf.clone().unbind(), family: g.family, id })
    }

    /// Adds a rigid body of `shape` (a physstep.Sphere, Box, Cylinder, Capsule or Mesh) in a
    /// 3D world; returns its handle (a `BodyHandle`: `w.bodies[h]`, `w.remove(h)`). `mass` (kg) or `density` (kg/m^3), at most one (neither:
    /// density 1); `position` of the shape's origin (m, default the origin), `orientation`
    /// of the shape's frame as a quaternion (w, x, y, z) (normalised; default the identity),
    /// `velocity` of the centre of mass (m/s), `angular_velocity` (rad/s, world frame);
    /// `pivot`, a point of the shape (shape frame, m) pinned to the world where it starts (a
    /// ball joint: a top on its tip; `velocity` must then be zero); `angular_drag`, a torque
    /// `-c omega` (N m s, default 0). ValueError naming the bad field (`dim` in a world that
    /// is not 3D); the world is then unchanged.
    #[pyo3(signature = (shape, *, mass=None, density=None, position=None, orientation=None, velocity=None, angular_velocity=None, pivot=None, angular_drag=None))]
    #[allow(clippy::too_many_arguments)]
    fn add_body(
        slf: &Bound<'_, Self>,
        shape: &Bound<'_, PyAny>,
        mass: Option<&Bound<'_, PyAny>>,
        density: Option<&Bound<'_, PyAny>>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        angular_velocity: Option<&Bound<'_, PyAny>>,
        pivot: Option<&Bound<'_, PyAny>>,
        angular_drag: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<crate::entity_handle::BodyHandle> {
        let shape = crate::shapes::from_py(shape, "shape")?;
        let mass = mass.filter(|m| !m.is_none()).map(|m| float(m, "mass")).transpose()?;
        let density = density.filter(|d| !d.is_none()).map(|d| float(d, "density")).transpose()?;
        let position = vec3(position, "position", [0.0; 3])?;
        let orientation = match orientation.filter(|o| !o.is_none()) {
            Some(o) => quaternion(o, "orientation")?,
            None => [1.0, 0.0, 0.0, 0.0],
        };
        let velocity = vec3(velocity, "velocity", [0.0; 3])?;
        let angular_velocity = vec3(angular_velocity, "angular_velocity", [0.0; 3])?;
        let pivot = pivot.filter(|p| !p.is_none()).map(|p| vector(p, "pivot", 3)).transpose()?;
        let angular_drag =
            angular_drag.filter(|c| !c.is_none()).map(|c| float(c, "angular_drag")).transpose()?;
        let p = BodyParams {
            shape,
            mass,
            density,
            position,
            orientation,
            velocity,
            angular_velocity,
            pivot,
            angular_drag: angular_drag.unwrap_or(0.0),
        };
        let mut g = slf.get().lock()?;
        let w = g.grow()?;
        let id = w.next_body_id().0;
        w.add_body(&p).map_err(py_err)?;
        Ok(crate::entity_handle::BodyHandle { world: slf.clone().unbind(), family: g.family, id })
    }

    /// Number of rigid bodies.
    #[getter]
    fn body_count(&self) -> PyResult<usize> {
        Ok(self.lock()?.engine.bodies().len())
    }

    /// Centres of mass of the bodies (nb, 3), m.
    fn body_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        per_body(py, &self.lock()?.engine, Engine::body_position)
    }

    /// Orientations of the bodies' shape frames (nb, 4), unit quaternions (w, x, y, z).
    fn body_orientations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        per_body(py, &self.lock()?.engine, Engine::body_orientation)
    }

    /// Velocities of the bodies' centres of mass (nb, 3), m/s.
    fn body_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        per_body(py, &self.lock()?.engine, Engine::body_velocity)
    }

    /// Angular velocities of the bodies (nb, 3), rad/s, world frame.
    fn body_angular_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        per_body(py, &self.lock()?.engine, Engine::body_angular_velocity)
    }

    /// Angular momenta of the bodies about their centres of mass (nb, 3), kg m^2/s, world
    /// frame.
    fn body_angular_momenta<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        per_body(py, &self.lock()?.engine, Engine::body_angular_momentum)
    }

    /// Total angular momentum about the origin (3,), kg m^2/s: the particles' m x x v (3D
    /// worlds) plus the bodies' c x P + L.
    fn angular_momentum<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let mut g = self.lock()?;
        Ok(PyArray1::from_slice(py, &g.flush()?.angular_momentum()))
    }

    /// Applies `force` (N, world frame) to body `body` for the next step, at the world point
    /// `at` (m; the centre of mass when None, else adding the torque (at - c) x force).
    /// Loads add up until a step takes them. ValueError naming `body`, `force` or `at`.
    #[pyo3(signature = (body, force, at=None))]
    fn apply_force(
        &self,
        body: &Bound<'_, PyAny>,
        force: &Bound<'_, PyAny>,
        at: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let mut g = self.lock()?;
        let b = crate::entity_handle::body(body, "body", &g)?;
        let force = vector(force, "force", 3)?;
        let at = at.filter(|a| !a.is_none()).map(|a| vector(a, "at", 3)).transpose()?;
        g.engine.apply_force(b, force, at).map_err(py_err)
    }

    /// Applies `torque` (N m, world frame) to body `body` for the next step. ValueError
    /// naming `body` or `torque`.
    fn apply_torque(&self, body: &Bound<'_, PyAny>, torque: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut g = self.lock()?;
        let b = crate::entity_handle::body(body, "body", &g)?;
        let torque = vector(torque, "torque", 3)?;
        g.engine.apply_torque(b, torque).map_err(py_err)
    }

    /// How drifts move the bodies' orientations: "matrix", "quaternion", "exponential" or
    /// "splitting" (the default); assign a name to switch (ValueError listing the valid
    /// names otherwise).
    #[getter]
    fn orientation_rule(&self) -> PyResult<&'static str> {
        Ok(self.lock()?.engine.bodies().rule().name())
    }

    #[setter]
    fn set_orientation_rule(&self, name: &Bound<'_, PyAny>) -> PyResult<()> {
        let rule = Rule::from_name(&text(name, "orientation_rule")?).map_err(py_err)?;
        self.lock()?.engine.set_orientation_rule(rule);
        Ok(())
    }

    /// What the bodies' angular state holds and so what a kick integrates: "momentum" (the
    /// angular momentum, the notes' form and the default), "velocity" (the angular velocity,
    /// gyroscopic term ignored, as many game engines do), "velocity-gyroscopic" (Euler's
    /// equations, explicit) or "velocity-implicit" (the gyroscopic term by Catto's one
    /// Newton step); assign a name to switch (the bodies keep their angular
    /// momentum; ValueError listing the valid names otherwise).
    #[getter]
    fn angular_form(&self) -> PyResult<&'static str> {
        Ok(self.lock()?.engine.bodies().form().name())
    }

    #[setter]
    fn set_angular_form(&self, name: &Bound<'_, PyAny>) -> PyResult<()> {
        let form = AngularForm::from_name(&text(name, "angular_form")?).map_err(py_err)?;
        self.lock()?.engine.set_angular_form(form);
        Ok(())
    }

    /// Adds a damped spring (`stiffness` N/m, `damping` N s/m) from `point` of body `body`
    /// (shape frame, m) to `other`, a particle index or a fixed anchor point (3 numbers, m);
    /// `rest_length` (m) defaults to the current distance. ValueError naming the bad field.
    #[pyo3(signature = (body, point, other, stiffness, rest_length=None, damping=None))]
    fn add_body_spring(
        slf: &Bound<'_, Self>,
        body: &Bound<'_, PyAny>,
        point: &Bound<'_, PyAny>,
        other: &Bound<'_, PyAny>,
        stiffness: &Bound<'_, PyAny>,
        rest_length: Option<&Bound<'_, PyAny>>,
        damping: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<crate::body_link_handle::BodySpringHandle> {
        let mut g = slf.get().lock()?;
        let b = crate::entity_handle::body(body, "body", &g)?;
        let point = vector(point, "point", 3)?;
        let stiffness = float(stiffness, "stiffness")?;
        let rest_length =
            rest_length.filter(|r| !r.is_none()).map(|r| float(r, "rest_length")).transpose()?;
        let damping = damping.filter(|c| !c.is_none()).map_or(Ok(0.0), |c| float(c, "damping"))?;
        g.flush()?;
        let other = crate::world_build::endpoint(other, "other", &g)?;
        let id = g.engine.next_body_link_ids()[0];
        g.engine.add_body_spring(b, point, other, stiffness, rest_length, damping).map_err(py_err)?;
        Ok(crate::body_link_handle::BodySpringHandle { world: slf.clone().unbind(), family: g.family, id })
    }

    /// Body orientations to draw (nb, 4), (w, x, y, z): slerped by `alpha` between the
    /// state before the last step of the latest advance() and the current one.
    fn interpolated_body_orientations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = self.lock()?.engine.interpolated_body_orientations();
        matrix(py, q.into_iter().flatten().collect(), 4)
    }
}

/// The angular forms of rigid bodies, in order: a dict of name to a one-line doc.
#[pyfunction]
pub(crate) fn angular_forms(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    for f in FORMS {
        d.set_item(f.name(), f.doc())?;
    }
    Ok(d)
}

/// The orientation rules of rigid bodies, in order: a dict of name to a one-line doc.
#[pyfunction]
pub(crate) fn orientation_rules(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    for r in RULES {
        d.set_item(r.name(), r.doc())?;
    }
    Ok(d)
}
