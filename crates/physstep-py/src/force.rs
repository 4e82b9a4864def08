//! `World.add_force(fn, ...)`: a Python callable as the engine's `ForceGenerator`.
//!
//! The callable is called once per force evaluation with numpy arrays of all particles
//! (never per particle). An exception it raises is kept in the world's slot and re-raised
//! unchanged once the engine has rolled the step back; a wrong shape or a non-finite force
//! is the engine's `Error::Force`, a `ValueError` naming the force.
//!
//! What the callable is handed, and why it is sound (docs/worlds.md, "Python forces"):
//!
//! * `x` and `v` are read-only `(n, dim)` float64 arrays, valid during the call only. When the
//!   engine hands the force the World's own positions and velocities (the method evaluates at
//!   the state: the Euler methods, Verlet's drifted positions, RK4's first stage), and the
//!   World lends them (`crate::slot`: during `step`, `advance` and `record`), they are views of
//!   the engine's `state.y`, made once a call of steps: no copy, and sound for as long as they
//!   live, whatever the callable keeps (the memory stays alive and in place under the World's
//!   lease, as `World.positions`' does). Anything else (a method's stage buffers, which it
//!   overwrites and may reallocate) is copied into arrays the force owns and refills call
//!   after call.
//! * After the call, an array whose reference count is above the force's own (the callable
//!   kept it, or a view of it: a view holds the array, or a lent view's base) is not reused:
//!   a kept copy keeps the values of that call, a kept view shows the World's state as it
//!   steps on. Keeping one is warned, once per force (`RuntimeWarning`), as it is most likely
//!   a history that would read the same array over and over: `x.copy()` keeps values.
//! * With `inplace=True` the callable is `f(t, x, v, out)`: `out` is a writeable `(n, dim)`
//!   array, zeroed before each call, that it fills (`np.multiply(v, -c, out=out)`) and the
//!   result is read from it; returning an array instead still works. Without it the
//!   callable returns the forces, read in place when they are a C-contiguous float64
//!   `(n, dim)` array (converted otherwise).
//! * The arrays are taken out of the force for the call and put back after it, so a
//!   callable that steps a copy of its own world (which shares this force) gets fresh
//!   arrays instead of the ones in use.

