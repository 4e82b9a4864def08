//! `physstep.World`: the engine's world with the names the Python API promises.
//!
//! Threading: a World is used by one thread at a time. Its state sits behind a mutex; a call
//! that finds it taken (another thread is stepping it, or a callback inside its own step
//! touched it) raises `WorldBusyError` at once rather than wait or corrupt anything. Long
//! calls (`step`) release the GIL in slices and look for Ctrl-C between them: an interrupt
//! leaves the world after the last whole step.

use crate::convert::{array, bytes, count, float, index, matrix, text, vector, whole};
use crate::errors::WorldBusyError;
use crate::force::{PyForce, Slot};
use crate::py_err;
use crate::record::SLICE;
use numpy::{PyArray1, PyArray2};
use physstep::clock::LoopMode;
use physstep::forces::{Endpoint, Force};
use physstep::world::{ParticleBatch, World as Engine, WorldParams};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::sync::{Mutex, MutexGuard, TryLockError};
use std::time::Instant;

/// Particles, forces, an integrator and a fixed-timestep game loop.
///
/// World(dim, method="symplectic-euler", dt=1/120, max_steps_per_frame=8,
/// max_frame_time=0.1, loop="accumulator", substeps=1). A World serves one thread at a time
/// (WorldBusyError otherwise); step() and the recording release the GIL and see Ctrl-C.
#[pyclass(module = "physstep._core", frozen)]
pub struct World {
    inner: Mutex<Inner>,
}

struct Inner {
    engine: Engine,
    /// A Python exception raised inside a step by a user force, to re-raise unchanged.
    slot: Slot,
    /// The Python forces as added: `(func, potential, jacobian, velocity_dependent, name)`,
    /// for pickling.
    user: Vec<Py<PyAny>>,
    /// A Python flow as made: `(func, jacobian, name, n)`, for pickling.
    flow: Option<Py<PyAny>>,
    /// Particles from `add_particle`, validated and waiting to be added in one batch:
    /// growing the engine's `[x; v]` state one particle at a time moves the velocity half
    /// every time, which is quadratic in a spawn loop. Every method that reads or steps the
    /// state flushes them first.
    pending: ParticleBatch,
}

impl Inner {
    /// The engine, with the particles waiting in the batch added.
    fn flush(&mut self) -> PyResult<&mut Engine> {
        if !self.pending.is_empty() {
            self.pending.commit(&mut self.engine).map_err(py_err)?;
        }
        Ok(&mut self.engine)
    }

    /// Particles in the world, waiting ones included.
    fn count(&self) -> usize {
        self.engine.len() + self.pending.len()
    }
}

/// The engine's error as a Python exception; an exception a user force raised during the
/// call comes first, unchanged.
pub(crate) fn raise(slot: &Slot, e: physstep::Error) -> PyErr {
    let kept = slot.lock().unwrap_or_else(std::sync::PoisonError::into_inner).take();
    kept.unwrap_or_else(|| py_err(e))
}

/// The other end of a spring or rod: a particle index or an anchor point.
fn endpoint(o: &Bound<'_, PyAny>, field: &str, dim: usize) -> PyResult<Endpoint> {
    if o.extract::<i64>().is_ok() && !o.is_instance_of::<pyo3::types::PyBool>() {
        return Ok(Endpoint::Particle(index(o, field)?));
    }
    let p = array(o, field, Some(dim), None)
        .map_err(|_| crate::convert::invalid(field, o, "a particle index or an anchor point"))?;
    let mut out = [0.0; 3];
    out[..dim].copy_from_slice(&p);
    Ok(Endpoint::Anchor(out))
}

impl World {
    /// The state, or `WorldBusyError` when another thread (or a callback of this world's own
    /// step) holds it.
    fn lock(&self) -> PyResult<MutexGuard<'_, Inner>> {
        match self.inner.try_lock() {
            Ok(g) => Ok(g),
            Err(TryLockError::WouldBlock) => Err(WorldBusyError::new_err(
                "this World is in use by another thread (a World serves one thread at a time: \
                 give each thread its own World, or guard it with a lock)",
            )),
            // A panic cannot happen inside (every engine call returns a Result); were it to,
            // the data is still whole, so go on with it.
            Err(TryLockError::Poisoned(p)) => Ok(p.into_inner()),
        }
    }

    fn wrap(engine: Engine) -> Self {
        Self::with_parts(engine, Slot::default(), Vec::new(), None)
    }

    pub(crate) fn with_parts(
        engine: Engine,
        slot: Slot,
        user: Vec<Py<PyAny>>,
        flow: Option<Py<PyAny>>,
    ) -> Self {
        Self { inner: Mutex::new(Inner { engine, slot, user, flow, pending: ParticleBatch::default() }) }
    }
}

