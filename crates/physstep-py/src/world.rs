//! `physstep.World`: the engine's world with the names the Python API promises.
//!
//! Threading (see `crate::handle`): a World serves one thread at a time. Long calls (`step`) release the GIL in slices and look for Ctrl-C between them: an interrupt
//! leaves the world after the last whole step.

use crate::convert::{array, count, float, text, whole};
use crate::handle::{raise, World};
use crate::py_err;
use crate::record::SLICE;
use crate::slot::Slot;

/// Steps times coordinates from which a `step` call hears Ctrl-C inside a step (below it a
/// call is over in microseconds: not worth two system calls).
const WATCHED_WORK: u64 = 4096;
use physstep::clock::LoopMode;
use physstep::world::{World as Engine, WorldParams};
use pyo3::prelude::*;
use std::time::Instant;

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
        // The scene's own method and dt unless given (physstep scenes lists them).
        let spec = physstep::scenes::spec(&name).map_err(py_err)?;
        let method =
            method.filter(|m| !m.is_none()).map_or(Ok(spec.method.to_string()), |m| text(m, "method"))?;
        let dt = dt.filter(|d| !d.is_none()).map_or(Ok(spec.dt), |d| float(d, "dt"))?;
        let params = crate::convert::params(params)?;
        let overrides: Vec<(&str, f64)> = params.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        let scene = physstep::scenes::build(&name, &overrides, &method, dt).map_err(py_err)?;
        Python::attach(|py| crate::errors::warn_conflicts(py, scene.world.constraint_conflicts()))?;
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
        slf: &Bound<'py, Self>,
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
        let py = slf.py();
        let mut g = slf.get().lock()?;
        let slot = g.slot.clone();
        let (w, _lend) = g.stepping(slf)?;
        let dt = w.dt();
        let rp = physstep::record::RecordParams { dt, until, every, stages, stop_on_diverge };
        let (rec, elapsed) = crate::record::run(py, w, rp, Some(&slot), false)?;
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
        let copy = Self::with_parts(engine, g.slot.clone(), user, flow);
        let mut c = copy.lock()?;
        c.body_forces = g.body_forces.clone();
        c.solid_forces = g.solid_forces.clone();
        // The copy takes this World's force handles.
        c.family = g.family;
        drop(c);
        Ok(copy)
    }

    /// As `__copy__`: the engine's data is copied, Python callables are shared.
    fn __deepcopy__(&self, py: Python<'_>, _memo: &Bound<'_, PyAny>) -> PyResult<Self> {
        self.__copy__(py)
    }

    /// Pickles as the engine's own scene text of the world and its snapshot, with the
    /// Python callables beside them (pickled as Python pickles functions: a lambda does not,
    /// and the World then refuses in one line); unpickled, it continues bitwise as the
    /// original would.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<crate::pickle::Reduce<'py>> {
        let mut g = self.lock()?;
        g.flush()?;
        crate::pickle::reduce(py, &g)
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

    /// `World(dim=..., particles=..., [bodies=...,] method=..., dt=..., time=...)`.
    fn __repr__(&self) -> PyResult<String> {
        let g = self.lock()?;
        let w = &g.engine;
        let bodies = match w.bodies().len() {
            0 => String::new(),
            n => format!("bodies={n}, "),
        };
        Ok(format!(
            "World(dim={}, particles={}, {bodies}method='{}', dt={}, time={})",
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

    /// Takes n fixed steps. Raises DivergedError/ConvergenceError if a step fails (that step
    /// is rolled back, the steps before it stay taken); Ctrl-C stops after a whole step, heard
    /// inside a long step too (the step under way rolled back).
    #[pyo3(signature = (n=None))]
    fn step(slf: &Bound<'_, Self>, n: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let py = slf.py();
        let mut left = n.map_or(Ok(1), |n| count(n, "n"))?;
        let mut g = slf.get().lock()?;
        let slot = g.slot.clone();
        let (w, _lend) = g.stepping(slf)?;
        // Ctrl-C inside a step of a call that may take long (crate::interrupt).
        let work = left.saturating_mul(w.positions().len() as u64);
        let _watch = (work >= WATCHED_WORK).then(crate::interrupt::Watch::new);
        if work >= WATCHED_WORK {
            py.check_signals()?;
        }
        // A Python force takes the GIL at each evaluation: the steps keep it rather than give
        // it up and take it back around every call (other threads still run while the
        // force's Python code does).
        let python_inside = w.model().user_forces() > 0;
        while left > 0 {
            let before = w.steps();
            let mut slice = || -> physstep::Result<()> {
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
                Ok(())
            };
            let taken = if python_inside { slice() } else { py.detach(slice) };
            left -= w.steps() - before;
            if let Err(e) = taken {
                if !crate::interrupt::stopped(py, &e, Some(&slot))? {
                    return Err(raise(&slot, e));
                }
            }
            if left > 0 {
                py.check_signals()?;
            }
        }
        Ok(())
    }

    /// Runs one frame of the game loop; returns the number of fixed steps taken.
    fn advance(slf: &Bound<'_, Self>, frame_time: &Bound<'_, PyAny>) -> PyResult<u32> {
        let frame_time = float(frame_time, "frame_time")?;
        let mut g = slf.get().lock()?;
        let slot = g.slot.clone();
        let (w, _lend) = g.stepping(slf)?;
        Ok(w.advance(frame_time).map_err(|e| raise(&slot, e))?.plan.steps)
    }
}
