//! `simulate`: a built-in scene run and recorded by the engine's `Recorder`, in slices so
//! Ctrl-C is seen between them.

use crate::convert::{array, count, flag, float, matrix, params, text};
use crate::py_err;
use numpy::IntoPyArray;
use physstep::record::{RecordParams, Recorder, Recording};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::time::{Duration, Instant};

/// How long the engine runs between two looks for Ctrl-C.
pub(crate) const SLICE: Duration = Duration::from_millis(50);

/// Runs a scene and returns its recorded trajectory as a dict of numpy arrays.
#[pyfunction]
#[pyo3(signature = (scene, method, dt, until, params=None, *, x0=None, v0=None, stages=None, every=None, stop_on_diverge=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn simulate<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    method: &Bound<'py, PyAny>,
    dt: &Bound<'py, PyAny>,
    until: &Bound<'py, PyAny>,
    params: Option<&Bound<'py, PyAny>>,
    x0: Option<&Bound<'py, PyAny>>,
    v0: Option<&Bound<'py, PyAny>>,
    stages: Option<&Bound<'py, PyAny>>,
    every: Option<&Bound<'py, PyAny>>,
    stop_on_diverge: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (scene, method) = (text(scene, "scene")?, text(method, "method")?);
    let (dt, until) = (float(dt, "dt")?, float(until, "until")?);
    let params = params_arg(params)?;
    let opt_flag = |o: Option<&Bound<'py, PyAny>>, f: &str| o.map_or(Ok(false), |o| flag(o, f));
    let stages = opt_flag(stages, "stages")?;
    let stop_on_diverge = opt_flag(stop_on_diverge, "stop_on_diverge")?;
    let every = match every {
        Some(e) => count(e, "every")?,
        None => 1,
    };
    let overrides: Vec<(&str, f64)> = params.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    let mut built = physstep::scenes::build(&scene, &overrides, &method, dt).map_err(py_err)?;
    let w = &mut built.world;
    let n = w.positions().len();
    if let Some(x0) = x0.filter(|o| !o.is_none()) {
        let x0 = initial(x0, "x0", n)?;
        w.set_positions(&x0).map_err(py_err)?;
    }
    if let Some(v0) = v0.filter(|o| !o.is_none()) {
        let v0 = initial(v0, "v0", n)?;
        w.set_velocities(&v0).map_err(py_err)?;
    }
    let rp = RecordParams { dt, until, every, stages, stop_on_diverge };
    let (rec, elapsed) = run(py, w, rp, None, true)?;
    let d = PyDict::new(py);
    d.set_item("scene", built.spec.name)?;
    let params_out = PyDict::new(py);
    for (p, v) in built.spec.params.iter().zip(&built.values) {
        params_out.set_item(p.name, *v)?;
    }
    d.set_item("params", params_out)?;
    let exact_known = built.exact_rows(&[]).is_some();
    fill(&d, &built.world, rec, elapsed, stages)?;
    // The exact solution is computed when it is read (`Trajectory.exact_x`): a sine and a
    // cosine per row are a fair part of a recording of the spring.
    if exact_known {
        built.world = physstep::world::World::new(physstep::world::WorldParams::default()).map_err(py_err)?;
        d.set_item("exact", ExactSolution { scene: std::sync::Mutex::new(built), n })?;
    } else {
        d.set_item("exact", py.None())?;
    }
    Ok(d)
}

/// A `(rows, cols)` float array handed to Python.
type Matrix<'py> = Bound<'py, numpy::PyArray2<f64>>;

/// A built-in scene's exact solution, kept by `simulate`'s result until it is read.
#[pyclass(module = "physstep._core", frozen)]
pub(crate) struct ExactSolution {
    /// The scene (its world emptied: only its exact solution is used).
    scene: std::sync::Mutex<physstep::scenes::Scene>,
    /// Coordinates per row.
    n: usize,
}