#[pymethods]
impl World {
    #[new]
    #[pyo3(signature = (dim, method=None, dt=None, max_steps_per_frame=None, max_frame_time=None, r#loop=None, substeps=None))]
    fn new(
        dim: &Bound<'_, PyAny>,
        method: Option<Bound<'_, PyAny>>,
        dt: Option<&Bound<'_, PyAny>>,
        max_steps_per_frame: Option<&Bound<'_, PyAny>>,
        max_frame_time: Option<&Bound<'_, PyAny>>,
        r#loop: Option<&Bound<'_, PyAny>>,
        substeps: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let defaults = WorldParams::default();
        let dim = whole(dim, "dim", 1, 3)? as usize;
        let method = match method {
            Some(m) => text(&m, "method")?,
            None => defaults.method.clone(),
        };
        let num = |o: Option<&Bound<'_, PyAny>>, f: &str, d: f64| o.map_or(Ok(d), |o| float(o, f));
        let dt = num(dt, "dt", defaults.dt)?;
        let max_frame_time = num(max_frame_time, "max_frame_time", defaults.max_frame_time)?;
        let cap = |o: Option<&Bound<'_, PyAny>>, f: &str, d: u32| {
            o.map_or(Ok(d), |o| whole(o, f, 1, i64::from(u32::MAX)).map(|v| v as u32))
        };
        let max_steps = cap(max_steps_per_frame, "max_steps_per_frame", defaults.max_steps_per_frame)?;
        let substeps = cap(substeps, "substeps", 1)?;
        let mode = match r#loop {
            Some(l) => LoopMode::from_name(&text(l, "loop")?, substeps).map_err(py_err)?,
            None => LoopMode::Accumulator,
        };
        let params =
            WorldParams { dim, method, dt, mode, max_steps_per_frame: max_steps, max_frame_time, ..defaults };
        Ok(Self::wrap(Engine::new(params).map_err(py_err)?))
    }

    /// A world built from a built-in scene; `params` is a dict of parameter overrides.
    #[staticmethod]
    #[pyo3(signature = (name, method=None, dt=None, params=None))]
    fn from_scene(
        name: &Bound<'_, PyAny>,
        method: Option<&Bound<'_, PyAny>>,
        dt: Option<&Bound<'_, PyAny>>,
        params: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let name = text(name, "name")?;
        let method = method.map_or(Ok("symplectic-euler".to_string()), |m| text(m, "method"))?;
        let dt = dt.map_or(Ok(WorldParams::default().dt), |d| float(d, "dt"))?;
        let params = crate::convert::params(params)?;
        let overrides: Vec<(&str, f64)> = params.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        let scene = physstep::scenes::build(&name, &overrides, &method, dt).map_err(py_err)?;
        Ok(Self::wrap(scene.world))
    }

    /// A world whose part is a first-order flow `func(t, y) -> dy` from state `y0` (an
    /// attractor, any ODE): the flow methods integrate it, the split methods refuse.
    /// `jacobian(t, y)` returns df/dy (len(y0), len(y0)) for the implicit methods.
    #[staticmethod]
    #[pyo3(signature = (func, y0, method=None, dt=None, jacobian=None, name=None))]
    fn from_flow(
        py: Python<'_>,
        func: &Bound<'_, PyAny>,
        y0: &Bound<'_, PyAny>,
        method: Option<&Bound<'_, PyAny>>,
        dt: Option<&Bound<'_, PyAny>>,
        jacobian: Option<&Bound<'_, PyAny>>,
        name: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        if !func.is_callable() {
            return Err(crate::convert::invalid("func", func, "callable"));
        }
        let jacobian = match jacobian.filter(|j| !j.is_none()) {
            Some(j) if j.is_callable() => Some(j.clone().unbind()),
            Some(j) => return Err(crate::convert::invalid("jacobian", j, "callable")),
            None => None,
        };
        let y0 = array(y0, "y0", None, None)?;
        let method = method.map_or(Ok("rk4".to_string()), |m| text(m, "method"))?;
        let dt = dt.map_or(Ok(WorldParams::default().dt), |d| float(d, "dt"))?;
        let name = match name {
            Some(n) => text(n, "name")?,
            None => {
                func.getattr("__name__").and_then(|n| n.extract::<String>()).unwrap_or_else(|_| "flow".into())
            }
        };
        let slot = Slot::default();
        let spec = (func, jacobian.as_ref().map(|j| j.bind(py)), &name, y0.len())
            .into_pyobject(py)?
            .into_any()
            .unbind();
        let generator =
            crate::force::PyFlow { name, func: func.clone().unbind(), jacobian, slot: slot.clone() };
        let flow = physstep::flows::Flow::User { n: y0.len(), generator: std::sync::Arc::new(generator) };
        let params = WorldParams { method, dt, ..WorldParams::default() };
        let engine = Engine::with_flow(flow, &y0, params).map_err(py_err)?;
        Ok(Self::with_parts(engine, slot, Vec::new(), Some(spec)))
    }

    /// Records a run of this world from its current state: `until` seconds of its fixed dt,
    /// a row every `every` steps. Returns the data of a `physstep.Trajectory` (as a dict).
    #[pyo3(signature = (until, every=None, stop_on_diverge=None, stages=None))]
    fn record<'py>(
        &self,
        py: Python<'py>,
        until: &Bound<'py, PyAny>,
        every: Option<&Bound<'py, PyAny>>,
        stop_on_diverge: Option<&Bound<'py, PyAny>>,
        stages: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let until = float(until, "until")?;
        let every = every.map_or(Ok(1), |e| count(e, "every"))?;
        let flag =
            |o: Option<&Bound<'py, PyAny>>, f: &str| o.map_or(Ok(false), |o| crate::convert::flag(o, f));
        let stop_on_diverge = flag(stop_on_diverge, "stop_on_diverge")?;
        let stages = flag(stages, "stages")?;
        let mut g = self.lock()?;
        let slot = g.slot.clone();
        let w = g.flush()?;
        let dt = w.dt();
        let rp = physstep::record::RecordParams { dt, until, every, stages, stop_on_diverge };
        let (rec, elapsed) = crate::record::run(py, w, rp, Some(&slot))?;
        let d = pyo3::types::PyDict::new(py);
        crate::record::fill(&d, w, rec, elapsed, stages)?;
        Ok(d)
    }

    /// A copy: the same particles, forces, method, clock and state (Python forces are
    /// shared, as functions are).
    fn __copy__(&self, py: Python<'_>) -> PyResult<Self> {
        let mut g = self.lock()?;
        let engine = g.flush()?.clone();
        let user = g.user.iter().map(|u| u.clone_ref(py)).collect();
        let flow = g.flow.as_ref().map(|f| f.clone_ref(py));
        Ok(Self::with_parts(engine, g.slot.clone(), user, flow))
    }

    /// As `__copy__`: the engine's data is copied, Python callables are shared.
    fn __deepcopy__(&self, py: Python<'_>, _memo: &Bound<'_, PyAny>) -> PyResult<Self> {
        self.__copy__(py)
    }

    /// Pickles as the world's parts (settings, particles, forces, flow, Python callables)
    /// and its snapshot; unpickled, it continues bitwise as the original would.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<crate::pickle::Reduce<'py>> {
        let mut g = self.lock()?;
        let snapshot = g.flush()?.snapshot();
        let parts = crate::pickle::parts(py, &g.engine, &g.user, g.flow.as_ref())?;
        let rebuild = py.import("physstep._core")?.getattr("_world_from_parts")?;
        Ok((rebuild, (parts.into_any(), PyBytes::new(py, &snapshot).into_any())))
    }

    /// Spatial dimensions.
    #[getter]
    fn dim(&self) -> PyResult<usize> {
        Ok(self.lock()?.engine.dim())
    }

    /// Number of particles.
    fn __len__(&self) -> PyResult<usize> {
        Ok(self.lock()?.count())
    }

    /// `World(dim=..., particles=..., method=..., dt=..., time=...)`.
    fn __repr__(&self) -> PyResult<String> {
        let g = self.lock()?;
        let w = &g.engine;
        Ok(format!(
            "World(dim={}, particles={}, method='{}', dt={}, time={})",
            w.dim(),
            g.count(),
            w.integrator().info().name,
            w.dt(),
            w.time()
        ))
    }

    /// The integrator's registry name; assign a name to switch.
    #[getter]
    fn method(&self) -> PyResult<&'static str> {
        Ok(self.lock()?.engine.integrator().info().name)
    }

    #[setter]
    fn set_method(&self, name: &Bound<'_, PyAny>) -> PyResult<()> {
        let name = text(name, "method")?;
        self.lock()?.engine.set_method(&name).map_err(py_err)
    }

    /// The fixed step, s; assign to change it.
    #[getter]
    fn dt(&self) -> PyResult<f64> {
        Ok(self.lock()?.engine.dt())
    }

    #[setter]
    fn set_dt(&self, dt: &Bound<'_, PyAny>) -> PyResult<()> {
        let dt = float(dt, "dt")?;
        self.lock()?.engine.set_dt(dt).map_err(py_err)
    }

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
        let w = g.flush()?;
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
        w.add_force(Force::Gravity { g }).map_err(py_err)
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
        w.add_spring(i, j, stiffness, rest_length, damping).map_err(py_err)
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
        g.flush()?.add_force(Force::Drag { linear, quadratic }).map_err(py_err)
    }

    /// Adds gravity towards a fixed `center` with parameter `gm` (m^3/s^2): a = -gm r / |r|^3.
    fn add_central_gravity(&self, center: &Bound<'_, PyAny>, gm: &Bound<'_, PyAny>) -> PyResult<()> {
        let gm = float(gm, "gm")?;
        let mut g = self.lock()?;
        let w = g.flush()?;
        let center = vector(center, "center", w.dim())?;
        w.add_force(Force::CentralGravity { center, gm }).map_err(py_err)
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
        guard.flush()?.add_force(Force::NBody { g: gval, softening }).map_err(py_err)
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
        w.add_rod(i, j, length).map_err(py_err)
    }

    /// Takes n fixed steps. Raises DivergedError/ConvergenceError if a step fails (that step
    /// is rolled back, the steps before it stay taken); Ctrl-C stops after a whole step.
    #[pyo3(signature = (n=None))]
    fn step(&self, py: Python<'_>, n: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let mut left = n.map_or(Ok(1), |n| count(n, "n"))?;
        let mut g = self.lock()?;
        let slot = g.slot.clone();
        let w = g.flush()?;
        while left > 0 {
            let taken = py.detach(|| -> physstep::Result<u64> {
                let start = Instant::now();
                let mut k = 0;
                while k < left {
                    let chunk = (left - k).min(64);
                    w.step(chunk)?;
                    k += chunk;
                    if start.elapsed() > SLICE {
                        break;
                    }
                }
                Ok(k)
            });
            left -= taken.map_err(|e| raise(&slot, e))?;
            if left > 0 {
                py.check_signals()?;
            }
        }
        Ok(())
    }

    /// Runs one frame of the game loop; returns the number of fixed steps taken.
    fn advance(&self, frame_time: &Bound<'_, PyAny>) -> PyResult<u32> {
        let frame_time = float(frame_time, "frame_time")?;
        let mut g = self.lock()?;
        let slot = g.slot.clone();
        Ok(g.flush()?.advance(frame_time).map_err(|e| raise(&slot, e))?.plan.steps)
    }

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
    /// of the latest `advance()`.
    fn interpolated_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        matrix(py, w.interpolated_positions(), w.dim())
    }

    /// Positions (n, dim), m: a copy; assign an array to move the particles.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        matrix(py, w.positions().to_vec(), w.dim())
    }

    #[setter(positions)]
    fn set_positions(&self, x: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        let x = array(x, "positions", Some(w.len()), Some(w.dim()))?;
        w.set_positions(&x).map_err(py_err)
    }

    /// Velocities (n, dim), m/s: a copy; assign an array to change them.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        matrix(py, w.velocities().to_vec(), w.dim())
    }

    #[setter(velocities)]
    fn set_velocities(&self, v: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut g = self.lock()?;
        let w = g.flush()?;
        let v = array(v, "velocities", Some(w.len()), Some(w.dim()))?;
        w.set_velocities(&v).map_err(py_err)
    }

    /// Accelerations at the current state (n, dim), m/s^2.
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

    /// Kinetic plus potential energy, J; None when a user force has no potential.
    fn energy(&self) -> PyResult<Option<f64>> {
        let mut g = self.lock()?;
        let slot = g.slot.clone();
        let w = g.flush()?;
        let e = w.energy();
        if let Some(err) = slot.lock().unwrap_or_else(std::sync::PoisonError::into_inner).take() {
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

    /// Adds a force written in Python: `func(t, x, v)` gets the time and the positions and
    /// velocities of all particles as (n, dim) arrays and returns the forces (n, dim), N. It
    /// is called once per force evaluation. `potential(x)` (J) makes the energy known;
    /// `jacobian(t, x, v)` returns (dF/dx, dF/dv), each (n dim, n dim), for the implicit
    /// methods; `velocity_dependent=False` saves re-evaluations when the force ignores v.
    /// An exception raised inside propagates unchanged, with the step rolled back. Returns
    /// the force's index among the user forces.
    #[pyo3(signature = (func, *, potential=None, jacobian=None, velocity_dependent=None, name=None))]
    fn add_force(
        &self,
        py: Python<'_>,
        func: &Bound<'_, PyAny>,
        potential: Option<&Bound<'_, PyAny>>,
        jacobian: Option<&Bound<'_, PyAny>>,
        velocity_dependent: Option<&Bound<'_, PyAny>>,
        name: Option<&Bound<'_, PyAny>>,
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
        let spec = (
            func.bind(py),
            potential.as_ref().map(|p| p.bind(py)),
            jacobian.as_ref().map(|j| j.bind(py)),
            velocity_dependent,
            &name,
        )
            .into_pyobject(py)?
            .into_any()
            .unbind();
        let slot = g.slot.clone();
        let w = g.flush()?;
        let force = PyForce { name, dim: w.dim(), func, potential, jacobian, velocity_dependent, slot };
        let k = w.add_force_generator(std::sync::Arc::new(force)).map_err(py_err)?;
        g.user.push(spec);
        Ok(k)
    }
}