use crate::slot::Slot;
use numpy::{npyffi, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use physstep::forces::ForceGenerator;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// The arrays a Python force hands its callable, kept between calls.
#[derive(Default)]
struct Lent {
    x: Option<Py<PyArray2<f64>>>,
    v: Option<Py<PyArray2<f64>>>,
    out: Option<Py<PyArray2<f64>>>,
}

/// Which array of [`Lent`].
#[derive(Clone, Copy)]
enum Which {
    X,
    V,
    Out,
}

impl Which {
    /// The part of a lent state it is (`crate::slot`): 0 the positions, 1 the velocities.
    fn part(self) -> usize {
        usize::from(matches!(self, Which::V))
    }
}

impl Lent {
    fn slot(&mut self, which: Which) -> &mut Option<Py<PyArray2<f64>>> {
        match which {
            Which::X => &mut self.x,
            Which::V => &mut self.v,
            Which::Out => &mut self.out,
        }
    }
}

/// A Python force.
pub(crate) struct PyForce {
    pub name: String,
    pub dim: usize,
    pub func: Py<PyAny>,
    pub potential: Option<Py<PyAny>>,
    pub jacobian: Option<Py<PyAny>>,
    pub velocity_dependent: bool,
    /// `func(t, x, v, out)` fills `out` (else `func(t, x, v)` returns the forces).
    pub inplace: bool,
    pub slot: Slot,
    /// The arrays handed to the callable, reused between calls (`None` while lent out).
    lent: Mutex<Lent>,
    /// Whether the callable was warned that it kept `x` or `v`.
    warned: AtomicBool,
}

/// A Python force as kept for pickling: func, potential, jacobian, velocity_dependent, name,
/// inplace.
type ForceSpec = (Py<PyAny>, Option<Py<PyAny>>, Option<Py<PyAny>>, bool, String, bool);

impl PyForce {
    /// A Python force; see [`World.add_force`](crate::handle::World).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        name: String,
        dim: usize,
        func: Py<PyAny>,
        potential: Option<Py<PyAny>>,
        jacobian: Option<Py<PyAny>>,
        velocity_dependent: bool,
        inplace: bool,
        slot: Slot,
    ) -> Self {
        let lent = Mutex::default();
        let warned = AtomicBool::new(false);
        Self { name, dim, func, potential, jacobian, velocity_dependent, inplace, slot, lent, warned }
    }

    /// The spec the bindings keep to pickle and copy this force:
    /// `(func, potential, jacobian, velocity_dependent, name, inplace)`.
    pub(crate) fn spec<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let spec = (
            self.func.bind(py),
            self.potential.as_ref().map(|p| p.bind(py)),
            self.jacobian.as_ref().map(|j| j.bind(py)),
            self.velocity_dependent,
            &self.name,
            self.inplace,
        );
        Ok(spec.into_pyobject(py)?.into_any())
    }

    /// The force a spec of [`PyForce::spec`] describes, on points of `dim` coordinates.
    pub(crate) fn from_spec(spec: &Bound<'_, PyAny>, dim: usize, slot: &Slot) -> PyResult<Self> {
        let (func, potential, jacobian, velocity_dependent, name, inplace): ForceSpec = spec.extract()?;
        Ok(Self::new(name, dim, func, potential, jacobian, velocity_dependent, inplace, slot.clone()))
    }

    /// The `(rows, dim)` array `which` for a call, holding `data` (zeros when `None`): the
    /// kept one when it has that shape, else a new one.
    fn take<'py>(
        &self,
        py: Python<'py>,
        which: Which,
        rows: usize,
        data: Option<&[f64]>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let kept = self.lent.try_lock().ok().and_then(|mut l| l.slot(which).take());
        let arr = match kept.map(|a| a.into_bound(py)) {
            // (Its holder may have reshaped it in place during the call: then a new one.)
            Some(a) if a.shape() == [rows, self.dim] && a.is_c_contiguous() => a,
            _ => {
                let a = PyArray2::<f64>::zeros(py, [rows, self.dim], false);
                if !matches!(which, Which::Out) {
                    // SAFETY: `a` was just made here and nothing else refers to it; clearing
                    // the WRITEABLE bit is what `PyArray_CLEARFLAGS` does. (An array that owns
                    // its memory may be made writeable again by its holder: it then writes
                    // only this copy, never the engine's state.)
                    unsafe {
                        (*npyffi::objects::_PyArray_GET_ITEM_DATA(a.as_array_ptr())).flags &=
                            !npyffi::NPY_ARRAY_WRITEABLE;
                    }
                }
                a
            }
        };
        // SAFETY: `arr` is either new or was put back by `give_back` when its reference count
        // was the force's own one alone: no Python object, view or buffer export refers to it
        // (each would hold a reference), so no one reads it while it is written here, and the
        // GIL is held. It is a C-contiguous float64 array that owns `rows * dim` values.
        let dst = unsafe { arr.as_slice_mut() }
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
        match data {
            Some(d) => dst.copy_from_slice(d),
            None => dst.fill(0.0),
        }
        Ok(arr)
    }

    /// After a call: `arr` is kept for the next call unless the callable kept a reference to
    /// it (then it is the callable's, with the values it had, and the next call makes a new
    /// one).
    fn give_back(&self, which: Which, arr: Bound<'_, PyArray2<f64>>) {
        // SAFETY: `arr` is a live object (we hold it) and the GIL is held. One reference:
        // `arr` itself.
        if unsafe { pyo3::ffi::Py_REFCNT(arr.as_ptr()) } == 1 {
            if let Ok(mut l) = self.lent.try_lock() {
                let slot = l.slot(which);
                if slot.is_none() {
                    *slot = Some(arr.unbind());
                }
            }
        }
    }

    /// Keeps `e` for the caller of the step; returns a message for the engine.
    fn keep(&self, py: Python<'_>, e: PyErr) -> String {
        keep(&self.slot, py, e)
    }

    /// Hands the `(rows, cols)` float array `out` to `take` as one row-major slice (read in
    /// place when it is a C-contiguous float64 array, converted otherwise), or says what is
    /// wrong with it.
    fn read_matrix(
        out: &Bound<'_, PyAny>,
        what: &str,
        rows: usize,
        cols: usize,
        take: &mut dyn FnMut(&[f64]),
    ) -> Result<(), String> {
        let bad_shape =
            |a: &Bound<'_, PyAny>| format!("{what} must have shape ({rows}, {cols}), not {}", shape(a));
        // The common case, read in place: a C-contiguous float64 array of the right shape.
        if let Ok(a) = out.cast::<PyArray2<f64>>() {
            if a.shape() == [rows, cols] && a.is_c_contiguous() {
                // SAFETY: the GIL is held from here until `take` returns, and neither `take`
                // nor anything else in this crate holds a mutable borrow of the array: no
                // one writes it while it is read (Python code would need the GIL). Not
                // `try_readonly`: its borrow bookkeeping (a global map) cost as much as the
                // rest of an evaluation at one particle.
                if let Ok(s) = unsafe { a.as_slice() } {
                    take(s);
                    return Ok(());
                }
            }
        }
        let arr = real_array(out).map_err(|got| {
            format!("{what} must be an array of real numbers of shape ({rows}, {cols}), not {got}")
        })?;
        let a: PyReadonlyArray2<'_, f64> = arr.extract().map_err(|_| bad_shape(&arr))?;
        if a.shape() != [rows, cols] {
            return Err(bad_shape(&arr));
        }
        match a.as_slice() {
            Ok(s) => take(s),
            Err(_) => take(&a.as_array().iter().copied().collect::<Vec<f64>>()),
        }
        Ok(())
    }

    /// `data`, the positions (`X`) or velocities (`V`) of `rows` points, for the callable, and
    /// whether it is lent (a view of the World's own state, `crate::slot`) rather than copied
    /// into an array the force owns.
    fn hand<'py>(
        &self,
        py: Python<'py>,
        which: Which,
        rows: usize,
        data: &[f64],
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, bool)> {
        match self.slot.view(py, which.part(), data)? {
            Some(view) => Ok((view, true)),
            None => Ok((self.take(py, which, rows, Some(data))?, false)),
        }
    }

    /// After a call: whether the callable kept `arr`, handed by [`PyForce::hand`], or a view
    /// of it; if not, `arr` serves the next call.
    fn hand_back(&self, which: Which, data: &[f64], (arr, lent): (Bound<'_, PyArray2<f64>>, bool)) -> bool {
        // SAFETY: `arr` is a live array (we hold it) and the GIL is held. Ours is one reference
        // to it; a view of it holds either it or (a lent view's) its base, the `StateView`,
        // which `arr` holds once.
        let kept = unsafe {
            let base = (*npyffi::objects::_PyArray_GET_ITEM_DATA(arr.as_array_ptr())).base;
            pyo3::ffi::Py_REFCNT(arr.as_ptr()) > 1 || (!base.is_null() && pyo3::ffi::Py_REFCNT(base) > 1)
        };
        // (Its holder may have reshaped it in place during the call: then a new one.)
        if !kept && arr.shape() == [data.len() / self.dim, self.dim] && arr.is_c_contiguous() {
            match lent {
                true => self.slot.give_back(which.part(), data, arr),
                false => self.give_back(which, arr),
            }
        }
        kept
    }

    /// Calls the callable at `t`, `x`, `v` (and `out`) and hands the forces it gave to `take`.
    /// A callable that keeps `x` or `v` (or a view of either) past the call is warned, once
    /// (`RuntimeWarning`): they are valid during the call only (a view of the World's state
    /// changes as it steps).
    fn call(&self, t: f64, x: &[f64], v: &[f64], take: &mut dyn FnMut(&[f64])) -> Result<(), String> {
        Python::attach(|py| {
            let n = x.len() / self.dim;
            let lent = (|| -> PyResult<_> {
                let xa = self.hand(py, Which::X, n, x)?;
                let va = self.hand(py, Which::V, n, v)?;
                let out = if self.inplace { Some(self.take(py, Which::Out, n, None)?) } else { None };
                Ok((xa, va, out))
            })();
            let (xa, va, out) = lent.map_err(|e| self.keep(py, e))?;
            let r = match &out {
                Some(o) => self.func.bind(py).call1((t, &xa.0, &va.0, o)),
                None => self.func.bind(py).call1((t, &xa.0, &va.0)),
            };
            let r = r.map_err(|e| self.keep(py, e)).and_then(|ret| match &out {
                Some(o) if ret.is_none() || ret.is(o) => {
                    drop(ret);
                    Self::read_matrix(o.as_any(), "the force written to out", n, self.dim, take)
                }
                _ => Self::read_matrix(&ret, "the returned force", n, self.dim, take),
            });
            let kept = [(self.hand_back(Which::X, x, xa), "x"), (self.hand_back(Which::V, v, va), "v")];
            if let Some(o) = out {
                self.give_back(Which::Out, o);
            }
            // (The engine checks the forces for NaN and infinity, and names the entry.)
            r?;
            match kept.iter().find(|(k, _)| *k) {
                Some((_, what)) if !self.warned.swap(true, Ordering::Relaxed) => {
                    let msg = format!(
                        "physstep: force '{}' kept its argument {what} (or a view of it) after \
                         returning: x and v are valid during the call only (views of the World's \
                         own state, which later steps change); keep a copy ({what}.copy())",
                        self.name
                    );
                    let kind = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
                    // (Warnings turned into errors: the step fails with it.)
                    PyErr::warn(py, &kind, &std::ffi::CString::new(msg).unwrap_or_default(), 1)
                        .map_err(|e| self.keep(py, e))
                }
                _ => Ok(()),
            }
        })
    }
}

