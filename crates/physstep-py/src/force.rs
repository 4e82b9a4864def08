//! `World.add_force(fn, ...)`: a Python callable as the engine's `ForceGenerator`.
//!
//! The callable is called once per force evaluation with numpy arrays of all particles
//! (never per particle). An exception it raises is kept in the world's slot and re-raised
//! unchanged once the engine has rolled the step back; a wrong shape or a non-finite force
//! is the engine's `Error::Force`, a `ValueError` naming the force.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use physstep::forces::ForceGenerator;
use pyo3::prelude::*;
use std::sync::{Arc, Mutex};

/// Where a Python exception raised inside a step waits to be re-raised.
pub(crate) type Slot = Arc<Mutex<Option<PyErr>>>;

/// A Python force.
pub(crate) struct PyForce {
    pub name: String,
    pub dim: usize,
    pub func: Py<PyAny>,
    pub potential: Option<Py<PyAny>>,
    pub jacobian: Option<Py<PyAny>>,
    pub velocity_dependent: bool,
    pub slot: Slot,
}

impl PyForce {
    /// `(n, dim)` numpy copies of a flat slice.
    fn arr<'py>(&self, py: Python<'py>, v: &[f64]) -> PyResult<Bound<'py, PyAny>> {
        let n = v.len() / self.dim;
        Ok(PyArray1::from_slice(py, v).reshape([n, self.dim])?.into_any())
    }

    /// Keeps `e` for the caller of the step; returns a message for the engine.
    fn keep(&self, py: Python<'_>, e: PyErr) -> String {
        let msg = format!("raised {}", e.value(py));
        let mut slot = self.slot.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if slot.is_none() {
            *slot = Some(e);
        }
        msg
    }

    /// A `(rows, cols)` float array from `out`, or a message naming what is wrong.
    fn matrix(
        &self,
        out: &Bound<'_, PyAny>,
        what: &str,
        rows: usize,
        cols: usize,
    ) -> Result<Vec<f64>, String> {
        let py = out.py();
        let arr = py
            .import("numpy")
            .and_then(|np| np.call_method1("asarray", (out, "float64")))
            .map_err(|_| format!("{what} must be an array of numbers of shape ({rows}, {cols})"))?;
        let a: PyReadonlyArray2<'_, f64> = arr
            .extract()
            .map_err(|_| format!("{what} must have shape ({rows}, {cols}), not {}", shape(&arr)))?;
        if a.shape() != [rows, cols] {
            return Err(format!("{what} must have shape ({rows}, {cols}), not {}", shape(&arr)));
        }
        Ok(a.as_array().iter().copied().collect())
    }
}

fn shape(a: &Bound<'_, PyAny>) -> String {
    a.getattr("shape").and_then(|s| s.str()).map(|s| s.to_string()).unwrap_or_else(|_| "?".into())
}

impl ForceGenerator for PyForce {
    fn name(&self) -> &str {
        &self.name
    }

    fn add_forces(&self, t: f64, x: &[f64], v: &[f64], f: &mut [f64]) -> Result<(), String> {
        Python::attach(|py| {
            let call = || -> PyResult<Bound<'_, PyAny>> {
                self.func.bind(py).call1((t, self.arr(py, x)?, self.arr(py, v)?))
            };
            let out = call().map_err(|e| self.keep(py, e))?;
            let n = x.len() / self.dim;
            let forces = self.matrix(&out, "the returned force", n, self.dim)?;
            // (The engine checks the sum for NaN and infinity, and names the entry.)
            for (fi, gi) in f.iter_mut().zip(&forces) {
                *fi += gi;
            }
            Ok(())
        })
    }

    fn velocity_dependent(&self) -> bool {
        self.velocity_dependent
    }

    fn potential(&self, x: &[f64]) -> Option<f64> {
        let p = self.potential.as_ref()?;
        Python::attach(|py| {
            let r = self.arr(py, x).and_then(|xa| p.bind(py).call1((xa,))).and_then(|u| u.extract::<f64>());
            match r {
                Ok(u) if u.is_finite() => Some(u),
                Ok(_) => None,
                Err(e) => {
                    self.keep(py, e);
                    None
                }
            }
        })
    }

    fn jacobian(&self, t: f64, x: &[f64], v: &[f64], dfdx: &mut [f64], dfdv: &mut [f64]) -> bool {
        let Some(jac) = self.jacobian.as_ref() else { return false };
        Python::attach(|py| {
            let n = x.len();
            let r = (|| -> PyResult<Bound<'_, PyAny>> {
                jac.bind(py).call1((t, self.arr(py, x)?, self.arr(py, v)?))
            })();
            let out = match r {
                Ok(o) => o,
                Err(e) => {
                    self.keep(py, e);
                    return false;
                }
            };
            let pair: Result<(Bound<'_, PyAny>, Bound<'_, PyAny>), _> = out.extract();
            let Ok((jx, jv)) = pair else { return false };
            match (self.matrix(&jx, "dF/dx", n, n), self.matrix(&jv, "dF/dv", n, n)) {
                (Ok(a), Ok(b)) if a.iter().chain(&b).all(|c| c.is_finite()) => {
                    dfdx.iter_mut().zip(&a).for_each(|(d, s)| *d += s);
                    dfdv.iter_mut().zip(&b).for_each(|(d, s)| *d += s);
                    true
                }
                _ => false,
            }
        })
    }
}

/// A Python flow `func(t, y) -> dy`.
pub(crate) struct PyFlow {
    pub name: String,
    pub func: Py<PyAny>,
    pub jacobian: Option<Py<PyAny>>,
    pub slot: Slot,
}

impl PyFlow {
    fn keep(&self, py: Python<'_>, e: PyErr) -> String {
        let msg = format!("raised {}", e.value(py));
        let mut slot = self.slot.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if slot.is_none() {
            *slot = Some(e);
        }
        msg
    }

    /// A flat float vector of length `n` from `out`, or a message naming what is wrong.
    fn vector(out: &Bound<'_, PyAny>, what: &str, n: usize) -> Result<Vec<f64>, String> {
        let py = out.py();
        let arr = py
            .import("numpy")
            .and_then(|np| np.call_method1("asarray", (out, "float64")))
            .and_then(|a| a.call_method0("ravel"))
            .map_err(|_| format!("{what} must be an array of {n} numbers"))?;
        let v: Vec<f64> = arr.extract().map_err(|_| format!("{what} must be an array of {n} numbers"))?;
        if v.len() != n {
            return Err(format!("{what} must have {n} entries, not {}", v.len()));
        }
        Ok(v)
    }
}

impl physstep::flows::FlowGenerator for PyFlow {
    fn name(&self) -> &str {
        &self.name
    }

    fn deriv(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), String> {
        Python::attach(|py| {
            let out =
                self.func.bind(py).call1((t, PyArray1::from_slice(py, y))).map_err(|e| self.keep(py, e))?;
            let v = Self::vector(&out, "the returned derivative", y.len())?;
            dy.copy_from_slice(&v);
            Ok(())
        })
    }

    fn jacobian(&self, t: f64, y: &[f64], dfdy: &mut [f64]) -> bool {
        let Some(jac) = self.jacobian.as_ref() else { return false };
        Python::attach(|py| match jac.bind(py).call1((t, PyArray1::from_slice(py, y))) {
            Ok(out) => match Self::vector(&out, "the Jacobian", y.len() * y.len()) {
                Ok(v) if v.iter().all(|c| c.is_finite()) => {
                    dfdy.copy_from_slice(&v);
                    true
                }
                _ => false,
            },
            Err(e) => {
                self.keep(py, e);
                false
            }
        })
    }
}
