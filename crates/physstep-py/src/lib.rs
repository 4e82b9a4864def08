//! Python bindings of physstep: conversion and error mapping only, no physics.
//!
//! Bad input becomes `ValueError` with the engine's message (it names the field and value);
//! a step that diverges or whose Newton solve fails becomes `DivergedError` /
//! `ConvergenceError` (both `StepError`, a `RuntimeError`). Nothing panics across the
//! boundary: every engine call returns a `Result`.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use physstep::error::Error;
use physstep::integrators::{registry, Info, StageLog, INFOS};
use physstep::scenes::SCENES;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

mod world;

create_exception!(_core, StepError, PyRuntimeError, "A step failed; the state was rolled back.");
create_exception!(_core, DivergedError, StepError, "A step produced a non-finite value; it was rolled back.");
create_exception!(
    _core,
    ConvergenceError,
    StepError,
    "An implicit method's Newton iteration did not converge."
);

/// The engine's error as the matching Python exception.
pub(crate) fn py_err(e: Error) -> PyErr {
    let msg = e.to_string();
    match e {
        Error::Diverged { .. } => DivergedError::new_err(msg),
        Error::NotConverged { .. } => ConvergenceError::new_err(msg),
        _ => PyValueError::new_err(msg),
    }
}

/// `rows x cols` numpy array from a flat row-major vector.
pub(crate) fn matrix(py: Python<'_>, data: Vec<f64>, cols: usize) -> PyResult<Bound<'_, PyArray2<f64>>> {
    let rows = data.len().checked_div(cols).unwrap_or(0);
    let arr = Array2::from_shape_vec((rows, cols), data).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(arr.into_pyarray(py))
}

/// One recorded evaluation point: step index, stage name, t, x, v, a.
type StageRow = (u64, &'static str, f64, Vec<f64>, Vec<f64>, Vec<f64>);

/// One integrator's metadata as a dict (the keys of `physstep.MethodInfo`).
fn info_dict<'py>(py: Python<'py>, i: &Info) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", i.name)?;
    d.set_item("order", i.order)?;
    d.set_item("symplectic", i.symplectic)?;
    d.set_item("implicit", i.implicit)?;
    d.set_item("evals", i.evals)?;
    d.set_item("split", i.split)?;
    d.set_item("doc", i.doc)?;
    Ok(d)
}

/// Every integrator's metadata, in registry order.
#[pyfunction]
fn methods(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for i in &INFOS {
        list.append(info_dict(py, i)?)?;
    }
    Ok(list)
}

/// Every built-in scene with its parameters and defaults.
#[pyfunction]
fn scenes(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for s in &SCENES {
        let d = PyDict::new(py);
        d.set_item("name", s.name)?;
        d.set_item("doc", s.doc)?;
        d.set_item("dim", s.dim)?;
        d.set_item("dt", s.dt)?;
        d.set_item("until", s.until)?;
        let params = PyList::empty(py);
        for p in s.params {
            let pd = PyDict::new(py);
            pd.set_item("name", p.name)?;
            pd.set_item("default", p.default)?;
            pd.set_item("doc", p.doc)?;
            params.append(pd)?;
        }
        d.set_item("params", params)?;
        list.append(d)?;
    }
    Ok(list)
}

/// Checks a method name, raising ValueError with the valid names.
#[pyfunction]
fn method_info<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyDict>> {
    info_dict(py, registry::info(name).map_err(py_err)?)
}