/// Keeps `e` in `slot` (the first one wins) for the caller of the step; returns a message
/// for the engine.
fn keep(slot: &Slot, py: Python<'_>, e: PyErr) -> String {
    let msg = format!("raised {}", e.value(py));
    slot.keep(e);
    msg
}

fn shape(a: &Bound<'_, PyAny>) -> String {
    a.getattr("shape").and_then(|s| s.str()).map(|s| s.to_string()).unwrap_or_else(|_| "?".into())
}

/// What a callable returned, in a few words for a message: `an array of complex128 of
/// shape (3, 2)`, `'abc' (str)`, `nan`.
fn describe(v: &Bound<'_, PyAny>) -> String {
    if let (Ok(dtype), Ok(shape)) = (v.getattr("dtype"), v.getattr("shape")) {
        if shape.len().is_ok_and(|n| n > 0) {
            return format!("an array of {dtype} of shape {shape}");
        }
    }
    let text = v.repr().map(|r| r.to_string()).unwrap_or_else(|_| "?".into());
    let text = if text.chars().count() > 40 {
        format!("{}...", text.chars().take(40).collect::<String>())
    } else {
        text
    };
    let kind = v.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into());
    if v.is_instance_of::<PyFloat>() {
        text
    } else {
        format!("{text} ({kind})")
    }
}

