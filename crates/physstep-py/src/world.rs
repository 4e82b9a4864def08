//! `physstep.World`: the engine's world with the names the Python API promises.

use crate::{matrix, py_err};
use numpy::{PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use physstep::clock::LoopMode;
use physstep::forces::{Endpoint, Force};
use physstep::world::{World as Engine, WorldParams};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

/// Particles, forces, an integrator and a fixed-timestep game loop.
#[pyclass(module = "physstep._core")]
pub struct World {
    inner: Engine,
    /// Particles from `add_particle`, validated and waiting to be added in one batch:
    /// growing the engine's `[x; v]` state one particle at a time moves the velocity half
    /// every time, which is quadratic in a spawn loop. Every method that reads or steps the
    /// state flushes them first.
    pending: Pending,
}

/// Validated particles not yet in the engine.
#[derive(Default)]
struct Pending {
    x: Vec<f64>,
    v: Vec<f64>,
    mass: Vec<f64>,
    fixed: Vec<bool>,
}

/// A vector argument of `dim` components, named `field` in errors.
fn vector(field: &str, v: Vec<f64>, dim: usize) -> PyResult<[f64; 3]> {
    if v.len() != dim {
        return Err(PyValueError::new_err(format!(
            "invalid {field} = {v:?}: must have {dim} components (dim = {dim})"
        )));
    }
    let mut out = [0.0; 3];
    out[..dim].copy_from_slice(&v);
    Ok(out)
}

/// A shape as Python prints it: `(4,)`, `(3, 2)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", shape.iter().map(ToString::to_string).collect::<Vec<_>>().join(", ")),
    }
}

/// Any array-like (numpy array, nested lists) as float64 numpy data of the wanted shape:
/// `cols = Some(dim)` for an `(n, dim)` matrix, `None` for a vector; `rows` fixes `n`.
fn array_arg(
    obj: &Bound<'_, PyAny>,
    field: &str,
    rows: Option<usize>,
    cols: Option<usize>,
) -> PyResult<Vec<f64>> {
    let py = obj.py();
    let want = match (rows, cols) {
        (Some(r), Some(c)) => format!("({r}, {c})"),
        (None, Some(c)) => format!("(n, {c})"),
        (Some(r), None) => format!("({r},)"),
        (None, None) => "(n,)".into(),
    };
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", "float64")?;
    let arr = py.import("numpy")?.call_method("ascontiguousarray", (obj,), Some(&kwargs)).map_err(|_| {
        PyValueError::new_err(format!("invalid {field}: must be an array of numbers of shape {want}"))
    })?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    let ok = match cols {
        Some(c) => shape.len() == 2 && shape[1] == c,
        None => shape.len() == 1,
    } && rows.is_none_or(|r| shape[0] == r);
    if !ok {
        return Err(PyValueError::new_err(format!(
            "invalid {field} shape {}: must be {want}",
            shape_text(&shape)
        )));
    }
    let data = if cols.is_some() {
        arr.extract::<PyReadonlyArray2<'_, f64>>()?.as_array().iter().copied().collect()
    } else {
        arr.extract::<PyReadonlyArray1<'_, f64>>()?.as_array().iter().copied().collect()
    };
    Ok(data)
}

/// A particle index argument, named `field` in errors.
fn index(field: &str, i: i64) -> PyResult<usize> {
    usize::try_from(i)
        .map_err(|_| PyValueError::new_err(format!("invalid {field} = {i}: must be a particle index >= 0")))
}

/// `other` as a particle index or an anchor point.
fn endpoint(field: &str, other: &Bound<'_, PyAny>, dim: usize) -> PyResult<Endpoint> {
    if let Ok(j) = other.extract::<i64>() {
        let j = usize::try_from(j).map_err(|_| {
            PyValueError::new_err(format!("invalid {field} = {j}: must be a particle index >= 0"))
        })?;
        return Ok(Endpoint::Particle(j));
    }
    let v: Vec<f64> = other.extract().map_err(|_| {
        PyValueError::new_err(format!(
            "invalid {field} = {other}: must be a particle index or an anchor point"
        ))
    })?;
    Ok(Endpoint::Anchor(vector(field, v, dim)?))
}