/// Runs a scene and returns its recorded trajectory as a dict of numpy arrays.
#[pyfunction]
#[pyo3(signature = (scene, method, dt, until, params=None, *, x0=None, v0=None, stages=false, every=1, stop_on_diverge=false))]
#[allow(clippy::too_many_arguments)]
fn simulate<'py>(
    py: Python<'py>,
    scene: &str,
    method: &str,
    dt: f64,
    until: f64,
    params: Option<Vec<(String, f64)>>,
    x0: Option<Vec<f64>>,
    v0: Option<Vec<f64>>,
    stages: bool,
    every: u64,
    stop_on_diverge: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let params = params.unwrap_or_default();
    let overrides: Vec<(&str, f64)> = params.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    let mut built = physstep::scenes::build(scene, &overrides, method, dt).map_err(py_err)?;
    if !(until.is_finite() && until >= 0.0) {
        return Err(PyValueError::new_err(format!("invalid until = {until}: must be a finite number >= 0")));
    }
    if every == 0 {
        return Err(PyValueError::new_err("invalid every = 0: must be at least 1"));
    }
    let w = &mut built.world;
    for (field, values) in [("x0", &x0), ("v0", &v0)] {
        if let Some(values) = values {
            let n = w.positions().len();
            if values.len() != n {
                return Err(PyValueError::new_err(format!(
                    "invalid len({field}) = {}: must be {n}, the scene's coordinate count",
                    values.len()
                )));
            }
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(PyValueError::new_err(format!(
                    "invalid {field}[{i}] = {}: must be finite",
                    values[i]
                )));
            }
        }
    }
    if let Some(x0) = x0 {
        w.set_positions(&x0).map_err(py_err)?;
    }
    if let Some(v0) = v0 {
        w.set_velocities(&v0).map_err(py_err)?;
    }
    // until / dt rounded down, forgiving the rounding of a quotient that should be whole.
    let ratio = until / dt;
    let steps =
        if (ratio - ratio.round()).abs() <= 1e-9 * ratio.max(1.0) { ratio.round() } else { ratio.floor() };
    if steps > 1e9 {
        return Err(PyValueError::new_err(format!(
            "invalid until = {until}: more than 1e9 steps of dt = {dt}"
        )));
    }
    let steps = steps as u64;
    let n = w.positions().len();
    let rows = steps / every + 2;
    // t, x, v, a and energy of every recorded row: refuse what would not fit in memory
    // rather than abort on a failed allocation.
    let values = rows.saturating_mul(3 * n as u64 + 2);
    if values > MAX_RECORDED {
        return Err(PyValueError::new_err(format!(
            "invalid every = {every}: {rows} rows of {n} coordinates would record {values} values \
             (more than {MAX_RECORDED}); record fewer rows with a larger every"
        )));
    }
    let cap = rows as usize;
    let (mut ts, mut xs, mut vs, mut accs, mut es) = (
        Vec::with_capacity(cap),
        Vec::with_capacity(cap * n),
        Vec::with_capacity(cap * n),
        Vec::with_capacity(cap * n),
        Vec::with_capacity(cap),
    );
    let mut log = StageLog::default();
    let mut stage_rows: Vec<StageRow> = Vec::new();
    let mut diverged: Option<String> = None;
    let start = std::time::Instant::now();
    // The loop touches no Python object: other Python threads run meanwhile.
    let evals0 = py
        .detach(|| -> Result<u64, Error> {
            let mut record = |w: &mut physstep::world::World| {
                ts.push(w.time());
                xs.extend_from_slice(w.positions());
                vs.extend_from_slice(w.velocities());
                accs.extend_from_slice(w.accelerations());
                es.push(w.energy());
            };
            record(w);
            let evals0 = w.evals();
            for k in 1..=steps {
                let r = if stages {
                    log.rows.clear();
                    let r = w.step_logged(dt, &mut log);
                    for row in &log.rows {
                        let (x, v) = row.y.split_at(n);
                        stage_rows.push((
                            k - 1,
                            row.stage,
                            row.t,
                            x.to_vec(),
                            v.to_vec(),
                            row.f[n..].to_vec(),
                        ));
                    }
                    r
                } else {
                    w.step_by(dt)
                };
                if let Err(e) = r {
                    if stop_on_diverge && matches!(e, Error::Diverged { .. } | Error::NotConverged { .. }) {
                        diverged = Some(e.to_string());
                        record(w);
                        break;
                    }
                    return Err(e);
                }
                if k % every == 0 || k == steps {
                    record(w);
                }
            }
            Ok(evals0)
        })
        .map_err(py_err)?;
    let elapsed = start.elapsed().as_nanos() as u64;
    let taken = w.steps();
    let evals = w.evals() - evals0;
    let d = PyDict::new(py);
    d.set_item("scene", built.spec.name)?;
    d.set_item("method", method)?;
    d.set_item("dt", dt)?;
    d.set_item("dim", built.spec.dim)?;
    d.set_item("steps", taken)?;
    d.set_item("evals", evals)?;
    d.set_item("elapsed_ns", elapsed)?;
    d.set_item("diverged", diverged)?;
    let params_out = PyDict::new(py);
    for (p, v) in built.spec.params.iter().zip(&built.values) {
        params_out.set_item(p.name, *v)?;
    }
    d.set_item("params", params_out)?;
    if built.has_exact() {
        let (mut ex, mut ev) = (Vec::with_capacity(xs.len()), Vec::with_capacity(xs.len()));
        for t in &ts {
            let (x, v) = built.exact(*t).unwrap_or_default();
            ex.extend(x);
            ev.extend(v);
        }
        d.set_item("exact_x", matrix(py, ex, n)?)?;
        d.set_item("exact_v", matrix(py, ev, n)?)?;
    } else {
        d.set_item("exact_x", py.None())?;
        d.set_item("exact_v", py.None())?;
    }
    d.set_item("t", PyArray1::from_vec(py, ts))?;
    d.set_item("x", matrix(py, xs, n)?)?;
    d.set_item("v", matrix(py, vs, n)?)?;
    d.set_item("a", matrix(py, accs, n)?)?;
    d.set_item("energy", PyArray1::from_vec(py, es))?;
    if stages {
        let rows = PyList::empty(py);
        for (k, stage, t, x, v, a) in stage_rows {
            rows.append((k, stage, t, x, v, a))?;
        }
        d.set_item("stages", rows)?;
    } else {
        d.set_item("stages", py.None())?;
    }
    Ok(d)
}

/// Most values `simulate` records (4 GB of f64).
const MAX_RECORDED: u64 = 500_000_000;

/// The native module `physstep._core`.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(methods, m)?)?;
    m.add_function(wrap_pyfunction!(method_info, m)?)?;
    m.add_function(wrap_pyfunction!(scenes, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_class::<world::World>()?;
    m.add("StepError", m.py().get_type::<StepError>())?;
    m.add("DivergedError", m.py().get_type::<DivergedError>())?;
    m.add("ConvergenceError", m.py().get_type::<ConvergenceError>())?;
    Ok(())
}