/// `v` as a C-contiguous float64 array when it holds real numbers (float, integer; never
/// complex, bool, strings or objects, which numpy would cast in silence or mangle), else
/// what it is ([`describe`]).
fn real_array<'py>(v: &Bound<'py, PyAny>) -> Result<Bound<'py, PyAny>, String> {
    let np = v.py().import("numpy").map_err(|_| describe(v))?;
    let arr = np.call_method1("asarray", (v,)).map_err(|_| describe(v))?;
    let kind: String = arr
        .getattr("dtype")
        .and_then(|d| d.getattr("kind"))
        .and_then(|k| k.extract())
        .map_err(|_| describe(v))?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(describe(v));
    }
    np.call_method1("ascontiguousarray", (arr, "float64")).map_err(|_| describe(v))
}

/// `v` as one real number (a float, an integer, a numpy scalar or 0-d array of them), else
/// what it is ([`describe`]).
fn real_scalar(v: &Bound<'_, PyAny>) -> Result<f64, String> {
    // (A float or a subclass of it: numpy's float64.)
    if let Ok(f) = v.cast::<PyFloat>() {
        return Ok(f.value());
    }
    if v.is_instance_of::<PyBool>() {
        return Err(describe(v));
    }
    let arr =
        v.py().import("numpy").and_then(|np| np.call_method1("asarray", (v,))).map_err(|_| describe(v))?;
    let kind: String = arr
        .getattr("dtype")
        .and_then(|d| d.getattr("kind"))
        .and_then(|k| k.extract())
        .map_err(|_| describe(v))?;
    let ndim = arr.getattr("ndim").and_then(|n| n.extract::<usize>()).map_err(|_| describe(v))?;
    if ndim != 0 || !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(describe(v));
    }
    arr.call_method0("item").and_then(|x| x.extract::<f64>()).map_err(|_| describe(v))
}