fn loop_mode(name: &str, substeps: u32) -> PyResult<LoopMode> {
    Ok(match name {
        "accumulator" => LoopMode::Accumulator,
        "step-per-frame" => LoopMode::StepPerFrame,
        "steps-per-frame" => LoopMode::StepsPerFrame(substeps),
        "frame-time" => LoopMode::FrameTime,
        "consume-frame" => LoopMode::ConsumeFrame,
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown loop '{other}'; valid loops: accumulator, step-per-frame, steps-per-frame, frame-time, consume-frame"
            )))
        }
    })
}

impl World {
    /// Adds the pending particles to the engine, in runs of equal `static` flag.
    fn flush(&mut self) -> PyResult<()> {
        if self.pending.mass.is_empty() {
            return Ok(());
        }
        let p = std::mem::take(&mut self.pending);
        let d = self.inner.dim();
        let mut start = 0;
        while start < p.mass.len() {
            let flag = p.fixed[start];
            let end = (start..p.mass.len()).find(|&i| p.fixed[i] != flag).unwrap_or(p.mass.len());
            let (xs, vs) = (&p.x[start * d..end * d], &p.v[start * d..end * d]);
            self.inner.add_particles(xs, Some(vs), Some(&p.mass[start..end]), flag).map_err(py_err)?;
            start = end;
        }
        Ok(())
    }

    /// Particles in the world, pending ones included.
    fn count(&self) -> usize {
        self.inner.len() + self.pending.mass.len()
    }

    fn distance(&self, i: usize, j: Endpoint) -> PyResult<f64> {
        let d = self.inner.dim();
        let x = self.inner.positions();
        if i >= self.inner.len() {
            return Err(PyValueError::new_err(format!(
                "invalid i = {i}: must be a particle index < {}",
                self.inner.len()
            )));
        }
        let other: Vec<f64> = match j {
            Endpoint::Particle(j) if j < self.inner.len() => x[j * d..(j + 1) * d].to_vec(),
            Endpoint::Particle(j) => {
                return Err(PyValueError::new_err(format!(
                    "invalid j = {j}: must be a particle index < {}",
                    self.inner.len()
                )))
            }
            Endpoint::Anchor(p) => p[..d].to_vec(),
        };
        Ok(x[i * d..(i + 1) * d].iter().zip(&other).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt())
    }
}

#[pymethods]
impl World {
    #[new]
    #[pyo3(signature = (dim, method="symplectic-euler", dt=1.0/120.0, max_steps_per_frame=8, max_frame_time=0.1, r#loop="accumulator", substeps=1))]
    fn new(
        dim: i64,
        method: &str,
        dt: f64,
        max_steps_per_frame: i64,
        max_frame_time: f64,
        r#loop: &str,
        substeps: i64,
    ) -> PyResult<Self> {
        let dim = usize::try_from(dim)
            .map_err(|_| PyValueError::new_err(format!("invalid dim = {dim}: must be 1, 2 or 3")))?;
        let max_steps = u32::try_from(max_steps_per_frame).map_err(|_| {
            PyValueError::new_err(format!(
                "invalid max_steps_per_frame = {max_steps_per_frame}: must be at least 1"
            ))
        })?;
        let substeps = u32::try_from(substeps).map_err(|_| {
            PyValueError::new_err(format!("invalid substeps = {substeps}: must be at least 1"))
        })?;
        let params = WorldParams {
            dim,
            method: method.into(),
            dt,
            mode: loop_mode(r#loop, substeps)?,
            max_steps_per_frame: max_steps,
            max_frame_time,
            ..WorldParams::default()
        };
        Ok(Self { inner: Engine::new(params).map_err(py_err)?, pending: Pending::default() })
    }

    /// A world built from a built-in scene.
    #[staticmethod]
    #[pyo3(signature = (name, method="symplectic-euler", dt=1.0/120.0, params=None))]
    fn from_scene(name: &str, method: &str, dt: f64, params: Option<Vec<(String, f64)>>) -> PyResult<Self> {
        let params = params.unwrap_or_default();
        let overrides: Vec<(&str, f64)> = params.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        let scene = physstep::scenes::build(name, &overrides, method, dt).map_err(py_err)?;
        Ok(Self { inner: scene.world, pending: Pending::default() })
    }

    /// Spatial dimensions.
    #[getter]
    fn dim(&self) -> usize {
        self.inner.dim()
    }

    fn __len__(&self) -> usize {
        self.count()
    }

    fn __repr__(&self) -> String {
        format!(
            "World(dim={}, particles={}, method='{}', dt={}, time={})",
            self.inner.dim(),
            self.count(),
            self.inner.integrator().info().name,
            self.inner.dt(),
            self.inner.time()
        )
    }

    /// The integrator's registry name; assign a name to switch.
    #[getter]
    fn method(&self) -> &'static str {
        self.inner.integrator().info().name
    }

