//! Solids of a World (rigid bodies with shapes that touch, stepped by the contact solver):
//! `add_solid` and the rest of the World's methods for them, their joints, springs and forces.
//! Their shapes are in `shapes.rs`.

use crate::convert::{array, float, invalid, matrix, text};
use crate::handle::World;
use crate::joint_handle::JointHandle;
use crate::py_err;
use crate::solid_handles::{solid_arg, SolidForceHandle, SolidHandle, SolidSpringHandle};
use numpy::{IntoPyArray, PyArray2};
use physstep::contact::{JointKind, JointParams, Kind, SolidParams, SolidSpring, SOLVERS};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Adds a Python force at `point` of `solid` to the engine and keeps its spec (for copies and
/// pickles).
pub(crate) fn add_force(
    py: Python<'_>,
    w: &mut physstep::world::World,
    kept: &mut Vec<crate::handle::SolidForceSpec>,
    solid: usize,
    point: Vec<f64>,
    spec: Py<PyAny>,
    slot: &crate::slot::Slot,
) -> PyResult<usize> {
    let force = crate::force::PyForce::from_spec(spec.bind(py), w.dim(), slot)?;
    let k = w.add_solid_force(solid, &point, std::sync::Arc::new(force)).map_err(py_err)?;
    kept.push((solid, point, std::sync::Arc::new(spec)));
    Ok(k)
}

fn numbers(o: Option<&Bound<'_, PyAny>>, field: &str) -> PyResult<Option<Vec<f64>>> {
    match o.filter(|o| !o.is_none()) {
        None => Ok(None),
        Some(o) => {
            if let Ok(x) = o.extract::<f64>() {
                if !o.is_instance_of::<pyo3::types::PyBool>() {
                    return Ok(Some(vec![x]));
                }
            }
            array(o, field, None, None).map(Some)
        }
    }
}

#[pymethods]
impl World {
    /// Adds a solid: a rigid body with a shape that collides with the other solids, stepped
    /// by the contact solver (docs/contact.md); returns its `SolidHandle` (an index: its row
    /// now).
    ///
    /// `shape`: physstep.Circle, Box (two half extents in 2D, three in 3D), Capsule,
    /// Polygon, Segment, Plane (static), Sphere or Mesh (static). `position` of the shape's
    /// origin (m, default the origin); `orientation`: the angle (rad) in 2D, a quaternion
    /// (w, x, y, z) in 3D; `velocity` (m/s) and `angular_velocity` (rad/s: one number in
    /// 2D); `kind`: "dynamic" (default), "static" or "kinematic"; `density` (kg/m^2 in 2D,
    /// kg/m^3 in 3D; default 1); `friction` >= 0 (default 0.6; a pair: the geometric mean);
    /// `restitution` in [0, 1] (default 0; a pair: the larger); `linear_damping` and
    /// `angular_damping`, drag in 1/s (>= 0, default 0: in each substep v *= 1 / (1 + h c),
    /// so speed decays as exp(-c t)); `bullet` (default False): continuous collision sweeps a
    /// dynamic bullet against the dynamic solids that are not bullets too (a small fast
    /// projectile then does not pass through a box). ValueError naming the bad field; the
    /// world is then unchanged.
    #[pyo3(signature = (shape, *, position=None, orientation=None, velocity=None, angular_velocity=None, kind=None, density=None, friction=None, restitution=None, linear_damping=None, angular_damping=None, bullet=None))]
    #[allow(clippy::too_many_arguments)]
    fn add_solid(
        slf: &Bound<'_, Self>,
        shape: &Bound<'_, PyAny>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        angular_velocity: Option<&Bound<'_, PyAny>>,
        kind: Option<&Bound<'_, PyAny>>,
        density: Option<&Bound<'_, PyAny>>,
        friction: Option<&Bound<'_, PyAny>>,
        restitution: Option<&Bound<'_, PyAny>>,
        linear_damping: Option<&Bound<'_, PyAny>>,
        angular_damping: Option<&Bound<'_, PyAny>>,
        bullet: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<SolidHandle> {
        let shape = crate::shapes::solid_shape(shape)?;
        let given = |o: Option<&Bound<'_, PyAny>>, field: &str, default: f64| -> PyResult<f64> {
            o.filter(|o| !o.is_none()).map_or(Ok(default), |o| float(o, field))
        };
        let kind = match kind.filter(|k| !k.is_none()) {
            Some(k) => Kind::by_name(&text(k, "kind")?).map_err(py_err)?,
            None => Kind::Dynamic,
        };
        let mut g = slf.get().lock()?;
        let dim = g.engine.dim();
        let mut p = SolidParams::new(shape, &vec![0.0; dim]);
        p.kind = kind;
        if let Some(x) = numbers(position, "position")? {
            p.position = x;
        }
        if let Some(q) = numbers(orientation, "orientation")? {
            p.orientation = q;
        }
        if let Some(v) = numbers(velocity, "velocity")? {
            p.velocity = v;
        }
        if let Some(w) = numbers(angular_velocity, "angular_velocity")? {
            p.angular_velocity = w;
        }
        p.density = given(density, "density", p.density)?;
        p.friction = given(friction, "friction", p.friction)?;
        p.restitution = given(restitution, "restitution", p.restitution)?;
        p.linear_damping = given(linear_damping, "linear_damping", 0.0)?;
        p.angular_damping = given(angular_damping, "angular_damping", 0.0)?;
        if let Some(b) = bullet.filter(|b| !b.is_none()) {
            p.bullet = crate::convert::flag(b, "bullet")?;
        }
        let row = g.grow()?.add_solid(p).map_err(py_err)?;
        Ok(SolidHandle::of_row(slf, &g.engine, g.family, row))
    }

    /// Adds a spring between `point_a` of solid `a` and `point_b` of solid `b` (each in its
    /// solid's frame, the frame its shape is given in, m), or, with `b` None, the fixed world
    /// point `point_b`: the force k (L - rest_length) + damping (the ends' relative speed
    /// along the line), N, pulls the two ends together along the line between them, equal and
    /// opposite, and turns each solid about its centre; applied in each of the contact
    /// solver's substeps. `stiffness` N/m and `damping` N s/m (default 0) >= 0;
    /// `rest_length` (m, >= 0) defaults to the distance between the ends now (0: the linear
    /// spring k d). Returns its `SolidSpringHandle`. ValueError naming the bad field; the
    /// world is then unchanged.
    #[pyo3(signature = (a, point_a, b=None, point_b=None, *, stiffness, rest_length=None, damping=None))]
    #[allow(clippy::too_many_arguments)]
    fn add_solid_spring(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyAny>,
        point_a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
        point_b: Option<&Bound<'_, PyAny>>,
        stiffness: &Bound<'_, PyAny>,
        rest_length: Option<&Bound<'_, PyAny>>,
        damping: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<SolidSpringHandle> {
        let a = solid_arg(slf.get(), a, "a")?;
        let b = b.filter(|o| !o.is_none()).map(|o| solid_arg(slf.get(), o, "b")).transpose()?;
        let point_a = numbers(Some(point_a), "point_a")?.unwrap_or_default();
        let mut g = slf.get().lock()?;
        let dim = g.engine.dim();
        let point_b = numbers(point_b, "point_b")?.unwrap_or_else(|| vec![0.0; dim]);
        let spring = SolidSpring {
            a,
            point_a,
            b,
            point_b,
            stiffness: float(stiffness, "stiffness")?,
            rest_length: rest_length.filter(|r| !r.is_none()).map(|r| float(r, "rest_length")).transpose()?,
            damping: damping.filter(|c| !c.is_none()).map_or(Ok(0.0), |c| float(c, "damping"))?,
        };
        let row = g.flush()?.add_solid_spring(spring).map_err(py_err)?;
        Ok(crate::solid_handles::spring_handle(slf, &g.engine, g.family, row))
    }

    /// Number of solid springs.
    #[getter]
    fn solid_spring_count(&self) -> PyResult<usize> {
        Ok(self.lock()?.engine.solid_springs().len())
    }

    /// The solid springs' two ends now (n, 2, dim), m: the end on `a`, then the end on `b`
    /// (or the world point). What a game draws.
    fn solid_spring_ends<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<f64>>> {
        let g = self.lock()?;
        let d = g.engine.dim();
        let ends = g.engine.solid_spring_ends();
        let n = ends.len() / (2 * d);
        let a = numpy::ndarray::Array3::from_shape_vec((n, 2, d), ends)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
        Ok(a.into_pyarray(py))
    }

    /// Energy of the solids, J: kinetic (translation and rotation), potential in the
    /// world's gravity (0 at the origin) and in the solid springs. What the exact motion of
    /// solids touching nothing, under gravity and undamped springs, conserves.
    fn solid_energy(&self) -> PyResult<f64> {
        Ok(self.lock()?.engine.solid_energy())
    }

    /// Applies `force` (N, world frame: dim numbers) to solid `solid` for the next step, at
    /// the world point `point` (default its centre of mass), which also turns it. Loads add
    /// up until a step takes them, held constant over its substeps. ValueError naming the
    /// bad field.
    #[pyo3(signature = (solid, force, point=None))]
    fn apply_solid_force(
        &self,
        solid: &Bound<'_, PyAny>,
        force: &Bound<'_, PyAny>,
        point: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let solid = solid_arg(self, solid, "solid")?;
        let force = numbers(Some(force), "force")?.unwrap_or_default();
        let at = numbers(point, "point")?;
        let mut g = self.lock()?;
        g.flush()?.apply_solid_force(solid, &force, at.as_deref()).map_err(py_err)
    }

    /// Adds a force from Python at `point` of solid `solid` (its frame, the frame its shape
    /// is given in, m; default the origin of its shape): `func(t, x, v)` sees that point as
    /// one particle, its world position and velocity as (1, dim) arrays, and returns the
    /// force on it (1, dim), N, which also turns the solid about its centre. It is evaluated
    /// once a step, at the step's start, and held constant over the contact solver's
    /// substeps. `potential(x)` (J) keeps World.energy() known; `name` names it in errors
    /// (default the function's). An exception raised inside propagates unchanged, and a
    /// result that is not finite is a ValueError naming the force; the step is rolled
    /// back either way. Returns its `SolidForceHandle`.
    #[pyo3(signature = (solid, func, point=None, *, potential=None, name=None))]
    fn add_solid_force(
        slf: &Bound<'_, Self>,
        py: Python<'_>,
        solid: &Bound<'_, PyAny>,
        func: &Bound<'_, PyAny>,
        point: Option<&Bound<'_, PyAny>>,
        potential: Option<&Bound<'_, PyAny>>,
        name: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<SolidForceHandle> {
        let solid = solid_arg(slf.get(), solid, "solid")?;
        if !func.is_callable() {
            return Err(invalid("func", func, "callable"));
        }
        let potential = match potential.filter(|p| !p.is_none()) {
            Some(p) if p.is_callable() => Some(p.clone().unbind()),
            Some(p) => return Err(invalid("potential", p, "callable")),
            None => None,
        };
        let name = match name.filter(|n| !n.is_none()) {
            Some(n) => text(n, "name")?,
            None => func
                .getattr("__name__")
                .and_then(|n| n.extract::<String>())
                .unwrap_or_else(|_| "solid force".into()),
        };
        let mut g = slf.get().lock()?;
        let dim = g.engine.dim();
        let point = numbers(point, "point")?.unwrap_or_else(|| vec![0.0; dim]);
        // Evaluated once a step: whether it reads v changes nothing, so it is taken to.
        let spec = (func, potential.as_ref().map(|p| p.bind(py)), py.None(), true, &name, false)
            .into_pyobject(py)?
            .into_any()
            .unbind();
        g.flush()?;
        let crate::handle::Inner { engine, solid_forces, slot, .. } = &mut *g;
        let row = add_force(py, engine, solid_forces, solid, point, spec, slot)?;
        Ok(crate::solid_handles::force_handle(slf, &g.engine, g.family, row, name))
    }

    /// Number of forces from Python on solids.
    #[getter]
    fn solid_force_count(&self) -> PyResult<usize> {
        Ok(self.lock()?.engine.solid_force_count())
    }

    /// Applies `torque` (N m: one number in 2D, a world-frame vector in 3D) to solid
    /// `solid` for the next step. ValueError naming the bad field.
    fn apply_solid_torque(&self, solid: &Bound<'_, PyAny>, torque: &Bound<'_, PyAny>) -> PyResult<()> {
        let solid = solid_arg(self, solid, "solid")?;
        let torque = numbers(Some(torque), "torque")?.unwrap_or_default();
        let mut g = self.lock()?;
        g.flush()?.apply_solid_torque(solid, &torque).map_err(py_err)
    }

    /// Adds a joint between solids `a` and `b` (handles or indices from add_solid; `b` None:
    /// the world, fixed), solved with the contacts; returns its `JointHandle`.
    ///
    /// `kind`: "ball" (a shared point), "revolute" (a hinge: the point, turning only about
    /// `axis` in 3D; limits `lower`/`upper` in rad, a motor `motor_speed` rad/s of at most
    /// `max_motor` N m), "distance" (the anchors `length` apart, default as made: rigid with
    /// `hertz` 0, else a spring of `hertz` and `damping_ratio`, between `min_length` and
    /// `max_length`), "weld" (glued; soft with `hertz` > 0) or "prismatic" (a slider along
    /// `axis`: limits of travel `lower`/`upper` in m, a motor of at most `max_motor` N).
    /// `anchor`: the shared point in world coordinates now (the end on `a` for a distance
    /// joint; `anchor_b` the end on `b`). Angles and travel count from the pose now; for a
    /// joint to the world they are the solid's own. `collide`: whether the two still collide
    /// (default no). ValueError naming the bad field; the world is then unchanged.
    #[pyo3(signature = (kind, a, b=None, *, anchor, anchor_b=None, axis=None, length=None, min_length=None, max_length=None, hertz=None, damping_ratio=None, lower=None, upper=None, motor_speed=None, max_motor=None, collide=false))]
    #[allow(clippy::too_many_arguments)]
    fn add_joint(
        slf: &Bound<'_, Self>,
        kind: &Bound<'_, PyAny>,
        a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
        anchor: &Bound<'_, PyAny>,
        anchor_b: Option<&Bound<'_, PyAny>>,
        axis: Option<&Bound<'_, PyAny>>,
        length: Option<&Bound<'_, PyAny>>,
        min_length: Option<&Bound<'_, PyAny>>,
        max_length: Option<&Bound<'_, PyAny>>,
        hertz: Option<&Bound<'_, PyAny>>,
        damping_ratio: Option<&Bound<'_, PyAny>>,
        lower: Option<&Bound<'_, PyAny>>,
        upper: Option<&Bound<'_, PyAny>>,
        motor_speed: Option<&Bound<'_, PyAny>>,
        max_motor: Option<&Bound<'_, PyAny>>,
        collide: bool,
    ) -> PyResult<JointHandle> {
        let kind = JointKind::by_name(&text(kind, "kind")?).map_err(py_err)?;
        let a = solid_arg(slf.get(), a, "a")?;
        let b = b.filter(|o| !o.is_none()).map(|o| solid_arg(slf.get(), o, "b")).transpose()?;
        let maybe = |o: Option<&Bound<'_, PyAny>>, field: &str| -> PyResult<Option<f64>> {
            o.filter(|o| !o.is_none()).map(|o| float(o, field)).transpose()
        };
        let mut p = JointParams::new(kind, a, b, &array(anchor, "anchor", None, None)?);
        p.anchor_b = numbers(anchor_b, "anchor_b")?;
        p.axis = numbers(axis, "axis")?;
        p.length = maybe(length, "length")?;
        p.min_length = maybe(min_length, "min_length")?;
        p.max_length = maybe(max_length, "max_length")?;
        p.hertz = maybe(hertz, "hertz")?.unwrap_or(p.hertz);
        p.damping_ratio = maybe(damping_ratio, "damping_ratio")?.unwrap_or(p.damping_ratio);
        p.lower = maybe(lower, "lower")?;
        p.upper = maybe(upper, "upper")?;
        p.motor_speed = maybe(motor_speed, "motor_speed")?.unwrap_or(p.motor_speed);
        p.max_motor = maybe(max_motor, "max_motor")?.unwrap_or(p.max_motor);
        p.collide = collide;
        let mut g = slf.get().lock()?;
        let row = g.grow()?.add_joint(p).map_err(py_err)?;
        Ok(crate::joint_handle::joint_handle(slf, &g.engine, g.family, row))
    }

    /// Number of joints.
    #[getter]
    fn joint_count(&self) -> PyResult<usize> {
        Ok(self.lock()?.engine.joint_count())
    }

    /// Each joint's position error now (m,): how far apart its anchors are (ball, revolute,
    /// weld), off its axis (prismatic), or outside its lengths (distance).
    fn joint_errors<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        Ok(self.lock()?.engine.joint_errors().into_pyarray(py))
    }

    /// Stiffness of the joints, Hz (default 120, capped at a quarter of the substep rate).
    #[getter]
    fn joint_hertz(&self) -> PyResult<f64> {
        Ok(self.lock()?.engine.contact_settings().joint_hertz)
    }

    #[setter]
    fn set_joint_hertz(&self, v: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(v, "joint_hertz")?;
        let mut g = self.lock()?;
        let mut s = g.engine.contact_settings();
        s.joint_hertz = v;
        g.grow()?.set_contact_settings(s).map_err(py_err)
    }

    /// Passes after each step that move jointed solids back together (0 to 1000; default 0).
    /// Tightens free-swinging linkages (a whipping chain's joints 30x closer); under a steady
    /// load it fights the soft joints and keeps a structure from coming fully to rest.
    #[getter]
    fn joint_projection(&self) -> PyResult<u32> {
        Ok(self.lock()?.engine.contact_settings().joint_projection)
    }

    #[setter]
    fn set_joint_projection(&self, n: &Bound<'_, PyAny>) -> PyResult<()> {
        let n = crate::convert::whole(n, "joint_projection", 0, 1000)? as u32;
        let mut g = self.lock()?;
        let mut s = g.engine.contact_settings();
        s.joint_projection = n;
        g.grow()?.set_contact_settings(s).map_err(py_err)
    }

    /// How long an island of touching (or jointed) solids must be slow before it falls
    /// asleep, s (default 0: never; Box2D's is 0.5). Slow: speed, and angular speed times the
    /// largest radius, below 0.05 m/s. A sleeping solid leaves the contact solver, keeps its
    /// place exactly and has zero velocity, until a moving solid comes within reach, a joint
    /// or spring ties it to one, a load acts on it, gravity changes or its motion is set; then
    /// its whole island wakes. Setting 0 wakes every solid at the next step. ValueError naming
    /// ``sleep_time`` unless finite and >= 0.
    #[getter]
    fn sleep_time(&self) -> PyResult<f64> {
        Ok(self.lock()?.engine.contact_settings().sleep_time)
    }

    #[setter]
    fn set_sleep_time(&self, v: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = float(v, "sleep_time")?;
        self.lock()?.grow()?.set_sleep_time(v).map_err(py_err)
    }

    /// Whether each solid is asleep (n,) bool (see :attr:`sleep_time`).
    fn solids_asleep<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray1<bool>>> {
        Ok(self.lock()?.engine.solids_asleep().into_pyarray(py))
    }

    /// Continuous collision of fast solids (default True): a dynamic solid that moves farther
    /// than the speculative distance (2 cm) in a step is swept against the static and
    /// kinematic solids and put back to where it first touches one, so it neither sinks into
    /// the ground nor passes through a thin wall. False: such a solid can end a step deep
    /// inside (a 1 m box thrown at the ground at 20 m/s sinks 30 cm).
    #[getter]
    fn continuous_collision(&self) -> PyResult<bool> {
        Ok(self.lock()?.engine.contact_settings().continuous)
    }

    #[setter]
    fn set_continuous_collision(&self, on: &Bound<'_, PyAny>) -> PyResult<()> {
        let on = crate::convert::flag(on, "continuous_collision")?;
        let mut g = self.lock()?;
        let mut s = g.engine.contact_settings();
        s.continuous = on;
        g.grow()?.set_contact_settings(s).map_err(py_err)
    }

    /// Number of solids.
    #[getter]
    fn solid_count(&self) -> PyResult<usize> {
        Ok(self.lock()?.engine.solid_count())
    }

    /// Origins of the solids' shapes (n, dim), m.
    fn solid_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let g = self.lock()?;
        matrix(py, g.engine.solid_positions(), g.engine.dim())
    }

    /// Orientations of the solids: angles (n,) in 2D, rad; quaternions (n, 4) as (w, x, y,
    /// z) in 3D.
    fn solid_orientations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let g = self.lock()?;
        crate::convert::orientations(py, g.engine.solid_orientations(), g.engine.dim())
    }

    /// Velocities of the solids' centres of mass (n, dim), m/s.
    fn solid_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let g = self.lock()?;
        matrix(py, g.engine.solid_velocities(), g.engine.dim())
    }

    /// Angular velocities of the solids: (n,) in 2D, (n, 3) in 3D, rad/s.
    fn solid_angular_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let g = self.lock()?;
        let w = g.engine.solid_angular_velocities();
        if g.engine.dim() == 3 {
            Ok(matrix(py, w, 3)?.into_any())
        } else {
            Ok(w.into_pyarray(py).into_any())
        }
    }

    /// The contact points of the latest step as arrays: ``pairs`` (m, 2) solid indices,
    /// ``points`` and ``normals`` (m, dim), ``depths`` (m,) (negative: not yet touching),
    /// ``normal_impulses`` and ``friction_impulses`` (m,), N s.
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let g = self.lock()?;
        let d = g.engine.dim();
        let c = g.engine.contacts();
        let out = PyDict::new(py);
        let pairs: Vec<i64> = c.pairs.iter().flatten().map(|&i| i as i64).collect();
        let n = c.pairs.len();
        let pairs = numpy::ndarray::Array2::from_shape_vec((n, 2), pairs)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
        out.set_item("pairs", pairs.into_pyarray(py))?;
        out.set_item("points", matrix(py, c.points, d)?)?;
        out.set_item("normals", matrix(py, c.normals, d)?)?;
        out.set_item("depths", c.depths.into_pyarray(py))?;
        out.set_item("normal_impulses", c.normal_impulses.into_pyarray(py))?;
        out.set_item("friction_impulses", c.friction_impulses.into_pyarray(py))?;
        Ok(out)
    }

    /// The deepest penetration among the latest step's contacts, m (0 without contacts).
    #[getter]
    fn max_penetration(&self) -> PyResult<f64> {
        Ok(self.lock()?.engine.max_penetration())
    }

    /// The passes over the contacts the contact solver made in the latest step, counted as
    /// they ran (solve, relax and position passes; 0 without solids or before a step). Every
    /// solver makes `2 x substeps x solver_iterations` (the lab compares them at equal cost).
    #[getter]
    fn contact_passes(&self) -> PyResult<u32> {
        Ok(self.lock()?.engine.contact_passes())
    }

    /// The contact solver's name (physstep.contact_solvers() lists them).
    #[getter]
    fn contact_solver(&self) -> PyResult<&'static str> {
        Ok(self.lock()?.engine.contact_settings().solver)
    }

    #[setter]
    fn set_contact_solver(&self, name: &Bound<'_, PyAny>) -> PyResult<()> {
        let name = text(name, "contact_solver")?;
        self.lock()?.grow()?.set_contact_solver(&name).map_err(py_err)
    }

    /// Substeps of the contact solver a step (1 to 1000; default 8).
    #[getter]
    fn substeps(&self) -> PyResult<u32> {
        Ok(self.lock()?.engine.contact_settings().substeps)
    }

    #[setter]
    fn set_substeps(&self, n: &Bound<'_, PyAny>) -> PyResult<()> {
        let n = crate::convert::whole(n, "substeps", 1, 1000)? as u32;
        self.lock()?.grow()?.set_substeps(n).map_err(py_err)
    }

    /// Solve and relax passes of the contact solver a substep (1 to 1000; default 1).
    #[getter]
    fn solver_iterations(&self) -> PyResult<u32> {
        Ok(self.lock()?.engine.contact_settings().iterations)
    }

    #[setter]
    fn set_solver_iterations(&self, n: &Bound<'_, PyAny>) -> PyResult<()> {
        let n = crate::convert::whole(n, "solver_iterations", 1, 1000)? as u32;
        self.lock()?.grow()?.set_solver_iterations(n).map_err(py_err)
    }
}