/// The error a Python force's jacobian (or a flow's) that returned something unusable
/// leaves for the caller: a `ValueError` naming the force.
fn bad_jacobian(name: &str, reason: String) -> PyErr {
    crate::py_err(physstep::Error::Force {
        name: name.into(),
        reason: format!("its jacobian {reason}"),
        non_finite: false,
    })
}

impl ForceGenerator for PyForce {
    fn name(&self) -> &str {
        &self.name
    }

    fn add_forces(&self, t: f64, x: &[f64], v: &[f64], f: &mut [f64]) -> Result<(), String> {
        self.call(t, x, v, &mut |g| f.iter_mut().zip(g).for_each(|(d, g)| *d += g))
    }

    /// The forces read where the callable left them (its `out`, or the array it returned),
    /// not added into `scratch` first.
    fn forces_to(
        &self,
        t: f64,
        x: &[f64],
        v: &[f64],
        _scratch: &mut Vec<f64>,
        take: &mut dyn FnMut(&[f64]),
    ) -> Result<(), String> {
        self.call(t, x, v, take)
    }

    fn velocity_dependent(&self) -> bool {
        self.velocity_dependent
    }

    fn potential(&self, x: &[f64]) -> Option<f64> {
        let p = self.potential.as_ref()?;
        Python::attach(|py| {
            let r = self.take(py, Which::X, x.len() / self.dim, Some(x)).and_then(|xa| {
                let u = p.bind(py).call1((&xa,));
                self.give_back(Which::X, xa);
                Ok(real_scalar(&u?))
            });
            match r {
                Ok(Ok(u)) if u.is_finite() => Some(u),
                Ok(bad) => {
                    let got = bad.map_or_else(|got| got, physstep::error::num);
                    let e = physstep::Error::invalid(
                        format!("potential of force '{}'", physstep::error::one_line(&self.name)),
                        got,
                        "a finite real number (the potential energy, J)",
                    );
                    self.keep(py, crate::py_err(e));
                    None
                }
                Err(e) => {
                    self.keep(py, e);
                    None
                }
            }
        })
    }