    #[setter]
    fn set_method(&mut self, name: &str) -> PyResult<()> {
        self.inner.set_method(name).map_err(py_err)
    }

    /// The fixed step, s; assign to change it.
    #[getter]
    fn dt(&self) -> f64 {
        self.inner.dt()
    }

    #[setter]
    fn set_dt(&mut self, dt: f64) -> PyResult<()> {
        self.inner.set_dt(dt).map_err(py_err)
    }

    #[pyo3(signature = (position, velocity=None, mass=1.0, r#static=false))]
    fn add_particle(
        &mut self,
        position: Vec<f64>,
        velocity: Option<Vec<f64>>,
        mass: f64,
        r#static: bool,
    ) -> PyResult<usize> {
        let d = self.inner.dim();
        let position = vector("position", position, d)?;
        let velocity = vector("velocity", velocity.unwrap_or_else(|| vec![0.0; d]), d)?;
        if !mass.is_finite() {
            // An infinite mass may clash with n-body gravity, whose error names the index
            // the particle would get: count the pending ones in first.
            self.flush()?;
        }
        self.inner.check_particles(&position[..d], Some(&velocity[..d]), Some(&[mass])).map_err(py_err)?;
        let i = self.count();
        self.pending.x.extend_from_slice(&position[..d]);
        self.pending.v.extend_from_slice(&velocity[..d]);
        self.pending.mass.push(mass);
        self.pending.fixed.push(r#static);
        Ok(i)
    }

    #[pyo3(signature = (positions, velocities=None, masses=None, r#static=false))]
    fn add_particles<'py>(
        &mut self,
        py: Python<'py>,
        positions: &Bound<'py, PyAny>,
        velocities: Option<&Bound<'py, PyAny>>,
        masses: Option<&Bound<'py, PyAny>>,
        r#static: bool,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        self.flush()?;
        let d = self.inner.dim();
        let x = array_arg(positions, "positions", None, Some(d))?;
        let k = x.len() / d;
        let v = velocities.map(|v| array_arg(v, "velocities", Some(k), Some(d))).transpose()?;
        let m = masses.map(|m| array_arg(m, "masses", Some(k), None)).transpose()?;
        let first = self.inner.add_particles(&x, v.as_deref(), m.as_deref(), r#static).map_err(py_err)?;
        Ok(PyArray1::from_vec(py, (first as i64..(first + k) as i64).collect()))
    }

    fn add_gravity(&mut self, g: Vec<f64>) -> PyResult<()> {
        self.flush()?;
        let g = vector("g", g, self.inner.dim())?;
        self.inner.add_force(Force::Gravity { g }).map_err(py_err)
    }

    #[pyo3(signature = (i, j_or_anchor, stiffness, rest_length=None, damping=0.0))]
    fn add_spring(
        &mut self,
        i: i64,
        j_or_anchor: &Bound<'_, PyAny>,
        stiffness: f64,
        rest_length: Option<f64>,
        damping: f64,
    ) -> PyResult<()> {
        self.flush()?;
        let i = index("i", i)?;
        let j = endpoint("j_or_anchor", j_or_anchor, self.inner.dim())?;
        let rest_length = match rest_length {
            Some(r) => r,
            None => self.distance(i, j)?,
        };
        self.inner.add_force(Force::Spring { i, j, stiffness, rest_length, damping }).map_err(py_err)
    }

    #[pyo3(signature = (linear=0.0, quadratic=0.0))]
    fn add_drag(&mut self, linear: f64, quadratic: f64) -> PyResult<()> {
        self.flush()?;
        self.inner.add_force(Force::Drag { linear, quadratic }).map_err(py_err)
    }

    fn add_central_gravity(&mut self, center: Vec<f64>, gm: f64) -> PyResult<()> {
        self.flush()?;
        let center = vector("center", center, self.inner.dim())?;
        self.inner.add_force(Force::CentralGravity { center, gm }).map_err(py_err)
    }

    #[pyo3(signature = (g=1.0, softening=0.0))]
    fn add_nbody_gravity(&mut self, g: f64, softening: f64) -> PyResult<()> {
        self.flush()?;
        self.inner.add_force(Force::NBody { g, softening }).map_err(py_err)
    }

    fn add_rod(&mut self, i: i64, anchor_or_j: &Bound<'_, PyAny>, length: f64) -> PyResult<()> {
        self.flush()?;
        let i = index("i", i)?;
        let j = endpoint("anchor_or_j", anchor_or_j, self.inner.dim())?;
        if !(length.is_finite() && length > 0.0) {
            return Err(PyValueError::new_err(format!(
                "invalid length = {length}: must be a finite number > 0"
            )));
        }
        let r = self.distance(i, j)?;
        if (r - length).abs() > 1e-9 * length {
            return Err(PyValueError::new_err(format!(
                "invalid length = {length}: must equal the current distance {r} between the rod's ends (move the particle first)"
            )));
        }
        self.inner.add_force(Force::Rod { i, j, length }).map_err(py_err)
    }

    /// Takes n fixed steps. Raises DivergedError/ConvergenceError if a step fails (that step
    /// is rolled back).
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: i64) -> PyResult<()> {
        self.flush()?;
        let n =
            u64::try_from(n).map_err(|_| PyValueError::new_err(format!("invalid n = {n}: must be >= 0")))?;
        let inner = &mut self.inner;
        py.detach(|| inner.step(n)).map_err(py_err)
    }

