//! The engine's errors as Python exceptions.
//!
//! Bad input becomes `ValueError` with the engine's message (it names the field and value);
//! a step that fails becomes `DivergedError` / `ConvergenceError` (both `StepError`, a
//! `RuntimeError`); a World used from two threads at once, `WorldBusyError`.

use physstep::error::Error;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyUserWarning, PyValueError};
use pyo3::prelude::*;

create_exception!(_core, StepError, PyRuntimeError, "A step failed; the state was rolled back.");
create_exception!(
    _core,
    DivergedError,
    StepError,
    "A step produced a non-finite or runaway value (or a non-finite energy); it was rolled back."
);
create_exception!(
    _core,
    ConvergenceError,
    StepError,
    "An implicit method's Newton iteration did not converge; the step was rolled back."
);
create_exception!(
    _core,
    WorldBusyError,
    PyRuntimeError,
    "The World is in use by another thread (or by a callback inside its own step)."
);

create_exception!(
    _core,
    ConstraintWarning,
    PyUserWarning,
    "The world's constraints cannot all be met (World.constraint_conflicts() lists why)."
);

/// Warns (`ConstraintWarning`) each line of `conflicts`: constraints that cannot all be
/// met. Called with the World unlocked (a warning filter may run Python code).
pub(crate) fn warn_conflicts(py: Python<'_>, conflicts: Vec<String>) -> PyResult<()> {
    let category = py.get_type::<ConstraintWarning>();
    for c in conflicts {
        let msg = std::ffi::CString::new(format!("the constraints cannot all be met: {c}"))
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        PyErr::warn(py, category.as_any(), &msg, 1)?;
    }
    Ok(())
}

/// The engine's error as the matching Python exception.
pub(crate) fn py_err(e: Error) -> PyErr {
    let msg = e.to_string();
    match e {
        Error::Diverged { .. } | Error::NonFinite { .. } => DivergedError::new_err(msg),
        Error::NotConverged { .. } | Error::Contacts { .. } => ConvergenceError::new_err(msg),
        Error::Interrupted { .. } => pyo3::exceptions::PyKeyboardInterrupt::new_err(msg),
        _ => PyValueError::new_err(msg),
    }
}

/// Registers the exception types on the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("StepError", py.get_type::<StepError>())?;
    m.add("DivergedError", py.get_type::<DivergedError>())?;
    m.add("ConvergenceError", py.get_type::<ConvergenceError>())?;
    m.add("WorldBusyError", py.get_type::<WorldBusyError>())?;
    m.add("ConstraintWarning", py.get_type::<ConstraintWarning>())?;
    Ok(())
}

/// A handle of another World (not a copy's or a pickle's of its own): `field`, the argument's name; `kinds`: the handle's entities (`particles`, `bodies`, ...).
pub(crate) fn foreign_handle(field: &str, kinds: &str, text: &str) -> PyErr {
    PyValueError::new_err(format!(
        "invalid {field} = {text}: must be a handle of this World's {kinds} (it is another World's; \
         a copy or a pickle of a World takes the handles of the World it came from)"
    ))
}

/// A handle whose entity, link or force was removed from its World.
pub(crate) fn removed_handle(what: &str, text: &str) -> PyErr {
    PyValueError::new_err(format!("invalid {what} = {text}: it was removed from its World"))
}