    /// `true` whenever the force has a jacobian: when it raises or returns something
    /// unusable, its error is kept for the caller and `dF/dx` is filled with NaN, so the
    /// Newton solve fails and the step is rolled back (never a silent fall back to finite
    /// differences).
    fn jacobian(&self, t: f64, x: &[f64], v: &[f64], dfdx: &mut [f64], dfdv: &mut [f64]) -> bool {
        let Some(jac) = self.jacobian.as_ref() else { return false };
        Python::attach(|py| {
            let n = x.len();
            let rows = n / self.dim;
            let r = (|| -> PyResult<Bound<'_, PyAny>> {
                let xa = self.take(py, Which::X, rows, Some(x))?;
                let va = self.take(py, Which::V, rows, Some(v))?;
                let r = jac.bind(py).call1((t, &xa, &va));
                self.give_back(Which::X, xa);
                self.give_back(Which::V, va);
                r
            })();
            let read = r.and_then(|out| {
                let pair = out.extract::<(Bound<'_, PyAny>, Bound<'_, PyAny>)>().map_err(|_| {
                    bad_jacobian(
                        &self.name,
                        format!("must return a pair (dF/dx, dF/dv), not {}", describe(&out)),
                    )
                })?;
                let (mut a, mut b) = (vec![0.0; n * n], vec![0.0; n * n]);
                for (m, what, acc) in [(&pair.0, "dF/dx", &mut a), (&pair.1, "dF/dv", &mut b)] {
                    Self::read_matrix(m, what, n, n, &mut |g| {
                        acc.iter_mut().zip(g).for_each(|(d, g)| *d += g)
                    })
                    .map_err(|e| bad_jacobian(&self.name, format!("returned {e}")))?;
                    if let Some(i) = acc.iter().position(|c| !c.is_finite()) {
                        let reason = format!(
                            "returned {what}[{}][{}] = {}: must be finite",
                            i / n,
                            i % n,
                            physstep::error::num(acc[i])
                        );
                        return Err(bad_jacobian(&self.name, reason));
                    }
                }
                Ok((a, b))
            });
            match read {
                Ok((a, b)) => {
                    dfdx.iter_mut().zip(&a).for_each(|(d, s)| *d += s);
                    dfdv.iter_mut().zip(&b).for_each(|(d, s)| *d += s);
                }
                Err(e) => {
                    self.keep(py, e);
                    dfdx.fill(f64::NAN);
                }
            }
            true
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
        keep(&self.slot, py, e)
    }

    /// A flat float vector of length `n` from `out`, or a message naming what is wrong.
    fn vector(out: &Bound<'_, PyAny>, what: &str, n: usize) -> Result<Vec<f64>, String> {
        let arr = real_array(out)
            .and_then(|a| a.call_method0("ravel").map_err(|_| describe(out)))
            .map_err(|got| format!("{what} must be an array of {n} real numbers, not {got}"))?;
        let v: Vec<f64> =
            arr.extract().map_err(|_| format!("{what} must be an array of {n} real numbers"))?;
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

    /// As [`PyForce`]'s: an exception or an unusable value is kept for the caller and the
    /// Jacobian filled with NaN, so the step fails and is rolled back.
    fn jacobian(&self, t: f64, y: &[f64], dfdy: &mut [f64]) -> bool {
        let Some(jac) = self.jacobian.as_ref() else { return false };
        Python::attach(|py| {
            let n = y.len();
            let read = jac.bind(py).call1((t, PyArray1::from_slice(py, y))).and_then(|out| {
                let v = Self::vector(&out, &format!("the Jacobian ({n} x {n})"), n * n)
                    .map_err(|e| bad_jacobian(&self.name, format!("returned {e}")))?;
                if let Some(i) = v.iter().position(|c| !c.is_finite()) {
                    let reason = format!(
                        "returned df/dy[{}][{}] = {}: must be finite",
                        i / n,
                        i % n,
                        physstep::error::num(v[i])
                    );
                    return Err(bad_jacobian(&self.name, reason));
                }
                Ok(v)
            });
            match read {
                Ok(v) => dfdy.copy_from_slice(&v),
                Err(e) => {
                    self.keep(py, e);
                    dfdy.fill(f64::NAN);
                }
            }
            true
        })
    }
}