    /// Runs one frame of the game loop; returns the number of fixed steps taken.
    fn advance(&mut self, frame_time: f64) -> PyResult<u32> {
        self.flush()?;
        Ok(self.inner.advance(frame_time).map_err(py_err)?.plan.steps)
    }

    /// Render interpolation factor in [0, 1).
    #[getter]
    fn alpha(&self) -> f64 {
        self.inner.alpha()
    }

    /// Totals of the game loop: frames, steps, clamped and dropped time (s).
    #[getter]
    fn clock_stats(&self) -> (u64, u64, f64, f64) {
        let s = self.inner.clock().stats();
        (s.frames, s.steps, s.clamped, s.dropped)
    }

    fn interpolated_positions<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.flush()?;
        matrix(py, self.inner.interpolated_positions(), self.inner.dim())
    }

    /// Positions (n, dim), m: a copy; assign an array to move the particles.
    #[getter]
    fn positions<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.flush()?;
        matrix(py, self.inner.positions().to_vec(), self.inner.dim())
    }

    #[setter(positions)]
    fn set_positions(&mut self, x: &Bound<'_, PyAny>) -> PyResult<()> {
        self.flush()?;
        let x = array_arg(x, "positions", Some(self.inner.len()), Some(self.inner.dim()))?;
        self.inner.set_positions(&x).map_err(py_err)
    }

    /// Velocities (n, dim), m/s: a copy; assign an array to change them.
    #[getter]
    fn velocities<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.flush()?;
        matrix(py, self.inner.velocities().to_vec(), self.inner.dim())
    }

    #[setter(velocities)]
    fn set_velocities(&mut self, v: &Bound<'_, PyAny>) -> PyResult<()> {
        self.flush()?;
        let v = array_arg(v, "velocities", Some(self.inner.len()), Some(self.inner.dim()))?;
        self.inner.set_velocities(&v).map_err(py_err)
    }

    /// Accelerations at the current state (n, dim), m/s^2.
    #[getter]
    fn accelerations<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.flush()?;
        let dim = self.inner.dim();
        matrix(py, self.inner.accelerations().to_vec(), dim)
    }

    /// Physics time, s.
    #[getter]
    fn time(&self) -> f64 {
        self.inner.time()
    }

    /// Steps taken.
    #[getter]
    fn steps(&self) -> u64 {
        self.inner.steps()
    }

    /// Force evaluations made.
    #[getter]
    fn evals(&self) -> u64 {
        self.inner.evals()
    }

    fn energy(&mut self) -> PyResult<f64> {
        self.flush()?;
        Ok(self.inner.energy())
    }

    fn momentum<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.flush()?;
        Ok(PyArray1::from_vec(py, self.inner.momentum()))
    }

    fn snapshot<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        self.flush()?;
        Ok(PyBytes::new(py, &self.inner.snapshot()))
    }

    fn restore(&mut self, data: &[u8]) -> PyResult<()> {
        self.flush()?;
        self.inner.restore(data).map_err(py_err)
    }

    fn state_hash(&mut self) -> PyResult<u64> {
        self.flush()?;
        Ok(self.inner.state_hash())
    }
}