/// What a run reports of its solids at the end: `solids` (how many), `count` (contact
/// points touching), `max_penetration` (m) and `max_speed` (the fastest centre of mass, m/s),
/// and while sleeping is on `asleep` (how many sleep: their contacts are not counted); None
/// without solids.
pub(crate) fn stats<'py>(
    py: Python<'py>,
    w: &physstep::world::World,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    if w.solid_count() == 0 {
        return Ok(None);
    }
    let d = PyDict::new(py);
    let v = w.solid_velocities();
    let speed = v.chunks(w.dim()).map(|c| c.iter().map(|x| x * x).sum::<f64>().sqrt()).fold(0.0, f64::max);
    d.set_item("solids", w.solid_count())?;
    d.set_item("count", w.contacts().depths.iter().filter(|x| **x >= 0.0).count())?;
    d.set_item("max_penetration", w.max_penetration())?;
    d.set_item("max_speed", speed)?;
    if w.contact_settings().sleep_time > 0.0 {
        d.set_item("asleep", w.solids_asleep().iter().filter(|a| **a).count())?;
    }
    Ok(Some(d))
}

/// The contact solvers in registry order, each a dict: `name`, `summary` (one line on what it
/// does), `family` (what it corrects: `velocity`, or `velocity + position`) and `passes` (the
/// constraint passes it makes a step, in the settings' terms).
#[pyfunction]
pub(crate) fn solver_infos(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    SOLVERS
        .iter()
        .map(|i| {
            let d = PyDict::new(py);
            d.set_item("name", i.name)?;
            d.set_item("summary", i.summary)?;
            d.set_item("family", i.family)?;
            d.set_item("passes", i.passes)?;
            Ok(d)
        })
        .collect()
}

/// The contact solvers, name -> one line on what each does, in registry order.
#[pyfunction]
pub(crate) fn contact_solvers(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    for i in SOLVERS {
        d.set_item(i.name, i.summary)?;
    }
    Ok(d)
}
