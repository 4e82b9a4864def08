//! The registries (methods, scenes) as Python lists of dicts.

use crate::convert::text;
use crate::py_err;
use physstep::integrators::{registry, Info, INFOS};
use physstep::scenes::{Loss, SCENES};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// One integrator's metadata as a dict (the keys of `physstep.MethodInfo`).
fn info_dict<'py>(py: Python<'py>, i: &Info) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", i.name)?;
    d.set_item("order", i.order)?;
    d.set_item("symplectic", i.symplectic)?;
    d.set_item("implicit", i.implicit)?;
    d.set_item("evals", i.evals)?;
    d.set_item("split", i.split)?;
    d.set_item("vector_positions", i.vector_positions)?;
    d.set_item("period", i.period)?;
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
    for s in SCENES {
        let d = PyDict::new(py);
        d.set_item("name", s.name)?;
        d.set_item("doc", s.doc)?;
        d.set_item("dim", s.dim)?;
        d.set_item("method", s.method)?;
        // Where it loses energy by design: (when, parameter, why), or None.
        let loss = match s.loss {
            Loss::None => None,
            Loss::Always(why) => Some(("always", "", why)),
            Loss::Nonzero(param, why) => Some(("nonzero", param, why)),
            Loss::BelowOne(param, why) => Some(("below_one", param, why)),
        };
        d.set_item("loss", loss)?;
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
fn method_info<'py>(py: Python<'py>, name: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    info_dict(py, registry::info(&text(name, "method")?).map_err(py_err)?)
}

/// Registers the functions on the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(methods, m)?)?;
    m.add_function(wrap_pyfunction!(method_info, m)?)?;
    m.add_function(wrap_pyfunction!(scenes, m)?)?;
    Ok(())
}