#[pymethods]
impl ExactSolution {
    /// `(exact_x, exact_v)` at times `t`, each `(len(t), coordinates)`.
    fn rows<'py>(&self, py: Python<'py>, t: &Bound<'py, PyAny>) -> PyResult<(Matrix<'py>, Matrix<'py>)> {
        let t = array(t, "t", None, None)?;
        let scene = self.scene.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let (ex, ev) = scene.exact_rows(&t).unwrap_or_default();
        Ok((matrix(py, ex, self.n)?, matrix(py, ev, self.n)?))
    }
}

/// Records `w` as `rp` says, in slices without the GIL (other Python threads run meanwhile)
/// with a look for Ctrl-C between them; returns the recording and the stepping time, ns.
/// A Python exception kept in `slot` by a user force comes first, unchanged. With
/// `defer_kinetic` the kinetic energies of a world of particles are left for [`fill`] to
/// hand out as a column computed when read.
pub(crate) fn run(
    py: Python<'_>,
    w: &mut physstep::world::World,
    rp: RecordParams,
    slot: Option<&crate::slot::Slot>,
    defer_kinetic: bool,
) -> PyResult<(Recording, u64)> {
    let fail = |e: physstep::Error| match slot {
        Some(s) => crate::handle::raise(s, e),
        None => py_err(e),
    };
    let recorder = if defer_kinetic { Recorder::deferring_kinetic(w, rp) } else { Recorder::new(w, rp) };
    let mut recorder = recorder.map_err(fail)?;
    // Steps between looks at the clock: up to 4096 for a small world (a call's set-up is a
    // fair part of a cheap step), at least 64; 64 with Python forces (slow steps).
    let coords = w.positions().len().max(1) as u64;
    let per_look = if slot.is_some() { 64 } else { (65_536 / coords).clamp(64, 4096) };
    let start = Instant::now();
    // A Ctrl-C before the watch began (while the scene was built) is heard here; after it,
    // inside a step.
    let _watch = crate::interrupt::Watch::new();
    py.check_signals()?;
    loop {
        let done = py.detach(|| -> physstep::Result<bool> {
            let slice = Instant::now();
            loop {
                if recorder.run(w, per_look)? {
                    return Ok(true);
                }
                if slice.elapsed() > SLICE {
                    return Ok(false);
                }
            }
        });
        match done {
            Ok(true) => break,
            Ok(false) => {}
            Err(e) if crate::interrupt::stopped(py, &e, slot)? => continue,
            Err(e) => return Err(fail(e)),
        }
        py.check_signals()?;
    }
    let elapsed = start.elapsed().as_nanos() as u64;
    let mut rec = recorder.finish();
    // A failure the run stopped at (stop_on_diverge) may have been a Python exception; a
    // potential that returned no number (its energy column unknown) left its error too.
    if let Some(s) = slot {
        if let Some(e) = s.take() {
            rec.diverged = None;
            return Err(e);
        }
    }
    Ok((rec, elapsed))
}

/// A (rows, cols) array of `data` (rows given: a world without particles has no columns).
fn table(
    py: Python<'_>,
    data: Vec<f64>,
    rows: usize,
    cols: usize,
) -> PyResult<Bound<'_, numpy::PyArray2<f64>>> {
    numpy::ndarray::Array2::from_shape_vec((rows, cols), data)
        .map(|a| a.into_pyarray(py))
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))
}

/// The recording's arrays and counts in `d` (the keys of `physstep.Trajectory`).
pub(crate) fn fill(
    d: &Bound<'_, PyDict>,
    w: &physstep::world::World,
    rec: Recording,
    elapsed: u64,
    stages: bool,
) -> PyResult<()> {
    let py = d.py();
    let n = w.positions().len();
    d.set_item("method", w.integrator().info().name)?;
    d.set_item("dt", w.dt())?;
    d.set_item("dim", w.dim())?;
    d.set_item("steps", w.steps())?;
    d.set_item("evals", rec.evals)?;
    d.set_item("elapsed_ns", elapsed)?;
    d.set_item("diverged", rec.diverged.as_ref().map(ToString::to_string))?;
    d.set_item("collisions", crate::world_balls::stats(py, w)?)?;
    d.set_item("contacts", crate::world_solids::stats(py, w)?)?;
    // A user force without a potential leaves the energy unknown: None, not a wrong number.
    let energy_known = rec.energy.len() == rec.t.len();
    let is_flow = w.flow().is_some();
    let rows = rec.t.len();
    let nb = w.bodies().len();
    let kind = if is_flow {
        "flow"
    } else if nb > 0 {
        "bodies"
    } else {
        "particles"
    };
    d.set_item("kind", kind)?;
    d.set_item("t", numpy::PyArray1::from_vec(py, rec.t))?;
    d.set_item("x", table(py, rec.x, rows, n)?)?;
    let v = table(py, rec.v, rows, n)?;
    d.set_item("v", &v)?;
    if is_flow {
        // A flow has a state and its derivative (`x`, `v` here), no accelerations.
        d.set_item("a", table(py, Vec::new(), rows, 0)?)?;
    } else {
        d.set_item("a", table(py, rec.a, rows, n)?)?;
    }
    if nb > 0 {
        d.set_item("angular_momentum", table(py, rec.angular_momentum, rows, 3)?)?;
        let spin = numpy::ndarray::Array3::from_shape_vec((rows, nb, 3), rec.body_spin)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
        d.set_item("body_spin", spin.into_pyarray(py))?;
    } else {
        d.set_item("angular_momentum", py.None())?;
        d.set_item("body_spin", py.None())?;
    }
    if energy_known {
        d.set_item("energy", numpy::PyArray1::from_vec(py, rec.energy))?;
    } else {
        d.set_item("energy", py.None())?;
    }
    if rec.kinetic.len() == rows {
        d.set_item("kinetic", numpy::PyArray1::from_vec(py, rec.kinetic))?;
    } else {
        // Deferred by the recorder (a world of particles): computed if it is read.
        let model = std::sync::Mutex::new(w.model().clone());
        d.set_item("kinetic", KineticRows { model, v: v.unbind() })?;
    }
    if stages {
        let list = PyList::empty(py);
        for (k, stage, t, x, v, a) in rec.stages {
            list.append((k, stage, t, x, v, a))?;
        }
        d.set_item("stages", list)?;
    } else {
        d.set_item("stages", py.None())?;
    }
    Ok(())
}

/// Scene parameters from a dict or pairs.
pub(crate) fn params_arg(o: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<(String, f64)>> {
    params(o)
}

/// An initial state of `n` coordinates, flat or `(particles, dim)`.
fn initial(o: &Bound<'_, PyAny>, field: &str, n: usize) -> PyResult<Vec<f64>> {
    let flat = o.py().import("numpy")?.call_method1("ravel", (o,));
    let flat = flat.map_err(|_| crate::convert::invalid(field, o, "an array of numbers"))?;
    let v = array(&flat, field, None, None)?;
    if v.len() != n {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "invalid len({field}) = {}: must be {n}, the scene's coordinate count",
            v.len()
        )));
    }
    if let Some(i) = v.iter().position(|c| !c.is_finite()) {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "invalid {field}[{i}] = {}: must be finite",
            v[i]
        )));
    }
    Ok(v)
}

/// The kinetic energy of every row of a recording of particles, computed when called (the
/// `kinetic` a recording deferred): [`physstep::world::Model::kinetic`] of each velocity row,
/// the bits the recording would have kept.
#[pyclass(module = "physstep._core", frozen)]
pub(crate) struct KineticRows {
    /// The world's masses (its force model, of which only the masses are used).
    model: std::sync::Mutex<physstep::world::Model>,
    /// The recorded velocities, (rows, coordinates).
    v: Py<numpy::PyArray2<f64>>,
}

#[pymethods]
impl KineticRows {
    /// The column, J, (rows,).
    fn __call__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        use numpy::{PyArrayMethods, PyUntypedArrayMethods};
        let v = self
            .v
            .bind(py)
            .try_readonly()
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
        let cols = v.shape()[1];
        let model = self.model.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let k: Vec<f64> = match v.as_slice() {
            Ok(s) if cols > 0 => s.chunks_exact(cols).map(|row| model.kinetic(row)).collect(),
            _ => v.as_array().rows().into_iter().map(|row| model.kinetic(&row.to_vec())).collect(),
        };
        Ok(numpy::PyArray1::from_vec(py, k))
    }
}
